//! The pieces of the binned surface-area-heuristic build: running boxes (with NaN-ignoring
//! min/max that stay single instructions in wasm) and the choice of a node's split.

use crate::geometry::Vec3;

/// SAH bins per axis.
const BINS: usize = 12;

/// Minimum by comparison: `f64::min` lowers to a libm call in wasm (its NaN rule has no wasm
/// instruction), which made building and refitting several times slower there. A NaN `b` is
/// ignored, as with `f64::min`.
#[inline(always)]
fn min(a: f64, b: f64) -> f64 {
    if b < a {
        b
    } else {
        a
    }
}

/// Maximum by comparison; see [`min`].
#[inline(always)]
fn max(a: f64, b: f64) -> f64 {
    if b > a {
        b
    } else {
        a
    }
}

/// Running min/max of points.
#[derive(Clone, Copy)]
pub(super) struct Aabb {
    pub(super) lo: [f64; 3],
    pub(super) hi: [f64; 3],
}

impl Aabb {
    pub(super) const EMPTY: Aabb = Aabb {
        lo: [f64::INFINITY; 3],
        hi: [f64::NEG_INFINITY; 3],
    };

    #[inline]
    pub(super) fn grow(&mut self, p: &[f64; 3]) {
        for ((lo, hi), p) in self.lo.iter_mut().zip(&mut self.hi).zip(p) {
            *lo = min(*lo, *p);
            *hi = max(*hi, *p);
        }
    }

    #[inline]
    pub(super) fn merge(&mut self, o: &Aabb) {
        for k in 0..3 {
            self.lo[k] = min(self.lo[k], o.lo[k]);
            self.hi[k] = max(self.hi[k], o.hi[k]);
        }
    }

    /// Half the surface area (the SAH only compares areas); 0 for an empty box.
    #[inline]
    fn half_area(&self) -> f64 {
        let d = [
            max(self.hi[0] - self.lo[0], 0.0),
            max(self.hi[1] - self.lo[1], 0.0),
            max(self.hi[2] - self.lo[2], 0.0),
        ];
        d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
    }

    pub(super) fn of_triangle(c: &[Vec3; 3]) -> Aabb {
        let mut b = Aabb::EMPTY;
        for p in c {
            b.grow(&[p.x, p.y, p.z]);
        }
        b
    }
}

/// Reorders `range` (whose centroids span `cb`) into two non-empty halves and returns the size of
/// the first: the cheapest binned-SAH split over the three axes, or (when `sah` is false, or every centroid coincides on
/// the chosen axis) a split by count at the median along the widest centroid axis.
#[inline(always)] // once per node; inlined so the binning loop gets the caller's AVX encoding
pub(super) fn split(
    range: &mut [u32],
    boxes: &[Aabb],
    centroids: &[[f64; 3]],
    cb: &Aabb,
    sah: bool,
) -> usize {
    let ext = [
        cb.hi[0] - cb.lo[0],
        cb.hi[1] - cb.lo[1],
        cb.hi[2] - cb.lo[2],
    ];
    // Axes with a positive extent (this also skips NaN extents) and their bin scales.
    let usable = ext.map(|e| e.partial_cmp(&0.0) == Some(std::cmp::Ordering::Greater));
    let scale = [0, 1, 2].map(|k| if usable[k] { BINS as f64 / ext[k] } else { 0.0 });
    if sah && usable.iter().any(|&u| u) {
        // One pass bins every triangle on the three axes at once.
        let mut bins = [[(Aabb::EMPTY, 0usize); BINS]; 3];
        for &t in range.iter() {
            let (c, bx) = (&centroids[t as usize], &boxes[t as usize]);
            for axis in 0..3 {
                let b = bin_of(c[axis], cb.lo[axis], scale[axis]);
                bins[axis][b].0.merge(bx);
                bins[axis][b].1 += 1;
            }
        }
        let mut best: Option<(f64, usize, usize)> = None; // (cost, axis, bins on the left)
        for axis in (0..3).filter(|&k| usable[k]) {
            let bins = &bins[axis];
            // Sweep from the right to get the right-side costs, then from the left.
            let mut right_cost = [0.0; BINS];
            let (mut acc, mut cnt) = (Aabb::EMPTY, 0usize);
            for i in (1..BINS).rev() {
                acc.merge(&bins[i].0);
                cnt += bins[i].1;
                right_cost[i] = acc.half_area() * cnt as f64;
            }
            let (mut acc, mut cnt) = (Aabb::EMPTY, 0usize);
            for i in 0..BINS - 1 {
                acc.merge(&bins[i].0);
                cnt += bins[i].1;
                if cnt == 0 || cnt == range.len() {
                    continue;
                }
                let cost = acc.half_area() * cnt as f64 + right_cost[i + 1];
                if best.is_none_or(|(c, _, _)| cost < c) {
                    best = Some((cost, axis, i + 1));
                }
            }
        }
        if let Some((_, axis, nbins)) = best {
            let mid = partition(range, |t| {
                bin_of(centroids[t as usize][axis], cb.lo[axis], scale[axis]) < nbins
            });
            if mid > 0 && mid < range.len() {
                return mid;
            }
        }
    }
    // Median split by count: always balanced, so the depth stays logarithmic.
    let axis = (0..3)
        .max_by(|&a, &b| ext[a].total_cmp(&ext[b]))
        .unwrap_or(0);
    let mid = range.len() / 2;
    range.select_nth_unstable_by(mid, |&a, &b| {
        centroids[a as usize][axis]
            .total_cmp(&centroids[b as usize][axis])
            .then(a.cmp(&b))
    });
    mid
}

#[inline]
fn bin_of(c: f64, lo: f64, scale: f64) -> usize {
    // Clamped to [0, BINS - 1] in floating point first (NaN -> 0; the maximum centroid goes to
    // the last bin), so the conversion is a plain truncation: the saturating `as` conversion
    // needed two conversions and five fix-ups per axis in the binning loop.
    let x = (c - lo) * scale;
    let x = if x > 0.0 { x } else { 0.0 };
    let x = if x < (BINS - 1) as f64 {
        x
    } else {
        (BINS - 1) as f64
    };
    // SAFETY: x is finite and in [0, BINS - 1], so its truncation fits in a u32.
    (unsafe { x.to_int_unchecked::<u32>() }) as usize
}

/// Stable-enough in-place partition (order inside each side is deterministic); returns the number
/// of elements for which `left` holds.
fn partition(range: &mut [u32], left: impl Fn(u32) -> bool) -> usize {
    let mut i = 0;
    for j in 0..range.len() {
        if left(range[j]) {
            range.swap(i, j);
            i += 1;
        }
    }
    i
}
