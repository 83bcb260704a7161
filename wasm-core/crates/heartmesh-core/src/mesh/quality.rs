//! Geometric quality of a triangle mesh: folds (adjacent triangles turned against each other),
//! self-intersections and triangle shape. A mesh can be closed, manifold and outward yet folded: a crease where two
//! neighbouring triangles meet at a sharp angle shows as a dark shard in the viewer and is not
//! part of any smooth heart surface, so the pipeline's tests hold real reconstructions to none.
//!
//! Triangle shape uses the normalised quality q = 4 sqrt(3) A / (l1^2 + l2^2 + l3^2) (Bank &
//! Smith, 1997): 1 for an equilateral triangle, 0 for a degenerate one.

use super::topology::EdgeMap;
use super::TriMesh;
use crate::geometry::Vec3;

/// Two neighbouring triangles whose normals differ by more than this are folded against each other.
pub const FOLD_DEG: f64 = 90.0;

/// Summary of a mesh's folds and triangle shapes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshQuality {
    /// Interior edges whose two triangles' normals differ by more than 90 degrees.
    pub folded_edges: usize,
    /// Pairs of triangles that pass through each other ([`super::intersect`]): 0 for a surface a
    /// volume mesher or a 3D-printing slicer can take.
    pub self_intersections: usize,
    /// Largest angle between the normals of two triangles sharing an edge (degrees).
    pub max_dihedral_deg: f64,
    /// Smallest and median triangle quality q (see the module doc).
    pub min_triangle_quality: f64,
    pub median_triangle_quality: f64,
    /// Longest edge (mm): slivers show up as edges far longer than the mean.
    pub max_edge_mm: f64,
    pub mean_edge_mm: f64,
}

fn unit_normal(c: [Vec3; 3]) -> Option<Vec3> {
    let n = (c[1] - c[0]).cross(&(c[2] - c[0]));
    let len = n.norm();
    (len > 0.0 && len.is_finite()).then(|| n / len)
}

/// Unit normal of every triangle (None for a degenerate one or an out-of-range index).
pub fn face_normals(mesh: &TriMesh) -> Vec<Option<Vec3>> {
    let n_pos = mesh.positions.len();
    mesh.triangles
        .iter()
        .enumerate()
        .map(|(i, t)| {
            if t.iter().all(|&v| (v as usize) < n_pos) {
                unit_normal(mesh.corners(i))
            } else {
                None
            }
        })
        .collect()
}

/// Angle (degrees) between the normals of the two triangles on edge `e`; None on a boundary or
/// non-manifold edge, or next to a degenerate triangle.
pub fn dihedral_deg(map: &EdgeMap, normals: &[Option<Vec3>], e: usize) -> Option<f64> {
    match map.half_edges_of(e) {
        &[h, g] => {
            let (n1, n2) = (normals[h as usize / 3]?, normals[g as usize / 3]?);
            Some(n1.dot(&n2).clamp(-1.0, 1.0).acos().to_degrees())
        }
        _ => None,
    }
}

/// Folded edges (as in [`MeshQuality::folded_edges`]) between triangles of one region, `labels`
/// holding one per triangle: where regions meet (a wall's rim, where the base turns into the
/// walls at about a right angle) the crease is by design, not a fold.
pub fn folded_edges_within<L: PartialEq>(mesh: &TriMesh, labels: &[L]) -> usize {
    let map = EdgeMap::new(mesh);
    let normals = face_normals(mesh);
    (0..map.edges.len())
        .filter(|&e| {
            let same_region = match map.half_edges_of(e) {
                &[h, g] => labels.get(h as usize / 3) == labels.get(g as usize / 3),
                _ => false,
            };
            same_region && dihedral_deg(&map, &normals, e).is_some_and(|a| a > FOLD_DEG)
        })
        .count()
}

/// Measures `mesh`; an empty mesh gives zeros.
pub fn quality(mesh: &TriMesh) -> MeshQuality {
    let n_pos = mesh.positions.len();
    let valid = |t: &[u32; 3]| t.iter().all(|&i| (i as usize) < n_pos);
    let normals: Vec<Option<Vec3>> = mesh
        .triangles
        .iter()
        .enumerate()
        .map(|(i, t)| {
            if valid(t) {
                unit_normal(mesh.corners(i))
            } else {
                None
            }
        })
        .collect();
    let map = EdgeMap::new(mesh);
    let mut folded = 0;
    let mut max_angle: f64 = 0.0;
    let (mut edge_sum, mut edge_max, mut edge_count) = (0.0, 0.0f64, 0usize);
    for (e, &[a, b]) in map.edges.iter().enumerate() {
        if (a as usize) < n_pos && (b as usize) < n_pos {
            let l = (mesh.positions[a as usize] - mesh.positions[b as usize]).norm();
            edge_sum += l;
            edge_max = edge_max.max(l);
            edge_count += 1;
        }
        if let Some(angle) = dihedral_deg(&map, &normals, e) {
            max_angle = max_angle.max(angle);
            if angle > FOLD_DEG {
                folded += 1;
            }
        }
    }
    let mut q: Vec<f64> = mesh
        .triangles
        .iter()
        .enumerate()
        .filter(|(_, t)| valid(t))
        .map(|(i, _)| {
            let [p0, p1, p2] = mesh.corners(i);
            let area = 0.5 * (p1 - p0).cross(&(p2 - p0)).norm();
            let sq = (p1 - p0).norm_squared() + (p2 - p1).norm_squared() + (p0 - p2).norm_squared();
            if sq > 0.0 {
                4.0 * 3f64.sqrt() * area / sq
            } else {
                0.0
            }
        })
        .collect();
    q.sort_by(f64::total_cmp);
    MeshQuality {
        folded_edges: folded,
        self_intersections: super::intersect::self_intersections(mesh),
        max_dihedral_deg: max_angle,
        min_triangle_quality: q.first().copied().unwrap_or(0.0),
        median_triangle_quality: q.get(q.len() / 2).copied().unwrap_or(0.0),
        max_edge_mm: edge_max,
        mean_edge_mm: if edge_count > 0 {
            edge_sum / edge_count as f64
        } else {
            0.0
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes::octahedron;

    #[test]
    fn octahedron_is_unfolded_and_equilateral() {
        let q = quality(&octahedron(1.0, Vec3::zeros()));
        assert_eq!(q.folded_edges, 0);
        // Neighbouring faces of a regular octahedron: normals 70.53 degrees apart.
        assert!((q.max_dihedral_deg - 70.528_779).abs() < 1e-4, "{q:?}");
        assert!((q.min_triangle_quality - 1.0).abs() < 1e-12);
        assert!((q.max_edge_mm - q.mean_edge_mm).abs() < 1e-12);
    }

    #[test]
    fn a_vertex_pushed_through_its_neighbours_folds() {
        let mut m = octahedron(1.0, Vec3::zeros());
        // Push the top vertex far down through the equator: its four triangles turn over.
        let top = m
            .positions
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.z.total_cmp(&b.1.z))
            .map(|(i, _)| i)
            .unwrap_or(0);
        m.positions[top].z = -0.9 * m.positions[top].z.abs() - 0.5;
        let q = quality(&m);
        assert!(q.folded_edges >= 4, "{q:?}");
        assert!(q.max_dihedral_deg > 90.0);
    }

    #[test]
    fn empty_mesh_is_all_zero() {
        let q = quality(&TriMesh::default());
        assert_eq!(q.folded_edges, 0);
        assert_eq!(q.max_edge_mm, 0.0);
    }
}
