//! Bounding volume hierarchy over the triangles of a [`TriMesh`] for exact closest-point queries.
//!
//! References: I. Wald, "On fast Construction of SAH-based Bounding Volume Hierarchies", IEEE
//! Symposium on Interactive Ray Tracing 2007 (binned surface-area heuristic); C. Ericson,
//! "Real-Time Collision Detection" 2005, chapter 6 (flat node arrays, ordered traversal).
//!
//! Why this shape: the deformation loop asks ~300 closest points per iteration on a mesh whose
//! vertices move but whose triangles stay the same for 20 iterations, so the tree is built once
//! per remesh step and [`Bvh::refit`] recomputes the boxes in place every iteration (no
//! allocation). Nodes live in one array in which every child comes after its parent, so a refit is
//! a single reverse sweep. Queries visit the nearer child first, keep the farther one on a fixed
//! stack array, and prune any subtree whose box is farther than the best hit so far.

use std::mem::MaybeUninit;

use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::TriMesh;
use crate::spatial::pair::PairBoxes;
use crate::spatial::triangle::{
    closest_on_edges, closest_point_on_regular_triangle, is_degenerate,
};

/// Triangles per leaf: small leaves keep the exact point-triangle tests few per query.
const LEAF_SIZE: usize = 4;
/// SAH bins per axis.
const BINS: usize = 12;
/// Below this depth the SAH chooses splits; deeper nodes are halved by count, which bounds the
/// depth by `SAH_DEPTH + log2(triangles)` whatever the geometry.
const SAH_DEPTH: usize = 48;
/// Nodes with at most this many triangles are halved by count: binning them costs more than the
/// few extra box tests a less careful split causes.
const SAH_MIN: usize = 16;
/// Traversal stack size; the depth bound above (with u32 triangle indices) stays below it.
const STACK: usize = SAH_DEPTH + 34;

/// The answer of a closest-point query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClosestHit {
    /// The closest point on the mesh surface.
    pub point: Vec3,
    /// Squared distance from the query to `point`.
    pub distance_sq: f64,
    /// Index of the triangle `point` lies on (the lowest index among equally close triangles).
    pub triangle: u32,
}

/// An axis-aligned box; inner nodes have `count == 0` and their children at `start`, `start + 1`;
/// leaves hold `order[start..start + count]`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Node {
    lo: [f64; 3],
    hi: [f64; 3],
    start: u32,
    count: u32,
}

impl Node {
    /// Squared distance from `q` to the box (0 inside).
    #[inline(always)]
    fn distance_sq(&self, q: &[f64; 3]) -> f64 {
        let mut d = 0.0;
        for ((lo, hi), q) in self.lo.iter().zip(&self.hi).zip(q) {
            let e = if q < lo {
                lo - q
            } else if q > hi {
                q - hi
            } else {
                0.0
            };
            d += e * e;
        }
        d
    }
}

/// A triangle's corners copied in leaf order, with its degeneracy decided once per refit: queries
/// then read contiguous memory and skip the thinness test.
#[derive(Debug, Clone, Copy, PartialEq)]
struct LeafTri {
    corners: [Vec3; 3],
    degenerate: bool,
}

impl LeafTri {
    #[inline]
    fn new(c: [Vec3; 3]) -> LeafTri {
        LeafTri {
            degenerate: is_degenerate(&c[0], &c[1], &c[2]),
            corners: c,
        }
    }

    #[inline(always)]
    fn closest(&self, q: &Vec3) -> Vec3 {
        let [a, b, c] = &self.corners;
        if self.degenerate {
            closest_on_edges(q, a, b, c)
        } else {
            closest_point_on_regular_triangle(q, a, b, c)
        }
    }
}

