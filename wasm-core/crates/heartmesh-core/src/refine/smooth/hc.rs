//! HC smoothing: Laplacian sweeps with a LOCAL shrink correction, each vertex pushed back after
//! every sweep by a smoothed share of its own displacement.
//!
//! Reference: J. Vollmer, R. Mencl, H. Mueller, "Improved Laplacian smoothing of noisy surface
//! meshes", Eurographics 1999 (the "HC" algorithm). One HC sweep, from positions q (o the
//! positions before smoothing):
//!   p = q + f (W q - q)                         (an umbrella sweep, W the row-stochastic mean)
//!   b = p - (alpha o + (1 - alpha) q)           (how far the sweep moved each vertex)
//!   q' = p - (beta b + (1 - beta) W b)          (push back by b, blended with its neighbours')
//!
//! Why: the remesh's global affine correction re-inflates the whole mesh by the AVERAGE shrink,
//! which Laplacian smoothing concentrates at sharp parts (an apex tip, a flat lid's rim); smooth
//! parts then overshoot and sharp parts stay shrunk (docs/VALIDATION.md, "Session 9: overrun past
//! the data", recommendation 2). The HC push-back undoes each vertex's own low-frequency motion.
//!
//! With alpha = 0 one sweep is linear in q alone: b = -f L q (L = I - W), and
//! q' = q - f (1 - beta) L^2 q, a bi-Laplacian step. Its gain at umbrella frequency k (an
//! eigenvalue of L, in [0, 2]) is 1 - f (1 - beta) k^2, against 1 - f k for the plain sweep:
//! the shape's low frequencies (k << 1) shrink by k^2 instead of k, the noise (k ~ 1-2) is still
//! removed. The step factors as (I - g L)(I + g L) with g = sqrt(f (1 - beta)), i.e. two umbrella
//! sweeps with factors g and -g, so n HC sweeps run through the same code as the other methods
//! (the Chebyshev series of `sweep::umbrella_steps`, the same bits natively and in wasm). Stable
//! for every factor the parameters allow: the gain stays in [1 - 4 f (1 - beta), 1] and
//! 4 f (1 - beta) <= 2 for f <= 1.
//!
//! alpha = 0: alpha > 0 pulls every sweep towards the unsmoothed positions, so the iteration
//! converges to a fixed point near the input and the sweep count no longer sets how much is
//! smoothed; the remesh needs the smoothing itself (Session 3: "smoothing the shape is what helps").
//! beta = 0.5 ([`HC_BETA`]): an even split between a vertex's own push-back and its neighbours'
//! mean, the common default (e.g. trimesh's `filter_humphrey`); HC needs beta > alpha. No other
//! value was tried (docs/VALIDATION.md, "Session 11: a local shrink correction").
//!
//! Measured there: the overrun past open ends falls from 11.7 to 3.2 mm (phantoms' median), but
//! at 200 x 0.1 HC keeps the middle frequencies the Laplacian removes, so it smooths much less
//! between the contours (misaligned Hausdorff +0.37 mm, folds x2.7): an option, not the default.

use super::{check_factor, check_finite, sweep::umbrella_steps, Umbrella};
use crate::error::{CoreError, Result};
use crate::mesh::TriMesh;

/// HC's beta: the share of a vertex's own displacement in its push-back (the rest is the mean of
/// its neighbours'). See the module docs.
pub const HC_BETA: f64 = 0.5;

/// The two umbrella factors (g, -g) whose sweeps compose to one HC sweep at alpha = 0.
pub fn hc_factors(factor: f64) -> [f64; 2] {
    let g = (factor * (1.0 - HC_BETA)).sqrt();
    [g, -g]
}

/// `iterations` HC sweeps (alpha 0, beta [`HC_BETA`]) with step `factor` (0..=1); no global
/// correction.
pub fn hc(mesh: &TriMesh, iterations: usize, factor: f64) -> Result<TriMesh> {
    hc_given(mesh, None, iterations, factor)
}

pub(super) fn hc_given(
    mesh: &TriMesh,
    given: Option<Umbrella>,
    iterations: usize,
    factor: f64,
) -> Result<TriMesh> {
    check_factor(factor)?;
    let steps = iterations
        .checked_mul(2)
        .ok_or_else(|| CoreError::ParamOutOfRange {
            name: "smoothing_iterations".into(),
            value: iterations as f64,
            min: 0.0,
            max: (usize::MAX / 2) as f64,
        })?;
    if factor == 0.0 {
        return umbrella_steps(mesh, given, 0, &[0.0]);
    }
    check_finite(umbrella_steps(mesh, given, steps, &hc_factors(factor))?)
}
