//! Evaluation of a fitted spline: the structure-of-arrays chunks of centres and weights (f64 and
//! f32), the kernel sums over them, and `evaluate` / `apply` in mixed precision (the hot loop of
//! the reconstruction) with their f64 and portable references.

use super::{TpsSolver, KERNEL_SCALE};
#[cfg(target_arch = "x86_64")]
use crate::deform::lanes::avx::{self, Avx32};
use crate::deform::lanes::{portable, Oct, Pair32, Quad, O4, Q2};
use crate::geometry::Vec3;

/// Lanes of the evaluation kernel (two f64x2 vectors in wasm).
const LANES: usize = 4;

/// Four centres and their weights, structure-of-arrays so the kernel loads whole lanes.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Chunk {
    x: [f64; 4],
    y: [f64; 4],
    z: [f64; 4],
    wx: [f64; 4],
    wy: [f64; 4],
    wz: [f64; 4],
}

/// Eight centres (relative to the fit's centre) and their weights in single precision: the chunks
/// of the mixed-precision evaluation.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Chunk32 {
    x: [f32; 8],
    y: [f32; 8],
    z: [f32; 8],
    wx: [f32; 8],
    wy: [f32; 8],
    wz: [f32; 8],
}

impl TpsSolver {
    /// Evaluation chunks; the padding lanes repeat the first centre with zero weight, which adds
    /// exactly zero.
    pub(super) fn build_chunks(&mut self, centres: &[Vec3]) {
        let n = self.n;
        let n_chunks = n.div_ceil(LANES);
        let pad = centres[0];
        self.chunks.resize(n_chunks, Chunk::default());
        for (ci, ch) in self.chunks.iter_mut().enumerate() {
            for l in 0..LANES {
                let i = ci * LANES + l;
                let (p, w) = if i < n {
                    let w = [self.rhs[i], self.rhs[n + i], self.rhs[2 * n + i]];
                    (centres[i], w.map(|x| x * KERNEL_SCALE))
                } else {
                    (pad, [0.0; 3])
                };
                ch.x[l] = p.x;
                ch.y[l] = p.y;
                ch.z[l] = p.z;
                ch.wx[l] = w[0];
                ch.wy[l] = w[1];
                ch.wz[l] = w[2];
            }
        }
        let c = self.centre;
        self.chunks32.resize(n.div_ceil(8), Chunk32::default());
        for (ci, ch) in self.chunks32.iter_mut().enumerate() {
            for l in 0..8 {
                let i = ci * 8 + l;
                let (p, w) = if i < n {
                    let w = [self.rhs[i], self.rhs[n + i], self.rhs[2 * n + i]];
                    (centres[i] - c, w.map(|x| x * KERNEL_SCALE))
                } else {
                    (pad - c, [0.0; 3])
                };
                ch.x[l] = p.x as f32;
                ch.y[l] = p.y as f32;
                ch.z[l] = p.z as f32;
                ch.wx[l] = w[0] as f32;
                ch.wy[l] = w[1] as f32;
                ch.wz[l] = w[2] as f32;
            }
        }
    }

    /// F at one point (the identity before a successful fit), through the mixed-precision
    /// kernel of [`apply`](Self::apply): the same bits.
    #[inline]
    pub fn evaluate(&self, p: Vec3) -> Vec3 {
        self.evaluate_mixed::<O4>(p)
    }

    /// [`evaluate`](Self::evaluate) through the portable plain-array lanes. Every target gives
    /// the same bits (the SSE, AVX and simd128 kernels keep its lane order); this is the reference
    /// that checks it.
    pub fn evaluate_portable(&self, p: Vec3) -> Vec3 {
        self.evaluate_mixed::<Pair32<portable::F4>>(p)
    }

    /// F at one point with the kernel sum in double precision: the reference of the
    /// mixed-precision evaluation (tests and error measurements; not the hot loop).
    pub fn evaluate_f64(&self, p: Vec3) -> Vec3 {
        if !self.fitted {
            return p;
        }
        let k = kernel_sum::<Q2>(&self.chunks, p);
        let d = p - self.centre;
        let af = |a: &[f64; 4]| a[0] + a[1] * d.x + a[2] * d.y + a[3] * d.z;
        Vec3::new(
            k[0] + af(&self.affine_c[0]),
            k[1] + af(&self.affine_c[1]),
            k[2] + af(&self.affine_c[2]),
        )
    }

