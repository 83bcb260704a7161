//! NRRD label maps (`.nrrd`, 3D Slicer's `.seg.nrrd` segmentations): the format researchers and
//! modellers who segment in 3D Slicer save, read into the same [`LabelVolume`] as a NIfTI so the
//! tracing and the roles are shared.
//!
//! Coordinates are kept in the file's own space, in mm: Slicer writes LPS (`space:
//! left-posterior-superior`) and reads mesh files as LPS, so a mesh made from a `.seg.nrrd` lies
//! on its segmentation in Slicer. A `.seg.nrrd` whose segments overlap is 4D, one layer per
//! group of non-overlapping segments along its first axis: the layers are flattened, the first
//! layer keeping a voxel, each segment with its own label.

use nifti::{Endianness, NiftiType};

use super::volume::{err, only_frame, pick_frame, read_labels, value_width, LabelVolume, Space};
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::io::gzip;
use crate::io::FrameChoice;

/// Whether `bytes` start as a NRRD file (`NRRD0001` .. `NRRD0005`).
pub fn is_nrrd(bytes: &[u8]) -> bool {
    bytes.len() >= 8 && &bytes[..7] == b"NRRD000" && bytes[7].is_ascii_digit()
}

/// Longest header read (bytes): Slicer's segment metadata runs to a few kB.
const MAX_HEADER: usize = 1 << 20;

/// Segment names by the label each has in a map.
pub type SegmentNames = Vec<(u16, String)>;

/// A segment of a `.seg.nrrd` (its metadata): name, layer and label value in that layer.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    pub name: String,
    pub layer: usize,
    pub value: u16,
}

/// The label map of a NRRD file (frame `want` of a 4D time series), and the named segments of a
/// `.seg.nrrd` by the label each has in the returned map.
pub fn read_nrrd_volume(
    bytes: &[u8],
    want: Option<&FrameChoice>,
) -> Result<(LabelVolume, SegmentNames)> {
    let header_end = find_header_end(bytes)?;
    let text = std::str::from_utf8(&bytes[..header_end.0])
        .map_err(|_| err("the NRRD header is not text"))?;
    let h = Header::parse(text)?;
    let data = &bytes[header_end.1..];
    let kind = h.kind()?;
    let width = value_width(kind)?;
    let sizes = &h.sizes;
    let (spatial, layers, frames) = h.shape()?;
    let grid = [sizes[spatial[0]], sizes[spatial[1]], sizes[spatial[2]]];
    let count = sizes
        .iter()
        .try_fold(1usize, |n, &s| n.checked_mul(s))
        .and_then(|n| n.checked_mul(width))
        .ok_or_else(|| err(format!("the NRRD sizes {} are too large", join(sizes))))?;
    let raw = h.voxel_bytes(data, count)?;
    if raw.len() < count {
        return Err(err(format!(
            "the file is truncated: the header declares {} voxels of {width} byte(s) ({count} \
             bytes) but {} follow the header",
            join(sizes),
            raw.len()
        )));
    }
    // `byte skip: -1`: the voxels are the data's last bytes.
    let raw = if h.byte_skip == -1 {
        &raw[raw.len() - count..]
    } else {
        &raw[..count]
    };
    let order = if h.big_endian {
        Endianness::Big
    } else {
        Endianness::Little
    };
    let decode = |chunk: &[u8]| read_labels(chunk, kind, order, None).map_err(retitle);
    let segments = h.segments();
    let (picked, names) = if layers > 1 {
        let (labels, names) = flatten_layers(raw, layers, &decode, &segments)?;
        (only_frame(labels), names)
    } else {
        let picked = pick_frame(raw, frames, decode, want)?;
        let names = segments
            .iter()
            .filter(|s| s.layer == 0)
            .map(|s| (s.value, s.name.clone()))
            .collect();
        (picked, names)
    };
    let placed = h.placement(&spatial)?;
    let volume = LabelVolume::of_frame(grid, placed, frames, picked);
    let volume = match h.space_convention() {
        Some(space) => volume.in_space(space),
        None => volume,
    };
    Ok((volume, names))
}

