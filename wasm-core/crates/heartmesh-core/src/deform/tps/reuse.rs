//! The reused-factor solve of a fit: conjugate gradients on the projected system, preconditioned
//! with an earlier step's Cholesky factor (rounded to f32, `pcg.rs`), and the constants that decide
//! when a fit reuses a factor and when it factorises afresh (see the parent module's doc).

use super::TpsSolver;
use crate::deform::dense::{axpy, dot};
use crate::deform::pcg::{
    apply_qt, deactivate_converged, factor_to_f32, precondition3_f32, projected_matvec,
};
use crate::geometry::Vec3;

/// Residual, relative to each coordinate's target norm |b_c|, at which a reused-factor solve
/// stops (see `fit_weighted`). Why this value: with the affine part fitted exactly to g, the
/// spline's values at the centres differ from the exact solution's by e - D Z B^-1 r, where
/// |e| = |r| and the eigenvalues of B are at least those of D >= 1 / lambda_eff, so by at most
/// 2 |r|. Targets in the pipeline's normalised units lie within a unit-diameter cloud,
/// |b_c| <= 0.5 sqrt(N), so with N = 200 the values move by at most 2e-9 * 7 = 1.4e-8 units,
/// 1.4e-6 mm at a 100 mm heart: below what the f32 evaluation already moves the vertices
/// (`apply`, 5.5e-6 mm). Measured on whole runs (`pipeline::reuse`, session 5): at most
/// 1.4e-7 mm per step against factorising every step (1.6e-8 mm at 1e-10), and the accuracy and
/// real-case figures (`tests/accuracy.rs`, `tests/real_cases.rs`) identical to 3 decimals (mm,
/// ml) to those at 1e-10; it saves 0.5 iterations per reused fit on SurFCo (3.56 -> 3.07) and
/// 9 of 46 factorisations on the biv-me patient 1 ED RV endocardium.
pub(super) const CG_RTOL: f64 = 1e-9;
/// Iterations after which a reuse is abandoned for this fit (then it factorises): a pass costs
/// about a seventh of a projection and factorisation at N = 200, so eight passes that failed
/// cost about what they could have saved.
pub(super) const CG_MAX_ITERATIONS: usize = 8;
/// A reuse that needed more iterations than this makes the next fit factorise afresh: the
/// factor has gone stale, and every further step would need more.
pub(super) const REFACTOR_AFTER: usize = 6;

/// Euclidean norm of each coordinate of the targets over the centres.
pub(super) fn targets_norms(targets: &[Vec3]) -> [f64; 3] {
    let mut s = [0.0; 3];
    for t in targets {
        for c in 0..3 {
            s[c] += t[c] * t[c];
        }
    }
    s.map(f64::sqrt)
}

#[derive(Debug, Clone, Default)]
pub(super) struct CgBuffers {
    /// The weights of the fit before the last one (warm start).
    pub(super) w_prev: Vec<f64>,
    pub(super) g: Vec<f64>,
    pub(super) r: Vec<f64>,
    pub(super) z: Vec<f64>,
    pub(super) p: Vec<f64>,
    pub(super) u: Vec<f64>,
    pub(super) y: Vec<f64>,
}

impl CgBuffers {
    pub(super) fn resize(&mut self, n: usize) {
        for b in [
            &mut self.w_prev,
            &mut self.g,
            &mut self.r,
            &mut self.z,
            &mut self.p,
            &mut self.u,
            &mut self.y,
        ] {
            b.resize(3 * n, 0.0);
        }
    }
}

