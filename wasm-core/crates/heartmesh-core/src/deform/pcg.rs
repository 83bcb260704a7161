//! Kernels of the reused-factor thin-plate-spline solve: the projected operator
//! v -> Z^T K Z v applied without forming Z^T K Z, the triangular solves with a kept Cholesky
//! factor, and the preconditioned conjugate gradient iteration that combines them.
//!
//! Reference: M. R. Hestenes & E. Stiefel, "Methods of conjugate gradients for solving linear
//! systems", J. Res. NBS 49(6), 1952; preconditioned form as in Y. Saad, "Iterative Methods for
//! Sparse Linear Systems", 2nd ed. SIAM 2003, algorithm 9.1. Why: between two deformation steps
//! the spline centres move by a small fraction of the remaining distance to the data, so the last
//! step's factor L_old L_old^T is a close approximation of the new projected system. Used as the
//! preconditioner it clusters the spectrum near 1, and a few iterations, each one pass over K and
//! two over L_old, replace the projection and the O(N^3) factorisation (see `tps/mod.rs`).
//!
//! Three right-hand sides (x, y, z) share every pass over a matrix; each keeps its own scalars.
//! All sums go through the fixed-order lane kernels of `dense.rs`, so every target gives the same
//! bits (no fused multiply-add).

use super::dense::{axpy, dot, dot3_q, dot3x2_q, dot_q};
#[cfg(target_arch = "x86_64")]
use super::lanes::avx::{self, Avx, Avx32};
use super::lanes::{avx_dispatch, Oct, Quad, O4, Q2};

/// x <- Q x = H_0 H_1 H_2 H_3 x for one N-vector (`hv`: 4 x N reflectors, row k zero before k).
pub(super) fn apply_q(hv: &[f64], hbeta: &[f64; 4], n: usize, x: &mut [f64]) {
    apply_q_q::<Q2>(hv, hbeta, n, x);
}

/// x <- Q^T x = H_3 H_2 H_1 H_0 x for one N-vector.
pub(super) fn apply_qt(hv: &[f64], hbeta: &[f64; 4], n: usize, x: &mut [f64]) {
    apply_qt_q::<Q2>(hv, hbeta, n, x);
}

#[inline(always)]
fn apply_q_q<Q: Quad>(hv: &[f64], hbeta: &[f64; 4], n: usize, x: &mut [f64]) {
    for k in (0..4).rev() {
        let v = &hv[k * n + k..(k + 1) * n];
        let s = hbeta[k] * dot_q::<Q>(v, &x[k..]);
        axpy(-s, v, &mut x[k..]);
    }
}

#[inline(always)]
fn apply_qt_q<Q: Quad>(hv: &[f64], hbeta: &[f64; 4], n: usize, x: &mut [f64]) {
    for k in 0..4 {
        let v = &hv[k * n + k..(k + 1) * n];
        let s = hbeta[k] * dot_q::<Q>(v, &x[k..]);
        axpy(-s, v, &mut x[k..]);
    }
}

avx_dispatch! {
    /// y = Q^T K Q [0; v] for three N-vectors (`v` rows with zeros at 0..4, K full); `u` is
    /// scratch. The product with the projected system without forming it.
    pub(super) fn projected_matvec / projected_matvec_avx (
        kmat: &[f64],
        hv: &[f64],
        hbeta: &[f64; 4],
        n: usize,
        v: &[f64],
        u: &mut [f64],
        y: &mut [f64],
    ) = projected_matvec_q::<Q2, Avx>;
}

#[inline(always)]
fn projected_matvec_q<Q: Quad>(
    kmat: &[f64],
    hv: &[f64],
    hbeta: &[f64; 4],
    n: usize,
    v: &[f64],
    u: &mut [f64],
    y: &mut [f64],
) {
    u.copy_from_slice(v);
    for row in u.chunks_exact_mut(n) {
        row[..4].fill(0.0);
        apply_q_q::<Q>(hv, hbeta, n, row);
    }
    matvec3_q::<Q>(kmat, n, u, y);
    for row in y.chunks_exact_mut(n) {
        apply_qt_q::<Q>(hv, hbeta, n, row);
    }
}

