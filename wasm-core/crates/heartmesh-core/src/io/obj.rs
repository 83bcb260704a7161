//! Wavefront OBJ triangle meshes: reading (`v`, `f` with `v/vt/vn` forms, negative indices,
//! polygons fan-triangulated; everything else ignored) and writing.

use super::text::{data_lines, decode, parse_coord, quote};
use super::{fmt_point, header_lines, MeshData, MeshRegions, Regions, MAX_MESH_ELEMENTS};
use crate::error::{CoreError, Result};
use crate::geometry::v3;
use crate::mesh::TriMesh;

/// Reads an OBJ file into a triangle mesh (faces with more than three corners become fans).
pub fn read_obj(bytes: &[u8]) -> Result<MeshData> {
    let text = decode(bytes)?;
    let mut mesh = TriMesh::default();
    let mut corners: Vec<u32> = Vec::new();
    let mut groups = Groups::default();
    for (line, row) in data_lines(&text) {
        let mut it = row.split_whitespace();
        match it.next() {
            Some("v") => {
                let mut c = [0.0; 3];
                for (k, name) in ["x", "y", "z"].iter().enumerate() {
                    let f = it.next().ok_or_else(|| {
                        CoreError::parse(line, format!("vertex has no {name} coordinate"))
                    })?;
                    c[k] = parse_coord(f, line, &format!("vertex {name}"))?;
                }
                if mesh.positions.len() >= MAX_MESH_ELEMENTS {
                    return Err(too_many(line));
                }
                mesh.positions.push(v3(c[0], c[1], c[2]));
            }
            Some("f") => {
                corners.clear();
                for tok in it {
                    corners.push(resolve_index(tok, mesh.positions.len(), line)?);
                }
                if corners.len() < 3 {
                    return Err(CoreError::parse(
                        line,
                        format!("face has {} corners; at least 3 needed", corners.len()),
                    ));
                }
                for k in 1..corners.len() - 1 {
                    if mesh.triangles.len() >= MAX_MESH_ELEMENTS {
                        return Err(too_many(line));
                    }
                    mesh.triangles
                        .push([corners[0], corners[k], corners[k + 1]]);
                    let g = groups.face();
                    groups.labels.push(g);
                }
            }
            Some("g") => groups.enter(it.collect::<Vec<_>>().join(" ")),
            _ => {}
        }
    }
    if mesh.positions.is_empty() {
        return Err(CoreError::parse(0, "no vertices (v lines) found"));
    }
    if mesh.triangles.is_empty() {
        return Err(CoreError::parse(0, "no faces (f lines) found"));
    }
    Ok(MeshData {
        mesh,
        point_data: None,
        regions: groups.finish(),
        coordinate_system: None,
    })
}

/// The `g` groups faces fall in, numbered 1, 2, ... in order of first appearance (what our
/// writer's region numbers are); faces before any `g` line are in OBJ's `default` group.
#[derive(Default)]
struct Groups {
    names: Vec<String>,
    /// The group of the next face (0: none entered yet).
    current: i32,
    labels: Vec<i32>,
    /// Whether any `g` line was seen: a file without one has no regions.
    named: bool,
}

impl Groups {
    fn enter(&mut self, name: String) {
        self.named = true;
        self.current = self.number(if name.is_empty() { "default" } else { &name });
    }

    fn number(&mut self, name: &str) -> i32 {
        match self.names.iter().position(|n| n == name) {
            Some(k) => k as i32 + 1,
            None => {
                self.names.push(name.to_string());
                self.names.len() as i32
            }
        }
    }

    fn face(&mut self) -> i32 {
        if self.current == 0 {
            self.current = self.number("default");
        }
        self.current
    }

    fn finish(self) -> Option<MeshRegions> {
        self.named.then(|| MeshRegions {
            array: "group".into(),
            labels: self.labels,
            names: (1..).zip(self.names).collect(),
        })
    }
}

fn too_many(line: usize) -> CoreError {
    CoreError::parse(
        line,
        format!("too many elements: the limit is {MAX_MESH_ELEMENTS} vertices or triangles"),
    )
}

