//! Many umbrella-smoothing sweeps as one truncated Chebyshev polynomial in the umbrella operator.
//!
//! References: G. Taubin, "A signal processing approach to fair surface design", SIGGRAPH 1995
//! (smoothing as a polynomial transfer function of the umbrella operator); L. N. Trefethen,
//! "Approximation Theory and Approximation Practice", SIAM 2013 (Chebyshev expansions, their
//! coefficient decay and Clenshaw's recurrence, chapters 3 and 7); C. W. Clenshaw, "A note on the
//! summation of Chebyshev series", MTAC 9, 1955.
//!
//! Why: a sweep is linear, x <- ((1 - f) I + f W) x with W the row-stochastic umbrella (interior:
//! the one-ring mean; open-boundary vertices: the mean of their two boundary neighbours; fixed
//! vertices: identity). n sweeps apply g(W) = prod_i ((1 - f_i) + f_i W), a polynomial of degree
//! n. W's spectrum is real and inside [-1, 1]: on a closed mesh W = D^-1 A is similar to the
//! symmetric D^-1/2 A D^-1/2; with boundaries W is block triangular (fixed rows are identity
//! rows, boundary rows reference only boundary vertices), each diagonal block again similar to a
//! symmetric one. On [-1, 1] the smoothing polynomial is very smooth (for f = 0.1, n = 200 it
//! falls from 1 at t = 1 to 0.8^200 ~ 4e-20 at t = -1), so its Chebyshev series converges fast and
//! a truncation of degree d << n reproduces it to rounding: 35 instead of 200 matrix products
//! (Taubin's lambda/mu pairs at lambda = 0.1: 20).
//!
//! Error bound. With p_d the truncation, |g(t) - p_d(t)| <= tail(d) = sum_{k>d} |c_k| on
//! [-1, 1]. For a diagonalisable W = V L V^-1 the positions then differ by at most
//! kappa(V) tail(d) |x|. On a closed mesh V = D^-1/2 Q (Q orthogonal), so kappa(V) =
//! sqrt(max degree / min degree): sqrt(12 / 3) = 2 at worst for a remeshed surface, about
//! sqrt(7 / 5) in practice. With boundaries W is not normal; the tests measure the difference on
//! an open tube instead of bounding it. The pipeline smooths in its normalised units (centred
//! contour points, divided by their diameter, ~100 mm), where |x| <= 1; the positions are also
//! centred here, so [`TOLERANCE`] = 1e-13 is ~1e-11 mm, far below anything decimation or the
//! measures resolve (the tests see <= 1e-12 of the shape's size).
//!
//! Stability. The coefficients come from an exact-order recurrence (multiplying the Chebyshev
//! series by one linear factor at a time: T_1 T_k = (T_{k+1} + T_{k-1}) / 2), no cosines, so every
//! target computes the same bits; for the Laplacian factors every term is positive and the
//! relative error is ~n eps. Clenshaw's recurrence on [-1, 1] amplifies rounding by at most
//! O(d^2) (Trefethen ch. 7 notes O(d) in practice): with d = 37 and |c| summing to 1, ~1e-13
//! relative, below the tests' 1e-9.

use std::sync::{Arc, Mutex};

/// Truncation tolerance on the coefficient tail, relative to the (centred) positions.
pub const TOLERANCE: f64 = 1e-13;

/// One Clenshaw step costs about this many direct sweeps: it executes about as many instructions
/// (callgrind on the SurFCo run: 107 k per step against 102 k per sweep) but streams three
/// vectors where a sweep streams one. Measured natively (`REFINE_BENCH_MIN=15 cargo bench
/// --bench refine`, 10 k vertices): 200 sweeps 12.5 ms, the degree-35 series 3.0 ms, so
/// 0.063 ms per sweep and 0.084 ms per step, a ratio of 1.35.
pub const STEP_COST: f64 = 1.4;

/// Chebyshev coefficients c_0..c_n of prod_{i < n} ((1 - f_i) + f_i t), step i with
/// f_i = `factors[i % len]`, as p(t) = sum c_k T_k(t) (c_0 taken whole).
///
/// Plain f64 products and sums in a fixed order: the same bits on every target.
pub fn smoothing_coefficients(factors: &[f64], iterations: usize) -> Vec<f64> {
    let mut c = vec![0.0; iterations + 2];
    c[0] = 1.0;
    let mut next = vec![0.0; iterations + 2];
    // Factors commute: apply them in the sweeps' order anyway, which for Taubin's lambda/mu
    // alternation keeps the partial products (and so their coefficients) near 1 in size.
    for i in 0..iterations {
        let f = factors[i % factors.len()];
        let (a, b) = (1.0 - f, f);
        // Degree after this factor: i + 1.
        for k in 0..=i + 1 {
            // T_1 * sum_j c_j T_j: c_0 goes whole to T_1, c_j (j >= 1) half to T_{j+1}, half to
            // T_{j-1}.
            let from_below = match k {
                0 => 0.0,
                1 => c[0],
                _ => 0.5 * c[k - 1],
            };
            let from_above = 0.5 * c[k + 1];
            next[k] = a * c[k] + b * (from_below + from_above);
        }
        std::mem::swap(&mut c, &mut next);
    }
    c.truncate(iterations + 1);
    c
}

