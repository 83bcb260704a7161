//! The boxes of a BVH node's two children side by side, so one two-lane pass gives both
//! point-to-box distances: SSE2 on x86_64 (baseline), simd128 on wasm32 when enabled, plain
//! arrays elsewhere.
//!
//! Reference: C. Ericson, "Real-Time Collision Detection" 2005, section 5.1.3 (point-AABB
//! distance). Why: the closest-point queries spend most of their instructions deciding which
//! children to visit, and both children are always tested together. The lanes compute
//! max(lo - q, q - hi, 0) per axis, which is the branchy form's value (0 inside, the gap outside),
//! summed x, y, z in the same order; the traversal only prunes with these values (with a margin),
//! so its answer does not depend on their last bit anyway.

/// Child boxes of one inner node, axis-major: `lo[k][c]` is the low bound on axis k of child c.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct PairBoxes {
    pub lo: [[f64; 2]; 3],
    pub hi: [[f64; 2]; 3],
    /// Each child's (start, count) packed as `start | count << 32`, so the traversal never
    /// reads the node array below the root.
    pub range: [u64; 2],
}

impl PairBoxes {
    /// Stores the box of child `c % 2`.
    #[inline(always)]
    pub fn set(&mut self, c: usize, lo: [f64; 3], hi: [f64; 3]) {
        let c = c % 2;
        for k in 0..3 {
            self.lo[k][c] = lo[k];
            self.hi[k][c] = hi[k];
        }
    }

    /// Squared distances from `q` to the two child boxes (0 inside). A NaN coordinate of `q`
    /// gives 0 (every box is visited), as the branchy form does.
    #[inline(always)]
    pub fn distance_sq(&self, q: &[f64; 3]) -> [f64; 2] {
        imp::distance_sq(self, q)
    }
}

#[cfg(target_arch = "x86_64")]
mod imp {
    //! SAFETY (every `unsafe` below): SSE2 is part of the x86_64 baseline; the loads read the
    //! 16 bytes of a `[f64; 2]` and the store writes those of one.
    use super::PairBoxes;
    use core::arch::x86_64::*;

    #[inline(always)]
    pub fn distance_sq(b: &PairBoxes, q: &[f64; 3]) -> [f64; 2] {
        unsafe {
            let zero = _mm_setzero_pd();
            let mut d = zero;
            for (k, &qk) in q.iter().enumerate() {
                let qk = _mm_set1_pd(qk);
                let lo = _mm_loadu_pd(b.lo[k].as_ptr());
                let hi = _mm_loadu_pd(b.hi[k].as_ptr());
                // maxpd returns its second operand when either is NaN: a NaN query gives 0.
                let e = _mm_max_pd(_mm_max_pd(_mm_sub_pd(lo, qk), _mm_sub_pd(qk, hi)), zero);
                d = _mm_add_pd(d, _mm_mul_pd(e, e));
            }
            let mut out = [0.0; 2];
            _mm_storeu_pd(out.as_mut_ptr(), d);
            out
        }
    }
}

#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
mod imp {
    use super::PairBoxes;
    use core::arch::wasm32::*;

    #[inline(always)]
    pub fn distance_sq(b: &PairBoxes, q: &[f64; 3]) -> [f64; 2] {
        let zero = f64x2_splat(0.0);
        let mut d = zero;
        for (k, &qk) in q.iter().enumerate() {
            let qk = f64x2_splat(qk);
            let lo = f64x2(b.lo[k][0], b.lo[k][1]);
            let hi = f64x2(b.hi[k][0], b.hi[k][1]);
            let g = f64x2_pmax(f64x2_sub(lo, qk), f64x2_sub(qk, hi));
            // pmax(a, b) is `a < b ? b : a`: with b = NaN this keeps 0, as on x86.
            let e = f64x2_pmax(zero, g);
            d = f64x2_add(d, f64x2_mul(e, e));
        }
        [f64x2_extract_lane::<0>(d), f64x2_extract_lane::<1>(d)]
    }
}

#[cfg(not(any(
    target_arch = "x86_64",
    all(target_arch = "wasm32", target_feature = "simd128")
)))]
mod imp {
    use super::PairBoxes;

    #[inline(always)]
    pub fn distance_sq(b: &PairBoxes, q: &[f64; 3]) -> [f64; 2] {
        let mut d = [0.0; 2];
        for (k, &qk) in q.iter().enumerate() {
            for (c, dc) in d.iter_mut().enumerate() {
                let g = b.lo[k][c] - qk;
                let h = qk - b.hi[k][c];
                let g = if h > g { h } else { g };
                // `0 < g` is false for NaN: a NaN query gives 0, as on x86.
                let e = if 0.0 < g { g } else { 0.0 };
                *dc += e * e;
            }
        }
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The branchy per-box form the lanes replace.
    fn branchy(lo: [f64; 3], hi: [f64; 3], q: &[f64; 3]) -> f64 {
        let mut d = 0.0;
        for k in 0..3 {
            let e = if q[k] < lo[k] {
                lo[k] - q[k]
            } else if q[k] > hi[k] {
                q[k] - hi[k]
            } else {
                0.0
            };
            d += e * e;
        }
        d
    }

    #[test]
    fn both_lanes_equal_the_branchy_distance() {
        let b = PairBoxes {
            lo: [[0.0, -3.0], [1.0, 2.0], [-1.0, 5.0]],
            hi: [[2.0, -1.0], [4.0, 2.5], [1.0, 9.0]],
            range: [0; 2],
        };
        let queries = [
            [1.0, 2.0, 0.0],   // inside the first box
            [-2.0, 2.25, 6.0], // inside the second
            [3.0, 0.0, -4.0],
            [-7.5, 9.0, 11.0],
            [0.0, 1.0, -1.0], // on a corner of the first
        ];
        for q in queries {
            let got = b.distance_sq(&q);
            for (c, g) in got.iter().enumerate() {
                let lo = [b.lo[0][c], b.lo[1][c], b.lo[2][c]];
                let hi = [b.hi[0][c], b.hi[1][c], b.hi[2][c]];
                assert_eq!(g.to_bits(), branchy(lo, hi, &q).to_bits(), "{q:?} {c}");
            }
        }
        assert_eq!(b.distance_sq(&[1.0, 2.0, 0.0])[0], 0.0);
        assert_eq!(b.distance_sq(&[3.0, 0.0, -4.0])[0], 1.0 + 1.0 + 9.0);
        // A NaN query is at distance 0 from everything (nothing is pruned).
        assert_eq!(b.distance_sq(&[f64::NAN, 0.0, 0.0])[0], 1.0);
        let nan = b.distance_sq(&[f64::NAN, f64::NAN, f64::NAN]);
        assert_eq!(nan, [0.0, 0.0]);
    }
}
