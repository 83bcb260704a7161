//! The VTK legacy writer: version 3.0 ASCII POLYDATA, triangles with point scalars and optional
//! region cell labels (meshes) or lines with string cell labels (contours).

use super::{CONTOUR_ID_ARRAY, SURFACE_ARRAY};
use crate::geometry::Vec3;
use crate::io::{header_lines, push_number_lines, push_point_lines, Regions};
use crate::mesh::TriMesh;

/// VTK's string encoding in legacy files: `%XX` for '%', spaces, control and non-ASCII bytes.
fn percent_encode(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for b in s.bytes() {
        if b <= b' ' || b > b'~' || b == b'%' {
            out.push_str(&format!("%{b:02X}"));
        } else {
            out.push(b as char);
        }
    }
    out
}

const TITLE_MAX: usize = 160;

/// The title line: version and comment, short (see [`write_vtk`]).
pub(super) fn title(header_comment: &str) -> String {
    // Readers such as three.js' VTKLoader look for "ASCII" within the first 250 bytes, so the
    // title (limited to 256 characters by the format) is kept well below that.
    let full: String = header_lines(header_comment)
        .join(" | ")
        .chars()
        .filter(|c| c.is_ascii() && !c.is_ascii_control())
        .collect();
    if full.len() <= TITLE_MAX {
        return full;
    }
    // Cut after the last whole clause that fits (else the last word), marked, rather than
    // mid-word: a wall's title ended "region 1 epicardium, 2 lv" (the full list is in the cell
    // data anyway). A cut that would keep under half the room falls back to the next finer one.
    const MORE: &str = " ...";
    let head = &full[..TITLE_MAX - MORE.len()];
    let cut = [["; ", " | "].as_slice(), &[", "], &[" "]]
        .iter()
        .find_map(|seps| {
            seps.iter()
                .filter_map(|sep| head.rfind(sep))
                .max()
                .filter(|&at| at >= head.len() / 2)
        })
        .unwrap_or(head.len());
    format!("{}{MORE}", &head[..cut])
}

/// Polylines (contours) as VTK legacy 3.0 ASCII POLYDATA LINES, after `verts` (landmarks: the
/// point of each one-point VERTICES cell, written first as VTK orders cell data: verts, lines);
/// `labels` (one (id, surface) per cell, verts then lines, or empty) go into a CELL_DATA field of
/// two string arrays.
pub(crate) fn write_lines(
    points: &[Vec3],
    verts: &[u32],
    cells: &[Vec<u32>],
    labels: &[(&str, &str)],
    header_comment: &str,
) -> Vec<u8> {
    let mut out = format!(
        "# vtk DataFile Version 3.0\n{}\nASCII\nDATASET POLYDATA\nPOINTS {} double\n",
        title(header_comment),
        points.len()
    );
    push_point_lines(&mut out, points);
    if !verts.is_empty() {
        out.push_str(&format!("VERTICES {} {}\n", verts.len(), 2 * verts.len()));
        for i in verts {
            out.push_str(&format!("1 {i}\n"));
        }
    }
    let size: usize = cells.iter().map(|c| c.len() + 1).sum();
    out.push_str(&format!("LINES {} {size}\n", cells.len()));
    for c in cells {
        out.push_str(&c.len().to_string());
        for i in c {
            out.push_str(&format!(" {i}"));
        }
        out.push('\n');
    }
    let n = verts.len() + cells.len();
    if !labels.is_empty() && labels.len() == n {
        out.push_str(&format!(
            "CELL_DATA {n}\nFIELD FieldData 2\n{CONTOUR_ID_ARRAY} 1 {n} string\n"
        ));
        for (id, _) in labels {
            out.push_str(&percent_encode(id));
            out.push('\n');
        }
        out.push_str(&format!("{SURFACE_ARRAY} 1 {n} string\n"));
        for (_, surface) in labels {
            out.push_str(&percent_encode(surface));
            out.push('\n');
        }
    }
    out.into_bytes()
}

/// VTK legacy 3.0 ASCII POLYDATA with triangles and the optional point scalars.
pub fn write_vtk(
    mesh: &TriMesh,
    point_data: Option<(&str, &[f64])>,
    header_comment: &str,
) -> Vec<u8> {
    write_vtk_with(mesh, point_data, None, header_comment)
}

