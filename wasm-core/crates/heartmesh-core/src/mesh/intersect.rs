//! Self-intersections: pairs of triangles of one mesh that pass through each other.
//!
//! A mesh can be closed, manifold, outward and free of folds and still pass through itself: two
//! sheets pulled across each other by contours that disagree, or a crease squeezed through its
//! neighbour. Volume meshers (TetGen, gmsh) refuse such a surface and 3D-printing slicers misread
//! it, and neither topology nor dihedral angles see it, so the report counts the pairs.
//!
//! Broad phase: triangle boxes swept along the axis of the mesh's largest extent (a few thousand
//! triangles: no tree needed). Narrow phase: two triangles that share no vertex cross when an edge
//! of one passes through the other; two that share one vertex cross only along a segment from it,
//! which ends on the edge opposite it in one of them (unless they are coplanar); two that share an
//! edge are neighbours (a fold there is [`super::quality`]'s). Touching counts as no crossing
//! (strict signs), and coplanar overlaps are not counted: both need exact coincidences that
//! reconstructed meshes do not have.

use super::TriMesh;
use crate::geometry::Vec3;

/// Signed volume (times 6) of the tetrahedron (a, b, c, d): positive when d lies on the side of
/// the plane (a, b, c) that its counter-clockwise normal points to.
fn orient(a: &Vec3, b: &Vec3, c: &Vec3, d: &Vec3) -> f64 {
    (b - a).cross(&(c - a)).dot(&(d - a))
}

/// Distances from a triangle's plane (mm, relative to the coordinates' size) below which a point
/// counts as in the plane. Flat parts of a mesh (a wall's base ring) are coplanar only up to
/// rounding: without this, rounding noise in the orientations of two neighbouring flat
/// triangles read as a crossing.
const IN_PLANE_REL: f64 = 1e-9;

/// Whether the open segment p-q passes through the interior of triangle (a, b, c).
fn segment_crosses(p: &Vec3, q: &Vec3, [a, b, c]: &[Vec3; 3]) -> bool {
    let (dp, dq) = (orient(a, b, c, p), orient(a, b, c, q));
    if dp == 0.0 || dq == 0.0 || (dp > 0.0) == (dq > 0.0) {
        return false;
    }
    let area2 = (b - a).cross(&(c - a)).norm();
    let size = [p, q, a, b, c].iter().map(|x| x.amax()).fold(1.0, f64::max);
    let tol = IN_PLANE_REL * size * area2;
    if dp.abs() <= tol || dq.abs() <= tol {
        return false;
    }
    let s = [orient(p, q, a, b), orient(p, q, b, c), orient(p, q, c, a)];
    s.iter().all(|&x| x > 0.0) || s.iter().all(|&x| x < 0.0)
}

/// Whether any edge of `t` passes through `u`.
fn edges_cross(t: &[Vec3; 3], u: &[Vec3; 3]) -> bool {
    (0..3).any(|k| segment_crosses(&t[k], &t[(k + 1) % 3], u))
}

/// Whether triangles `i` and `j` of `mesh` (vertex indices `ti`, `tj`) pass through each other.
fn triangles_cross(mesh: &TriMesh, ti: &[u32; 3], tj: &[u32; 3], i: usize, j: usize) -> bool {
    let shared: Vec<u32> = ti.iter().filter(|v| tj.contains(v)).copied().collect();
    let (ci, cj) = (mesh.corners(i), mesh.corners(j));
    match shared.as_slice() {
        [] => edges_cross(&ci, &cj) || edges_cross(&cj, &ci),
        [v] => {
            // The edge of each triangle opposite the shared vertex.
            let opposite = |t: &[u32; 3], c: &[Vec3; 3]| {
                let k = t.iter().position(|w| w == v).unwrap_or(0);
                (c[(k + 1) % 3], c[(k + 2) % 3])
            };
            let (p, q) = opposite(ti, &ci);
            let (r, s) = opposite(tj, &cj);
            segment_crosses(&p, &q, &cj) || segment_crosses(&r, &s, &ci)
        }
        _ => false,
    }
}

/// Number of pairs of triangles of `mesh` that pass through each other (0 for a surface that does
/// not intersect itself). Triangles with an out-of-range index or a non-finite corner are skipped.
pub fn self_intersections(mesh: &TriMesh) -> usize {
    crossing_pairs(mesh).len()
}

