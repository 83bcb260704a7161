//! PLY meshes (Turk 1994 "The PLY polygon file format"): ASCII and binary readers for any scalar
//! and list property types, and a binary little-endian writer with an optional per-vertex float
//! property (e.g. `distance`) that three.js' PLYLoader and ParaView show as a scalar, and an
//! optional per-face `int` region label (the reader skips face properties it does not use).

use super::text::{quote, word_end};
use super::{header_lines, read_regions, MeshData, MeshRegions, Regions, MAX_MESH_ELEMENTS};
use crate::error::{CoreError, Result};
use crate::geometry::v3;
use crate::mesh::TriMesh;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
}

#[derive(Debug)]
enum Property {
    Scalar(Scalar, String),
    /// Count type and item type (the list's name is not needed: the first list of `face` is used).
    List(Scalar, Scalar),
}

#[derive(Debug)]
struct Element {
    name: String,
    count: usize,
    props: Vec<Property>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

/// Where values come from: whitespace tokens (ASCII) or raw bytes (binary).
struct Body<'a> {
    bytes: &'a [u8],
    pos: usize,
    enc: Encoding,
    /// Current 1-based line (ASCII only).
    line: usize,
}

impl Body<'_> {
    fn err(&self, msg: impl Into<String>) -> CoreError {
        match self.enc {
            Encoding::Ascii => CoreError::parse(self.line, msg),
            _ => CoreError::parse(0, format!("at byte {}: {}", self.pos, msg.into())),
        }
    }

    fn value(&mut self, ty: Scalar) -> Result<f64> {
        if self.enc == Encoding::Ascii {
            return self.token(ty);
        }
        let n = ty.size();
        let raw = self
            .bytes
            .get(self.pos..self.pos + n)
            .ok_or_else(|| self.err("file ends early (truncated)"))?;
        let mut b = [0u8; 8];
        b[..n].copy_from_slice(raw);
        if self.enc == Encoding::Big {
            b[..n].reverse();
        }
        self.pos += n;
        Ok(match ty {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F64 => f64::from_le_bytes(b),
        })
    }

    fn token(&mut self, ty: Scalar) -> Result<f64> {
        while let Some(&c) = self.bytes.get(self.pos) {
            if c == b'\n' {
                self.line += 1;
            }
            if !c.is_ascii_whitespace() {
                break;
            }
            self.pos += 1;
        }
        let start = self.pos;
        self.pos = word_end(self.bytes, start);
        if start == self.pos {
            return Err(self.err("file ends early (truncated)"));
        }
        let tok = std::str::from_utf8(&self.bytes[start..self.pos]).unwrap_or("?");
        let v: f64 = tok
            .parse()
            .map_err(|_| self.err(format!("{} is not a number", quote(tok))))?;
        if matches!(ty, Scalar::F32 | Scalar::F64) || v.fract() == 0.0 {
            Ok(v)
        } else {
            Err(self.err(format!("{} is not an integer", quote(tok))))
        }
    }
}

/// A parsed PLY header.
struct Header {
    elements: Vec<Element>,
    enc: Encoding,
    /// Byte offset of the body.
    body_start: usize,
    /// Number of header lines (the body's first line is the next).
    lines: usize,
    /// The text of each `comment` line.
    comments: Vec<String>,
}

