//! Keeping an inner surface inside an outer one, at least a given distance in.
//!
//! The endo- and epicardium are reconstructed apart, each approximating its own contours; where
//! the wall is thinner than their errors (a thinned apex, a breath-hold offset between the
//! images the two were drawn on) the endocardium can come out through the epicardium. A wall
//! solid is then no solid: volume meshers refuse it and slicers misprint it. Moving the
//! offending endocardial vertices to a minimum depth under the epicardium makes it one again,
//! and the caller reports how many moved and how far, so the repair is never silent.

use super::TriMesh;
use crate::geometry::Vec3;
use crate::metrics::function::winding_number;
use crate::sim::slice::Plane;
use crate::spatial::Bvh;

/// What [`push_inside`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Pushed {
    /// Vertices moved.
    pub vertices: usize,
    /// The longest move (mm).
    pub max_mm: f64,
}

/// Shortfalls up to this are rounding, not a wall too thin: a vertex an earlier push left at
/// the depth measures its depth again to within ~1e-15 mm, and moving it by that would keep
/// [`push`]'s callers going round after the surfaces are already apart.
const MOVE_TOLERANCE_MM: f64 = 1e-9;

/// Which side of the other surface the moved vertices must end up on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Keep {
    /// Inside it (the endocardium under the epicardium).
    Inside,
    /// Outside it (the epicardium over the endocardium).
    Outside,
}

/// Moves every vertex of `mesh` on the wrong side of `other` (per `keep`), or on the right side
/// but nearer than `depth_mm`, along the normal of the nearest face of `other` until it is
/// `depth_mm` from that face's plane on the right side. `other` faces outwards; `closed` is
/// `other` closed (e.g. by a cap across a cut), for the side test (its winding number): the cap
/// is no surface to keep away from. Vertices flagged in `plane`'s mask stay in that plane (their
/// move is projected onto it): they are the outline a base ring is built on.
pub fn push(
    mesh: &mut TriMesh,
    other: &TriMesh,
    closed: &TriMesh,
    depth_mm: f64,
    keep: Keep,
    plane: Option<(&Plane, &[bool])>,
) -> Pushed {
    let mut pushed = Pushed::default();
    if !(depth_mm.is_finite() && depth_mm >= 0.0) || other.triangles.is_empty() {
        return pushed;
    }
    // +1: inward is the way to go; -1: outward.
    let sign = match keep {
        Keep::Inside => 1.0,
        Keep::Outside => -1.0,
    };
    let bvh = Bvh::build(other);
    for (i, p) in mesh.positions.iter_mut().enumerate() {
        let Some(hit) = bvh.closest_point(other, *p) else {
            continue;
        };
        let d = hit.distance_sq.sqrt();
        let Some(n) = outward_normal(other, hit.triangle as usize) else {
            continue;
        };
        // How far the point stands out on the wrong side of the nearest face's plane.
        let wrong = sign * (*p - hit.point).dot(&n);
        // Clearly on the right side of the nearest face needs no winding number (which visits
        // every triangle of `other`, so only where the cheap test cannot tell).
        let clearly_right = wrong < -0.5 * d;
        let on_wrong_side = !clearly_right && {
            let inside = winding_number(closed, p) >= 0.5;
            inside != (keep == Keep::Inside)
        };
        if !(d < depth_mm || on_wrong_side) {
            continue;
        }
        // Along the face's normal by as much as the point is short of the depth, keeping its
        // offset across the normal: points beyond the same feature of `other` (an edge, the rim
        // of a cut) land apart instead of on one point.
        let short = wrong + depth_mm;
        if short <= MOVE_TOLERANCE_MM {
            continue;
        }
        let mut target = *p - n * (sign * short);
        if let Some((pl, flags)) = plane {
            if flags.get(i).copied().unwrap_or(false) {
                target -= pl.normal * pl.signed_distance(&target);
            }
        }
        let moved = (target - *p).norm();
        if moved > 0.0 {
            *p = target;
            pushed.vertices += 1;
            pushed.max_mm = pushed.max_mm.max(moved);
        }
    }
    pushed
}