/// The truncated series for these sweeps: [`smoothing_coefficients`] cut at
/// [`truncation_degree`]. The last answer is remembered: the pipeline asks the same question at
/// every remesh, and the O(n^2) recurrence (~0.65 M instructions at n = 200) is then skipped.
pub fn truncated_series(factors: &[f64], iterations: usize) -> Arc<Vec<f64>> {
    type Entry = (Vec<u64>, usize, Arc<Vec<f64>>);
    static LAST: Mutex<Option<Entry>> = Mutex::new(None);
    let key: Vec<u64> = factors.iter().map(|f| f.to_bits()).collect();
    // A poisoned lock only means another thread panicked mid-update: recompute then.
    if let Ok(last) = LAST.lock() {
        if let Some((k, n, c)) = last.as_ref() {
            if *k == key && *n == iterations {
                return Arc::clone(c);
            }
        }
    }
    let mut c = smoothing_coefficients(factors, iterations);
    c.truncate(truncation_degree(&c, TOLERANCE) + 1);
    let c = Arc::new(c);
    if let Ok(mut last) = LAST.lock() {
        *last = Some((key, iterations, Arc::clone(&c)));
    }
    c
}

/// Smallest degree d whose tail sum_{k>d} |c_k| is at most `tolerance`.
pub fn truncation_degree(c: &[f64], tolerance: f64) -> usize {
    let mut tail = 0.0;
    for d in (0..c.len()).rev() {
        let with = tail + c[d].abs();
        if with > tolerance {
            return d;
        }
        tail = with;
    }
    0
}

/// Whether the Chebyshev form with `degree` steps is clearly cheaper than `iterations` sweeps.
pub fn worth_it(degree: usize, iterations: usize) -> bool {
    (degree + 1) as f64 * STEP_COST < 0.8 * iterations as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Chebyshev series by Clenshaw, scalar.
    fn eval(c: &[f64], t: f64) -> f64 {
        let (mut b1, mut b2) = (0.0, 0.0);
        for k in (1..c.len()).rev() {
            let b = c[k] + 2.0 * t * b1 - b2;
            b2 = b1;
            b1 = b;
        }
        c[0] + t * b1 - b2
    }

    fn direct(factors: &[f64], n: usize, t: f64) -> f64 {
        (0..n).fold(1.0, |p, i| {
            let f = factors[i % factors.len()];
            p * ((1.0 - f) + f * t)
        })
    }

    #[test]
    fn coefficients_reproduce_the_product() {
        for (factors, n) in [
            (vec![0.1], 200usize),
            (vec![0.3], 7),
            (vec![0.1, crate::refine::smooth::taubin_mu(0.1)], 200),
            (vec![1.0], 3),
        ] {
            let c = smoothing_coefficients(&factors, n);
            assert_eq!(c.len(), n + 1);
            for j in 0..=40 {
                let t = -1.0 + j as f64 / 20.0;
                let (p, g) = (eval(&c, t), direct(&factors, n, t));
                assert!((p - g).abs() < 1e-13, "{factors:?} n {n} t {t}: {p} vs {g}");
            }
        }
        // (0.5 + 0.5 t)^2 = 3/8 + T_1 / 2 + T_2 / 8.
        let c = smoothing_coefficients(&[0.5], 2);
        assert_eq!(c, vec![0.375, 0.5, 0.125]);
    }

    #[test]
    fn degrees_at_the_tolerance() {
        // The degrees the sweep counts reduce to (the tail bounds the error on [-1, 1]).
        let d = |f: f64, n: usize| truncation_degree(&smoothing_coefficients(&[f], n), TOLERANCE);
        assert_eq!(d(0.1, 200), 35);
        assert_eq!(d(0.1, 50), 19);
        assert_eq!(d(0.3, 200), 58);
        // Gentler steps decay faster in t: (0.99 + 0.01 t)^200 ~ exp(-2 (1 - t)).
        assert_eq!(d(0.01, 200), 15);
        // t^200 (f = 1): the binomial coefficients of t^n are a Gaussian of width ~sqrt(n).
        assert_eq!(d(1.0, 200), 102);
        // Taubin lambda/mu (0.1, -0.101), 100 pairs: the pass-band filter is smooth too.
        let taubin = [0.1, crate::refine::smooth::taubin_mu(0.1)];
        let c = smoothing_coefficients(&taubin, 200);
        assert_eq!(truncation_degree(&c, TOLERANCE), 20);
        assert!(worth_it(d(0.1, 200), 200));
        assert!(!worth_it(d(0.1, 10), 10));
        // The remembered series follows its arguments.
        for (f, n, len) in [
            (0.1, 200, 36),
            (0.1, 50, 20),
            (0.1, 200, 36),
            (0.3, 200, 59),
        ] {
            let c = truncated_series(&[f], n);
            assert_eq!(c.len(), len);
            assert_eq!(c[0], smoothing_coefficients(&[f], n)[0]);
        }
        // Truncated at d, the series is within the tolerance of the product everywhere.
        let c = smoothing_coefficients(&[0.1], 200);
        let deg = d(0.1, 200);
        for j in 0..=200 {
            let t = -1.0 + j as f64 / 100.0;
            let err = (eval(&c[..=deg], t) - direct(&[0.1], 200, t)).abs();
            assert!(err <= TOLERANCE + 1e-15, "t {t}: {err}");
        }
    }
}
