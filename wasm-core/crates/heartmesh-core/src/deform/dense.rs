//! Small dense linear algebra for the thin-plate-spline solve: a register-blocked Cholesky
//! factorisation and the dot / axpy kernels it and the projection use.
//!
//! Reference: G. H. Golub & C. F. Van Loan, "Matrix Computations", 4th ed. 2013, section 4.2
//! (Cholesky, dot-product form) and 1.5 (register blocking). Why hand-written: nalgebra's
//! Cholesky allocates and was 1.5x slower in wasm, faer the slowest in wasm
//! (PERFORMANCE.md); the sizes here (N ~ 150-400) fit in L2, where blocking for registers is what
//! matters. All sums run in a fixed lane order (`lanes/`), so every target gives the same bits.

#[cfg(target_arch = "x86_64")]
use super::lanes::avx::Avx;
use super::lanes::{avx_dispatch, Quad, Q2};
use crate::error::{CoreError, Result};

avx_dispatch! {
    /// Cholesky factorisation A = L L^T of the lower triangle of an m x m row-major matrix, in
    /// place.
    ///
    /// Dot-product (Crout) form, register-blocked two rows by two columns: the four dot products
    /// of rows (i, i+1) with rows (j, j+1) share their loads, which halves the memory traffic that
    /// bounds the plain form (about N^3 / 6 loads from L2). Every entry's arithmetic is fixed, so
    /// results are reproducible.
    ///
    /// Natively on a CPU with AVX the same arithmetic runs four lanes per instruction (same bits).
    #[inline(never)] // one call per fit: kept out of line for profiles
    pub(super) fn cholesky_in_place / cholesky_avx (a: &mut [f64], m: usize) -> Result<()>
        = cholesky_q::<Q2, Avx>;
}

#[inline(always)]
fn cholesky_q<Q: Quad>(a: &mut [f64], m: usize) -> Result<()> {
    let mut i = 0;
    while i + 1 < m {
        let (done, rest) = a.split_at_mut(i * m);
        let (ri, rest) = rest.split_at_mut(m);
        let ri = &mut ri[..i + 1];
        let ri1 = &mut rest[..i + 2];
        let mut j = 0;
        while j + 1 < i {
            let rj = &done[j * m..j * m + j + 1];
            let rj1 = &done[(j + 1) * m..(j + 1) * m + j + 2];
            let [d00, d01, d10, d11] = dot2x2::<Q>(&ri[..j], &ri1[..j], &rj[..j], &rj1[..j]);
            let (ljj, lj1j, lj1j1) = (rj[j], rj1[j], rj1[j + 1]);
            let x00 = (ri[j] - d00) / ljj;
            let x10 = (ri1[j] - d10) / ljj;
            ri[j + 1] = (ri[j + 1] - d01 - x00 * lj1j) / lj1j1;
            ri1[j + 1] = (ri1[j + 1] - d11 - x10 * lj1j) / lj1j1;
            ri[j] = x00;
            ri1[j] = x10;
            j += 2;
        }
        if j < i {
            let rj = &done[j * m..j * m + j + 1];
            ri[j] = (ri[j] - dot_q::<Q>(&ri[..j], &rj[..j])) / rj[j];
            ri1[j] = (ri1[j] - dot_q::<Q>(&ri1[..j], &rj[..j])) / rj[j];
        }
        // Diagonal 2 x 2 block.
        let lii = pivot(ri[i] - dot_q::<Q>(&ri[..i], &ri[..i]), i)?;
        ri[i] = lii;
        ri1[i] = (ri1[i] - dot_q::<Q>(&ri1[..i], &ri[..i])) / lii;
        ri1[i + 1] = pivot(ri1[i + 1] - dot_q::<Q>(&ri1[..i + 1], &ri1[..i + 1]), i + 1)?;
        i += 2;
    }
    if i < m {
        let (done, rest) = a.split_at_mut(i * m);
        let ri = &mut rest[..i + 1];
        for j in 0..i {
            let rj = &done[j * m..j * m + j + 1];
            ri[j] = (ri[j] - dot_q::<Q>(&ri[..j], &rj[..j])) / rj[j];
        }
        ri[i] = pivot(ri[i] - dot_q::<Q>(&ri[..i], &ri[..i]), i)?;
    }
    Ok(())
}

/// Square root of a Cholesky pivot, or the error that says the system is not SPD.
#[inline]
fn pivot(d: f64, i: usize) -> Result<f64> {
    if d > 0.0 && d.is_finite() {
        Ok(d.sqrt())
    } else {
        Err(CoreError::Numerical(format!(
            "TPS: projected system is not positive definite (pivot {i} = {d:e})"
        )))
    }
}

