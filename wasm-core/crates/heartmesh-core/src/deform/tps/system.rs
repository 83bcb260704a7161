//! Assembly and projection of a fit's linear system: the kernel matrix K, the Householder QR of
//! the centred affine basis, K projected to Q^T K Q by one block reflector, the projected
//! right-hand sides, and the recovery of the weights and the affine part from the solution.

use super::{TpsSolver, KERNEL_SCALE};
use crate::deform::dense::{axpy, dot, dot_q};
#[cfg(target_arch = "x86_64")]
use crate::deform::lanes::avx::{self, Avx};
use crate::deform::lanes::{Quad, Q2};
use crate::deform::pcg::{apply_q, apply_qt};
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;

/// Relative size below which a column of the centred affine basis counts as zero (coplanar,
/// collinear or coincident centres).
const COPLANAR_TOL: f64 = 1e-10;

impl TpsSolver {
    /// Householder QR of the centred affine basis A = [1, x - c] (N x 4); keeps the reflectors
    /// and R, fails on coplanar centres.
    #[inline(never)] // one call per fit: kept out of line for profiles
    pub(super) fn householder_affine(&mut self, centres: &[Vec3]) -> Result<()> {
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
    pub(super) fn assemble_kernel(&mut self, centres: &[Vec3], diag: f64, weights: Option<&[f64]>) {
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
    pub(super) fn project_kernel(&mut self) {
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
    pub(super) fn project_rhs(&mut self, targets: &[Vec3]) {
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
    pub(super) fn recover_weights_and_affine(&mut self, bg: &[[f64; 4]; 3]) -> Result<()> {
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
}