/// A BVH over a mesh's triangles. It keeps a copy of the triangles' corners (refreshed by
/// [`Bvh::refit`]), so queries answer for the mesh as it was at the last build or refit.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// The boxes of nodes 2k + 1 and 2k + 2 (the children of one inner node: children are
    /// always appended in pairs after the root) at index k, for the two-lane box tests.
    pairs: Vec<PairBoxes>,
    /// Triangle indices in leaf order.
    order: Vec<u32>,
    /// Corners of `order[k]` at index k.
    tris: Vec<LeafTri>,
    /// Position in `tris` of each mesh triangle (`u32::MAX` for one left out).
    slot: Vec<u32>,
    /// Number of triangles of the mesh the tree was built for.
    n_triangles: usize,
    depth: usize,
}

/// Whether this CPU runs AVX code (cached by std after the first call). The build and the queries
/// are then compiled with the three-operand VEX encoding, which drops most of the register copies
/// that made up a fifth of their SSE2 instructions; the arithmetic (IEEE adds, muls, min/max, no
/// fused multiply-add) and so every result is the same. (The refit came out 4% longer: left as is.)
#[cfg(target_arch = "x86_64")]
#[inline]
fn avx_available() -> bool {
    std::arch::is_x86_feature_detected!("avx")
}

/// Corners of triangle `t`, or None if it refers to a missing vertex.
#[inline(always)]
fn corners(mesh: &TriMesh, t: usize) -> Option<[Vec3; 3]> {
    let [a, b, c] = *mesh.triangles.get(t)?;
    let p = &mesh.positions;
    Some([
        *p.get(a as usize)?,
        *p.get(b as usize)?,
        *p.get(c as usize)?,
    ])
}

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
struct Aabb {
    lo: [f64; 3],
    hi: [f64; 3],
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        lo: [f64::INFINITY; 3],
        hi: [f64::NEG_INFINITY; 3],
    };

    #[inline]
    fn grow(&mut self, p: &[f64; 3]) {
        for ((lo, hi), p) in self.lo.iter_mut().zip(&mut self.hi).zip(p) {
            *lo = min(*lo, *p);
            *hi = max(*hi, *p);
        }
    }

    #[inline]
    fn merge(&mut self, o: &Aabb) {
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

    fn of_triangle(c: &[Vec3; 3]) -> Aabb {
        let mut b = Aabb::EMPTY;
        for p in c {
            b.grow(&[p.x, p.y, p.z]);
        }
        b
    }
}

