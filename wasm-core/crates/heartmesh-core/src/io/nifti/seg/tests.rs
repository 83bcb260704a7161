use super::super::volume::read_label_frame;
use super::super::{read_dicom_seg, read_nifti, write::write_nifti};
use super::*;
use crate::contours::ContourSet;
use crate::io::gzip::inflate;
use dicom_core::value::DataSetSequence;
use dicom_core::{DataElement, PrimitiveValue, Tag as DTag, VR};
use dicom_object::{FileMetaTableBuilder, InMemDicomObject};

/// The app's example segmentation (CardioMesh spasm: RV 1, myocardium 2, LV cavity 3).
fn sample() -> LabelVolume {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../public/samples/cardiomesh-spasm-seg.nii.gz"
    );
    let raw = std::fs::read(path).unwrap();
    let bytes = inflate(&raw).unwrap();
    read_label_frame(&bytes, None).unwrap()
}

/// `v` cut to `[i0, i0 + ni) x [j0, j0 + nj)` in plane, its origin moved with it: an odd size
/// makes the frames' bits run across byte boundaries.
fn crop(v: &LabelVolume, i0: usize, ni: usize, j0: usize, nj: usize) -> LabelVolume {
    let [di, dj, dk] = v.dims;
    let mut labels = Vec::with_capacity(ni * nj * dk);
    for k in 0..dk {
        for j in j0..j0 + nj {
            for i in i0..i0 + ni {
                labels.push(v.labels[i + di * (j + dj * k)]);
            }
        }
    }
    let origin = v.origin + v.axes[0] * i0 as f64 + v.axes[1] * j0 as f64;
    LabelVolume::new([ni, nj, dk], origin, v.axes, labels)
}

fn el(
    group: u16,
    element: u16,
    vr: VR,
    value: impl Into<PrimitiveValue>,
) -> DataElement<InMemDicomObject> {
    DataElement::new(DTag(group, element), vr, value.into())
}

fn seq(group: u16, element: u16, items: Vec<InMemDicomObject>) -> DataElement<InMemDicomObject> {
    DataElement::new(DTag(group, element), VR::SQ, DataSetSequence::from(items))
}

fn item(elements: Vec<DataElement<InMemDicomObject>>) -> InMemDicomObject {
    InMemDicomObject::from_element_iter(elements)
}

fn ds(values: &[f64]) -> String {
    let v: Vec<String> = values.iter().map(|x| format!("{x:.6}")).collect();
    v.join("\\")
}

/// How a test SEG is written.
struct Spec {
    /// 1 (binary) or 8 (fractional, 255 = inside).
    bits: u16,
    transfer_syntax: &'static str,
    /// SpacingBetweenSlices written (None: left out, as many writers do).
    spacing_between: Option<f64>,
    /// The first frame written lies in another orientation (its own PlaneOrientationSequence): a
    /// long-axis view segmented in the same object.
    tilt_first: bool,
}

const BINARY: Spec = Spec {
    bits: 1,
    transfer_syntax: "1.2.840.10008.1.2.1",
    spacing_between: None,
    tilt_first: false,
};