/// Parses the header.
fn header(bytes: &[u8]) -> Result<Header> {
    if !bytes.starts_with(b"ply") {
        return Err(CoreError::parse(1, "not a PLY file (no \"ply\" magic)"));
    }
    let end = bytes
        .windows(10)
        .position(|w| w == b"end_header")
        .ok_or_else(|| CoreError::parse(0, "no end_header line (truncated header?)"))?;
    let body_start = bytes[end..]
        .iter()
        .position(|&b| b == b'\n')
        .map(|p| end + p + 1)
        .unwrap_or(bytes.len());
    let text = std::str::from_utf8(&bytes[..end])
        .map_err(|_| CoreError::parse(0, "PLY header is not text"))?;
    let mut elements: Vec<Element> = Vec::new();
    let mut enc = None;
    let mut nlines = 1;
    let mut comments = Vec::new();
    for (i, raw) in text.split('\n').enumerate() {
        let line = i + 1;
        nlines = line + 1;
        let mut it = raw.split_whitespace();
        match it.next() {
            Some("format") => {
                enc = Some(match it.next() {
                    Some("ascii") => Encoding::Ascii,
                    Some("binary_little_endian") => Encoding::Little,
                    Some("binary_big_endian") => Encoding::Big,
                    other => {
                        return Err(CoreError::parse(
                            line,
                            format!("unknown PLY format {}", quote(other.unwrap_or(""))),
                        ))
                    }
                })
            }
            Some("comment") => comments.push(it.collect::<Vec<_>>().join(" ")),
            Some("element") => {
                let name = it.next().unwrap_or("").to_string();
                let count: usize = it
                    .next()
                    .and_then(|c| c.parse().ok())
                    .ok_or_else(|| CoreError::parse(line, "element without a valid count"))?;
                if count > MAX_MESH_ELEMENTS {
                    return Err(CoreError::parse(
                        line,
                        format!("{count} {name} elements: the limit is {MAX_MESH_ELEMENTS}"),
                    ));
                }
                // A second vertex or face element would mix two meshes (and their point data)
                // into one; no writer produces it.
                if matches!(name.as_str(), "vertex" | "face")
                    && elements.iter().any(|e| e.name == name)
                {
                    return Err(CoreError::parse(
                        line,
                        format!("a second {name} element; a PLY mesh has one"),
                    ));
                }
                elements.push(Element {
                    name,
                    count,
                    props: Vec::new(),
                });
            }
            Some("property") => {
                let el = elements
                    .last_mut()
                    .ok_or_else(|| CoreError::parse(line, "property before any element"))?;
                let bad = |t: &str| CoreError::parse(line, format!("unknown type {}", quote(t)));
                let t = it.next().unwrap_or("");
                if t == "list" {
                    let ct = it.next().unwrap_or("");
                    let it2 = it.next().unwrap_or("");
                    let c = Scalar::parse(ct).ok_or_else(|| bad(ct))?;
                    let v = Scalar::parse(it2).ok_or_else(|| bad(it2))?;
                    el.props.push(Property::List(c, v));
                } else {
                    let s = Scalar::parse(t).ok_or_else(|| bad(t))?;
                    el.props
                        .push(Property::Scalar(s, it.next().unwrap_or("").to_string()));
                }
            }
            _ => {}
        }
    }
    let enc = enc.ok_or_else(|| CoreError::parse(0, "PLY header has no format line"))?;
    Ok(Header {
        elements,
        enc,
        body_start,
        lines: nlines,
        comments,
    })
}

/// Reads a PLY mesh: `vertex` x/y/z (plus the first other scalar property as point data) and the
/// first list property of `face` (fan-triangulated).
pub fn read_ply(bytes: &[u8]) -> Result<MeshData> {
    let Header {
        elements,
        enc,
        body_start,
        lines,
        comments,
    } = header(bytes)?;
    let mut body = Body {
        bytes,
        pos: body_start,
        enc,
        line: lines,
    };
    let mut face_labels = FaceLabels::default();
    let mut mesh = TriMesh::default();
    let mut data: Option<(String, Vec<f64>)> = None;
    let mut values: Vec<f64> = Vec::new();
    let mut list: Vec<f64> = Vec::new();
    let mut saw_vertex = false;
    for el in &elements {
        let is_vertex = el.name == "vertex";
        let is_face = el.name == "face";
        let pos_of = |n: &str| {
            el.props
                .iter()
                .position(|p| matches!(p, Property::Scalar(_, name) if name == n))
        };
        let xyz = [pos_of("x"), pos_of("y"), pos_of("z")];
        let extra = el.props.iter().position(|p| {
            matches!(p, Property::Scalar(_, n) if !matches!(n.as_str(),
                "x" | "y" | "z" | "nx" | "ny" | "nz" | "red" | "green" | "blue" | "alpha"
                | "s" | "t" | "u" | "v"))
        });
        if is_vertex {
            saw_vertex = true;
            if xyz.iter().any(Option::is_none) {
                return Err(CoreError::parse(0, "vertex element lacks x, y or z"));
            }
            if let Some(Property::Scalar(_, n)) = extra.map(|i| &el.props[i]) {
                data = Some((n.clone(), Vec::new()));
            }
        }
        let face_list = el
            .props
            .iter()
            .position(|p| matches!(p, Property::List(..)));
        let label = if is_face {
            face_labels.property(&el.props)
        } else {
            None
        };
        for _ in 0..el.count {
            values.clear();
            for (k, p) in el.props.iter().enumerate() {
                match p {
                    Property::Scalar(t, _) => values.push(body.value(*t)?),
                    Property::List(ct, vt) => {
                        let n = body.value(*ct)?;
                        if !(0.0..=65535.0).contains(&n) {
                            return Err(body.err(format!("list length {n} is invalid")));
                        }
                        list.clear();
                        for _ in 0..n as usize {
                            list.push(body.value(*vt)?);
                        }
                        values.push(f64::NAN);
                        if is_face && Some(k) == face_list {
                            push_polygon(&mut mesh, &list, &body)?;
                            face_labels.corners.push(list.len());
                        }
                    }
                }
            }
            if let Some(i) = label {
                face_labels.values.push(values[i]);
            }
            if is_vertex {
                let c = xyz.map(|i| values[i.unwrap_or(0)]);
                if !c.iter().all(|v| v.is_finite()) {
                    return Err(body.err("vertex with a non-finite coordinate"));
                }
                mesh.positions.push(v3(c[0], c[1], c[2]));
                if let (Some((_, d)), Some(i)) = (data.as_mut(), extra) {
                    d.push(values[i]);
                }
            }
        }
    }
    if !saw_vertex || mesh.positions.is_empty() {
        return Err(CoreError::parse(0, "no vertices found"));
    }
    if mesh.triangles.is_empty() {
        return Err(CoreError::parse(0, "no faces found"));
    }
    let n = mesh.positions.len();
    if let Some(t) = mesh
        .triangles
        .iter()
        .find(|t| t.iter().any(|&i| i as usize >= n))
    {
        return Err(CoreError::parse(
            0,
            format!("face {t:?} refers to a vertex beyond the {n} vertices"),
        ));
    }
    let regions = face_labels.finish(&comments, mesh.triangles.len());
    Ok(MeshData {
        mesh,
        point_data: data,
        regions,
        coordinate_system: None,
    })
}

