//! VTK XML PolyData (.vtp, "VTK File Formats", XML section): points, polygons, lines, the first
//! point-data array and the cell-data string arrays that name our contours. Meshes may be written
//! with region labels as cell data, which the reader passes over.
//!
//! Read as VTK and ParaView write it in every mode: ascii, inline base64 (`format="binary"`) and
//! appended data (`format="appended"`, raw bytes, VTK's default, or base64), each uncompressed
//! or zlib-compressed, with UInt32 or UInt64 headers ([`data_array`], [`appended`]), in one
//! `<Piece>` or several (their points merged where a cut repeats them). The writer
//! uses ascii arrays, which ParaView, VTK and 3D Slicer read.

mod appended;
mod base64;
mod data_array;

use crate::io::xml_escape;
use std::cell::Cell;
use std::collections::{BTreeMap, HashMap};

use roxmltree::{Document, Node};

use super::vtk::{
    contours_from_lines, mesh_from_cells, vertex_landmarks, LineLabels, CONTOUR_ID_ARRAY,
    SURFACE_ARRAY,
};
use super::{
    header_lines, push_number_lines, push_point_lines, read_regions, MeshData, MeshRegions,
    Regions, MAX_MESH_ELEMENTS,
};
use crate::contours::ContourSet;
use crate::error::{CoreError, Result};
use crate::geometry::{v3, Vec3};
use crate::mesh::TriMesh;
use data_array::{Layout, Stream};

/// Most values one data array may hold (ascii or binary): points of the largest mesh accepted.
const MAX_ARRAY_VALUES: usize = 4 * MAX_MESH_ELEMENTS;

#[derive(Default)]
struct Parsed {
    points: Vec<Vec3>,
    polys: Vec<Vec<u32>>,
    lines: Vec<Vec<u32>>,
    lines_at: usize,
    point_data: Option<(String, Vec<f64>)>,
    labels: LineLabels,
    /// Landmarks: the named one-point vertex cells (see [`vertex_landmarks`]).
    landmarks: Vec<(String, Vec3)>,
    /// A whole-number cell array's value for each of `polys`, with its name and label names.
    poly_labels: Option<PolyLabels>,
}

/// Labels of polygons from a `<CellData>` integer array (see [`MeshRegions`]).
#[derive(Debug)]
struct PolyLabels {
    array: String,
    labels: Vec<i32>,
    names: BTreeMap<i32, String>,
}

fn line_of(doc: &Document, node: Node) -> usize {
    doc.text_pos_at(node.range().start).row as usize
}

fn parse(bytes: &[u8]) -> Result<Parsed> {
    // Raw appended data is not text: cut it off before decoding and parsing the XML.
    let appended::Split {
        xml,
        data: appended,
    } = appended::split(bytes)?;
    let text = super::text::decode(&xml)?;
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
    let layout = Layout::new(
        root.attribute("header_type"),
        root.attribute("byte_order"),
        root.attribute("compressor"),
    )
    .map_err(|m| CoreError::parse(line_of(&doc, root), m))?;
    let appended = match appended {
        None => None,
        Some(data) => {
            let node = root
                .children()
                .find(|n| n.has_tag_name("AppendedData"))
                .ok_or_else(|| {
                    CoreError::parse(
                        line_of(&doc, root),
                        "<AppendedData> is not inside <VTKFile>",
                    )
                })?;
            let base64 = match node.attribute("encoding").map(str::trim) {
                None | Some("raw") => false,
                Some("base64") => true,
                Some(other) => {
                    return Err(CoreError::parse(
                        line_of(&doc, node),
                        format!("AppendedData encoding {other:?} is not supported (raw or base64)"),
                    ))
                }
            };
            Some(Appended { data, base64 })
        }
    };
    let ctx = Ctx {
        doc: &doc,
        layout,
        appended,
        budget: Cell::new(super::gzip::MAX_INFLATED_BYTES),
    };
    // A writer asked for several pieces (vtkXMLPolyDataWriter's NumberOfPieces) puts each in its
    // own <Piece> with its own point numbering: all of them are the file's data.
    let mut pieces = root
        .descendants()
        .filter(|n| n.has_tag_name("Piece"))
        .peekable();
    if pieces.peek().is_none() {
        return Err(CoreError::parse(line_of(&doc, root), "no <Piece> element"));
    }
    let mut all = Parsed::default();
    let mut seen = HashMap::new();
    for piece in pieces {
        let part = ctx.piece(piece)?;
        all.append(part, line_of(&doc, piece), &mut seen)?;
    }
    Ok(all)
}

