//! DICOM Segmentation objects (SEG: PS3.3 A.51, C.8.20 Segmentation module, C.7.6.16
//! multi-frame functional groups): the label maps that OHIF, 3D Slicer's DICOM export, highdicom
//! and AI segmentation services write into a PACS. A SEG is a stack of one-bit frames (or 8-bit
//! "fractional" ones), each one segment's mask on one image plane: the frame's
//! PlanePositionSequence gives its ImagePositionPatient, the shared (or per-frame)
//! PlaneOrientationSequence and PixelMeasuresSequence its orientation and pixel spacing, and its
//! SegmentIdentificationSequence which segment it shows. Frames where a segment is absent are
//! usually left out, so the planes are gathered by their height along the stack's normal and
//! laid on a regular grid; the result is a label map like a NIfTI's (segment number = label),
//! read by the same outlining ([`super::read_volume_study`]), in DICOM patient coordinates (LPS,
//! mm). Pixel (column c, row r) of a frame is ImagePositionPatient + c column spacings along the
//! rows + r row spacings along the columns, as for any DICOM image.

use super::nrrd::SegmentNames;
use super::volume::{err, LabelVolume, Space};
use crate::error::Result;
use crate::geometry::{v3, Vec3};
use crate::io::dicom_read::{self, rle, DataSet, Tag, Value};
use crate::io::FrameChoice;
use std::borrow::Cow;

mod tag {
    use super::Tag;
    pub const TRANSFER_SYNTAX: Tag = (0x0002, 0x0010);
    pub const SOP_CLASS_UID: Tag = (0x0008, 0x0016);
    pub const MODALITY: Tag = (0x0008, 0x0060);
    pub const SPACING_BETWEEN_SLICES: Tag = (0x0018, 0x0088);
    pub const IMAGE_POSITION: Tag = (0x0020, 0x0032);
    pub const IMAGE_ORIENTATION: Tag = (0x0020, 0x0037);
    pub const FRAME_CONTENT: Tag = (0x0020, 0x9111);
    pub const PLANE_POSITION: Tag = (0x0020, 0x9113);
    pub const PLANE_ORIENTATION: Tag = (0x0020, 0x9116);
    pub const TEMPORAL_POSITION_INDEX: Tag = (0x0020, 0x9128);
    pub const NUMBER_OF_FRAMES: Tag = (0x0028, 0x0008);
    pub const ROWS: Tag = (0x0028, 0x0010);
    pub const COLUMNS: Tag = (0x0028, 0x0011);
    pub const PIXEL_SPACING: Tag = (0x0028, 0x0030);
    pub const BITS_ALLOCATED: Tag = (0x0028, 0x0100);
    pub const PIXEL_MEASURES: Tag = (0x0028, 0x9110);
    pub const SEGMENT_SEQUENCE: Tag = (0x0062, 0x0002);
    pub const SEGMENT_NUMBER: Tag = (0x0062, 0x0004);
    pub const SEGMENT_LABEL: Tag = (0x0062, 0x0005);
    pub const SEGMENT_IDENTIFICATION: Tag = (0x0062, 0x000A);
    pub const REFERENCED_SEGMENT_NUMBER: Tag = (0x0062, 0x000B);
    pub const MAX_FRACTIONAL_VALUE: Tag = (0x0062, 0x000E);
    pub const SEGMENTATION_TYPE: Tag = (0x0062, 0x0001);
    pub const PIXEL_PADDING_VALUE: Tag = (0x0028, 0x0120);
    pub const SHARED_GROUPS: Tag = (0x5200, 0x9229);
    pub const PER_FRAME_GROUPS: Tag = (0x5200, 0x9230);
    pub const PIXEL_DATA: Tag = (0x7FE0, 0x0010);
    /// The sequences read, which implicit VR files do not mark as such.
    pub const SEQUENCES: [Tag; 8] = [
        SEGMENT_SEQUENCE,
        SHARED_GROUPS,
        PER_FRAME_GROUPS,
        PLANE_ORIENTATION,
        PLANE_POSITION,
        PIXEL_MEASURES,
        SEGMENT_IDENTIFICATION,
        FRAME_CONTENT,
    ];
}

/// Segmentation Storage (PS3.4 B.5).
pub const SEGMENTATION_STORAGE: &str = "1.2.840.10008.5.1.4.1.1.66.4";

