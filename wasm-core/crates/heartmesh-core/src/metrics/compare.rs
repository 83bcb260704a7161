//! Mesh-to-mesh comparison against a ground truth, as in the validation of Villard, Grau & Zacur
//! (J. Imaging 2018, section 3): distances both ways, Hausdorff distance and volumes, with both
//! surfaces clipped at the most basal short-axis plane (the paper compares only what the contours
//! cover).
//!
//! Both surfaces are sampled densely and uniformly by area (every triangle split into k x k equal
//! sub-triangles of at most ~1 mm^2, one sample at each centroid, weighted by its area, plus every
//! vertex for the maximum), in the spirit of the sampled surface distances of METRO (Cignoni,
//! Rocchini & Scopigno, Computer Graphics Forum 1998). Weighting by area makes the statistics a
//! property of the surfaces, not of their tessellations. Distances go to the whole other surface,
//! so the clip adds no artificial boundary to measure against.

use crate::contours::ContourSet;
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::TriMesh;
use crate::params::Params;
use crate::pipeline::Reconstruction;
use crate::sim::slice::Plane;
use crate::spatial::Bvh;
use serde::Serialize;

/// A clipping plane: points with `signed_distance > 0` (the basal side, where the normal points)
/// are left out of every measure.
pub type ClipPlane = Plane;

/// Area-weighted distance statistics in mm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DistanceStats {
    pub mean: f64,
    pub median: f64,
    pub p95: f64,
    /// Largest distance over the samples and the vertices.
    pub max: f64,
    /// Where the largest distance occurs (a point of the measured surface, mm): the place to look.
    pub max_at: [f64; 3],
    pub min: f64,
    /// Number of area samples measured.
    pub count: usize,
}

/// Result of [`compare`]; field names are the `heartmesh compare --json` contract (issue 5).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CompareReport {
    /// From points of the reconstructed mesh to the truth surface.
    pub mesh_to_truth: DistanceStats,
    /// From points of the truth surface to the reconstructed mesh.
    pub truth_to_mesh: DistanceStats,
    /// max(mesh_to_truth.max, truth_to_mesh.max).
    pub hausdorff: f64,
    /// Enclosed volumes in ml; with a clip plane, of the parts below it closed by a flat cap.
    pub volume_truth_ml: f64,
    pub volume_mesh_ml: f64,
    /// True when a clip plane was applied.
    pub clipped: bool,
}

/// Target area per sample, mm^2.
const SAMPLE_AREA_MM2: f64 = 1.0;
/// Subdivisions per triangle edge are capped so a single huge triangle cannot exhaust memory.
const MAX_SPLITS: usize = 400;

/// Compares a reconstruction `mesh` with the `truth`, both clipped at `clip` when given.
pub fn compare(truth: &TriMesh, mesh: &TriMesh, clip: Option<&ClipPlane>) -> Result<CompareReport> {
    let truth_bvh = Bvh::build(truth);
    let mesh_bvh = Bvh::build(mesh);
    let mesh_to_truth = directed(mesh, truth, &truth_bvh, clip)?;
    let truth_to_mesh = directed(truth, mesh, &mesh_bvh, clip)?;
    Ok(CompareReport {
        hausdorff: mesh_to_truth.max.max(truth_to_mesh.max),
        mesh_to_truth,
        truth_to_mesh,
        volume_truth_ml: clipped_volume_mm3(truth, clip).abs() / 1000.0,
        volume_mesh_ml: clipped_volume_mm3(mesh, clip).abs() / 1000.0,
        clipped: clip.is_some(),
    })
}

/// The most basal short-axis plane of a contour set, as the pipeline classifies and orders it (the
/// paper clips there): the normal is the long axis, pointing to the base. `params` selects the
/// surface of multi-surface files.
pub fn clip_plane_from_contours(set: &ContourSet, params: Params) -> Result<ClipPlane> {
    basal_plane(&Reconstruction::new(set, params)?)
}

/// The most basal short-axis plane of a reconstruction: the normal is its long axis, pointing to
/// the base.
pub fn basal_plane(rec: &Reconstruction) -> Result<ClipPlane> {
    let axis = rec.long_axis();
    let top = rec
        .slice_heights()
        .into_iter()
        .fold(f64::NEG_INFINITY, f64::max);
    Plane::new(axis * top, axis)
        .ok_or_else(|| CoreError::Degenerate("no short-axis slice to clip at".into()))
}

