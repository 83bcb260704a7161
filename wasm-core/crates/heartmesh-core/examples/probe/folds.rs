//! PROBE_FOLDS=1: how the folds of the final remesh-free steps form. Keeps a snapshot of the mesh
//! after every step of the last remesh interval (same triangles throughout), then, for every edge
//! folded at the end, prints its dihedral angle step by step and the attractors near it: their
//! contour kind, distance to the mesh, and whether their closest point lies on a triangle that
//! faces them (front) or turns its back to them (back: the point landed on the wrong wall).
use heartmesh_core::geometry::Vec3;
use heartmesh_core::mesh::quality::{dihedral_deg, face_normals, FOLD_DEG};
use heartmesh_core::mesh::topology::EdgeMap;
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::spatial::Bvh;

/// One step of the final phase: the mesh after it and the attractors it used.
pub struct Snapshot {
    pub iteration: usize,
    pub mesh: TriMesh,
    pub attractors: Vec<Vec3>,
}

/// Prints the history of every fold of the last snapshot. `kind_of` tells an attractor's contour
/// kind (true: long axis); `height` maps a point to mm above the apex.
pub fn report(snaps: &[Snapshot], kind_of: &dyn Fn(&Vec3) -> bool, height: &dyn Fn(&Vec3) -> f64) {
    let Some(last) = snaps.last() else { return };
    // Snapshots since the last topology change.
    let first = snaps
        .iter()
        .rposition(|s| s.mesh.triangles != last.mesh.triangles)
        .map_or(0, |i| i + 1);
    let run = &snaps[first..];
    let map = EdgeMap::new(&last.mesh);
    let normals: Vec<_> = run.iter().map(|s| face_normals(&s.mesh)).collect();
    let folded: Vec<usize> = (0..map.edges.len())
        .filter(|&e| {
            dihedral_deg(&map, &normals[normals.len() - 1], e).is_some_and(|a| a > FOLD_DEG)
        })
        .collect();
    println!(
        "fold history from iteration {} ({} folded edges at the end)",
        run[0].iteration,
        folded.len()
    );
    for s in run {
        let n = face_normals(&s.mesh);
        let c = (0..map.edges.len())
            .filter(|&e| dihedral_deg(&map, &n, e).is_some_and(|a| a > FOLD_DEG))
            .count();
        print!("{}:{} ", s.iteration, c);
    }
    println!();
    for &e in &folded {
        let [u, v] = map.edges[e];
        let traj: Vec<String> = normals
            .iter()
            .enumerate()
            .filter(|(k, _)| k % 4 == 0 || *k == normals.len() - 1)
            .map(|(_, n)| format!("{:.0}", dihedral_deg(&map, n, e).unwrap_or(f64::NAN)))
            .collect();
        let m = (last.mesh.positions[u as usize] + last.mesh.positions[v as usize]) * 0.5;
        let len = (last.mesh.positions[u as usize] - last.mesh.positions[v as usize]).norm();
        println!(
            "edge {u}-{v} at h {:.1} len {len:.2}: dihedral every 4 steps {}",
            height(&m),
            traj.join(" ")
        );
        // Attractors near the fold at the step where it first passed 90 degrees.
        let k = normals
            .iter()
            .position(|n| dihedral_deg(&map, n, e).is_some_and(|a| a > FOLD_DEG))
            .unwrap_or(0);
        let before = if k > 0 { &run[k - 1] } else { &run[0] };
        let bvh = Bvh::build(&before.mesh);
        let fn_before = face_normals(&before.mesh);
        let mb = (before.mesh.positions[u as usize] + before.mesh.positions[v as usize]) * 0.5;
        let mut near: Vec<(f64, String)> = run[k]
            .attractors
            .iter()
            .filter(|q| (*q - mb).norm() < 8.0)
            .filter_map(|q| {
                let h = bvh.closest_point(&before.mesh, *q)?;
                let side = fn_before[h.triangle as usize]
                    .map_or("?", |n| if n.dot(&(q - h.point)) >= 0.0 { "out" } else { "in" });
                let moved = (h.point - mb).norm();
                Some((
                    (q - mb).norm(),
                    format!(
                        "{} at {:.1} mm from the edge, {:.2} mm off the mesh ({side}), closest point {:.1} mm from the edge",
                        if kind_of(q) { "LAX" } else { "SAX" },
                        (q - mb).norm(),
                        h.distance_sq.sqrt(),
                        moved
                    ),
                ))
            })
            .collect();
        near.sort_by(|a, b| a.0.total_cmp(&b.0));
        // The attractors within 4 mm of the fold: their distance to the mesh, every 4 steps, and
        // where their closest point lies (v: at a vertex, e: on an edge, f: inside a face).
        for q in run[k].attractors.iter().filter(|q| (*q - mb).norm() < 4.0) {
            let traj: Vec<String> = run
                .iter()
                .enumerate()
                .filter(|(i, s)| (i % 4 == 0 || *i == run.len() - 1) && s.attractors.contains(q))
                .filter_map(|(_, s)| {
                    let h = Bvh::build(&s.mesh).closest_point(&s.mesh, *q)?;
                    let c = s.mesh.corners(h.triangle as usize);
                    let at = c.iter().filter(|v| (*v - h.point).norm() < 1e-6).count();
                    let on_edge = (0..3).any(|j| {
                        let (a, b) = (c[j], c[(j + 1) % 3]);
                        let t =
                            ((h.point - a).dot(&(b - a)) / (b - a).norm_squared()).clamp(0.0, 1.0);
                        (a + (b - a) * t - h.point).norm() < 1e-6
                    });
                    let tag = if at > 0 {
                        "v"
                    } else if on_edge {
                        "e"
                    } else {
                        "f"
                    };
                    Some(format!("{:.2}{tag}", h.distance_sq.sqrt()))
                })
                .collect();
            println!(
                "    attractor {:.1} mm from the fold: distance {}",
                (q - mb).norm(),
                traj.join(" ")
            );
        }
        println!(
            "  first folded at iteration {}; attractors within 8 mm:",
            run[k].iteration
        );
        for (_, s) in near.iter().take(8) {
            println!("    {s}");
        }
    }
}