impl Parsed {
    /// Adds a later piece. Its point numbers start again at 0, and the points it shares with
    /// earlier pieces (a surface cut into pieces repeats the corners along each cut) are
    /// written again: those bit-identical to an earlier piece's are merged, so a closed surface
    /// stays closed.
    fn append(
        &mut self,
        part: Parsed,
        line: usize,
        seen: &mut HashMap<[u64; 3], u32>,
    ) -> Result<()> {
        let first = self.points.is_empty();
        let (had_lines, new_lines) = (self.lines.len(), part.lines.len());
        self.labels = if first {
            part.labels
        } else {
            std::mem::take(&mut self.labels).concat(had_lines, part.labels, new_lines)
        };
        let mut data = match (self.point_data.take(), part.point_data) {
            (_, Some(d)) if first => Some((d.0, Vec::with_capacity(d.1.len()), d.1)),
            (Some((name, v)), Some((other, w))) if name == other => Some((name, v, w)),
            _ => None,
        };
        let mut index = Vec::with_capacity(part.points.len());
        // Only earlier pieces' points are merged: a piece's own points stay as it numbers them.
        let mut added = Vec::new();
        for (k, p) in part.points.into_iter().enumerate() {
            let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
            let i = match seen.get(&key) {
                Some(&i) => i,
                None => {
                    if self.points.len() >= MAX_MESH_ELEMENTS {
                        return Err(CoreError::parse(
                            line,
                            "too many points in the pieces together",
                        ));
                    }
                    let i = self.points.len() as u32;
                    self.points.push(p);
                    added.push((key, i));
                    if let Some((_, v, w)) = data.as_mut() {
                        v.push(w[k]);
                    }
                    i
                }
            };
            index.push(i);
        }
        for (key, i) in added {
            seen.entry(key).or_insert(i);
        }
        self.point_data = data.map(|(name, v, _)| (name, v));
        let renumber = |cells: Vec<Vec<u32>>| {
            cells.into_iter().map(|c| {
                c.into_iter()
                    .map(|i| index[i as usize])
                    .collect::<Vec<u32>>()
            })
        };
        self.poly_labels = match (self.poly_labels.take(), part.poly_labels) {
            (_, p) if first => p,
            (Some(mut a), Some(b)) if a.array == b.array => {
                a.labels.extend(b.labels);
                for (l, n) in b.names {
                    a.names.entry(l).or_insert(n);
                }
                Some(a)
            }
            _ => None,
        };
        self.polys.extend(renumber(part.polys));
        self.lines.extend(renumber(part.lines));
        self.landmarks.extend(part.landmarks);
        if self.lines_at == 0 {
            self.lines_at = part.lines_at;
        }
        Ok(())
    }
}

