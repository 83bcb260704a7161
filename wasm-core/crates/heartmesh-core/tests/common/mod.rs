//! Shared helpers of the accuracy and real-case integration tests: fixture paths, running a full
//! reconstruction at the defaults, contour-to-mesh distances and mesh validity checks.
#![allow(dead_code)] // each test binary uses a subset

use heartmesh_core::contours::plane::fit_plane;
use heartmesh_core::contours::{Contour, ContourSet};
use heartmesh_core::geometry::Vec3;
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::pipeline::Reconstruction;
use heartmesh_core::spatial::Bvh;
use heartmesh_core::{io, Params};
use std::collections::HashMap;
use std::path::PathBuf;
use std::time::Instant;

/// `shared/data/<sub>`: the test data beside the repository (`../shared` of the checkout, as CI
/// lays it out: CARGO_MANIFEST_DIR/../../../../shared/data), or beside any ancestor directory
/// (git worktrees live deeper).
pub fn data_path(sub: &str) -> PathBuf {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let found = manifest
        .ancestors()
        .map(|a| a.join("shared/data"))
        .find(|d| d.is_dir());
    found
        .unwrap_or_else(|| manifest.join("../../../../shared/data"))
        .join(sub)
}

pub fn load_mesh(name: &str) -> TriMesh {
    let path = data_path(&format!("meshes/{name}"));
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    io::read_mesh(name, &bytes)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .mesh
}

/// A reference mesh as ground truth: welded (the CAP atlas mean shape has an unwelded apex) and
/// consistently oriented (biv-me's RV mixes orientations, which spoils volumes).
pub fn load_truth(name: &str) -> TriMesh {
    use heartmesh_core::sim::repair::{orient_consistently, weld};
    orient_consistently(&weld(&load_mesh(name), 1e-6).0).0
}

/// The spasm subject's RV cavity: its RV free wall plus the septal part of its LV epicardium.
pub fn spasm_rv_cavity() -> TriMesh {
    heartmesh_core::sim::cavity::rv_cavity(
        &load_truth("cardiomesh-spasm-RV_endo.obj"),
        &load_truth("cardiomesh-spasm-LV_epi.obj"),
        40.0,
    )
    .unwrap_or_else(|e| panic!("spasm RV cavity: {e}"))
}

pub fn load_contours(sub: &str) -> ContourSet {
    let path = data_path(&format!("contours/{sub}"));
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    io::read_contours(sub, &bytes).unwrap_or_else(|e| panic!("{sub}: {e}"))
}

/// Runs a reconstruction to the end at the given parameters; returns the mesh and the seconds taken.
pub fn reconstruct(set: &ContourSet, params: Params) -> (TriMesh, f64) {
    let t0 = Instant::now();
    let mut rec = Reconstruction::new(set, params).unwrap_or_else(|e| panic!("new: {e}"));
    let mut steps = 0;
    loop {
        let report = rec.step().unwrap_or_else(|e| panic!("step {steps}: {e}"));
        steps += 1;
        if report.done {
            break;
        }
        assert!(steps < 100_000, "reconstruction never reported done");
    }
    (rec.mesh().clone(), t0.elapsed().as_secs_f64())
}

/// The contours of `set` that delineate `surface`.
pub fn surface_contours(set: &ContourSet, surface: &str) -> Vec<Contour> {
    set.contours
        .iter()
        .filter(|c| c.surface.as_deref() == Some(surface))
        .cloned()
        .collect()
}

/// Distance in mm from every point of `set`'s `surface` contours to `mesh`.
pub fn surface_to_mesh(set: &ContourSet, surface: &str, mesh: &TriMesh) -> Vec<f64> {
    contour_to_mesh_of(&surface_contours(set, surface), mesh)
}

/// Distance in mm from every contour point of `set` to the surface of `mesh`.
pub fn contour_to_mesh(set: &ContourSet, mesh: &TriMesh) -> Vec<f64> {
    contour_to_mesh_of(&set.contours, mesh)
}

/// Distance in mm from every point of `contours` to `mesh` (own BVH query, independent of the
/// pipeline's measure).
pub fn contour_to_mesh_of(contours: &[Contour], mesh: &TriMesh) -> Vec<f64> {
    let bvh = Bvh::build(mesh);
    contours
        .iter()
        .flat_map(|c| c.points())
        .map(|p| {
            bvh.closest_point(mesh, *p)
                .map_or(f64::INFINITY, |h| h.distance_sq.sqrt())
        })
        .collect()
}