/// The four dot products of (a0, a1) with (b0, b1), four lanes each, all slices of one length.
#[inline(always)]
fn dot2x2<Q: Quad>(a0: &[f64], a1: &[f64], b0: &[f64], b1: &[f64]) -> [f64; 4] {
    let n = a0.len().min(a1.len()).min(b0.len()).min(b1.len());
    let c = n / 4 * 4;
    fn quads(s: &[f64], c: usize) -> &[[f64; 4]] {
        s[..c].as_chunks::<4>().0
    }
    let mut acc = [Q::zero(); 4]; // a0.b0, a0.b1, a1.b0, a1.b1
    for ((x0, x1), (y0, y1)) in quads(a0, c)
        .iter()
        .zip(quads(a1, c))
        .zip(quads(b0, c).iter().zip(quads(b1, c)))
    {
        let (x0, x1) = (Q::load(x0), Q::load(x1));
        let (y0, y1) = (Q::load(y0), Q::load(y1));
        acc[0] = acc[0].add(x0.mul(y0));
        acc[1] = acc[1].add(x0.mul(y1));
        acc[2] = acc[2].add(x1.mul(y0));
        acc[3] = acc[3].add(x1.mul(y1));
    }
    let mut out = acc.map(Q::sum);
    for k in c..n {
        out[0] += a0[k] * b0[k];
        out[1] += a0[k] * b1[k];
        out[2] += a1[k] * b0[k];
        out[3] += a1[k] * b1[k];
    }
    out
}

#[cfg(test)]
/// The unblocked dot-product Cholesky, kept as the reference of the blocked one.
fn cholesky_reference(a: &mut [f64], m: usize) -> Result<()> {
    for i in 0..m {
        let (done, rest) = a.split_at_mut(i * m);
        let row_i = &mut rest[..i + 1];
        for j in 0..i {
            let row_j = &done[j * m..j * m + j + 1];
            let s = row_i[j] - dot(&row_i[..j], &row_j[..j]);
            row_i[j] = s / row_j[j];
        }
        row_i[i] = pivot(row_i[i] - dot(&row_i[..i], &row_i[..i]), i)?;
    }
    Ok(())
}

/// Dot product in eight lanes (two four-lane accumulators hide the add latency) with a fixed
/// summation order, so results are reproducible on every target.
#[inline]
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    dot_q::<Q2>(a, b)
}

/// [`dot`] over any four-lane vector (same bits with each).
#[inline(always)]
pub(super) fn dot_q<Q: Quad>(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let c = n / 8 * 8;
    let (pa, pb) = (a[..c].as_chunks::<4>().0, b[..c].as_chunks::<4>().0);
    let mut acc = [Q::zero(); 2];
    for (x, y) in pa.chunks_exact(2).zip(pb.chunks_exact(2)) {
        for l in 0..2 {
            acc[l] = acc[l].add(Q::load(&x[l]).mul(Q::load(&y[l])));
        }
    }
    let mut s = acc[0].sum() + acc[1].sum();
    for (x, y) in a[c..n].iter().zip(&b[c..n]) {
        s += x * y;
    }
    s
}

/// [`dot3_q`] of two rows `a0`, `a1` (of one length) with the same `b0`, `b1`, `b2`, sharing the
/// loads of the b's: five loads per eight-element step and row pair instead of eight, and one
/// loop (one hard-to-predict exit) per two rows. Each of the six results has the bits of its own
/// `dot3_q`.
#[inline(always)]
pub(super) fn dot3x2_q<Q: Quad>(
    a0: &[f64],
    a1: &[f64],
    b0: &[f64],
    b1: &[f64],
    b2: &[f64],
) -> [[f64; 3]; 2] {
    let n = a0
        .len()
        .min(a1.len())
        .min(b0.len())
        .min(b1.len())
        .min(b2.len());
    let c = n / 8 * 8;
    fn pairs(s: &[f64], c: usize) -> &[[[f64; 4]; 2]] {
        s[..c].as_chunks::<4>().0.as_chunks::<2>().0
    }
    // acc[row][rhs][half]
    let mut acc = [[[Q::zero(); 2]; 3]; 2];
    for ((x0, x1), ((y0, y1), y2)) in pairs(a0, c)
        .iter()
        .zip(pairs(a1, c))
        .zip(pairs(b0, c).iter().zip(pairs(b1, c)).zip(pairs(b2, c)))
    {
        for l in 0..2 {
            let (p, q) = (Q::load(&x0[l]), Q::load(&x1[l]));
            for (r, y) in [&y0[l], &y1[l], &y2[l]].into_iter().enumerate() {
                let y = Q::load(y);
                acc[0][r][l] = acc[0][r][l].add(p.mul(y));
                acc[1][r][l] = acc[1][r][l].add(q.mul(y));
            }
        }
    }
    let mut s = [
        [
            acc[0][0][0].sum() + acc[0][0][1].sum(),
            acc[0][1][0].sum() + acc[0][1][1].sum(),
            acc[0][2][0].sum() + acc[0][2][1].sum(),
        ],
        [
            acc[1][0][0].sum() + acc[1][0][1].sum(),
            acc[1][1][0].sum() + acc[1][1][1].sum(),
            acc[1][2][0].sum() + acc[1][2][1].sum(),
        ],
    ];
    for k in c..n {
        for (row, a) in [a0, a1].into_iter().enumerate() {
            s[row][0] += a[k] * b0[k];
            s[row][1] += a[k] * b1[k];
            s[row][2] += a[k] * b2[k];
        }
    }
    s
}

