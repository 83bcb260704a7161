//! A prior on the shifts, weighed against what the crossings say, direction by direction
//! (docs/VALIDATION.md, "Session 10: long-axis views along the axis").
//!
//! The joint estimate is a least-squares fit: each group's shift t with normal matrix H (the
//! weighted crossings' normals) and per-crossing noise variance s^2 (a crossing of weight w has
//! variance s^2 / w) has covariance s^2 H^-1. A long-axis view slides along the axis past walls
//! that barely change with height, so H is small that way and noise (the slices' tilts and
//! through-plane motion) is fitted as shift. Breath-hold shifts are themselves a few mm: with the
//! prior t ~ N(0, p^2 I) the posterior mean is (H + k I)^-1 H t, k = s^2 / p^2 — each eigen-
//! direction of H shrinks by lambda / (lambda + k), so well-seen directions keep their shift and
//! weakly seen ones move toward zero. Both variances come from the fit itself (empirical Bayes:
//! s^2 from the residuals left, p^2 from the shifts found), so there is no constant to tune.

use crate::geometry::Vec3;

/// The fit's noise and the shifts' spread, in mm^2 per in-plane direction.
#[derive(Debug, Clone, Copy)]
pub(super) struct Variances {
    pub noise: f64,
    pub prior: f64,
}

impl Variances {
    /// `weighted_sq`: sum over the matched crossings of weight x (normal . residual)^2;
    /// `crossings`: their count; `shifts`: the moving groups' shifts (two unknowns each).
    pub fn estimate(weighted_sq: f64, crossings: usize, shifts: &[Vec3]) -> Option<Variances> {
        let unknowns = 2 * shifts.len();
        if shifts.is_empty() || crossings <= unknowns {
            return None;
        }
        let noise = weighted_sq / (crossings - unknowns) as f64;
        let prior = shifts.iter().map(|t| t.norm_squared()).sum::<f64>() / unknowns as f64;
        (noise.is_finite() && prior.is_finite() && prior > 0.0)
            .then_some(Variances { noise, prior })
    }

    /// k = s^2 / p^2, in (weighted) crossings.
    pub fn ratio(&self) -> f64 {
        self.noise / self.prior
    }
}

/// The posterior mean of one group's shift `t` (in the plane with unit normal `normal`), its
/// crossings' normal matrix `h` and the prior weight `k`: (H + k I)^-1 H t in the plane.
pub(super) fn shrink(t: &Vec3, h: &nalgebra::Matrix3<f64>, normal: &Vec3, k: f64) -> Vec3 {
    let (u, v) = crate::contours::axis::frame_for(normal);
    let (a, b, c) = (u.dot(&(h * u)), u.dot(&(h * v)), v.dot(&(h * v)));
    let hm = nalgebra::Matrix2::new(a, b, b, c);
    let damped = hm + nalgebra::Matrix2::identity() * k;
    let tt = nalgebra::Vector2::new(u.dot(t), v.dot(t));
    match damped.try_inverse() {
        Some(inv) => {
            let s = inv * (hm * tt);
            u * s.x + v * s.y
        }
        None => *t,
    }
}