/// Label Map Segmentation Storage (DICOM 2024c, Supplement 243).
pub const LABEL_MAP_SEGMENTATION_STORAGE: &str = "1.2.840.10008.5.1.4.1.1.66.7";

/// Transfer syntaxes whose pixel data are raw little-endian bytes (implicit, explicit VR).
const NATIVE_LITTLE: [&str; 2] = ["1.2.840.10008.1.2", "1.2.840.10008.1.2.1"];

/// At most this many planes on the grid, gaps included (a cardiac stack has 8-20; a wild
/// position must not make a grid of millions of empty slices).
const MAX_PLANES: usize = 2048;
/// At most this many voxels in the label map (2 bytes each in memory, a browser worker's too).
const MAX_VOXELS: usize = 1 << 26;

/// Planes whose heights along the normal differ by less than this (mm) are one plane.
const SAME_PLANE_MM: f64 = 0.01;

/// Whether `bytes` is a DICOM Segmentation object (modality SEG or its SOP class), judged from
/// its header only.
pub fn is_seg(bytes: &[u8]) -> bool {
    if !crate::io::rtstruct::is_dicom(bytes) {
        return false;
    }
    let Ok(set) = dicom_read::read_header(bytes, &[]) else {
        return false;
    };
    set.text(tag::MODALITY).as_deref() == Some("SEG")
        || matches!(
            set.text(tag::SOP_CLASS_UID).as_deref(),
            Some(SEGMENTATION_STORAGE | LABEL_MAP_SEGMENTATION_STORAGE)
        )
}

fn us(set: &DataSet, t: Tag) -> Option<u16> {
    let b = set.bytes(t)?;
    Some(u16::from_le_bytes([*b.first()?, *b.get(1)?]))
}

fn ul(set: &DataSet, t: Tag) -> Option<u32> {
    let b = set.bytes(t)?;
    Some(u32::from_le_bytes(b.get(..4)?.try_into().ok()?))
}

/// The first item of functional group `group` in a frame's per-frame item, else in the shared
/// one: the standard lets each group be in either place.
fn group<'s, 'a>(
    frame: Option<&'s DataSet<'a>>,
    shared: Option<&'s DataSet<'a>>,
    group: Tag,
) -> Option<&'s DataSet<'a>> {
    frame
        .and_then(|f| f.items(group).first())
        .or_else(|| shared.and_then(|s| s.items(group).first()))
}

/// One frame's place: which plane, which segment, which time.
struct Frame {
    /// Its number in the file (from 0): where its pixels are.
    number: usize,
    position: Vec3,
    segment: u16,
    time: u32,
}

/// The plane every frame shares: its row and column directions and pixel spacing (between
/// rows, between columns).
#[derive(Clone, Copy, PartialEq)]
struct Plane {
    row: Vec3,
    col: Vec3,
    spacing: [f64; 2],
}

fn plane_of(frame: Option<&DataSet>, shared: Option<&DataSet>, n: usize) -> Result<Plane> {
    let orientation = group(frame, shared, tag::PLANE_ORIENTATION)
        .and_then(|g| g.numbers(tag::IMAGE_ORIENTATION))
        .ok_or_else(|| err(format!("frame {n} has no ImageOrientationPatient")))?;
    let spacing = group(frame, shared, tag::PIXEL_MEASURES)
        .and_then(|g| g.numbers(tag::PIXEL_SPACING))
        .ok_or_else(|| err(format!("frame {n} has no PixelSpacing")))?;
    let [r1, r2, r3, c1, c2, c3]: [f64; 6] = orientation[..]
        .try_into()
        .map_err(|_| err("ImageOrientationPatient needs 6 numbers"))?;
    let [dr, dc]: [f64; 2] = spacing[..]
        .try_into()
        .map_err(|_| err("PixelSpacing needs 2 numbers"))?;
    let (row, col) = (v3(r1, r2, r3), v3(c1, c2, c3));
    let (Some(row), Some(col)) = (row.try_normalize(1e-6), col.try_normalize(1e-6)) else {
        return Err(err("ImageOrientationPatient's directions are degenerate"));
    };
    if row.cross(&col).norm() < 0.5 {
        return Err(err("ImageOrientationPatient's directions are degenerate"));
    }
    if !(dr > 0.0 && dc > 0.0 && dr < 1e3 && dc < 1e3) {
        return Err(err(format!(
            "PixelSpacing {dr} \\ {dc} is not a spacing in mm"
        )));
    }
    Ok(Plane {
        row,
        col,
        spacing: [dr, dc],
    })
}

