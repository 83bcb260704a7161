//! VTK legacy files ("The VTK User's Guide", file formats chapter), POLYDATA only: points, lines,
//! polygons and triangle strips, ASCII or BINARY (big-endian), in the classic cell layout and in
//! the 5.1 OFFSETS/CONNECTIVITY layout, plus the first point SCALARS array. Used both for meshes
//! (polygons) and for contours (lines). The writer emits version 3.0 ASCII, which every VTK-based
//! tool and three.js' VTKLoader read.

use super::builder::ContourBuilder;
use super::text::{quote, word_end};
use super::{read_regions, MeshData, MeshRegions, MAX_MESH_ELEMENTS};
use crate::contours::ContourSet;
use crate::error::{CoreError, Result};
use crate::geometry::{v3, Vec3};
use crate::mesh::TriMesh;

pub(crate) use write::write_lines;
pub(crate) use write::write_vtk_with;
pub use write::{write_unstructured, write_vtk};

#[cfg(test)]
mod tests;
mod unstructured;
mod write;

pub use unstructured::{is_unstructured_grid, read_unstructured, DataArray, UnstructuredGrid};

/// The parts of a POLYDATA file heartmesh uses.
#[derive(Debug, Default)]
pub struct PolyData {
    pub points: Vec<Vec3>,
    pub lines: Vec<Vec<u32>>,
    pub polys: Vec<Vec<u32>>,
    pub point_scalars: Option<(String, Vec<f64>)>,
    /// 1-based line where each line cell's data starts (ASCII), for messages.
    pub lines_at: usize,
    /// VERTICES cells (they come first in the cell data order); named one-point cells are our
    /// landmarks (see [`LANDMARK_SURFACE`]).
    pub verts: Vec<Vec<u32>>,
    /// String arrays of CELL_DATA fields (name, one value per cell).
    pub cell_strings: Vec<(String, Vec<String>)>,
    /// The first SCALARS array of CELL_DATA (name, first component per cell).
    pub cell_scalars: Option<(String, Vec<f64>)>,
    /// VERTICES, LINES, POLYGONS and TRIANGLE_STRIPS cells: cell data runs over them in this
    /// order, whatever order the file lists the sections in.
    pub cell_counts: [usize; 4],
    /// The cell of each of `polys`: whether it came from a strip, and its index in its section.
    pub poly_cells: Vec<(bool, usize)>,
}

impl PolyData {
    /// The cell-data label of each polygon as triangle regions, when CELL_DATA has a whole-number
    /// SCALARS array (names from the string array `NAME_name`, as our writer puts them).
    pub fn regions(&self, triangles: usize) -> Option<MeshRegions> {
        let (name, values) = self.cell_scalars.as_ref()?;
        let [verts, lines, polys, _] = self.cell_counts;
        let cell = |&(strip, k): &(bool, usize)| verts + lines + if strip { polys + k } else { k };
        let labels: Vec<i32> = self
            .poly_cells
            .iter()
            .map(|c| values.get(cell(c)).and_then(|&v| read_regions::as_label(v)))
            .collect::<Option<_>>()?;
        let names_array = format!("{name}_name");
        let names = self
            .cell_strings
            .iter()
            .find(|(a, _)| *a == names_array)
            .map(|(_, cells)| {
                let per_poly: Vec<String> = self
                    .poly_cells
                    .iter()
                    .map(|c| cells.get(cell(c)).cloned().unwrap_or_default())
                    .collect();
                read_regions::names_from_cells(&labels, &per_poly)
            })
            .unwrap_or_default();
        MeshRegions::from_polygons(
            name.clone(),
            &labels,
            self.polys.iter().map(Vec::len),
            names,
            triangles,
        )
    }
}

/// Per-line labels kept through the polyline formats: the contour identifier and the surface.
pub const CONTOUR_ID_ARRAY: &str = "contour_id";
pub const SURFACE_ARRAY: &str = "surface";
/// The `surface` value of a landmark's cell. A landmark (valve, apex, RV insert) is written as VTK
/// itself represents a lone point: a vertex cell (VERTICES / `<Verts>`) of one point, appended
/// after the contour points, with its name in [`CONTOUR_ID_ARRAY`]. This marker (and not only a
/// name) is what makes our readers take a vertex cell back as a landmark, so that the vertex cells
/// of other tools' files, labelled or not, are still ignored as before; in ParaView it shows the
/// landmarks as a category of their own when coloring by `surface`.
pub const LANDMARK_SURFACE: &str = "landmark";