/// Voxels along the three spatial axes and the number of time frames of a NRRD label map, from
/// its header alone (None: not a readable NRRD header).
pub fn grid(bytes: &[u8]) -> Option<([usize; 3], usize)> {
    let end = find_header_end(bytes).ok()?;
    let h = Header::parse(std::str::from_utf8(&bytes[..end.0]).ok()?).ok()?;
    let (spatial, _, frames) = h.shape().ok()?;
    Some((spatial.map(|a| h.sizes[a]), frames))
}

/// Where the header's text ends and the data begin (the first empty line).
fn find_header_end(bytes: &[u8]) -> Result<(usize, usize)> {
    let head = &bytes[..bytes.len().min(MAX_HEADER)];
    for (i, w) in head.windows(2).enumerate() {
        if w == b"\n\n" {
            return Ok((i, i + 2));
        }
        if w == b"\n\r" && head.get(i + 2) == Some(&b'\n') {
            return Ok((i, i + 3));
        }
    }
    Err(err(
        "the NRRD header has no end (an empty line before the data) in its first megabyte",
    ))
}

/// The image's values for `NIfTI is an image` errors, said of a NRRD.
fn retitle(e: CoreError) -> CoreError {
    match e {
        CoreError::Parse { line, message } => {
            CoreError::parse(line, message.replace("this NIfTI is", "this NRRD is"))
        }
        other => other,
    }
}

/// Labels of the layers of a `.seg.nrrd` merged into one map (first layer first): each (layer,
/// value) becomes its segment's number (index + 1), or a new number when no segment names it.
fn flatten_layers(
    raw: &[u8],
    layers: usize,
    decode: &impl Fn(&[u8]) -> Result<Vec<u16>>,
    segments: &[Segment],
) -> Result<(Vec<u16>, SegmentNames)> {
    let values = decode(raw)?;
    let voxels = values.len() / layers;
    let mut ids: Vec<((usize, u16), u16)> = segments
        .iter()
        .enumerate()
        .map(|(n, s)| ((s.layer, s.value), n as u16 + 1))
        .collect();
    let mut names: Vec<(u16, String)> = segments
        .iter()
        .enumerate()
        .map(|(n, s)| (n as u16 + 1, s.name.clone()))
        .collect();
    let mut next = segments.len() as u16 + 1;
    let mut out = vec![0u16; voxels];
    for (v, label) in out.iter_mut().enumerate() {
        for layer in 0..layers {
            let value = values[v * layers + layer];
            if value == 0 {
                continue;
            }
            let id = match ids.iter().find(|(k, _)| *k == (layer, value)) {
                Some((_, id)) => *id,
                None => {
                    if next == u16::MAX {
                        return Err(err("the NRRD layers hold too many distinct labels"));
                    }
                    ids.push(((layer, value), next));
                    names.push((next, format!("layer {layer} value {value}")));
                    next += 1;
                    next - 1
                }
            };
            *label = id;
            break;
        }
    }
    names.retain(|(id, _)| out.contains(id));
    Ok((out, names))
}

fn join(sizes: &[usize]) -> String {
    sizes
        .iter()
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join(" x ")
}

/// The header fields the reader uses.
#[derive(Debug, Default)]
struct Header {
    type_name: String,
    sizes: Vec<usize>,
    encoding: String,
    big_endian: bool,
    /// Per axis: its space direction (None: `none`, a non-spatial axis); None: no such field.
    directions: Option<Vec<Option<Vec3>>>,
    spacings: Option<Vec<f64>>,
    origin: Option<Vec3>,
    space: String,
    byte_skip: i64,
    line_skip: usize,
    /// `key:=value` pairs (Slicer's segment metadata).
    pairs: Vec<(String, String)>,
}

