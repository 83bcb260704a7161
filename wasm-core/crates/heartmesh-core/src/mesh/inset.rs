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
}