/// The contour identifier and surface of every line cell, when the file carries them.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct LineLabels {
    pub ids: Option<Vec<String>>,
    pub surfaces: Option<Vec<String>>,
}

impl LineLabels {
    /// Picks the label arrays from a file's cell string arrays; `first` is the index of the first
    /// line cell in the cell order (after vertices), `n` the number of lines.
    pub fn from_cell_strings(arrays: &[(String, Vec<String>)], first: usize, n: usize) -> Self {
        let pick = |name: &str| {
            arrays
                .iter()
                .find(|(a, _)| a == name)
                .and_then(|(_, v)| v.get(first..first + n))
                .map(<[String]>::to_vec)
        };
        LineLabels {
            ids: pick(CONTOUR_ID_ARRAY),
            surfaces: pick(SURFACE_ARRAY),
        }
    }

    /// The labels of `n` lines followed by those of `m` more (the next piece of a file). A
    /// piece without an array gets empty labels, which read as unnamed (`lineK`) or unassigned.
    pub fn concat(self, n: usize, next: LineLabels, m: usize) -> Self {
        let join = |a: Option<Vec<String>>, b: Option<Vec<String>>| match (a, b) {
            (None, None) => None,
            (a, b) => {
                let mut a = a.unwrap_or_else(|| vec![String::new(); n]);
                a.extend(b.unwrap_or_else(|| vec![String::new(); m]));
                Some(a)
            }
        };
        LineLabels {
            ids: join(self.ids, next.ids),
            surfaces: join(self.surfaces, next.surfaces),
        }
    }
}

struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
    binary: bool,
}