impl Ctx<'_, '_> {
    /// One `<Piece>`: its points, cells, first point-data array, labels and landmarks.
    fn piece(&self, piece: Node) -> Result<Parsed> {
        let doc = self.doc;
        let ctx = self;
        let count = |name: &str| -> Result<usize> {
            let v = piece.attribute(name).unwrap_or("0");
            v.trim()
                .parse::<usize>()
                .ok()
                .filter(|&n| n <= MAX_MESH_ELEMENTS)
                .ok_or_else(|| {
                    CoreError::parse(
                        line_of(doc, piece),
                        format!("{name}={v:?} is not a valid count"),
                    )
                })
        };
        let npoints = count("NumberOfPoints")?;
        let section = |tag: &str| piece.children().find(|n| n.has_tag_name(tag));

        let pts_node = section("Points")
            .and_then(|p| p.children().find(|n| n.has_tag_name("DataArray")))
            .ok_or_else(|| CoreError::parse(line_of(doc, piece), "no <Points> data array"))?;
        let flat = ctx.array(pts_node)?;
        if flat.len() != 3 * npoints {
            return Err(CoreError::parse(
                line_of(doc, pts_node),
                format!("Points has {} values; expected 3 x {npoints}", flat.len()),
            ));
        }
        let points: Vec<Vec3> = flat.chunks_exact(3).map(|c| v3(c[0], c[1], c[2])).collect();
        if !flat.iter().all(|v| v.is_finite()) {
            return Err(CoreError::parse(
                line_of(doc, pts_node),
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
                    line_of(doc, sec),
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
                        line_of(doc, offs),
                        format!("bad offset {end}"),
                    ));
                }
                let mut cell = Vec::new();
                for &i in &conn_v[start as usize..end as usize] {
                    if !(i >= 0.0 && (i as usize) < npoints && i.fract() == 0.0) {
                        return Err(CoreError::parse(
                            line_of(doc, conn),
                            format!("point index {i} is outside 0..{npoints}"),
                        ));
                    }
                    cell.push(i as u32);
                }
                out.push(cell);
                start = end;
            }
            Ok((out, line_of(doc, conn)))
        };
        let (polys, _) = cells("Polys")?;
        let (lines, lines_at) = cells("Lines")?;
        // Vertex cells matter only as our landmarks: a <Verts> section this reader cannot follow is
        // dropped, as every <Verts> was before landmarks were written there, never the geometry.
        let verts = cells("Verts").map(|(v, _)| v).unwrap_or_default();

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
        let nverts = count("NumberOfVerts")?;
        let strings: Vec<(String, Vec<String>)> = section("CellData")
            .map(|cd| {
                cd.children()
                    // VTK 9 (ParaView's "Save Data") writes string arrays as `<Array>`.
                    .filter(|n| n.has_tag_name("DataArray") || n.has_tag_name("Array"))
                    .filter(|n| n.attribute("type") == Some("String"))
                    .filter_map(|n| {
                        let name = n.attribute("Name")?.to_string();
                        ctx.strings(n).transpose().map(|v| v.map(|v| (name, v)))
                    })
                    .collect::<Result<_>>()
            })
            .transpose()?
            .unwrap_or_default();
        let first_poly = nverts + lines.len() + count("NumberOfStrips")?;
        let poly_labels = section("CellData").and_then(|cd| {
            poly_labels(ctx, cd, &strings, first_poly, polys.len())
                .ok()
                .flatten()
        });
        let labels = LineLabels::from_cell_strings(&strings, nverts, lines.len());
        let landmarks = if verts.len() == nverts {
            let vert_labels = LineLabels::from_cell_strings(&strings, 0, nverts);
            vertex_landmarks(&points, &verts, &vert_labels)
        } else {
            Vec::new()
        };
        Ok(Parsed {
            points,
            polys,
            lines,
            lines_at,
            point_data,
            labels,
            landmarks,
            poly_labels,
        })
    }
}