impl Header {
    fn parse(text: &str) -> Result<Header> {
        let mut h = Header {
            encoding: "raw".into(),
            ..Header::default()
        };
        let mut dimension = None;
        for (n, line) in text.lines().enumerate().skip(1) {
            let line = line.trim_end_matches('\r');
            let bad = |what: &str| CoreError::parse(n + 1, format!("NRRD header: {what}"));
            if line.starts_with('#') || line.trim().is_empty() {
                continue;
            }
            if let Some((k, v)) = line.split_once(":=") {
                h.pairs.push((k.trim().to_string(), v.trim().to_string()));
                continue;
            }
            let Some((field, value)) = line.split_once(':') else {
                return Err(bad(&format!("{line:?} is not a field")));
            };
            let value = value.trim();
            match field.trim().to_ascii_lowercase().as_str() {
                "type" => h.type_name = value.to_ascii_lowercase(),
                "dimension" => {
                    dimension = Some(value.parse::<usize>().map_err(|_| bad("bad dimension"))?)
                }
                "sizes" => {
                    h.sizes = value
                        .split_whitespace()
                        .map(|s| s.parse::<usize>().ok().filter(|&v| v > 0))
                        .collect::<Option<Vec<_>>>()
                        .ok_or_else(|| {
                            bad(&format!("sizes {value:?} must be whole numbers over 0"))
                        })?
                }
                "encoding" => h.encoding = value.to_ascii_lowercase(),
                "endian" => h.big_endian = value.eq_ignore_ascii_case("big"),
                "space" => h.space = value.to_ascii_lowercase(),
                "space directions" => {
                    h.directions = Some(
                        value
                            .split_whitespace()
                            .map(|d| match d {
                                "none" => Ok(None),
                                _ => vector(d).map(Some).ok_or_else(|| {
                                    bad(&format!("space direction {d:?} is not a vector"))
                                }),
                            })
                            .collect::<Result<Vec<_>>>()?,
                    )
                }
                "spacings" => {
                    h.spacings = Some(
                        value
                            .split_whitespace()
                            .map(|s| s.parse::<f64>().unwrap_or(f64::NAN))
                            .collect(),
                    )
                }
                "space origin" => {
                    h.origin =
                        Some(vector(value).ok_or_else(|| bad("space origin is not a vector"))?)
                }
                "byte skip" => h.byte_skip = value.parse().map_err(|_| bad("bad byte skip"))?,
                "line skip" => h.line_skip = value.parse().map_err(|_| bad("bad line skip"))?,
                "data file" | "datafile" => {
                    return Err(err(format!(
                        "the NRRD header's voxels are in another file ({value}): save the \
                         segmentation as one .nrrd or .seg.nrrd"
                    )))
                }
                _ => {}
            }
        }
        let dimension = dimension.ok_or_else(|| err("the NRRD header has no dimension"))?;
        if h.sizes.len() != dimension || !(3..=4).contains(&dimension) {
            return Err(err(format!(
                "the NRRD volume has dimension {dimension} and sizes {}: a label map is 3D (or \
                 4D: segment layers or time frames)",
                join(&h.sizes)
            )));
        }
        if h.directions.as_ref().is_some_and(|d| d.len() != dimension) {
            return Err(err("the NRRD space directions do not match its dimension"));
        }
        Ok(h)
    }

    fn kind(&self) -> Result<NiftiType> {
        Ok(match self.type_name.as_str() {
            "uchar" | "unsigned char" | "uint8" | "uint8_t" => NiftiType::Uint8,
            "signed char" | "int8" | "int8_t" => NiftiType::Int8,
            "short" | "short int" | "signed short" | "signed short int" | "int16" | "int16_t" => {
                NiftiType::Int16
            }
            "ushort" | "unsigned short" | "unsigned short int" | "uint16" | "uint16_t" => {
                NiftiType::Uint16
            }
            "int" | "signed int" | "int32" | "int32_t" => NiftiType::Int32,
            "uint" | "unsigned int" | "uint32" | "uint32_t" => NiftiType::Uint32,
            "longlong"
            | "long long"
            | "long long int"
            | "signed long long"
            | "signed long long int"
            | "int64"
            | "int64_t" => NiftiType::Int64,
            "ulonglong"
            | "unsigned long long"
            | "unsigned long long int"
            | "uint64"
            | "uint64_t" => NiftiType::Uint64,
            "float" => NiftiType::Float32,
            "double" => NiftiType::Float64,
            other => return Err(err(format!("NRRD type {other:?} is not a label type"))),
        })
    }