impl Cursor<'_> {
    fn line(&self) -> usize {
        super::text::line_of(self.bytes, self.pos)
    }

    fn err(&self, msg: impl Into<String>) -> CoreError {
        if self.binary {
            CoreError::parse(0, format!("at byte {}: {}", self.pos, msg.into()))
        } else {
            CoreError::parse(self.line(), msg)
        }
    }

    fn skip_ws(&mut self) {
        while self
            .bytes
            .get(self.pos)
            .is_some_and(u8::is_ascii_whitespace)
        {
            self.pos += 1;
        }
    }

    /// Next whitespace-delimited word, or None at the end.
    fn word(&mut self) -> Option<&str> {
        self.skip_ws();
        let start = self.pos;
        self.pos = word_end(self.bytes, start);
        if start == self.pos {
            return None;
        }
        std::str::from_utf8(&self.bytes[start..self.pos]).ok()
    }

    fn need_word(&mut self, what: &str) -> Result<String> {
        match self.word() {
            Some(w) => Ok(w.to_string()),
            None => Err(self.err(format!("file ends early: expected {what}"))),
        }
    }

    fn count(&mut self, what: &str) -> Result<usize> {
        let w = self.need_word(what)?;
        let n: usize = w
            .parse()
            .map_err(|_| self.err(format!("{what}: {} is not a count", quote(&w))))?;
        if n > 4 * MAX_MESH_ELEMENTS {
            return Err(self.err(format!("{what} {n} exceeds the limit")));
        }
        Ok(n)
    }

    /// Moves past the end of the current line (binary data starts on the next line).
    fn end_line(&mut self) {
        while let Some(&c) = self.bytes.get(self.pos) {
            self.pos += 1;
            if c == b'\n' {
                break;
            }
        }
    }

    /// One string of a binary string array, as `vtkDataWriter` writes it: a big-endian length
    /// whose two top bits say its size (`11`: 1 byte, `10`: 2, `01`: 4, `00`: 8 bytes, the rest
    /// of it the length), then the bytes.
    fn binary_string(&mut self) -> Result<String> {
        let first = *self
            .bytes
            .get(self.pos)
            .ok_or_else(|| self.err("file ends early in a string array"))?;
        let size = match first >> 6 {
            3 => 1,
            2 => 2,
            1 => 4,
            _ => 8,
        };
        let head = self
            .bytes
            .get(self.pos..self.pos + size)
            .ok_or_else(|| self.err("file ends early in a string array"))?;
        let mask = if size == 8 {
            u64::MAX
        } else {
            (1u64 << (8 * size - 2)) - 1
        };
        let len = head.iter().fold(0u64, |acc, &b| (acc << 8) | u64::from(b)) & mask;
        let start = self.pos + size;
        let end = usize::try_from(len)
            .ok()
            .and_then(|l| start.checked_add(l))
            .filter(|&e| e <= self.bytes.len())
            .ok_or_else(|| self.err("a string runs past the end of the file"))?;
        self.pos = end;
        Ok(String::from_utf8_lossy(&self.bytes[start..end]).into_owned())
    }

    /// The rest of the current line (without its `\r\n`), moving past it.
    fn rest_of_line(&mut self) -> &[u8] {
        let start = self.pos.min(self.bytes.len());
        let len = self.bytes[start..]
            .iter()
            .position(|&b| b == b'\n')
            .unwrap_or(self.bytes.len() - start);
        self.pos = start + len + 1;
        let line = &self.bytes[start..start + len];
        line.strip_suffix(b"\r").unwrap_or(line)
    }

    fn number(&mut self, ty: &str) -> Result<f64> {
        if !self.binary {
            let w = self.need_word("a number")?;
            return w
                .parse::<f64>()
                .map_err(|_| self.err(format!("{} is not a number", quote(&w))));
        }
        let size = match ty {
            "char" | "unsigned_char" | "bit" => 1,
            "short" | "unsigned_short" => 2,
            "int" | "unsigned_int" | "float" | "vtktypeint32" | "vtktypeuint32" => 4,
            "long" | "unsigned_long" | "double" | "vtktypeint64" | "vtktypeuint64"
            | "vtkidtype" => 8,
            other => return Err(self.err(format!("unknown data type {}", quote(other)))),
        };
        let raw = self
            .bytes
            .get(self.pos..self.pos + size)
            .ok_or_else(|| self.err("file ends early (truncated binary data)"))?;
        let mut b = [0u8; 8];
        b[8 - size..].copy_from_slice(raw);
        self.pos += size;
        let be = u64::from_be_bytes(b);
        Ok(match ty {
            "char" => raw[0] as i8 as f64,
            "unsigned_char" | "bit" => raw[0] as f64,
            "short" => be as u16 as i16 as f64,
            "unsigned_short" => be as u16 as f64,
            "int" | "vtktypeint32" => be as u32 as i32 as f64,
            "unsigned_int" | "vtktypeuint32" => be as u32 as f64,
            "float" => f32::from_bits(be as u32) as f64,
            "double" => f64::from_bits(be),
            "long" | "vtktypeint64" | "vtkidtype" => be as i64 as f64,
            _ => be as f64,
        })
    }

    fn index(&mut self, ty: &str, npoints: usize) -> Result<u32> {
        let v = self.number(ty)?;
        if v >= 0.0 && v.fract() == 0.0 && (v as usize) < npoints {
            Ok(v as u32)
        } else {
            Err(self.err(format!("point index {v} is outside 0..{npoints}")))
        }
    }
}

/// The header of a legacy file up to its dataset type: a cursor just after `DATASET KIND` and
/// whether the data are binary; an error saying `wanted` and what was found when the dataset is
/// not `kind`.
fn open_dataset<'a>(bytes: &'a [u8], kind: &str, wanted: &str) -> Result<(Cursor<'a>, bool)> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    if !bytes.starts_with(b"# vtk DataFile") {
        return Err(CoreError::parse(
            1,
            "not a VTK legacy file (no \"# vtk DataFile\")",
        ));
    }
    let mut c = Cursor {
        bytes,
        pos: 0,
        binary: false,
    };
    c.end_line(); // version
    c.end_line(); // title
    let fmt = c.need_word("ASCII or BINARY")?.to_ascii_uppercase();
    let binary = match fmt.as_str() {
        "ASCII" => false,
        "BINARY" => true,
        other => return Err(c.err(format!("expected ASCII or BINARY, found {}", quote(other)))),
    };
    let kw = c.need_word("DATASET")?.to_ascii_uppercase();
    let found = c.need_word("a dataset type")?.to_ascii_uppercase();
    if kw != "DATASET" || found != kind {
        return Err(c.err(format!("{wanted}, found {kw} {found}")));
    }
    Ok((c, binary))
}

