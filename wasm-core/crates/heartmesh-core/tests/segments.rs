//! Wall thickness by AHA segment (`metrics::segments`, `heartmesh myocardium`'s `segments`)
//! against known walls: a reference shape's endo- and epicardium sliced on one acquisition,
//! reconstructed at the defaults, the wall built, and each of the 17 segments' mean thickness
//! compared with the same segment of the wall the truth surfaces make at the same base, placed
//! by the same septum direction (the segments' placement is the file's to give; this measures
//! the thickness in them).
//!
//! Run with `--nocapture` for the `SEGMENTS` lines (docs/VALIDATION.md).

mod common;

use common::*;
use heartmesh_core::geometry::Vec3;
use heartmesh_core::mesh::wall::{build_wall, Wall};
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::metrics::compare::common_basal_plane;
use heartmesh_core::metrics::segments::{segments, thickening, Orientation, Segments};
use heartmesh_core::sim::planes::anatomical_axis;
use heartmesh_core::sim::planes::simulate_surfaces;
use heartmesh_core::sim::{AcquisitionSpec, Misalignment};
use heartmesh_core::{Params, Reconstruction};

/// A segment's mean thickness may differ from the truth's by the two surfaces' mean-error
/// targets together (issue 2: LV mean <= 0.2 mm each): the thickness is their difference.
const SEGMENT_MM: f64 = 0.4;
/// With every plane shifted up to 2 mm and tilted up to 2 degrees, a surface is held to a
/// contour-to-mesh mean of 1 mm (issue 2); a segment averages over a sixth of a ring, so
/// half of the two surfaces' sum.
const MISALIGNED_SEGMENT_MM: f64 = 1.0;

fn reconstruct(set: &heartmesh_core::ContourSet, surface: &str) -> Reconstruction {
    let params = Params {
        surface: Some(surface.to_string()),
        ..Params::default()
    };
    let mut rec = Reconstruction::new(set, params).unwrap();
    rec.run().unwrap();
    rec
}

/// The reconstructed wall's segments and the truth wall's, at the reconstruction's base.
fn case(endo: &TriMesh, epi: &TriMesh, spec: &AcquisitionSpec, septum: Vec3) -> [Segments; 2] {
    let set = simulate_surfaces(&[("LV_EPI", epi), ("LV_ENDO", endo)], spec)
        .unwrap()
        .contours;
    let (endo_rec, epi_rec) = (reconstruct(&set, "LV_ENDO"), reconstruct(&set, "LV_EPI"));
    let base = common_basal_plane(&endo_rec, &epi_rec).unwrap();
    let wall = build_wall(endo_rec.mesh(), epi_rec.mesh(), &base, Some(1.0)).unwrap();
    let truth = build_wall(endo, epi, &base, None).unwrap();
    let orientation = Orientation {
        septum,
        source: "test",
        points: 1,
    };
    let of = |w: &Wall| segments(w, &orientation).unwrap();
    [of(&wall), of(&truth)]
}

/// Every segment's mean against the truth's; returns the largest difference.
fn check(name: &str, [got, truth]: &[Segments; 2], limit: f64) -> f64 {
    let mut worst: f64 = 0.0;
    let mut line = String::new();
    for (g, t) in got.segments.iter().zip(&truth.segments) {
        let (g, t) = (g.mean_mm.unwrap(), t.mean_mm.unwrap());
        line.push_str(&format!(" {:.2}/{:.2}", g, t));
        worst = worst.max((g - t).abs());
    }
    eprintln!("SEGMENTS {name}: worst {worst:.2} mm; mean got/truth by segment:{line}");
    assert!(worst <= limit, "{name}: a segment is {worst:.2} mm off");
    worst
}

fn centroid(m: &TriMesh) -> Vec3 {
    m.positions.iter().sum::<Vec3>() / m.positions.len() as f64
}

#[test]
fn cap_atlas_segments_match_the_truth() {
    let endo = load_truth("cap-atlas-mean-ED-LV_ENDO-open.obj");
    let epi = load_truth("cap-atlas-mean-ED-LV_EPI-open.obj");
    // The atlas has no RV: any direction across the axis places the segments alike on both.
    let s = case(&endo, &epi, &AcquisitionSpec::default(), Vec3::x());
    check("CAP atlas", &s, SEGMENT_MM);
}