/// Moves the vertices of `inner`'s triangles that still pass through `outer` towards `depth_mm`
/// under the face they pass through, and returns what moved. [`push`] measures each vertex
/// against its nearest face of `outer`, so where `outer` folds inwards between an inner
/// triangle's corners (a crease sharper than the triangle is small) every corner can stand at
/// the depth under its own nearest face while the triangle's middle comes out through another:
/// only the crossing itself says which face that is. A corner above `depth_mm` under that
/// face's plane moves along the face's normal towards that depth by at most `step_mm` (the
/// deepest move where several faces ask): the plane runs on past the face, and a corner far
/// along it would go deep for a crossing a small move clears, so callers step and look again.
/// `fixed` vertices (an outline in a base plane) stay. `outer` faces outwards.
pub fn clear_crossings(
    inner: &mut TriMesh,
    outer: &TriMesh,
    fixed: &[bool],
    depth_mm: f64,
    step_mm: f64,
) -> Pushed {
    let mut pushed = Pushed::default();
    if !(depth_mm.is_finite() && depth_mm >= 0.0) || outer.triangles.is_empty() {
        return pushed;
    }
    let mut target: Vec<Option<Vec3>> = vec![None; inner.positions.len()];
    for (a, b) in crossings_between(outer, inner) {
        let Some(n) = outward_normal(outer, a) else {
            continue;
        };
        let on_face = outer.corners(a)[0];
        for &v in &inner.triangles[b] {
            let v = v as usize;
            if fixed.get(v).copied().unwrap_or(false) {
                continue;
            }
            let at = inner.positions[v];
            let above = ((at - on_face).dot(&n) + depth_mm).min(step_mm);
            if above > MOVE_TOLERANCE_MM {
                let to = at - n * above;
                // Where several crossed faces ask, the longest move.
                if target[v].is_none_or(|t| (t - at).norm() < above) {
                    target[v] = Some(to);
                }
            }
        }
    }
    for (p, t) in inner.positions.iter_mut().zip(target) {
        let Some(t) = t else { continue };
        pushed.vertices += 1;
        pushed.max_mm = pushed.max_mm.max((t - *p).norm());
        *p = t;
    }
    pushed
}

/// The pairs (triangle of `a`, triangle of `b`) that pass through each other: the two surfaces
/// as one mesh, `a` listed first, and its crossing pairs that join them.
fn crossings_between(a: &TriMesh, b: &TriMesh) -> Vec<(usize, usize)> {
    let n_a = a.triangles.len();
    let offset = a.positions.len() as u32;
    let mut positions = a.positions.clone();
    positions.extend_from_slice(&b.positions);
    let mut triangles = a.triangles.clone();
    triangles.extend(b.triangles.iter().map(|t| t.map(|v| v + offset)));
    super::intersect::crossing_pairs(&TriMesh::new(positions, triangles))
        .into_iter()
        .filter(|&(s, t)| s < n_a && t >= n_a)
        .map(|(s, t)| (s, t - n_a))
        .collect()
}