/// The coordinates after `POINTS` (the keyword read): every one finite.
fn read_points(c: &mut Cursor, binary: bool) -> Result<Vec<Vec3>> {
    let n = c.count("point count")?;
    let ty = c.need_word("point data type")?.to_ascii_lowercase();
    c.end_line();
    c.binary = binary;
    let mut points = Vec::with_capacity(n.min(c.bytes.len() / 3));
    for _ in 0..n {
        let p = v3(c.number(&ty)?, c.number(&ty)?, c.number(&ty)?);
        if !p.iter().all(|x| x.is_finite()) {
            return Err(c.err("point with a non-finite coordinate"));
        }
        points.push(p);
    }
    c.binary = false;
    Ok(points)
}

/// Parses a legacy POLYDATA file.
pub fn read_polydata(bytes: &[u8]) -> Result<PolyData> {
    let (mut c, binary) = open_dataset(bytes, "POLYDATA", "only DATASET POLYDATA is supported")?;
    let mut pd = PolyData::default();
    while let Some(w) = c.word() {
        let w = w.to_ascii_uppercase();
        match w.as_str() {
            "POINTS" => pd.points = read_points(&mut c, binary)?,
            "LINES" | "POLYGONS" | "TRIANGLE_STRIPS" | "VERTICES" => {
                let at = c.line();
                let cells = read_cells(&mut c, binary, pd.points.len())?;
                match w.as_str() {
                    "LINES" => {
                        pd.lines_at = at + 1;
                        pd.cell_counts[1] = cells.len();
                        pd.lines = cells;
                    }
                    "POLYGONS" => {
                        let first = pd.cell_counts[2];
                        pd.cell_counts[2] += cells.len();
                        pd.poly_cells
                            .extend((first..first + cells.len()).map(|k| (false, k)));
                        pd.polys.extend(cells);
                    }
                    "VERTICES" => {
                        pd.cell_counts[0] += cells.len();
                        pd.verts.extend(cells);
                    }
                    "TRIANGLE_STRIPS" => {
                        let first = pd.cell_counts[3];
                        pd.cell_counts[3] += cells.len();
                        for (j, s) in cells.into_iter().enumerate() {
                            for k in 2..s.len() {
                                let t = if k % 2 == 0 {
                                    vec![s[k - 2], s[k - 1], s[k]]
                                } else {
                                    vec![s[k - 1], s[k - 2], s[k]]
                                };
                                pd.polys.push(t);
                                pd.poly_cells.push((true, first + j));
                            }
                        }
                    }
                    _ => {}
                }
            }
            "POINT_DATA" => {
                read_point_data(&mut c, &mut pd, binary)?;
                // Our writer (and others) put CELL_DATA after the point data, whose further
                // arrays this reader does not follow: the labels are found by their keyword.
                if let Some(at) = find_keyword(c.bytes, c.pos, b"CELL_DATA") {
                    c.pos = at;
                    c.word();
                    // Found by search, not reached by parsing: a problem there drops the labels.
                    if read_cell_data(&mut c, &mut pd, binary).is_err() {
                        pd.cell_scalars = None;
                    }
                }
                break;
            }
            "CELL_DATA" => {
                read_cell_data(&mut c, &mut pd, binary)?;
                break;
            }
            "FIELD" => skip_dataset_field(&mut c, binary)?,
            "METADATA" => skip_metadata(&mut c),
            other => {
                return Err(c.err(format!("unexpected keyword {}", quote(other))));
            }
        }
    }
    if pd.points.is_empty() {
        return Err(CoreError::parse(0, "no POINTS found"));
    }
    Ok(pd)
}

/// The first SCALARS array after `POINT_DATA` (the keyword read), kept when it has one value
/// per point.
fn read_point_data(c: &mut Cursor, pd: &mut PolyData, binary: bool) -> Result<()> {
    let n = c.count("point data count")?;
    if let Some(s) = read_point_scalars(c, binary, n)? {
        if s.1.len() == pd.points.len() {
            pd.point_scalars = Some(s);
        }
    }
    Ok(())
}

