//! Edge topology of triangle meshes: which edges exist, which are shared, whether the surface is a
//! closed, consistently oriented 2-manifold.
//!
//! The remeshing steps (Dyn, Levin & Gregory 1990 butterfly subdivision; Garland & Heckbert 1997
//! quadric decimation; Villard et al. 2018 for the pipeline) all assume a manifold, oriented mesh
//! and must keep it so; this module is how they (and the tests) check that assumption cheaply.
//!
//! Half-edges are numbered `3 * t + k`: the directed edge from corner `k` to corner `(k + 1) % 3`
//! of triangle `t`. Edges are found by bucketing half-edges on their lower vertex (a counting sort,
//! linear time, deterministic), not by hashing.

use crate::error::{CoreError, Result};
use crate::mesh::TriMesh;

/// Marker for "no twin" (boundary or non-manifold half-edge) in [`EdgeMap::twins`].
pub const NO_TWIN: u32 = u32::MAX;

/// The undirected edges of a mesh and the half-edges that use each of them.
#[derive(Debug, Clone)]
pub struct EdgeMap {
    /// Undirected edges as (lower, higher) vertex index, sorted.
    pub edges: Vec<[u32; 2]>,
    /// Edge index of every half-edge `3 * t + k`.
    pub edge_of: Vec<u32>,
    /// CSR offsets into `half_edges`, one more entry than `edges`.
    offsets: Vec<u32>,
    half_edges: Vec<u32>,
    /// Number of vertex slots covered (at least `positions.len()`, more if indices are out of range).
    vertex_slots: usize,
}

/// Start and end vertex of half-edge `h`.
#[inline]
pub fn half_edge_ends(triangles: &[[u32; 3]], h: u32) -> (u32, u32) {
    let t = (h / 3) as usize;
    let k = (h % 3) as usize;
    (triangles[t][k], triangles[t][(k + 1) % 3])
}

/// The half-edge before `h` in its triangle (ends where `h` starts).
#[inline]
pub fn prev_half_edge(h: u32) -> u32 {
    h - h % 3 + (h + 2) % 3
}

/// The half-edge after `h` in its triangle (starts where `h` ends).
#[inline]
pub fn next_half_edge(h: u32) -> u32 {
    h - h % 3 + (h + 1) % 3
}

