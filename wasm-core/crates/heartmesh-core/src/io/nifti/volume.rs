//! A NIfTI-1 label map in memory: the header checked against the bytes that follow it, the voxel
//! grid's placement in millimetres, and the labels of one time frame.
//!
//! The header is parsed by the `nifti` crate. The voxels and the affine are read here, because
//! that crate's volume reader allocates the size the header declares before reading (a 400-byte
//! file could ask for gigabytes) and its qform affine panics on negative spacings; every size
//! below is checked against the bytes actually present first.

use nalgebra::{Matrix3, Vector3};
use nifti::{NiftiHeader, NiftiType};

use crate::contours::CoordinateSystem;
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::io::FrameChoice;

/// Most distinct labels a label map may hold; more is an image (MRI intensities), not a
/// segmentation.
pub const MAX_LABELS: usize = 64;

const HEADER_BYTES: usize = 348;

pub(super) fn err(message: impl Into<String>) -> CoreError {
    CoreError::parse(0, message)
}

/// What the 4 bytes at 344 of a NIfTI-1 header, or at 4 of a NIfTI-2 header, say.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Magic {
    /// `n+1`: header and voxels in one file (.nii).
    Single,
    /// `ni1`: a header whose voxels are in a separate .img file.
    Pair,
    /// `n+2` / `ni2`: NIfTI-2.
    Nifti2,
}

/// The NIfTI magic of `bytes` (already inflated), if any.
/// Both must match: the header's declared size (348 for NIfTI-1, 540 for NIfTI-2, in either byte
/// order) and the magic, so that no text file is taken for one by chance.
pub fn magic(bytes: &[u8]) -> Option<Magic> {
    let size = bytes.get(..4)?;
    let declares = |n: i32| size == n.to_le_bytes() || size == n.to_be_bytes();
    if declares(540) && matches!(bytes.get(4..7), Some(b"n+2" | b"ni2")) {
        return Some(Magic::Nifti2);
    }
    if !declares(348) {
        return None;
    }
    match bytes.get(344..347)? {
        b"n+1" => Some(Magic::Single),
        b"ni1" => Some(Magic::Pair),
        _ => None,
    }
}

/// Which way a label map's world axes point, as the signs that turn its coordinates into DICOM's
/// LPS+ (+x towards the patient's left, +y posterior, +z superior). A study's files may come in
/// different conventions (a NIfTI stack is RAS+, a DICOM SEG view of it LPS+): a view is turned
/// into its stack's before their pixels are compared.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Space(pub [f64; 3]);

impl Space {
    /// DICOM's patient coordinates (SEG, RTSTRUCT), 3D Slicer's NRRD.
    pub const LPS: Space = Space([1.0, 1.0, 1.0]);
    /// NIfTI's world coordinates.
    pub const RAS: Space = Space([-1.0, -1.0, 1.0]);
    /// Some NRRD writers'.
    pub const LAS: Space = Space([1.0, -1.0, 1.0]);

    /// The patient frame of mesh files this space is (LAS and others have none).
    pub fn coordinate_system(self) -> Option<CoordinateSystem> {
        if self == Space::LPS {
            Some(CoordinateSystem::Lps)
        } else if self == Space::RAS {
            Some(CoordinateSystem::Ras)
        } else {
            None
        }
    }

    /// Signs that turn a point of `self` into one of `to` (each axis flipped or kept).
    fn to(self, to: Space) -> Vec3 {
        Vec3::new(
            self.0[0] * to.0[0],
            self.0[1] * to.0[1],
            self.0[2] * to.0[2],
        )
    }
}

