//! Two-lane f64 and four-lane f32 vectors for the TPS kernels, one implementation per target with identical
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
    //! are always available; the loads and stores stay within the 16 bytes of a `[f64; 2]` or `[f32; 4]` (SSE, for f32, is
    //! baseline too).
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

    #[derive(Clone, Copy)]
    pub struct F4(__m128);

    impl super::Lanes32 for F4 {
        #[inline(always)]
        fn splat(x: f32) -> F4 {
            F4(unsafe { _mm_set1_ps(x) })
        }
        #[inline(always)]
        fn load(a: &[f32; 4]) -> F4 {
            // SAFETY: `a` is valid for reading 16 bytes; the load is unaligned.
            F4(unsafe { _mm_loadu_ps(a.as_ptr()) })
        }
        #[inline(always)]
        fn add(self, o: F4) -> F4 {
            F4(unsafe { _mm_add_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn sub(self, o: F4) -> F4 {
            F4(unsafe { _mm_sub_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn mul(self, o: F4) -> F4 {
            F4(unsafe { _mm_mul_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn sqrt(self) -> F4 {
            F4(unsafe { _mm_sqrt_ps(self.0) })
        }
        #[inline(always)]
        fn lanes(self) -> [f32; 4] {
            let mut out = [0.0; 4];
            // SAFETY: `out` is valid for writing 16 bytes; the store is unaligned.
            unsafe { _mm_storeu_ps(out.as_mut_ptr(), self.0) };
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

    #[derive(Clone, Copy)]
    pub struct F4(v128);

    impl super::Lanes32 for F4 {
        #[inline(always)]
        fn splat(x: f32) -> F4 {
            F4(f32x4_splat(x))
        }
        #[inline(always)]
        fn load(a: &[f32; 4]) -> F4 {
            // SAFETY: `a` is valid for reading 16 bytes; wasm loads need no alignment.
            F4(unsafe { v128_load(a.as_ptr() as *const v128) })
        }
        #[inline(always)]
        fn add(self, o: F4) -> F4 {
            F4(f32x4_add(self.0, o.0))
        }
        #[inline(always)]
        fn sub(self, o: F4) -> F4 {
            F4(f32x4_sub(self.0, o.0))
        }
        #[inline(always)]
        fn mul(self, o: F4) -> F4 {
            F4(f32x4_mul(self.0, o.0))
        }
        #[inline(always)]
        fn sqrt(self) -> F4 {
            F4(f32x4_sqrt(self.0))
        }
        #[inline(always)]
        fn lanes(self) -> [f32; 4] {
            [
                f32x4_extract_lane::<0>(self.0),
                f32x4_extract_lane::<1>(self.0),
                f32x4_extract_lane::<2>(self.0),
                f32x4_extract_lane::<3>(self.0),
            ]
        }
    }
}

#[cfg(not(any(
    target_arch = "x86_64",
    all(target_arch = "wasm32", target_feature = "simd128")
)))]
mod imp {
    pub use super::portable::{F2, F4};
}

/// The plain-array version: the fallback target, and the reference the tests compare with.
pub(crate) mod portable {
    // On the SIMD targets only the tests build these (the fallback target's lanes otherwise).
    #[allow(dead_code)]
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

    #[derive(Clone, Copy)]
    pub struct F4([f32; 4]);

    impl super::Lanes32 for F4 {
        #[inline(always)]
        fn splat(x: f32) -> F4 {
            F4([x; 4])
        }
        #[inline(always)]
        fn load(a: &[f32; 4]) -> F4 {
            F4(*a)
        }
        #[inline(always)]
        fn add(self, o: F4) -> F4 {
            F4([0, 1, 2, 3].map(|l| self.0[l] + o.0[l]))
        }
        #[inline(always)]
        fn sub(self, o: F4) -> F4 {
            F4([0, 1, 2, 3].map(|l| self.0[l] - o.0[l]))
        }
        #[inline(always)]
        fn mul(self, o: F4) -> F4 {
            F4([0, 1, 2, 3].map(|l| self.0[l] * o.0[l]))
        }
        #[inline(always)]
        fn sqrt(self) -> F4 {
            F4(self.0.map(f32::sqrt))
        }
        #[inline(always)]
        fn lanes(self) -> [f32; 4] {
            self.0
        }
    }
}

/// The fastest two-lane f64 vector of the target.
pub use imp::F2;
/// The fastest four-lane f32 vector of the target.
pub use imp::F4;

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

/// Four f32 lanes with lane-wise IEEE arithmetic (single precision: the mixed-precision kernels).
pub trait Lanes32: Copy {
    fn splat(x: f32) -> Self;
    fn load(a: &[f32; 4]) -> Self;
    fn add(self, o: Self) -> Self;
    fn sub(self, o: Self) -> Self;
    fn mul(self, o: Self) -> Self;
    fn sqrt(self) -> Self;
    fn lanes(self) -> [f32; 4];
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

/// Eight f32 lanes, the single-precision counterpart of [`Quad`]: [`Pair32`] is two four-lane
/// vectors (SSE, simd128 or arrays), [`avx::Avx32`] one 256-bit AVX register. Lane for lane both
/// do the same IEEE single-precision operations (no FMA), so they give the same bits.
pub trait Oct: Copy {
    fn splat(x: f32) -> Self;
    fn load(a: &[f32; 8]) -> Self;
    fn add(self, o: Self) -> Self;
    fn sub(self, o: Self) -> Self;
    fn mul(self, o: Self) -> Self;
    fn sqrt(self) -> Self;
    fn lanes(self) -> [f32; 8];

    #[inline(always)]
    fn zero() -> Self {
        Self::splat(0.0)
    }
    /// `((l0 + l1) + (l2 + l3)) + ((l4 + l5) + (l6 + l7))`: the fixed final order of an
    /// eight-lane sum, the same for every implementation.
    #[inline(always)]
    fn sum(self) -> f32 {
        let l = self.lanes();
        ((l[0] + l[1]) + (l[2] + l[3])) + ((l[4] + l[5]) + (l[6] + l[7]))
    }
}

/// Two four-lane f32 vectors as eight lanes.
#[derive(Clone, Copy)]
pub struct Pair32<V: Lanes32>(V, V);

impl<V: Lanes32> Oct for Pair32<V> {
    #[inline(always)]
    fn splat(x: f32) -> Self {
        Pair32(V::splat(x), V::splat(x))
    }
    #[inline(always)]
    fn load(a: &[f32; 8]) -> Self {
        let h = a.as_chunks::<4>().0;
        Pair32(V::load(&h[0]), V::load(&h[1]))
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Pair32(self.0.add(o.0), self.1.add(o.1))
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Pair32(self.0.sub(o.0), self.1.sub(o.1))
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Pair32(self.0.mul(o.0), self.1.mul(o.1))
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Pair32(self.0.sqrt(), self.1.sqrt())
    }
    #[inline(always)]
    fn lanes(self) -> [f32; 8] {
        let (a, b) = (self.0.lanes(), self.1.lanes());
        [a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]]
    }
}

/// The eight f32 lanes of the target without run-time detection.
pub type O4 = Pair32<F4>;

/// A kernel over rows of four f64 lanes (`out` holds rows `start..start + out.len()`), written once
/// over [`Quad`]; [`run_rows`] picks the lanes.
pub trait RowKernel {
    fn rows<Q: Quad>(&self, start: usize, out: &mut [[f64; 4]]);
}

/// Runs `k` with one AVX register per row when the CPU has AVX (checked at run time), otherwise
/// with [`Q2`]: the same lane operations, so the same bits on every target.
pub fn run_rows<K: RowKernel>(k: &K, start: usize, out: &mut [[f64; 4]]) {
    #[cfg(target_arch = "x86_64")]
    if avx::available() {
        // SAFETY: the CPU has AVX.
        return unsafe { run_rows_avx(k, start, out) };
    }
    k.rows::<Q2>(start, out);
}

/// [`run_rows`] compiled for AVX, so that the inlined kernel is too.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn run_rows_avx<K: RowKernel>(k: &K, start: usize, out: &mut [[f64; 4]]) {
    k.rows::<avx::Avx>(start, out);
}

#[cfg(target_arch = "x86_64")]
pub mod avx;

/// Defines `$name`, which runs `$kernel::<$avx>` when the CPU has AVX (checked at run time) and
/// `$kernel::<$base>` otherwise, and `$avx_name`, the AVX instance compiled with
/// `#[target_feature(enable = "avx")]` so that the inlined kernel is too (x86_64 only). The two
/// lane types do the same lane operations in the same order, so both give the same bits; the
/// attributes (docs, `cfg`, `inline`, `allow`) apply to both functions.
macro_rules! avx_dispatch {
    (
        $(#[$attr:meta])*
        $vis:vis fn $name:ident / $avx_name:ident ($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)?
            = $kernel:ident::<$base:ty, $avx:ty>;
    ) => {
        $(#[$attr])*
        $vis fn $name($($arg: $ty),*) $(-> $ret)? {
            #[cfg(target_arch = "x86_64")]
            if $crate::deform::lanes::avx::available() {
                // SAFETY: the CPU has AVX.
                return unsafe { $avx_name($($arg),*) };
            }
            $kernel::<$base>($($arg),*)
        }

        $(#[$attr])*
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx")]
        unsafe fn $avx_name($($arg: $ty),*) $(-> $ret)? {
            $kernel::<$avx>($($arg),*)
        }
    };
}
pub(crate) use avx_dispatch;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spatial::testutil::SplitMix64;

    /// One pass of every operation over eight f32 lanes, summed at the end.
    #[inline(always)]
    fn mix<O: Oct>(a: &[f32; 8], b: &[f32; 8]) -> ([f32; 8], f32) {
        let (x, y) = (O::load(a), O::load(b));
        let r = x
            .mul(x)
            .add(y.mul(y))
            .sqrt()
            .sub(y)
            .mul(O::splat(0.3))
            .add(x);
        (r.lanes(), r.sum())
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn mix_avx(a: &[f32; 8], b: &[f32; 8]) -> ([f32; 8], f32) {
        mix::<avx::Avx32>(a, b)
    }

    /// The target's f32 lanes (SSE natively, simd128 in wasm), AVX and the plain arrays give the
    /// same bits, which is what keeps native results equal to wasm's.
    #[test]
    fn f32_lanes_give_the_same_bits_everywhere() {
        let mut rng = SplitMix64::new(11);
        for _ in 0..2000 {
            let a: [f32; 8] = std::array::from_fn(|_| rng.range(-3.0, 3.0) as f32);
            let b: [f32; 8] = std::array::from_fn(|_| rng.range(-1e-3, 1e3) as f32);
            let want = mix::<Pair32<portable::F4>>(&a, &b);
            let bits = |(l, s): ([f32; 8], f32)| (l.map(f32::to_bits), s.to_bits());
            assert_eq!(bits(mix::<O4>(&a, &b)), bits(want));
            #[cfg(target_arch = "x86_64")]
            if avx::available() {
                // SAFETY: the CPU has AVX.
                assert_eq!(bits(unsafe { mix_avx(&a, &b) }), bits(want));
            }
            // And the lanes are plain IEEE single precision.
            let l0 = ((a[0] * a[0] + b[0] * b[0]).sqrt() - b[0]) * 0.3 + a[0];
            assert_eq!(want.0[0].to_bits(), l0.to_bits());
        }
    }
}
