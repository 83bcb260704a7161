//! Approximating 3D thin-plate spline, fitted once per deformation step.
//!
//! Reference: F. L. Bookstein, "Principal warps: thin-plate splines and the decomposition of
//! deformations", IEEE TPAMI 11(6), 1989; approximating (smoothing) form as in G. Wahba, "Spline
//! Models for Observational Data", SIAM 1990; use in Villard, Grau & Zacur, J. Imaging 2018
//! (see METHOD.md section 4).
//!
//! F(x) = sum_i w_i G(|x - P_i|) + a0 + a1 x + a2 y + a3 z with G(r) = -r / (8 pi), solving
//! [[G + I / lambda_eff, A], [A^T, 0]] [w; a] = [Q'; 0] for the three coordinates at once.
//!
//! Why this solution path: the saddle-point system is symmetric but indefinite, so a general LU
//! would be needed; projected onto the null space of A^T it becomes symmetric positive definite
//! (G is conditionally positive definite of order 2 in 3D, and I / lambda_eff > 0), which a
//! Cholesky factorises in half the work and with residuals near machine precision. With the
//! Householder QR A = Q [R; 0], Q = [Q1 Q2]: w = Q2 g where (Q2^T K Q2) g = Q2^T b, and
//! R a = Q1^T (b - K w). Q^T K Q is formed in O(N^2) by applying the four reflectors from both
//! sides as one block reflector, on the lower triangle only; its off-diagonal block gives
//! Q1^T K w without keeping K. (An f32 factor with f64 iterative refinement was measured in
//! session 4: two refinement steps per fit cost what the f32 factor saved, +7% instructions natively
//! and -1.5% in wasm, so the projected system stays an f64 Cholesky.)
//!
//! Reuse across deformation steps: between two steps the centres (closest mesh points to the
//! attractors) move by a fraction of the remaining distance, so the projected system changes
//! little. A fit at the same N as the last one, with the same attractors, solves it by conjugate
//! gradients preconditioned with the last factor (`pcg.rs`), warm-started from the last two
//! solutions; it factorises afresh when the attractors were re-sampled
//! ([`TpsSolver::invalidate_factor`]), when a reuse did not converge in `CG_MAX_ITERATIONS`, or
//! after one needed more than `REFACTOR_AFTER`. Measured on whole default runs (session 5, with
//! `CG_RTOL` 1e-9 and the f32 preconditioner): the SurFCo example factorises 11 of 236 fits
//! (3.07 iterations per reused fit), biv-me patient 1 ED RV endocardium 37 of 250 (5.45, 10
//! reuses abandoned); vertices move by at most 1.4e-7 mm per step against factorising every step
//! (`pipeline::reuse`). The preconditioner applies the kept factor in single precision (`pcg.rs`:
//! half the bytes per pass, 147 M -> 88 M instructions on SurFCo, the same iteration counts
//! as the f64 one); the CG uses the Polak-Ribiere beta, which tolerates its rounding (RV: 9 -> 8
//! abandoned reuses), while residuals, products and solution stay f64.
//!
//! The affine part is fitted in a basis centred on the mean of the centres (1, x - c): the same
//! function F, but R no longer mixes the constant column with large coordinates, which keeps the
//! coplanarity test and the 4 x 4 solve well conditioned. Nothing else is rescaled: the pipeline
//! passes normalised units already.
//!
//! Evaluation is the hot loop of the whole reconstruction (vertices x centres per iteration). It is
//! mixed precision: the affine part in f64, the kernel sum (the non-affine correction) in f32 with
//! the centres relative to their mean, stored as structure-of-arrays chunks of eight with the
//! weights pre-multiplied by -1/(8 pi); `apply` states the error (micrometres). The lanes are
//! explicit vectors (`lanes/`: two SSE / simd128 / plain-array halves, or one AVX register
//! natively when the CPU has it) with the same arithmetic in the same order, so every target, and
//! the portable reference `evaluate_portable`, gives identical bits; `evaluate_f64` is the
//! all-double reference. The projection, the residuals and the f64 fallback use the f64
//! four-lane vectors; the f32 factor and its triangular solves the f32 eight-lane ones.

mod eval;
mod reuse;
mod system;
#[cfg(test)]
mod tests;

use super::dense::cholesky_in_place;
use super::pcg::{chol_solve3, f32_stride, mirror_lower};
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use eval::{Chunk, Chunk32};
use reuse::{targets_norms, CgBuffers, CG_MAX_ITERATIONS, CG_RTOL, REFACTOR_AFTER};

/// -1 / (8 pi): the 3D biharmonic Green's function is G(r) = KERNEL_SCALE * r.
const KERNEL_SCALE: f64 = -1.0 / (8.0 * std::f64::consts::PI);