/// `7`, `7/1`, `7//3`, `7/1/3` or negative (relative to the vertices read so far).
fn resolve_index(tok: &str, count: usize, line: usize) -> Result<u32> {
    let head = tok.split('/').next().unwrap_or(tok);
    let i: i64 = head.parse().map_err(|_| {
        CoreError::parse(
            line,
            format!("face corner {} is not a vertex index", quote(tok)),
        )
    })?;
    let n = count as i64;
    let idx = if i > 0 { i - 1 } else { n + i };
    if i == 0 || idx < 0 || idx >= n {
        return Err(CoreError::parse(
            line,
            format!("face refers to vertex {i}, but {count} vertices are defined so far"),
        ));
    }
    u32::try_from(idx).map_err(|_| too_many(line))
}

/// Writes OBJ text: a `# heartmesh <version>` line, the comment, then `v` and `f` lines.
pub fn write_obj(mesh: &TriMesh, header_comment: &str) -> Vec<u8> {
    write_obj_with(mesh, None, header_comment)
}

/// [`write_obj`] with a `g NAME` line before each run of triangles of one region (checked by
/// [`super::write_mesh_with`]): groups are how OBJ names parts of a mesh, and every OBJ reader
/// (ours included) takes the faces whatever groups they are in. The triangles keep their order,
/// so the vertex and face numbering is the same as without regions.
pub(crate) fn write_obj_with(
    mesh: &TriMesh,
    regions: Option<&Regions>,
    header_comment: &str,
) -> Vec<u8> {
    let mut out = String::with_capacity(40 * mesh.positions.len() + 24 * mesh.triangles.len());
    for l in header_lines(header_comment) {
        out.push_str("# ");
        out.push_str(&l);
        out.push('\n');
    }
    out.push_str(&format!(
        "# {} vertices, {} triangles, mm\n",
        mesh.positions.len(),
        mesh.triangles.len()
    ));
    for p in &mesh.positions {
        out.push_str(&format!("v {}\n", fmt_point(p, " ")));
    }
    for (k, t) in mesh.triangles.iter().enumerate() {
        if let Some(name) = regions.and_then(|r| group_starts(r, k)) {
            out.push_str(&format!("g {name}\n"));
        }
        out.push_str(&format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1));
    }
    out.into_bytes()
}

/// The region name when triangle `t` starts a new run (the first triangle, or a region change).
fn group_starts<'a>(regions: &'a Regions, t: usize) -> Option<&'a str> {
    let changed = t == 0 || regions.ids.get(t) != regions.ids.get(t - 1);
    changed.then(|| regions.name_of(t))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_forms_and_fans() {
        let s = "# c\no thing\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n\
                 f 1/1/1 2/1/1 3/1/1\nf -4//1 -2//1 -1//1\ns off\nf 1 2 3 4\n";
        let m = read_obj(s.as_bytes()).unwrap().mesh;
        assert_eq!(m.positions.len(), 4);
        assert_eq!(
            m.triangles,
            vec![[0, 1, 2], [0, 2, 3], [0, 1, 2], [0, 2, 3]]
        );
    }

    #[test]
    fn errors_have_lines() {
        let e = read_obj(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n").unwrap_err();
        assert_eq!(e.line(), Some(4));
        assert!(e.to_string().contains("vertex 4"), "{e}");
        let e = read_obj(b"v 0 0 0\nv 1 x 0\n").unwrap_err();
        assert_eq!(e.line(), Some(2));
        let e = read_obj(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 0 2\n").unwrap_err();
        assert_eq!(e.line(), Some(4));
        assert!(read_obj(b"v 0 0 0\n").is_err());
    }

    #[test]
    fn reference_mesh_is_closed_and_outward() {
        let bytes = super::super::sample("meshes/bivme-patient1-ED-LV_ENDO-closed.obj");
        let m = read_obj(&bytes).unwrap().mesh;
        assert!(m.triangles.len() > 100);
        // An LV endocardium at end-diastole holds roughly 50-300 ml.
        let ml = m.volume_ml().abs();
        assert!((50.0..300.0).contains(&ml), "{ml} ml");
    }
}
