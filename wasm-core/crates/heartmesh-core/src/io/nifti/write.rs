//! Writing a label map as NIfTI-1: what the validation lab's simulated segmentations are saved as
//! (`heartmesh segment`), for the reader, other tools and the app to open.

use super::volume::LabelVolume;

/// The label map (its one frame) as a single-file NIfTI-1 (`.nii`; gzip-compressed for `.nii.gz`
/// when `gzip`):
/// uint8 labels when they fit, else uint16; millimetres; the placement as an sform (code 1,
/// scanner) and the spacings in `pixdim`.
pub fn write_nifti(volume: &LabelVolume, gzip: bool) -> Vec<u8> {
    let wide = volume.labels.iter().any(|&l| l > 255);
    let mut h = vec![0u8; 352];
    let mut put = |at: usize, bytes: &[u8]| h[at..at + bytes.len()].copy_from_slice(bytes);
    put(0, &348i32.to_le_bytes());
    put(40, &3i16.to_le_bytes());
    for (n, d) in volume.dims.iter().enumerate() {
        put(42 + 2 * n, &(*d as i16).to_le_bytes());
    }
    for n in 3..7 {
        put(42 + 2 * n, &1i16.to_le_bytes());
    }
    let (datatype, bitpix) = if wide { (512i16, 16i16) } else { (2, 8) };
    put(70, &datatype.to_le_bytes());
    put(72, &bitpix.to_le_bytes());
    let s = volume.spacing();
    let pixdim = [1.0, s[0], s[1], s[2], 1.0, 1.0, 1.0, 1.0];
    for (n, p) in pixdim.iter().enumerate() {
        put(76 + 4 * n, &(*p as f32).to_le_bytes());
    }
    put(108, &352f32.to_le_bytes());
    put(123, &[2 | 8]); // mm, seconds
    put(254, &1i16.to_le_bytes());
    for r in 0..3 {
        let row = [
            volume.axes[0][r],
            volume.axes[1][r],
            volume.axes[2][r],
            volume.origin[r],
        ];
        for (c, v) in row.iter().enumerate() {
            put(280 + 16 * r + 4 * c, &(*v as f32).to_le_bytes());
        }
    }
    put(344, b"n+1\0");
    if wide {
        h.extend(volume.labels.iter().flat_map(|l| l.to_le_bytes()));
    } else {
        h.extend(volume.labels.iter().map(|&l| l as u8));
    }
    if !gzip {
        return h;
    }
    crate::io::gzip::deflate(&h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec3;
    use crate::io::nifti::volume::read_label_volume;

    #[test]
    fn written_label_maps_read_back() {
        for (top, gzip) in [(7u16, false), (600, true)] {
            let v = LabelVolume::new(
                [3, 2, 4],
                Vec3::new(-5.0, 7.5, 100.0),
                [
                    Vec3::new(0.0, 1.25, 0.0),
                    Vec3::new(-1.25, 0.0, 0.0),
                    Vec3::new(0.0, 0.0, 8.0),
                ],
                (0..24).map(|n| (n % 3) as u16 * top / 2).collect(),
            );
            let bytes = write_nifti(&v, gzip);
            let back = read_label_volume(&crate::io::gzip::inflate(&bytes).unwrap()).unwrap();
            assert_eq!((back.dims, back.frames), (v.dims, 1));
            assert_eq!(back.labels, v.labels);
            let p = back.world([2.0, 1.0, 1.0]);
            assert!((p - v.world([2.0, 1.0, 1.0])).norm() < 1e-4, "{p:?}");
        }
    }
}