/// The arrays after `CELL_DATA n` (the keyword read): the first SCALARS (labels) and the string
/// arrays of FIELD blocks, then the POINT_DATA that VTK's own writer puts after them.
///
/// Labels are extras: a cell data layout this reader does not follow drops them, never the
/// geometry or the point data.
fn read_cell_data(c: &mut Cursor, pd: &mut PolyData, binary: bool) -> Result<()> {
    let n = c.count("cell data count")?;
    loop {
        let save = c.pos;
        let word = c.word().map(str::to_ascii_uppercase);
        c.pos = save;
        match word.as_deref() {
            Some("FIELD") => match read_cell_fields(c, n, binary) {
                Ok(arrays) => pd.cell_strings.extend(arrays),
                Err(_) => break,
            },
            Some("SCALARS") => match read_point_scalars(c, binary, n) {
                Ok(s) => {
                    if pd.cell_scalars.is_none() {
                        pd.cell_scalars = s;
                    }
                }
                Err(_) => break,
            },
            Some("POINT_DATA") => {
                c.word();
                return read_point_data(c, pd, binary);
            }
            _ => break,
        }
    }
    // Point data after cell arrays this reader passed over only in part.
    if pd.point_scalars.is_none() {
        if let Some(at) = find_keyword(c.bytes, c.pos, b"POINT_DATA") {
            c.pos = at;
            c.word();
            // Found by search, not reached by parsing: a problem there drops the point data.
            if read_point_data(c, pd, binary).is_err() {
                pd.point_scalars = None;
            }
        }
    }
    Ok(())
}

/// Byte offset of `keyword` at the start of a line at or after `from`.
fn find_keyword(bytes: &[u8], from: usize, keyword: &[u8]) -> Option<usize> {
    let rest = bytes.get(from..)?;
    rest.windows(keyword.len() + 1)
        .position(|w| w[0] == b'\n' && &w[1..] == keyword)
        .map(|p| from + p + 1)
}

/// One array's header line in a FIELD block (`NAME COMPONENTS TUPLES TYPE`); None for VTK's
/// `NULL_ARRAY` placeholder, which has no header and no values.
struct FieldArray {
    name: String,
    components: usize,
    tuples: usize,
    ty: String,
}

impl FieldArray {
    fn read(c: &mut Cursor) -> Result<Option<FieldArray>> {
        let name = c.need_word("array name")?;
        if name == "NULL_ARRAY" {
            return Ok(None);
        }
        let components = c.count("component count")?;
        let tuples = c.count("tuple count")?;
        let ty = c.need_word("array type")?.to_ascii_lowercase();
        Ok(Some(FieldArray {
            name,
            components,
            tuples,
            ty,
        }))
    }

    fn values(&self) -> usize {
        self.components.saturating_mul(self.tuples)
    }
}

/// Skips the `METADATA` block VTK 9 may write after an array's values.
fn skip_array_metadata(c: &mut Cursor) {
    let save = c.pos;
    if c.word().map(str::to_ascii_uppercase).as_deref() == Some("METADATA") {
        skip_metadata(c);
    } else {
        c.pos = save;
    }
}

/// Skips the dataset's own FIELD block (after `FIELD`), where VTK's writer puts field data:
/// right after `DATASET POLYDATA`, before POINTS (VTK's file-format guide; heartmesh's app writes
/// its parameters there). Nothing in it is geometry, so it is read past, not stopped at: stopping
/// there lost every POINTS and cell after it ("no POINTS found").
fn skip_dataset_field(c: &mut Cursor, binary: bool) -> Result<()> {
    c.need_word("field name")?;
    let arrays = c.count("field array count")?;
    for _ in 0..arrays {
        let Some(a) = FieldArray::read(c)? else {
            continue;
        };
        let (ty, total) = (a.ty.as_str(), a.values());
        c.end_line();
        if ty == "string" || ty == "utf8_string" {
            if binary {
                for _ in 0..total {
                    c.binary_string()?;
                }
                skip_array_metadata(c);
                continue;
            }
            for _ in 0..total {
                if c.pos >= c.bytes.len() {
                    return Err(c.err("file ends early in a string array"));
                }
                c.rest_of_line();
            }
        } else {
            c.binary = binary;
            for _ in 0..total {
                c.number(ty)?;
            }
            c.binary = false;
        }
        skip_array_metadata(c);
    }
    Ok(())
}