    /// The voxel bytes, decoded from the encoding, after the byte and line skips.
    fn voxel_bytes<'a>(&self, data: &'a [u8], count: usize) -> Result<std::borrow::Cow<'a, [u8]>> {
        let mut data = data;
        for _ in 0..self.line_skip {
            let at = data
                .iter()
                .position(|&b| b == b'\n')
                .map_or(data.len(), |p| p + 1);
            data = &data[at..];
        }
        let decoded: std::borrow::Cow<'a, [u8]> = match self.encoding.as_str() {
            "raw" => std::borrow::Cow::Borrowed(data),
            "gzip" | "gz" => {
                if !gzip::is_gzip(data) {
                    return Err(err("the NRRD data are not gzip as its header says"));
                }
                gzip::inflate(data)?
            }
            "ascii" | "text" | "txt" => {
                let kind = self.kind()?;
                let width = value_width(kind)?;
                let text = std::str::from_utf8(data)
                    .map_err(|_| err("the NRRD ascii data are not text"))?;
                let mut out = Vec::with_capacity(count);
                for word in text.split_whitespace().take(count / width) {
                    let v: f64 = word
                        .parse()
                        .map_err(|_| err(format!("NRRD ascii value {word:?} is not a number")))?;
                    // Re-encoded as little-endian doubles' integer part in the file's type width.
                    out.extend_from_slice(&encode(v, kind, width));
                }
                return Ok(std::borrow::Cow::Owned(out));
            }
            other => {
                return Err(err(format!(
                    "NRRD encoding {other:?} is not read (raw, gzip or ascii): save the \
                     segmentation with compression on or off"
                )))
            }
        };
        let skip = self.byte_skip;
        Ok(match skip {
            -1 => decoded,
            s if s >= 0 => {
                let s = (s as usize).min(decoded.len());
                match decoded {
                    std::borrow::Cow::Borrowed(b) => std::borrow::Cow::Borrowed(&b[s..]),
                    std::borrow::Cow::Owned(v) => std::borrow::Cow::Owned(v[s..].to_vec()),
                }
            }
            _ => return Err(err(format!("NRRD byte skip {skip} is not read"))),
        })
    }

    fn segments(&self) -> Vec<Segment> {
        let get = |k: &str| {
            self.pairs
                .iter()
                .find(|(key, _)| key == k)
                .map(|(_, v)| v.as_str())
        };
        (0..)
            .map_while(|n| {
                let name = get(&format!("Segment{n}_Name"))?;
                Some(Segment {
                    name: name.to_string(),
                    layer: get(&format!("Segment{n}_Layer"))
                        .and_then(|v| v.parse().ok())
                        .unwrap_or(0),
                    value: get(&format!("Segment{n}_LabelValue"))
                        .and_then(|v| v.parse().ok())
                        .unwrap_or(n as u16 + 1),
                })
            })
            .take(1000)
            .collect()
    }

    /// The spatial axes (those with a space direction; all of them without `space directions`),
    /// the segment layers (a first non-spatial axis) and the time frames (a last one).
    fn shape(&self) -> Result<([usize; 3], usize, usize)> {
        let sizes = &self.sizes;
        let spatial: Vec<usize> = (0..sizes.len())
            .filter(|&a| self.directions.as_ref().is_none_or(|d| d[a].is_some()))
            .collect();
        if spatial.len() != 3 {
            return Err(err(format!(
                "the NRRD volume has {} spatial axes (sizes {}): a label map needs 3",
                spatial.len(),
                join(sizes)
            )));
        }
        let extra: Vec<usize> = (0..sizes.len()).filter(|a| !spatial.contains(a)).collect();
        let (layers, frames) = match extra[..] {
            [] => (1, 1),
            [0] => (sizes[0], 1),
            [3] => (1, sizes[3]),
            _ => {
                return Err(err(format!(
                "the NRRD volume's non-spatial axes ({:?} of sizes {}) are neither segment layers \
                     (first axis) nor time frames (last axis)",
                extra,
                join(sizes)
            )))
            }
        };

        Ok(([spatial[0], spatial[1], spatial[2]], layers, frames))
    }

    /// The convention of `space` (None: not one of the patient spaces).
    fn space_convention(&self) -> Option<Space> {
        match self.space.as_str() {
            "left-posterior-superior" | "lps" => Some(Space::LPS),
            "right-anterior-superior" | "ras" => Some(Space::RAS),
            "left-anterior-superior" | "las" => Some(Space::LAS),
            _ => None,
        }
    }

    /// Origin and per-voxel axes (mm) of the spatial axes, and how they were given.
    fn placement(&self, spatial: &[usize]) -> Result<(Vec3, [Vec3; 3], &'static str)> {
        let space: &'static str = match self.space.as_str() {
            "left-posterior-superior" | "lps" => "space directions (LPS, as 3D Slicer saves)",
            "right-anterior-superior" | "ras" => "space directions (RAS)",
            "left-anterior-superior" | "las" => "space directions (LAS)",
            _ => "space directions",
        };
        let (axes, how) = match &self.directions {
            Some(d) => (
                [0, 1, 2].map(|k| d[spatial[k]].unwrap_or(Vec3::zeros())),
                space,
            ),
            None => {
                let s = |a: usize| {
                    self.spacings
                        .as_ref()
                        .and_then(|s| s.get(a).copied())
                        .filter(|v| v.is_finite() && *v > 0.0)
                        .unwrap_or(1.0)
                };
                (
                    [
                        Vec3::x() * s(spatial[0]),
                        Vec3::y() * s(spatial[1]),
                        Vec3::z() * s(spatial[2]),
                    ],
                    "spacings",
                )
            }
        };
        let origin = self.origin.unwrap_or(Vec3::zeros());
        let longest = axes.iter().map(|a| a.norm()).fold(0.0, f64::max);
        let m = nalgebra::Matrix3::from_columns(&axes);
        let finite = origin.iter().chain(m.iter()).all(|v| v.is_finite());
        if !finite || m.determinant().abs() <= 1e-9 * longest.powi(3) || longest > 1e3 {
            return Err(err(format!(
                "the NRRD voxel placement is degenerate or not in mm: voxel steps {:?}",
                axes.map(|a| [a.x, a.y, a.z])
            )));
        }
        Ok((origin, axes, how))
    }
}

