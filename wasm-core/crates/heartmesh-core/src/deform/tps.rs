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
//! explicit vectors (`lanes.rs`: two SSE / simd128 / plain-array halves, or one AVX register
//! natively when the CPU has it) with the same arithmetic in the same order, so every target, and
//! the portable reference `evaluate_portable`, gives identical bits; `evaluate_f64` is the
//! all-double reference. The projection, the residuals and the f64 fallback use the f64
//! four-lane vectors; the f32 factor and its triangular solves the f32 eight-lane ones.

use super::dense::{axpy, cholesky_in_place, dot, dot_q};
#[cfg(target_arch = "x86_64")]
use super::lanes::avx::{self, Avx, Avx32};
use super::lanes::{portable, Oct, Pair32, Quad, O4, Q2};
use super::pcg::{
    apply_q, apply_qt, chol_solve3, deactivate_converged, f32_stride, factor_to_f32, mirror_lower,
    precondition3_f32, projected_matvec,
};
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;

/// Lanes of the evaluation kernel (two f64x2 vectors in wasm).
const LANES: usize = 4;
/// Relative size below which a column of the centred affine basis counts as zero (coplanar,
/// collinear or coincident centres).
const COPLANAR_TOL: f64 = 1e-10;

/// -1 / (8 pi): the 3D biharmonic Green's function is G(r) = KERNEL_SCALE * r.
const KERNEL_SCALE: f64 = -1.0 / (8.0 * std::f64::consts::PI);

/// Four centres and their weights, structure-of-arrays so the kernel loads whole lanes.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Chunk {
    x: [f64; 4],
    y: [f64; 4],
    z: [f64; 4],
    wx: [f64; 4],
    wy: [f64; 4],
    wz: [f64; 4],
}

/// Eight centres (relative to the fit's centre) and their weights in single precision: the chunks
/// of the mixed-precision evaluation.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Chunk32 {
    x: [f32; 8],
    y: [f32; 8],
    z: [f32; 8],
    wx: [f32; 8],
    wy: [f32; 8],
    wz: [f32; 8],
}

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

#[derive(Debug, Clone, Default)]
struct CgBuffers {
    /// The weights of the fit before the last one (warm start).
    w_prev: Vec<f64>,
    g: Vec<f64>,
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    u: Vec<f64>,
    y: Vec<f64>,
}

