//! Laplacian smoothing with a LOCAL shrink correction by "twicing": every vertex is pushed back
//! by the low-passed part of its own smoothing displacement, instead of the whole mesh by one
//! affine map.
//!
//! Reference: J. W. Tukey, "Exploratory Data Analysis", 1977 ("twicing": smooth, then smooth the
//! residual and add it back). With S the remesh's n umbrella sweeps of factor f and o the
//! positions before smoothing, the displacement o - S o is what the smoothing removed; its own
//! low-passed part S (o - S o) is the shrink of the shape (the noise it removed is high-passed
//! and stays removed), so the result is S o + S (o - S o) = 2 S o - S (S o).
//!
//! Why: the remesh's global affine correction re-inflates the whole mesh by the AVERAGE shrink,
//! which Laplacian smoothing concentrates at sharp parts (an apex tip, a flat lid's rim), so
//! smooth parts overshoot, e.g. an unconstrained cap runs on past the data, and sharp parts stay
//! shrunk (docs/VALIDATION.md, "Session 9: overrun past the data", recommendation 2). Here each
//! vertex gets back the shrink of its own neighbourhood.
//!
//! Filter: at umbrella frequency k (eigenvalue of I - W, in [0, 2]) S has gain s = (1 - f k)^n
//! and the result 2 s - s^2 = 1 - (1 - s)^2. Where the shape lives (s near 1) the loss 1 - s
//! becomes its square: 200 sweeps of 0.1 keep 82% at k = 0.01, twicing 97%; where s is near 0 the
//! result is near 0 as well (2 s), so the noise is removed as by the plain sweeps and the strong
//! low-pass between the contours stays (docs/VALIDATION.md, "Session 3": the smoothing is a useful
//! prior). Stable for factors up to [`TWICING_MAX_FACTOR`]: then 1 - f k >= 0 at every k, so
//! 0 <= s <= 1 and 0 <= 2 s - s^2 <= 1 (above it s can be -1 at k = 2, a gain of -3). Both passes
//! are the umbrella sweeps of
//! `sweep::umbrella_steps` (the Chebyshev series): twice the smoothing's cost, the same bits
//! natively and in wasm.
//!
//! Measured (docs/VALIDATION.md, "Session 11: a local shrink correction"): the overrun past open
//! ends halves (phantoms' median 11.7 -> 6.0 mm), aligned acquisitions gain a little (paired
//! Hausdorff -0.04 mm), misaligned ones are unchanged; the paper's method stays the default.

use super::{check_factor_at_most, check_finite, sweep::umbrella_steps, Umbrella};
use crate::error::Result;
use crate::mesh::TriMesh;

/// Largest step factor for which twicing never amplifies (module docs).
pub const TWICING_MAX_FACTOR: f64 = 0.5;

/// `iterations` umbrella sweeps of step `factor` (0..=[`TWICING_MAX_FACTOR`]) with the twicing
/// correction.
pub fn twicing(mesh: &TriMesh, iterations: usize, factor: f64) -> Result<TriMesh> {
    twicing_given(mesh, None, iterations, factor)
}

pub(super) fn twicing_given(
    mesh: &TriMesh,
    given: Option<Umbrella>,
    iterations: usize,
    factor: f64,
) -> Result<TriMesh> {
    check_factor_at_most(factor, TWICING_MAX_FACTOR)?;
    let once = umbrella_steps(mesh, given.clone(), iterations, &[factor])?;
    let twice = umbrella_steps(&once, given, iterations, &[factor])?;
    let mut out = once;
    for (p, q) in out.positions.iter_mut().zip(&twice.positions) {
        *p = *p * 2.0 - q;
    }
    check_finite(out)
}