/// A label map: the grid, its placement and the labels of one time frame (a cine's other frames
/// are only listed: holding every frame would multiply the memory a browser worker needs).
#[derive(Debug, Clone)]
pub struct LabelVolume {
    /// Voxels along i, j, k.
    pub dims: [usize; 3],
    /// World position (mm) of voxel (0, 0, 0)'s centre.
    pub origin: Vec3,
    /// World step (mm) of one voxel along i, j and k: the affine's columns.
    pub axes: [Vec3; 3],
    /// Which placement the header gave: "sform", "qform" or "pixdim" (none: voxel grid scaled).
    pub placement: &'static str,
    /// One label per voxel of frame `frame`, i fastest, then j and k.
    pub labels: Vec<u16>,
    /// Time frames in the file (the 4th dimension; 1 for a 3D file).
    pub frames: usize,
    /// The frames holding any label, ascending.
    pub labelled: Vec<usize>,
    /// The frame `labels` holds.
    pub frame: usize,
    /// The convention of its world coordinates (None: the file does not say).
    pub space: Option<Space>,
}

impl LabelVolume {
    /// A single-frame label map placed by an sform (what the validation lab paints).
    pub fn new(dims: [usize; 3], origin: Vec3, axes: [Vec3; 3], labels: Vec<u16>) -> Self {
        Self::of_frame(dims, (origin, axes, "sform"), 1, only_frame(labels))
    }