/// The base of the wall between two surfaces of one heart (endo- and epicardium): the lower of
/// their most basal short-axis planes, along the first's long axis, so that both surfaces stand
/// on their own slices everywhere below it.
pub fn common_basal_plane(first: &Reconstruction, second: &Reconstruction) -> Result<Plane> {
    Ok(common_basal_plane_with(
        basal_plane(first)?,
        basal_plane(second)?,
    ))
}

/// The lower of two basal planes along the first's normal.
fn common_basal_plane_with(a: Plane, b: Plane) -> Plane {
    let (ha, hb) = (a.normal.dot(&a.origin), a.normal.dot(&b.origin));
    if hb < ha {
        Plane {
            origin: a.normal * hb,
            normal: a.normal,
        }
    } else {
        a
    }
}

/// [`common_basal_plane`] of any number of surfaces (a biventricular wall's three): the lowest
/// of their most basal short-axis planes, along the first's long axis.
pub fn common_basal_plane_all(surfaces: &[&Reconstruction]) -> Result<Plane> {
    let (first, rest) = surfaces
        .split_first()
        .ok_or_else(|| CoreError::Degenerate("no surface to find a base plane of".into()))?;
    let mut plane = basal_plane(first)?;
    for s in rest {
        plane = common_basal_plane_with(plane, basal_plane(s)?);
    }
    Ok(plane)
}

/// [`common_basal_plane`] of two surfaces of a contour file (e.g. LV_ENDO and LV_EPI), from the
/// contours alone: the slices and the long axis are fixed when a reconstruction is set up, so
/// callers holding only the finished meshes (the app) get the plane the command line uses.
pub fn common_basal_plane_of(
    set: &ContourSet,
    params: &Params,
    first: &str,
    second: &str,
) -> Result<Plane> {
    let setup = |surface: &str| {
        Reconstruction::new(
            set,
            Params {
                surface: Some(surface.to_string()),
                ..params.clone()
            },
        )
    };
    common_basal_plane(&setup(first)?, &setup(second)?)
}

/// Distance statistics from the surface of `from` to the surface of `to`.
pub fn directed(
    from: &TriMesh,
    to: &TriMesh,
    to_bvh: &Bvh,
    clip: Option<&ClipPlane>,
) -> Result<DistanceStats> {
    let keep = |p: &Vec3| clip.is_none_or(|c| c.signed_distance(p) <= 0.0);
    let dist = |p: &Vec3| -> Result<f64> {
        to_bvh
            .closest_point(to, *p)
            .map(|h| h.distance_sq.sqrt())
            .ok_or_else(|| CoreError::InvalidMesh("compared mesh has no triangle".into()))
    };
    let mut samples: Vec<(f64, f64)> = Vec::new();
    let mut err = None;
    let mut max = f64::NEG_INFINITY;
    let mut max_at = Vec3::zeros();
    let mut min = f64::INFINITY;
    let mut record = |p: &Vec3, d: f64| {
        if d > max {
            max = d;
            max_at = *p;
        }
        min = min.min(d);
    };
    for_each_sample(from, |p, w| {
        if err.is_some() || !keep(&p) {
            return;
        }
        match dist(&p) {
            Ok(d) => {
                record(&p, d);
                samples.push((d, w));
            }
            Err(e) => err = Some(e),
        }
    });
    if let Some(e) = err {
        return Err(e);
    }
    if samples.is_empty() {
        return Err(CoreError::InvalidMesh(
            "nothing left to measure below the clip plane".into(),
        ));
    }
    for p in from.positions.iter().filter(|p| keep(p)) {
        record(p, dist(p)?);
    }
    Ok(weighted_stats(samples, max, max_at, min))
}

/// Distance from every vertex of `truth` to `mesh` (the colour map on the truth).
pub fn vertex_distances(truth: &TriMesh, mesh: &TriMesh) -> Vec<f64> {
    let bvh = Bvh::build(mesh);
    truth
        .positions
        .iter()
        .map(|p| {
            bvh.closest_point(mesh, *p)
                .map_or(f64::NAN, |h| h.distance_sq.sqrt())
        })
        .collect()
}

