//! VTK XML PolyData (.vtp, "VTK File Formats", XML section): points, polygons, lines and the
//! first point-data array, with ascii or inline base64 ("binary", uncompressed) data arrays.
//! The writer uses ascii arrays, which ParaView, VTK and 3D Slicer read.

use roxmltree::{Document, Node};

use super::vtk::{
    contours_from_lines, mesh_from_cells, LineLabels, CONTOUR_ID_ARRAY, SURFACE_ARRAY,
};
use super::{fmt_num, fmt_point, header_lines, MeshData, MAX_MESH_ELEMENTS};
use crate::contours::ContourSet;
use crate::error::{CoreError, Result};
use crate::geometry::{v3, Vec3};
use crate::mesh::TriMesh;

struct Parsed {
    points: Vec<Vec3>,
    polys: Vec<Vec<u32>>,
    lines: Vec<Vec<u32>>,
    lines_at: usize,
    point_data: Option<(String, Vec<f64>)>,
    labels: LineLabels,
}

fn line_of(doc: &Document, node: Node) -> usize {
    doc.text_pos_at(node.range().start).row as usize
}

fn parse(bytes: &[u8]) -> Result<Parsed> {
    let text = super::text::decode(bytes)?;
    let doc = Document::parse(&text).map_err(|e| {
        let p = e.pos();
        CoreError::parse(p.row as usize, format!("not valid XML: {e}"))
    })?;
    let root = doc.root_element();
    if root.tag_name().name() != "VTKFile" || root.attribute("type") != Some("PolyData") {
        return Err(CoreError::parse(
            line_of(&doc, root),
            "not a VTK PolyData file (expected <VTKFile type=\"PolyData\">)",
        ));
    }
    if root.attribute("compressor").is_some() {
        return Err(CoreError::parse(
            line_of(&doc, root),
            "compressed VTP is not supported; save with ascii or uncompressed binary data",
        ));
    }
    let header64 = root.attribute("header_type") == Some("UInt64");
    let big = root.attribute("byte_order") == Some("BigEndian");
    let piece = root
        .descendants()
        .find(|n| n.has_tag_name("Piece"))
        .ok_or_else(|| CoreError::parse(line_of(&doc, root), "no <Piece> element"))?;
    let count = |name: &str| -> Result<usize> {
        let v = piece.attribute(name).unwrap_or("0");
        v.trim()
            .parse::<usize>()
            .ok()
            .filter(|&n| n <= MAX_MESH_ELEMENTS)
            .ok_or_else(|| {
                CoreError::parse(
                    line_of(&doc, piece),
                    format!("{name}={v:?} is not a valid count"),
                )
            })
    };
    let npoints = count("NumberOfPoints")?;
    let section = |tag: &str| piece.children().find(|n| n.has_tag_name(tag));
    let ctx = Ctx {
        doc: &doc,
        header64,
        big,
    };

    let pts_node = section("Points")
        .and_then(|p| p.children().find(|n| n.has_tag_name("DataArray")))
        .ok_or_else(|| CoreError::parse(line_of(&doc, piece), "no <Points> data array"))?;
    let flat = ctx.array(pts_node)?;
    if flat.len() != 3 * npoints {
        return Err(CoreError::parse(
            line_of(&doc, pts_node),
            format!("Points has {} values; expected 3 x {npoints}", flat.len()),
        ));
    }
    let points: Vec<Vec3> = flat.chunks_exact(3).map(|c| v3(c[0], c[1], c[2])).collect();
    if !flat.iter().all(|v| v.is_finite()) {
        return Err(CoreError::parse(
            line_of(&doc, pts_node),
            "non-finite point coordinate",
        ));
    }

    let cells = |tag: &str| -> Result<(Vec<Vec<u32>>, usize)> {
        let Some(sec) = section(tag) else {
            return Ok((Vec::new(), 0));
        };
        let named = |n: &str| {
            sec.children()
                .find(|c| c.has_tag_name("DataArray") && c.attribute("Name") == Some(n))
        };
        let (Some(conn), Some(offs)) = (named("connectivity"), named("offsets")) else {
            return Err(CoreError::parse(
                line_of(&doc, sec),
                format!("<{tag}> needs connectivity and offsets arrays"),
            ));
        };
        let conn_v = ctx.array(conn)?;
        let offs_v = ctx.array(offs)?;
        let mut out = Vec::with_capacity(offs_v.len());
        let mut start = 0.0;
        for &end in &offs_v {
            if !(end >= start && end <= conn_v.len() as f64) {
                return Err(CoreError::parse(
                    line_of(&doc, offs),
                    format!("bad offset {end}"),
                ));
            }
            let mut cell = Vec::new();
            for &i in &conn_v[start as usize..end as usize] {
                if !(i >= 0.0 && (i as usize) < npoints && i.fract() == 0.0) {
                    return Err(CoreError::parse(
                        line_of(&doc, conn),
                        format!("point index {i} is outside 0..{npoints}"),
                    ));
                }
                cell.push(i as u32);
            }
            out.push(cell);
            start = end;
        }
        Ok((out, line_of(&doc, conn)))
    };
    let (polys, _) = cells("Polys")?;
    let (lines, lines_at) = cells("Lines")?;

    let mut point_data = None;
    if let Some(pd) = section("PointData") {
        let wanted = pd.attribute("Scalars");
        let arr = pd
            .children()
            .filter(|n| n.has_tag_name("DataArray"))
            .find(|n| wanted.is_none() || n.attribute("Name") == wanted);
        if let Some(arr) = arr {
            let comps: usize = arr
                .attribute("NumberOfComponents")
                .and_then(|c| c.parse().ok())
                .unwrap_or(1);
            let v = ctx.array(arr)?;
            if comps == 1 && v.len() == npoints {
                let name = arr.attribute("Name").unwrap_or("scalars").to_string();
                point_data = Some((name, v));
            }
        }
    }
    // Cell data runs over verts, lines, strips, polys in that order.
    let verts = count("NumberOfVerts")?;
    let strings: Vec<(String, Vec<String>)> = section("CellData")
        .map(|cd| {
            cd.children()
                .filter(|n| n.has_tag_name("DataArray") && n.attribute("type") == Some("String"))
                .filter_map(|n| Some((n.attribute("Name")?.to_string(), ascii_strings(n)?)))
                .collect()
        })
        .unwrap_or_default();
    let labels = LineLabels::from_cell_strings(&strings, verts, lines.len());
    Ok(Parsed {
        points,
        polys,
        lines,
        lines_at,
        point_data,
        labels,
    })
}