fn same_plane(a: &Plane, b: &Plane) -> bool {
    (a.row - b.row).norm() < 1e-4
        && (a.col - b.col).norm() < 1e-4
        && (a.spacing[0] - b.spacing[0]).abs() < 1e-4 * a.spacing[0]
        && (a.spacing[1] - b.spacing[1]).abs() < 1e-4 * a.spacing[1]
}

/// How the frames' pixels say which segment a pixel is in.
#[derive(Clone, Copy)]
enum Coding {
    /// One bit per pixel (bit 0 of each byte first, frames packed end to end with no padding:
    /// PS3.5 8.1.1), the frame's segment where set.
    Binary,
    /// A byte per pixel, the frame's segment over half the maximum fractional value.
    Fractional { threshold: u16 },
    /// LABELMAP (DICOM 2024c): a frame holds every segment of its plane, each pixel the number
    /// of its segment (8 or 16 bits), 0 and the pixel padding value being background.
    LabelMap { wide: bool, padding: Option<u16> },
}

impl Coding {
    /// The segment pixel `index` (counted over all frames) is in, if any; `segment`: the frame's.
    fn segment_at(self, data: &[u8], index: usize, segment: u16) -> Option<u16> {
        let value = match self {
            Coding::Binary => return (data[index / 8] >> (index % 8) & 1 == 1).then_some(segment),
            Coding::Fractional { threshold } => {
                return (u16::from(data[index]) > threshold).then_some(segment)
            }
            Coding::LabelMap { wide: false, .. } => u16::from(data[index]),
            Coding::LabelMap { wide: true, .. } => {
                u16::from_le_bytes([data[2 * index], data[2 * index + 1]])
            }
        };
        match self {
            Coding::LabelMap { padding, .. } if value != 0 && Some(value) != padding => Some(value),
            _ => None,
        }
    }

    /// Bytes of pixel data `pixels` pixels take.
    fn bytes_for(self, pixels: usize) -> Option<usize> {
        match self {
            Coding::Binary => Some(pixels.div_ceil(8)),
            Coding::Fractional { .. } | Coding::LabelMap { wide: false, .. } => Some(pixels),
            Coding::LabelMap { wide: true, .. } => pixels.checked_mul(2),
        }
    }
}

/// What a SEG holds as a label map.
pub struct SegRead {
    pub volume: LabelVolume,
    /// Segment names by number (= label).
    pub names: SegmentNames,
    /// Pixels two segments claimed: each keeps the first frame's segment (a label map holds one
    /// label per voxel).
    pub overlaps: usize,
    /// Single planes in another orientation than the stack's (long-axis views segmented in the
    /// same object), each a one-slice label map of the same time frame, in the file's order.
    pub views: Vec<LabelVolume>,
    /// Frames neither on the stack nor on a single plane of their own, not read.
    pub aside: usize,
}

/// Frames of one orientation laid on one grid.
struct Group {
    plane: Plane,
    frames: Vec<Frame>,
    /// Each frame's plane on the grid.
    index: Vec<usize>,
    origin: Vec3,
    step: Vec3,
    depth: usize,
}

/// Where every frame of a SEG goes, read from its header alone.
struct Layout {
    rows: usize,
    cols: usize,
    count: usize,
    coding: Coding,
    names: SegmentNames,
    stack: Group,
    views: Vec<Group>,
    aside: usize,
    /// TemporalPositionIndex values present, ascending: frame t of the file is `times[t]`.
    times: Vec<u32>,
}

/// Voxels along i, j, k of a SEG's stack and its number of time frames, from its header alone
/// (the bytes may stop where the pixel data begins); None when it is not a SEG that reads.
pub fn grid(bytes: &[u8]) -> Option<([usize; 3], usize)> {
    let set = dicom_read::read_header(bytes, &tag::SEQUENCES).ok()?;
    let l = layout(&set).ok()?;
    Some(([l.cols, l.rows, l.stack.depth], l.times.len()))
}