/// Copies the lower triangle of an N x N row-major matrix onto its upper triangle, so that
/// [`matvec3`] reads whole rows (one dot product per row instead of a dot product and three
/// axpys over the lower triangle, which costs a third more time per product).
pub(super) fn mirror_lower(a: &mut [f64], n: usize) {
    #[cfg(target_arch = "x86_64")]
    if avx::available() && a.len() >= n * n {
        // SAFETY: the CPU has AVX, and `a` holds the n x n matrix.
        return unsafe { mirror_lower_avx(a, n) };
    }
    mirror_lower_from(a, n, 0);
}

/// The entries (i, j), j < i, of [`mirror_lower`] not inside a full 4 x 4 tile strictly below the
/// diagonal of the first `tiled` rows (`tiled` a multiple of 4): copies, so any split gives the
/// same matrix.
fn mirror_lower_from(a: &mut [f64], n: usize, tiled: usize) {
    for i in 1..n {
        let j0 = if i < tiled { i / 4 * 4 } else { 0 };
        let (above, rest) = a.split_at_mut(i * n);
        for (dst, v) in above.chunks_exact_mut(n).skip(j0).zip(&rest[j0..i]) {
            dst[i] = *v;
        }
    }
}

/// [`mirror_lower`] by 4 x 4 tiles transposed in registers (four loads, eight shuffles and four
/// stores per sixteen entries, against a load and a store per entry): the mirror was a tenth of
/// the reused-factor solve.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn mirror_lower_avx(a: &mut [f64], n: usize) {
    use core::arch::x86_64::*;
    let tiled = n / 4 * 4;
    let p = a.as_mut_ptr();
    for bi in (0..tiled).step_by(4) {
        for bj in (0..bi).step_by(4) {
            // SAFETY: rows bi..bi + 4 and bj..bj + 4 and columns bj..bj + 4 and bi..bi + 4 are
            // all below `tiled` <= n, so every access is inside the n x n matrix (caller checked
            // a.len() >= n * n); the read tile (below the diagonal) and the written one (above)
            // do not overlap.
            unsafe {
                let r0 = _mm256_loadu_pd(p.add(bi * n + bj));
                let r1 = _mm256_loadu_pd(p.add((bi + 1) * n + bj));
                let r2 = _mm256_loadu_pd(p.add((bi + 2) * n + bj));
                let r3 = _mm256_loadu_pd(p.add((bi + 3) * n + bj));
                let t0 = _mm256_unpacklo_pd(r0, r1);
                let t1 = _mm256_unpackhi_pd(r0, r1);
                let t2 = _mm256_unpacklo_pd(r2, r3);
                let t3 = _mm256_unpackhi_pd(r2, r3);
                _mm256_storeu_pd(p.add(bj * n + bi), _mm256_permute2f128_pd(t0, t2, 0x20));
                _mm256_storeu_pd(
                    p.add((bj + 1) * n + bi),
                    _mm256_permute2f128_pd(t1, t3, 0x20),
                );
                _mm256_storeu_pd(
                    p.add((bj + 2) * n + bi),
                    _mm256_permute2f128_pd(t0, t2, 0x31),
                );
                _mm256_storeu_pd(
                    p.add((bj + 3) * n + bi),
                    _mm256_permute2f128_pd(t1, t3, 0x31),
                );
            }
        }
    }
    mirror_lower_from(a, n, tiled);
}

avx_dispatch! {
    /// y = K u for three N-vectors at once (`u`, `y`: 3 x N rows), K a full N x N row-major matrix:
    /// one pass over K, each row's three dot products sharing its loads.
    #[cfg(test)]
    fn matvec3 / matvec3_avx (kmat: &[f64], n: usize, u: &[f64], y: &mut [f64])
        = matvec3_q::<Q2, Avx>;
}