/// [`write_vtk`] with the regions (checked by [`crate::io::write_mesh_with`]) as CELL_DATA after
/// the POINT_DATA block: `SCALARS ARRAY int 1` with `id + 1` per triangle, the cell scalars that
/// ParaView colours and thresholds by, and a FIELD string array `ARRAY_name` with each
/// triangle's region name, so the numbers explain themselves. The legacy format lets the two
/// blocks come in either order (VTK reads both); this one keeps every byte before CELL_DATA as
/// without regions, and our reader, which stops after POINT_DATA, reads the mesh as before.
pub(crate) fn write_vtk_with(
    mesh: &TriMesh,
    point_data: Option<(&str, &[f64])>,
    regions: Option<&Regions>,
    header_comment: &str,
) -> Vec<u8> {
    let title = title(header_comment);
    let mut out = format!(
        "# vtk DataFile Version 3.0\n{title}\nASCII\nDATASET POLYDATA\nPOINTS {} double\n",
        mesh.positions.len()
    );
    push_point_lines(&mut out, &mesh.positions);
    out.push_str(&format!(
        "POLYGONS {} {}\n",
        mesh.triangles.len(),
        4 * mesh.triangles.len()
    ));
    for t in &mesh.triangles {
        out.push_str(&format!("3 {} {} {}\n", t[0], t[1], t[2]));
    }
    if let Some((name, values)) = point_data {
        out.push_str(&format!(
            "POINT_DATA {}\nSCALARS {} double 1\nLOOKUP_TABLE default\n",
            values.len(),
            array_name(name)
        ));
        push_number_lines(&mut out, values);
    }
    if let Some(r) = regions {
        push_region_cells(&mut out, r, mesh.triangles.len());
    }
    out.into_bytes()
}

/// An array name as one legacy-file token: printable ASCII, anything else as `_`.
fn array_name(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_ascii_graphic() { c } else { '_' })
        .collect()
}

/// The CELL_DATA block of [`write_vtk_with`] for `n` triangles.
fn push_region_cells(out: &mut String, regions: &Regions, n: usize) {
    out.push_str(&format!(
        "CELL_DATA {n}\nSCALARS {} int 1\nLOOKUP_TABLE default\n",
        array_name(regions.array)
    ));
    for t in 0..n {
        out.push_str(&format!("{}\n", regions.value(t)));
    }
    out.push_str(&format!(
        "FIELD FieldData 1\n{} 1 {n} string\n",
        array_name(&regions.names_array())
    ));
    for t in 0..n {
        out.push_str(&percent_encode(regions.name_of(t)));
        out.push('\n');
    }
}

/// A volume mesh as VTK legacy 3.0 ASCII UNSTRUCTURED_GRID: `cells` as (VTK cell type, point
/// indices), then per-point double arrays (SCALARS) and vectors (VECTORS), and per-cell int
/// arrays (SCALARS) (the
/// hexahedral myocardium, `mesh::hex_wall`, for ParaView, meshio and the simulation codes that
/// read VTK).
pub fn write_unstructured(
    points: &[Vec3],
    cells: &[(u8, &[u32])],
    point_data: &[(&str, &[f64])],
    point_vectors: &[(&str, &[Vec3])],
    cell_data: &[(&str, &[u32])],
    header_comment: &str,
) -> Vec<u8> {
    let title = title(header_comment);
    let mut out = format!(
        "# vtk DataFile Version 3.0\n{title}\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS {} double\n",
        points.len()
    );
    push_point_lines(&mut out, points);
    let size: usize = cells.iter().map(|(_, p)| p.len() + 1).sum();
    out.push_str(&format!("CELLS {} {size}\n", cells.len()));
    for (_, ids) in cells {
        out.push_str(&ids.len().to_string());
        for i in *ids {
            out.push(' ');
            out.push_str(&i.to_string());
        }
        out.push('\n');
    }
    out.push_str(&format!("CELL_TYPES {}\n", cells.len()));
    for (ty, _) in cells {
        out.push_str(&format!("{ty}\n"));
    }
    if !point_data.is_empty() || !point_vectors.is_empty() {
        out.push_str(&format!("POINT_DATA {}\n", points.len()));
        for (name, values) in point_data {
            out.push_str(&format!(
                "SCALARS {} double 1\nLOOKUP_TABLE default\n",
                array_name(name)
            ));
            push_number_lines(&mut out, values);
        }
        for (name, vectors) in point_vectors {
            out.push_str(&format!("VECTORS {} double\n", array_name(name)));
            push_point_lines(&mut out, vectors);
        }
    }
    if !cell_data.is_empty() {
        out.push_str(&format!("CELL_DATA {}\n", cells.len()));
        for (name, values) in cell_data {
            out.push_str(&format!(
                "SCALARS {} int 1\nLOOKUP_TABLE default\n",
                array_name(name)
            ));
            for v in *values {
                out.push_str(&format!("{v}\n"));
            }
        }
    }
    out.into_bytes()
}