/// The label map of a SEG (time frame `want`: index from 0 in TemporalPositionIndex order; none:
/// the first).
pub fn read_seg_volume(bytes: &[u8], want: Option<&FrameChoice>) -> Result<SegRead> {
    let set = dicom_read::read_file(bytes, &tag::SEQUENCES)
        .map_err(|e| err(format!("DICOM SEG: {e}")))?;
    let l = layout(&set)?;
    let rle = set.text(tag::TRANSFER_SYNTAX).as_deref() == Some(rle::RLE_LOSSLESS);
    let data: Cow<[u8]> = match set.get(tag::PIXEL_DATA) {
        Some(Value::Bytes(b)) if !rle => Cow::Borrowed(*b),
        Some(Value::Fragments(items)) if rle => Cow::Owned(decode_rle(items, &l)?),
        Some(_) => {
            return Err(err(
                "DICOM SEG with compressed pixel data other than RLE: export it uncompressed",
            ))
        }
        None => return Err(err("DICOM SEG without pixel data (7FE0,0010)")),
    };
    let data = &data[..];
    let (rows, cols, count) = (l.rows, l.cols, l.count);
    let needed = (rows * cols)
        .checked_mul(count)
        .and_then(|n| l.coding.bytes_for(n))
        .ok_or_else(|| err("DICOM SEG frames too large"))?;
    if data.len() < needed {
        return Err(err(format!(
            "the file is truncated: {count} frames of {cols} x {rows} pixels need {needed} bytes \
             of pixel data, {} are there",
            data.len()
        )));
    }
    let chosen = match want {
        Some(w) => (0..l.times.len())
            .find(|&t| w.matches(&t.to_string()))
            .ok_or_else(|| {
                err(format!(
                    "no frame {} in the DICOM SEG (its time frames: 0 to {})",
                    w.label(),
                    l.times.len() - 1
                ))
            })?,
        None => 0,
    };
    let paint = |g: &Group| paint(g, &l, chosen, data);
    let (volume, overlaps) = paint(&l.stack);
    let views = l.views.iter().map(|g| paint(g).0).collect();
    Ok(SegRead {
        volume,
        names: l.names,
        overlaps,
        views,
        aside: l.aside,
    })
}

/// The frames of an RLE SEG (`items`: the basic offset table, then one fragment per frame, as
/// PS3.5 A.4.2 has it) as native pixel data: a binary SEG's frames packed end to end, bit after
/// bit, as an uncompressed one stores them (each RLE frame starts on a byte of its own).
fn decode_rle(items: &[&[u8]], l: &Layout) -> Result<Vec<u8>> {
    let frames = items.get(1..).unwrap_or_default();
    if frames.len() != l.count {
        return Err(err(format!(
            "the RLE DICOM SEG holds {} pixel data fragments for {} frames (one each expected)",
            frames.len(),
            l.count
        )));
    }
    let pixels = l.rows * l.cols;
    let (segments, length) = match l.coding {
        Coding::Binary => (1, pixels.div_ceil(8)),
        Coding::Fractional { .. } | Coding::LabelMap { wide: false, .. } => (1, pixels),
        Coding::LabelMap { wide: true, .. } => (2, pixels),
    };
    let total = (pixels.checked_mul(l.count))
        .and_then(|n| l.coding.bytes_for(n))
        .filter(|&n| n <= MAX_VOXELS.saturating_mul(2))
        .ok_or_else(|| err("DICOM SEG frames too large"))?;
    let mut out = vec![0u8; total];
    for (f, fragment) in frames.iter().enumerate() {
        let frame = rle::decode_frame(fragment, segments, length)
            .map_err(|e| err(format!("frame {} of the DICOM SEG: {e}", f + 1)))?;
        match l.coding {
            Coding::Binary => {
                for p in (0..pixels).filter(|p| frame[p / 8] >> (p % 8) & 1 == 1) {
                    let bit = f * pixels + p;
                    out[bit / 8] |= 1 << (bit % 8);
                }
            }
            _ => {
                let size = frame.len();
                out[f * size..(f + 1) * size].copy_from_slice(&frame);
            }
        }
    }
    Ok(out)
}