    #[inline(always)]
    fn evaluate_mixed<O: Oct>(&self, p: Vec3) -> Vec3 {
        if !self.fitted {
            return p;
        }
        let d = p - self.centre;
        let k = kernel_sum32::<O>(&self.chunks32, [d.x as f32, d.y as f32, d.z as f32]);
        let af = |a: &[f64; 4]| a[0] + a[1] * d.x + a[2] * d.y + a[3] * d.z;
        Vec3::new(
            f64::from(k[0]) + af(&self.affine_c[0]),
            f64::from(k[1]) + af(&self.affine_c[1]),
            f64::from(k[2]) + af(&self.affine_c[2]),
        )
    }

    /// Replaces every point by F(point); leaves them unchanged before a successful fit.
    ///
    /// Mixed precision: the affine part, the centring and the final sum stay in f64; only the
    /// kernel sum sum_i w_i G(|x - P_i|) (the non-affine displacement, a small correction) runs
    /// in f32, eight lanes per step (two SSE / simd128 halves, or one AVX register natively when
    /// the CPU has it; same bits). Measured against the f64 kernel over whole default runs
    /// (`pipeline::precision` test): the largest vertex difference of any step is
    /// 2.4e-6 mm on the SurFCo example and 5.5e-6 mm on biv-me patient 1 ED RV endocardium,
    /// against steps of up to a millimetre and contour distances of tenths of millimetres.
    /// Rounding the centred coordinates to f32 costs ~1e-7 of the mesh size, and the kernel sum
    /// is a small correction to the affine map; the result is still deterministic and the same
    /// bits on every target.
    pub fn apply(&self, points: &mut [Vec3]) {
        if !self.fitted {
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if avx::available() {
            // SAFETY: the CPU has AVX.
            return unsafe { self.apply_avx(points) };
        }
        self.apply_mixed::<O4>(points);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn apply_avx(&self, points: &mut [Vec3]) {
        self.apply_mixed::<Avx32>(points);
    }

    #[inline(always)]
    fn apply_mixed<O: Oct>(&self, points: &mut [Vec3]) {
        for p in points {
            *p = self.evaluate_mixed::<O>(*p);
        }
    }

    /// [`apply`](Self::apply) with the f64 kernel sum (the reference; see
    /// [`evaluate_f64`](Self::evaluate_f64)).
    pub fn apply_f64(&self, points: &mut [Vec3]) {
        for p in points {
            *p = self.evaluate_f64(*p);
        }
    }
}

/// sum_i w_i G(|p - P_i|) in f32 for the three coordinates, `p` and the centres relative to the
/// fit's centre: eight lanes, lane l summing centres l, l + 8, ..., then the fixed `Oct::sum`.
#[inline(always)]
fn kernel_sum32<O: Oct>(chunks: &[Chunk32], p: [f32; 3]) -> [f32; 3] {
    let (px, py, pz) = (O::splat(p[0]), O::splat(p[1]), O::splat(p[2]));
    let mut acc = [O::zero(); 3];
    for ch in chunks {
        let dx = px.sub(O::load(&ch.x));
        let dy = py.sub(O::load(&ch.y));
        let dz = pz.sub(O::load(&ch.z));
        let r = dx.mul(dx).add(dy.mul(dy)).add(dz.mul(dz)).sqrt();
        acc[0] = acc[0].add(O::load(&ch.wx).mul(r));
        acc[1] = acc[1].add(O::load(&ch.wy).mul(r));
        acc[2] = acc[2].add(O::load(&ch.wz).mul(r));
    }
    acc.map(O::sum)
}

/// sum_i w_i G(|p - P_i|) for the three coordinates: four lanes, lane l summing centres l, l + 4,
/// ..., then (l0 + l1) + (l2 + l3); the same bits with every `Quad` implementation.
#[inline(always)]
fn kernel_sum<Q: Quad>(chunks: &[Chunk], p: Vec3) -> [f64; 3] {
    let (px, py, pz) = (Q::splat(p.x), Q::splat(p.y), Q::splat(p.z));
    let mut acc = [Q::zero(); 3];
    for ch in chunks {
        let dx = px.sub(Q::load(&ch.x));
        let dy = py.sub(Q::load(&ch.y));
        let dz = pz.sub(Q::load(&ch.z));
        let r = dx.mul(dx).add(dy.mul(dy)).add(dz.mul(dz)).sqrt();
        acc[0] = acc[0].add(Q::load(&ch.wx).mul(r));
        acc[1] = acc[1].add(Q::load(&ch.wy).mul(r));
        acc[2] = acc[2].add(Q::load(&ch.wz).mul(r));
    }
    acc.map(Q::sum)
}
