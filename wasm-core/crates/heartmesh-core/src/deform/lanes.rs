//! Two-lane f64 vectors for the TPS kernels, one implementation per target with identical
//! arithmetic: SSE2 on x86_64 (part of the baseline, always present), simd128 on wasm32 when the
//! feature is enabled, and plain arrays elsewhere.
//!
//! Why not leave it to the auto-vectoriser: reductions in floating point cannot be reordered by
//! the compiler, and for the register-blocked dot products of the Cholesky it picked shuffles
//! across dot products that ran slower than scalar code. Writing the lanes out fixes both the
//! speed and the summation order, so every target computes the same bits (each lane operation is
//! an IEEE add, sub, mul or sqrt; no fused multiply-add).

#[cfg(target_arch = "x86_64")]
mod imp {
    //! SAFETY (every `unsafe` below): SSE2 is part of the x86_64 baseline, so these intrinsics
    //! are always available; the load and store stay within the 16 bytes of a `[f64; 2]`.
    use core::arch::x86_64::*;

    #[derive(Clone, Copy)]
    pub struct F2(__m128d);

    impl super::Lanes for F2 {
        #[inline(always)]
        fn splat(x: f64) -> F2 {
            F2(unsafe { _mm_set1_pd(x) })
        }
        #[inline(always)]
        fn load(a: &[f64; 2]) -> F2 {
            // SAFETY: `a` is valid for reading 16 bytes; the load is unaligned.
            F2(unsafe { _mm_loadu_pd(a.as_ptr()) })
        }
        #[inline(always)]
        fn add(self, o: F2) -> F2 {
            F2(unsafe { _mm_add_pd(self.0, o.0) })
        }
        #[inline(always)]
        fn sub(self, o: F2) -> F2 {
            F2(unsafe { _mm_sub_pd(self.0, o.0) })
        }
        #[inline(always)]
        fn mul(self, o: F2) -> F2 {
            F2(unsafe { _mm_mul_pd(self.0, o.0) })
        }
        #[inline(always)]
        fn sqrt(self) -> F2 {
            F2(unsafe { _mm_sqrt_pd(self.0) })
        }
        #[inline(always)]
        fn lanes(self) -> [f64; 2] {
            let mut out = [0.0; 2];
            // SAFETY: `out` is valid for writing 16 bytes; the store is unaligned.
            unsafe { _mm_storeu_pd(out.as_mut_ptr(), self.0) };
            out
        }
    }
}

#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
mod imp {
    use core::arch::wasm32::*;

    #[derive(Clone, Copy)]
    pub struct F2(v128);

    impl super::Lanes for F2 {
        #[inline(always)]
        fn splat(x: f64) -> F2 {
            F2(f64x2_splat(x))
        }
        #[inline(always)]
        fn load(a: &[f64; 2]) -> F2 {
            // SAFETY: `a` is valid for reading 16 bytes; wasm loads need no alignment.
            F2(unsafe { v128_load(a.as_ptr() as *const v128) })
        }
        #[inline(always)]
        fn add(self, o: F2) -> F2 {
            F2(f64x2_add(self.0, o.0))
        }
        #[inline(always)]
        fn sub(self, o: F2) -> F2 {
            F2(f64x2_sub(self.0, o.0))
        }
        #[inline(always)]
        fn mul(self, o: F2) -> F2 {
            F2(f64x2_mul(self.0, o.0))
        }
        #[inline(always)]
        fn sqrt(self) -> F2 {
            F2(f64x2_sqrt(self.0))
        }
        #[inline(always)]
        fn lanes(self) -> [f64; 2] {
            [
                f64x2_extract_lane::<0>(self.0),
                f64x2_extract_lane::<1>(self.0),
            ]
        }
    }
}

#[cfg(not(any(
    target_arch = "x86_64",
    all(target_arch = "wasm32", target_feature = "simd128")
)))]
mod imp {
    pub use super::portable::F2;
}

/// The plain-array version: the fallback target, and the reference the tests compare with.
pub(crate) mod portable {
    #[derive(Clone, Copy)]
    pub struct F2([f64; 2]);

    impl super::Lanes for F2 {
        #[inline(always)]
        fn splat(x: f64) -> F2 {
            F2([x, x])
        }
        #[inline(always)]
        fn load(a: &[f64; 2]) -> F2 {
            F2(*a)
        }
        #[inline(always)]
        fn add(self, o: F2) -> F2 {
            F2([self.0[0] + o.0[0], self.0[1] + o.0[1]])
        }
        #[inline(always)]
        fn sub(self, o: F2) -> F2 {
            F2([self.0[0] - o.0[0], self.0[1] - o.0[1]])
        }
        #[inline(always)]
        fn mul(self, o: F2) -> F2 {
            F2([self.0[0] * o.0[0], self.0[1] * o.0[1]])
        }
        #[inline(always)]
        fn sqrt(self) -> F2 {
            F2([self.0[0].sqrt(), self.0[1].sqrt()])
        }
        #[inline(always)]
        fn lanes(self) -> [f64; 2] {
            self.0
        }
    }
}

/// The fastest two-lane vector of the target.
pub use imp::F2;

/// Two f64 lanes with lane-wise IEEE arithmetic.
pub trait Lanes: Copy {
    fn splat(x: f64) -> Self;
    fn load(a: &[f64; 2]) -> Self;
    fn add(self, o: Self) -> Self;
    fn sub(self, o: Self) -> Self;
    fn mul(self, o: Self) -> Self;
    fn sqrt(self) -> Self;
    fn lanes(self) -> [f64; 2];

    #[inline(always)]
    fn zero() -> Self {
        Self::splat(0.0)
    }
    /// `(l0 + l1)` of `self` plus `(l0 + l1)` of `hi`: the fixed final order of a 4-lane sum.
    #[inline(always)]
    fn sum4(self, hi: Self) -> f64 {
        let (a, b) = (self.lanes(), hi.lanes());
        (a[0] + a[1]) + (b[0] + b[1])
    }
}
