//! Four f64 and eight f32 lanes in one 256-bit AVX register, for the CPUs that have it.
//!
//! SAFETY (every `unsafe` below): these methods are only called from functions compiled
//! with `#[target_feature(enable = "avx")]`, which run only after `available()` returned
//! true; the loads and stores stay within the 32 bytes of a `[f64; 4]` or `[f32; 8]`.
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

/// Eight f32 lanes in one 256-bit register.
#[derive(Clone, Copy)]
pub struct Avx32(__m256);

impl super::Oct for Avx32 {
    #[inline(always)]
    fn splat(x: f32) -> Avx32 {
        Avx32(unsafe { _mm256_set1_ps(x) })
    }
    #[inline(always)]
    fn load(a: &[f32; 8]) -> Avx32 {
        // SAFETY: `a` is valid for reading 32 bytes; the load is unaligned.
        Avx32(unsafe { _mm256_loadu_ps(a.as_ptr()) })
    }
    #[inline(always)]
    fn add(self, o: Avx32) -> Avx32 {
        Avx32(unsafe { _mm256_add_ps(self.0, o.0) })
    }
    #[inline(always)]
    fn sub(self, o: Avx32) -> Avx32 {
        Avx32(unsafe { _mm256_sub_ps(self.0, o.0) })
    }
    #[inline(always)]
    fn mul(self, o: Avx32) -> Avx32 {
        Avx32(unsafe { _mm256_mul_ps(self.0, o.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> Avx32 {
        Avx32(unsafe { _mm256_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn lanes(self) -> [f32; 8] {
        let mut out = [0.0; 8];
        // SAFETY: `out` is valid for writing 32 bytes; the store is unaligned.
        unsafe { _mm256_storeu_ps(out.as_mut_ptr(), self.0) };
        out
    }
}