/// PROBE_STAGES=K: the remesh's three stages applied to the mesh after step K, with the folds and
/// the largest dihedral after each (which stage makes a fold).
pub fn stages(mesh: &TriMesh) -> Result<(), heartmesh_core::CoreError> {
    use heartmesh_core::mesh::quality::quality;
    use heartmesh_core::refine::{decimate, smooth, subdivide};
    let show = |name: &str, m: &TriMesh| {
        let q = quality(m);
        println!(
            "  stage {name}: {} triangles, folds {}, max dihedral {:.0}, min q {:.3}",
            m.triangles.len(),
            q.folded_edges,
            q.max_dihedral_deg,
            q.min_triangle_quality
        );
    };
    show("input", mesh);
    let s = subdivide(mesh)?;
    show("subdivided", &s);
    let m = smooth(&s, 200, 0.1)?;
    show("smoothed", &m);
    let d = decimate(&m, 0.72)?;
    show("decimated", &d);
    Ok(())
}

/// Largest turning angle (degrees, over 3 mm of arc each side) of any contour at a point within
/// `radius` of `at`: a corner in the data (e.g. where an RV free wall meets the septum).
pub fn sharpest_turn(set: &heartmesh_core::ContourSet, at: &Vec3, radius: f64) -> f64 {
    let mut best = 0.0f64;
    for c in &set.contours {
        for piece in &c.pieces {
            let p = &piece.points;
            let n = p.len();
            for i in 0..n {
                if (p[i] - at).norm() > radius {
                    continue;
                }
                // Walk 3 mm of arc each way (wrapping on a closed piece).
                let walk = |dir: isize| -> Option<Vec3> {
                    let (mut j, mut len) = (i as isize, 0.0);
                    while len < 3.0 {
                        let k = j + dir;
                        let k = if piece.closed {
                            k.rem_euclid(n as isize)
                        } else {
                            k
                        };
                        if k < 0 || k >= n as isize || k as usize == i {
                            return None;
                        }
                        len += (p[k as usize] - p[j as usize]).norm();
                        j = k;
                    }
                    Some(p[j as usize])
                };
                if let (Some(a), Some(b)) = (walk(-1), walk(1)) {
                    let (u, v) = (p[i] - a, b - p[i]);
                    let c = u.dot(&v) / (u.norm() * v.norm());
                    best = best.max(c.clamp(-1.0, 1.0).acos().to_degrees());
                }
            }
        }
    }
    best
}
