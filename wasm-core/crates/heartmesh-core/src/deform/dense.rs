//! Small dense linear algebra for the thin-plate-spline solve: a register-blocked Cholesky
//! factorisation and the dot / axpy kernels it and the projection use.
//!
//! Reference: G. H. Golub & C. F. Van Loan, "Matrix Computations", 4th ed. 2013, section 4.2
//! (Cholesky, dot-product form) and 1.5 (register blocking). Why hand-written: nalgebra's
//! Cholesky allocates and was 1.5x slower in wasm, faer the slowest in wasm
//! (PERFORMANCE.md); the sizes here (N ~ 150-400) fit in L2, where blocking for registers is what
//! matters. All sums run in a fixed lane order (`lanes.rs`), so every target gives the same bits.

#[cfg(target_arch = "x86_64")]
use super::lanes::avx::{self, Avx, Avx32};
use super::lanes::{Real, Vector, O4, Q2};
use crate::error::{CoreError, Result};

/// Cholesky factorisation A = L L^T of the lower triangle of an m x m row-major matrix, in place.
///
/// Dot-product (Crout) form, register-blocked two rows by two columns: the four dot products of
/// rows (i, i+1) with rows (j, j+1) share their loads, which halves the memory traffic that bounds
/// the plain form (about N^3 / 6 loads from L2). Every entry's arithmetic is fixed, so results are
/// reproducible.
///
/// Natively on a CPU with AVX the same arithmetic runs four lanes per instruction (same bits).
#[inline(never)] // one call per fit: kept out of line for profiles
pub(super) fn cholesky_in_place(a: &mut [f64], m: usize) -> Result<()> {
    #[cfg(target_arch = "x86_64")]
    if avx::available() {
        // SAFETY: the CPU has AVX.
        return unsafe { cholesky_avx(a, m) };
    }
    cholesky_q::<Q2>(a, m)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn cholesky_avx(a: &mut [f64], m: usize) -> Result<()> {
    cholesky_q::<Avx>(a, m)
}

/// Row stride of the padded f32 factor of [`cholesky32_in_place`]: m rounded up to whole
/// eight-lane vectors.
pub(super) fn padded_stride(m: usize) -> usize {
    m.div_ceil(8) * 8
}

/// [`cholesky_in_place`] in single precision (eight f32 lanes): the factor of the mixed-precision
/// solve, which refines its solutions against the f64 matrix (`tps.rs`). Same bits on every
/// target.
///
/// Layout (why: no scalar tails): `a` is m rows of `padded_stride(m)` holding the strictly lower
/// triangle, zeros elsewhere (the caller zeroes the diagonal and upper part); `diag` holds the
/// diagonal, A's on entry, L's on return. With the diagonal kept out of the rows, every entry of a
/// finished row j at or beyond column j is zero, so the 2 x 2 blocked dot products of the rows
/// run over whole vectors (rounded up past j) and add only exact zeros: at this size the scalar
/// tails and the per-entry overhead cost as much as the vector work.
#[inline(never)] // one call per fit: kept out of line for profiles
pub(super) fn cholesky32_in_place(a: &mut [f32], diag: &mut [f32], m: usize) -> Result<()> {
    #[cfg(target_arch = "x86_64")]
    if avx::available() {
        // SAFETY: the CPU has AVX.
        return unsafe { cholesky32_avx(a, diag, m) };
    }
    cholesky_padded::<O4>(a, diag, m)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn cholesky32_avx(a: &mut [f32], diag: &mut [f32], m: usize) -> Result<()> {
    cholesky_padded::<Avx32>(a, diag, m)
}

/// The padded layout of [`cholesky32_in_place`] over any lane vector.
#[inline(always)]
fn cholesky_padded<Q: Vector>(a: &mut [Q::E], diag: &mut [Q::E], m: usize) -> Result<()> {
    let w = lane_count::<Q>();
    let p = m.div_ceil(w) * w;
    let up = |k: usize| k.div_ceil(w) * w;
    let zero = Q::E::ZERO;
    let mut i = 0;
    while i < m {
        let two = i + 1 < m;
        let (done, rest) = a.split_at_mut(i * p);
        let (ri, rest) = rest.split_at_mut(p);
        let ri1: &mut [Q::E] = if two { &mut rest[..p] } else { &mut [] };
        let mut j = 0;
        while j + 1 < i {
            let (rj, rj1) = (&done[j * p..(j + 1) * p], &done[(j + 1) * p..(j + 2) * p]);
            // Column j of rows i, i+1 is being replaced: zero it so the padded dot products
            // (which reach column j) add nothing there.
            let aij = ri[j];
            ri[j] = zero;
            let ai1j = if two { ri1[j] } else { zero };
            if two {
                ri1[j] = zero;
            }
            let c = up(j);
            // The last row of an odd m pairs with itself (its second results are unused).
            let r1: &[Q::E] = if two { &ri1[..c] } else { &ri[..c] };
            let [d00, d01, d10, d11] = dot2x2::<Q>(&ri[..c], r1, &rj[..c], &rj1[..c]);
            let (ljj, lj1j, lj1j1) = (diag[j], rj1[j], diag[j + 1]);
            let x00 = (aij - d00) / ljj;
            ri[j + 1] = (ri[j + 1] - d01 - x00 * lj1j) / lj1j1;
            ri[j] = x00;
            if two {
                let x10 = (ai1j - d10) / ljj;
                ri1[j + 1] = (ri1[j + 1] - d11 - x10 * lj1j) / lj1j1;
                ri1[j] = x10;
            }
            j += 2;
        }
        if j < i {
            let rj = &done[j * p..j * p + j];
            ri[j] = (ri[j] - dot_q::<Q>(&ri[..j], rj)) / diag[j];
            if two {
                ri1[j] = (ri1[j] - dot_q::<Q>(&ri1[..j], rj)) / diag[j];
            }
        }
        // Diagonal block.
        let lii = pivot(diag[i] - dot_q::<Q>(&ri[..i], &ri[..i]), i)?;
        diag[i] = lii;
        if two {
            ri1[i] = (ri1[i] - dot_q::<Q>(&ri1[..i], &ri[..i])) / lii;
            diag[i + 1] = pivot(
                diag[i + 1] - dot_q::<Q>(&ri1[..i + 1], &ri1[..i + 1]),
                i + 1,
            )?;
        }
        i += 2;
    }
    Ok(())
}

/// The blocked Cholesky over any lane vector (f64 or f32 elements).
#[inline(always)]
fn cholesky_q<Q: Vector>(a: &mut [Q::E], m: usize) -> Result<()> {
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
fn pivot<E: Real>(d: E, i: usize) -> Result<E> {
    if d > E::ZERO && d.is_finite() {
        Ok(d.sqrt())
    } else {
        Err(CoreError::Numerical(format!(
            "TPS: projected system is not positive definite (pivot {i} = {d:e})"
        )))
    }
}

/// The four dot products of (a0, a1) with (b0, b1), one lane vector each, all slices of one length.
#[inline(always)]
fn dot2x2<Q: Vector>(a0: &[Q::E], a1: &[Q::E], b0: &[Q::E], b1: &[Q::E]) -> [Q::E; 4] {
    let n = a0.len().min(a1.len()).min(b0.len()).min(b1.len());
    let c = n - n % lane_count::<Q>();
    let mut acc = [Q::zero(); 4]; // a0.b0, a0.b1, a1.b0, a1.b1
    for ((x0, x1), (y0, y1)) in Q::blocks(&a0[..c])
        .iter()
        .zip(Q::blocks(&a1[..c]))
        .zip(Q::blocks(&b0[..c]).iter().zip(Q::blocks(&b1[..c])))
    {
        let (x0, x1) = (Q::load_block(x0), Q::load_block(x1));
        let (y0, y1) = (Q::load_block(y0), Q::load_block(y1));
        acc[0] = acc[0].vadd(x0.vmul(y0));
        acc[1] = acc[1].vadd(x0.vmul(y1));
        acc[2] = acc[2].vadd(x1.vmul(y0));
        acc[3] = acc[3].vadd(x1.vmul(y1));
    }
    let mut out = acc.map(Q::total);
    for k in c..n {
        out[0] += a0[k] * b0[k];
        out[1] += a0[k] * b1[k];
        out[2] += a1[k] * b0[k];
        out[3] += a1[k] * b1[k];
    }
    out
}

/// Lanes of a vector type (4 for f64, 8 for f32).
#[inline(always)]
fn lane_count<Q: Vector>() -> usize {
    size_of::<Q::Block>() / size_of::<Q::E>()
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

/// [`dot`] over any lane vector: two vector accumulators (hiding the add latency) summed in a
/// fixed order, so each vector type gives the same bits on every target.
#[inline(always)]
pub(super) fn dot_q<Q: Vector>(a: &[Q::E], b: &[Q::E]) -> Q::E {
    let n = a.len().min(b.len());
    let c = n - n % (2 * lane_count::<Q>());
    let (pa, pb) = (Q::blocks(&a[..c]), Q::blocks(&b[..c]));
    let mut acc = [Q::zero(); 2];
    for (x, y) in pa.chunks_exact(2).zip(pb.chunks_exact(2)) {
        for l in 0..2 {
            acc[l] = acc[l].vadd(Q::load_block(&x[l]).vmul(Q::load_block(&y[l])));
        }
    }
    let mut s = acc[0].total() + acc[1].total();
    for (x, y) in a[c..n].iter().zip(&b[c..n]) {
        s += *x * *y;
    }
    s
}

/// Three [`dot_q`]s of `a` with `b0`, `b1`, `b2` sharing the loads of `a`; each result has the
/// bits of its own `dot_q`.
#[inline(always)]
pub(super) fn dot3_q<Q: Vector>(a: &[Q::E], b0: &[Q::E], b1: &[Q::E], b2: &[Q::E]) -> [Q::E; 3] {
    let n = a.len().min(b0.len()).min(b1.len()).min(b2.len());
    let c = n - n % (2 * lane_count::<Q>());
    let (pa, p0, p1, p2) = (
        Q::blocks(&a[..c]),
        Q::blocks(&b0[..c]),
        Q::blocks(&b1[..c]),
        Q::blocks(&b2[..c]),
    );
    let mut acc = [[Q::zero(); 2]; 3];
    for (x, ((y0, y1), y2)) in pa.chunks_exact(2).zip(
        p0.chunks_exact(2)
            .zip(p1.chunks_exact(2))
            .zip(p2.chunks_exact(2)),
    ) {
        for l in 0..2 {
            let xl = Q::load_block(&x[l]);
            acc[0][l] = acc[0][l].vadd(xl.vmul(Q::load_block(&y0[l])));
            acc[1][l] = acc[1][l].vadd(xl.vmul(Q::load_block(&y1[l])));
            acc[2][l] = acc[2][l].vadd(xl.vmul(Q::load_block(&y2[l])));
        }
    }
    let mut s = acc.map(|a| a[0].total() + a[1].total());
    for (k, x) in a.iter().enumerate().take(n).skip(c) {
        s[0] += *x * b0[k];
        s[1] += *x * b1[k];
        s[2] += *x * b2[k];
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
    use crate::spatial::testutil::SplitMix64;

    /// The dispatched factorisation (AVX when the CPU has it) and the two-lane and portable
    /// kernels give the same bits, so native results equal wasm's.
    #[test]
    fn every_lane_width_gives_the_same_bits() {
        use crate::deform::lanes::{portable, Pair};
        let mut rng = SplitMix64::new(7);
        for m in [1, 2, 3, 7, 8, 9, 33, 64, 101] {
            let b: Vec<f64> = (0..m * m).map(|_| rng.range(-1.0, 1.0)).collect();
            let mut a = vec![0.0; m * m];
            for i in 0..m {
                for j in 0..m {
                    let s: f64 = (0..m).map(|k| b[i * m + k] * b[j * m + k]).sum();
                    a[i * m + j] = s + if i == j { m as f64 } else { 0.0 };
                }
            }
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
            if super::avx::available() {
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

    /// The padded f32 factor: L L^T reproduces A to f32 accuracy, for even and odd sizes, and the
    /// dispatched (AVX natively), target and portable lanes give the same bits.
    #[test]
    fn padded_f32_cholesky_factors_and_gives_the_same_bits() {
        use crate::deform::lanes::{portable, Pair32};
        let mut rng = SplitMix64::new(17);
        for m in [1, 2, 3, 7, 8, 9, 16, 17, 33, 64, 101] {
            let b: Vec<f64> = (0..m * m).map(|_| rng.range(-1.0, 1.0)).collect();
            let a = |i: usize, j: usize| {
                let s: f64 = (0..m).map(|k| b[i * m + k] * b[j * m + k]).sum();
                s + if i == j { m as f64 } else { 0.0 }
            };
            let p = padded_stride(m);
            let mut l = vec![7.0f32; m * p]; // garbage that the layout must overwrite
            let mut d = vec![0.0f32; m];
            for i in 0..m {
                for j in 0..p {
                    l[i * p + j] = if j < i { a(i, j) as f32 } else { 0.0 };
                }
                d[i] = a(i, i) as f32;
            }
            let (mut l2, mut d2, mut l3, mut d3) = (l.clone(), d.clone(), l.clone(), d.clone());
            cholesky32_in_place(&mut l, &mut d, m).unwrap();
            cholesky_padded::<O4>(&mut l2, &mut d2, m).unwrap();
            cholesky_padded::<Pair32<portable::F4>>(&mut l3, &mut d3, m).unwrap();
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!((bits(&l), bits(&d)), (bits(&l2), bits(&d2)), "m {m}");
            assert_eq!((bits(&l), bits(&d)), (bits(&l3), bits(&d3)), "m {m}");
            let lij = |i: usize, j: usize| -> f64 {
                match i.cmp(&j) {
                    std::cmp::Ordering::Greater => f64::from(l[i * p + j]),
                    std::cmp::Ordering::Equal => f64::from(d[i]),
                    std::cmp::Ordering::Less => 0.0,
                }
            };
            for i in 0..m {
                assert!(l[i * p + i..(i + 1) * p].iter().all(|x| *x == 0.0));
                for j in 0..=i {
                    let s: f64 = (0..=j).map(|k| lij(i, k) * lij(j, k)).sum();
                    let want = a(i, j);
                    assert!(
                        (s - want).abs() <= 1e-5 * m as f64,
                        "m {m} ({i},{j}): {s} vs {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn blocked_cholesky_equals_the_plain_one() {
        let mut rng = SplitMix64::new(6);
        for m in [1, 2, 3, 4, 5, 8, 9, 37, 64] {
            // SPD: B B^T + m I.
            let b: Vec<f64> = (0..m * m).map(|_| rng.range(-1.0, 1.0)).collect();
            let mut a = vec![0.0; m * m];
            for i in 0..m {
                for j in 0..m {
                    let s: f64 = (0..m).map(|k| b[i * m + k] * b[j * m + k]).sum();
                    a[i * m + j] = s + if i == j { m as f64 } else { 0.0 };
                }
            }
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