/// The first scalar property of the face element, read as a label per face (our writer's
/// `int region`; other tools' `int label` or `uchar material`), with names from the header's
/// `comment ARRAY K NAME` lines.
#[derive(Default)]
struct FaceLabels {
    name: String,
    values: Vec<f64>,
    /// Corners of each face, to give its label to each of its fan triangles.
    corners: Vec<usize>,
}

impl FaceLabels {
    /// Index of the label among the face's properties, when it has a scalar one.
    fn property(&mut self, props: &[Property]) -> Option<usize> {
        let (i, name) = props.iter().enumerate().find_map(|(i, p)| match p {
            Property::Scalar(_, n) => Some((i, n)),
            Property::List(..) => None,
        })?;
        self.name = name.clone();
        Some(i)
    }

    /// None when the face has no such property or a value is not a whole number.
    fn finish(self, comments: &[String], triangles: usize) -> Option<MeshRegions> {
        if self.name.is_empty() {
            return None;
        }
        let labels: Vec<i32> = self
            .values
            .iter()
            .map(|&v| read_regions::as_label(v))
            .collect::<Option<_>>()?;
        let names = comments
            .iter()
            .filter_map(|c| {
                let mut it = c.splitn(3, ' ');
                (it.next()? == self.name).then_some(())?;
                let label = it.next()?.parse().ok()?;
                Some((label, it.next()?.trim().to_string()))
            })
            .collect();
        MeshRegions::from_polygons(
            self.name,
            &labels,
            self.corners.into_iter(),
            names,
            triangles,
        )
    }
}

fn push_polygon(mesh: &mut TriMesh, list: &[f64], body: &Body) -> Result<()> {
    if list.len() < 3 {
        return Err(body.err(format!(
            "face has {} corners; at least 3 needed",
            list.len()
        )));
    }
    let idx = |v: f64| -> Result<u32> {
        if v >= 0.0 && v < MAX_MESH_ELEMENTS as f64 {
            Ok(v as u32)
        } else {
            Err(body.err(format!("face index {v} is invalid")))
        }
    };
    let first = idx(list[0])?;
    for k in 1..list.len() - 1 {
        if mesh.triangles.len() >= MAX_MESH_ELEMENTS {
            return Err(body.err("too many faces"));
        }
        mesh.triangles
            .push([first, idx(list[k])?, idx(list[k + 1])?]);
    }
    Ok(())
}

/// Binary little-endian PLY with float coordinates, the optional float property and
/// `vertex_indices` as `list uchar int`.
pub fn write_ply(
    mesh: &TriMesh,
    point_data: Option<(&str, &[f64])>,
    header_comment: &str,
) -> Vec<u8> {
    write_ply_with(mesh, point_data, None, header_comment)
}