struct Ctx<'a, 'i> {
    doc: &'a Document<'i>,
    header64: bool,
    big: bool,
}

impl Ctx<'_, '_> {
    /// The values of a DataArray as f64.
    fn array(&self, node: Node) -> Result<Vec<f64>> {
        let line = line_of(self.doc, node);
        let text = node.text().unwrap_or("");
        match node.attribute("format").unwrap_or("ascii") {
            "ascii" => {
                let mut out = Vec::new();
                for (k, tok) in text.split_ascii_whitespace().enumerate() {
                    if out.len() >= 4 * MAX_MESH_ELEMENTS {
                        return Err(CoreError::parse(line, "data array exceeds the size limit"));
                    }
                    out.push(tok.parse::<f64>().map_err(|_| {
                        CoreError::parse(
                            line,
                            format!(
                                "value {} ({}) is not a number",
                                k + 1,
                                super::text::quote(tok)
                            ),
                        )
                    })?);
                }
                Ok(out)
            }
            "binary" => self.binary(node, text, line),
            other => Err(CoreError::parse(
                line,
                format!("DataArray format {other:?} is not supported (ascii or binary only)"),
            )),
        }
    }

    fn binary(&self, node: Node, text: &str, line: usize) -> Result<Vec<f64>> {
        let raw = base64(text).ok_or_else(|| CoreError::parse(line, "invalid base64 data"))?;
        let hsize = if self.header64 { 8 } else { 4 };
        let ty = node.attribute("type").unwrap_or("Float32");
        let size = match ty {
            "Int8" | "UInt8" => 1,
            "Int16" | "UInt16" => 2,
            "Int32" | "UInt32" | "Float32" => 4,
            "Int64" | "UInt64" | "Float64" => 8,
            other => {
                return Err(CoreError::parse(
                    line,
                    format!("unknown DataArray type {other:?}"),
                ))
            }
        };
        let body = raw.get(hsize..).unwrap_or(&[]);
        let mut out = Vec::with_capacity(body.len() / size);
        for c in body.chunks_exact(size) {
            let mut b = [0u8; 8];
            b[..size].copy_from_slice(c);
            if self.big {
                b[..size].reverse();
            }
            let u = u64::from_le_bytes(b);
            out.push(match ty {
                "Int8" => u as u8 as i8 as f64,
                "Int16" => u as u16 as i16 as f64,
                "Int32" => u as u32 as i32 as f64,
                "Int64" => u as i64 as f64,
                "Float32" => f32::from_bits(u as u32) as f64,
                "Float64" => f64::from_bits(u),
                _ => u as f64,
            });
        }
        Ok(out)
    }
}

