//! Light repair of reference meshes before they serve as ground truth: welding coincident vertices,
//! finding boundary loops, closing small holes.
//!
//! Reference meshes carry artefacts that are not anatomy: the Cardiac Atlas Project mean shape has
//! its apex vertex duplicated 29 times (an unwelded pole that reads as an apical hole). A truth
//! with a hole would charge the reconstruction (correctly closed there) with the hole's size, and a
//! false boundary misleads the choice of apex and base. Welding by a spatial hash and closing holes
//! with a centroid fan (the simplest case of Liepa, "Filling holes in meshes", SGP 2003) remove such
//! artefacts while leaving real openings (valve rims) untouched.

use crate::geometry::Vec3;
use crate::mesh::TriMesh;
use std::collections::{HashMap, HashSet};

/// Merges vertices closer than `tol_mm` (the first one of each cluster is kept), drops triangles that
/// become degenerate or duplicated, and drops unused vertices. Returns the mesh and the number of
/// vertices merged away.
pub fn weld(mesh: &TriMesh, tol_mm: f64) -> (TriMesh, usize) {
    let tol = tol_mm.max(0.0);
    let cell = if tol > 0.0 { tol } else { 1.0 };
    let key = |p: &Vec3| {
        (
            (p.x / cell).floor() as i64,
            (p.y / cell).floor() as i64,
            (p.z / cell).floor() as i64,
        )
    };
    let mut grid: HashMap<(i64, i64, i64), Vec<u32>> = HashMap::new();
    let mut rep: Vec<u32> = Vec::with_capacity(mesh.positions.len());
    let mut merged = 0;
    for (i, p) in mesh.positions.iter().enumerate() {
        let (kx, ky, kz) = key(p);
        let mut found = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(list) = grid.get(&(kx + dx, ky + dy, kz + dz)) {
                        for &j in list {
                            if (mesh.positions[j as usize] - p).norm() <= tol {
                                found = Some(j);
                                break 'search;
                            }
                        }
                    }
                }
            }
        }
        match found {
            Some(j) => {
                rep.push(j);
                merged += 1;
            }
            None => {
                rep.push(i as u32);
                grid.entry((kx, ky, kz)).or_default().push(i as u32);
            }
        }
    }
    let mut seen: HashSet<[u32; 3]> = HashSet::new();
    let mut triangles = Vec::with_capacity(mesh.triangles.len());
    for t in &mesh.triangles {
        if t.iter().any(|&v| v as usize >= rep.len()) {
            continue;
        }
        let r = [rep[t[0] as usize], rep[t[1] as usize], rep[t[2] as usize]];
        if r[0] == r[1] || r[1] == r[2] || r[0] == r[2] {
            continue;
        }
        // Rotation-invariant key so the same oriented triangle is kept once.
        let m = (0..3).min_by_key(|&k| r[k]).unwrap_or(0);
        if seen.insert([r[m], r[(m + 1) % 3], r[(m + 2) % 3]]) {
            triangles.push(r);
        }
    }
    // Compact: keep used vertices in first-use order.
    let mut remap = vec![u32::MAX; mesh.positions.len()];
    let mut positions = Vec::new();
    for t in &mut triangles {
        for v in t.iter_mut() {
            if remap[*v as usize] == u32::MAX {
                remap[*v as usize] = positions.len() as u32;
                positions.push(mesh.positions[*v as usize]);
            }
            *v = remap[*v as usize];
        }
    }
    (TriMesh::new(positions, triangles), merged)
}

