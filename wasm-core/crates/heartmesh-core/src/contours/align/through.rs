//! A short-axis slice's third unknown: its position along its own normal (docs/VALIDATION.md,
//! "Session 11: through-plane alignment").
//!
//! A breath-hold moves the heart mostly head to foot, which is partly along the short-axis stack's
//! normal, so a slice may have been imaged a little above or below where its header puts it. In-plane
//! shifts cannot represent that: a ring imaged 1 mm higher has the radius of the wall 1 mm higher,
//! and the long-axis views then settle 1 mm lower (session 10). Where a view's curve crosses the
//! slice's plane on a sloped wall, moving the plane along its normal moves the crossing across
//! the ring, so the crossings carry the offset: strongly near the apex and base, hardly at all
//! along straight walls.

use super::groups::Group;
use crate::contours::ContourKind;
use crate::geometry::Vec3;
use nalgebra::{Matrix3, Vector3};

/// No through-plane offset beyond this fraction of the stack's median slice spacing: a slice
/// moved half a spacing would sit halfway to its neighbour, far beyond a breath-hold's few mm
/// and beyond where its crossings could still be told from the neighbour's.
const THROUGH_CAP_OF_SPACING: f64 = 0.5;

/// A prior pulling each offset towards 0 with the weight of this many crossings (the same unit
/// as the damping): an offset seen by much more than one crossing's worth of information (near
/// the apex and base) is measured almost unbiased; one along straight walls, where the
/// crossings hardly see it, stays near 0 instead of drifting with contour noise. Without it
/// (session 11) 11 of 40 population meshes got worse, by up to 0.20 mm, and real slices moved
/// 3 mm on half a crossing of information; with it 9 of 40, by at most 0.019 mm.
pub(super) const PRIOR: f64 = 1.0;

/// How the crossing of a segment with direction `d` moves in the plane of normal `n` (unit) when
/// the plane moves by 1 along `n`, relative to the plane's own frame (the in-plane part of
/// d / (d . n)); zero for a segment lying in the plane (no crossing to move).
pub(super) fn crossing_rate(d: &Vec3, n: &Vec3) -> Vec3 {
    let along = d.dot(n);
    if along.abs() < 1e-12 {
        return Vec3::zeros();
    }
    (d - n * along) / along
}

/// The through-plane part of one slice's normal equations (unknowns: in-plane shift, offset s
/// along the normal). A crossing's residual along its curve's normal `m`, e, changes by
/// -m . dt for an in-plane shift dt and by +(m . g) s, g the [`crossing_rate`].
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Through {
    /// Sum of w m (-(m . g)): the coupling of the in-plane shift and the offset.
    pub cross: Vec3,
    /// Sum of w (m . g)^2: the offset's information (in weighted crossings; each at most the
    /// squared cosine of the curve's angle to the plane).
    pub info: f64,
    /// Sum of w (-(m . g)) e.
    pub b: f64,
}

impl Through {
    /// Adds one crossing of weight `w`, curve normal `m`, residual `r` and crossing rate `g`.
    pub fn add(&mut self, w: f64, m: &Vec3, r: &Vec3, g: &Vec3) {
        let j = -m.dot(g);
        self.cross += m * (w * j);
        self.info += w * j * j;
        self.b += w * j * m.dot(r);
    }
}

/// Half of a slice's damped Gauss-Newton step in its in-plane shift and its offset together
/// (the offset's now `offset`, pulled towards 0 by [`PRIOR`]):
/// `h`, `b` the in-plane normal equations (3 x 3, world axes), `th` the through-plane part,
/// `damping` added in each of the three directions (as for the in-plane step: weakly seen
/// directions move slowly, the fixed point is unbiased).
pub(super) fn step(
    g: &Group,
    h: &Matrix3<f64>,
    b: &Vec3,
    th: &Through,
    damping: f64,
    offset: f64,
) -> Vec3 {
    let n = g.normal;
    let (u, v) = crate::contours::axis::frame_for(&n);
    let (hu, hv) = (h * u, h * v);
    let a = Matrix3::new(
        u.dot(&hu) + damping,
        u.dot(&hv),
        u.dot(&th.cross),
        v.dot(&hu),
        v.dot(&hv) + damping,
        v.dot(&th.cross),
        u.dot(&th.cross),
        v.dot(&th.cross),
        th.info + damping + PRIOR,
    );
    let rhs = Vector3::new(u.dot(b), v.dot(b), th.b - PRIOR * offset);
    match a.try_inverse() {
        Some(inv) => {
            let d = inv * rhs;
            (u * d.x + v * d.y + n * d.z) * 0.5
        }
        None => Vec3::zeros(),
    }
}

/// The cap on a slice's offset (mm): [`THROUGH_CAP_OF_SPACING`] of the median spacing between
/// neighbouring slices along the axis; 0 (no offset) with fewer than two slices.
pub(super) fn cap(groups: &[Group]) -> f64 {
    let sax: Vec<&Group> = groups
        .iter()
        .filter(|g| g.kind == ContourKind::Sax)
        .collect();
    let Some(first) = sax.first() else {
        return 0.0;
    };
    let axis = first.normal;
    let mut heights: Vec<f64> = sax.iter().map(|g| g.centroid.dot(&axis)).collect();
    heights.sort_by(f64::total_cmp);
    let mut gaps: Vec<f64> = heights.windows(2).map(|w| w[1] - w[0]).collect();
    gaps.retain(|d| d.is_finite() && *d > 0.0);
    if gaps.is_empty() {
        return 0.0;
    }
    gaps.sort_by(f64::total_cmp);
    THROUGH_CAP_OF_SPACING * gaps[gaps.len() / 2]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    #[test]
    fn a_crossing_moves_along_its_curve_as_the_plane_rises() {
        // A wall sloping 45 degrees outward: the plane 1 mm higher crosses it 1 mm farther out.
        let g = crossing_rate(&v3(1.0, 0.0, 1.0), &v3(0.0, 0.0, 1.0));
        assert!((g - v3(1.0, 0.0, 0.0)).norm() < 1e-12);
        // A wall along the normal: the crossing does not move.
        assert_eq!(
            crossing_rate(&v3(0.0, 0.0, 2.0), &v3(0.0, 0.0, 1.0)),
            Vec3::zeros()
        );
        // A curve in the plane: no crossing.
        assert_eq!(
            crossing_rate(&v3(1.0, 0.0, 0.0), &v3(0.0, 0.0, 1.0)),
            Vec3::zeros()
        );
    }
}