    /// The label map of `grid` voxels placed as `placement` says (origin, axes, and which
    /// header fields gave them), of `frames` time frames, keeping `picked` (its index, labels
    /// and the frames holding labels, as [`pick_frame`] gives them). Every maker of a label map
    /// builds it here, so the readers and the lab fill each field alike.
    pub(super) fn of_frame(
        grid: [usize; 3],
        placement: (Vec3, [Vec3; 3], &'static str),
        frames: usize,
        picked: (usize, Vec<u16>, Vec<usize>),
    ) -> Self {
        let (origin, axes, placement) = placement;
        let (frame, labels, labelled) = picked;
        LabelVolume {
            dims: grid,
            origin,
            axes,
            placement,
            labels,
            frames,
            labelled,
            frame,
            space: None,
        }
    }

    /// The same map said to be in `space`.
    pub(super) fn in_space(self, space: Space) -> Self {
        LabelVolume {
            space: Some(space),
            ..self
        }
    }

    /// The same map with its world coordinates turned into `to`'s convention (unchanged when
    /// either convention is unknown: the files are then taken to share one).
    pub(super) fn turned_into(mut self, to: Option<Space>) -> Self {
        if let (Some(from), Some(to)) = (self.space, to) {
            let signs = from.to(to);
            self.origin.component_mul_assign(&signs);
            for axis in &mut self.axes {
                axis.component_mul_assign(&signs);
            }
            self.space = Some(to);
        }
        self
    }

    /// World position (mm) of a point in voxel-index coordinates (centres at whole numbers).
    pub fn world(&self, ijk: [f64; 3]) -> Vec3 {
        self.origin + self.axes[0] * ijk[0] + self.axes[1] * ijk[1] + self.axes[2] * ijk[2]
    }

    /// Voxel spacing (mm) along i, j and k.
    pub fn spacing(&self) -> [f64; 3] {
        [
            self.axes[0].norm(),
            self.axes[1].norm(),
            self.axes[2].norm(),
        ]
    }
}

/// Reads a label map from the (inflated) bytes of a single-file NIfTI-1: its first frame holding
/// labels.
#[cfg(test)]
pub fn read_label_volume(bytes: &[u8]) -> Result<LabelVolume> {
    read_label_frame(bytes, None)
}

/// Voxels along i, j, k and the number of time frames a NIfTI-1 header declares (None: not a
/// readable NIfTI-1 header), without reading the voxels: enough to tell a short-axis stack from a
/// single long-axis slice among files opened together.
pub fn grid(header_bytes: &[u8]) -> Option<([usize; 3], usize)> {
    if magic(header_bytes) != Some(Magic::Single) {
        return None;
    }
    let header = NiftiHeader::from_reader(header_bytes).ok()?;
    let dims = header.dim().ok()?;
    let size = |a: usize| dims.get(a).map_or(1, |&d| usize::from(d));
    Some(([size(0), size(1), size(2)], size(3)))
}

/// Reads frame `want` of a label map (by its number from 0; None: the first holding labels, or
/// frame 0 of an empty map) from the (inflated) bytes of a single-file NIfTI-1.
pub fn read_label_frame(bytes: &[u8], want: Option<&FrameChoice>) -> Result<LabelVolume> {
    match magic(bytes) {
        Some(Magic::Single) => {}
        Some(Magic::Pair) => {
            return Err(err(
                "this is the header of a NIfTI .hdr/.img pair: its voxels are in the .img file; \
                 save the label map as one .nii or .nii.gz",
            ))
        }
        Some(Magic::Nifti2) => {
            return Err(err(
                "NIfTI-2 files are not read; save the label map as NIfTI-1 (.nii or .nii.gz)",
            ))
        }
        None => return Err(err("not a NIfTI-1 file (no n+1 magic at byte 344)")),
    }
    let header = NiftiHeader::from_reader(bytes)
        .map_err(|e| err(format!("the NIfTI header cannot be read ({e})")))?;
    let dims = header.dim().map_err(|_| {
        err(format!(
            "the NIfTI header's dimensions are invalid: dim = {:?} (dim[0], the count, must be \
             1 to 7 and each size at least 1)",
            header.dim
        ))
    })?;
    if dims.len() < 2 {
        return Err(err(
            "the NIfTI volume has one dimension: a label map needs slices",
        ));
    }
    if let Some(d) = dims.iter().skip(4).position(|&d| d > 1) {
        return Err(err(format!(
            "the NIfTI volume has {} values per voxel in dimension {}: a label map holds one",
            dims[4 + d],
            5 + d
        )));
    }
    let size = |a: usize| dims.get(a).map_or(1, |&d| usize::from(d));
    let grid = [size(0), size(1), size(2)];
    let frames = size(3);
    let kind = header.data_type().map_err(|_| {
        err(format!(
            "NIfTI data type {} is not a known type",
            header.datatype
        ))
    })?;
    let width = value_width(kind)?;
    let count = grid[0] * grid[1] * grid[2] * frames;
    let start = header.vox_offset;
    if !start.is_finite() || start < HEADER_BYTES as f32 || start as f64 > bytes.len() as f64 {
        return Err(err(format!(
            "the NIfTI header puts the voxels at byte {start}, outside the file ({} bytes)",
            bytes.len()
        )));
    }
    let start = start as usize;
    let needed = count.saturating_mul(width);
    if needed > bytes.len() - start {
        return Err(err(format!(
            "the file is truncated: the header declares {} voxels of {} byte(s) ({} bytes) but \
             {} follow the header",
            dims_text(dims),
            width,
            needed,
            bytes.len() - start
        )));
    }
    let placed = placement(&header)?;
    let scale = scaling(&header);
    let picked = pick_frame(
        &bytes[start..start + needed],
        frames,
        |data| read_labels(data, kind, header.endianness, scale),
        want,
    )?;
    Ok(LabelVolume::of_frame(grid, placed, frames, picked).in_space(Space::RAS))
}

/// The only frame of a map holding one, as [`pick_frame`] would give it (frame 0, its labels,
/// and frame 0 as labelled unless every voxel is background), so a map made in one piece (the
/// lab's, a NRRD's segment layers) reads as a one-frame file does.
pub(super) fn only_frame(labels: Vec<u16>) -> (usize, Vec<u16>, Vec<usize>) {
    let labelled = if labels.iter().any(|&l| l != 0) {
        vec![0]
    } else {
        Vec::new()
    };
    (0, labels, labelled)
}

/// The frame `want` (None: the first holding labels, else the last) of `frames` equal frames of
/// voxel bytes, decoded by `decode`; also the frames holding labels. Frames other than the one
/// kept are decoded only to see whether they hold labels, then dropped.
pub(super) fn pick_frame(
    data: &[u8],
    frames: usize,
    decode: impl Fn(&[u8]) -> Result<Vec<u16>>,
    want: Option<&FrameChoice>,
) -> Result<(usize, Vec<u16>, Vec<usize>)> {
    let frame_bytes = data.len() / frames.max(1);
    let mut labelled = Vec::new();
    let mut kept: Option<(usize, Vec<u16>)> = None;
    for (t, chunk) in data
        .chunks_exact(frame_bytes.max(1))
        .take(frames)
        .enumerate()
    {
        let labels = decode(chunk)?;
        let any = labels.iter().any(|&l| l != 0);
        if any {
            labelled.push(t);
        }
        let chosen = match want {
            Some(w) => w.matches(&t.to_string()),
            None => any && labelled.len() == 1,
        };
        if chosen || (kept.is_none() && t + 1 == frames && want.is_none()) {
            kept = Some((t, labels));
        }
    }
    let Some((frame, labels)) = kept else {
        let shown: Vec<String> = labelled.iter().take(8).map(usize::to_string).collect();
        return Err(err(format!(
            "no frame {} in the label map (frames with labels: {})",
            want.map_or("", |w| w.label()),
            shown.join(", ")
        )));
    };
    Ok((frame, labels, labelled))
}

fn dims_text(dims: &[u16]) -> String {
    dims.iter()
        .map(|d| d.to_string())
        .collect::<Vec<_>>()
        .join(" x ")
}

pub(super) fn value_width(kind: NiftiType) -> Result<usize> {
    Ok(match kind {
        NiftiType::Uint8 | NiftiType::Int8 => 1,
        NiftiType::Int16 | NiftiType::Uint16 => 2,
        NiftiType::Int32 | NiftiType::Uint32 | NiftiType::Float32 => 4,
        NiftiType::Int64 | NiftiType::Uint64 | NiftiType::Float64 => 8,
        other => {
            return Err(err(format!(
                "NIfTI data type {other:?} is not a label type (integers or real numbers)"
            )))
        }
    })
}

/// `scl_slope`/`scl_inter` when they apply (a slope of 0 or not finite means none, per NIfTI-1).
fn scaling(h: &NiftiHeader) -> Option<(f64, f64)> {
    let slope = f64::from(h.scl_slope);
    let inter = f64::from(h.scl_inter);
    (slope != 0.0 && slope.is_finite() && inter.is_finite() && (slope, inter) != (1.0, 0.0))
        .then_some((slope, inter))
}

/// Millimetres per unit of the header's space unit (meters, mm, microns; unknown read as mm).
fn unit_mm(h: &NiftiHeader) -> f64 {
    match h.xyzt_units & 7 {
        1 => 1000.0,
        3 => 0.001,
        _ => 1.0,
    }
}

/// Origin and per-voxel axes in mm, from the sform, else the qform, else the spacings alone.
fn placement(h: &NiftiHeader) -> Result<(Vec3, [Vec3; 3], &'static str)> {
    let mm = unit_mm(h);
    let (origin, m, how) = if h.sform_code > 0 {
        let r = [h.srow_x, h.srow_y, h.srow_z].map(|r| r.map(f64::from));
        let m = Matrix3::new(
            r[0][0], r[0][1], r[0][2], r[1][0], r[1][1], r[1][2], r[2][0], r[2][1], r[2][2],
        );
        (Vec3::new(r[0][3], r[1][3], r[2][3]), m, "sform")
    } else if h.qform_code > 0 {
        let (b, c, d) = (
            f64::from(h.quatern_b),
            f64::from(h.quatern_c),
            f64::from(h.quatern_d),
        );
        let a = (1.0 - (b * b + c * c + d * d)).max(0.0).sqrt();
        let rot = Matrix3::new(
            a * a + b * b - c * c - d * d,
            2.0 * (b * c - a * d),
            2.0 * (b * d + a * c),
            2.0 * (b * c + a * d),
            a * a + c * c - b * b - d * d,
            2.0 * (c * d - a * b),
            2.0 * (b * d - a * c),
            2.0 * (c * d + a * b),
            a * a + d * d - c * c - b * b,
        );
        let qfac = if h.pixdim[0] < 0.0 { -1.0 } else { 1.0 };
        let s = |i: usize| f64::from(h.pixdim[i]).abs();
        let m = rot * Matrix3::from_diagonal(&Vector3::new(s(1), s(2), qfac * s(3)));
        let o = Vec3::new(
            f64::from(h.quatern_x),
            f64::from(h.quatern_y),
            f64::from(h.quatern_z),
        );
        (o, m, "qform")
    } else {
        let s = |i: usize| f64::from(h.pixdim[i]).abs();
        let m = Matrix3::from_diagonal(&Vector3::new(s(1), s(2), s(3)));
        (Vec3::zeros(), m, "pixdim")
    };
    let m = m * mm;
    let origin = origin * mm;
    let axes = [0, 1, 2].map(|c| Vec3::new(m[(0, c)], m[(1, c)], m[(2, c)]));
    let finite = origin.iter().chain(m.iter()).all(|v| v.is_finite());
    let volume = m.determinant().abs();
    let longest = axes.iter().map(|a| a.norm()).fold(0.0, f64::max);
    if finite && longest > 1e3 {
        return Err(err(format!(
            "the NIfTI header puts voxels {longest:.0} mm apart ({how}, space unit {}): not an \
             image of a heart; check its units (xyzt_units)",
            ["unknown", "metres", "mm", "microns"][usize::from(h.xyzt_units & 3)]
        )));
    }
    let flat = volume.is_nan() || volume <= 1e-9 * longest.powi(3);
    if !finite || flat {
        return Err(err(format!(
            "the NIfTI header's voxel placement ({how}) is degenerate: voxel steps {:?} mm",
            axes.map(|a| [a.x, a.y, a.z])
        )));
    }
    Ok((origin, axes, how))
}

pub(super) fn read_labels(
    data: &[u8],
    kind: NiftiType,
    order: nifti::Endianness,
    scale: Option<(f64, f64)>,
) -> Result<Vec<u16>> {
    let width = value_width(kind)?;
    let big = order == nifti::Endianness::Big;
    let mut out = Vec::with_capacity(data.len() / width);
    let mut distinct: Vec<u16> = Vec::new();
    for (n, raw) in data.chunks_exact(width).enumerate() {
        let mut b = [0u8; 8];
        b[..width].copy_from_slice(raw);
        if big {
            b[..width].reverse();
        }
        let v = match kind {
            NiftiType::Uint8 => f64::from(b[0]),
            NiftiType::Int8 => f64::from(b[0] as i8),
            NiftiType::Int16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            NiftiType::Uint16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            NiftiType::Int32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            NiftiType::Uint32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            NiftiType::Float32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            NiftiType::Int64 => i64::from_le_bytes(b) as f64,
            NiftiType::Uint64 => u64::from_le_bytes(b) as f64,
            _ => f64::from_le_bytes(b),
        };
        let v = scale.map_or(v, |(s, i)| v * s + i);
        let label = v.round();
        if !(label.is_finite() && (label - v).abs() <= 1e-3 && (0.0..=65535.0).contains(&label)) {
            return Err(not_labels(format!(
                "voxel {n} holds {v}, not a whole-number label"
            )));
        }
        let label = label as u16;
        if label != 0 && !distinct.contains(&label) {
            distinct.push(label);
            if distinct.len() > MAX_LABELS {
                return Err(not_labels(format!(
                    "it holds more than {MAX_LABELS} values"
                )));
            }
        }
        out.push(label);
    }
    Ok(out)
}

/// What the refusal of an image says, whatever the format (the NRRD and SEG readers retitle it).
pub(super) const IMAGE_NOT_LABELS: &str = "is an image, not a label map";

fn not_labels(why: String) -> CoreError {
    err(format!(
        "this NIfTI {IMAGE_NOT_LABELS} (segmentation): {why}; open the segmentation (background \
         0, one whole number per structure)"
    ))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A NIfTI-1 file (uint8 labels) with the given sform rows, written field by field after the
    /// NIfTI-1 specification (nifti1.h) so that the reader is checked against the layout rather
    /// than against itself.
    pub(crate) fn nifti_bytes(
        dims: &[u16],
        sform: Option<[[f32; 4]; 3]>,
        voxels: &[u8],
    ) -> Vec<u8> {
        let mut h = vec![0u8; 352];
        h[0..4].copy_from_slice(&348i32.to_le_bytes());
        let mut dim = [1u16; 8];
        dim[0] = dims.len() as u16;
        dim[1..=dims.len()].copy_from_slice(dims);
        for (n, d) in dim.iter().enumerate() {
            h[40 + 2 * n..42 + 2 * n].copy_from_slice(&d.to_le_bytes());
        }
        h[70..72].copy_from_slice(&2i16.to_le_bytes()); // uint8
        h[72..74].copy_from_slice(&8i16.to_le_bytes());
        let pixdim = [1.0f32, 1.5, 1.5, 10.0, 1.0, 0.0, 0.0, 0.0];
        for (n, p) in pixdim.iter().enumerate() {
            h[76 + 4 * n..80 + 4 * n].copy_from_slice(&p.to_le_bytes());
        }
        h[108..112].copy_from_slice(&352f32.to_le_bytes());
        h[123] = 2; // mm
        if let Some(rows) = sform {
            h[254..256].copy_from_slice(&1i16.to_le_bytes());
            for (r, row) in rows.iter().enumerate() {
                for (c, v) in row.iter().enumerate() {
                    let at = 280 + 16 * r + 4 * c;
                    h[at..at + 4].copy_from_slice(&v.to_le_bytes());
                }
            }
        }
        h[344..348].copy_from_slice(b"n+1\0");
        h.extend_from_slice(voxels);
        h
    }

    #[test]
    fn sform_places_voxels_in_mm() {
        let rows = [
            [0.0, 2.0, 0.0, 5.0],
            [1.5, 0.0, 0.0, -3.0],
            [0.0, 0.0, 8.0, 1.0],
        ];
        let bytes = nifti_bytes(&[2, 3, 2], Some(rows), &[1; 12]);
        let v = read_label_volume(&bytes).unwrap();
        assert_eq!(v.dims, [2, 3, 2]);
        assert_eq!(v.placement, "sform");
        let p = v.world([1.0, 2.0, 1.0]);
        assert!((p - Vec3::new(9.0, -1.5, 9.0)).norm() < 1e-9, "{p:?}");
        assert_eq!(v.spacing(), [1.5, 2.0, 8.0]);
    }

    #[test]
    fn without_sform_or_qform_the_spacings_scale_the_grid() {
        let bytes = nifti_bytes(&[2, 2, 2], None, &[0, 1, 2, 3, 0, 1, 2, 3]);
        let v = read_label_volume(&bytes).unwrap();
        assert_eq!(v.placement, "pixdim");
        assert!((v.world([1.0, 1.0, 1.0]) - Vec3::new(1.5, 1.5, 10.0)).norm() < 1e-9);
        assert_eq!(v.labels, vec![0, 1, 2, 3, 0, 1, 2, 3]);
    }

    #[test]
    fn qform_rotation_and_metres() {
        let mut bytes = nifti_bytes(&[2, 2, 2], None, &[0; 8]);
        bytes[252..254].copy_from_slice(&1i16.to_le_bytes());
        // 90 degrees about z: quaternion (cos 45, 0, 0, sin 45).
        let s = std::f32::consts::FRAC_1_SQRT_2;
        for (n, v) in [0.0f32, 0.0, s, 0.01, 0.02, 0.03].iter().enumerate() {
            bytes[256 + 4 * n..260 + 4 * n].copy_from_slice(&v.to_le_bytes());
        }
        bytes[123] = 1; // metres: pixdim 1.5 m would be absurd, so scale pixdim down
        for (n, p) in [1.0f32, 0.0015, 0.0015, 0.01].iter().enumerate() {
            bytes[76 + 4 * n..80 + 4 * n].copy_from_slice(&p.to_le_bytes());
        }
        let v = read_label_volume(&bytes).unwrap();
        assert_eq!(v.placement, "qform");
        let p = v.world([1.0, 0.0, 1.0]);
        // i steps along +y (rotated), k along z; origin (10, 20, 30) mm.
        assert!((p - Vec3::new(10.0, 21.5, 40.0)).norm() < 1e-3, "{p:?}");
    }

    #[test]
    fn hostile_headers_are_refused_with_reasons() {
        let good = nifti_bytes(&[4, 4, 2], None, &[0; 32]);
        let truncated = &good[..good.len() - 5];
        let e = read_label_volume(truncated).unwrap_err().to_string();
        assert!(e.contains("truncated"), "{e}");
        let mut huge = good.clone();
        huge[42..44].copy_from_slice(&65535u16.to_le_bytes());
        huge[44..46].copy_from_slice(&65535u16.to_le_bytes());
        assert!(read_label_volume(&huge)
            .unwrap_err()
            .to_string()
            .contains("truncated"));
        let mut two = good.clone();
        two[0..4].copy_from_slice(&540i32.to_be_bytes());
        two[4..8].copy_from_slice(b"n+2\0");
        assert!(read_label_volume(&two)
            .unwrap_err()
            .to_string()
            .contains("NIfTI-2"));
        let mut text = b"contour,x,y,z\n".repeat(40);
        text[344..348].copy_from_slice(b"n+1\0");
        assert_eq!(magic(&text), None, "the magic alone is not enough");
        let mut pair = good.clone();
        pair[344..348].copy_from_slice(b"ni1\0");
        assert!(read_label_volume(&pair)
            .unwrap_err()
            .to_string()
            .contains(".img"));
        let mut image = nifti_bytes(&[2, 2, 2], None, &[0; 32]);
        image[70..72].copy_from_slice(&16i16.to_le_bytes()); // float32: 8 values of 4 bytes
        image[72..74].copy_from_slice(&32i16.to_le_bytes());
        image[352..356].copy_from_slice(&0.37f32.to_le_bytes());
        let e = read_label_volume(&image).unwrap_err().to_string();
        assert!(e.contains("not a label map"), "{e}");
        let mut offset = good.clone();
        offset[108..112].copy_from_slice(&1e9f32.to_le_bytes());
        assert!(read_label_volume(&offset)
            .unwrap_err()
            .to_string()
            .contains("byte"));
        let mut flat = nifti_bytes(&[4, 4, 2], Some([[1.0, 0.0, 0.0, 0.0]; 3]), &[0; 32]);
        assert!(read_label_volume(&flat)
            .unwrap_err()
            .to_string()
            .contains("degenerate"));
        flat[280..284].copy_from_slice(&f32::NAN.to_le_bytes());
        assert!(read_label_volume(&flat).is_err());
        let mut five = good.clone();
        five[40..42].copy_from_slice(&5u16.to_le_bytes());
        five[50..52].copy_from_slice(&3u16.to_le_bytes());
        assert!(read_label_volume(&five)
            .unwrap_err()
            .to_string()
            .contains("per voxel"));
        let mut bad_type = good;
        bad_type[70..72].copy_from_slice(&128i16.to_le_bytes());
        assert!(read_label_volume(&bad_type).is_err());
        // Every prefix of a valid file fails cleanly.
        let file = nifti_bytes(&[3, 3, 2], None, &[1; 18]);
        for n in 0..file.len() {
            assert!(read_label_volume(&file[..n]).is_err());
        }
    }
}