#[inline(always)]
fn matvec3_q<Q: Quad>(kmat: &[f64], n: usize, u: &[f64], y: &mut [f64]) {
    let (u0, rest) = u.split_at(n);
    let (u1, u2) = rest.split_at(n);
    let (u1, u2) = (&u1[..n], &u2[..n]);
    // Rows in pairs sharing the loads of u (same bits per row as one row at a time).
    let mut rows = kmat.chunks_exact(n).take(n);
    let mut i = 0;
    while let (Some(r0), Some(r1)) = (rows.next(), rows.next()) {
        let d = dot3x2_q::<Q>(r0, r1, u0, u1, u2);
        for (k, dk) in d.iter().enumerate() {
            y[i + k] = dk[0];
            y[n + i + k] = dk[1];
            y[2 * n + i + k] = dk[2];
        }
        i += 2;
    }
    if i + 1 == n {
        if let Some(row) = kmat.get(i * n..(i + 1) * n) {
            let d = dot3_q::<Q>(row, u0, u1, u2);
            y[i] = d[0];
            y[n + i] = d[1];
            y[2 * n + i] = d[2];
        }
    }
}

avx_dispatch! {
    /// Solves L L^T x = b in place for three m-vectors (`x`: 3 x `stride` rows, the unknowns at
    /// `[off, off + m)` of each row), L the lower triangle of an m x m row-major factor.
    pub(super) fn chol_solve3 / chol_solve3_avx (
        chol: &[f64],
        m: usize,
        x: &mut [f64],
        stride: usize,
        off: usize,
    ) = chol_solve3_q::<Q2, Avx>;
}

/// The three right-hand sides go through each row of L together (one load of the row); each
/// one's arithmetic is that of a separate `dot_q` / `axpy` solve.
#[inline(always)]
fn chol_solve3_q<Q: Quad>(chol: &[f64], m: usize, x: &mut [f64], stride: usize, off: usize) {
    let (bx, rest) = x.split_at_mut(stride);
    let (by, bz) = rest.split_at_mut(stride);
    let (yx, yy, yz) = (
        &mut bx[off..off + m],
        &mut by[off..off + m],
        &mut bz[off..off + m],
    );
    for i in 0..m {
        let row = &chol[i * m..i * m + i + 1];
        let d = dot3_q::<Q>(&row[..i], &yx[..i], &yy[..i], &yz[..i]);
        yx[i] = (yx[i] - d[0]) / row[i];
        yy[i] = (yy[i] - d[1]) / row[i];
        yz[i] = (yz[i] - d[2]) / row[i];
    }
    for i in (0..m).rev() {
        let row = &chol[i * m..i * m + i + 1];
        let v = [yx[i] / row[i], yy[i] / row[i], yz[i] / row[i]];
        (yx[i], yy[i], yz[i]) = (v[0], v[1], v[2]);
        let a = v.map(|v| -v);
        let (px, py, pz) = (&mut yx[..i], &mut yy[..i], &mut yz[..i]);
        for (((r, ex), ey), ez) in row[..i].iter().zip(px).zip(py).zip(pz) {
            *ex += a[0] * r;
            *ey += a[1] * r;
            *ez += a[2] * r;
        }
    }
}

/// Clears `active[c]` for each coordinate whose residual (rows of `r`, 3 x n, unknowns at 4..n)
/// has a norm at or below `tol[c]`.
pub(super) fn deactivate_converged(r: &[f64], n: usize, tol: &[f64; 3], active: &mut [bool; 3]) {
    for (c, a) in active.iter_mut().enumerate() {
        let row = &r[c * n + 4..(c + 1) * n];
        if *a && dot(row, row).sqrt() <= tol[c] {
            *a = false;
        }
    }
}

/// Row stride of the f32 factor copies: m rounded up to whole eight-lane blocks.
pub(super) fn f32_stride(m: usize) -> usize {
    m.div_ceil(8) * 8
}