/// Calls `f(point, area)` for the area samples of `mesh` (see the module docs).
pub fn for_each_sample(mesh: &TriMesh, mut f: impl FnMut(Vec3, f64)) {
    for t in 0..mesh.triangles.len() {
        if mesh.triangles[t]
            .iter()
            .any(|&v| v as usize >= mesh.positions.len())
        {
            continue;
        }
        let [a, b, c] = mesh.corners(t);
        let (ab, ac) = (b - a, c - a);
        let area = 0.5 * ab.cross(&ac).norm();
        if !(area.is_finite() && area > 0.0) {
            continue;
        }
        let k = ((area / SAMPLE_AREA_MM2).sqrt().ceil() as usize).clamp(1, MAX_SPLITS);
        let w = area / (k * k) as f64;
        let kf = k as f64;
        for i in 0..k {
            for j in 0..k - i {
                // Upward sub-triangle centroid...
                f(
                    a + ab * ((i as f64 + 1.0 / 3.0) / kf) + ac * ((j as f64 + 1.0 / 3.0) / kf),
                    w,
                );
                // ...and the downward one beside it.
                if i + j + 1 < k {
                    f(
                        a + ab * ((i as f64 + 2.0 / 3.0) / kf) + ac * ((j as f64 + 2.0 / 3.0) / kf),
                        w,
                    );
                }
            }
        }
    }
}

/// Mean and quantiles of distances weighted by area; `max`/`min` come from the caller (samples and
/// vertices).
fn weighted_stats(mut samples: Vec<(f64, f64)>, max: f64, max_at: Vec3, min: f64) -> DistanceStats {
    samples.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: f64 = samples.iter().map(|s| s.1).sum();
    let mean = samples.iter().map(|s| s.0 * s.1).sum::<f64>() / total;
    let quantile = |q: f64| {
        let target = q * total;
        let mut acc = 0.0;
        for s in &samples {
            acc += s.1;
            if acc >= target {
                return s.0;
            }
        }
        samples.last().map_or(f64::NAN, |s| s.0)
    };
    DistanceStats {
        mean,
        median: quantile(0.5),
        p95: quantile(0.95),
        max,
        max_at: [max_at.x, max_at.y, max_at.z],
        min,
        count: samples.len(),
    }
}

