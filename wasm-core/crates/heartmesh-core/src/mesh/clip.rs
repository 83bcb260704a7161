//! Cutting a closed mesh at a plane and keeping one side, with the cut's outline.
//!
//! A myocardium wall ([`super::wall`]) is the part of the endo- and epicardial surfaces below the
//! base, joined across the base by a flat ring; that needs each surface cut exactly at the plane,
//! every new vertex shared by the two triangles of its edge (so the cut surface stays manifold),
//! and the outline of the cut as vertex loops in order. The volume clip of
//! [`crate::metrics::compare`] only integrates and keeps no mesh, so it cannot serve here.
//!
//! Vertices within `snap` of the plane are moved onto it first: without that, a vertex a hair
//! below the plane leaves slivers a hair wide along the cut, which volume meshers reject.

use super::topology::{boundary_half_edges, EdgeMap};
use super::TriMesh;
use crate::error::{CoreError, Result};
use crate::sim::slice::Plane;
use std::collections::HashMap;

/// How far from the plane (mm) a vertex of the result may be and still count as on it.
const IN_PLANE_MM: f64 = 1e-7;

/// The part of a mesh below a plane.
#[derive(Debug, Clone)]
pub struct Clipped {
    pub mesh: TriMesh,
    /// The cut's outline: loops of vertex indices of `mesh`, all in the plane, each running the
    /// way the mesh's boundary half-edges run (counter-clockwise about the plane normal for an
    /// outward-facing surface below it).
    pub loops: Vec<Vec<u32>>,
}

/// Where a vertex lies: below the plane, on it, or above it.
#[derive(Clone, Copy, PartialEq)]
enum Side {
    Below,
    On,
    Above,
}

/// Keeps the part of `mesh` below `plane` (where `signed_distance < 0`), cutting the triangles
/// that cross it. The mesh should be closed: the cut's outline is then the whole boundary of
/// the result, and a boundary edge off the plane is an error (the surface was open below the
/// base), as is a boundary that touches itself.
pub fn clip_below(mesh: &TriMesh, plane: &Plane, snap: f64) -> Result<Clipped> {
    let mut positions = mesh.positions.clone();
    let mut sides = Vec::with_capacity(positions.len());
    let mut dist = Vec::with_capacity(positions.len());
    for p in &mut positions {
        let d = plane.signed_distance(p);
        if !d.is_finite() {
            return Err(CoreError::InvalidMesh(
                "a vertex of the mesh is not finite".into(),
            ));
        }
        let side = if d.abs() <= snap {
            *p -= plane.normal * d;
            Side::On
        } else if d < 0.0 {
            Side::Below
        } else {
            Side::Above
        };
        sides.push(side);
        dist.push(if side == Side::On { 0.0 } else { d });
    }
    let mut cut_vertices: HashMap<(u32, u32), u32> = HashMap::new();
    let mut triangles = Vec::with_capacity(mesh.triangles.len());
    for tri in &mesh.triangles {
        if tri.iter().any(|&v| v as usize >= sides.len()) {
            return Err(CoreError::InvalidMesh(format!(
                "triangle {tri:?} refers to a vertex beyond the {} vertices",
                sides.len()
            )));
        }
        let s = tri.map(|v| sides[v as usize]);
        match (s.contains(&Side::Below), s.contains(&Side::Above)) {
            (false, _) => continue,
            (true, false) => {
                triangles.push(*tri);
                continue;
            }
            (true, true) => {}
        }
        // Sutherland-Hodgman against the half-space below: 3 or 4 corners, in order.
        let mut poly: Vec<u32> = Vec::with_capacity(4);
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let (sa, sb) = (s[k], s[(k + 1) % 3]);
            if sa != Side::Above {
                poly.push(a);
            }
            let crosses = matches!(
                (sa, sb),
                (Side::Below, Side::Above) | (Side::Above, Side::Below)
            );
            if crosses {
                let key = (a.min(b), a.max(b));
                let v = *cut_vertices.entry(key).or_insert_with(|| {
                    let (pa, pb) = (positions[a as usize], positions[b as usize]);
                    let (da, db) = (dist[a as usize], dist[b as usize]);
                    let mut x = pa + (pb - pa) * (da / (da - db));
                    // Exactly in the plane, whatever the rounding of the interpolation.
                    x -= plane.normal * plane.signed_distance(&x);
                    positions.push(x);
                    (positions.len() - 1) as u32
                });
                poly.push(v);
            }
        }
        for k in 1..poly.len().saturating_sub(1) {
            triangles.push([poly[0], poly[k], poly[k + 1]]);
        }
    }
    let clipped = super::topology::compact(&TriMesh::new(positions, triangles))?;
    // Snapped and cut vertices were projected onto the plane: their distance is rounding only.
    let flags: Vec<bool> = clipped
        .positions
        .iter()
        .map(|p| plane.signed_distance(p).abs() <= IN_PLANE_MM)
        .collect();
    let loops = outline(&clipped, &flags)?;
    Ok(Clipped {
        mesh: clipped,
        loops,
    })
}

