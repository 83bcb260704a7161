//! Nearest-segment queries over the contours' polyline segments, for the distance field on the
//! mesh (one query per mesh vertex at the end of every run).
//!
//! Reference: C. Ericson, "Real-Time Collision Detection" 2005, chapter 6 (bounding volume
//! hierarchies: flat pre-order node arrays, nearer child first, pruning by box distance).
//!
//! Why a tree of its own: the field used to test every vertex against every segment, ~200 M
//! instructions on the SurFCo example (3k vertices x 1.6k segments), more than a quarter of the
//! whole reconstruction. Segments are few and fixed, so a median-split tree is built once per call;
//! the triangle [`crate::spatial::Bvh`] is not reused because its leaves are triangles and its
//! refit machinery is not needed here.

use crate::geometry::Vec3;

/// Segments per leaf.
const LEAF: usize = 4;
/// A box is skipped only when it is farther than the best hit by more than this relative margin,
/// so rounding in the box test can never skip the segment the exhaustive search would choose.
const PRUNE_MARGIN: f64 = 1e-9;

#[derive(Debug, Clone, Copy)]
struct Node {
    lo: [f64; 3],
    hi: [f64; 3],
    /// Leaves: first index into `order`; inner nodes: the index of the right child (the left one
    /// follows its parent).
    start: u32,
    /// Segments in a leaf; 0 for inner nodes.
    count: u32,
}

impl Node {
    fn distance_sq(&self, q: &Vec3) -> f64 {
        let mut d = 0.0;
        for k in 0..3 {
            let e = (self.lo[k] - q[k]).max(q[k] - self.hi[k]).max(0.0);
            d += e * e;
        }
        d
    }
}