/// The string arrays of the FIELD blocks that follow `CELL_DATA n` (ASCII files); numeric
/// arrays are skipped. Strings are one per line, percent-encoded as VTK's own writer does.
fn read_cell_fields(
    c: &mut Cursor,
    ncells: usize,
    binary: bool,
) -> Result<Vec<(String, Vec<String>)>> {
    let mut out = Vec::new();
    loop {
        let save = c.pos;
        if c.word().map(str::to_ascii_uppercase).as_deref() != Some("FIELD") {
            c.pos = save;
            return Ok(out);
        }
        c.need_word("field name")?;
        let arrays = c.count("field array count")?;
        for _ in 0..arrays {
            let Some(a) = FieldArray::read(c)? else {
                continue;
            };
            let total = a.values();
            if a.ty == "string" || a.ty == "utf8_string" {
                c.end_line();
                let mut v = Vec::with_capacity(total.min(c.bytes.len()));
                for _ in 0..total {
                    if c.pos >= c.bytes.len() {
                        return Err(c.err("file ends early in a string array"));
                    }
                    v.push(if binary {
                        c.binary_string()?
                    } else {
                        percent_decode(c.rest_of_line())
                    });
                }
                if a.components == 1 && a.tuples == ncells {
                    out.push((a.name, v));
                }
            } else {
                c.end_line();
                c.binary = binary;
                for _ in 0..total {
                    c.number(&a.ty)?;
                }
                c.binary = false;
            }
            skip_array_metadata(c);
        }
    }
}