/// The boundary of `mesh` as loops; every boundary vertex must be flagged as in the plane and
/// pass the boundary once.
fn outline(mesh: &TriMesh, in_plane: &[bool]) -> Result<Vec<Vec<u32>>> {
    let map = EdgeMap::new(mesh);
    let mut next: HashMap<u32, u32> = HashMap::new();
    for (a, b) in boundary_half_edges(mesh, &map) {
        for v in [a, b] {
            if !in_plane.get(v as usize).copied().unwrap_or(false) {
                return Err(CoreError::InvalidMesh(
                    "the surface is open below the cut (a boundary edge off the plane)".into(),
                ));
            }
        }
        if next.insert(a, b).is_some() {
            return Err(CoreError::InvalidMesh(
                "the cut outline touches itself (a vertex on two boundary loops)".into(),
            ));
        }
    }
    let mut starts: Vec<u32> = next.keys().copied().collect();
    starts.sort_unstable();
    let mut seen: HashMap<u32, ()> = HashMap::new();
    let mut loops = Vec::new();
    for start in starts {
        if seen.contains_key(&start) {
            continue;
        }
        let mut ring = vec![start];
        seen.insert(start, ());
        let mut v = start;
        loop {
            let Some(&w) = next.get(&v) else {
                return Err(CoreError::InvalidMesh(
                    "the cut outline is not closed".into(),
                ));
            };
            if w == start {
                break;
            }
            if seen.insert(w, ()).is_some() {
                return Err(CoreError::InvalidMesh(
                    "the cut outline is not a simple loop".into(),
                ));
            }
            ring.push(w);
            v = w;
        }
        loops.push(ring);
    }
    Ok(loops)
}

/// The cut with only the connected piece of the mesh that ends at outline `keep`, or None when
/// another outline ends on that piece too (a piece with a hole across the plane, which no
/// choice of piece turns into one outline). A plane near the top of a surface can catch a fold
/// of it that dips below the plane on its own; that fold is no part of the surface's body below
/// the plane, and the caller decides (by its size) whether to leave it out.
pub fn keep_piece_of(cut: &Clipped, keep: usize) -> Option<Clipped> {
    let mesh = &cut.mesh;
    let nv = mesh.positions.len();
    // Union-find over the vertices of each triangle.
    let mut parent: Vec<usize> = (0..nv).collect();
    fn root(parent: &mut [usize], mut v: usize) -> usize {
        while parent[v] != v {
            parent[v] = parent[parent[v]];
            v = parent[v];
        }
        v
    }
    for t in &mesh.triangles {
        let a = root(&mut parent, t[0] as usize);
        for &w in &t[1..] {
            let b = root(&mut parent, w as usize);
            parent[b] = a;
        }
    }
    let piece = root(&mut parent, *cut.loops.get(keep)?.first()? as usize);
    for (k, l) in cut.loops.iter().enumerate() {
        if k != keep && l.iter().any(|&v| root(&mut parent, v as usize) == piece) {
            return None;
        }
    }
    let mut remap = vec![u32::MAX; nv];
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for t in &mesh.triangles {
        if root(&mut parent, t[0] as usize) != piece {
            continue;
        }
        triangles.push(t.map(|v| {
            let slot = &mut remap[v as usize];
            if *slot == u32::MAX {
                *slot = positions.len() as u32;
                positions.push(mesh.positions[v as usize]);
            }
            *slot
        }));
    }
    let ring = cut.loops[keep].iter().map(|&v| remap[v as usize]).collect();
    Some(Clipped {
        mesh: TriMesh::new(positions, triangles),
        loops: vec![ring],
    })
}

/// Mean edge length of a mesh (mm); 0 for a mesh without triangles.
pub fn mean_edge_length(mesh: &TriMesh) -> f64 {
    let mut sum = 0.0;
    let mut n = 0usize;
    for t in 0..mesh.triangles.len() {
        let c = mesh.corners(t);
        for k in 0..3 {
            sum += (c[(k + 1) % 3] - c[k]).norm();
            n += 1;
        }
    }
    if n == 0 {
        0.0
    } else {
        sum / n as f64
    }
}