/// Where the SEG's frames go: the stack is the orientation most frames share; another
/// orientation whose frames lie on one plane is a long-axis view; frames of any other are set
/// aside.
fn layout(set: &DataSet) -> Result<Layout> {
    if let Some(ts) = set.text(tag::TRANSFER_SYNTAX) {
        if !NATIVE_LITTLE.contains(&ts.as_str()) && ts != rle::RLE_LOSSLESS {
            return Err(err(format!(
                "DICOM SEG in transfer syntax {ts} (compressed other than RLE, or big endian): \
                 export it uncompressed (explicit VR little endian)"
            )));
        }
    }
    let rows = us(set, tag::ROWS).ok_or_else(|| err("DICOM SEG without Rows (0028,0010)"))?;
    let cols = us(set, tag::COLUMNS).ok_or_else(|| err("DICOM SEG without Columns (0028,0011)"))?;
    let (rows, cols) = (usize::from(rows), usize::from(cols));
    let count = set
        .text(tag::NUMBER_OF_FRAMES)
        .and_then(|t| t.trim().parse::<usize>().ok())
        .ok_or_else(|| err("DICOM SEG without NumberOfFrames (0028,0008)"))?;
    let bits = us(set, tag::BITS_ALLOCATED).unwrap_or(1);
    let label_map = set.text(tag::SEGMENTATION_TYPE).as_deref() == Some("LABELMAP")
        || set.text(tag::SOP_CLASS_UID).as_deref() == Some(LABEL_MAP_SEGMENTATION_STORAGE);
    let coding = match (label_map, bits) {
        (false, 1) => Coding::Binary,
        (false, 8) => Coding::Fractional {
            threshold: us(set, tag::MAX_FRACTIONAL_VALUE).unwrap_or(255) / 2,
        },
        (true, 8 | 16) => Coding::LabelMap {
            wide: bits == 16,
            padding: us(set, tag::PIXEL_PADDING_VALUE),
        },
        (false, _) => {
            return Err(err(format!(
                "DICOM SEG with {bits} bits per pixel: a binary (1) or fractional (8) one is read"
            )))
        }
        (true, _) => {
            return Err(err(format!(
                "DICOM label map SEG with {bits} bits per pixel: 8 or 16 are read"
            )))
        }
    };
    if rows == 0 || cols == 0 || count == 0 {
        return Err(err(format!(
            "DICOM SEG of {count} frames of {cols} x {rows} pixels: nothing to read"
        )));
    }
    let names: SegmentNames = set
        .items(tag::SEGMENT_SEQUENCE)
        .iter()
        .filter_map(|s| {
            let n = us(s, tag::SEGMENT_NUMBER)?;
            Some((n, s.text(tag::SEGMENT_LABEL).unwrap_or_default()))
        })
        .collect();
    let shared = set.items(tag::SHARED_GROUPS).first();
    let per_frame = set.items(tag::PER_FRAME_GROUPS);
    if per_frame.len() != count {
        return Err(err(format!(
            "DICOM SEG of {count} frames describes {} in its PerFrameFunctionalGroupsSequence",
            per_frame.len()
        )));
    }
    let planes = per_frame
        .iter()
        .enumerate()
        .map(|(n, item)| plane_of(Some(item), shared, n + 1))
        .collect::<Result<Vec<Plane>>>()?;
    // Frame numbers by orientation, the most shared first (the first met among equals).
    let mut kinds: Vec<(Plane, Vec<usize>)> = Vec::new();
    for (n, p) in planes.iter().enumerate() {
        match kinds.iter_mut().find(|(q, _)| same_plane(p, q)) {
            Some((_, members)) => members.push(n),
            None => kinds.push((*p, vec![n])),
        }
    }
    kinds.sort_by_key(|(_, members)| std::cmp::Reverse(members.len()));
    let mut kinds = kinds.into_iter();
    let (plane, members) = kinds
        .next()
        .ok_or_else(|| err("DICOM SEG without frames"))?;
    let frames_of = |members: &[usize]| {
        members
            .iter()
            .map(|&n| frame_of(n, &per_frame[n], shared, coding))
            .collect::<Result<Vec<Frame>>>()
    };
    let stack = lay(plane, frames_of(&members)?, set)?;
    let pixels = rows * cols;
    if stack.depth > MAX_PLANES || pixels.saturating_mul(stack.depth) > MAX_VOXELS {
        return Err(err(format!(
            "the DICOM SEG's planes span {} slices of {cols} x {rows} pixels: too large a label map",
            stack.depth
        )));
    }
    let mut views = Vec::new();
    let mut aside = 0;
    for (plane, members) in kinds {
        match frames_of(&members).and_then(|f| lay(plane, f, set)) {
            Ok(view) if view.depth == 1 => views.push(view),
            _ => aside += members.len(),
        }
    }
    let mut times: Vec<u32> = std::iter::once(&stack)
        .chain(&views)
        .flat_map(|g| g.frames.iter().map(|f| f.time))
        .collect();
    times.sort_unstable();
    times.dedup();
    Ok(Layout {
        rows,
        cols,
        count,
        coding,
        names,
        stack,
        views,
        aside,
        times,
    })
}