/// Rounds the factor L (lower triangle of an m x m row-major f64 matrix) to single precision
/// for [`precondition3_f32`]: the strict lower triangle of L into `l32` and of L^T (its strict
/// upper triangle) into `lt32`, rows of [`f32_stride`] with zeros everywhere else, and the
/// reciprocals of the diagonal into `dinv`. The zeros let every dot product of the two solves
/// run over whole aligned eight-lane blocks, with no scalar tail: the extra products are exact
/// zeros (the unknowns are finite), so they do not change the sums.
pub(super) fn factor_to_f32(
    l: &[f64],
    l32: &mut [f32],
    lt32: &mut [f32],
    dinv: &mut [f32],
    m: usize,
) {
    let s = f32_stride(m);
    l32.fill(0.0);
    lt32.fill(0.0);
    for (i, row) in l.chunks_exact(m).take(m).enumerate() {
        for (j, v) in row[..i].iter().enumerate() {
            let v = *v as f32;
            l32[i * s + j] = v;
            lt32[j * s + i] = v;
        }
        dinv[i] = 1.0 / row[i] as f32;
    }
}

avx_dispatch! {
    /// z <- (L L^T)^-1 z in single precision for three m-vectors (layout of [`chol_solve3`]), with
    /// the f32 factor of [`factor_to_f32`]; `w` is 3 x [`f32_stride`] f32 scratch. Why f32: the
    /// preconditioner of the reused-factor solve only approximates the new system's inverse (the
    /// factor is a step old), so its own rounding at 1e-7 relative is far below that approximation
    /// error, and each pass over a triangle moves half the bytes in twice the lanes. The residuals,
    /// the products and the solution stay f64, so the converged answer keeps its tolerance.
    #[allow(clippy::too_many_arguments)] // the factor's three arrays and the rows' layout
    pub(super) fn precondition3_f32 / precondition3_f32_avx (
        l32: &[f32],
        lt32: &[f32],
        dinv: &[f32],
        m: usize,
        x: &mut [f64],
        stride: usize,
        off: usize,
        w: &mut [f32],
    ) = precondition3_f32_o::<O4, Avx32>;
}

#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn precondition3_f32_o<O: Oct>(
    l32: &[f32],
    lt32: &[f32],
    dinv: &[f32],
    m: usize,
    x: &mut [f64],
    stride: usize,
    off: usize,
    w: &mut [f32],
) {
    let s = f32_stride(m);
    let (wx, rest) = w[..3 * s].split_at_mut(s);
    let (wy, wz) = rest.split_at_mut(s);
    for (c, wc) in [&mut *wx, &mut *wy, &mut *wz].into_iter().enumerate() {
        for (a, b) in wc
            .iter_mut()
            .zip(&x[c * stride + off..c * stride + off + m])
        {
            *a = *b as f32;
        }
        wc[m..].fill(0.0);
    }
    for i in 0..m {
        let e = i.div_ceil(8) * 8;
        let row = &l32[i * s..i * s + e];
        let d = dot3_o::<O>(row, &wx[..e], &wy[..e], &wz[..e]);
        wx[i] = (wx[i] - d[0]) * dinv[i];
        wy[i] = (wy[i] - d[1]) * dinv[i];
        wz[i] = (wz[i] - d[2]) * dinv[i];
    }
    for i in (0..m).rev() {
        let b = (i + 1) / 8 * 8;
        let row = &lt32[i * s + b..(i + 1) * s];
        let d = dot3_o::<O>(row, &wx[b..], &wy[b..], &wz[b..]);
        wx[i] = (wx[i] - d[0]) * dinv[i];
        wy[i] = (wy[i] - d[1]) * dinv[i];
        wz[i] = (wz[i] - d[2]) * dinv[i];
    }
    for (c, wc) in [&*wx, &*wy, &*wz].into_iter().enumerate() {
        for (a, b) in x[c * stride + off..c * stride + off + m].iter_mut().zip(wc) {
            *a = f64::from(*b);
        }
    }
}