/// Squared distance from `v` to segment `(a, b)` (a point when `a == b`).
#[inline]
pub fn segment_distance_sq(v: &Vec3, a: &Vec3, b: &Vec3) -> f64 {
    let ab = b - a;
    let l2 = ab.norm_squared();
    let t = if l2 > 0.0 {
        ((v - a).dot(&ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - v).norm_squared()
}

/// A bounding-box tree over line segments answering exact nearest-segment distances.
pub struct SegmentTree {
    segments: Vec<(Vec3, Vec3)>,
    order: Vec<u32>,
    nodes: Vec<Node>,
}

impl SegmentTree {
    /// Builds the tree; segments with non-finite ends are left out (they can be nobody's nearest).
    pub fn new(segments: Vec<(Vec3, Vec3)>) -> SegmentTree {
        let finite = |p: &Vec3| p.iter().all(|c| c.is_finite());
        let mut order: Vec<u32> = (0..segments.len() as u32)
            .filter(|&i| {
                let (a, b) = &segments[i as usize];
                finite(a) && finite(b)
            })
            .collect();
        let mut tree = SegmentTree {
            segments,
            order: Vec::new(),
            nodes: Vec::new(),
        };
        if !order.is_empty() {
            let n = order.len();
            tree.build(&mut order, 0, n);
        }
        tree.order = order;
        tree
    }

    fn bounds(&self, ids: &[u32]) -> ([f64; 3], [f64; 3]) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for &i in ids {
            let (a, b) = &self.segments[i as usize];
            for k in 0..3 {
                lo[k] = lo[k].min(a[k]).min(b[k]);
                hi[k] = hi[k].max(a[k]).max(b[k]);
            }
        }
        (lo, hi)
    }

    /// Splits `order[start..end]` at the median of the segment midpoints along the box's longest
    /// axis: balanced, so the depth is log2(segments / LEAF) whatever the geometry.
    fn build(&mut self, order: &mut [u32], start: usize, end: usize) {
        let (lo, hi) = self.bounds(&order[start..end]);
        let me = self.nodes.len();
        self.nodes.push(Node {
            lo,
            hi,
            start: start as u32,
            count: (end - start) as u32,
        });
        if end - start <= LEAF {
            return;
        }
        let axis = (0..3)
            .max_by(|&i, &j| (hi[i] - lo[i]).total_cmp(&(hi[j] - lo[j])))
            .unwrap_or(0);
        let mid = (start + end) / 2;
        let segs = &self.segments;
        let key = |i: &u32| {
            let (a, b) = &segs[*i as usize];
            a[axis] + b[axis]
        };
        order[start..end]
            .select_nth_unstable_by(mid - start, |x, y| key(x).total_cmp(&key(y)).then(x.cmp(y)));
        self.build(order, start, mid);
        let right = self.nodes.len() as u32;
        self.build(order, mid, end);
        self.nodes[me].start = right;
        self.nodes[me].count = 0;
    }

    /// Distance from `v` to the nearest segment: exactly the minimum over all segments of
    /// [`segment_distance_sq`], square-rooted; infinite with no segments or a non-finite `v`.
    pub fn distance(&self, v: &Vec3) -> f64 {
        if self.nodes.is_empty() || !v.iter().all(|c| c.is_finite()) {
            return f64::INFINITY;
        }
        let mut best = f64::INFINITY;
        let mut stack: Vec<(u32, f64)> = Vec::with_capacity(64);
        stack.push((0, self.nodes[0].distance_sq(v)));
        while let Some((idx, d)) = stack.pop() {
            if d > best * (1.0 + PRUNE_MARGIN) {
                continue;
            }
            let node = &self.nodes[idx as usize];
            if node.count > 0 {
                let ids = &self.order[node.start as usize..(node.start + node.count) as usize];
                for &i in ids {
                    let (a, b) = &self.segments[i as usize];
                    best = best.min(segment_distance_sq(v, a, b));
                }
                continue;
            }
            let (l, r) = (idx + 1, node.start);
            let (dl, dr) = (
                self.nodes[l as usize].distance_sq(v),
                self.nodes[r as usize].distance_sq(v),
            );
            // The nearer child is popped first.
            if dl <= dr {
                stack.push((r, dr));
                stack.push((l, dl));
            } else {
                stack.push((l, dl));
                stack.push((r, dr));
            }
        }
        best.sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::prng::SplitMix64;

    fn brute(segs: &[(Vec3, Vec3)], v: &Vec3) -> f64 {
        segs.iter()
            .map(|(a, b)| segment_distance_sq(v, a, b))
            .fold(f64::INFINITY, f64::min)
            .sqrt()
    }

    #[test]
    fn equals_the_exhaustive_search() {
        let mut rng = SplitMix64::new(7);
        let mut r = |s: f64| (rng.next_f64() - 0.5) * s;
        // Polylines on a few planes, like contours, plus isolated points (zero-length segments).
        let mut segs = Vec::new();
        for ring in 0..12 {
            let z = ring as f64 * 10.0;
            let mut prev = Vec3::new(30.0, 0.0, z);
            for k in 1..=60 {
                let t = k as f64 / 60.0 * std::f64::consts::TAU;
                let p = Vec3::new(30.0 * t.cos(), 25.0 * t.sin(), z + 0.5 * t.sin());
                segs.push((prev, p));
                prev = p;
            }
        }
        for _ in 0..20 {
            let p = Vec3::new(r(80.0), r(80.0), r(200.0));
            segs.push((p, p));
        }
        let tree = SegmentTree::new(segs.clone());
        for _ in 0..2000 {
            let v = Vec3::new(r(120.0), r(120.0), r(300.0));
            assert_eq!(tree.distance(&v), brute(&segs, &v));
        }
    }

    #[test]
    fn empty_and_non_finite() {
        let tree = SegmentTree::new(Vec::new());
        assert_eq!(tree.distance(&Vec3::zeros()), f64::INFINITY);
        let nan = Vec3::new(f64::NAN, 0.0, 0.0);
        let one = SegmentTree::new(vec![
            (Vec3::zeros(), Vec3::new(1.0, 0.0, 0.0)),
            (nan, Vec3::zeros()),
        ]);
        assert_eq!(one.distance(&Vec3::new(0.5, 2.0, 0.0)), 2.0);
        assert_eq!(one.distance(&nan), f64::INFINITY);
    }
}