/// Frame `n`'s place (its per-frame functional groups `item`).
fn frame_of(n: usize, item: &DataSet, shared: Option<&DataSet>, coding: Coding) -> Result<Frame> {
    let position = group(Some(item), shared, tag::PLANE_POSITION)
        .and_then(|g| g.numbers(tag::IMAGE_POSITION))
        .and_then(|p| <[f64; 3]>::try_from(&p[..]).ok())
        .ok_or_else(|| err(format!("frame {} has no ImagePositionPatient", n + 1)))?;
    let segment = match coding {
        // A label map's frame holds its plane's every segment.
        Coding::LabelMap { .. } => 0,
        _ => group(Some(item), shared, tag::SEGMENT_IDENTIFICATION)
            .and_then(|g| us(g, tag::REFERENCED_SEGMENT_NUMBER))
            .filter(|&s| s > 0)
            .ok_or_else(|| err(format!("frame {} names no segment", n + 1)))?,
    };
    let time = group(Some(item), None, tag::FRAME_CONTENT)
        .and_then(|g| ul(g, tag::TEMPORAL_POSITION_INDEX))
        .unwrap_or(1);
    Ok(Frame {
        number: n,
        position: v3(position[0], position[1], position[2]),
        segment,
        time,
    })
}

/// `frames` of one orientation laid on a grid ([`stack`]).
fn lay(plane: Plane, frames: Vec<Frame>, set: &DataSet) -> Result<Group> {
    let normal = plane.row.cross(&plane.col).normalize();
    let (index, origin, step) = stack(&frames, &normal, &plane, set)?;
    let depth = index.iter().max().map_or(1, |k| k + 1);
    Ok(Group {
        plane,
        frames,
        index,
        origin,
        step,
        depth,
    })
}

/// The label map of group `g` at time frame `chosen` (an index into `l.times`), and the pixels
/// two segments claimed.
fn paint(g: &Group, l: &Layout, chosen: usize, data: &[u8]) -> (LabelVolume, usize) {
    let pixels = l.rows * l.cols;
    let mut labels = vec![0u16; pixels * g.depth];
    let mut labelled = vec![false; l.times.len()];
    let mut overlaps = 0usize;
    for (f, &k) in g.frames.iter().zip(&g.index) {
        let t = l.times.binary_search(&f.time).unwrap_or(0);
        let first = f.number * pixels;
        for p in 0..pixels {
            let Some(segment) = l.coding.segment_at(data, first + p, f.segment) else {
                continue;
            };
            labelled[t] = true;
            if t != chosen {
                continue;
            }
            let v = &mut labels[k * pixels + p];
            if *v == 0 {
                *v = segment;
            } else if *v != segment {
                overlaps += 1;
            }
        }
    }
    let labelled: Vec<usize> = (0..l.times.len()).filter(|&t| labelled[t]).collect();
    let axes = [
        g.plane.row * g.plane.spacing[1],
        g.plane.col * g.plane.spacing[0],
        g.step,
    ];
    let volume = LabelVolume::of_frame(
        [l.cols, l.rows, g.depth],
        (g.origin, axes, "frame positions (DICOM SEG, LPS)"),
        l.times.len(),
        (chosen, labels, labelled),
    )
    .in_space(Space::LPS);
    (volume, overlaps)
}