/// Makes triangle orientation consistent across every manifold edge (breadth-first flood from the
/// first triangle of each connected patch), then flips closed patches with negative volume so
/// normals face outward. Returns the mesh and the number of triangles flipped. Some reference
/// meshes (biv-me's RV) mix orientations, which breaks volumes computed by the divergence theorem.
pub fn orient_consistently(mesh: &TriMesh) -> (TriMesh, usize) {
    let mut out = mesh.clone();
    let n = out.triangles.len();
    let mut by_edge: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (t, tri) in out.triangles.iter().enumerate() {
        for k in 0..3 {
            let (u, v) = (tri[k], tri[(k + 1) % 3]);
            by_edge.entry((u.min(v), u.max(v))).or_default().push(t);
        }
    }
    let has_directed =
        |tri: &[u32; 3], u: u32, v: u32| (0..3).any(|k| tri[k] == u && tri[(k + 1) % 3] == v);
    let mut visited = vec![false; n];
    let mut flipped = 0;
    for seed in 0..n {
        if visited[seed] {
            continue;
        }
        visited[seed] = true;
        let mut patch = vec![seed];
        let mut queue = std::collections::VecDeque::from([seed]);
        while let Some(t) = queue.pop_front() {
            let tri = out.triangles[t];
            for k in 0..3 {
                let (u, v) = (tri[k], tri[(k + 1) % 3]);
                let Some(nbrs) = by_edge.get(&(u.min(v), u.max(v))) else {
                    continue;
                };
                if nbrs.len() != 2 {
                    continue; // boundary or non-manifold edge: no constraint
                }
                for &o in nbrs {
                    if o == t || visited[o] {
                        continue;
                    }
                    // Consistent neighbours traverse the shared edge in the opposite direction.
                    if has_directed(&out.triangles[o], u, v) {
                        out.triangles[o].swap(1, 2);
                        flipped += 1;
                    }
                    visited[o] = true;
                    patch.push(o);
                    queue.push_back(o);
                }
            }
        }
        let vol: f64 = patch
            .iter()
            .map(|&t| {
                let [a, b, c] = out.corners(t);
                a.dot(&b.cross(&c))
            })
            .sum();
        if vol < 0.0 {
            for &t in &patch {
                out.triangles[t].swap(1, 2);
            }
            flipped += patch.len();
        }
    }
    (out, flipped)
}

/// Twice the largest distance of a loop's points from their centroid: a cheap diameter.
pub fn loop_diameter(mesh: &TriMesh, lp: &[u32]) -> f64 {
    if lp.is_empty() {
        return 0.0;
    }
    let c = lp.iter().map(|&v| mesh.positions[v as usize]).sum::<Vec3>() / lp.len() as f64;
    2.0 * lp
        .iter()
        .map(|&v| (mesh.positions[v as usize] - c).norm())
        .fold(0.0, f64::max)
}

/// Boundary loops as vertex sequences, each following the direction of its triangles' edges.
/// Boundaries that do not close into loops (non-manifold meshes) are skipped.
pub fn boundary_loops(mesh: &TriMesh) -> Vec<Vec<u32>> {
    let mut directed: HashSet<(u32, u32)> = HashSet::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            directed.insert((t[k], t[(k + 1) % 3]));
        }
    }
    let mut next: HashMap<u32, u32> = HashMap::new();
    let mut starts: Vec<u32> = Vec::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            let (u, v) = (t[k], t[(k + 1) % 3]);
            if !directed.contains(&(v, u)) && next.insert(u, v).is_none() {
                starts.push(u);
            }
        }
    }
    let mut seen: HashSet<u32> = HashSet::new();
    let mut loops = Vec::new();
    for s in starts {
        if seen.contains(&s) {
            continue;
        }
        let mut lp = vec![s];
        seen.insert(s);
        let mut cur = s;
        let closed = loop {
            let Some(&n) = next.get(&cur) else {
                break false;
            };
            if n == s {
                break true;
            }
            if !seen.insert(n) {
                break false;
            }
            lp.push(n);
            cur = n;
        };
        if closed && lp.len() >= 3 {
            loops.push(lp);
        }
    }
    loops
}