/// The label map (its one frame) as a NRRD file (`.nrrd`, `.seg.nrrd`): uint8 labels when they
/// fit, else uint16, little-endian, gzip-encoded when `gzip`; `space` is written as given (the
/// coordinates are not changed: LPS coordinates should say `left-posterior-superior`). `names`:
/// segment names by label, written as 3D Slicer's segment metadata.
pub fn write_nrrd(
    volume: &LabelVolume,
    gzip: bool,
    space: &str,
    names: &[(u16, String)],
) -> Vec<u8> {
    let wide = volume.labels.iter().any(|&l| l > 255);
    let v = |a: Vec3| format!("({},{},{})", a.x, a.y, a.z);
    let mut text = format!(
        "NRRD0004\n# written by heartmesh\ntype: {}\ndimension: 3\nspace: {space}\nsizes: {} {} {}\n\
         space directions: {} {} {}\nkinds: domain domain domain\nendian: little\n\
         encoding: {}\nspace origin: {}\n",
        if wide { "uint16" } else { "uint8" },
        volume.dims[0],
        volume.dims[1],
        volume.dims[2],
        v(volume.axes[0]),
        v(volume.axes[1]),
        v(volume.axes[2]),
        if gzip { "gzip" } else { "raw" },
        v(volume.origin)
    );
    for (n, (label, name)) in names.iter().enumerate() {
        text += &format!(
            "Segment{n}_Name:={name}\nSegment{n}_LabelValue:={label}\nSegment{n}_Layer:=0\n"
        );
    }
    text.push('\n');
    let data: Vec<u8> = if wide {
        volume.labels.iter().flat_map(|l| l.to_le_bytes()).collect()
    } else {
        volume.labels.iter().map(|&l| l as u8).collect()
    };
    let mut out = text.into_bytes();
    if gzip {
        out.extend(gzip::deflate(&data));
    } else {
        out.extend(data);
    }
    out
}