/// [`write_ply`] with the regions (checked by [`super::write_mesh_with`]) as a face property
/// `int ARRAY` after `vertex_indices`, holding `id + 1`: PLY readers (ours, trimesh, Open3D's
/// tensor API, ParaView) keep face properties they do not know as per-face attributes. PLY has
/// no string attributes, so the names go into `comment ARRAY K NAME` header lines.
pub(crate) fn write_ply_with(
    mesh: &TriMesh,
    point_data: Option<(&str, &[f64])>,
    regions: Option<&Regions>,
    header_comment: &str,
) -> Vec<u8> {
    let mut out = ply_header(mesh, point_data, regions, header_comment).into_bytes();
    let per_vertex = 12 + if point_data.is_some() { 4 } else { 0 };
    let per_face = 13 + if regions.is_some() { 4 } else { 0 };
    out.reserve(per_vertex * mesh.positions.len() + per_face * mesh.triangles.len());
    for (i, p) in mesh.positions.iter().enumerate() {
        for c in p.iter() {
            out.extend_from_slice(&(*c as f32).to_le_bytes());
        }
        if let Some((_, d)) = point_data {
            let v = d.get(i).copied().unwrap_or(f64::NAN);
            out.extend_from_slice(&(v as f32).to_le_bytes());
        }
    }
    for (k, t) in mesh.triangles.iter().enumerate() {
        out.push(3);
        for &i in t {
            out.extend_from_slice(&(i as i32).to_le_bytes());
        }
        if let Some(r) = regions {
            out.extend_from_slice(&r.value(k).to_le_bytes());
        }
    }
    out
}

/// The header text of [`write_ply_with`], up to and including `end_header`.
fn ply_header(
    mesh: &TriMesh,
    point_data: Option<(&str, &[f64])>,
    regions: Option<&Regions>,
    header_comment: &str,
) -> String {
    let mut h = String::from("ply\nformat binary_little_endian 1.0\n");
    for l in header_lines(header_comment) {
        let l: String = l.chars().filter(|c| !c.is_control()).collect();
        h.push_str(&format!("comment {l}\n"));
    }
    let region_property = regions.map(|r| property_name(r.array));
    if let (Some(r), Some(prop)) = (regions, &region_property) {
        for (k, name) in r.names.iter().enumerate() {
            h.push_str(&format!("comment {prop} {} {name}\n", k + 1));
        }
    }
    h.push_str(&format!(
        "element vertex {}\nproperty float x\nproperty float y\nproperty float z\n",
        mesh.positions.len()
    ));
    if let Some((name, _)) = point_data {
        h.push_str(&format!("property float {}\n", property_name(name)));
    }
    h.push_str(&format!(
        "element face {}\nproperty list uchar int vertex_indices\n",
        mesh.triangles.len()
    ));
    if let Some(prop) = region_property {
        h.push_str(&format!("property int {prop}\n"));
    }
    h.push_str("end_header\n");
    h
}

/// A PLY property name: letters, digits and `_` only.
fn property_name(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if s.is_empty() {
        "value".into()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ascii_quad_with_extra_element() {
        let s = "ply\nformat ascii 1.0\ncomment x\nelement vertex 4\nproperty double x\n\
                 property double y\nproperty double z\nproperty uchar red\nproperty float quality\n\
                 element face 1\nproperty list uchar uint vertex_index\n\
                 element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n\
                 0 0 0 1 0.5\n1 0 0 1 1.5\n1 1 0 1 2.5\n0 1 0 1 3.5\n4 0 1 2 3\n0 1\n";
        let d = read_ply(s.as_bytes()).unwrap();
        assert_eq!(d.mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        let (name, v) = d.point_data.unwrap();
        assert_eq!(name, "quality");
        assert_eq!(v, vec![0.5, 1.5, 2.5, 3.5]);
    }

    #[test]
    fn second_vertex_element_is_refused() {
        // Found by the ply fuzz target: positions came from both vertex elements but the point
        // data only from the second.
        let s = "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n\
                 property float z\nelement vertex 3\nproperty float x\nproperty float y\n\
                 property float z\nproperty float d\nelement face 1\n\
                 property list uchar int vertex_indices\nend_header\n\
                 0 0 0 1\n1 0 0 2\n0 1 0 3\n3 0 1 2\n";
        let e = read_ply(s.as_bytes()).unwrap_err().to_string();
        assert!(
            e.contains("line 7") && e.contains("second vertex element"),
            "{e}"
        );
    }

    #[test]
    fn truncated_and_bad() {
        let s = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                 property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
                 end_header\n0 0 0\n1 0 0\n1 q 0\n3 0 1 2\n";
        let e = read_ply(s.as_bytes()).unwrap_err();
        assert_eq!(e.line(), Some(12), "{e}");
        let e = read_ply(&s.as_bytes()[..s.len() - 9]).unwrap_err();
        assert!(e.to_string().contains("q"), "{e}");
        assert!(read_ply(b"ply\nformat binary_little_endian 1.0\nelement vertex 9\nproperty float x\nend_header\n\x00").is_err());
    }
}