/// Closes every boundary loop whose perimeter is at most `max_perimeter_mm` with a fan around its
/// centroid; returns the new mesh and the number of holes closed.
pub fn close_small_holes(mesh: &TriMesh, max_perimeter_mm: f64) -> (TriMesh, usize) {
    let mut out = mesh.clone();
    let mut closed = 0;
    for lp in boundary_loops(mesh) {
        let pts: Vec<Vec3> = lp.iter().map(|&v| mesh.positions[v as usize]).collect();
        let perimeter: f64 = (0..pts.len())
            .map(|i| (pts[(i + 1) % pts.len()] - pts[i]).norm())
            .sum();
        if perimeter > max_perimeter_mm {
            continue;
        }
        let centre = pts.iter().sum::<Vec3>() / pts.len() as f64;
        out.positions.push(centre);
        let c = out.positions.len() as u32 - 1;
        for i in 0..lp.len() {
            let (u, v) = (lp[i], lp[(i + 1) % lp.len()]);
            // The boundary edge u->v belongs to an existing triangle: the fan traverses it v->u.
            out.triangles.push([v, u, c]);
        }
        closed += 1;
    }
    (out, closed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;
    use crate::sim::shapes::uv_sphere;

    #[test]
    fn weld_merges_an_unwelded_pole() {
        let sphere = uv_sphere(v3(0.0, 0.0, 0.0), 10.0, 16, 8);
        let mut m = sphere.clone();
        // Give every bottom-fan triangle its own copy of the pole (as the CAP atlas mean shape does).
        let n = m.positions.len() as u32;
        let pole = m.positions[0];
        let mut extra = 0;
        for t in &mut m.triangles {
            if t[0] == 0 {
                m.positions.push(pole);
                t[0] = n + extra;
                extra += 1;
            }
        }
        m.positions[0] += v3(0.0, 0.0, -100.0); // the original pole is now unused
        assert_eq!(boundary_loops(&m).len(), 1);
        let (w, merged) = weld(&m, 1e-6);
        assert_eq!(merged, extra as usize - 1);
        assert!(boundary_loops(&w).is_empty());
        assert_eq!(w.positions.len(), sphere.positions.len());
        assert!((w.signed_volume() - sphere.signed_volume()).abs() < 1e-9);
    }

    #[test]
    fn orientation_is_made_consistent_and_outward() {
        let sphere = uv_sphere(v3(1.0, 2.0, 3.0), 10.0, 24, 12);
        let mut m = sphere.clone();
        for (i, t) in m.triangles.iter_mut().enumerate() {
            if i % 3 == 0 || i < 30 {
                t.swap(1, 2);
            }
        }
        let (fixed, flipped) = orient_consistently(&m);
        assert!(flipped > 0);
        assert_eq!(fixed.triangles.len(), sphere.triangles.len());
        assert!((fixed.signed_volume() - sphere.signed_volume()).abs() < 1e-9);
        // Already consistent and outward: nothing to do.
        assert_eq!(orient_consistently(&sphere).1, 0);
    }

    #[test]
    fn pole_hole_is_closed_and_rim_is_kept() {
        let full = uv_sphere(v3(0.0, 0.0, 0.0), 10.0, 32, 16);
        // Remove the bottom pole fan (a small hole) and the upper half (a large opening).
        let mut m = full.clone();
        m.triangles = full
            .triangles
            .iter()
            .copied()
            .filter(|t| !t.contains(&0) && t.iter().all(|&v| full.positions[v as usize].z < 0.5))
            .collect();
        let loops = boundary_loops(&m);
        assert_eq!(loops.len(), 2);
        let (closed, n) = close_small_holes(&m, 20.0);
        assert_eq!(n, 1);
        assert_eq!(boundary_loops(&closed).len(), 1);
        // Closing the whole sphere's pole hole gives back a watertight, outward sphere.
        let mut holed = full.clone();
        holed.triangles.retain(|t| !t.contains(&0));
        let (refilled, n) = close_small_holes(&holed, 20.0);
        assert_eq!(n, 1);
        assert!(boundary_loops(&refilled).is_empty());
        let (v0, v1) = (full.signed_volume(), refilled.signed_volume());
        assert!((v0 - v1).abs() / v0 < 1e-3, "{v0} vs {v1}");
    }
}