/// `v` in `kind`'s little-endian bytes (ascii data re-encoded for the shared decoder).
fn encode(v: f64, kind: NiftiType, width: usize) -> Vec<u8> {
    let bytes: [u8; 8] = match kind {
        NiftiType::Float32 => {
            let mut b = [0u8; 8];
            b[..4].copy_from_slice(&(v as f32).to_le_bytes());
            b
        }
        NiftiType::Float64 => v.to_le_bytes(),
        _ => (v as i64).to_le_bytes(),
    };
    bytes[..width].to_vec()
}

/// `(x,y,z)` as a vector.
fn vector(text: &str) -> Option<Vec3> {
    let inner = text.trim().strip_prefix('(')?.strip_suffix(')')?;
    let v: Vec<f64> = inner
        .split(',')
        .map(|s| s.trim().parse::<f64>().ok())
        .collect::<Option<Vec<_>>>()?;
    (v.len() == 3).then(|| Vec3::new(v[0], v[1], v[2]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::nifti::roles::tests::heart_slice;
    use crate::io::nifti::{read_nifti, read_nrrd, write_nifti};

    /// Six heart slices (40 x 40 pixels of 1.5 mm, 10 mm apart) placed off the origin, rotated.
    fn stack() -> LabelVolume {
        LabelVolume::new(
            [40, 40, 6],
            Vec3::new(-30.0, 12.5, 100.0),
            [
                Vec3::new(0.0, 1.5, 0.0),
                Vec3::new(-1.5, 0.0, 0.0),
                Vec3::new(0.0, 0.0, 10.0),
            ],
            heart_slice(40, 3, 2, 1).repeat(6),
        )
    }

    fn header(fields: &str) -> Vec<u8> {
        format!("NRRD0004\n{}\n\n", fields.trim_end()).into_bytes()
    }

    #[test]
    fn a_slicer_segmentation_reads_as_the_same_label_map_as_nifti() {
        let v = stack();
        let names = [
            (1, "RV".to_string()),
            (2, "Myocardium".to_string()),
            (3, "LV".to_string()),
        ];
        let nii = read_nifti(&write_nifti(&v, false), None).unwrap();
        for gz in [false, true] {
            let bytes = write_nrrd(&v, gz, "left-posterior-superior", &names);
            assert!(is_nrrd(&bytes));
            let set = read_nrrd(&bytes, None).unwrap();
            assert_eq!(set.surfaces(), ["LV_ENDO", "LV_EPI", "RV_ENDO"]);
            assert_eq!(set.contours.len(), nii.contours.len());
            for (a, b) in set.contours.iter().zip(&nii.contours) {
                assert_eq!(a.id, b.id);
                for (p, q) in a.points().zip(b.points()) {
                    assert!((p - q).norm() < 1e-9);
                }
            }
            let note = &set.warnings[0];
            assert!(
                note.contains("space directions (LPS, as 3D Slicer saves)")
                    && note.ends_with("segments 1 RV, 2 Myocardium, 3 LV"),
                "{note}"
            );
        }
    }

    #[test]
    fn layers_frames_and_encodings() {
        // Two layers (overlapping segments), first axis: voxel by voxel, layer 0 then 1. Layer 0
        // holds the LV (1) in the first half, layer 1 a "whole heart" (1) everywhere.
        let n = 4 * 4 * 2;
        let mut data = Vec::new();
        for i in 0..n {
            data.push(u8::from(i < n / 2));
            data.push(1);
        }
        let mut bytes = header(
            "type: uint8\ndimension: 4\nsizes: 2 4 4 2\nspace: left-posterior-superior\n\
             space directions: none (2,0,0) (0,2,0) (0,0,8)\nkinds: list domain domain domain\n\
             encoding: raw\nSegment0_Name:=LV\nSegment0_LabelValue:=1\nSegment0_Layer:=0\n\
             Segment1_Name:=Heart\nSegment1_LabelValue:=1\nSegment1_Layer:=1\n",
        );
        bytes.extend(&data);
        let (v, names) = read_nrrd_volume(&bytes, None).unwrap();
        assert_eq!(v.dims, [4, 4, 2]);
        assert_eq!(&v.labels[..2], &[1, 1]);
        assert_eq!(v.labels[n - 1], 2);
        assert_eq!(names, [(1, "LV".to_string()), (2, "Heart".to_string())]);
        assert_eq!(v.axes[2], Vec3::new(0.0, 0.0, 8.0));

        // Time frames on the last axis: frame 1 chosen.
        let mut bytes = header(
            "type: short\ndimension: 4\nsizes: 2 2 2 3\nendian: big\nencoding: raw\n\
             space directions: (1,0,0) (0,1,0) (0,0,5) none",
        );
        for t in 0..3i16 {
            for _ in 0..8 {
                bytes.extend((t * 2).to_be_bytes());
            }
        }
        let (v, _) = read_nrrd_volume(&bytes, FrameChoice::new("1").as_ref()).unwrap();
        assert_eq!((v.frames, v.frame, v.labels[0]), (3, 1, 2));
        assert_eq!(v.labelled, [1, 2]);

        // ASCII, spacings instead of directions, data at the end (byte skip -1).
        let mut bytes =
            header("type: int\ndimension: 3\nsizes: 2 2 2\nspacings: 1.5 1.5 10\nencoding: ascii");
        bytes.extend(b"0 1 1 0\n2 2 0 0\n");
        let (v, _) = read_nrrd_volume(&bytes, None).unwrap();
        assert_eq!(v.labels, [0, 1, 1, 0, 2, 2, 0, 0]);
        assert_eq!(v.placement, "spacings");
        let mut bytes = header(
            "type: uchar\ndimension: 3\nsizes: 2 2 1\nbyte skip: -1\nencoding: raw\n\
             space directions: (1,0,0) (0,1,0) (0,0,1)",
        );
        bytes.extend([9, 9, 9, 0, 1, 0, 1]);
        assert_eq!(
            read_nrrd_volume(&bytes, None).unwrap().0.labels,
            [0, 1, 0, 1]
        );
    }

    #[test]
    fn what_is_refused_says_why() {
        let refused = |fields: &str, data: &[u8]| {
            let mut b = header(fields);
            b.extend(data);
            read_nrrd_volume(&b, None).unwrap_err().to_string()
        };
        let base = "type: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n";
        assert!(
            refused(&format!("{base}data file: x.raw"), &[]).contains("in another file (x.raw)")
        );
        assert!(refused(
            "type: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: bzip2",
            &[0; 8]
        )
        .contains("encoding \"bzip2\" is not read"));
        assert!(refused(base, &[1; 5]).contains("truncated"));
        assert!(refused(
            "type: uchar\ndimension: 2\nsizes: 4 4\nencoding: raw",
            &[0; 16]
        )
        .contains("a label map is 3D"));
        assert!(refused("type: block\ndimension: 3\nsizes: 2 2 2", &[0; 8])
            .contains("not a label type"));
        assert!(refused(
            "type: float\ndimension: 3\nsizes: 2 2 2\nencoding: raw",
            &0.5f32.to_le_bytes().repeat(8)
        )
        .contains("this NRRD is an image, not a label map"));
        assert!(refused(
            &format!("{base}space directions: (1,0,0) (2,0,0) (0,0,1)"),
            &[0; 8]
        )
        .contains("degenerate"));
        assert!(refused("type: uchar\ndimension: 3\nsizes: 2 0 2", &[])
            .contains("whole numbers over 0"));
        let no_end = b"NRRD0004\ntype: uchar\n".to_vec();
        assert!(read_nrrd_volume(&no_end, None)
            .unwrap_err()
            .to_string()
            .contains("no end"));
        assert!(!is_nrrd(b"NRRD") && !is_nrrd(b"contour,x,y,z\n"));
    }
}