impl EdgeMap {
    pub fn new(mesh: &TriMesh) -> EdgeMap {
        let tris = &mesh.triangles;
        let max_index = tris
            .iter()
            .flatten()
            .map(|&i| i as usize + 1)
            .max()
            .unwrap_or(0);
        let vertex_slots = mesh.positions.len().max(max_index);
        let nh = tris.len() * 3;

        // Counting sort of half-edges by their lower vertex; each slot holds the sort key
        // (higher vertex << 32 | half-edge), so buckets sort as plain integers.
        let mut bucket_start = vec![0u32; vertex_slots + 1];
        for t in tris {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                bucket_start[a.min(b) as usize + 1] += 1;
            }
        }
        for v in 0..vertex_slots {
            bucket_start[v + 1] += bucket_start[v];
        }
        let mut fill = bucket_start.clone();
        let mut keys = vec![0u64; nh];
        for (ti, t) in tris.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let lo = a.min(b) as usize;
                keys[fill[lo] as usize] = ((a.max(b) as u64) << 32) | (3 * ti + k) as u64;
                fill[lo] += 1;
            }
        }
        drop(fill);

        let mut edges = Vec::with_capacity(nh / 2 + 1);
        let mut offsets = Vec::with_capacity(nh / 2 + 2);
        let mut edge_of = vec![0u32; nh];
        let mut sorted = vec![0u32; nh];
        for lo in 0..vertex_slots {
            let base = bucket_start[lo] as usize;
            let bucket = &mut keys[base..bucket_start[lo + 1] as usize];
            // Buckets hold a vertex's few edges: sorting by (higher vertex, half-edge) is cheap and
            // makes the edge order independent of anything but the mesh.
            bucket.sort_unstable();
            let mut previous_hi = u32::MAX;
            for (i, &key) in bucket.iter().enumerate() {
                let hi = (key >> 32) as u32;
                let h = key as u32;
                if hi != previous_hi {
                    edges.push([lo as u32, hi]);
                    offsets.push((base + i) as u32);
                    previous_hi = hi;
                }
                edge_of[h as usize] = (edges.len() - 1) as u32;
                sorted[base + i] = h;
            }
        }
        offsets.push(nh as u32);
        EdgeMap {
            edges,
            edge_of,
            offsets,
            half_edges: sorted,
            vertex_slots,
        }
    }

    /// The half-edges lying on edge `e` (1: boundary, 2: interior, more: non-manifold).
    #[inline]
    pub fn half_edges_of(&self, e: usize) -> &[u32] {
        &self.half_edges[self.offsets[e] as usize..self.offsets[e + 1] as usize]
    }

    /// Number of vertex slots the map covers.
    pub fn vertex_slots(&self) -> usize {
        self.vertex_slots
    }

    /// For every half-edge, its oppositely directed partner, or [`NO_TWIN`] when the edge is a
    /// boundary, is shared by more than two triangles, or its two triangles disagree in orientation.
    pub fn twins(&self, mesh: &TriMesh) -> Vec<u32> {
        let mut twin = vec![NO_TWIN; self.edge_of.len()];
        for e in 0..self.edges.len() {
            if let &[h, g] = self.half_edges_of(e) {
                let (a, _) = half_edge_ends(&mesh.triangles, h);
                let (c, _) = half_edge_ends(&mesh.triangles, g);
                if a != c {
                    twin[h as usize] = g;
                    twin[g as usize] = h;
                }
            }
        }
        twin
    }
}

/// Topological health of a mesh. `manifold` implies every edge has at most two triangles, shared
/// edges are traversed in opposite directions, every vertex's triangles form one fan (a disk inside,
/// a half-disk on the boundary), and there are no degenerate triangles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshValidity {
    /// No boundary edges (and at least one triangle).
    pub closed: bool,
    pub manifold: bool,
    /// Every shared edge is traversed in opposite directions by its two triangles.
    pub oriented: bool,
    pub boundary_edges: usize,
    pub boundary_loops: usize,
    /// V - E + F with V counting referenced vertices only (2 for a sphere, 0 for an open tube).
    pub euler_characteristic: i64,
    /// Triangles with a repeated or out-of-range index, or (numerically) zero area.
    pub degenerate_triangles: usize,
    /// Triangles whose vertex set equals an earlier triangle's (either orientation: "fins").
    pub duplicate_triangles: usize,
    pub unreferenced_vertices: usize,
}

impl MeshValidity {
    /// A manifold, oriented mesh without boundary.
    pub fn is_closed_manifold(&self) -> bool {
        self.closed && self.manifold && self.oriented
    }

    /// Human-readable list of the problems, for error messages.
    pub fn describe(&self) -> String {
        format!(
            "closed={} manifold={} oriented={} boundary_edges={} boundary_loops={} euler={} \
             degenerate={} duplicate={} unreferenced={}",
            self.closed,
            self.manifold,
            self.oriented,
            self.boundary_edges,
            self.boundary_loops,
            self.euler_characteristic,
            self.degenerate_triangles,
            self.duplicate_triangles,
            self.unreferenced_vertices
        )
    }
}

/// Disjoint-set forest with path halving; indices are u32 to halve memory traffic.
struct UnionFind {
    parent: Vec<u32>,
}

impl UnionFind {
    fn new(n: usize) -> Self {
        UnionFind {
            parent: (0..n as u32).collect(),
        }
    }
    fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let gp = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = gp;
            x = gp;
        }
        x
    }
    fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        // Smaller root wins, so the forest (and anything derived from it) is deterministic.
        if ra < rb {
            self.parent[rb as usize] = ra;
        } else if rb < ra {
            self.parent[ra as usize] = rb;
        }
    }
}