/// A SEG of label maps on one grid, one per time frame (TemporalPositionIndex 1, 2, ...): a
/// frame per slice and label present, none for empty ones, listed last slice first (the reader
/// must not rely on their order).
fn write_seg(times: &[&LabelVolume], spec: &Spec) -> Vec<u8> {
    let v = times[0];
    let [ni, nj, nk] = v.dims;
    let row = v.axes[0].normalize();
    let col = v.axes[1].normalize();
    let spacing = [v.axes[1].norm(), v.axes[0].norm()];
    let mut per_frame = Vec::new();
    let mut bits: Vec<bool> = Vec::new();
    let mut labels_seen = std::collections::BTreeSet::new();
    for (t, vol) in times.iter().enumerate() {
        for k in (0..nk).rev() {
            let slice = &vol.labels[ni * nj * k..ni * nj * (k + 1)];
            let mut present: Vec<u16> = slice.iter().copied().filter(|&l| l != 0).collect();
            present.sort_unstable();
            present.dedup();
            for label in present {
                labels_seen.insert(label);
                let p = v.origin + v.axes[2] * k as f64;
                per_frame.push(item(vec![
                    seq(
                        0x0020,
                        0x9111,
                        vec![item(vec![el(0x0020, 0x9128, VR::UL, (t + 1) as u32)])],
                    ),
                    seq(
                        0x0020,
                        0x9113,
                        vec![item(vec![el(0x0020, 0x0032, VR::DS, ds(&[p.x, p.y, p.z]))])],
                    ),
                    seq(
                        0x0062,
                        0x000A,
                        vec![item(vec![el(0x0062, 0x000B, VR::US, label)])],
                    ),
                ]));
                bits.extend(slice.iter().map(|&l| l == label));
            }
        }
    }
    if spec.tilt_first {
        let n = row.cross(&col);
        per_frame[0].put(seq(
            0x0020,
            0x9116,
            vec![item(vec![el(
                0x0020,
                0x0037,
                VR::DS,
                ds(&[n.x, n.y, n.z, col.x, col.y, col.z]),
            )])],
        ));
    }
    let pixels: Vec<u8> = if spec.bits == 1 {
        let mut packed = vec![0u8; bits.len().div_ceil(8)];
        for (n, _) in bits.iter().enumerate().filter(|(_, &b)| b) {
            packed[n / 8] |= 1 << (n % 8);
        }
        if packed.len() % 2 == 1 {
            packed.push(0);
        }
        packed
    } else {
        bits.iter().map(|&b| if b { 255 } else { 0 }).collect()
    };
    let segments: Vec<InMemDicomObject> = labels_seen
        .iter()
        .map(|&l| {
            item(vec![
                el(0x0062, 0x0004, VR::US, l),
                el(0x0062, 0x0005, VR::LO, format!("structure {l}")),
            ])
        })
        .collect();
    let mut obj = InMemDicomObject::from_element_iter([
        el(0x0008, 0x0016, VR::UI, SEGMENTATION_STORAGE),
        el(0x0008, 0x0018, VR::UI, "1.2.826.0.1.3680043.10.1234.1"),
        el(0x0008, 0x0060, VR::CS, "SEG"),
        el(0x0028, 0x0002, VR::US, 1u16),
        el(0x0028, 0x0004, VR::CS, "MONOCHROME2"),
        el(0x0028, 0x0008, VR::IS, per_frame.len().to_string()),
        el(0x0028, 0x0010, VR::US, nj as u16),
        el(0x0028, 0x0011, VR::US, ni as u16),
        el(0x0028, 0x0100, VR::US, spec.bits),
        el(0x0028, 0x0101, VR::US, spec.bits),
        el(0x0028, 0x0102, VR::US, spec.bits - 1),
        el(
            0x0062,
            0x0001,
            VR::CS,
            if spec.bits == 1 {
                "BINARY"
            } else {
                "FRACTIONAL"
            },
        ),
        seq(0x0062, 0x0002, segments),
        seq(
            0x5200,
            0x9229,
            vec![item(vec![
                seq(
                    0x0020,
                    0x9116,
                    vec![item(vec![el(
                        0x0020,
                        0x0037,
                        VR::DS,
                        ds(&[row.x, row.y, row.z, col.x, col.y, col.z]),
                    )])],
                ),
                seq(
                    0x0028,
                    0x9110,
                    vec![item(
                        [
                            el(0x0028, 0x0030, VR::DS, ds(&spacing)),
                            el(0x0018, 0x0050, VR::DS, ds(&[v.axes[2].norm()])),
                        ]
                        .into_iter()
                        .chain(
                            spec.spacing_between
                                .map(|d| el(0x0018, 0x0088, VR::DS, ds(&[d]))),
                        )
                        .collect(),
                    )],
                ),
            ])],
        ),
        seq(0x5200, 0x9230, per_frame),
        el(0x7FE0, 0x0010, VR::OB, PrimitiveValue::U8(pixels.into())),
    ]);
    if spec.bits == 8 {
        obj.put(el(0x0062, 0x000E, VR::US, 255u16));
    }
    let file = obj
        .with_meta(
            FileMetaTableBuilder::new()
                .transfer_syntax(spec.transfer_syntax)
                .media_storage_sop_class_uid(SEGMENTATION_STORAGE)
                .media_storage_sop_instance_uid("1.2.826.0.1.3680043.10.1234.1"),
        )
        .unwrap();
    let mut out = Vec::new();
    file.write_all(&mut out).unwrap();
    out
}