/// The grid's third axis: each frame's plane index (from the lowest plane along the normal, gaps
/// included), the origin (voxel (0, 0, 0) of the lowest plane) and the step from one plane to the
/// next. The planes' spacing is SpacingBetweenSlices when every plane lies on it, else the
/// smallest gap between distinct planes; the step is fitted to the frames' positions (a stack may be sheared: its
/// planes offset in plane from one to the next), and every frame must lie on it to a tenth of a
/// pixel.
fn stack(
    frames: &[Frame],
    normal: &Vec3,
    plane: &Plane,
    set: &DataSet,
) -> Result<(Vec<usize>, Vec3, Vec3)> {
    let first = frames[0].position;
    let heights: Vec<f64> = frames
        .iter()
        .map(|f| (f.position - first).dot(normal))
        .collect();
    let mut distinct: Vec<f64> = heights.clone();
    distinct.sort_by(f64::total_cmp);
    distinct.dedup_by(|a, b| (*a - *b).abs() < SAME_PLANE_MM);
    let lowest = distinct[0];
    let given = set
        .items(tag::SHARED_GROUPS)
        .first()
        .and_then(|g| g.items(tag::PIXEL_MEASURES).first())
        .and_then(|g| g.numbers(tag::SPACING_BETWEEN_SLICES))
        .and_then(|v| v.first().copied())
        .filter(|&s| s > SAME_PLANE_MM && s < 1e3);
    let smallest = distinct
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    let measured = if smallest.is_finite() { smallest } else { 1.0 };
    // SpacingBetweenSlices is often written wrong (the slice thickness, say): it is taken only
    // when every plane lies a whole number of it from the lowest; the planes' own smallest gap
    // otherwise.
    let on_grid = |spacing: f64| {
        distinct.iter().all(|h| {
            let k = (h - lowest) / spacing;
            (k - k.round()).abs() <= 0.1
        })
    };
    let spacing = given.filter(|&g| on_grid(g)).unwrap_or(measured);
    if !on_grid(spacing) {
        let off = distinct
            .iter()
            .find(|h| {
                let k = (*h - lowest) / spacing;
                (k - k.round()).abs() > 0.1
            })
            .map_or(0.0, |h| h - lowest);
        return Err(err(format!(
            "the DICOM SEG's planes are not evenly spaced ({off:.2} mm from the lowest, the \
             smallest gap being {spacing:.2} mm)"
        )));
    }
    let mut index = Vec::with_capacity(frames.len());
    for h in &heights {
        let k = (h - lowest) / spacing;
        if k.round() >= MAX_PLANES as f64 {
            return Err(err(format!(
                "the DICOM SEG's planes span over {MAX_PLANES} slices of {spacing:.2} mm"
            )));
        }
        index.push(k.round() as usize);
    }
    // Slices where no segment was drawn have no frame, but a stack is mostly drawn: a few
    // planes spread over thousands of positions are a damaged file, not a grid to allocate.
    let depth = index.iter().max().map_or(1, |k| k + 1);
    if depth > 2 * distinct.len() + 16 {
        return Err(err(format!(
            "the DICOM SEG's {} planes are spread over {depth} slice positions of {spacing:.2} mm",
            distinct.len()
        )));
    }
    // Least squares of position against plane index: the step and the origin.
    let n = frames.len() as f64;
    let k_mean = index.iter().sum::<usize>() as f64 / n;
    let p_mean = frames.iter().map(|f| f.position).sum::<Vec3>() / n;
    let (mut num, mut den) = (Vec3::zeros(), 0.0);
    for (f, &k) in frames.iter().zip(&index) {
        let dk = k as f64 - k_mean;
        num += (f.position - p_mean) * dk;
        den += dk * dk;
    }
    let step = if den > 0.0 {
        num / den
    } else {
        normal * spacing
    };
    let origin = p_mean - step * k_mean;
    let tolerance = 0.1 * plane.spacing[0].min(plane.spacing[1]);
    for (n, (f, &k)) in frames.iter().zip(&index).enumerate() {
        let off = (f.position - (origin + step * k as f64)).norm();
        if off > tolerance {
            return Err(err(format!(
                "frame {} of the DICOM SEG lies {off:.2} mm off the stack the others make: its \
                 planes do not form one grid",
                n + 1
            )));
        }
    }
    Ok((index, origin, step))
}

#[cfg(test)]
mod tests;