/// Checks closedness, manifoldness, orientation and counts defects. Never panics, whatever the
/// indices hold.
pub fn validity(mesh: &TriMesh) -> MeshValidity {
    validity_with_map(mesh, &EdgeMap::new(mesh))
}

/// [`validity`] reusing an edge map built for `mesh`.
pub fn validity_with_map(mesh: &TriMesh, map: &EdgeMap) -> MeshValidity {
    check(mesh, map, true)
}

/// The three verdicts a pass/fail gate needs (see [`MeshValidity`] for their meaning).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Health {
    pub closed: bool,
    pub manifold: bool,
    pub oriented: bool,
}

/// `closed`, `manifold` and `oriented` exactly as [`validity_with_map`] finds them, without the
/// defect counts that do not decide them (duplicates need a sort of all triangles, boundary
/// loops and the Euler characteristic more passes): the remesh checks every round's input and
/// output, and only builds the full report when a check fails.
pub fn health_with_map(mesh: &TriMesh, map: &EdgeMap) -> Health {
    let v = check(mesh, map, false);
    Health {
        closed: v.closed,
        manifold: v.manifold,
        oriented: v.oriented,
    }
}

/// The checks of [`validity_with_map`]; without `full`, the counts that do not decide
/// `closed`, `manifold` or `oriented` (loops, Euler characteristic, duplicates, unreferenced)
/// are left at 0.
fn check(mesh: &TriMesh, map: &EdgeMap, full: bool) -> MeshValidity {
    let tris = &mesh.triangles;
    let nv = mesh.positions.len();

    let mut degenerate = 0usize;
    let mut referenced = vec![false; if full { map.vertex_slots() } else { 0 }];
    for t in tris {
        let [a, b, c] = *t;
        if full {
            for &i in t {
                referenced[i as usize] = true;
            }
        }
        let bad_index = a == b || b == c || a == c || t.iter().any(|&i| i as usize >= nv);
        let zero_area = !bad_index && {
            let (pa, pb, pc) = (
                mesh.positions[a as usize],
                mesh.positions[b as usize],
                mesh.positions[c as usize],
            );
            let n = (pb - pa).cross(&(pc - pa)).norm();
            let scale = (pb - pa)
                .norm_squared()
                .max((pc - pa).norm_squared())
                .max((pc - pb).norm_squared());
            // NaN coordinates count as degenerate too.
            n.is_nan() || n <= 1e-12 * scale
        };
        if bad_index || zero_area {
            degenerate += 1;
        }
    }
    let referenced_count = referenced.iter().filter(|&&r| r).count();
    let unreferenced = if full {
        nv.saturating_sub(referenced[..nv].iter().filter(|&&r| r).count())
    } else {
        0
    };
    let duplicates = if full { duplicate_count(tris) } else { 0 };

    let mut boundary_edges = 0usize;
    let mut edge_manifold = true;
    let mut oriented = true;
    let mut corners = UnionFind::new(tris.len() * 3);
    let slots = if full { map.vertex_slots() } else { 0 };
    let mut boundary_graph = UnionFind::new(slots);
    let mut on_boundary = vec![false; slots];
    for e in 0..map.edges.len() {
        match *map.half_edges_of(e) {
            [_] => {
                boundary_edges += 1;
                if full {
                    let [a, b] = map.edges[e];
                    boundary_graph.union(a, b);
                    on_boundary[a as usize] = true;
                    on_boundary[b as usize] = true;
                }
            }
            [h, g] => {
                let (a, _) = half_edge_ends(tris, h);
                let (c, _) = half_edge_ends(tris, g);
                // Corners of the shared vertices in both triangles belong to the same fan.
                let (h_from, h_to) = (h, next_half_edge(h));
                let (g_from, g_to) = (g, next_half_edge(g));
                if a != c {
                    corners.union(h_from, g_to);
                    corners.union(h_to, g_from);
                } else {
                    oriented = false;
                    corners.union(h_from, g_from);
                    corners.union(h_to, g_to);
                }
            }
            _ => edge_manifold = false,
        }
    }
    let boundary_loops = (0..slots as u32)
        .filter(|&v| on_boundary[v as usize] && boundary_graph.find(v) == v)
        .count();

    // A vertex is a single fan when exactly one of its corners is a root.
    let mut fans = vec![0u32; map.vertex_slots()];
    for c in 0..(tris.len() * 3) as u32 {
        if corners.find(c) == c {
            let v = tris[(c / 3) as usize][(c % 3) as usize];
            fans[v as usize] += 1;
        }
    }
    let single_fans = fans.iter().all(|&f| f <= 1);

    let manifold = edge_manifold && oriented && single_fans && degenerate == 0;
    MeshValidity {
        closed: boundary_edges == 0 && !tris.is_empty(),
        manifold,
        oriented,
        boundary_edges,
        boundary_loops,
        euler_characteristic: referenced_count as i64 - map.edges.len() as i64 + tris.len() as i64,
        degenerate_triangles: degenerate,
        duplicate_triangles: duplicates,
        unreferenced_vertices: unreferenced,
    }
}

