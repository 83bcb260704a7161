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

pub use validity::{health_with_map, validity, validity_with_map, Health, MeshValidity};

#[cfg(test)]
mod tests;
mod validity;

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
