//! Meshes handed over as flat typed arrays (three.js geometry buffers from the browser: xyz
//! positions and triangle indices), the in-memory twin of the file readers. Refuses what would
//! make later measures meaningless or unsafe: partial triangles, dangling indices, non-finite
//! coordinates, more elements than any file reader accepts.

use super::MAX_MESH_ELEMENTS;
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::TriMesh;

/// Builds a [`TriMesh`] from `positions` (x, y, z per vertex, mm) and `indices` (three per
/// triangle, counter-clockwise seen from outside).
pub fn mesh_from_buffers(positions: &[f32], indices: &[u32]) -> Result<TriMesh> {
    let bad = |m: String| Err(CoreError::InvalidMesh(m));
    if !positions.len().is_multiple_of(3) {
        return bad(format!(
            "{} position values are not whole xyz triples",
            positions.len()
        ));
    }
    if !indices.len().is_multiple_of(3) || indices.is_empty() {
        return bad(format!("{} indices are not whole triangles", indices.len()));
    }
    let n = positions.len() / 3;
    if n > MAX_MESH_ELEMENTS || indices.len() / 3 > MAX_MESH_ELEMENTS {
        return bad(format!(
            "more than {MAX_MESH_ELEMENTS} vertices or triangles"
        ));
    }
    if let Some(&i) = indices.iter().find(|&&i| i as usize >= n) {
        return bad(format!("index {i} is past the last of {n} vertices"));
    }
    if let Some(k) = positions.iter().position(|v| !v.is_finite()) {
        return bad(format!("vertex {} has a non-finite coordinate", k / 3));
    }
    let points = positions
        .chunks_exact(3)
        .map(|c| Vec3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2])))
        .collect();
    let triangles = indices
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    Ok(TriMesh::new(points, triangles))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn buffers_round_trip_and_refusals() {
        let m = crate::mesh::shapes::octahedron(12.5, Vec3::new(1.0, -2.0, 3.0));
        let back = mesh_from_buffers(&m.positions_f32(), &m.indices_u32()).unwrap();
        assert_eq!(back.triangles, m.triangles);
        assert!((back.volume_ml() - m.volume_ml()).abs() < 1e-6);
        let msg = |p: &[f32], i: &[u32]| mesh_from_buffers(p, i).unwrap_err().to_string();
        assert_eq!(
            msg(&[0.0; 8], &[0, 1, 2]),
            "invalid mesh: 8 position values are not whole xyz triples"
        );
        assert_eq!(
            msg(&[0.0; 9], &[]),
            "invalid mesh: 0 indices are not whole triangles"
        );
        assert_eq!(
            msg(&[0.0; 9], &[0, 1, 3]),
            "invalid mesh: index 3 is past the last of 3 vertices"
        );
        assert_eq!(
            msg(
                &[0.0, 0.0, 0.0, 1.0, f32::NAN, 0.0, 0.0, 1.0, 0.0],
                &[0, 1, 2]
            ),
            "invalid mesh: vertex 1 has a non-finite coordinate"
        );
    }
}
