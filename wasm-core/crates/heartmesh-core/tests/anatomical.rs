//! The anatomical layout (`metrics::anatomical`, `reconstruct --anatomical-mesh`) against the
//! truth: a reference LV sliced as an acquisition, reconstructed at the defaults, laid out, and
//! each grid vertex compared with the same vertex of the layout the truth surface itself gives at
//! the same base plane and septum. That distance is what shape analysis inherits from the
//! reconstruction: where vertex k of one heart lies against vertex k of another.
//!
//! Run with `--nocapture` for the `ANATOMICAL` lines (docs/VALIDATION.md).

mod common;

use common::*;
use heartmesh_core::geometry::Vec3;
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::metrics::anatomical::{build, Layout};
use heartmesh_core::metrics::compare::basal_plane;
use heartmesh_core::metrics::segments::Orientation;
use heartmesh_core::sim::planes::simulate_surfaces;
use heartmesh_core::sim::{AcquisitionSpec, Misalignment};
use heartmesh_core::{Params, Reconstruction};

/// A grid vertex may lie this far from the truth's, on average (mm): the surface's own mean
/// error (issue 2: LV <= 0.2 mm) plus what sliding along the surface adds where the ring
/// sections or the apex's rays meet it at a slant.
const MEAN_MM: f64 = 0.5;
/// With every plane shifted up to 2 mm and tilted up to 2 degrees (the surface is then held to
/// a contour-to-mesh mean of 1 mm).
const MISALIGNED_MEAN_MM: f64 = 1.5;

fn centroid(m: &TriMesh) -> Vec3 {
    m.positions.iter().sum::<Vec3>() / m.positions.len() as f64
}

/// Per grid vertex, the distance between the reconstruction's layout and the truth's.
fn vertex_errors(truth: &TriMesh, septum: Vec3, spec: &AcquisitionSpec) -> Vec<f64> {
    let set = simulate_surfaces(&[("LV_ENDO", truth)], spec)
        .unwrap()
        .contours;
    let params = Params {
        surface: Some("LV_ENDO".into()),
        ..Params::default()
    };
    let mut rec = Reconstruction::new(&set, params).unwrap();
    rec.run().unwrap();
    let base = basal_plane(&rec).unwrap();
    let orientation = Orientation {
        septum,
        source: "test",
        points: 1,
    };
    let got = build(rec.mesh(), &base, &orientation, Layout::DEFAULT).unwrap();
    let want = build(truth, &base, &orientation, Layout::DEFAULT).unwrap();
    assert_eq!(got.mesh.triangles, want.mesh.triangles);
    got.mesh
        .positions
        .iter()
        .zip(&want.mesh.positions)
        .map(|(a, b)| (a - b).norm())
        .collect()
}

fn check(name: &str, errors: &[f64], limit: f64) {
    let mut sorted = errors.to_vec();
    sorted.sort_by(f64::total_cmp);
    let p95 = sorted[(0.95 * sorted.len() as f64) as usize];
    let (m, worst) = (mean(errors), max(errors));
    eprintln!(
        "ANATOMICAL {name}: grid vertex vs truth's: mean {m:.3} p95 {p95:.3} max {worst:.3} mm \
         ({} vertices)",
        errors.len()
    );
    assert!(m <= limit, "{name}: mean {m:.3} mm");
}

#[test]
fn reconstructed_grids_lie_where_the_truths_do() {
    let spasm_rv = centroid(&load_truth("cardiomesh-spasm-RV_endo.obj"));
    let bivme_rv = centroid(&load_truth("bivme-patient1-ED-RV_ENDO-closed.obj"));
    let cases = [
        // The atlas has no RV: any direction across the axis lays both grids out alike.
        ("CAP atlas", "cap-atlas-mean-ED-LV_ENDO-open.obj", None),
        ("spasm", "cardiomesh-spasm-LV_endo.obj", Some(spasm_rv)),
        (
            "biv-me",
            "bivme-patient1-ED-LV_ENDO-closed.obj",
            Some(bivme_rv),
        ),
        ("spasm epi", "cardiomesh-spasm-LV_epi.obj", Some(spasm_rv)),
    ];
    for (name, file, rv) in cases {
        let truth = load_truth(file);
        let septum = rv.map_or(Vec3::x(), |c| c - centroid(&truth));
        check(
            name,
            &vertex_errors(&truth, septum, &AcquisitionSpec::default()),
            MEAN_MM,
        );
        let spec = AcquisitionSpec {
            misalignment: Some(Misalignment {
                shift_mm: 2.0,
                tilt_deg: 2.0,
            }),
            seed: 1,
            ..AcquisitionSpec::default()
        };
        check(
            &format!("{name} misaligned"),
            &vertex_errors(&truth, septum, &spec),
            MISALIGNED_MEAN_MM,
        );
    }
}
