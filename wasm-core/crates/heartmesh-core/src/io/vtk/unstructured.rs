//! VTK legacy UNSTRUCTURED_GRID files (volume meshes: `myocardium --hex-mesh`'s hexahedra, the
//! tetrahedra gmsh, TetGen or VTK write): the points, the cells and their types, and what data
//! arrays the points and cells carry (name, components, range). Enough for `heartmesh info` to
//! describe a volume mesh instead of refusing it; nothing here builds a surface from one.

use super::{find_keyword, open_dataset, read_cells, read_points, scalars_header};
use super::{skip_array_metadata, skip_dataset_field, skip_metadata, Cursor, FieldArray};
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::io::text::quote;
use serde::Serialize;

/// The parts of an UNSTRUCTURED_GRID file heartmesh reads.
#[derive(Debug, Default)]
pub struct UnstructuredGrid {
    pub points: Vec<Vec3>,
    /// Per cell, its point indices and its VTK type number.
    pub cells: Vec<Vec<u32>>,
    pub types: Vec<u8>,
    pub point_arrays: Vec<DataArray>,
    pub cell_arrays: Vec<DataArray>,
}

/// One data array of the points or cells: its name, how many components each tuple has, and
/// the range of its values (of the tuples' lengths for vectors and normals).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DataArray {
    pub name: String,
    pub components: usize,
    /// SCALARS, VECTORS, NORMALS, TENSORS, FIELD, ... as the file calls it.
    pub kind: String,
    /// None for string arrays and empty ones.
    pub min: Option<f64>,
    pub max: Option<f64>,
}

/// Whether `bytes` is a VTK legacy file whose dataset is an UNSTRUCTURED_GRID.
pub fn is_unstructured_grid(bytes: &[u8]) -> bool {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    bytes.starts_with(b"# vtk DataFile")
        && find_keyword(bytes, 0, b"DATASET UNSTRUCTURED_GRID").is_some_and(|at| at < 2048)
}

/// Parses a legacy UNSTRUCTURED_GRID file (ASCII or BINARY, classic or 5.1 cell layout).
pub fn read_unstructured(bytes: &[u8]) -> Result<UnstructuredGrid> {
    let (mut c, binary) = open_dataset(
        bytes,
        "UNSTRUCTURED_GRID",
        "expected DATASET UNSTRUCTURED_GRID",
    )?;
    let mut g = UnstructuredGrid::default();
    // Which attribute arrays now follow: none yet, the points' (n) or the cells' (n).
    let mut target: Option<(bool, usize)> = None;
    while let Some(w) = c.word() {
        let w = w.to_ascii_uppercase();
        match w.as_str() {
            "POINTS" => {
                g.points = read_points(&mut c, binary)?;
                skip_array_metadata(&mut c);
            }
            "CELLS" => {
                g.cells = read_cells(&mut c, binary, g.points.len())?;
                skip_array_metadata(&mut c);
            }
            "CELL_TYPES" => {
                let n = c.count("cell type count")?;
                c.end_line();
                c.binary = binary;
                g.types = Vec::with_capacity(n.min(bytes.len()));
                for _ in 0..n {
                    let t = c.number("int")?;
                    if !(0.0..=255.0).contains(&t) || t.fract() != 0.0 {
                        return Err(c.err(format!("{t} is not a VTK cell type")));
                    }
                    g.types.push(t as u8);
                }
                c.binary = false;
                skip_array_metadata(&mut c);
            }
            "POINT_DATA" | "CELL_DATA" => {
                let n = c.count("data count")?;
                target = Some((w == "POINT_DATA", n));
            }
            "FIELD" if target.is_none() => skip_dataset_field(&mut c, binary)?,
            "METADATA" => skip_metadata(&mut c),
            array => {
                let Some((on_points, n)) = target else {
                    return Err(c.err(format!("unexpected keyword {}", quote(array))));
                };
                let arrays = read_arrays(&mut c, array, n, binary)?;
                if on_points {
                    g.point_arrays.extend(arrays);
                } else {
                    g.cell_arrays.extend(arrays);
                }
            }
        }
    }
    check(&g)?;
    Ok(g)
}

