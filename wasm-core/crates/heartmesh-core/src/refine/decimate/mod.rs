//! Quadric error decimation by edge collapse.
//!
//! Reference: M. Garland, P. S. Heckbert, "Surface simplification using quadric error metrics",
//! SIGGRAPH 1997. Each vertex carries the sum of the (area-weighted) plane quadrics of its
//! triangles; the cheapest edge collapses first, to the point minimising the summed quadric.
//!
//! What this implementation adds, and why:
//! - The link condition (Dey et al. 1999; Hoppe 1993) plus minimum fan sizes, so every collapse
//!   keeps a manifold mesh manifold: the method's thin-plate-spline steps and the closest-point
//!   queries need a clean surface after every remesh, and a fin or pinch would grow over 12 rounds.
//! - Boundary handling (Garland & Heckbert section 6): each boundary edge adds a heavily weighted
//!   plane through it, perpendicular to its triangle, so open ends keep their outline; interior
//!   edges joining two boundary vertices are never collapsed (that would pinch the surface).
//! - Rejection of collapses that turn a triangle by more than ~80 degrees or make it (nearly)
//!   degenerate, so the result stays oriented without fold-overs.
//! - A priority queue with lazy invalidation instead of decrease-key (a 4-ary heap, see
//!   `heap.rs`): entries of collapsed vertices are skipped, and since merging only adds quadrics,
//!   a queued cost is a lower bound of the edge's current cost, so a popped entry whose cost has
//!   grown is simply queued again. Ties are broken by vertex index: results are deterministic.
//! - Vertex-to-triangle lists live in one shared array (a merged vertex's list is appended at its
//!   end), so the hot loop does not allocate.

use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::topology::{validity_with_map, EdgeMap};
use crate::mesh::TriMesh;
use crate::refine::heap::{Entry, MinHeap4};
use crate::refine::quadric::Quadric;

mod legal;
#[cfg(test)]
mod tests;
mod unfold;

/// Weight of a boundary-edge constraint plane relative to the area weight of ordinary planes
/// (per mm^2 of squared edge length).
const BOUNDARY_WEIGHT: f64 = 10.0;
/// A collapse may not turn any triangle's normal further than acos(0.17) ~ 80 degrees.
const MIN_NORMAL_COS: f64 = 0.17;
/// Triangles with quality 2 sqrt(3) |n| / sum(l^2) (1 = equilateral) below this are only accepted
/// when they were at least as bad before the collapse.
const MIN_QUALITY: f64 = 0.02;
/// Edge-length term of the collapse cost: cost = quadric error + LENGTH_PENALTY x mean triangle
/// area x |a - b|^2 (both terms in mm^4). Where the surface is flat in one direction (along a
/// ventricle's long axis) the quadric error is ~0 for many collapses, and without this term
/// they run in index order and leave long slivers (28 mm edges seen) whose flat interior cuts
/// the chord of the curved wall. With it the shortest edges go first, so edge lengths stay even.
/// Two collapsed vertices' quadrics cover about 12 mean triangle areas, so 0.01 weighs an edge of
/// length L like a plane deviation of ~0.03 L: it orders near-free collapses and barely
/// changes the others. Measured on tests/accuracy.rs (docs/VALIDATION.md, session 3): 0.003,
/// 0.01 and 0.03 all lower every LV and RV mean; 0.1 and 1 start to cost accuracy on the RV.
const LENGTH_PENALTY: f64 = 0.01;

/// Edges shorter than this share of the mesh's typical edge (that of an equilateral triangle of
/// the mean area) collapse without the turn and quality tests: at that scale a collapse moves the
/// surface by a tenth of an edge at most. Two kinds of mesh need it (docs/VALIDATION.md, session
/// 49). A knot: a patch the deformation squeezed into a ball of tiny triangles facing every way,
/// where any collapse turns one of them over, so none runs; each remesh's subdivision then
/// quadruples it (vertices within 1 mm: 2, 4, 15, 48, 177 in five remeshes) until the stalled
/// decimation eats the rest of the surface. And needles: rings of hundreds of points 10 mm
/// apart (`--ring-points` 500 on a small ring), whose shortest edges cannot go without turning a
/// neighbour, so the decimation stalls. On sound meshes no edge is this short: the method's
/// meshes of the real cases at the defaults are unchanged to the byte; 0.05 left the needles.
const KNOT_EDGE: f64 = 0.1;