/// The polygons' labels: the `Scalars` array of `<CellData>` (else its first numeric one) when
/// it holds one whole number per cell; cell data runs over verts, lines, strips, polys, so the
/// polygons' values start at `first`. Labels are extras: any doubt gives None, never an error.
fn poly_labels(
    ctx: &Ctx,
    cell_data: Node,
    strings: &[(String, Vec<String>)],
    first: usize,
    polys: usize,
) -> Result<Option<PolyLabels>> {
    let wanted = cell_data.attribute("Scalars");
    let Some(arr) = cell_data
        .children()
        .filter(|n| n.has_tag_name("DataArray") && n.attribute("type") != Some("String"))
        .find(|n| wanted.is_none() || n.attribute("Name") == wanted)
    else {
        return Ok(None);
    };
    let comps = arr.attribute("NumberOfComponents").unwrap_or("1");
    let Some(array) = arr.attribute("Name").filter(|_| comps == "1") else {
        return Ok(None);
    };
    let values = ctx.array(arr)?;
    let Some(labels): Option<Vec<i32>> = values
        .get(first..first + polys)
        .and_then(|v| v.iter().map(|&x| read_regions::as_label(x)).collect())
    else {
        return Ok(None);
    };
    let names_array = format!("{array}_name");
    let names = strings
        .iter()
        .find(|(a, _)| *a == names_array)
        .and_then(|(_, v)| v.get(first..first + polys))
        .map(|v| read_regions::names_from_cells(&labels, v))
        .unwrap_or_default();
    Ok(Some(PolyLabels {
        array: array.to_string(),
        labels,
        names,
    }))
}

/// The appended data block (see [`appended`]): the bytes after its `_` marker.
struct Appended<'a> {
    data: &'a [u8],
    base64: bool,
}

/// What reading a DataArray needs beside its element.
struct Ctx<'a, 'i> {
    doc: &'a Document<'i>,
    layout: Layout,
    appended: Option<Appended<'a>>,
    /// Bytes the file's compressed arrays may still inflate to (a few kilobytes of zlib can
    /// claim gigabytes): the bound of gzip input.
    budget: Cell<usize>,
}

impl Ctx<'_, '_> {
    /// The values of a DataArray as f64.
    ///
    /// Ascii values of a Float32 array are rounded to f32: VTK prints the shortest text of the
    /// f32 it holds (`0.3`), so the same data saved in any other mode (which keeps the f32 bits)
    /// reads to the very same points. Our own files are Float64 and read unchanged.
    fn array(&self, node: Node) -> Result<Vec<f64>> {
        let line = line_of(self.doc, node);
        let text = node.text().unwrap_or("");
        let ty = node.attribute("type").unwrap_or("Float32");
        match node.attribute("format").unwrap_or("ascii") {
            "ascii" => {
                let f32_values = ty == "Float32";
                let mut out = Vec::new();
                for (k, tok) in text.split_ascii_whitespace().enumerate() {
                    if out.len() >= MAX_ARRAY_VALUES {
                        return Err(CoreError::parse(line, "data array exceeds the size limit"));
                    }
                    let v = tok.parse::<f64>().map_err(|_| {
                        CoreError::parse(
                            line,
                            format!(
                                "value {} ({}) is not a number",
                                k + 1,
                                super::text::quote(tok)
                            ),
                        )
                    })?;
                    out.push(if f32_values { v as f32 as f64 } else { v });
                }
                Ok(out)
            }
            _ => {
                let bytes = self.binary(node, line)?;
                data_array::numbers(&bytes, ty, self.layout.big_endian, MAX_ARRAY_VALUES)
                    .map_err(|m| CoreError::parse(line, m))
            }
        }
    }

    /// The strings of a String array; None when the array is in no format this reader knows
    /// (the labels are then simply absent).
    fn strings(&self, node: Node) -> Result<Option<Vec<String>>> {
        match node.attribute("format").unwrap_or("ascii") {
            "ascii" => Ok(ascii_strings(node)),
            "binary" | "appended" => {
                let bytes = self.binary(node, line_of(self.doc, node))?;
                Ok(Some(data_array::strings(&bytes)))
            }
            _ => Ok(None),
        }
    }