fn percent_decode(line: &[u8]) -> String {
    let mut out = Vec::with_capacity(line.len());
    let mut i = 0;
    while i < line.len() {
        let hex = line
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match (line[i], hex) {
            (b'%', Some(v)) => {
                out.push(v);
                i += 3;
            }
            (b, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// METADATA blocks (VTK 8+) end at a blank line.
fn skip_metadata(c: &mut Cursor) {
    while c.pos < c.bytes.len() {
        c.end_line();
        let rest = &c.bytes[c.pos..];
        let blank = rest
            .iter()
            .take_while(|&&b| b != b'\n')
            .all(|b| b.is_ascii_whitespace());
        if blank {
            c.end_line();
            return;
        }
    }
}

/// Cells in either layout: `n size` + `k i0 .. ik` records, or (5.1) `OFFSETS`/`CONNECTIVITY`.
fn read_cells(c: &mut Cursor, binary: bool, npoints: usize) -> Result<Vec<Vec<u32>>> {
    let n = c.count("cell count")?;
    let size = c.count("cell data size")?;
    let save = c.pos;
    let next = c.word().map(str::to_ascii_uppercase);
    if next.as_deref() == Some("OFFSETS") {
        // 5.1 layout: n is the number of offsets (cells + 1), size the connectivity length.
        let ty = c.need_word("offset type")?.to_ascii_lowercase();
        c.end_line();
        c.binary = binary;
        let mut offsets = Vec::with_capacity(n.min(c.bytes.len()));
        for _ in 0..n {
            offsets.push(c.number(&ty)?);
        }
        c.binary = false;
        if !c
            .need_word("CONNECTIVITY")?
            .eq_ignore_ascii_case("CONNECTIVITY")
        {
            return Err(c.err("expected CONNECTIVITY after OFFSETS"));
        }
        let ty = c.need_word("connectivity type")?.to_ascii_lowercase();
        c.end_line();
        c.binary = binary;
        let mut conn = Vec::with_capacity(size.min(c.bytes.len()));
        for _ in 0..size {
            conn.push(c.index(&ty, npoints)?);
        }
        c.binary = false;
        let mut cells = Vec::new();
        for w in offsets.windows(2) {
            let (a, b) = (w[0], w[1]);
            if !(a >= 0.0 && a <= b && b <= size as f64) {
                return Err(c.err(format!("bad cell offsets {a}..{b}")));
            }
            cells.push(conn[a as usize..b as usize].to_vec());
        }
        return Ok(cells);
    }
    c.pos = save;
    c.end_line();
    c.binary = binary;
    let mut cells = Vec::with_capacity(n.min(c.bytes.len()));
    let mut used = 0usize;
    for _ in 0..n {
        let k = c.number("int")?;
        let room = size.saturating_sub(used + 1) as f64;
        if !(k >= 0.0 && k.fract() == 0.0 && k <= room) {
            return Err(c.err(format!(
                "cell size {k} does not fit the declared data size {size}"
            )));
        }
        used += 1 + k as usize;
        let mut cell = Vec::with_capacity(k as usize);
        for _ in 0..k as usize {
            cell.push(c.index("int", npoints)?);
        }
        cells.push(cell);
    }
    c.binary = false;
    Ok(cells)
}

/// The first `SCALARS name type [components]` array of POINT_DATA (first component); also
/// passes over a cell data SCALARS array (`n` cells).
fn read_point_scalars(
    c: &mut Cursor,
    binary: bool,
    n: usize,
) -> Result<Option<(String, Vec<f64>)>> {
    let Some(w) = c.word().map(str::to_ascii_uppercase) else {
        return Ok(None);
    };
    if w != "SCALARS" {
        return Ok(None);
    }
    let (name, ty, comps) = scalars_header(c)?;
    c.end_line();
    c.binary = binary;
    let mut v = Vec::with_capacity(n.min(c.bytes.len()));
    for _ in 0..n {
        v.push(c.number(&ty)?);
        for _ in 1..comps {
            c.number(&ty)?;
        }
    }
    c.binary = false;
    Ok(Some((name, v)))
}

/// The rest of a `SCALARS name type [components]` line (the keyword read) and the optional
/// `LOOKUP_TABLE name` after it: (name, type, components).
fn scalars_header(c: &mut Cursor) -> Result<(String, String, usize)> {
    let name = c.need_word("scalar name")?;
    let ty = c.need_word("scalar type")?.to_ascii_lowercase();
    let save = c.pos;
    let mut comps = 1usize;
    match c.word().map(|w| w.parse::<usize>()) {
        Some(Ok(k)) if (1..=4).contains(&k) => comps = k,
        _ => c.pos = save,
    }
    let save = c.pos;
    if c.word().map(str::to_ascii_uppercase).as_deref() == Some("LOOKUP_TABLE") {
        c.need_word("lookup table name")?;
    } else {
        c.pos = save;
    }
    Ok((name, ty, comps))
}

/// Reads the polygons of a POLYDATA file as a triangle mesh (fan-triangulated).
pub fn read_vtk_mesh(bytes: &[u8]) -> Result<MeshData> {
    let mut pd = read_polydata(bytes)?;
    let points = std::mem::take(&mut pd.points);
    let mut data = mesh_from_cells(points, &pd.polys, pd.point_scalars.take())?;
    data.regions = pd.regions(data.mesh.triangles.len());
    Ok(data)
}

pub(crate) fn mesh_from_cells(
    points: Vec<Vec3>,
    polys: &[Vec<u32>],
    point_data: Option<(String, Vec<f64>)>,
) -> Result<MeshData> {
    check_indices(points.len(), polys)?;
    let mut triangles = Vec::new();
    for p in polys {
        for k in 1..p.len().saturating_sub(1) {
            if triangles.len() >= MAX_MESH_ELEMENTS {
                return Err(CoreError::parse(0, "too many triangles"));
            }
            triangles.push([p[0], p[k], p[k + 1]]);
        }
    }
    if triangles.is_empty() {
        return Err(CoreError::parse(0, "no polygons found"));
    }
    let point_data = point_data.filter(|(_, v)| v.len() == points.len());
    Ok(MeshData {
        mesh: TriMesh::new(points, triangles),
        point_data,
        regions: None,
        coordinate_system: None,
    })
}

/// Cells read before a later POINTS section replaced the points may point past the end.
fn check_indices(n: usize, cells: &[Vec<u32>]) -> Result<()> {
    match cells.iter().flatten().find(|&&i| i as usize >= n) {
        Some(i) => Err(CoreError::parse(
            0,
            format!("cell refers to point {i}, but there are {n} points"),
        )),
        None => Ok(()),
    }
}

/// Reads the line cells of a POLYDATA file as contours `line1`, `line2`, ... (one per cell).
/// Without line cells, the polygons are read as closed contours (`contours_from_polygons`).
pub fn read_vtk_contours(bytes: &[u8]) -> Result<ContourSet> {
    let pd = read_polydata(bytes)?;
    if pd.lines.is_empty() && !pd.polys.is_empty() {
        return contours_from_polygons(&pd.points, &pd.polys, pd.lines_at);
    }
    let labels = LineLabels::from_cell_strings(&pd.cell_strings, pd.verts.len(), pd.lines.len());
    let vert_labels = LineLabels::from_cell_strings(&pd.cell_strings, 0, pd.verts.len());
    let landmarks = vertex_landmarks(&pd.points, &pd.verts, &vert_labels);
    contours_from_lines(&pd.points, &pd.lines, pd.lines_at, &labels, &landmarks)
}

/// The landmarks among vertex cells: one-point cells named in [`CONTOUR_ID_ARRAY`] whose surface
/// is [`LANDMARK_SURFACE`] (as [`crate::io::write_contour_lines`] writes them). Other vertex cells
/// (point clouds, glyph seeds of other tools) are left out, as they always were.
pub(crate) fn vertex_landmarks(
    points: &[Vec3],
    verts: &[Vec<u32>],
    labels: &LineLabels,
) -> Vec<(String, Vec3)> {
    let (Some(ids), Some(surfaces)) = (&labels.ids, &labels.surfaces) else {
        return Vec::new();
    };
    verts
        .iter()
        .zip(ids.iter().zip(surfaces))
        .filter_map(|(cell, (id, surface))| match cell.as_slice() {
            [i] if !id.is_empty() && surface == LANDMARK_SURFACE => {
                Some((id.clone(), *points.get(*i as usize)?))
            }
            _ => None,
        })
        .collect()
}

/// Polygons of fewer points than this (median) are a surface's faces, not delineated curves.
const MIN_CONTOUR_POLYGON: usize = 6;

/// One closed contour per polygon, `polygon1`, `polygon2`, ...: DICOM-RT converters (a
/// CLOSED_PLANAR contour is a polygon) and some VTK pipelines store closed curves this way.
/// Polygons of a few points each are a surface mesh's faces: refused with what the file is.
pub(crate) fn contours_from_polygons(
    points: &[Vec3],
    polys: &[Vec<u32>],
    line: usize,
) -> Result<ContourSet> {
    check_indices(points.len(), polys)?;
    let mut sizes: Vec<usize> = polys.iter().map(Vec::len).collect();
    sizes.sort_unstable();
    let median = sizes.get(sizes.len() / 2).copied().unwrap_or(0);
    if median < MIN_CONTOUR_POLYGON {
        return Err(CoreError::parse(
            0,
            format!(
                "no LINES (polylines) found: the file holds a surface of {} polygons (a mesh), \
                 not contours",
                polys.len()
            ),
        ));
    }
    let mut b = ContourBuilder::new();
    for (k, cell) in polys.iter().enumerate() {
        let ring: Vec<Vec3> = cell.iter().map(|&i| points[i as usize]).collect();
        b.push_piece(&format!("polygon{}", k + 1), None, ring, Some(true), line)?;
    }
    b.finish()
}

/// One contour per line cell, `line1`, `line2`, ... unless the file names them; cells with the
/// same identifier are the pieces of one contour. `landmarks` (see [`vertex_landmarks`]) go
/// through the builder like those of the other readers.
pub(crate) fn contours_from_lines(
    points: &[Vec3],
    lines: &[Vec<u32>],
    line: usize,
    labels: &LineLabels,
    landmarks: &[(String, Vec3)],
) -> Result<ContourSet> {
    if lines.is_empty() {
        return Err(CoreError::parse(0, "no LINES (polylines) found"));
    }
    check_indices(points.len(), lines)?;
    let mut b = ContourBuilder::new();
    for (k, cell) in lines.iter().enumerate() {
        let id = match labels.ids.as_ref().and_then(|v| v.get(k)) {
            Some(id) if !id.is_empty() => id.clone(),
            _ => format!("line{}", k + 1),
        };
        let surface = labels
            .surfaces
            .as_ref()
            .and_then(|v| v.get(k))
            .filter(|s| !s.is_empty());
        for &i in cell {
            b.push(&id, surface.map(String::as_str), points[i as usize], line)?;
        }
        b.break_run();
    }
    for (name, p) in landmarks {
        b.landmark(name, *p, line)?;
    }
    b.finish()
}
