//! Whether a mesh is a closed, consistently oriented 2-manifold: the full verdict with its counts
//! ([`validity`]) and the three pass/fail answers a gate needs ([`health_with_map`]).

use super::{half_edge_ends, next_half_edge, EdgeMap};
use crate::mesh::TriMesh;

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