    /// The data bytes of a `binary` (inline base64) or `appended` DataArray.
    fn binary(&self, node: Node, line: usize) -> Result<Vec<u8>> {
        let err = |m: String| CoreError::parse(line, m);
        let mut budget = self.budget.get();
        let bytes = match node.attribute("format").unwrap_or("ascii") {
            "binary" => {
                let text: Vec<u8> = node
                    .text()
                    .unwrap_or("")
                    .bytes()
                    .filter(|b| !b.is_ascii_whitespace())
                    .collect();
                data_array::array_bytes(&self.layout, Stream::base64(&text, 0), &mut budget)
            }
            "appended" => {
                let app = self.appended.as_ref().ok_or_else(|| {
                    err("format=\"appended\" but the file has no <AppendedData>".into())
                })?;
                let v = node.attribute("offset").unwrap_or("").trim();
                let offset = v
                    .parse::<usize>()
                    .ok()
                    .ok_or_else(|| err(format!("offset {v:?} is not a valid offset")))?;
                if offset >= app.data.len() {
                    return Err(err(format!(
                        "offset {offset} is past the end of the appended data ({} bytes; \
                         truncated file?)",
                        app.data.len()
                    )));
                }
                let stream = if app.base64 {
                    Stream::base64(app.data, offset)
                } else {
                    Stream::raw(app.data, offset)
                };
                data_array::array_bytes(&self.layout, stream, &mut budget)
            }
            other => Err(format!(
                "DataArray format {other:?} is not supported (ascii, binary or appended)"
            )),
        }
        .map_err(err)?;
        self.budget.set(budget);
        Ok(bytes)
    }
}

/// Reads the polygons of a VTP file as a triangle mesh.
pub fn read_vtp_mesh(bytes: &[u8]) -> Result<MeshData> {
    let p = parse(bytes)?;
    let mut data = mesh_from_cells(p.points, &p.polys, p.point_data)?;
    data.regions = p.poly_labels.and_then(|l| {
        MeshRegions::from_polygons(
            l.array,
            &l.labels,
            p.polys.iter().map(Vec::len),
            l.names,
            data.mesh.triangles.len(),
        )
    });
    Ok(data)
}

/// Reads the polylines of a VTP file as contours (named by a `contour_id` cell array when there is
/// one, else `line1`, `line2`, ...) and the landmarks among its vertex cells.
pub fn read_vtp_contours(bytes: &[u8]) -> Result<ContourSet> {
    let p = parse(bytes)?;
    if p.lines.is_empty() && !p.polys.is_empty() {
        return super::vtk::contours_from_polygons(&p.points, &p.polys, p.lines_at);
    }
    contours_from_lines(&p.points, &p.lines, p.lines_at, &p.labels, &p.landmarks)
}