/// Standard base64 (whitespace ignored, padding optional); None on a bad character.
fn base64(text: &str) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(text.len() * 3 / 4);
    let mut acc = 0u32;
    let mut bits = 0;
    for c in text.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            b'=' => continue,
            c if c.is_ascii_whitespace() => continue,
            _ => return None,
        };
        acc = (acc << 6) | v as u32;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

/// Reads the polygons of a VTP file as a triangle mesh.
pub fn read_vtp_mesh(bytes: &[u8]) -> Result<MeshData> {
    let p = parse(bytes)?;
    mesh_from_cells(p.points, &p.polys, p.point_data)
}

/// Reads the polylines of a VTP file as contours (named by a `contour_id` cell array when there is
/// one, else `line1`, `line2`, ...).
pub fn read_vtp_contours(bytes: &[u8]) -> Result<ContourSet> {
    let p = parse(bytes)?;
    if p.lines.is_empty() && !p.polys.is_empty() {
        return super::vtk::contours_from_polygons(&p.points, &p.polys, p.lines_at);
    }
    contours_from_lines(&p.points, &p.lines, p.lines_at, &p.labels)
}

/// An ascii String DataArray as VTK writes it: each string as its byte values, ended by a 0.
/// Other encodings of string arrays are not read (the labels are then simply absent).
fn ascii_strings(node: Node) -> Option<Vec<String>> {
    if node.attribute("format").unwrap_or("ascii") != "ascii" {
        return None;
    }
    let mut out = Vec::new();
    let mut cur = Vec::new();
    for w in node.text().unwrap_or("").split_ascii_whitespace() {
        match w.parse::<u8>().ok()? {
            0 => out.push(String::from_utf8_lossy(&std::mem::take(&mut cur)).into_owned()),
            b => cur.push(b),
        }
    }
    Some(out)
}

fn push_string_array(out: &mut String, name: &str, values: &[&str]) {
    out.push_str(&format!(
        "<DataArray type=\"String\" Name=\"{name}\" format=\"ascii\">\n"
    ));
    for v in values {
        for b in v.bytes() {
            out.push_str(&format!("{b} "));
        }
        out.push_str("0\n");
    }
    out.push_str("</DataArray>\n");
}

/// The XML declaration, the header as a comment (no `--` inside, which XML forbids) and the
/// opening tags of one PolyData piece with its element counts.
fn prologue(header_comment: &str, points: usize, lines: usize, polys: usize) -> String {
    let comment = header_lines(header_comment)
        .join(" | ")
        .replace("--", "- -");
    format!(
        "<?xml version=\"1.0\"?>\n<!-- {comment} -->\n\
         <VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\">\n<PolyData>\n\
         <Piece NumberOfPoints=\"{points}\" NumberOfVerts=\"0\" NumberOfLines=\"{lines}\" NumberOfStrips=\"0\" NumberOfPolys=\"{polys}\">\n"
    )
}