/// Re-seeding the queue from all remaining edges catches collapses that were illegal when first
/// popped but became legal later; a few passes are enough in practice.
const MAX_PASSES: usize = 8;

/// Mutable state of one decimation.
struct Decimator {
    positions: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    triangle_alive: Vec<bool>,
    live_triangles: usize,
    quadrics: Vec<Quadric>,
    boundary: Vec<bool>,
    vertex_alive: Vec<bool>,
    /// Vertex v's triangles are refs[start[v]..start[v] + count[v]] (dead ones filtered on read).
    refs: Vec<u32>,
    start: Vec<u32>,
    count: Vec<u32>,
    marks: Vec<u32>,
    mark: u32,
    heap: MinHeap4,
    /// Queue entries that name a collapsed vertex (estimate, reset by each sweep).
    dead_entries: usize,
    /// Scratch of the legality test: the merged fan's triangles and their new normals.
    fan: Vec<([u32; 3], Vec3)>,
    /// Collapses must not leave a folded edge around the merged vertex (the repair rounds).
    guard_folds: bool,
    /// Cost per mm^2 of squared collapsed-edge length (see [`LENGTH_PENALTY`]).
    length_weight: f64,
    /// Squared length below which an edge belongs to a knot (see [`KNOT_EDGE`]).
    knot_edge2: f64,
    /// The CPU has AVX: checked once per decimation instead of once per cost evaluation.
    #[cfg(target_arch = "x86_64")]
    avx: bool,
}