impl TpsSolver {
    /// Solves the projected system (Q^T K Q)[4.., 4..] g = (Q^T b)[4..] by conjugate gradients
    /// preconditioned with the factor in `chol` (an earlier step's), starting from the projection
    /// of the earlier weights in `cg.g`. On success g is in rhs[4..] of each row and the result
    /// is the affine block (Q^T K Q)[0..4, 4..] g per coordinate and the iteration count; None when
    /// the residual did not fall below `tol` within [`CG_MAX_ITERATIONS`] (rhs still holds Q^T b).
    pub(super) fn solve_reusing(&mut self, tol: &[f64; 3]) -> Option<([[f64; 4]; 3], usize)> {
        let (n, m) = (self.n, self.n - 4);
        if !self.chol_t_ok {
            factor_to_f32(
                &self.chol,
                &mut self.chol32,
                &mut self.chol_t32,
                &mut self.chol_dinv32,
                m,
            );
            self.chol_t_ok = true;
        }
        let cg = &mut self.cg;
        for g in cg.g.chunks_exact_mut(n) {
            apply_qt(&self.hv, &self.hbeta, n, g);
            g[..4].fill(0.0);
        }
        // r = c - B g, with t the affine block of Q^T K Q [0; g].
        projected_matvec(
            &self.kmat,
            &self.hv,
            &self.hbeta,
            n,
            &cg.g,
            &mut cg.u,
            &mut cg.y,
        );
        let mut t = [[0.0; 4]; 3];
        for (c, tc) in t.iter_mut().enumerate() {
            let row = c * n..(c + 1) * n;
            let (r, y, b) = (&mut cg.r[row.clone()], &cg.y[row.clone()], &self.rhs[row]);
            for ((ri, yi), bi) in r[4..].iter_mut().zip(&y[4..]).zip(&b[4..]) {
                *ri = bi - yi;
            }
            tc.copy_from_slice(&y[..4]);
        }
        // Each coordinate stops once its residual is below its tolerance. The test runs right
        // after the residuals are computed or updated, before the preconditioner: the pass that
        // would only prepare a search direction for an iteration that never comes is skipped
        // (one of the ~4 preconditioner passes of a typical fit; the iterates are the same).
        let mut active = [true; 3];
        deactivate_converged(&cg.r, n, tol, &mut active);
        let mut rz = [0.0; 3];
        if active.iter().any(|a| *a) {
            cg.z.copy_from_slice(&cg.r);
            precondition3_f32(
                &self.chol32,
                &self.chol_t32,
                &self.chol_dinv32,
                m,
                &mut cg.z,
                n,
                4,
                &mut self.pre_w,
            );
            cg.p.copy_from_slice(&cg.z);
            rz = [0, 1, 2].map(|c| {
                let row = c * n + 4..(c + 1) * n;
                dot(&cg.r[row.clone()], &cg.z[row])
            });
        }
        let mut alphas = [0.0; 3];
        let mut iterations = 0;
        while active.iter().any(|a| *a) {
            if iterations == CG_MAX_ITERATIONS {
                return None;
            }
            iterations += 1;
            projected_matvec(
                &self.kmat,
                &self.hv,
                &self.hbeta,
                n,
                &cg.p,
                &mut cg.u,
                &mut cg.y,
            );
            for c in (0..3).filter(|&c| active[c]) {
                let row = c * n..(c + 1) * n;
                let (p, y) = (&cg.p[row.clone()], &cg.y[row.clone()]);
                let pq = dot(&p[4..], &y[4..]);
                if !(pq > 0.0 && pq.is_finite() && rz[c] > 0.0) {
                    return None;
                }
                let alpha = rz[c] / pq;
                alphas[c] = alpha;
                axpy(alpha, &p[4..], &mut cg.g[c * n + 4..(c + 1) * n]);
                axpy(-alpha, &y[4..], &mut cg.r[c * n + 4..(c + 1) * n]);
                for k in 0..4 {
                    t[c][k] += alpha * y[k];
                }
            }
            deactivate_converged(&cg.r, n, tol, &mut active);
            if !active.iter().any(|a| *a) {
                break;
            }
            if iterations == CG_MAX_ITERATIONS {
                return None;
            }
            cg.z.copy_from_slice(&cg.r);
            precondition3_f32(
                &self.chol32,
                &self.chol_t32,
                &self.chol_dinv32,
                m,
                &mut cg.z,
                n,
                4,
                &mut self.pre_w,
            );
            for c in (0..3).filter(|&c| active[c]) {
                let row = c * n + 4..(c + 1) * n;
                let rz_new = dot(&cg.r[row.clone()], &cg.z[row.clone()]);
                // Polak-Ribiere: z_new . (r_new - r_old) / rz_old, r_new - r_old = -alpha y.
                let zy = dot(&cg.y[row.clone()], &cg.z[row.clone()]);
                let beta = -alphas[c] * zy / rz[c];
                rz[c] = rz_new;
                for (p, z) in cg.p[row.clone()].iter_mut().zip(&cg.z[row]) {
                    *p = z + beta * *p;
                }
            }
        }
        for c in 0..3 {
            let row = c * n + 4..(c + 1) * n;
            self.rhs[row.clone()].copy_from_slice(&cg.g[row]);
        }
        Some((t, iterations))
    }
}