/// XML PolyData with ascii arrays: Float64 points, Int32 connectivity/offsets, the point data.
pub fn write_vtp(
    mesh: &TriMesh,
    point_data: Option<(&str, &[f64])>,
    header_comment: &str,
) -> Vec<u8> {
    let mut out = prologue(
        header_comment,
        mesh.positions.len(),
        0,
        mesh.triangles.len(),
    );
    if let Some((name, values)) = point_data {
        let name = xml_escape(name);
        out.push_str(&format!(
            "<PointData Scalars=\"{name}\">\n<DataArray type=\"Float64\" Name=\"{name}\" format=\"ascii\">\n"
        ));
        for v in values {
            out.push_str(&fmt_num(*v));
            out.push('\n');
        }
        out.push_str("</DataArray>\n</PointData>\n");
    }
    out.push_str(
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
    );
    for p in &mesh.positions {
        out.push_str(&format!("{}\n", fmt_point(p, " ")));
    }
    out.push_str("</DataArray>\n</Points>\n<Polys>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n");
    for t in &mesh.triangles {
        out.push_str(&format!("{} {} {}\n", t[0], t[1], t[2]));
    }
    out.push_str("</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n");
    for k in 1..=mesh.triangles.len() {
        out.push_str(&format!("{}\n", 3 * k));
    }
    out.push_str("</DataArray>\n</Polys>\n</Piece>\n</PolyData>\n</VTKFile>\n");
    out.into_bytes()
}

/// Polylines as VTK XML PolyData; `labels` (one (id, surface) per cell, or empty) become the
/// `contour_id` and `surface` string arrays of CellData.
pub(crate) fn write_lines(
    points: &[Vec3],
    cells: &[Vec<u32>],
    labels: &[(&str, &str)],
    header_comment: &str,
) -> Vec<u8> {
    let mut out = prologue(header_comment, points.len(), cells.len(), 0);
    out.push_str(
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
    );
    for p in points {
        out.push_str(&format!("{}\n", fmt_point(p, " ")));
    }
    out.push_str("</DataArray>\n</Points>\n<Lines>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n");
    for c in cells {
        let row: Vec<String> = c.iter().map(|i| i.to_string()).collect();
        out.push_str(&row.join(" "));
        out.push('\n');
    }
    out.push_str("</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n");
    let mut end = 0;
    for c in cells {
        end += c.len();
        out.push_str(&format!("{end}\n"));
    }
    out.push_str("</DataArray>\n</Lines>\n");
    if !labels.is_empty() && labels.len() == cells.len() {
        out.push_str("<CellData>\n");
        let ids: Vec<&str> = labels.iter().map(|l| l.0).collect();
        let surfaces: Vec<&str> = labels.iter().map(|l| l.1).collect();
        push_string_array(&mut out, CONTOUR_ID_ARRAY, &ids);
        push_string_array(&mut out, SURFACE_ARRAY, &surfaces);
        out.push_str("</CellData>\n");
    }
    out.push_str("</Piece>\n</PolyData>\n</VTKFile>\n");
    out.into_bytes()
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polylines_ascii_and_binary() {
        let s = r#"<?xml version="1.0"?>
<VTKFile type="PolyData" version="0.1" byte_order="LittleEndian">
<PolyData><Piece NumberOfPoints="4" NumberOfLines="1">
<Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 1 1 0 0 1 0</DataArray></Points>
<Lines><DataArray type="Int32" Name="connectivity" format="ascii">0 1 2 3</DataArray>
<DataArray type="Int32" Name="offsets" format="binary">BAAAAAQAAAA=</DataArray></Lines>
</Piece></PolyData></VTKFile>"#;
        let set = read_vtp_contours(s.as_bytes()).unwrap();
        assert_eq!(set.contours.len(), 1);
        assert_eq!(set.point_count(), 4);
        let e = read_vtp_contours(s.replace("1 1 0 0", "1 x 0 0").as_bytes()).unwrap_err();
        assert_eq!(e.line(), Some(4), "{e}");
        let e = read_vtp_contours(b"<VTKFile type=\"PolyData\"><PolyData>").unwrap_err();
        assert!(e.to_string().contains("XML"), "{e}");
    }

    #[test]
    fn base64_decodes() {
        assert_eq!(base64("aGVhcnQ=").unwrap(), b"heart");
        assert!(base64("a$").is_none());
    }
}
