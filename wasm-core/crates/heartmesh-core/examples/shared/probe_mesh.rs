//! Probes of a mesh for the study examples (`corner`, `uneven_tips`): where along a ray a surface
//! lies (how high a lid sits over a point of the base) and on which side of it a point is.

use heartmesh_core::geometry::Vec3;
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::spatial::Bvh;

/// Signed distance of `p` to `mesh` (+ outside the mesh), by the closest triangle's normal.
pub fn signed(bvh: &Bvh, mesh: &TriMesh, p: &Vec3) -> f64 {
    let Some(h) = bvh.closest_point(mesh, *p) else {
        return f64::NAN;
    };
    let t = mesh.triangles[h.triangle as usize];
    let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
    let n = (b - a).cross(&(c - a));
    let d = h.distance_sq.sqrt();
    if (p - h.point).dot(&n) >= 0.0 {
        d
    } else {
        -d
    }
}

/// Distances along `u` (from `o`, ahead of it) at which the ray crosses `mesh`'s triangles: brute
/// force over every triangle (Moller-Trumbore), as the examples probe a handful of rays per mesh.
pub fn hits<'a>(mesh: &'a TriMesh, o: &'a Vec3, u: &'a Vec3) -> impl Iterator<Item = f64> + 'a {
    mesh.triangles.iter().filter_map(move |t| {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let (e1, e2) = (b - a, c - a);
        let p = u.cross(&e2);
        let det = e1.dot(&p);
        if det.abs() < 1e-12 {
            return None;
        }
        let s = o - a;
        let bu = s.dot(&p) / det;
        let q = s.cross(&e1);
        let bv = u.dot(&q) / det;
        let d = e2.dot(&q) / det;
        (bu >= 0.0 && bv >= 0.0 && bu + bv <= 1.0 && d > 0.0).then_some(d)
    })
}
