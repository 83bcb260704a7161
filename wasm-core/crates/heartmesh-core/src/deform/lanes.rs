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
}

/// Four f64 lanes: the `(lo, hi)` pairs of two-lane vectors that the kernels accumulate in, as
/// one value. [`Pair`] is exactly that pair of two-lane vectors; [`avx::Avx`] is one 256-bit AVX
/// register, used natively when the CPU has AVX (checked at run time). Lane for lane both do the
/// same IEEE operations (AVX without FMA), so the results have the same bits as the two-lane
/// kernels in wasm and in the portable reference.
pub trait Quad: Copy {
    fn splat(x: f64) -> Self;
    fn load(a: &[f64; 4]) -> Self;
    fn add(self, o: Self) -> Self;
    fn sub(self, o: Self) -> Self;
    fn mul(self, o: Self) -> Self;
    fn sqrt(self) -> Self;
    fn lanes(self) -> [f64; 4];

    #[inline(always)]
    fn zero() -> Self {
        Self::splat(0.0)
    }
    /// `(l0 + l1) + (l2 + l3)`: the fixed final order of a four-lane sum (= `Lanes::sum4`).
    #[inline(always)]
    fn sum(self) -> f64 {
        let l = self.lanes();
        (l[0] + l[1]) + (l[2] + l[3])
    }
}

/// Two two-lane vectors as four lanes.
#[derive(Clone, Copy)]
pub struct Pair<V: Lanes>(V, V);

impl<V: Lanes> Quad for Pair<V> {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        Pair(V::splat(x), V::splat(x))
    }
    #[inline(always)]
    fn load(a: &[f64; 4]) -> Self {
        let h = a.as_chunks::<2>().0;
        Pair(V::load(&h[0]), V::load(&h[1]))
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Pair(self.0.add(o.0), self.1.add(o.1))
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Pair(self.0.sub(o.0), self.1.sub(o.1))
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Pair(self.0.mul(o.0), self.1.mul(o.1))
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Pair(self.0.sqrt(), self.1.sqrt())
    }
    #[inline(always)]
    fn lanes(self) -> [f64; 4] {
        let (a, b) = (self.0.lanes(), self.1.lanes());
        [a[0], a[1], b[0], b[1]]
    }
}

/// The four lanes of the target without run-time detection.
pub type Q2 = Pair<F2>;

#[cfg(target_arch = "x86_64")]
pub mod avx {
    //! SAFETY (every `unsafe` below): these methods are only called from functions compiled
    //! with `#[target_feature(enable = "avx")]`, which run only after `available()` returned
    //! true; the loads and stores stay within the 32 bytes of a `[f64; 4]`.
    use core::arch::x86_64::*;

    #[derive(Clone, Copy)]
    pub struct Avx(__m256d);

    /// Whether this CPU runs AVX code (cached by std after the first call).
    #[inline]
    pub fn available() -> bool {
        std::arch::is_x86_feature_detected!("avx")
    }

    impl super::Quad for Avx {
        #[inline(always)]
        fn splat(x: f64) -> Avx {
            Avx(unsafe { _mm256_set1_pd(x) })
        }
        #[inline(always)]
        fn load(a: &[f64; 4]) -> Avx {
            // SAFETY: `a` is valid for reading 32 bytes; the load is unaligned.
            Avx(unsafe { _mm256_loadu_pd(a.as_ptr()) })
        }
        #[inline(always)]
        fn add(self, o: Avx) -> Avx {
            Avx(unsafe { _mm256_add_pd(self.0, o.0) })
        }
        #[inline(always)]
        fn sub(self, o: Avx) -> Avx {
            Avx(unsafe { _mm256_sub_pd(self.0, o.0) })
        }
        #[inline(always)]
        fn mul(self, o: Avx) -> Avx {
            Avx(unsafe { _mm256_mul_pd(self.0, o.0) })
        }
        #[inline(always)]
        fn sqrt(self) -> Avx {
            Avx(unsafe { _mm256_sqrt_pd(self.0) })
        }
        #[inline(always)]
        fn lanes(self) -> [f64; 4] {
            let mut out = [0.0; 4];
            // SAFETY: `out` is valid for writing 32 bytes; the store is unaligned.
            unsafe { _mm256_storeu_pd(out.as_mut_ptr(), self.0) };
            out
        }
    }
}
