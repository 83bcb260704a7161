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

use sah::{split, Aabb};

mod sah;
#[cfg(test)]
mod tests;

/// Triangles per leaf: small leaves keep the exact point-triangle tests few per query.
const LEAF_SIZE: usize = 4;
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

/// A node's (start, count) in one word, as the traversal carries it.
#[inline(always)]
fn pack(start: u32, count: u32) -> u64 {
    u64::from(start) | (u64::from(count) << 32)
}

#[inline(always)]
fn unpack(range: u64) -> (u32, u32) {
    (range as u32, (range >> 32) as u32)
}