/// The pairs of triangles (indices, the smaller first) that pass through each other: which parts
/// of a labelled solid cross which ([`self_intersections`] counts them).
pub fn crossing_pairs(mesh: &TriMesh) -> Vec<(usize, usize)> {
    let n_pos = mesh.positions.len();
    let mut boxes: Vec<(usize, Vec3, Vec3)> = Vec::with_capacity(mesh.triangles.len());
    for (t, tri) in mesh.triangles.iter().enumerate() {
        if tri.iter().any(|&v| v as usize >= n_pos) {
            continue;
        }
        let c = mesh.corners(t);
        if !c.iter().all(|p| p.iter().all(|x| x.is_finite())) {
            continue;
        }
        let lo = c[0].inf(&c[1]).inf(&c[2]);
        let hi = c[0].sup(&c[1]).sup(&c[2]);
        boxes.push((t, lo, hi));
    }
    let Some(first) = boxes.first() else {
        return Vec::new();
    };
    let (lo, hi) = boxes
        .iter()
        .fold((first.1, first.2), |(l, h), b| (l.inf(&b.1), h.sup(&b.2)));
    let extent = hi - lo;
    let axis = (0..3)
        .max_by(|&a, &b| extent[a].total_cmp(&extent[b]))
        .unwrap_or(0);
    boxes.sort_by(|a, b| a.1[axis].total_cmp(&b.1[axis]).then(a.0.cmp(&b.0)));
    let mut pairs = Vec::new();
    for (k, (i, lo_i, hi_i)) in boxes.iter().enumerate() {
        for (j, lo_j, hi_j) in &boxes[k + 1..] {
            if lo_j[axis] > hi_i[axis] {
                break;
            }
            let overlap = (0..3).all(|d| lo_j[d] <= hi_i[d] && lo_i[d] <= hi_j[d]);
            if overlap && triangles_cross(mesh, &mesh.triangles[*i], &mesh.triangles[*j], *i, *j) {
                pairs.push((*i.min(j), *i.max(j)));
            }
        }
    }
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes::octahedron;

    fn tri_mesh(tris: &[[Vec3; 3]]) -> TriMesh {
        let positions = tris.iter().flatten().copied().collect();
        let triangles = (0..tris.len() as u32)
            .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
            .collect();
        TriMesh::new(positions, triangles)
    }

    #[test]
    fn a_closed_convex_surface_does_not_intersect_itself() {
        assert_eq!(self_intersections(&octahedron(10.0, Vec3::zeros())), 0);
        assert_eq!(self_intersections(&TriMesh::default()), 0);
    }

    #[test]
    fn two_triangles_through_each_other_are_one_pair() {
        let a = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(0.0, 4.0, 0.0),
        ];
        // Pierces a's interior at (1, 1, 0), in x = 1.
        let b = [
            Vec3::new(1.0, 1.0, -1.0),
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(1.0, -3.0, 0.0),
        ];
        assert_eq!(self_intersections(&tri_mesh(&[a, b])), 1);
        // Moved 5 mm along z: apart.
        let b_far = b.map(|p| p + Vec3::new(0.0, 0.0, 5.0));
        assert_eq!(self_intersections(&tri_mesh(&[a, b_far])), 0);
        // Touching at a corner only: no crossing.
        let b_touch = [
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(6.0, 0.0, 1.0),
            Vec3::new(6.0, 1.0, -1.0),
        ];
        assert_eq!(self_intersections(&tri_mesh(&[a, b_touch])), 0);
    }

    #[test]
    fn triangles_sharing_a_vertex_cross_only_through_their_opposite_edges() {
        let v = Vec3::new(0.0, 0.0, 0.0);
        let a = [v, Vec3::new(4.0, 0.0, 0.0), Vec3::new(0.0, 4.0, 0.0)];
        // Shares v; its far edge passes through a at x = y = 1.5 (z from -1 to +1).
        let b = [v, Vec3::new(1.5, 1.5, -1.0), Vec3::new(1.5, 1.5, 1.0)];
        let mut m = tri_mesh(&[a, b]);
        m.positions[3] = m.positions[0];
        m.triangles[1][0] = 0;
        assert_eq!(self_intersections(&m), 1);
        // Lifted off a's plane: only the shared corner is common.
        m.positions[4].z = 0.5;
        assert_eq!(self_intersections(&m), 0);
    }

    #[test]
    fn two_overlapping_closed_surfaces_intersect_and_apart_do_not() {
        let two = |dx: f64| {
            let a = octahedron(10.0, Vec3::zeros());
            let b = octahedron(10.0, Vec3::new(dx, 1.0, 2.0));
            let off = a.positions.len() as u32;
            let mut m = a.clone();
            m.positions.extend(&b.positions);
            m.triangles
                .extend(b.triangles.iter().map(|t| t.map(|v| v + off)));
            m
        };
        assert_eq!(self_intersections(&two(30.0)), 0);
        // Each surface passes through the other along a closed loop over several faces of each
        // (8 of the 8 x 8 pairs).
        assert_eq!(self_intersections(&two(8.0)), 8);
    }
}