/// Number of triangles whose vertex set equals an earlier triangle's (sorted vertex triples,
/// sorted).
fn duplicate_count(tris: &[[u32; 3]]) -> usize {
    let mut keys: Vec<([u32; 3], u32)> = tris
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let mut k = *t;
            k.sort_unstable();
            (k, i as u32)
        })
        .collect();
    keys.sort_unstable();
    keys.windows(2).filter(|w| w[0].0 == w[1].0).count()
}

/// One-ring neighbours of every vertex in compressed-row form (one allocation for the whole mesh).
#[derive(Debug, Clone)]
pub struct VertexNeighbours {
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
}

impl VertexNeighbours {
    /// Neighbours of `v`, ascending.
    #[inline]
    pub fn of(&self, v: usize) -> &[u32] {
        &self.neighbours[self.offsets[v] as usize..self.offsets[v + 1] as usize]
    }

    /// Number of neighbours (valence) of `v`.
    #[inline]
    pub fn valence(&self, v: usize) -> usize {
        (self.offsets[v + 1] - self.offsets[v]) as usize
    }

    pub fn vertex_count(&self) -> usize {
        self.offsets.len() - 1
    }
}

/// One-ring neighbours from an edge map (reuse the map when you already have one).
pub fn vertex_neighbours_from(map: &EdgeMap) -> VertexNeighbours {
    let n = map.vertex_slots();
    let mut offsets = vec![0u32; n + 1];
    for &[a, b] in &map.edges {
        if a != b {
            offsets[a as usize + 1] += 1;
            offsets[b as usize + 1] += 1;
        }
    }
    for v in 0..n {
        offsets[v + 1] += offsets[v];
    }
    let mut fill = offsets.clone();
    let mut neighbours = vec![0u32; offsets[n] as usize];
    // Edges are sorted by (lower, higher), so each list comes out ascending.
    for &[a, b] in &map.edges {
        if a != b {
            neighbours[fill[a as usize] as usize] = b;
            fill[a as usize] += 1;
            neighbours[fill[b as usize] as usize] = a;
            fill[b as usize] += 1;
        }
    }
    VertexNeighbours {
        offsets,
        neighbours,
    }
}

/// One-ring neighbours of every vertex.
pub fn vertex_neighbours(mesh: &TriMesh) -> VertexNeighbours {
    vertex_neighbours_from(&EdgeMap::new(mesh))
}