/// Three single-precision dot products of `a` with `b0`, `b1`, `b2` sharing the loads of `a`:
/// eight lanes each, then the fixed `Oct::sum` and a plain tail, the same order on every target.
#[inline(always)]
fn dot3_o<O: Oct>(a: &[f32], b0: &[f32], b1: &[f32], b2: &[f32]) -> [f32; 3] {
    let n = a.len().min(b0.len()).min(b1.len()).min(b2.len());
    let c = n / 8 * 8;
    fn octs(s: &[f32], c: usize) -> &[[f32; 8]] {
        s[..c].as_chunks::<8>().0
    }
    let mut acc = [O::zero(); 3];
    for (x, ((y0, y1), y2)) in octs(a, c)
        .iter()
        .zip(octs(b0, c).iter().zip(octs(b1, c)).zip(octs(b2, c)))
    {
        let xl = O::load(x);
        acc[0] = acc[0].add(xl.mul(O::load(y0)));
        acc[1] = acc[1].add(xl.mul(O::load(y1)));
        acc[2] = acc[2].add(xl.mul(O::load(y2)));
    }
    let mut s = [acc[0].sum(), acc[1].sum(), acc[2].sum()];
    for (k, x) in a.iter().enumerate().take(n).skip(c) {
        s[0] += x * b0[k];
        s[1] += x * b1[k];
        s[2] += x * b2[k];
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deform::dense::cholesky_in_place;
    use crate::deform::lanes::{portable, Pair, Pair32};
    use crate::spatial::testutil::{random_spd, SplitMix64};

    fn bits(v: &[f64]) -> Vec<u64> {
        v.iter().map(|x| x.to_bits()).collect()
    }

    /// A random SPD m x m matrix (row-major, full).
    fn spd(rng: &mut SplitMix64, m: usize) -> Vec<f64> {
        random_spd(rng, m).1
    }

    #[test]
    fn matvec_and_solve_match_plain_arithmetic_and_give_the_same_bits_in_every_lane_width() {
        let mut rng = SplitMix64::new(11);
        for n in [1, 3, 8, 9, 17, 64, 101] {
            let a = spd(&mut rng, n);
            let mut lower = a.clone();
            for i in 0..n {
                for j in i + 1..n {
                    lower[i * n + j] = 7.0; // garbage above the diagonal, as after a fit
                }
            }
            let mut plain = lower.clone();
            mirror_lower(&mut lower, n);
            assert_eq!(lower, a, "n {n}: mirror");
            mirror_lower_from(&mut plain, n, 0);
            assert_eq!(plain, a, "n {n}: plain mirror");
            let u: Vec<f64> = (0..3 * n).map(|_| rng.range(-1.0, 1.0)).collect();
            let mut y = vec![0.0; 3 * n];
            matvec3(&a, n, &u, &mut y);
            let mut y2 = vec![0.0; 3 * n];
            matvec3_q::<Pair<portable::F2>>(&a, n, &u, &mut y2);
            assert_eq!(bits(&y), bits(&y2), "n {n}: matvec lanes");
            // Rows in pairs: the bits of one row at a time.
            for i in 0..n {
                let d = dot3_q::<Q2>(&a[i * n..(i + 1) * n], &u[..n], &u[n..2 * n], &u[2 * n..]);
                for (c, dc) in d.iter().enumerate() {
                    assert_eq!(y[c * n + i].to_bits(), dc.to_bits(), "n {n}: row {i}");
                }
            }
            for c in 0..3 {
                for i in 0..n {
                    let want: f64 = (0..n).map(|j| a[i * n + j] * u[c * n + j]).sum();
                    assert!((y[c * n + i] - want).abs() < 1e-12 * n as f64, "n {n}");
                }
            }
            // Solve L L^T x = y for rows of stride n + 2 at offset 2 (the layout of the fits).
            let mut l = a.clone();
            cholesky_in_place(&mut l, n).unwrap();
            let stride = n + 2;
            let mut x = vec![0.0; 3 * stride];
            for c in 0..3 {
                x[c * stride + 2..(c + 1) * stride].copy_from_slice(&y[c * n..(c + 1) * n]);
            }
            let mut x2 = x.clone();
            let x0 = x.clone();
            chol_solve3(&l, n, &mut x, stride, 2);
            chol_solve3_q::<Pair<portable::F2>>(&l, n, &mut x2, stride, 2);
            assert_eq!(bits(&x), bits(&x2), "n {n}: solve lanes");
            let s = f32_stride(n);
            let (mut l32, mut lt32) = (vec![7.0f32; n * s], vec![7.0f32; n * s]);
            let mut dinv = vec![0.0f32; n];
            factor_to_f32(&l, &mut l32, &mut lt32, &mut dinv, n);
            let mut w = vec![f32::NAN; 3 * s];
            let (mut x5, mut x6) = (x0.clone(), x0.clone());
            precondition3_f32(&l32, &lt32, &dinv, n, &mut x5, stride, 2, &mut w);
            precondition3_f32_o::<Pair32<portable::F4>>(
                &l32, &lt32, &dinv, n, &mut x6, stride, 2, &mut w,
            );
            assert_eq!(bits(&x5), bits(&x6), "n {n}: f32 preconditioner lanes");
            #[cfg(target_arch = "x86_64")]
            {
                let mut x7 = x0.clone();
                precondition3_f32_o::<O4>(&l32, &lt32, &dinv, n, &mut x7, stride, 2, &mut w);
                assert_eq!(bits(&x5), bits(&x7), "n {n}: f32 preconditioner SSE");
            }
            // Single precision: within 1e-5 relative of the f64 solve (these matrices have
            // condition numbers of a few), and untouched outside the unknowns.
            let scale = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for (k, (a, b)) in x5.iter().zip(&x).enumerate() {
                if k % stride < 2 {
                    assert_eq!(a.to_bits(), x0[k].to_bits());
                } else {
                    assert!((a - b).abs() < 1e-5 * scale, "n {n}: f32 {a} vs {b}");
                }
            }
            for c in 0..3 {
                for i in 0..n {
                    let got = x[c * stride + 2 + i];
                    assert!(
                        (got - u[c * n + i]).abs() < 1e-10,
                        "n {n}: {got} vs {}",
                        u[c * n + i]
                    );
                }
            }
        }
    }

    #[test]
    fn q_and_q_transpose_are_inverse_orthogonal_maps() {
        let mut rng = SplitMix64::new(12);
        let n = 37;
        // Four unit-ish reflectors, row k zero before k, beta = 2 / |v|^2.
        let mut hv = vec![0.0; 4 * n];
        let mut hbeta = [0.0; 4];
        for k in 0..4 {
            for i in k..n {
                hv[k * n + i] = rng.range(-1.0, 1.0);
            }
            let vv: f64 = hv[k * n..(k + 1) * n].iter().map(|x| x * x).sum();
            hbeta[k] = 2.0 / vv;
        }
        let x: Vec<f64> = (0..n).map(|_| rng.range(-1.0, 1.0)).collect();
        let mut y = x.clone();
        apply_q(&hv, &hbeta, n, &mut y);
        let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
        assert!((norm(&y) - norm(&x)).abs() < 1e-13);
        assert!(y.iter().zip(&x).any(|(a, b)| (a - b).abs() > 1e-3));
        apply_qt(&hv, &hbeta, n, &mut y);
        for (a, b) in y.iter().zip(&x) {
            assert!((a - b).abs() < 1e-14);
        }
        // The projected product: the same bits through every lane width.
        let k: Vec<f64> = (0..n * n).map(|_| rng.range(-1.0, 1.0)).collect();
        let v: Vec<f64> = (0..3 * n).map(|_| rng.range(-1.0, 1.0)).collect();
        let (mut u, mut p1, mut p2) = (vec![0.0; 3 * n], vec![0.0; 3 * n], vec![0.0; 3 * n]);
        projected_matvec(&k, &hv, &hbeta, n, &v, &mut u, &mut p1);
        projected_matvec_q::<Pair<portable::F2>>(&k, &hv, &hbeta, n, &v, &mut u, &mut p2);
        assert_eq!(bits(&p1), bits(&p2));
    }
}