/// An ascii String DataArray as VTK writes it: each string as its byte values, ended by a 0.
/// VTK writes the bytes as signed chars (`-62 -75` for "µ"), we write them unsigned; None on
/// anything else (the labels are then simply absent).
fn ascii_strings(node: Node) -> Option<Vec<String>> {
    let mut out = Vec::new();
    let mut cur = Vec::new();
    for w in node.text().unwrap_or("").split_ascii_whitespace() {
        let b = w.parse::<i16>().ok().filter(|b| (-128..=255).contains(b))? as u8;
        match b {
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
fn prologue(
    header_comment: &str,
    points: usize,
    verts: usize,
    lines: usize,
    polys: usize,
) -> String {
    let header = header_lines(header_comment);
    let comment = header.join(" | ").replace("--", "- -");
    // 3D Slicer looks for the patient frame of a VTP in a field data string array `SPACE`.
    let space = header
        .iter()
        .find_map(|l| super::space_of_line(l))
        .map(|s| {
            let codes: Vec<String> = s.bytes().map(|b| b.to_string()).collect();
            format!(
                "<FieldData>\n<Array type=\"String\" Name=\"SPACE\" NumberOfTuples=\"1\" format=\"ascii\">\n{} 0\n</Array>\n</FieldData>\n",
                codes.join(" ")
            )
        })
        .unwrap_or_default();
    format!(
        "<?xml version=\"1.0\"?>\n<!-- {comment} -->\n\
         <VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\">\n<PolyData>\n{space}\
         <Piece NumberOfPoints=\"{points}\" NumberOfVerts=\"{verts}\" NumberOfLines=\"{lines}\" NumberOfStrips=\"0\" NumberOfPolys=\"{polys}\">\n"
    )
}

/// XML PolyData with ascii arrays: Float64 points, Int32 connectivity/offsets, the point data.
pub fn write_vtp(
    mesh: &TriMesh,
    point_data: Option<(&str, &[f64])>,
    header_comment: &str,
) -> Vec<u8> {
    write_vtp_with(mesh, point_data, None, header_comment)
}

/// [`write_vtp`] with the regions (checked by [`super::write_mesh_with`]) as
/// `<CellData Scalars="ARRAY">`: an Int32 array of `id + 1` per triangle (the active cell
/// scalars ParaView colours and thresholds by) and the String array `ARRAY_name` with each
/// triangle's region name, both ascii like the file's other arrays. The VTK XML schema orders a
/// piece's sections PointData, CellData, Points, then the cells.
pub(crate) fn write_vtp_with(
    mesh: &TriMesh,
    point_data: Option<(&str, &[f64])>,
    regions: Option<&Regions>,
    header_comment: &str,
) -> Vec<u8> {
    let mut out = prologue(
        header_comment,
        mesh.positions.len(),
        0,
        0,
        mesh.triangles.len(),
    );
    if let Some((name, values)) = point_data {
        let name = xml_escape(name);
        out.push_str(&format!(
            "<PointData Scalars=\"{name}\">\n<DataArray type=\"Float64\" Name=\"{name}\" format=\"ascii\">\n"
        ));
        push_number_lines(&mut out, values);
        out.push_str("</DataArray>\n</PointData>\n");
    }
    if let Some(r) = regions {
        push_region_cells(&mut out, r, mesh.triangles.len());
    }
    out.push_str(
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
    );
    push_point_lines(&mut out, &mesh.positions);
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

/// The `<CellData>` section of [`write_vtp_with`] for `n` triangles.
fn push_region_cells(out: &mut String, regions: &Regions, n: usize) {
    let name = xml_escape(regions.array);
    out.push_str(&format!(
        "<CellData Scalars=\"{name}\">\n<DataArray type=\"Int32\" Name=\"{name}\" format=\"ascii\">\n"
    ));
    for t in 0..n {
        out.push_str(&format!("{}\n", regions.value(t)));
    }
    out.push_str("</DataArray>\n");
    let names: Vec<&str> = (0..n).map(|t| regions.name_of(t)).collect();
    push_string_array(out, &xml_escape(&regions.names_array()), &names);
    out.push_str("</CellData>\n");
}

/// Polylines as VTK XML PolyData, after `verts` (landmarks: the point of each one-point cell of
/// `<Verts>`, first in VTK's cell data order: verts, lines); `labels` (one (id, surface) per
/// cell, verts then lines, or empty) become the `contour_id` and `surface` string arrays of
/// CellData.
pub(crate) fn write_lines(
    points: &[Vec3],
    verts: &[u32],
    cells: &[Vec<u32>],
    labels: &[(&str, &str)],
    header_comment: &str,
) -> Vec<u8> {
    let mut out = prologue(header_comment, points.len(), verts.len(), cells.len(), 0);
    out.push_str(
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
    );
    push_point_lines(&mut out, points);
    out.push_str("</DataArray>\n</Points>\n");
    if !verts.is_empty() {
        let ids: Vec<String> = verts.iter().map(u32::to_string).collect();
        let offsets: Vec<String> = (1..=verts.len()).map(|k| k.to_string()).collect();
        out.push_str(&format!(
            "<Verts>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n{}\n\
             </DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n{}\n\
             </DataArray>\n</Verts>\n",
            ids.join(" "),
            offsets.join(" ")
        ));
    }
    out.push_str("<Lines>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n");
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
    if !labels.is_empty() && labels.len() == verts.len() + cells.len() {
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

    /// ParaView / VTK 9 save string arrays as `<Array type="String">`: the contour names and
    /// surfaces still come through (they were all read as `line1`, `line2`, ... before).
    #[test]
    fn vtk9_string_arrays_name_the_contours() {
        let s = r#"<?xml version="1.0"?>
<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" header_type="UInt64">
<PolyData><Piece NumberOfPoints="6" NumberOfVerts="0" NumberOfLines="2" NumberOfStrips="0" NumberOfPolys="0">
<CellData>
<Array type="String" Name="contour_id" format="ascii">115 49 0 115 50 0</Array>
<Array type="String" Name="surface" format="ascii">76 86 0 76 86 0</Array>
</CellData>
<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 9 0 0 0 9 0 0 0 10 9 0 10 0 9 10</DataArray></Points>
<Lines><DataArray type="Int64" Name="connectivity" format="ascii">0 1 2 0 3 4 5 3</DataArray>
<DataArray type="Int64" Name="offsets" format="ascii">4 8</DataArray></Lines>
</Piece></PolyData></VTKFile>"#;
        let set = read_vtp_contours(s.as_bytes()).unwrap();
        let named: Vec<(&str, Option<&str>)> = set
            .contours
            .iter()
            .map(|c| (c.id.as_str(), c.surface.as_deref()))
            .collect();
        assert_eq!(named, [("s1", Some("LV")), ("s2", Some("LV"))]);
    }

    /// Landmarks survive CSV -> VTP -> read: one-point `<Verts>` cells (NumberOfVerts counted),
    /// labelled first in the CellData string arrays, and the contours are unchanged. Vertex cells
    /// without our labels (other tools) are still ignored.
    #[test]
    fn landmarks_round_trip_as_verts() {
        let csv = "contour,surface,x,y,z\n\
                   a,LV_ENDO,0,0,0\na,LV_ENDO,10,0,0\na,LV_ENDO,10,10,0\na,LV_ENDO,0,10,0\n\
                   b,LV_EPI,0,0,5\nb,LV_EPI,12.5,0,5\nb,LV_EPI,25,0.125,5\n\
                   # landmark APEX_POINT 5 5 -30.0625\n\
                   # landmark AORTA_VALVE -1e-7 3.3333333333333335 7\n";
        let mut set = crate::io::read_contours("l.csv", csv.as_bytes()).unwrap();
        assert_eq!(set.landmarks.len(), 2);
        set.landmarks
            .push(("odd name & <µ>".into(), v3(1.0, 2.0, 3.0)));
        let bytes = crate::io::write_contour_lines(&set, true, "");
        let text = String::from_utf8(bytes.clone()).unwrap();
        assert!(text.contains(
            "NumberOfPoints=\"10\" NumberOfVerts=\"3\" NumberOfLines=\"2\" NumberOfStrips=\"0\" \
             NumberOfPolys=\"0\""
        ));
        assert!(text.contains("Name=\"connectivity\" format=\"ascii\">\n7 8 9\n"));
        assert!(text.contains("Name=\"offsets\" format=\"ascii\">\n1 2 3\n"));
        let back = read_vtp_contours(&bytes).unwrap();
        assert_eq!(back.landmarks, set.landmarks);
        assert_eq!(back.contours.len(), 2);
        for (b, c) in back.contours.iter().zip(&set.contours) {
            assert_eq!(
                (&b.id, &b.surface, &b.pieces),
                (&c.id, &c.surface, &c.pieces)
            );
        }
        // Another tool's file: the same cells without our labels, or labels that are no landmark.
        let bare = format!(
            "{}</Piece>\n</PolyData>\n</VTKFile>\n",
            &text[..text.find("<CellData>").unwrap()]
        );
        let other = read_vtp_contours(bare.as_bytes()).unwrap();
        assert_eq!((other.contours.len(), other.landmarks.len()), (2, 0));
        let unmarked = text.replacen("108 97 110 100 109 97 114 107 0", "0", 3);
        let other = read_vtp_contours(unmarked.as_bytes()).unwrap();
        assert_eq!((other.contours.len(), other.landmarks.len()), (2, 0));
        assert_eq!(other.contours[1].surface.as_deref(), Some("LV_EPI"));
    }
}