impl Decimator {
    fn new(mesh: &TriMesh, centre: Vec3, known: Known) -> Result<Decimator> {
        // The edge map only finds the boundary edges (and checks the input): a mesh known to be
        // closed has none, and on the 4x subdivided mesh of a remesh step the map costs as much
        // as a tenth of the decimation.
        let map = match known {
            Known::ClosedManifold => None,
            _ => Some(EdgeMap::new(mesh)),
        };
        if let (Known::Nothing, Some(map)) = (known, &map) {
            let validity = validity_with_map(mesh, map);
            if !validity.manifold {
                return Err(CoreError::InvalidMesh(format!(
                    "decimation needs a manifold, oriented mesh ({})",
                    validity.describe()
                )));
            }
        }
        let n = mesh.positions.len();
        let positions: Vec<Vec3> = mesh.positions.iter().map(|p| p - centre).collect();
        let mut quadrics = vec![Quadric::default(); n];
        let mut area = 0.0;
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            let cross = (b - a).cross(&(c - a));
            let len = cross.norm();
            area += 0.5 * len;
            if len > 0.0 {
                let normal = cross / len;
                let q = Quadric::plane(normal, -normal.dot(&a), 0.5 * len);
                for &v in t {
                    quadrics[v as usize].add(&q);
                }
            }
        }
        let mut boundary = vec![false; n];
        let edges = map.as_ref().map_or(0, |m| m.edges.len());
        if let Some(map) = &map {
            for e in 0..map.edges.len() {
                if let &[h] = map.half_edges_of(e) {
                    let t = mesh.triangles[(h / 3) as usize];
                    let [pa, pb, pc] = t.map(|i| positions[i as usize]);
                    let normal = (pb - pa).cross(&(pc - pa));
                    let [a, b] = map.edges[e];
                    let (p, q) = (positions[a as usize], positions[b as usize]);
                    let along = q - p;
                    let side = along.cross(&normal);
                    let len = side.norm();
                    if len > 0.0 {
                        let side = side / len;
                        let quad = Quadric::plane(
                            side,
                            -side.dot(&p),
                            BOUNDARY_WEIGHT * along.norm_squared(),
                        );
                        quadrics[a as usize].add(&quad);
                        quadrics[b as usize].add(&quad);
                    }
                    boundary[a as usize] = true;
                    boundary[b as usize] = true;
                }
            }
        }
        let mut count = vec![0u32; n];
        for t in &mesh.triangles {
            for &v in t {
                count[v as usize] += 1;
            }
        }
        let mut start = vec![0u32; n];
        let mut total = 0u32;
        for v in 0..n {
            start[v] = total;
            total += count[v];
        }
        // Room for the merged lists appended by collapses, so growth is rare.
        let mut refs = vec![0u32; total as usize];
        refs.reserve(total as usize * 2);
        let mut fill = start.clone();
        for (ti, t) in mesh.triangles.iter().enumerate() {
            for &v in t {
                refs[fill[v as usize] as usize] = ti as u32;
                fill[v as usize] += 1;
            }
        }
        Ok(Decimator {
            positions,
            triangles: mesh.triangles.clone(),
            triangle_alive: vec![true; mesh.triangles.len()],
            live_triangles: mesh.triangles.len(),
            quadrics,
            boundary,
            vertex_alive: vec![true; n],
            refs,
            start,
            count,
            marks: vec![0; n],
            mark: 0,
            // Two entries per edge; a closed triangle mesh has 3T / 2 edges.
            heap: MinHeap4::with_capacity(edges.max(3 * mesh.triangles.len() / 2) * 2),
            dead_entries: 0,
            fan: Vec::new(),
            guard_folds: false,
            length_weight: LENGTH_PENALTY * area / mesh.triangles.len().max(1) as f64,
            // An equilateral triangle of area A has edges of squared length 4 A / sqrt(3).
            knot_edge2: KNOT_EDGE * KNOT_EDGE * 4.0 / 3f64.sqrt() * area
                / mesh.triangles.len().max(1) as f64,
            #[cfg(target_arch = "x86_64")]
            avx: std::arch::is_x86_feature_detected!("avx"),
        })
    }

    #[inline]
    fn list(&self, v: u32) -> std::ops::Range<usize> {
        let s = self.start[v as usize] as usize;
        s..s + self.count[v as usize] as usize
    }

    fn next_mark(&mut self) -> u32 {
        if self.mark >= u32::MAX - 4 {
            self.marks.fill(0);
            self.mark = 0;
        }
        self.mark += 2;
        self.mark
    }

    fn live_count(&self, v: u32) -> usize {
        self.list(v)
            .filter(|&i| self.triangle_alive[self.refs[i] as usize])
            .count()
    }

    /// Cost and target point of collapsing (a, b): the quadric error plus the edge-length
    /// penalty.
    fn evaluate(&self, a: u32, b: u32) -> (f64, Vec3) {
        #[cfg(target_arch = "x86_64")]
        if self.avx {
            // SAFETY: `avx` is only set when the CPU has AVX (see `Decimator::new`).
            return unsafe { self.evaluate_avx(a, b) };
        }
        self.evaluate_body(a, b)
    }

    /// [`Decimator::evaluate`] compiled with the three-operand VEX encoding: a quarter of its
    /// SSE2 instructions were register copies. Same IEEE operations (no fused multiply-add), so
    /// the same costs and points.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn evaluate_avx(&self, a: u32, b: u32) -> (f64, Vec3) {
        self.evaluate_body(a, b)
    }

    #[inline(always)]
    fn evaluate_body(&self, a: u32, b: u32) -> (f64, Vec3) {
        let (pa, pb) = (self.positions[a as usize], self.positions[b as usize]);
        let (error, p) = self.quadric_cost(a, b);
        (error + self.length_weight * (pb - pa).norm_squared(), p)
    }

    /// Quadric error and target point of collapsing (a, b).
    #[inline(always)]
    fn quadric_cost(&self, a: u32, b: u32) -> (f64, Vec3) {
        let q = self.quadrics[a as usize].sum(&self.quadrics[b as usize]);
        let (pa, pb) = (self.positions[a as usize], self.positions[b as usize]);
        let mid = (pa + pb) * 0.5;
        if let Some(p) = q.optimum() {
            // An optimum far outside the edge comes from a nearly flat quadric: not trustworthy.
            if (p - mid).norm_squared() <= (pb - pa).norm_squared() {
                return (q.error(p), p);
            }
        }
        [pa, pb, mid]
            .into_iter()
            .map(|p| (q.error(p), p))
            .fold(
                (f64::INFINITY, mid),
                |best, c| {
                    if c.0 < best.0 {
                        c
                    } else {
                        best
                    }
                },
            )
    }

    fn push(&mut self, a: u32, b: u32) {
        let (a, b) = (a.min(b), a.max(b));
        let (cost, _) = self.evaluate(a, b);
        self.heap.push(Entry::new(cost, a, b));
    }

    /// Marks `v` and its neighbours with `m`.
    fn mark_ring(&mut self, v: u32, m: u32) {
        self.marks[v as usize] = m;
        for i in self.list(v) {
            let t = self.refs[i] as usize;
            if self.triangle_alive[t] {
                for w in self.triangles[t] {
                    self.marks[w as usize] = m;
                }
            }
        }
    }

    /// Queues the edges around `v` to vertices not marked with `m` (each once).
    fn push_unmarked(&mut self, v: u32, m: u32) {
        for i in self.list(v) {
            let t = self.refs[i] as usize;
            if !self.triangle_alive[t] {
                continue;
            }
            for w in self.triangles[t] {
                if self.marks[w as usize] != m {
                    self.marks[w as usize] = m;
                    self.push(v, w);
                }
            }
        }
    }

    /// Queues every live edge (each once, from its lower vertex).
    fn seed(&mut self) {
        let mut seeds = self.heap.take();
        seeds.clear();
        self.dead_entries = 0;
        for v in 0..self.positions.len() as u32 {
            if !self.vertex_alive[v as usize] {
                continue;
            }
            let m = self.next_mark();
            for i in self.list(v) {
                let t = self.refs[i] as usize;
                if !self.triangle_alive[t] {
                    continue;
                }
                for w in self.triangles[t] {
                    // Tried branch-free (session 7): a third of the mispredicts, but twice the
                    // instructions; no faster.
                    if w > v && self.marks[w as usize] != m {
                        self.marks[w as usize] = m;
                        let (cost, _) = self.evaluate(v, w);
                        seeds.push(Entry::new(cost, v, w));
                    }
                }
            }
        }
        self.heap.rebuild(seeds);
    }

    /// Collapses b into a at p (a keeps its index).
    fn collapse(&mut self, a: u32, b: u32, p: Vec3) {
        // a's old edges keep their queue entries: quadrics only grow, so their queued costs are
        // lower bounds, refreshed when popped. Only edges a inherits from b are new.
        let m = self.next_mark();
        self.mark_ring(a, m);
        // b's edges (one per live triangle, plus one on a boundary) lose their entries.
        let mut live_b = 0usize;
        for i in self.list(b) {
            let t = self.refs[i] as usize;
            if !self.triangle_alive[t] {
                continue;
            }
            live_b += 1;
            if self.triangles[t].contains(&a) {
                self.triangle_alive[t] = false;
                self.live_triangles -= 1;
            } else {
                for w in &mut self.triangles[t] {
                    if *w == b {
                        *w = a;
                    }
                }
            }
        }
        self.dead_entries += live_b + usize::from(self.boundary[b as usize]);
        if self.refs.len() + (self.count[a as usize] + self.count[b as usize]) as usize
            > self.refs.capacity()
        {
            self.compact_refs();
        }
        let new_start = self.refs.len();
        // Every entry is written and the end advances only past live ones (no branch on
        // liveness, which mispredicts); the room was checked above.
        let room = (self.count[a as usize] + self.count[b as usize]) as usize;
        self.refs.resize(new_start + room, 0);
        let mut end = new_start;
        for v in [a, b] {
            for i in self.list(v) {
                let t = self.refs[i];
                self.refs[end] = t;
                end += usize::from(self.triangle_alive[t as usize]);
            }
        }
        self.refs.truncate(end);
        self.start[a as usize] = new_start as u32;
        self.count[a as usize] = (self.refs.len() - new_start) as u32;
        self.count[b as usize] = 0;
        self.vertex_alive[b as usize] = false;
        let qb = self.quadrics[b as usize];
        self.quadrics[a as usize].add(&qb);
        self.positions[a as usize] = p;
        self.boundary[a as usize] |= self.boundary[b as usize];
        self.push_unmarked(a, m);
    }

    /// Rewrites the vertex-triangle lists without dead entries (rarely: when the shared array
    /// would otherwise have to grow).
    fn compact_refs(&mut self) {
        let mut write = 0usize;
        for v in 0..self.positions.len() {
            let range = self.list(v as u32);
            self.start[v] = write as u32;
            for i in range {
                let t = self.refs[i];
                if self.triangle_alive[t as usize] {
                    self.refs[write] = t;
                    write += 1;
                }
            }
            self.count[v] = write as u32 - self.start[v];
        }
        self.refs.truncate(write);
    }

    fn drop_outdated(&mut self) {
        self.dead_entries = 0;
        let alive = &self.vertex_alive;
        self.heap
            .retain(|e| alive[e.a() as usize] && alive[e.b() as usize]);
    }

    fn run(&mut self, target: usize) {
        self.seed();
        for _ in 0..MAX_PASSES {
            let mut collapsed = 0usize;
            while self.live_triangles > target {
                let Some(c) = self.heap.pop() else { break };
                // Both alive means still adjacent: an edge only disappears by collapsing.
                let (a, b) = (c.a(), c.b());
                if !self.vertex_alive[a as usize] || !self.vertex_alive[b as usize] {
                    continue;
                }
                let (cost, p) = self.evaluate(a, b);
                if c.is_below(cost) {
                    self.heap.push(Entry::new(cost, a, b));
                    continue;
                }
                if self.legal(a, b, p) {
                    self.collapse(a, b, p);
                    collapsed += 1;
                    // Each edge has one entry, so a collapsed vertex leaves about one dead entry
                    // per edge it had. Popping one costs a root-to-leaf walk; once a third of the
                    // queue is dead, one sequential sweep is cheaper.
                    if 3 * self.dead_entries > self.heap.len() + 64 {
                        self.drop_outdated();
                    }
                }
            }
            if self.live_triangles <= target || collapsed == 0 {
                break;
            }
            self.seed();
        }
    }

    fn finish(self, centre: Vec3) -> TriMesh {
        let mut remap = vec![u32::MAX; self.positions.len()];
        let mut positions = Vec::new();
        let mut triangles = Vec::with_capacity(self.live_triangles);
        for (t, tri) in self.triangles.iter().enumerate() {
            if !self.triangle_alive[t] {
                continue;
            }
            triangles.push(tri.map(|v| {
                let slot = &mut remap[v as usize];
                if *slot == u32::MAX {
                    *slot = positions.len() as u32;
                    positions.push(self.positions[v as usize] + centre);
                }
                *slot
            }));
        }
        TriMesh::new(positions, triangles)
    }
}