/// Fits and applies approximating thin-plate splines, reusing its buffers across fits: after the
/// first fit at a given number of centres, neither `fit` nor `apply` allocates.
#[derive(Debug, Clone, Default)]
pub struct TpsSolver {
    n: usize,
    /// N x N row-major, lower triangle used: the kernel matrix, then Q^T K Q in place.
    kmat: Vec<f64>,
    /// Householder vectors, 4 x N (row k is zero before index k).
    hv: Vec<f64>,
    hbeta: [f64; 4],
    /// R of the QR of the centred affine basis (upper triangular).
    r: [[f64; 4]; 4],
    /// (N-4) x (N-4) row-major; the Cholesky factor L in its lower triangle.
    chol: Vec<f64>,
    /// Right-hand sides, 3 x N (x, y, z rows): b, then Q^T b, then the solution w.
    rhs: Vec<f64>,
    /// Scratch, 4 x N: X = K V, then Y, of the block reflector update.
    tmp: Vec<f64>,
    /// Evaluation data: f64 (the reference) and f32 (the hot loop).
    chunks: Vec<Chunk>,
    chunks32: Vec<Chunk32>,
    centre: Vec3,
    /// Affine part per output coordinate in the centred basis: (a0, ax, ay, az).
    affine_c: [[f64; 4]; 3],
    fitted: bool,
    /// `chol` holds the factor of an earlier projected system at this N (the preconditioner of
    /// the reused path).
    factor_ok: bool,
    /// Never reuse a factor: every fit projects and factorises (the reference path).
    always_refactor: bool,
    /// Conjugate-gradient work rows, 3 x N each (entries 0..4 unused or the affine block).
    cg: CgBuffers,
    /// Iterations of the last reused fit (0 after a factorisation).
    last_iterations: usize,
    stats: SolveStats,
    /// The factor in `chol` rounded to f32: L (lower triangle) and L^T (upper triangle), the
    /// preconditioner's two triangular solves; `pre_w` is its 3 x (N-4) scratch.
    chol32: Vec<f32>,
    chol_t32: Vec<f32>,
    chol_dinv32: Vec<f32>,
    pre_w: Vec<f32>,
    chol_t_ok: bool,
    /// `cg.w_prev` holds the weights of the fit before last, at the same centres' indices.
    w_prev_ok: bool,
}

/// How the fits of a solver were solved (counts since it was created).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SolveStats {
    /// Fits that projected and factorised the system.
    pub factorisations: usize,
    /// Fits solved by conjugate gradients with an earlier factor.
    pub reused: usize,
    /// Reuse attempts that did not converge (each followed by a factorisation).
    pub failed: usize,
    /// Conjugate-gradient iterations over all reused and failed fits.
    pub iterations: usize,
}

impl TpsSolver {
    pub fn new() -> Self {
        Self::default()
    }

    /// Every later fit projects and factorises its own system (true), or may solve it by
    /// conjugate gradients preconditioned with an earlier factor (false, the default).
    pub fn set_always_refactor(&mut self, always: bool) {
        self.always_refactor = always;
    }

    /// The next fit factorises: its centres are not a small move of the last fit's (new
    /// attractors).
    pub fn invalidate_factor(&mut self) {
        self.factor_ok = false;
    }

    /// How the fits so far were solved.
    pub fn stats(&self) -> SolveStats {
        self.stats
    }