pub fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

pub fn max(v: &[f64]) -> f64 {
    v.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
}

/// Closed (every edge in exactly two triangles), manifold and consistently oriented (each edge
/// traversed once in each direction), with positive enclosed volume (outward normals). Returns a
/// description of the first problem found.
pub fn check_closed_manifold_outward(mesh: &TriMesh) -> Result<(), String> {
    if mesh.triangles.is_empty() {
        return Err("empty mesh".into());
    }
    let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &mesh.triangles {
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            return Err(format!("degenerate triangle {t:?}"));
        }
        if t.iter().any(|&v| v as usize >= mesh.positions.len()) {
            return Err(format!("triangle {t:?} indexes past the vertices"));
        }
        for k in 0..3 {
            *directed.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    for (&(u, v), &n) in &directed {
        if n != 1 {
            return Err(format!(
                "edge {u}->{v} used {n} times in the same direction"
            ));
        }
        if !directed.contains_key(&(v, u)) {
            return Err(format!(
                "edge {u}-{v} is a boundary or inconsistently oriented"
            ));
        }
    }
    if !mesh
        .positions
        .iter()
        .all(|p| p.iter().all(|c| c.is_finite()))
    {
        return Err("non-finite vertex".into());
    }
    let vol = mesh.signed_volume();
    if vol <= 0.0 {
        return Err(format!(
            "signed volume {vol} mm^3 is not positive (inward normals)"
        ));
    }
    Ok(())
}

/// Height of a point as a fraction of the shape's extent along an axis (0 = apex, 1 = base).
pub fn height_fraction(p: &Vec3, lo: f64, hi: f64, centre: &Vec3, dir: &Vec3) -> f64 {
    (dir.dot(&(p - centre)) - lo) / (hi - lo)
}

/// For every point of `surface` in `cvi` (contours read from pixels: a cvi42 workspace, Sunnybrook
/// files): its distance from the nearest point of the GPFile's same surface, measured in the
/// contour's image plane (the fixtures moved each point onto its plane), and how many contours.
pub fn in_plane_gaps(cvi: &ContourSet, gp: &ContourSet, surface: &str) -> (Vec<f64>, usize) {
    let theirs: Vec<Vec3> = gp
        .contours
        .iter()
        .filter(|c| c.surface.as_deref() == Some(surface))
        .flat_map(|c| c.points().copied().collect::<Vec<_>>())
        .collect();
    let mut gaps = Vec::new();
    let mut contours = 0;
    for c in cvi
        .contours
        .iter()
        .filter(|c| c.surface.as_deref() == Some(surface))
    {
        contours += 1;
        let plane = fit_plane(c.points()).unwrap();
        assert!(plane.max_residual < 1e-6, "{}: off its image plane", c.id);
        let n = plane.normal;
        for p in c.points() {
            let in_plane = |q: &Vec3| {
                let d = q - p;
                (d - n * d.dot(&n)).norm() + if d.dot(&n).abs() > 3.0 { 1e9 } else { 0.0 }
            };
            let gap = theirs.iter().map(in_plane).fold(f64::INFINITY, f64::min);
            gaps.push(gap);
        }
    }
    (gaps, contours)
}

/// Asserts that `ours` (contours read from pixels) holds as many `surface` contours as the GPFile
/// `gp` and that each point lies within `rounding` mm of a GPFile point in its image plane;
/// prints the figures under `tag` (e.g. "CVI42 frame None").
pub fn assert_on_gpfile_points(
    tag: &str,
    ours: &ContourSet,
    gp: &ContourSet,
    surface: &str,
    rounding: f64,
) {
    let (gaps, n) = in_plane_gaps(ours, gp, surface);
    let theirs = gp
        .contours
        .iter()
        .filter(|c| c.surface.as_deref() == Some(surface))
        .count();
    eprintln!(
        "{tag} {surface}: {n} contours ({theirs} in the GPFile), {} points, in-plane gap mean \
         {:.4} max {:.4} mm",
        gaps.len(),
        mean(&gaps),
        max(&gaps)
    );
    assert_eq!(n, theirs, "{surface}");
    assert!(max(&gaps) <= rounding + 1e-9, "{surface}: {}", max(&gaps));
}