impl Bvh {
    /// Builds the tree with a binned SAH. Triangles that refer to missing vertices are left out
    /// (they have no geometry to be close to); an empty mesh gives an empty tree.
    pub fn build(mesh: &TriMesh) -> Bvh {
        #[cfg(target_arch = "x86_64")]
        if avx_available() {
            // SAFETY: the CPU has AVX.
            return unsafe { Bvh::build_avx(mesh) };
        }
        Bvh::build_body(mesh)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn build_avx(mesh: &TriMesh) -> Bvh {
        Bvh::build_body(mesh)
    }

    #[inline(always)]
    fn build_body(mesh: &TriMesh) -> Bvh {
        let n = mesh.triangles.len();
        let mut boxes = Vec::with_capacity(n);
        let mut centroids = Vec::with_capacity(n);
        let mut order = Vec::with_capacity(n);
        for t in 0..n {
            if let Some(c) = corners(mesh, t) {
                let b = Aabb::of_triangle(&c);
                let m = (c[0] + c[1] + c[2]) / 3.0;
                boxes.push(b);
                centroids.push([m.x, m.y, m.z]);
                order.push(t as u32);
            } else {
                boxes.push(Aabb::EMPTY);
                centroids.push([0.0; 3]);
            }
        }
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(2 * order.len() / LEAF_SIZE + 1),
            pairs: Vec::new(),
            order,
            tris: Vec::new(),
            slot: Vec::new(),
            n_triangles: n,
            depth: 0,
        };
        if bvh.order.is_empty() {
            return bvh;
        }
        bvh.nodes.push(Node {
            lo: [0.0; 3],
            hi: [0.0; 3],
            start: 0,
            count: bvh.order.len() as u32,
        });
        // (node index, depth); children are appended after their parent.
        let mut todo = vec![(0usize, 1usize)];
        while let Some((ni, depth)) = todo.pop() {
            bvh.depth = bvh.depth.max(depth);
            let (start, count) = (bvh.nodes[ni].start as usize, bvh.nodes[ni].count as usize);
            let range = &mut bvh.order[start..start + count];
            if count <= LEAF_SIZE {
                continue;
            }
            // The node's own box comes from the refit below (children before parents, O(n)),
            // not from merging every triangle box at every level.
            let mut cb = Aabb::EMPTY;
            for &t in range.iter() {
                cb.grow(&centroids[t as usize]);
            }
            let sah = depth <= SAH_DEPTH && count > SAH_MIN;
            let mid = split(range, &boxes, &centroids, &cb, sah);
            let left = bvh.nodes.len();
            for (s, c) in [(start, mid), (start + mid, count - mid)] {
                bvh.nodes.push(Node {
                    lo: [0.0; 3],
                    hi: [0.0; 3],
                    start: s as u32,
                    count: c as u32,
                });
            }
            bvh.nodes[ni].start = left as u32;
            bvh.nodes[ni].count = 0;
            todo.push((left + 1, depth + 1));
            todo.push((left, depth + 1));
        }
        bvh.pairs = vec![PairBoxes::default(); (bvh.nodes.len() - 1) / 2];
        for (ni, node) in bvh.nodes.iter().enumerate().skip(1) {
            bvh.pairs[(ni - 1) / 2].range[(ni - 1) % 2] = pack(node.start, node.count);
        }
        let unset = LeafTri {
            corners: [Vec3::zeros(); 3],
            degenerate: true,
        };
        bvh.tris = vec![unset; bvh.order.len()];
        bvh.slot = vec![u32::MAX; n];
        for (k, &t) in bvh.order.iter().enumerate() {
            bvh.slot[t as usize] = k as u32;
        }
        // Boxes and corners. Cannot fail: `order` holds only triangles whose corners exist, and
        // the triangle count is the mesh's.
        if bvh.refit(mesh).is_err() {
            return Bvh::default();
        }
        bvh
    }

    /// Recomputes every box from the mesh's current vertex positions, keeping the tree structure.
    /// The mesh must have the triangles the tree was built from (only the positions may differ).
    pub fn refit(&mut self, mesh: &TriMesh) -> Result<()> {
        if mesh.triangles.len() != self.n_triangles {
            return Err(CoreError::InvalidMesh(format!(
                "BVH refit: mesh has {} triangles, tree was built for {}",
                mesh.triangles.len(),
                self.n_triangles
            )));
        }
        for ni in (0..self.nodes.len()).rev() {
            let node = self.nodes[ni];
            let mut b = Aabb::EMPTY;
            if node.count == 0 {
                let (l, r) = (
                    &self.nodes[node.start as usize],
                    &self.nodes[node.start as usize + 1],
                );
                b.lo = l.lo;
                b.hi = l.hi;
                b.merge(&Aabb { lo: r.lo, hi: r.hi });
            } else {
                let s = node.start as usize;
                let e = s + node.count as usize;
                for (&t, lt) in self.order[s..e].iter().zip(&mut self.tris[s..e]) {
                    let c = corners(mesh, t as usize).ok_or_else(|| {
                        CoreError::InvalidMesh(format!(
                            "BVH refit: triangle {t} refers to a missing vertex"
                        ))
                    })?;
                    for p in &c {
                        b.grow(&[p.x, p.y, p.z]);
                    }
                    *lt = LeafTri::new(c);
                }
            }
            self.nodes[ni].lo = b.lo;
            self.nodes[ni].hi = b.hi;
            if let Some(pair) = ni.checked_sub(1).and_then(|c| self.pairs.get_mut(c / 2)) {
                pair.set(ni - 1, b.lo, b.hi);
            }
        }
        Ok(())
    }

    /// Whether the tree holds no triangle.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Number of nodes (inner and leaves).
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Depth of the deepest leaf (root = 1; 0 when empty).
    pub fn depth(&self) -> usize {
        self.depth
    }