/// Signed volume (mm^3) of the part of `mesh` below `clip`, closed by the flat cap in the plane
/// (the cap's contribution vanishes because the apex of every tetrahedron is on the plane); without
/// a clip, the ordinary enclosed volume (meaningful for closed meshes only).
pub fn clipped_volume_mm3(mesh: &TriMesh, clip: Option<&ClipPlane>) -> f64 {
    let Some(plane) = clip else {
        return mesh.signed_volume();
    };
    let o = plane.origin;
    let tet = |a: &Vec3, b: &Vec3, c: &Vec3| (a - o).dot(&(b - o).cross(&(c - o))) / 6.0;
    let mut vol = 0.0;
    for t in 0..mesh.triangles.len() {
        if mesh.triangles[t]
            .iter()
            .any(|&v| v as usize >= mesh.positions.len())
        {
            continue;
        }
        let corners = mesh.corners(t);
        let d: Vec<f64> = corners.iter().map(|p| plane.signed_distance(p)).collect();
        // Sutherland-Hodgman against the half-space d <= 0: at most 4 vertices.
        let mut poly: Vec<Vec3> = Vec::with_capacity(4);
        for k in 0..3 {
            let (p, q) = (corners[k], corners[(k + 1) % 3]);
            let (dp, dq) = (d[k], d[(k + 1) % 3]);
            if dp <= 0.0 {
                poly.push(p);
            }
            if (dp <= 0.0) != (dq <= 0.0) {
                poly.push(p + (q - p) * (dp / (dp - dq)));
            }
        }
        for k in 1..poly.len().saturating_sub(1) {
            vol += tet(&poly[0], &poly[k], &poly[k + 1]);
        }
    }
    vol
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;
    use crate::sim::shapes::uv_sphere;
    use std::f64::consts::PI;

    #[test]
    fn concentric_spheres_are_one_mm_apart_both_ways() {
        let inner = uv_sphere(v3(1.0, 2.0, 3.0), 10.0, 128, 64);
        let outer = uv_sphere(v3(1.0, 2.0, 3.0), 11.0, 160, 80);
        let r = compare(&inner, &outer, None).unwrap();
        for s in [r.mesh_to_truth, r.truth_to_mesh] {
            assert!((s.mean - 1.0).abs() < 0.02, "{s:?}");
            assert!((s.median - 1.0).abs() < 0.02, "{s:?}");
            assert!((s.p95 - 1.0).abs() < 0.02, "{s:?}");
            assert!((s.max - 1.0).abs() < 0.02, "{s:?}");
            assert!((s.min - 1.0).abs() < 0.02, "{s:?}");
        }
        assert!((r.hausdorff - 1.0).abs() < 0.02);
        let vt = 4.0 / 3.0 * PI * 1.0;
        let vm = 4.0 / 3.0 * PI * 1.331;
        assert!(
            (r.volume_truth_ml - vt).abs() / vt < 0.01,
            "{}",
            r.volume_truth_ml
        );
        assert!(
            (r.volume_mesh_ml - vm).abs() / vm < 0.01,
            "{}",
            r.volume_mesh_ml
        );
        // At least one sample per mm^2 (outer area 1520 mm^2) and per triangle.
        assert!(r.mesh_to_truth.count >= outer.triangles.len().max(1520));
    }

    #[test]
    fn sphere_against_itself_and_a_retessellation() {
        let a = uv_sphere(v3(0.0, 0.0, 0.0), 10.0, 96, 48);
        let r = compare(&a, &a, None).unwrap();
        assert!(r.hausdorff < 1e-9, "{r:?}");
        // A different tessellation of the same sphere: only the faceting error (< 0.03 mm) remains.
        let b = uv_sphere(v3(0.0, 0.0, 0.0), 10.0, 200, 100);
        let r = compare(&a, &b, None).unwrap();
        assert!(r.hausdorff < 0.03, "{r:?}");
        assert!(
            r.truth_to_mesh.mean < 0.02 && r.mesh_to_truth.mean < 0.02,
            "{r:?}"
        );
    }

    #[test]
    fn clipping_keeps_the_apical_side_and_caps_the_volume() {
        let inner = uv_sphere(v3(0.0, 0.0, 0.0), 10.0, 128, 64);
        let outer = uv_sphere(v3(0.0, 0.0, 0.0), 11.0, 128, 64);
        let clip = Plane::new(v3(0.0, 0.0, 0.0), v3(0.0, 0.0, 1.0)).unwrap();
        let r = compare(&inner, &outer, Some(&clip)).unwrap();
        assert!(r.clipped);
        assert!((r.truth_to_mesh.mean - 1.0).abs() < 0.02);
        // Half spheres: half the volume.
        let vt = 2.0 / 3.0 * PI * 1.0;
        assert!(
            (r.volume_truth_ml - vt).abs() / vt < 0.01,
            "{}",
            r.volume_truth_ml
        );
        // Half the samples of the unclipped comparison.
        let full = compare(&inner, &outer, None).unwrap();
        let ratio = r.truth_to_mesh.count as f64 / full.truth_to_mesh.count as f64;
        assert!((ratio - 0.5).abs() < 0.02, "{ratio}");
        // A plane below everything leaves nothing to measure: a typed error, no panic.
        let below = Plane::new(v3(0.0, 0.0, -50.0), v3(0.0, 0.0, 1.0)).unwrap();
        assert_eq!(
            compare(&inner, &outer, Some(&below)).unwrap_err().code(),
            "invalid_mesh"
        );
    }

    #[test]
    fn offset_region_shows_in_max_not_mean() {
        // Truth: sphere r = 10; "reconstruction": the same with a 10-degree polar cap pushed out.
        let truth = uv_sphere(v3(0.0, 0.0, 0.0), 10.0, 96, 48);
        let mut mesh = truth.clone();
        for p in &mut mesh.positions {
            if p.z > 9.9 {
                *p *= 1.2;
            }
        }
        let r = compare(&truth, &mesh, None).unwrap();
        assert!(r.hausdorff > 1.5, "{r:?}");
        // The worst place is on the pushed-out cap (a point of the measured mesh, z > 9.9 * 1.2).
        assert!(r.mesh_to_truth.max_at[2] > 11.0, "{r:?}");
        assert!(r.truth_to_mesh.mean < 0.05, "{r:?}");
        assert!(r.truth_to_mesh.median < 1e-9, "{r:?}");
    }
}