/// Removes about `target_reduction` of the triangles (0.72 keeps ~28%) by quadric-error edge
/// collapses, stopping early when no legal collapse remains. The input must be manifold and
/// oriented; the output is too, closed if the input was, with unused vertices dropped (vertex
/// order follows first use by the surviving triangles).
pub fn decimate(mesh: &TriMesh, target_reduction: f64) -> Result<TriMesh> {
    decimate_checked(mesh, target_reduction, Known::Nothing)
}

/// What the caller already knows about a mesh handed to [`decimate_checked`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Known {
    /// Check that it is manifold and oriented.
    Nothing,
    /// Manifold and oriented, e.g. right after subdividing and smoothing a checked mesh.
    Manifold,
    /// Manifold, oriented and closed (no boundary edges).
    ClosedManifold,
}

/// [`decimate`] for a mesh whose validity the caller may already know (`known` other than
/// `Nothing` skips the validity pass; `ClosedManifold` also skips the boundary search).
pub(crate) fn decimate_checked(
    mesh: &TriMesh,
    target_reduction: f64,
    known: Known,
) -> Result<TriMesh> {
    if !(0.0..1.0).contains(&target_reduction) {
        return Err(CoreError::ParamOutOfRange {
            name: "target_reduction".into(),
            value: target_reduction,
            min: 0.0,
            max: 0.99,
        });
    }
    if mesh
        .positions
        .iter()
        .any(|p| !p.iter().all(|c| c.is_finite()))
    {
        return Err(CoreError::Numerical(
            "non-finite vertex position before decimation".into(),
        ));
    }
    // Work relative to the centroid: quadric errors then do not lose digits to a far origin.
    let centre = if mesh.positions.is_empty() {
        Vec3::zeros()
    } else {
        mesh.positions.iter().fold(Vec3::zeros(), |s, p| s + p) / mesh.positions.len() as f64
    };
    let mut state = Decimator::new(mesh, centre, known)?;
    let target = ((1.0 - target_reduction) * mesh.triangles.len() as f64).round() as usize;
    state.run(target);
    state.unfold();
    Ok(state.finish(centre))
}