impl CgBuffers {
    fn resize(&mut self, n: usize) {
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

    /// Solves the projected system (Q^T K Q)[4.., 4..] g = (Q^T b)[4..] by conjugate gradients
    /// preconditioned with the factor in `chol` (an earlier step's), starting from the projection
    /// of the earlier weights in `cg.g`. On success g is in rhs[4..] of each row and the result
    /// is the affine block (Q^T K Q)[0..4, 4..] g per coordinate and the iteration count; None when
    /// the residual did not fall below `tol` within [`CG_MAX_ITERATIONS`] (rhs still holds Q^T b).
    fn solve_reusing(&mut self, tol: &[f64; 3]) -> Option<([[f64; 4]; 3], usize)> {
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

    /// Householder QR of the centred affine basis A = [1, x - c] (N x 4); keeps the reflectors
    /// and R, fails on coplanar centres.
    #[inline(never)] // one call per fit: kept out of line for profiles
    fn householder_affine(&mut self, centres: &[Vec3]) -> Result<()> {
        let n = self.n;
        let c = self.centre;
        // Columns of A, stored in hv (then turned into the reflectors row by row).
        let (col0, rest) = self.hv.split_at_mut(n);
        let (col1, rest) = rest.split_at_mut(n);
        let (col2, col3) = rest.split_at_mut(n);
        for (i, p) in centres.iter().enumerate() {
            col0[i] = 1.0;
            col1[i] = p.x - c.x;
            col2[i] = p.y - c.y;
            col3[i] = p.z - c.z;
        }
        let scale = (0..4)
            .map(|k| dot(&self.hv[k * n..(k + 1) * n], &self.hv[k * n..(k + 1) * n]).sqrt())
            .fold(0.0, f64::max);
        self.r = [[0.0; 4]; 4];
        for k in 0..4 {
            let (done, rest) = self.hv.split_at_mut((k + 1) * n);
            let v = &mut done[k * n..];
            for x in &mut v[..k] {
                *x = 0.0;
            }
            let norm = dot(&v[k..], &v[k..]).sqrt();
            if norm.is_nan() || norm <= COPLANAR_TOL * scale {
                return Err(CoreError::Numerical(
                    "TPS: the centres are coplanar (or collinear, or coincident)".into(),
                ));
            }
            let alpha = if v[k] > 0.0 { -norm } else { norm };
            v[k] -= alpha;
            // |v[k]| = norm + |x_k| >= norm > 0, so v^T v > 0.
            let beta = 2.0 / dot(&v[k..], &v[k..]);
            self.hbeta[k] = beta;
            self.r[k][k] = alpha;
            // Apply H_k to the remaining columns (stored after v in `rest`).
            for j in 0..(3 - k) {
                let col = &mut rest[j * n..(j + 1) * n];
                let s = beta * dot(&v[k..], &col[k..]);
                axpy(-s, &v[k..], &mut col[k..]);
                self.r[k][k + 1 + j] = col[k];
            }
        }
        Ok(())
    }

    /// K = G + diag(1 / (lambda_eff w_i)) over the centres (w_i = 1 without weights), lower
    /// triangle only (K is symmetric; every later step reads the lower triangle). Rows are filled from structure-of-arrays coordinates so the
    /// square roots vectorise.
    #[inline(never)] // one call per fit: kept out of line for profiles
    fn assemble_kernel(&mut self, centres: &[Vec3], diag: f64, weights: Option<&[f64]>) {
        #[cfg(target_arch = "x86_64")]
        if avx::available() {
            // SAFETY: the CPU has AVX.
            unsafe { self.assemble_kernel_avx(centres, diag) };
        } else {
            self.assemble_kernel_lanes(centres, diag);
        }
        #[cfg(not(target_arch = "x86_64"))]
        self.assemble_kernel_lanes(centres, diag);
        if let Some(w) = weights {
            let n = self.n;
            for (i, wi) in w.iter().enumerate() {
                self.kmat[i * n + i] = diag / wi;
            }
        }
    }

    /// Elementwise (no sums), so the 256-bit build gives the same bits as the 128-bit one.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn assemble_kernel_avx(&mut self, centres: &[Vec3], diag: f64) {
        self.assemble_kernel_lanes(centres, diag);
    }

    #[inline(always)]
    fn assemble_kernel_lanes(&mut self, centres: &[Vec3], diag: f64) {
        let n = self.n;
        let (xs, rest) = self.tmp.split_at_mut(n);
        let (ys, rest) = rest.split_at_mut(n);
        let zs = &mut rest[..n];
        for (i, p) in centres.iter().enumerate() {
            (xs[i], ys[i], zs[i]) = (p.x, p.y, p.z);
        }
        for (i, p) in centres.iter().enumerate() {
            let row = &mut self.kmat[i * n..i * n + i + 1];
            let cols = xs[..i].iter().zip(&ys[..i]).zip(&zs[..i]);
            for (g, ((x, y), z)) in row[..i].iter_mut().zip(cols) {
                let (dx, dy, dz) = (p.x - x, p.y - y, p.z - z);
                *g = KERNEL_SCALE * (dx * dx + dy * dy + dz * dz).sqrt();
            }
            row[i] = diag;
        }
    }

    /// K <- Q^T K Q for Q = H_0 H_1 H_2 H_3, then copies the trailing (N-4) x (N-4) block (lower
    /// triangle) into the Cholesky buffer.
    ///
    /// The four reflectors are applied as one block (compact WY form, Q = I - V T V^T; Schreiber &
    /// Van Loan, SIAM J. Sci. Stat. Comput. 10(1), 1989), so K is read twice instead of eight
    /// times: X = K V, then K -= Y V^T + V Y^T with Y = X T - V (T^T V^T X T) / 2.
    #[inline(never)] // one call per fit: kept out of line for profiles
    fn project_kernel(&mut self) {
        #[cfg(target_arch = "x86_64")]
        if avx::available() {
            // SAFETY: the CPU has AVX.
            return unsafe { self.project_kernel_avx() };
        }
        self.project_kernel_q::<Q2>();
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn project_kernel_avx(&mut self) {
        self.project_kernel_q::<Avx>();
    }

    #[inline(always)]
    fn project_kernel_q<Q: Quad>(&mut self) {
        let n = self.n;
        let v = &self.hv;
        // T: upper triangular with H_0 ... H_3 = I - V T V^T.
        let mut t = [[0.0; 4]; 4];
        for j in 0..4 {
            let mut z = [0.0; 4];
            for (k, zk) in z.iter_mut().enumerate().take(j) {
                *zk = dot_q::<Q>(&v[k * n + j..(k + 1) * n], &v[j * n + j..(j + 1) * n]);
            }
            for (a, row) in t.iter_mut().enumerate().take(j) {
                row[j] = -self.hbeta[j] * (a..j).map(|b| row[b] * z[b]).sum::<f64>();
            }
            t[j][j] = self.hbeta[j];
        }
        // X = K V (column-major, 4 x N, in tmp) from the lower triangle: row i gives the j <= i
        // terms of X[i] by dot products and the j < i terms of X[j] by axpys.
        self.tmp.fill(0.0);
        for i in 0..n {
            let row = &self.kmat[i * n..i * n + i + 1];
            for k in 0..4 {
                let vk = &v[k * n..(k + 1) * n];
                let xk = &mut self.tmp[k * n..(k + 1) * n];
                xk[i] += dot_q::<Q>(row, &vk[..i + 1]);
                if vk[i] != 0.0 {
                    axpy(vk[i], &row[..i], &mut xk[..i]);
                }
            }
        }
        // S = T^T (V^T X) T (symmetric 4 x 4).
        let mut vx = [[0.0; 4]; 4];
        for (a, row) in vx.iter_mut().enumerate() {
            for (b, e) in row.iter_mut().enumerate() {
                *e = dot_q::<Q>(
                    &v[a * n + a..(a + 1) * n],
                    &self.tmp[b * n + a..(b + 1) * n],
                );
            }
        }
        let mut mt = [[0.0; 4]; 4];
        for a in 0..4 {
            for b in 0..4 {
                mt[a][b] = (0..=b).map(|c| vx[a][c] * t[c][b]).sum();
            }
        }
        let mut sm = [[0.0; 4]; 4];
        for a in 0..4 {
            for b in 0..4 {
                sm[a][b] = (0..=a).map(|c| t[c][a] * mt[c][b]).sum();
            }
        }
        // Y = X T - V S / 2, row by row in place.
        for i in 0..n {
            let x = [0, 1, 2, 3].map(|k| self.tmp[k * n + i]);
            let vi = [0, 1, 2, 3].map(|k| v[k * n + i]);
            for b in 0..4 {
                let xt: f64 = (0..=b).map(|a| x[a] * t[a][b]).sum();
                let vs: f64 = (0..4).map(|a| vi[a] * sm[a][b]).sum();
                self.tmp[b * n + i] = xt - 0.5 * vs;
            }
        }
        // K -= Y V^T + V Y^T in one pass over the lower triangle.
        let (y, v) = (&self.tmp, &self.hv);
        for i in 0..n {
            let yi = [y[i], y[n + i], y[2 * n + i], y[3 * n + i]];
            let vi = [v[i], v[n + i], v[2 * n + i], v[3 * n + i]];
            let e = i + 1;
            let row = &mut self.kmat[i * n..i * n + e];
            let cols = (
                (
                    &v[..e],
                    &v[n..n + e],
                    &v[2 * n..2 * n + e],
                    &v[3 * n..3 * n + e],
                ),
                (
                    &y[..e],
                    &y[n..n + e],
                    &y[2 * n..2 * n + e],
                    &y[3 * n..3 * n + e],
                ),
            );
            let ((v0, v1, v2, v3), (y0, y1, y2, y3)) = cols;
            for j in 0..e {
                let a = (yi[0] * v0[j] + yi[1] * v1[j]) + (yi[2] * v2[j] + yi[3] * v3[j]);
                let b = (vi[0] * y0[j] + vi[1] * y1[j]) + (vi[2] * y2[j] + vi[3] * y3[j]);
                row[j] -= a + b;
            }
        }
        let m = n - 4;
        for i in 0..m {
            let src = &self.kmat[(4 + i) * n + 4..(4 + i) * n + 5 + i];
            self.chol[i * m..i * m + i + 1].copy_from_slice(src);
        }
    }

    /// rhs <- Q^T b for the three coordinates of the targets.
    #[inline(never)] // one call per fit: kept out of line for profiles
    fn project_rhs(&mut self, targets: &[Vec3]) {
        let n = self.n;
        for (i, t) in targets.iter().enumerate() {
            self.rhs[i] = t.x;
            self.rhs[n + i] = t.y;
            self.rhs[2 * n + i] = t.z;
        }
        for b in self.rhs.chunks_exact_mut(n) {
            apply_qt(&self.hv, &self.hbeta, n, b);
        }
    }

    /// a from R a = Q1^T b - (Q^T K Q)[0..4, 4..] g, then w = Q [0; g].
    fn recover_weights_and_affine(&mut self, bg: &[[f64; 4]; 3]) -> Result<()> {
        let n = self.n;
        for (c, b) in self.rhs.chunks_exact_mut(n).enumerate() {
            let t = [0, 1, 2, 3].map(|k| b[k] - bg[c][k]);
            let mut a = [0.0; 4];
            for k in (0..4).rev() {
                let mut s = t[k];
                for (rkj, aj) in self.r[k][k + 1..].iter().zip(&a[k + 1..]) {
                    s -= rkj * aj;
                }
                a[k] = s / self.r[k][k];
            }
            self.affine_c[c] = a;
            b[..4].fill(0.0);
            apply_q(&self.hv, &self.hbeta, n, b);
        }
        let finite = self.rhs.iter().all(|x| x.is_finite())
            && self.affine_c.iter().flatten().all(|x| x.is_finite());
        if finite {
            Ok(())
        } else {
            Err(CoreError::Numerical(
                "TPS: the solution is not finite (ill-conditioned centres)".into(),
            ))
        }
    }

    /// Evaluation chunks; the padding lanes repeat the first centre with zero weight, which adds
    /// exactly zero.
    fn build_chunks(&mut self, centres: &[Vec3]) {
        let n = self.n;
        let n_chunks = n.div_ceil(LANES);
        let pad = centres[0];
        self.chunks.resize(n_chunks, Chunk::default());
        for (ci, ch) in self.chunks.iter_mut().enumerate() {
            for l in 0..LANES {
                let i = ci * LANES + l;
                let (p, w) = if i < n {
                    let w = [self.rhs[i], self.rhs[n + i], self.rhs[2 * n + i]];
                    (centres[i], w.map(|x| x * KERNEL_SCALE))
                } else {
                    (pad, [0.0; 3])
                };
                ch.x[l] = p.x;
                ch.y[l] = p.y;
                ch.z[l] = p.z;
                ch.wx[l] = w[0];
                ch.wy[l] = w[1];
                ch.wz[l] = w[2];
            }
        }
        let c = self.centre;
        self.chunks32.resize(n.div_ceil(8), Chunk32::default());
        for (ci, ch) in self.chunks32.iter_mut().enumerate() {
            for l in 0..8 {
                let i = ci * 8 + l;
                let (p, w) = if i < n {
                    let w = [self.rhs[i], self.rhs[n + i], self.rhs[2 * n + i]];
                    (centres[i] - c, w.map(|x| x * KERNEL_SCALE))
                } else {
                    (pad - c, [0.0; 3])
                };
                ch.x[l] = p.x as f32;
                ch.y[l] = p.y as f32;
                ch.z[l] = p.z as f32;
                ch.wx[l] = w[0] as f32;
                ch.wy[l] = w[1] as f32;
                ch.wz[l] = w[2] as f32;
            }
        }
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

    /// F at one point (the identity before a successful fit), through the mixed-precision
    /// kernel of [`apply`](Self::apply): the same bits.
    #[inline]
    pub fn evaluate(&self, p: Vec3) -> Vec3 {
        self.evaluate_mixed::<O4>(p)
    }

    /// [`evaluate`](Self::evaluate) through the portable plain-array lanes. Every target gives
    /// the same bits (the SSE, AVX and simd128 kernels keep its lane order); this is the reference
    /// that checks it.
    pub fn evaluate_portable(&self, p: Vec3) -> Vec3 {
        self.evaluate_mixed::<Pair32<portable::F4>>(p)
    }

    /// F at one point with the kernel sum in double precision: the reference of the
    /// mixed-precision evaluation (tests and error measurements; not the hot loop).
    pub fn evaluate_f64(&self, p: Vec3) -> Vec3 {
        if !self.fitted {
            return p;
        }
        let k = kernel_sum::<Q2>(&self.chunks, p);
        let d = p - self.centre;
        let af = |a: &[f64; 4]| a[0] + a[1] * d.x + a[2] * d.y + a[3] * d.z;
        Vec3::new(
            k[0] + af(&self.affine_c[0]),
            k[1] + af(&self.affine_c[1]),
            k[2] + af(&self.affine_c[2]),
        )
    }

    #[inline(always)]
    fn evaluate_mixed<O: Oct>(&self, p: Vec3) -> Vec3 {
        if !self.fitted {
            return p;
        }
        let d = p - self.centre;
        let k = kernel_sum32::<O>(&self.chunks32, [d.x as f32, d.y as f32, d.z as f32]);
        let af = |a: &[f64; 4]| a[0] + a[1] * d.x + a[2] * d.y + a[3] * d.z;
        Vec3::new(
            f64::from(k[0]) + af(&self.affine_c[0]),
            f64::from(k[1]) + af(&self.affine_c[1]),
            f64::from(k[2]) + af(&self.affine_c[2]),
        )
    }

    /// Replaces every point by F(point); leaves them unchanged before a successful fit.
    ///
    /// Mixed precision: the affine part, the centring and the final sum stay in f64; only the
    /// kernel sum sum_i w_i G(|x - P_i|) (the non-affine displacement, a small correction) runs
    /// in f32, eight lanes per step (two SSE / simd128 halves, or one AVX register natively when
    /// the CPU has it; same bits). Measured against the f64 kernel over whole default runs
    /// (`pipeline::precision` test): the largest vertex difference of any step is
    /// 2.4e-6 mm on the SurFCo example and 5.5e-6 mm on biv-me patient 1 ED RV endocardium,
    /// against steps of up to a millimetre and contour distances of tenths of millimetres.
    /// Rounding the centred coordinates to f32 costs ~1e-7 of the mesh size, and the kernel sum
    /// is a small correction to the affine map; the result is still deterministic and the same
    /// bits on every target.
    pub fn apply(&self, points: &mut [Vec3]) {
        if !self.fitted {
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if avx::available() {
            // SAFETY: the CPU has AVX.
            return unsafe { self.apply_avx(points) };
        }
        self.apply_mixed::<O4>(points);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn apply_avx(&self, points: &mut [Vec3]) {
        self.apply_mixed::<Avx32>(points);
    }

    #[inline(always)]
    fn apply_mixed<O: Oct>(&self, points: &mut [Vec3]) {
        for p in points {
            *p = self.evaluate_mixed::<O>(*p);
        }
    }

    /// [`apply`](Self::apply) with the f64 kernel sum (the reference; see
    /// [`evaluate_f64`](Self::evaluate_f64)).
    pub fn apply_f64(&self, points: &mut [Vec3]) {
        for p in points {
            *p = self.evaluate_f64(*p);
        }
    }
}

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
const CG_RTOL: f64 = 1e-9;
/// Iterations after which a reuse is abandoned for this fit (then it factorises): a pass costs
/// about a seventh of a projection and factorisation at N = 200, so eight passes that failed
/// cost about what they could have saved.
const CG_MAX_ITERATIONS: usize = 8;
/// A reuse that needed more iterations than this makes the next fit factorise afresh: the
/// factor has gone stale, and every further step would need more.
const REFACTOR_AFTER: usize = 6;

/// Euclidean norm of each coordinate of the targets over the centres.
fn targets_norms(targets: &[Vec3]) -> [f64; 3] {
    let mut s = [0.0; 3];
    for t in targets {
        for c in 0..3 {
            s[c] += t[c] * t[c];
        }
    }
    s.map(f64::sqrt)
}

/// sum_i w_i G(|p - P_i|) in f32 for the three coordinates, `p` and the centres relative to the
/// fit's centre: eight lanes, lane l summing centres l, l + 8, ..., then the fixed `Oct::sum`.
#[inline(always)]
fn kernel_sum32<O: Oct>(chunks: &[Chunk32], p: [f32; 3]) -> [f32; 3] {
    let (px, py, pz) = (O::splat(p[0]), O::splat(p[1]), O::splat(p[2]));
    let mut acc = [O::zero(); 3];
    for ch in chunks {
        let dx = px.sub(O::load(&ch.x));
        let dy = py.sub(O::load(&ch.y));
        let dz = pz.sub(O::load(&ch.z));
        let r = dx.mul(dx).add(dy.mul(dy)).add(dz.mul(dz)).sqrt();
        acc[0] = acc[0].add(O::load(&ch.wx).mul(r));
        acc[1] = acc[1].add(O::load(&ch.wy).mul(r));
        acc[2] = acc[2].add(O::load(&ch.wz).mul(r));
    }
    acc.map(O::sum)
}

/// sum_i w_i G(|p - P_i|) for the three coordinates: four lanes, lane l summing centres l, l + 4,
/// ..., then (l0 + l1) + (l2 + l3); the same bits with every `Quad` implementation.
#[inline(always)]
fn kernel_sum<Q: Quad>(chunks: &[Chunk], p: Vec3) -> [f64; 3] {
    let (px, py, pz) = (Q::splat(p.x), Q::splat(p.y), Q::splat(p.z));
    let mut acc = [Q::zero(); 3];
    for ch in chunks {
        let dx = px.sub(Q::load(&ch.x));
        let dy = py.sub(Q::load(&ch.y));
        let dz = pz.sub(Q::load(&ch.z));
        let r = dx.mul(dx).add(dy.mul(dy)).add(dz.mul(dz)).sqrt();
        acc[0] = acc[0].add(Q::load(&ch.wx).mul(r));
        acc[1] = acc[1].add(Q::load(&ch.wy).mul(r));
        acc[2] = acc[2].add(Q::load(&ch.wz).mul(r));
    }
    acc.map(Q::sum)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;
    use crate::spatial::testutil::SplitMix64;

    /// Random centres in a unit-diameter-ish cloud away from the origin (normalised units, not
    /// centred, as the pipeline passes them).
    fn cloud(rng: &mut SplitMix64, n: usize) -> Vec<Vec3> {
        (0..n)
            .map(|_| v3(1.5, -0.7, 0.3) + rng.vec3(-0.35, 0.35))
            .collect()
    }

    /// A smooth non-affine displacement of about 0.05.
    fn warp(p: &Vec3) -> Vec3 {
        p + v3(
            0.05 * (3.0 * p.y).sin(),
            0.04 * p.x * p.z,
            0.03 * (2.0 * p.x + p.y).cos(),
        )
    }

    fn affine_map(p: &Vec3) -> Vec3 {
        v3(
            1.1 * p.x - 0.2 * p.y + 0.05 * p.z + 0.3,
            0.1 * p.x + 0.9 * p.y - 0.1 * p.z - 0.2,
            -0.05 * p.x + 0.15 * p.y + 1.2 * p.z + 0.1,
        )
    }

    /// Normwise backward error of the full augmented system in the plain basis (1, x, y, z):
    /// max |residual| / (||M||_inf max|x| + max|rhs|).
    fn augmented_residual(
        centres: &[Vec3],
        targets: &[Vec3],
        lambda_eff: f64,
        s: &TpsSolver,
    ) -> f64 {
        let n = centres.len();
        let w = s.weights();
        let a = s.affine();
        let mut max_res: f64 = 0.0;
        let mut m_norm: f64 = 0.0;
        for i in 0..n {
            let mut row_sum = 1.0 / lambda_eff;
            let mut f = [0.0; 3];
            for j in 0..n {
                let g = if i == j {
                    1.0 / lambda_eff
                } else {
                    KERNEL_SCALE * (centres[i] - centres[j]).norm()
                };
                if i != j {
                    row_sum += g.abs();
                }
                for c in 0..3 {
                    f[c] += g * w[j][c];
                }
            }
            let p = centres[i];
            row_sum += 1.0 + p.x.abs() + p.y.abs() + p.z.abs();
            m_norm = m_norm.max(row_sum);
            for c in 0..3 {
                let fa = f[c] + a[c][0] + a[c][1] * p.x + a[c][2] * p.y + a[c][3] * p.z;
                max_res = max_res.max((fa - targets[i][c]).abs());
            }
        }
        // A^T w = 0 rows.
        let col_sum: f64 = centres.iter().map(|p| p.abs().max()).sum::<f64>() + n as f64;
        m_norm = m_norm.max(col_sum);
        for c in 0..3 {
            let mut r = [0.0; 4];
            for (p, wi) in centres.iter().zip(&w) {
                r[0] += wi[c];
                r[1] += wi[c] * p.x;
                r[2] += wi[c] * p.y;
                r[3] += wi[c] * p.z;
            }
            max_res = max_res.max(r.iter().fold(0.0, |m, x| m.max(x.abs())));
        }
        let x_max = w
            .iter()
            .map(|v| v.abs().max())
            .chain(a.iter().flatten().map(|x| x.abs()))
            .fold(0.0, f64::max);
        let b_max = targets.iter().map(|t| t.abs().max()).fold(0.0, f64::max);
        max_res / (m_norm * x_max + b_max)
    }

    #[test]
    fn large_lambda_reproduces_targets() {
        let mut rng = SplitMix64::new(1);
        let centres = cloud(&mut rng, 120);
        let targets: Vec<Vec3> = centres.iter().map(warp).collect();
        let mut s = TpsSolver::new();
        s.fit(&centres, &targets, 1e12).unwrap();
        let worst = centres
            .iter()
            .zip(&targets)
            .map(|(c, t)| (s.evaluate(*c) - t).norm())
            .fold(0.0, f64::max);
        assert!(worst < 1e-6, "max |F(P) - Q'| = {worst:e}");
        // And it is a genuine warp, not the affine fit: the affine part alone misses by far more.
        let mut plain = TpsSolver::new();
        plain.fit(&centres, &targets, 1e-9).unwrap();
        let affine_miss = centres
            .iter()
            .zip(&targets)
            .map(|(c, t)| (plain.evaluate(*c) - t).norm())
            .fold(0.0, f64::max);
        assert!(affine_miss > 1e-3, "affine misses by {affine_miss:e}");
    }

    /// Unit weights are the unweighted fit (same bits); a tiny weight frees its centre while the
    /// others are still interpolated.
    #[test]
    fn weights_scale_each_centres_data_term() {
        let mut rng = SplitMix64::new(5);
        let centres = cloud(&mut rng, 60);
        let mut targets: Vec<Vec3> = centres.iter().map(warp).collect();
        targets[7] += Vec3::new(0.5, 0.0, 0.0);
        let mut plain = TpsSolver::new();
        plain.fit(&centres, &targets, 1e8).unwrap();
        let mut ones = TpsSolver::new();
        ones.fit_weighted(&centres, &targets, 1e8, Some(&[1.0; 60]))
            .unwrap();
        let probe = Vec3::new(0.3, -0.2, 0.1);
        assert_eq!(plain.evaluate(probe), ones.evaluate(probe));
        // Interpolating fit: centre 7 is pulled 0.5 off the smooth warp.
        assert!((plain.evaluate(centres[7]) - targets[7]).norm() < 1e-4);
        let mut w = vec![1.0; 60];
        w[7] = 1e-8;
        let mut weighted = TpsSolver::new();
        weighted
            .fit_weighted(&centres, &targets, 1e8, Some(&w))
            .unwrap();
        let miss7 = (weighted.evaluate(centres[7]) - targets[7]).norm();
        assert!(
            miss7 > 0.3,
            "down-weighted centre still interpolated: {miss7}"
        );
        let others = (0..60)
            .filter(|&i| i != 7)
            .map(|i| (weighted.evaluate(centres[i]) - targets[i]).norm())
            .fold(0.0, f64::max);
        assert!(others < 1e-4, "other centres miss by {others:e}");
        for bad in [vec![1.0; 59], vec![0.0; 60], vec![f64::NAN; 60]] {
            assert!(weighted
                .fit_weighted(&centres, &targets, 1e8, Some(&bad))
                .is_err());
        }
    }

    #[test]
    fn affine_targets_give_an_affine_map_everywhere() {
        let mut rng = SplitMix64::new(2);
        let centres = cloud(&mut rng, 80);
        let targets: Vec<Vec3> = centres.iter().map(affine_map).collect();
        for lambda_eff in [1e-8, 1.0, 1e5 / 80.0, 1e12] {
            let mut s = TpsSolver::new();
            s.fit(&centres, &targets, lambda_eff).unwrap();
            let mut probes: Vec<Vec3> = (0..200).map(|_| rng.vec3(-3.0, 3.0)).collect();
            let want: Vec<Vec3> = probes.iter().map(affine_map).collect();
            s.apply(&mut probes);
            for (got, want) in probes.iter().zip(&want) {
                assert!(
                    (got - want).norm() < 1e-9,
                    "lambda {lambda_eff}: {got:?} vs {want:?}"
                );
            }
        }
    }

    #[test]
    fn tiny_lambda_is_the_least_squares_affine_fit() {
        let mut rng = SplitMix64::new(9);
        let centres = cloud(&mut rng, 60);
        let targets: Vec<Vec3> = centres.iter().map(warp).collect();
        let mut s = TpsSolver::new();
        s.fit(&centres, &targets, 1e-10).unwrap();
        // Least-squares residuals are orthogonal to the affine basis: sum r = 0, sum r x^T = 0.
        let mut moments = [[0.0f64; 4]; 3];
        for (p, t) in centres.iter().zip(&targets) {
            let r = s.evaluate(*p) - t;
            for c in 0..3 {
                moments[c][0] += r[c];
                moments[c][1] += r[c] * p.x;
                moments[c][2] += r[c] * p.y;
                moments[c][3] += r[c] * p.z;
            }
        }
        for m in moments.iter().flatten() {
            assert!(m.abs() < 1e-9, "moment {m:e}");
        }
    }

    #[test]
    fn augmented_system_residual_is_tiny() {
        let mut rng = SplitMix64::new(3);
        for n in [50, 51, 300, 1000] {
            let centres = cloud(&mut rng, n);
            let targets: Vec<Vec3> = centres
                .iter()
                .map(|p| warp(p) + rng.vec3(-0.01, 0.01))
                .collect();
            let mut s = TpsSolver::new();
            for lambda_eff in [1e5 / n as f64, 1e12] {
                s.fit(&centres, &targets, lambda_eff).unwrap();
                let res = augmented_residual(&centres, &targets, lambda_eff, &s);
                assert!(
                    res <= 1e-10,
                    "N = {n}, lambda_eff = {lambda_eff}: residual {res:e}"
                );
            }
        }
    }

    #[test]
    fn repeated_fits_give_identical_bits_and_reuse_buffers() {
        let mut rng = SplitMix64::new(4);
        let centres = cloud(&mut rng, 200);
        let targets: Vec<Vec3> = centres.iter().map(warp).collect();
        let mut probes: Vec<Vec3> = (0..500)
            .map(|_| v3(1.5, -0.7, 0.3) + rng.vec3(-0.5, 0.5))
            .collect();
        let mut s = TpsSolver::new();
        s.fit(&centres, &targets, 1e5 / 200.0).unwrap();
        let ptrs = (
            s.kmat.as_ptr(),
            s.chol.as_ptr(),
            s.chunks.as_ptr(),
            s.rhs.as_ptr(),
        );
        let w1 = s.weights();
        let mut a = probes.clone();
        s.apply(&mut a);
        // Another fit in between, then the same fit again on the same solver and a fresh one.
        s.fit(&targets, &centres, 3.0).unwrap();
        s.fit(&centres, &targets, 1e5 / 200.0).unwrap();
        assert_eq!(
            ptrs,
            (
                s.kmat.as_ptr(),
                s.chol.as_ptr(),
                s.chunks.as_ptr(),
                s.rhs.as_ptr()
            ),
            "a fit at the same N reallocated"
        );
        let mut fresh = TpsSolver::new();
        fresh.fit(&centres, &targets, 1e5 / 200.0).unwrap();
        let mut b = probes.clone();
        s.apply(&mut b);
        fresh.apply(&mut probes);
        assert_eq!(w1, s.weights());
        assert_eq!(w1, fresh.weights());
        assert_eq!(a, b);
        assert_eq!(a, probes);
    }

    /// Centres moved a little (as between two deformation steps): the next fit reuses the
    /// factor, converges, and agrees with a factorised fit to the tolerance's bound; new centres
    /// after `invalidate_factor` factorise again.
    #[test]
    fn reused_factor_solves_nearby_systems_to_the_tolerance() {
        let mut rng = SplitMix64::new(21);
        let n = 200;
        let mut centres = cloud(&mut rng, n);
        let mut s = TpsSolver::new();
        let mut exact = TpsSolver::new();
        exact.set_always_refactor(true);
        let probes: Vec<Vec3> = (0..300)
            .map(|_| v3(1.5, -0.7, 0.3) + rng.vec3(-0.4, 0.4))
            .collect();
        for step in 0..6 {
            let targets: Vec<Vec3> = centres.iter().map(warp).collect();
            let w: Vec<f64> = (0..n)
                .map(|i| if i % 7 == step { 0.3 } else { 1.0 })
                .collect();
            let weights = (step >= 4).then_some(&w[..]);
            s.fit_weighted(&centres, &targets, 1e5 / n as f64, weights)
                .unwrap();
            exact
                .fit_weighted(&centres, &targets, 1e5 / n as f64, weights)
                .unwrap();
            let worst = probes
                .iter()
                .map(|p| (s.evaluate_f64(*p) - exact.evaluate_f64(*p)).norm())
                .fold(0.0f64, f64::max);
            // 2 |r| <= 2 CG_RTOL |b| with |b| ~ 25 here.
            assert!(worst < 1e-8, "step {step}: {worst:e}");
            // Each centre moves by up to 2e-4 of the cloud's size.
            for c in &mut centres {
                *c += rng.vec3(-2e-4, 2e-4);
            }
        }
        let st = s.stats();
        assert_eq!(st.factorisations + st.reused, 6);
        assert!(st.reused >= 4, "{st:?}");
        assert_eq!(exact.stats().reused, 0);
        let fresh = cloud(&mut rng, n);
        let targets: Vec<Vec3> = fresh.iter().map(warp).collect();
        s.invalidate_factor();
        s.fit(&fresh, &targets, 1e5 / n as f64).unwrap();
        assert_eq!(s.stats().factorisations, st.factorisations + 1);
    }

    #[test]
    fn kernel_matches_a_plain_sum() {
        let mut rng = SplitMix64::new(5);
        for n in [4, 5, 7, 31, 300] {
            let centres = cloud(&mut rng, n);
            let targets: Vec<Vec3> = centres.iter().map(warp).collect();
            let mut s = TpsSolver::new();
            s.fit(&centres, &targets, 50.0).unwrap();
            let w = s.weights();
            let aff = s.affine();
            for _ in 0..50 {
                let p = v3(1.5, -0.7, 0.3) + rng.vec3(-0.6, 0.6);
                let mut want = Vec3::zeros();
                // Sum of the terms' magnitudes: the scale of the f32 kernel sum's rounding.
                let mut magnitude = 0.0;
                for (c, wi) in centres.iter().zip(&w) {
                    want += wi * (KERNEL_SCALE * (p - c).norm());
                    magnitude += wi.norm() * (KERNEL_SCALE * (p - c).norm()).abs();
                }
                for c in 0..3 {
                    want[c] += aff[c][0] + aff[c][1] * p.x + aff[c][2] * p.y + aff[c][3] * p.z;
                }
                let exact = s.evaluate_f64(p);
                assert!(
                    (exact - want).norm() <= 1e-12 * want.norm(),
                    "{exact:?} vs {want:?}"
                );
                // Mixed precision: within a few f32 roundings of the terms' magnitudes.
                let got = s.evaluate(p);
                assert!(
                    (got - want).norm() <= 1e-6 * magnitude + 1e-15,
                    "n {n}: {got:?} vs {want:?} (terms {magnitude:e})"
                );
                assert_eq!(got, s.evaluate_portable(p));
                // `apply` (AVX natively when available) gives the same bits as `evaluate`.
                let mut q = [p];
                s.apply(&mut q);
                assert_eq!(q[0], s.evaluate_portable(p));
                let mut r = [p];
                s.apply_f64(&mut r);
                assert_eq!(r[0], exact);
            }
        }
    }

    /// Two attractors can share a closest mesh point: at the pipeline's lambda the smoothing term
    /// keeps the system definite, and F there is the mean of the two targets (minus the small
    /// kernel correction), not a blow-up.
    #[test]
    fn duplicate_centres_are_handled_at_finite_lambda() {
        let mut rng = SplitMix64::new(8);
        let mut centres = cloud(&mut rng, 150);
        centres[7] = centres[3];
        let mut targets: Vec<Vec3> = centres.iter().map(warp).collect();
        targets[3] += v3(0.004, 0.0, 0.0);
        targets[7] -= v3(0.004, 0.0, 0.0);
        let mut s = TpsSolver::new();
        s.fit(&centres, &targets, 1e5 / 150.0).unwrap();
        let mid = (targets[3] + targets[7]) / 2.0;
        let f = s.evaluate(centres[3]);
        assert!((f - mid).norm() < 1e-3, "F = {f:?}, mean target {mid:?}");
        let w = s.weights();
        assert!(w.iter().all(|w| w.norm() < 1e3), "weights blew up");
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        let mut s = TpsSolver::new();
        let sq = [
            v3(0., 0., 0.),
            v3(1., 0., 0.),
            v3(0., 1., 0.),
            v3(1., 1., 0.),
            v3(0.5, 0.2, 0.),
        ];
        let tet = [
            v3(0., 0., 0.),
            v3(1., 0., 0.),
            v3(0., 1., 0.),
            v3(0., 0., 1.),
        ];
        let cases: Vec<(Vec<Vec3>, Vec<Vec3>, f64)> = vec![
            (tet[..3].to_vec(), tet[..3].to_vec(), 1.0), // too few
            (sq.to_vec(), sq.to_vec(), 1.0),             // coplanar
            (vec![tet[0]; 6], vec![tet[0]; 6], 1.0),     // coincident
            (tet.to_vec(), tet[..3].to_vec(), 1.0),      // length mismatch
            (tet.to_vec(), tet.to_vec(), 0.0),           // lambda 0
            (tet.to_vec(), tet.to_vec(), f64::NAN),      // lambda NaN
            (
                tet.to_vec(),
                vec![tet[0], tet[1], tet[2], v3(f64::INFINITY, 0., 0.)],
                1.0,
            ),
        ];
        for (c, t, l) in cases {
            let e = s.fit(&c, &t, l).unwrap_err();
            assert_eq!(e.code(), "numerical");
            assert!(s.is_empty());
            // An unfitted solver is the identity.
            let mut p = [v3(1., 2., 3.)];
            s.apply(&mut p);
            assert_eq!(p[0], v3(1., 2., 3.));
        }
        // The minimal case works: 4 non-coplanar centres interpolate exactly (w = 0 there).
        let t: Vec<Vec3> = tet.iter().map(|p| p * 2.0 + v3(0.1, 0.0, 0.0)).collect();
        s.fit(&tet, &t, 1e3).unwrap();
        for (c, t) in tet.iter().zip(&t) {
            assert!((s.evaluate(*c) - t).norm() < 1e-12);
        }
    }
}