/// Boundary half-edges (directed as in their triangle) of a mesh.
pub fn boundary_half_edges(mesh: &TriMesh, map: &EdgeMap) -> Vec<(u32, u32)> {
    (0..map.edges.len())
        .filter_map(|e| match *map.half_edges_of(e) {
            [h] => Some(half_edge_ends(&mesh.triangles, h)),
            _ => None,
        })
        .collect()
}

/// Previous and next vertex along the boundary (in the direction of the boundary half-edges) of
/// every vertex with exactly one boundary passage; `[NO_TWIN, NO_TWIN]` for interior vertices and
/// for vertices where several boundary loops touch (non-manifold).
pub fn boundary_links(mesh: &TriMesh, map: &EdgeMap) -> Vec<[u32; 2]> {
    let mut links = vec![[NO_TWIN, NO_TWIN]; map.vertex_slots()];
    let mut passages = vec![0u8; map.vertex_slots()];
    for (a, b) in boundary_half_edges(mesh, map) {
        links[a as usize][1] = b;
        links[b as usize][0] = a;
        passages[a as usize] = passages[a as usize].saturating_add(1);
    }
    for (link, &p) in links.iter_mut().zip(&passages) {
        if p > 1 || (link[0] == NO_TWIN) != (link[1] == NO_TWIN) {
            *link = [NO_TWIN, NO_TWIN];
        }
    }
    links
}

/// Which vertices lie on a boundary edge (mask of length `positions.len()`).
pub fn boundary_vertices(mesh: &TriMesh) -> Vec<bool> {
    let map = EdgeMap::new(mesh);
    let mut mask = vec![false; map.vertex_slots()];
    for (a, b) in boundary_half_edges(mesh, &map) {
        mask[a as usize] = true;
        mask[b as usize] = true;
    }
    mask.truncate(mesh.positions.len());
    mask
}

/// Drops vertices no triangle uses, keeping the order of the rest. Triangles with out-of-range
/// indices are an error.
pub fn compact(mesh: &TriMesh) -> Result<TriMesh> {
    let nv = mesh.positions.len();
    let mut remap = vec![u32::MAX; nv];
    for t in &mesh.triangles {
        for &i in t {
            let slot = remap.get_mut(i as usize).ok_or_else(|| {
                CoreError::InvalidMesh(format!("vertex index {i} out of range ({nv} vertices)"))
            })?;
            *slot = 0;
        }
    }
    let mut positions = Vec::with_capacity(nv);
    for (v, slot) in remap.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = positions.len() as u32;
            positions.push(mesh.positions[v]);
        }
    }
    let triangles = mesh
        .triangles
        .iter()
        .map(|t| t.map(|i| remap[i as usize]))
        .collect();
    Ok(TriMesh::new(positions, triangles))
}