#[test]
fn spasm_segments_match_the_truth_with_the_septum_towards_its_rv() {
    let endo = load_truth("cardiomesh-spasm-LV_endo.obj");
    let epi = load_truth("cardiomesh-spasm-LV_epi.obj");
    let rv = load_truth("cardiomesh-spasm-RV_endo.obj");
    let septum = centroid(&rv) - centroid(&endo);
    let aligned = case(&endo, &epi, &AcquisitionSpec::default(), septum);
    check("spasm", &aligned, SEGMENT_MM);
    // The septum of this subject is its thickest wall, as the truth has it.
    let [got, truth] = &aligned;
    for s in [got, truth] {
        let m = |id: usize| s.segments[id - 1].mean_mm.unwrap();
        assert!(m(8) + m(9) > m(11) + m(12), "mid septum vs lateral: {s:?}");
    }
    for seed in [1, 2] {
        let spec = AcquisitionSpec {
            misalignment: Some(Misalignment {
                shift_mm: 2.0,
                tilt_deg: 2.0,
            }),
            seed,
            ..AcquisitionSpec::default()
        };
        let s = case(&endo, &epi, &spec, septum);
        check(
            &format!("spasm misaligned seed {seed}"),
            &s,
            MISALIGNED_SEGMENT_MM,
        );
    }
}

/// An end-systolic copy of a surface: contracted about `centre` by `along` on `axis` and by
/// `across` in the short-axis plane (the ventricle narrows more than it shortens).
fn contracted(mesh: &TriMesh, centre: Vec3, axis: Vec3, along: f64, across: f64) -> TriMesh {
    TriMesh {
        positions: mesh
            .positions
            .iter()
            .map(|p| {
                let q = p - centre;
                let a = axis * q.dot(&axis);
                centre + a * along + (q - a) * across
            })
            .collect(),
        ..mesh.clone()
    }
}

/// Systolic thickening by segment against the truth's: the CardioMesh LV at end-diastole, and at
/// end-systole its endocardium drawn in more than its epicardium (the wall thickens), each
/// phase sliced and reconstructed on its own. A segment's thickening may be off by what its two
/// thicknesses may be ([`SEGMENT_MM`] each) over its end-diastolic thickness.
#[test]
fn systolic_thickening_by_segment_matches_the_truth() {
    let endo = load_truth("cardiomesh-spasm-LV_endo.obj");
    let epi = load_truth("cardiomesh-spasm-LV_epi.obj");
    let rv = load_truth("cardiomesh-spasm-RV_endo.obj");
    let septum = centroid(&rv) - centroid(&endo);
    let axis = anatomical_axis(&epi, 0.0).unwrap();
    let centre = centroid(&endo);
    let es_endo = contracted(&endo, centre, axis.direction, 0.9, 0.7);
    let es_epi = contracted(&epi, centre, axis.direction, 0.95, 0.9);
    let spec = AcquisitionSpec::default();
    let [ed, ed_truth] = case(&endo, &epi, &spec, septum);
    let [es, es_truth] = case(&es_endo, &es_epi, &spec, septum);
    let got = thickening(&ed, &es);
    let want = thickening(&ed_truth, &es_truth);
    let mut line = String::new();
    let mut worst: f64 = 0.0;
    for ((g, w), t) in got.iter().zip(&want).zip(&ed_truth.segments) {
        let (g, w) = (g.thickening_percent.unwrap(), w.thickening_percent.unwrap());
        let limit = 100.0 * 2.0 * SEGMENT_MM / t.mean_mm.unwrap();
        line.push_str(&format!(" {g:.0}/{w:.0}"));
        worst = worst.max((g - w).abs());
        assert!(
            (g - w).abs() <= limit,
            "segment {}: {g:.1} % vs {w:.1} %",
            t.id
        );
        // The wall thickens everywhere in this contraction, and the reconstruction says so.
        assert!(
            w > 10.0 && g > 0.0,
            "segment {}: {g:.1} % vs {w:.1} %",
            t.id
        );
    }
    eprintln!("THICKENING spasm: worst {worst:.1} points; got/truth % by segment:{line}");
}