/// The contours of `v` read as a NIfTI: what a SEG of the same map must give.
fn as_nifti(v: &LabelVolume) -> ContourSet {
    read_nifti(&write_nifti(v, false), None).unwrap()
}

/// Each surface's points: two readings of one label map agree point for point, to the 1e-6 of
/// the DS strings the test writes.
fn points_by_surface(set: &ContourSet) -> Vec<(String, Vec<Vec3>)> {
    let mut out: Vec<(String, Vec<Vec3>)> = set
        .surfaces()
        .into_iter()
        .map(|s| {
            let p: Vec<Vec3> = set
                .contours
                .iter()
                .filter(|c| c.surface.as_deref() == Some(s.as_str()))
                .flat_map(|c| c.points().copied().collect::<Vec<_>>())
                .collect();
            (s, p)
        })
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

/// The same surfaces with the same point counts, every point within 1e-3 mm of one of the other's.
fn assert_same_points(a: &ContourSet, b: &ContourSet) {
    let (a, b) = (points_by_surface(a), points_by_surface(b));
    assert_eq!(a.len(), b.len());
    for ((sa, pa), (sb, pb)) in a.iter().zip(&b) {
        assert_eq!(sa, sb);
        assert_eq!(pa.len(), pb.len(), "{sa}");
        let worst = pa
            .iter()
            .map(|p| {
                pb.iter()
                    .map(|q| (p - q).norm())
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max);
        assert!(worst < 1e-3, "{sa}: {worst} mm");
    }
}

#[test]
fn a_seg_reads_as_the_label_map_it_was_written_from() {
    // 91 x 87 pixels: frames of 7917 bits, so each starts inside a byte.
    let v = crop(&sample(), 5, 91, 3, 87);
    let nifti = as_nifti(&v);
    for spec in [
        BINARY,
        Spec {
            bits: 8,
            transfer_syntax: "1.2.840.10008.1.2.1",
            spacing_between: Some(10.0),
            tilt_first: false,
        },
        Spec {
            bits: 1,
            transfer_syntax: "1.2.840.10008.1.2",
            spacing_between: None,
            tilt_first: false,
        },
        // The slice thickness written where the spacing belongs (8 mm; the planes are 10 apart):
        // the planes' own gaps win.
        Spec {
            bits: 1,
            transfer_syntax: "1.2.840.10008.1.2.1",
            spacing_between: Some(8.0),
            tilt_first: false,
        },
    ] {
        let bytes = write_seg(&[&v], &spec);
        assert!(is_seg(&bytes));
        let seg = read_dicom_seg(&bytes, None).unwrap();
        assert_eq!(seg.surfaces().len(), 3);
        assert_same_points(&seg, &nifti);
        let note = &seg.warnings[0];
        assert!(note.contains("frame positions (DICOM SEG, LPS)"), "{note}");
        assert!(
            note.contains("segments 1 structure 1, 2 structure 2, 3 structure 3"),
            "{note}"
        );
    }
}

#[test]
fn time_frames_are_read_one_at_a_time() {
    let v = crop(&sample(), 0, 90, 0, 90);
    // The second frame: the LV cavity (3) grown into the myocardium (2) everywhere.
    let mut grown = v.clone();
    for l in grown.labels.iter_mut().filter(|l| **l == 2) {
        *l = 3;
    }
    let bytes = write_seg(&[&v, &grown], &BINARY);
    let first = read_dicom_seg(&bytes, None).unwrap();
    let tf = first.time_frames.as_ref().unwrap();
    assert_eq!(tf.count, 2);
    let second = read_dicom_seg(&bytes, FrameChoice::new("1").as_ref()).unwrap();
    assert_same_points(&first, &as_nifti(&v));
    assert_same_points(&second, &as_nifti(&grown));
    let e = read_dicom_seg(&bytes, FrameChoice::new("5").as_ref())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("no frame 5 in the DICOM SEG (its time frames: 0 to 1)"),
        "{e}"
    );
}

#[test]
fn segs_that_are_no_stack_or_are_cut_are_refused_with_the_reason() {
    let v = crop(&sample(), 0, 64, 0, 64);
    let good = write_seg(&[&v], &BINARY);
    let reason = |b: &[u8]| read_dicom_seg(b, None).unwrap_err().to_string();
    // Cut inside the pixel data.
    let e = reason(&good[..good.len() - 200]);
    assert!(e.contains("truncated") || e.contains("DICOM"), "{e}");
    // A compressed transfer syntax (the header says so; the reader does not decode JPEG or RLE).
    let rle = write_seg(
        &[&v],
        &Spec {
            bits: 1,
            transfer_syntax: "1.2.840.10008.1.2.5",
            spacing_between: None,
            tilt_first: false,
        },
    );
    assert!(
        reason(&rle).contains("export it uncompressed"),
        "{}",
        reason(&rle)
    );
    // One frame's plane 3.7 mm off the 10 mm grid (its ImagePositionPatient rewritten in place).
    let mut shifted = good.clone();
    let at = find(&shifted, b"\x20\x00\x32\x00DS").unwrap();
    let len = u16::from_le_bytes([shifted[at + 6], shifted[at + 7]]) as usize;
    let value = String::from_utf8_lossy(&shifted[at + 8..at + 8 + len]).to_string();
    let mut parts: Vec<f64> = value
        .trim()
        .split('\\')
        .map(|x| x.trim().parse().unwrap())
        .collect();
    parts[2] += 3.7;
    let mut moved = ds(&parts);
    if moved.len() > len {
        moved = format!("{:.2}\\{:.2}\\{:.2}", parts[0], parts[1], parts[2]);
    }
    assert!(moved.len() <= len, "{moved}");
    let padded = format!("{moved:<len$}");
    shifted[at + 8..at + 8 + len].copy_from_slice(padded.as_bytes());
    let e = reason(&shifted);
    assert!(
        e.contains("not evenly spaced") || e.contains("across its plane"),
        "{e}"
    );
    // Not a SEG: an image goes to the structure-set reader, which says what it is.
    assert!(!is_seg(
        &crate::io::rtstruct::write_rtstruct(&ContourSet::default(), "x").unwrap_or_default()
    ));
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

#[test]
fn mutated_segs_never_panic() {
    let v = crop(&sample(), 10, 37, 10, 29);
    let good = write_seg(&[&v], &BINARY);
    let mut rng = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        rng
    };
    for n in 0..400 {
        let mut b = good.clone();
        match n % 3 {
            0 => {
                for _ in 0..4 {
                    let at = (next() as usize) % b.len();
                    b[at] = next() as u8;
                }
            }
            1 => b.truncate((next() as usize) % b.len()),
            _ => {
                let at = (next() as usize) % b.len();
                let bytes = (next() as u32).to_le_bytes();
                b.splice(at..at, bytes);
            }
        }
        let _ = read_dicom_seg(&b, None);
        let _ = read_dicom_seg(&b, FrameChoice::new("1").as_ref());
    }
}

#[test]
fn frames_of_another_orientation_are_set_aside_and_said() {
    let v = crop(&sample(), 0, 90, 0, 90);
    let bytes = write_seg(
        &[&v],
        &Spec {
            tilt_first: true,
            ..BINARY
        },
    );
    let set = read_dicom_seg(&bytes, None).unwrap();
    assert!(
        set.warnings.iter().any(|w| w.starts_with(
            "1 frame of the DICOM SEG in another orientation or pixel spacing than the stack"
        )),
        "{:?}",
        set.warnings
    );
    // The frame set aside is the first written: the top slice's lowest label. Without it, the
    // rest is the label map with that slice's label cleared.
    let [ni, nj, nk] = v.dims;
    let top = (0..nk)
        .rev()
        .find(|&k| {
            v.labels[ni * nj * k..ni * nj * (k + 1)]
                .iter()
                .any(|&l| l != 0)
        })
        .unwrap();
    let slice = ni * nj * top..ni * nj * (top + 1);
    let lowest = v.labels[slice.clone()]
        .iter()
        .copied()
        .filter(|&l| l != 0)
        .min()
        .unwrap();
    let mut without = v.clone();
    for l in without.labels[slice].iter_mut().filter(|l| **l == lowest) {
        *l = 0;
    }
    assert_same_points(&set, &as_nifti(&without));
}