/// Three [`dot_q`]s of `a` with `b0`, `b1`, `b2` sharing the loads of `a`; each result has the
/// bits of its own `dot_q`.
#[inline(always)]
pub(super) fn dot3_q<Q: Quad>(a: &[f64], b0: &[f64], b1: &[f64], b2: &[f64]) -> [f64; 3] {
    let n = a.len().min(b0.len()).min(b1.len()).min(b2.len());
    let c = n / 8 * 8;
    fn pairs(s: &[f64], c: usize) -> &[[[f64; 4]; 2]] {
        s[..c].as_chunks::<4>().0.as_chunks::<2>().0
    }
    let mut acc = [[Q::zero(); 2]; 3];
    for (x, ((y0, y1), y2)) in pairs(a, c)
        .iter()
        .zip(pairs(b0, c).iter().zip(pairs(b1, c)).zip(pairs(b2, c)))
    {
        for l in 0..2 {
            let xl = Q::load(&x[l]);
            acc[0][l] = acc[0][l].add(xl.mul(Q::load(&y0[l])));
            acc[1][l] = acc[1][l].add(xl.mul(Q::load(&y1[l])));
            acc[2][l] = acc[2][l].add(xl.mul(Q::load(&y2[l])));
        }
    }
    // Written out: `acc.map(..)` was left as an out-of-line call that spilled the AVX registers.
    let mut s = [
        acc[0][0].sum() + acc[0][1].sum(),
        acc[1][0].sum() + acc[1][1].sum(),
        acc[2][0].sum() + acc[2][1].sum(),
    ];
    for (k, x) in a.iter().enumerate().take(n).skip(c) {
        s[0] += x * b0[k];
        s[1] += x * b1[k];
        s[2] += x * b2[k];
    }
    s
}

/// y += alpha x.
#[inline]
pub(super) fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += alpha * xi;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spatial::testutil::{random_spd, SplitMix64};

    /// The dispatched factorisation (AVX when the CPU has it) and the two-lane and portable
    /// kernels give the same bits, so native results equal wasm's.
    #[test]
    fn every_lane_width_gives_the_same_bits() {
        use crate::deform::lanes::{portable, Pair};
        let mut rng = SplitMix64::new(7);
        for m in [1, 2, 3, 7, 8, 9, 33, 64, 101] {
            let (b, a) = random_spd(&mut rng, m);
            let (mut l1, mut l2, mut l3) = (a.clone(), a.clone(), a.clone());
            cholesky_in_place(&mut l1, m).unwrap();
            cholesky_q::<Q2>(&mut l2, m).unwrap();
            cholesky_q::<Pair<portable::F2>>(&mut l3, m).unwrap();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&l1), bits(&l2), "m {m}");
            assert_eq!(bits(&l1), bits(&l3), "m {m}");
            let (x, y) = (&b[..m * m / 2 + 3.min(m)], &a[..m * m / 2 + 3.min(m)]);
            let d = dot(x, y);
            assert_eq!(d.to_bits(), dot_q::<Pair<portable::F2>>(x, y).to_bits());
            #[cfg(target_arch = "x86_64")]
            if crate::deform::lanes::avx::available() {
                // SAFETY: the CPU has AVX.
                let e = unsafe { dot_avx(x, y) };
                assert_eq!(d.to_bits(), e.to_bits());
            }
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn dot_avx(a: &[f64], b: &[f64]) -> f64 {
        dot_q::<Avx>(a, b)
    }

    #[test]
    fn blocked_cholesky_equals_the_plain_one() {
        let mut rng = SplitMix64::new(6);
        for m in [1, 2, 3, 4, 5, 8, 9, 37, 64] {
            let (_, a) = random_spd(&mut rng, m);
            let (mut l1, mut l2) = (a.clone(), a.clone());
            cholesky_in_place(&mut l1, m).unwrap();
            cholesky_reference(&mut l2, m).unwrap();
            for i in 0..m {
                for j in 0..=i {
                    let (x, y) = (l1[i * m + j], l2[i * m + j]);
                    assert!(
                        (x - y).abs() <= 1e-12 * (1.0 + y.abs()),
                        "m {m} ({i},{j}): {x} {y}"
                    );
                }
                // L L^T reproduces A.
                for j in 0..=i {
                    let s: f64 = (0..=j).map(|k| l1[i * m + k] * l1[j * m + k]).sum();
                    assert!((s - a[i * m + j]).abs() <= 1e-12 * m as f64 * m as f64);
                }
            }
        }
        // Not SPD: an error, not a NaN factor.
        let mut a = vec![1.0, 0.0, 2.0, 1.0];
        assert_eq!(
            cholesky_in_place(&mut a, 2).unwrap_err().code(),
            "numerical"
        );
    }
}