    /// Number of centres of the current fit (0 before the first).
    pub fn len(&self) -> usize {
        if self.fitted {
            self.n
        } else {
            0
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Fits F with F(centres[i]) ~ targets[i]; `lambda_eff` weighs the data term against the
    /// bending energy (large: interpolating; small: close to the least-squares affine map).
    pub fn fit(&mut self, centres: &[Vec3], targets: &[Vec3], lambda_eff: f64) -> Result<()> {
        self.fit_weighted(centres, targets, lambda_eff, None)
    }

    /// [`TpsSolver::fit`] with a data weight per centre: the data term becomes
    /// lambda_eff * sum_i weights[i] |F(P_i) - Q'_i|^2, so the diagonal of the system is
    /// 1 / (lambda_eff weights[i]). Weights must be finite and positive; None is all ones.
    pub fn fit_weighted(
        &mut self,
        centres: &[Vec3],
        targets: &[Vec3],
        lambda_eff: f64,
        weights: Option<&[f64]>,
    ) -> Result<()> {
        self.fitted = false;
        let n = centres.len();
        if targets.len() != n {
            return Err(CoreError::Numerical(format!(
                "TPS: {} centres but {} targets",
                n,
                targets.len()
            )));
        }
        if n < 4 {
            return Err(CoreError::Numerical(format!(
                "TPS: {n} centres, at least 4 non-coplanar centres are needed"
            )));
        }
        if !(lambda_eff.is_finite() && lambda_eff > 0.0) {
            return Err(CoreError::Numerical(format!(
                "TPS: lambda_eff = {lambda_eff} must be finite and positive"
            )));
        }
        if let Some(w) = weights {
            if w.len() != n || !w.iter().all(|x| x.is_finite() && *x > 0.0) {
                return Err(CoreError::Numerical(
                    "TPS: one finite, positive weight per centre is needed".into(),
                ));
            }
        }
        if centres
            .iter()
            .chain(targets)
            .any(|p| !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite()))
        {
            return Err(CoreError::Numerical(
                "TPS: non-finite centre or target".into(),
            ));
        }
        // A factor of the same size from the last fit (not a new set of centres) can serve as the
        // preconditioner, unless the last reuse already needed many iterations (stale factor).
        let same_centres = self.factor_ok && self.n == n;
        let reuse = same_centres && !self.always_refactor && self.last_iterations <= REFACTOR_AFTER;
        self.factor_ok = false;
        self.n = n;
        let m = n - 4;
        self.kmat.resize(n * n, 0.0);
        self.hv.resize(4 * n, 0.0);
        self.chol.resize(m * m, 0.0);
        let m32 = f32_stride(m);
        self.chol32.resize(m * m32, 0.0);
        self.chol_t32.resize(m * m32, 0.0);
        self.chol_dinv32.resize(m, 0.0);
        self.pre_w.resize(3 * m32, 0.0);
        self.rhs.resize(3 * n, 0.0);
        self.tmp.resize(4 * n, 0.0);
        self.cg.resize(n);

        self.centre = centres.iter().sum::<Vec3>() / n as f64;
        self.householder_affine(centres)?;
        if reuse {
            // Warm start: the weights extrapolated linearly from the last two fits, 2 w_1 - w_2
            // (only w_1 after a factorisation of new centres), projected on the new null space in
            // `solve_reusing`. Measured: 0.4 fewer iterations per fit than w_1 alone.
            self.cg.g.copy_from_slice(&self.rhs);
            if self.w_prev_ok {
                for (g, p) in self.cg.g.iter_mut().zip(&self.cg.w_prev) {
                    *g = 2.0 * *g - p;
                }
            }
        }
        self.w_prev_ok = same_centres;
        self.cg.w_prev.copy_from_slice(&self.rhs);
        self.assemble_kernel(centres, 1.0 / lambda_eff, weights);
        if reuse {
            mirror_lower(&mut self.kmat, n);
        }
        self.project_rhs(targets);
        let mut bg = [[0.0; 4]; 3];
        let mut solved = false;
        if reuse {
            let tol = targets_norms(targets).map(|x| CG_RTOL * x);
            match self.solve_reusing(&tol) {
                Some((b, iterations)) => {
                    bg = b;
                    solved = true;
                    self.last_iterations = iterations;
                    self.stats.reused += 1;
                    self.stats.iterations += iterations;
                }
                None => {
                    self.stats.failed += 1;
                    self.stats.iterations += CG_MAX_ITERATIONS;
                }
            }
        }
        if !solved {
            self.project_kernel();
            cholesky_in_place(&mut self.chol, m)?;
            self.chol_t_ok = false;
            chol_solve3(&self.chol, m, &mut self.rhs, n, 4);
            // (Q^T K Q)[0..4, 4..] g, read through its mirror in the lower triangle.
            for (c, b) in self.rhs.chunks_exact(n).enumerate() {
                for (j, gj) in b[4..].iter().enumerate() {
                    let row = &self.kmat[(4 + j) * n..(4 + j) * n + 4];
                    for k in 0..4 {
                        bg[c][k] += row[k] * gj;
                    }
                }
            }
            self.last_iterations = 0;
            self.stats.factorisations += 1;
        }
        self.recover_weights_and_affine(&bg)?;
        self.build_chunks(centres);
        self.fitted = true;
        self.factor_ok = true;
        Ok(())
    }

    /// Kernel weights w_i of the current fit (one per centre).
    pub fn weights(&self) -> Vec<Vec3> {
        let n = self.len();
        (0..n)
            .map(|i| Vec3::new(self.rhs[i], self.rhs[n + i], self.rhs[2 * n + i]))
            .collect()
    }

    /// Affine part of the current fit in the plain basis: row c gives (a0, ax, ay, az) with
    /// F_c(x) = ... + a0 + ax x + ay y + az z.
    pub fn affine(&self) -> [[f64; 4]; 3] {
        let c = self.centre;
        self.affine_c
            .map(|[a0, ax, ay, az]| [a0 - ax * c.x - ay * c.y - az * c.z, ax, ay, az])
    }
}