/// Makes the orientation consistent (breadth-first over triangles sharing an edge) and then flips
/// each connected piece whose signed volume is negative, so closed meshes face outwards.
/// Returns an error for non-orientable surfaces (a Moebius strip) or out-of-range indices.
pub fn orient_outward(mesh: &mut TriMesh) -> Result<()> {
    let nv = mesh.positions.len();
    if let Some(i) = mesh.triangles.iter().flatten().find(|&&i| i as usize >= nv) {
        return Err(CoreError::InvalidMesh(format!(
            "vertex index {i} out of range ({nv} vertices)"
        )));
    }
    let map = EdgeMap::new(mesh);
    let tris = &mesh.triangles;
    let nt = tris.len();
    let mut flip = vec![false; nt];
    let mut component = vec![u32::MAX; nt];
    let mut queue = Vec::with_capacity(nt);
    let mut volumes: Vec<f64> = Vec::new();
    for seed in 0..nt {
        if component[seed] != u32::MAX {
            continue;
        }
        let id = volumes.len() as u32;
        volumes.push(0.0);
        component[seed] = id;
        queue.clear();
        queue.push(seed as u32);
        let mut head = 0;
        while head < queue.len() {
            let t = queue[head] as usize;
            head += 1;
            for k in 0..3 {
                let h = (3 * t + k) as u32;
                let e = map.edge_of[h as usize] as usize;
                let &[x, y] = map.half_edges_of(e) else {
                    continue;
                };
                let g = if x == h { y } else { x };
                let u = (g / 3) as usize;
                let same_direction = half_edge_ends(tris, h).0 == half_edge_ends(tris, g).0;
                let want = flip[t] ^ same_direction;
                if component[u] == u32::MAX {
                    component[u] = id;
                    flip[u] = want;
                    queue.push(u as u32);
                } else if flip[u] != want {
                    return Err(CoreError::InvalidMesh(
                        "surface is not orientable".to_string(),
                    ));
                }
            }
        }
    }
    for t in 0..nt {
        let [a, b, c] = mesh.triangles[t].map(|i| mesh.positions[i as usize]);
        let v = a.dot(&b.cross(&c)) / 6.0;
        volumes[component[t] as usize] += if flip[t] { -v } else { v };
    }
    for t in 0..nt {
        if flip[t] ^ (volumes[component[t] as usize] < 0.0) {
            mesh.triangles[t].swap(1, 2);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;
    use crate::mesh::shapes::{cylinder_tube, icosphere};

    fn tetra() -> TriMesh {
        crate::mesh::shapes::unit_tetrahedron()
    }

    #[test]
    fn tetra_is_closed_manifold() {
        let v = validity(&tetra());
        assert!(v.is_closed_manifold(), "{}", v.describe());
        assert_eq!(v.euler_characteristic, 2);
        assert_eq!(v.boundary_edges, 0);
        assert_eq!(v.boundary_loops, 0);
        assert_eq!(v.degenerate_triangles, 0);
        assert_eq!(v.duplicate_triangles, 0);
    }

    #[test]
    fn single_triangle_is_open_disk() {
        let m = TriMesh::new(
            vec![
                v3(0., 0., 0.),
                v3(1., 0., 0.),
                v3(0., 1., 0.),
                v3(5., 5., 5.),
            ],
            vec![[0, 1, 2]],
        );
        let v = validity(&m);
        assert!(!v.closed);
        assert!(v.manifold);
        assert_eq!(v.boundary_edges, 3);
        assert_eq!(v.boundary_loops, 1);
        assert_eq!(v.euler_characteristic, 1);
        assert_eq!(v.unreferenced_vertices, 1);
        let c = compact(&m).unwrap();
        assert_eq!(c.positions.len(), 3);
        assert_eq!(validity(&c).unreferenced_vertices, 0);
    }

    #[test]
    fn flipped_face_is_not_oriented_and_orient_fixes_it() {
        let mut m = tetra();
        m.triangles[3].swap(1, 2);
        let v = validity(&m);
        assert!(!v.oriented);
        assert!(!v.manifold);
        orient_outward(&mut m).unwrap();
        let v = validity(&m);
        assert!(v.is_closed_manifold());
        assert!((m.signed_volume() - 1.0 / 6.0).abs() < 1e-12);

        // Fully inverted: consistent but inward; orient_outward makes the volume positive.
        let mut inv = tetra();
        inv.flip_orientation();
        assert!(inv.signed_volume() < 0.0);
        orient_outward(&mut inv).unwrap();
        assert!((inv.signed_volume() - 1.0 / 6.0).abs() < 1e-12);
    }

    #[test]
    fn health_agrees_with_validity() {
        let mut meshes = vec![tetra(), TriMesh::new(tetra().positions, vec![[0, 1, 2]])];
        let mut flipped = tetra();
        flipped.triangles[3].swap(1, 2);
        meshes.push(flipped);
        let mut pinched = tetra();
        pinched
            .positions
            .extend([v3(-1., 0., 0.), v3(0., -1., 0.), v3(0., 0., -1.)]);
        pinched
            .triangles
            .extend([[0, 4, 5], [0, 6, 4], [0, 5, 6], [4, 6, 5]]);
        meshes.push(pinched);
        let mut fin = tetra();
        fin.triangles.push([0, 1, 2]);
        meshes.push(fin);
        let mut flat = tetra();
        flat.positions[3] = flat.positions[0];
        meshes.push(flat);
        let mut verdicts = Vec::new();
        for m in &meshes {
            let map = EdgeMap::new(m);
            let (v, h) = (validity_with_map(m, &map), health_with_map(m, &map));
            assert_eq!(
                (h.closed, h.manifold, h.oriented),
                (v.closed, v.manifold, v.oriented)
            );
            verdicts.push(h.manifold);
        }
        // Only the tetrahedron and the lone triangle are manifold.
        assert_eq!(verdicts, [true, true, false, false, false, false]);
    }

    #[test]
    fn fin_and_pinch_are_not_manifold() {
        // Two tetrahedra sharing only vertex 0: every edge is fine, the vertex fan is not.
        let mut m = tetra();
        m.positions
            .extend([v3(-1., 0., 0.), v3(0., -1., 0.), v3(0., 0., -1.)]);
        m.triangles
            .extend([[0, 4, 5], [0, 6, 4], [0, 5, 6], [4, 6, 5]]);
        orient_outward(&mut m).unwrap();
        let v = validity(&m);
        assert!(v.closed && v.oriented);
        assert!(!v.manifold, "pinched vertex must be non-manifold");
        assert_eq!(v.euler_characteristic, 3);

        // A fin: a triangle repeated with the opposite orientation on a closed tetrahedron.
        let mut f = tetra();
        f.triangles.push([0, 1, 2]);
        let v = validity(&f);
        assert_eq!(v.duplicate_triangles, 1);
        assert!(!v.manifold);
    }

    #[test]
    fn degenerate_and_out_of_range_do_not_panic() {
        let m = TriMesh::new(
            vec![v3(0., 0., 0.), v3(1., 0., 0.), v3(2., 0., 0.)],
            vec![[0, 1, 2], [0, 0, 1], [0, 1, 7]],
        );
        let v = validity(&m);
        assert_eq!(v.degenerate_triangles, 3);
        assert!(!v.manifold);
        assert!(compact(&m).is_err());
        let mut m2 = m.clone();
        assert!(orient_outward(&mut m2).is_err());
    }

    #[test]
    fn sphere_and_tubes() {
        let s = icosphere(10.0, 3);
        let v = validity(&s);
        assert!(v.is_closed_manifold());
        assert_eq!(v.euler_characteristic, 2);

        let open = cylinder_tube(10.0, 30.0, 50, 7, false);
        let v = validity(&open);
        assert!(v.manifold && v.oriented && !v.closed);
        assert_eq!(v.boundary_loops, 2);
        assert_eq!(v.boundary_edges, 100);
        assert_eq!(v.euler_characteristic, 0);
        let mask = boundary_vertices(&open);
        assert_eq!(mask.iter().filter(|&&b| b).count(), 100);

        let lidded = cylinder_tube(10.0, 30.0, 50, 7, true);
        let v = validity(&lidded);
        assert!(v.is_closed_manifold(), "{}", v.describe());
        assert_eq!(v.euler_characteristic, 2);
        assert!(lidded.signed_volume() > 0.0);
        let nb = vertex_neighbours(&lidded);
        let max_valence = (0..nb.vertex_count()).map(|v| nb.valence(v)).max();
        assert_eq!(max_valence, Some(50));
    }

    #[test]
    fn neighbours_are_symmetric_and_sorted() {
        let s = icosphere(1.0, 1);
        let nb = vertex_neighbours(&s);
        for v in 0..nb.vertex_count() {
            let ring = nb.of(v);
            assert!(ring.windows(2).all(|w| w[0] < w[1]));
            for &w in ring {
                assert!(nb.of(w as usize).contains(&(v as u32)));
            }
            assert!(nb.valence(v) == 5 || nb.valence(v) == 6);
        }
    }
}