    /// The closest point of the mesh surface to `q`; None when the tree is empty (or every
    /// distance is NaN). `mesh` must be the mesh of the last build or refit (its geometry is read
    /// from the tree's copy). Ties go to the lowest triangle index, so results are deterministic and
    /// equal to a brute-force scan.
    pub fn closest_point(&self, mesh: &TriMesh, q: Vec3) -> Option<ClosestHit> {
        self.closest_point_near(mesh, q, u32::MAX)
    }

    /// [`Bvh::closest_point`], starting from triangle `hint` (any index; one out of range is
    /// ignored). The answer is the same whatever the hint, because the hint only supplies the
    /// first candidate: the traversal still visits every box that could hold a closer triangle or
    /// an equally close one with a lower index. A good hint (the answer of a nearby query, or of
    /// the same query before the mesh moved a little) prunes most boxes from the start.
    #[inline(never)] // one call per query; kept out of line for profiles
    pub fn closest_point_near(&self, mesh: &TriMesh, q: Vec3, hint: u32) -> Option<ClosestHit> {
        let _ = mesh; // kept in the signature so callers pair each query with its mesh
        #[cfg(target_arch = "x86_64")]
        if avx_available() {
            // SAFETY: the CPU has AVX.
            return unsafe { self.closest_avx(q, hint) };
        }
        self.closest_body(q, hint)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn closest_avx(&self, q: Vec3, hint: u32) -> Option<ClosestHit> {
        self.closest_body(q, hint)
    }

    #[inline(always)]
    fn closest_body(&self, q: Vec3, hint: u32) -> Option<ClosestHit> {
        if self.nodes.is_empty() {
            return None;
        }
        let qa = [q.x, q.y, q.z];
        let mut best = ClosestHit {
            point: q,
            distance_sq: f64::INFINITY,
            triangle: u32::MAX,
        };
        // The hint's triangle, once tested here, is skipped in its leaf: the same test would give
        // the same (point, distance), which the tie rule (a strictly lower index) never prefers.
        let mut tested = u32::MAX;
        if let Some(&k) = self.slot.get(hint as usize) {
            if let Some(lt) = self.tris.get(k as usize) {
                tested = hint;
                let p = lt.closest(&q);
                let d = (q - p).norm_squared();
                // A NaN distance is never a best (as in the leaf loop below).
                if d < best.distance_sq {
                    best = ClosestHit {
                        point: p,
                        distance_sq: d,
                        triangle: hint,
                    };
                }
            }
        }
        // A box is pruned only when it is farther than the best hit by more than rounding, so a
        // triangle whose computed distance ties the best is never missed.
        let bound = |best: f64| best * (1.0 + 1e-12);
        let mut limit = bound(best.distance_sq);
        // Left uninitialised: zeroing the whole stack cost as much as a sixth of a query, and
        // only entries below `sp` (all written first) are ever read.
        let mut stack = [const { MaybeUninit::<(u64, f64)>::uninit() }; STACK];
        let mut sp = 0usize;
        // The node being visited, as its (start, count) packed in a u64 (see `PairBoxes::range`).
        let root = &self.nodes[0];
        let mut range = pack(root.start, root.count);
        let mut nd = root.distance_sq(&qa);
        loop {
            if nd <= limit {
                let (start, count) = unpack(range);
                if count == 0 {
                    // Children come in pairs after the root, so start >= 1 and start - 1 is even.
                    let Some(pair) = self.pairs.get((start as usize).wrapping_sub(1) / 2) else {
                        break; // cannot happen in a tree built by `build`
                    };
                    let [dl, dr] = pair.distance_sq(&qa);
                    let (near, dn, far, df) = if dr < dl {
                        (pair.range[1], dr, pair.range[0], dl)
                    } else {
                        (pair.range[0], dl, pair.range[1], dr)
                    };
                    if df <= limit && sp < STACK {
                        stack[sp].write((far, df));
                        sp += 1;
                    }
                    range = near;
                    nd = dn;
                    continue;
                }
                let s = start as usize;
                let e = s + count as usize;
                for (&t, lt) in self.order[s..e].iter().zip(&self.tris[s..e]) {
                    if t == tested {
                        continue;
                    }
                    let p = lt.closest(&q);
                    let d = (q - p).norm_squared();
                    if d < best.distance_sq || (d == best.distance_sq && t < best.triangle) {
                        best = ClosestHit {
                            point: p,
                            distance_sq: d,
                            triangle: t,
                        };
                        limit = bound(d);
                    }
                }
            }
            if sp == 0 {
                break;
            }
            sp -= 1;
            // SAFETY: every entry below the old `sp` was written by the push above before `sp`
            // passed it.
            (range, nd) = unsafe { stack[sp].assume_init() };
        }
        (best.triangle != u32::MAX).then_some(best)
    }

    /// Squared distance from `q` to triangle `t`, computed exactly as the queries compute it, so it
    /// is never below what `closest_point_near` returns for `q`: a cheap upper bound. None when `t`
    /// is not in the tree (out of range, or skipped for non-finite corners).
    pub fn distance_sq_to_triangle(&self, q: Vec3, t: u32) -> Option<f64> {
        let &k = self.slot.get(t as usize)?;
        let lt = self.tris.get(k as usize)?;
        Some((q - lt.closest(&q)).norm_squared())
    }

    /// Closest points of many queries: `out` is cleared and receives one hit per query, in order,
    /// or stays empty when the tree is empty. Reuses `out`'s allocation.
    pub fn closest_points(&self, mesh: &TriMesh, queries: &[Vec3], out: &mut Vec<ClosestHit>) {
        out.clear();
        if self.nodes.is_empty() {
            return;
        }
        out.reserve(queries.len());
        for q in queries {
            let hit = self.closest_point(mesh, *q).unwrap_or(ClosestHit {
                point: Vec3::from_element(f64::NAN),
                distance_sq: f64::NAN,
                triangle: u32::MAX,
            });
            out.push(hit);
        }
    }
}

/// Reorders `range` (whose centroids span `cb`) into two non-empty halves and returns the size of
/// the first: the cheapest binned-SAH split over the three axes, or (when `sah` is false, or every centroid coincides on
/// the chosen axis) a split by count at the median along the widest centroid axis.
#[inline(always)] // once per node; inlined so the binning loop gets the caller's AVX encoding
fn split(range: &mut [u32], boxes: &[Aabb], centroids: &[[f64; 3]], cb: &Aabb, sah: bool) -> usize {
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

/// A node's (start, count) in one word, as the traversal carries it.
#[inline(always)]
fn pack(start: u32, count: u32) -> u64 {
    u64::from(start) | (u64::from(count) << 32)
}

#[inline(always)]
fn unpack(range: u64) -> (u32, u32) {
    (range as u32, (range >> 32) as u32)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;
    use crate::spatial::testutil::{random_soup, uv_sphere, SplitMix64};
    use crate::spatial::triangle::closest_point_on_triangle;

    fn brute(mesh: &TriMesh, q: Vec3) -> Option<ClosestHit> {
        let mut best: Option<ClosestHit> = None;
        for t in 0..mesh.triangles.len() {
            let [a, b, c] = mesh.corners(t);
            let p = closest_point_on_triangle(&q, &a, &b, &c);
            let d = (q - p).norm_squared();
            if best.is_none_or(|h| d < h.distance_sq) {
                best = Some(ClosestHit {
                    point: p,
                    distance_sq: d,
                    triangle: t as u32,
                });
            }
        }
        best
    }

    fn check_against_brute(mesh: &TriMesh, bvh: &Bvh, queries: &[Vec3]) {
        for q in queries {
            let got = bvh.closest_point(mesh, *q).expect("non-empty mesh");
            let want = brute(mesh, *q).expect("non-empty mesh");
            assert_eq!(got, want, "query {q:?}");
        }
    }

    #[test]
    fn random_soups_equal_brute_force() {
        let mut rng = SplitMix64::new(42);
        for (nv, nt) in [(3, 1), (10, 7), (60, 100), (400, 1500)] {
            let mesh = random_soup(&mut rng, nv, nt);
            let bvh = Bvh::build(&mesh);
            let queries: Vec<Vec3> = (0..300).map(|_| rng.vec3(-15.0, 15.0)).collect();
            check_against_brute(&mesh, &bvh, &queries);
        }
    }

    #[test]
    fn sphere_queries_equal_brute_force() {
        let mut rng = SplitMix64::new(3);
        let mut mesh = uv_sphere(30.0, 24, 40);
        // Jitter the vertices so the sphere is not symmetric, and query near and far from it.
        for p in &mut mesh.positions {
            *p += rng.vec3(-0.5, 0.5);
        }
        let bvh = Bvh::build(&mesh);
        assert!(bvh.depth() < STACK);
        let mut queries: Vec<Vec3> = (0..200).map(|_| rng.vec3(-40.0, 40.0)).collect();
        queries.extend(mesh.positions.iter().take(50).copied()); // on vertices: exact ties
        check_against_brute(&mesh, &bvh, &queries);
        // A query on a shared vertex has distance 0 and the lowest incident triangle.
        let h = bvh.closest_point(&mesh, mesh.positions[0]).unwrap();
        assert_eq!(h.distance_sq, 0.0);
        assert_eq!(h.triangle, 0);
    }

    #[test]
    fn refit_equals_rebuild_for_queries() {
        let mut rng = SplitMix64::new(11);
        let mut mesh = uv_sphere(20.0, 24, 40);
        let mut bvh = Bvh::build(&mesh);
        let nodes_before = bvh.node_count();
        // A smooth, large deformation: anisotropic stretch plus a bend.
        for p in &mut mesh.positions {
            *p = v3(1.6 * p.x + 0.01 * p.z * p.z, 0.7 * p.y, p.z + 0.2 * p.x) + rng.vec3(-0.3, 0.3);
        }
        bvh.refit(&mesh).unwrap();
        assert_eq!(bvh.node_count(), nodes_before);
        let rebuilt = Bvh::build(&mesh);
        // Every box contains its triangles' corners.
        for node in &bvh.nodes {
            if node.count > 0 {
                let s = node.start as usize;
                for &t in &bvh.order[s..s + node.count as usize] {
                    for p in mesh.corners(t as usize) {
                        for k in 0..3 {
                            assert!(node.lo[k] <= p[k] && p[k] <= node.hi[k]);
                        }
                    }
                }
            }
        }
        let queries: Vec<Vec3> = (0..300).map(|_| rng.vec3(-40.0, 40.0)).collect();
        for q in &queries {
            let a = bvh.closest_point(&mesh, *q).unwrap();
            let b = rebuilt.closest_point(&mesh, *q).unwrap();
            assert_eq!(a, b);
            assert_eq!(Some(a), brute(&mesh, *q));
        }
        // Refitting back to the original positions gives the original boxes exactly.
        let original = uv_sphere(20.0, 24, 40);
        bvh.refit(&original).unwrap();
        assert_eq!(bvh, Bvh::build(&original));
    }

    #[test]
    fn empty_and_invalid_meshes_do_not_panic() {
        let empty = TriMesh::default();
        let bvh = Bvh::build(&empty);
        assert!(bvh.is_empty());
        assert_eq!(bvh.closest_point(&empty, v3(1., 2., 3.)), None);
        let mut out = vec![];
        bvh.closest_points(&empty, &[v3(0., 0., 0.)], &mut out);
        assert!(out.is_empty());

        // A triangle with a missing vertex is left out; the valid one still answers.
        let mesh = TriMesh::new(
            vec![v3(0., 0., 0.), v3(1., 0., 0.), v3(0., 1., 0.)],
            vec![[0, 1, 7], [0, 1, 2]],
        );
        let bvh = Bvh::build(&mesh);
        let h = bvh.closest_point(&mesh, v3(0.2, 0.2, 1.0)).unwrap();
        assert_eq!(h.triangle, 1);
        assert!((h.distance_sq - 1.0).abs() < 1e-15);
        // Refit with a different topology is an error, not a panic.
        let mut bvh = bvh;
        assert!(bvh.refit(&TriMesh::default()).is_err());
        bvh.refit(&mesh).unwrap(); // the left-out triangle is not refitted either
        let mut shrunk = mesh.clone();
        shrunk.positions.truncate(2);
        assert_eq!(bvh.refit(&shrunk).unwrap_err().code(), "invalid_mesh");

        // A NaN vertex poisons only its own triangles: the others still answer.
        let mut mesh = uv_sphere(5.0, 8, 12);
        mesh.positions[3] = v3(f64::NAN, 0.0, 0.0);
        let mut bvh = Bvh::build(&mesh);
        bvh.refit(&mesh).unwrap();
        let h = bvh.closest_point(&mesh, v3(0.0, 0.0, 9.0)).unwrap();
        assert!((h.distance_sq.sqrt() - 4.0).abs() < 1e-9, "{h:?}");

        // Many identical triangles (all centroids equal) still build a shallow tree.
        let mesh = TriMesh::new(
            vec![v3(0., 0., 0.), v3(1., 0., 0.), v3(0., 1., 0.)],
            vec![[0, 1, 2]; 1000],
        );
        let bvh = Bvh::build(&mesh);
        assert!(bvh.depth() <= 12, "depth {}", bvh.depth());
        assert_eq!(
            bvh.closest_point(&mesh, v3(0.1, 0.1, 0.0))
                .unwrap()
                .triangle,
            0
        );
    }

    #[test]
    fn any_hint_gives_the_same_hit() {
        let mut rng = SplitMix64::new(17);
        let mut mesh = uv_sphere(30.0, 24, 40);
        for p in &mut mesh.positions {
            *p += rng.vec3(-0.5, 0.5);
        }
        let n = mesh.triangles.len() as u32;
        let bvh = Bvh::build(&mesh);
        let mut queries: Vec<Vec3> = (0..200).map(|_| rng.vec3(-40.0, 40.0)).collect();
        queries.extend(mesh.positions.iter().take(50).copied()); // exact ties on vertices
        let mut hinted = 0;
        for q in &queries {
            let want = brute(&mesh, *q).unwrap();
            let near = bvh.closest_point(&mesh, *q).unwrap().triangle;
            // The answer itself, a neighbour-ish index, a random one, and invalid ones.
            let r = (rng.range(0.0, n as f64) as u32).min(n - 1);
            for hint in [near, near.saturating_sub(1), r, n, u32::MAX] {
                assert_eq!(
                    bvh.closest_point_near(&mesh, *q, hint),
                    Some(want),
                    "hint {hint}"
                );
                hinted += 1;
            }
        }
        assert_eq!(hinted, 5 * 250);
        // A soup with a left-out triangle: its index as a hint is ignored.
        let mesh = TriMesh::new(
            vec![v3(0., 0., 0.), v3(1., 0., 0.), v3(0., 1., 0.)],
            vec![[0, 1, 7], [0, 1, 2]],
        );
        let bvh = Bvh::build(&mesh);
        let h = bvh.closest_point_near(&mesh, v3(0.2, 0.2, 1.0), 0).unwrap();
        assert_eq!(h.triangle, 1);
    }

    #[test]
    fn batch_matches_single_queries() {
        let mut rng = SplitMix64::new(5);
        let mesh = uv_sphere(10.0, 16, 30);
        let bvh = Bvh::build(&mesh);
        let queries: Vec<Vec3> = (0..100).map(|_| rng.vec3(-20.0, 20.0)).collect();
        let mut out = Vec::new();
        bvh.closest_points(&mesh, &queries, &mut out);
        assert_eq!(out.len(), queries.len());
        for (q, h) in queries.iter().zip(&out) {
            assert_eq!(Some(*h), bvh.closest_point(&mesh, *q));
            // On a sphere of radius 10 the distance is close to | |q| - 10 |.
            assert!((h.distance_sq.sqrt() - (q.norm() - 10.0).abs()).abs() < 0.2);
        }
    }
}