/// Unit outward normal of triangle `t` (None when degenerate).
fn outward_normal(mesh: &TriMesh, t: usize) -> Option<Vec3> {
    let [a, b, c] = mesh.corners(t);
    let n = (b - a).cross(&(c - a));
    let len = n.norm();
    (len > 0.0 && len.is_finite()).then(|| n / len)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes::octahedron;

    /// Points around the middle of a flat face, 1 mm outside to 0.5 mm inside, come back `depth`
    /// inside; pushing again moves nothing (a vertex left at the depth measures it again only to
    /// rounding, ~1e-15 mm), which is what lets the wall's separation rounds stop.
    #[test]
    fn a_second_push_moves_nothing() {
        let outer = octahedron(30.0, Vec3::zeros());
        // The face through (30,0,0), (0,30,0), (0,0,30): centre (10,10,10), normal (1,1,1)/sqrt 3.
        let n = Vec3::new(1.0, 1.0, 1.0).normalize();
        let (u, v) = (
            Vec3::new(1.0, -1.0, 0.0).normalize(),
            Vec3::new(1.0, 1.0, -2.0).normalize(),
        );
        let mut positions = Vec::new();
        for i in 0..15 {
            for j in 0..15 {
                let off = 1.0 - 1.5 * ((i * 15 + j) % 7) as f64 / 6.0;
                let q = Vec3::new(10.0, 10.0, 10.0)
                    + u * (0.37 * i as f64 - 2.6)
                    + v * (0.41 * j as f64 - 2.9)
                    + n * off;
                positions.push(q);
            }
        }
        let mut inner = TriMesh::new(positions, Vec::new());
        let depth = 1.0;
        let first = push(&mut inner, &outer, &outer, depth, Keep::Inside, None);
        assert_eq!(first.vertices, inner.positions.len());
        assert!((first.max_mm - 2.0).abs() < 1e-9, "{}", first.max_mm);
        let again = push(&mut inner, &outer, &outer, depth, Keep::Inside, None);
        assert_eq!(again, Pushed::default());
    }

    /// An outer surface folded inwards along a crease (a V valley, z = |x| / 2, facing +z) and
    /// a flat inner quad 2 mm under its flanks at x = +-8 (1.79 mm under their planes): every
    /// corner is at the depth under its nearest face, so [`push`] moves nothing, yet the quad's
    /// middle stands 2 mm out through the crease. Stepping clears it, moving the corners by
    /// little more than that.
    #[test]
    fn a_triangle_through_an_inward_crease_is_moved_under_it() {
        let outer = TriMesh::new(
            vec![
                Vec3::new(-10.0, -10.0, 5.0),
                Vec3::new(-10.0, 10.0, 5.0),
                Vec3::new(0.0, -10.0, 0.0),
                Vec3::new(0.0, 10.0, 0.0),
                Vec3::new(10.0, -10.0, 5.0),
                Vec3::new(10.0, 10.0, 5.0),
            ],
            vec![[0, 2, 3], [0, 3, 1], [2, 4, 5], [2, 5, 3]],
        );
        let quad = |z: f64| {
            TriMesh::new(
                vec![
                    Vec3::new(-8.0, -3.0, z),
                    Vec3::new(8.0, -3.0, z),
                    Vec3::new(8.0, 3.0, z),
                    Vec3::new(-8.0, 3.0, z),
                ],
                vec![[0, 2, 1], [0, 3, 2]],
            )
        };
        let mut inner = quad(2.0);
        let depth = 1.0;
        assert_eq!(
            push(&mut inner, &outer, &outer, depth, Keep::Inside, None),
            Pushed::default()
        );
        let crossings = |inner: &TriMesh| crossings_between(&outer, inner).len();
        assert!(crossings(&inner) > 0);
        let mut passes = 0;
        while clear_crossings(&mut inner, &outer, &[], depth, 0.5).vertices > 0 {
            passes += 1;
            assert!(passes < 20, "never cleared");
        }
        assert_eq!(crossings(&inner), 0);
        // The corners went down and in, 0.5 mm along a flank's normal (0.45, 0, 0.89) per pass,
        // until the quad passed under the crease: 5 passes, 2.5 mm.
        let moved: Vec<f64> = inner
            .positions
            .iter()
            .zip(&quad(2.0).positions)
            .map(|(p, q)| (p - q).norm())
            .collect();
        assert_eq!(passes, 5, "{moved:?}");
        assert!(moved.iter().all(|&m| (m - 2.5).abs() < 1e-9), "{moved:?}");
        // A fixed corner stays.
        let mut inner = quad(2.0);
        clear_crossings(&mut inner, &outer, &[true, false, false, false], depth, 0.5);
        assert_eq!(inner.positions[0], quad(2.0).positions[0]);
    }
}