/// The counts agree: one type per cell, every cell of a known type with its points.
fn check(g: &UnstructuredGrid) -> Result<()> {
    if g.points.is_empty() {
        return Err(CoreError::parse(0, "no POINTS found"));
    }
    if g.cells.len() != g.types.len() {
        return Err(CoreError::parse(
            0,
            format!(
                "{} cells but {} cell types (CELLS and CELL_TYPES must agree)",
                g.cells.len(),
                g.types.len()
            ),
        ));
    }
    for (k, (cell, &ty)) in g.cells.iter().zip(&g.types).enumerate() {
        if let Some(n) = crate::mesh::cells::point_count(ty) {
            if cell.len() != n {
                return Err(CoreError::parse(
                    0,
                    format!(
                        "cell {k} is a {} with {} points (it has {n})",
                        crate::mesh::cells::type_name(ty),
                        cell.len()
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// One attribute array (or a FIELD block's arrays) of `n` tuples, after its keyword.
fn read_arrays(c: &mut Cursor, keyword: &str, n: usize, binary: bool) -> Result<Vec<DataArray>> {
    let (name, ty, components) = match keyword {
        "SCALARS" => scalars_header(c)?,
        "VECTORS" | "NORMALS" => {
            let name = c.need_word("array name")?;
            (name, c.need_word("array type")?.to_ascii_lowercase(), 3)
        }
        "TENSORS" => {
            let name = c.need_word("array name")?;
            (name, c.need_word("array type")?.to_ascii_lowercase(), 9)
        }
        "COLOR_SCALARS" => {
            let name = c.need_word("array name")?;
            let k = c.count("colour components")?;
            let ty = if binary { "unsigned_char" } else { "float" };
            (name, ty.to_string(), k)
        }
        "TEXTURE_COORDINATES" => {
            let name = c.need_word("array name")?;
            let k = c.count("texture dimension")?;
            (name, c.need_word("array type")?.to_ascii_lowercase(), k)
        }
        "LOOKUP_TABLE" => {
            c.need_word("lookup table name")?;
            let size = c.count("lookup table size")?;
            let ty = if binary { "unsigned_char" } else { "float" };
            values(c, ty, size.saturating_mul(4), 1, binary)?;
            return Ok(Vec::new());
        }
        "FIELD" => return read_field(c, binary),
        other => return Err(c.err(format!("unexpected keyword {}", quote(other)))),
    };
    let (min, max) = values(c, &ty, n.saturating_mul(components), components, binary)?;
    Ok(vec![DataArray {
        name,
        components,
        kind: keyword.to_string(),
        min,
        max,
    }])
}

/// A FIELD block's arrays (after `FIELD`).
fn read_field(c: &mut Cursor, binary: bool) -> Result<Vec<DataArray>> {
    c.need_word("field name")?;
    let count = c.count("field array count")?;
    let mut out = Vec::new();
    for _ in 0..count {
        let Some(a) = FieldArray::read(c)? else {
            continue;
        };
        let (min, max) = if a.ty == "string" || a.ty == "utf8_string" {
            c.end_line();
            for _ in 0..a.values() {
                if c.pos >= c.bytes.len() {
                    return Err(c.err("file ends early in a string array"));
                }
                if binary {
                    c.binary_string()?;
                } else {
                    c.rest_of_line();
                }
            }
            skip_array_metadata(c);
            (None, None)
        } else {
            values(c, &a.ty, a.values(), a.components, binary)?
        };
        out.push(DataArray {
            name: a.name,
            components: a.components,
            kind: "FIELD".into(),
            min,
            max,
        });
    }
    Ok(out)
}

/// Reads `total` numbers of `ty` (binary data from the next line), the range of the values
/// (or, for 3-component tuples, of their lengths).
fn values(
    c: &mut Cursor,
    ty: &str,
    total: usize,
    components: usize,
    binary: bool,
) -> Result<(Option<f64>, Option<f64>)> {
    c.end_line();
    c.binary = binary;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut tuple = [0.0f64; 3];
    for i in 0..total {
        let v = c.number(ty)?;
        if components == 3 {
            tuple[i % 3] = v;
            if i % 3 == 2 {
                let len = (tuple[0] * tuple[0] + tuple[1] * tuple[1] + tuple[2] * tuple[2]).sqrt();
                lo = lo.min(len);
                hi = hi.max(len);
            }
        } else if v.is_finite() {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    c.binary = false;
    skip_array_metadata(c);
    Ok(if lo <= hi {
        (Some(lo), Some(hi))
    } else {
        (None, None)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;
    use crate::io::vtk::write_unstructured;

    /// Two unit cubes side by side (x 0-2) and a wedge on top of the first.
    fn grid() -> (Vec<Vec3>, Vec<(u8, Vec<u32>)>) {
        let mut p = Vec::new();
        for z in [0.0, 1.0] {
            for (x, y) in [(0., 0.), (1., 0.), (2., 0.), (0., 1.), (1., 1.), (2., 1.)] {
                p.push(v3(x, y, z));
            }
        }
        p.push(v3(0.0, 0.0, 2.0)); // 12
        p.push(v3(1.0, 0.0, 2.0)); // 13
        p.push(v3(0.0, 1.0, 2.0)); // 14
        let cells = vec![
            (12, vec![0, 1, 4, 3, 6, 7, 10, 9]),
            (12, vec![1, 2, 5, 4, 7, 8, 11, 10]),
            (13, vec![6, 7, 9, 12, 13, 14]),
        ];
        (p, cells)
    }

    #[test]
    fn our_own_volume_mesh_reads_back_with_its_arrays() {
        let (points, cells) = grid();
        let refs: Vec<(u8, &[u32])> = cells.iter().map(|(t, c)| (*t, c.as_slice())).collect();
        let height: Vec<f64> = points.iter().map(|p| p.z).collect();
        let up = vec![v3(0.0, 0.0, 2.0); points.len()];
        let segment = [1u32, 2, 17];
        let bytes = write_unstructured(
            &points,
            &refs,
            &[("height", &height)],
            &[("up", &up)],
            &[("segment", &segment)],
            "a test grid",
        );
        assert!(is_unstructured_grid(&bytes));
        let g = read_unstructured(&bytes).unwrap();
        assert_eq!(g.points, points);
        assert_eq!(g.types, vec![12, 12, 13]);
        assert_eq!(
            g.cells,
            cells.iter().map(|c| c.1.clone()).collect::<Vec<_>>()
        );
        let names: Vec<(&str, usize, Option<f64>, Option<f64>)> = g
            .point_arrays
            .iter()
            .chain(&g.cell_arrays)
            .map(|a| (a.name.as_str(), a.components, a.min, a.max))
            .collect();
        assert_eq!(
            names,
            vec![
                ("height", 1, Some(0.0), Some(2.0)),
                ("up", 3, Some(2.0), Some(2.0)),
                ("segment", 1, Some(1.0), Some(17.0)),
            ]
        );
        let q = crate::mesh::cells::quality(
            &g.points,
            g.types
                .iter()
                .zip(&g.cells)
                .map(|(&t, c)| (t, c.as_slice())),
        );
        assert!((q.volume - 2.5).abs() < 1e-12, "{}", q.volume);
        assert_eq!(q.inverted, 0);
    }

    #[test]
    fn other_writers_layouts_read_too() {
        // VTK 9's 5.1 layout (OFFSETS / CONNECTIVITY), a FIELD block of point data with a
        // string array, METADATA, and a dataset FIELD before the points.
        let text = "# vtk DataFile Version 5.1\nvtk output\nASCII\nDATASET UNSTRUCTURED_GRID\n\
            FIELD FieldData 1\nTimeValue 1 1 double\n0\n\
            POINTS 5 float\n0 0 0 1 0 0 0 1 0\n0 0 1 1 1 1\n\
            METADATA\nINFORMATION 0\n\n\
            CELLS 3 8\nOFFSETS vtktypeint64\n0 4 8\nCONNECTIVITY vtktypeint64\n0 1 2 3 1 2 3 4\n\
            CELL_TYPES 2\n10\n10\n\
            POINT_DATA 5\nFIELD FieldData 2\nid 1 5 int\n0 1 2 3 4\nlabel 1 5 string\na\nb\nc\nd\ne\n\
            CELL_DATA 2\nNORMALS n float\n0 0 3 0 4 0\n";
        let g = read_unstructured(text.as_bytes()).unwrap();
        assert_eq!(g.cells, vec![vec![0, 1, 2, 3], vec![1, 2, 3, 4]]);
        assert_eq!(g.point_arrays.len(), 2);
        assert_eq!(
            (g.point_arrays[0].min, g.point_arrays[0].max),
            (Some(0.0), Some(4.0))
        );
        assert_eq!(g.point_arrays[1].min, None, "strings have no range");
        assert_eq!(
            (g.cell_arrays[0].min, g.cell_arrays[0].max),
            (Some(3.0), Some(4.0))
        );
        // BINARY (big-endian): one tetrahedron, float points, int cells.
        let mut b =
            b"# vtk DataFile Version 3.0\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n"
                .to_vec();
        for x in [0f32, 0., 0., 2., 0., 0., 0., 2., 0., 0., 0., 2.] {
            b.extend_from_slice(&x.to_be_bytes());
        }
        b.extend_from_slice(b"\nCELLS 1 5\n");
        for i in [4i32, 0, 1, 2, 3] {
            b.extend_from_slice(&i.to_be_bytes());
        }
        b.extend_from_slice(b"\nCELL_TYPES 1\n");
        b.extend_from_slice(&10i32.to_be_bytes());
        b.push(b'\n');
        let g = read_unstructured(&b).unwrap();
        let q = crate::mesh::cells::quality(&g.points, [(g.types[0], g.cells[0].as_slice())]);
        assert!((q.volume - 8.0 / 6.0).abs() < 1e-9, "{}", q.volume);
    }

    #[test]
    fn broken_grids_are_errors_not_panics() {
        let head = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n\
            POINTS 4 double\n0 0 0 1 0 0 0 1 0 0 0 1\n";
        for (tail, says) in [
            (
                "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 2\n10\n10\n",
                "1 cells but 2 cell types",
            ),
            (
                "CELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n10\n",
                "is a tetrahedron with 3 points",
            ),
            ("CELLS 1 5\n4 0 1 2 9\nCELL_TYPES 1\n10\n", "outside 0..4"),
            (
                "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n300\n",
                "not a VTK cell type",
            ),
            ("CELLS 1 5\n4 0 1", "ends"),
            ("SCALARS s double\n1 2 3 4\n", "unexpected keyword"),
            (
                "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\nPOINT_DATA 4\nSCALARS s double\n1 2\n",
                "",
            ),
        ] {
            let e = read_unstructured(format!("{head}{tail}").as_bytes()).unwrap_err();
            assert!(e.to_string().contains(says), "{tail:?}: {e}");
        }
        let poly = b"# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 0 float\n";
        assert!(!is_unstructured_grid(poly));
        assert!(read_unstructured(poly)
            .unwrap_err()
            .to_string()
            .contains("UNSTRUCTURED_GRID"));
        assert!(read_unstructured(b"").is_err());
    }
}
