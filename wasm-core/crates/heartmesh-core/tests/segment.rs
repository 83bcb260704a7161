//! A Segment study file lands every curve where Segment's own conversion puts it. The fixture
//! (tests/data/segment-patient1, written by scripts/segment_fixture.py) is biv-me's patient 1 as
//! Segment saves a study: a compressed level-5 MAT-file whose `setstruct` holds a short-axis cine
//! stack (five slices 17.7 mm apart, 20 frames, ED 1 and ES 10, with its image), four long-axis
//! views, a scout and a rotated stack, the curves in pixels (80 x frames x slices, NaN where not
//! drawn). Beside it, the same curves in millimetres, placed by the script's own conversion.

mod common;

use common::*;
use heartmesh_core::contours::ContourSet;
use heartmesh_core::io::{self, ContourOptions, FrameChoice};
use heartmesh_core::Params;
use std::path::PathBuf;

fn fixture(name: &str) -> Vec<u8> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/segment-patient1")
        .join(name);
    std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn read_segment(frame: Option<&str>) -> ContourSet {
    let options = ContourOptions {
        frame: frame.and_then(FrameChoice::new),
        ..ContourOptions::default()
    };
    io::read_contours_with("patient1.mat", &fixture("patient1.mat"), &options).unwrap()
}

fn expected(name: &str) -> ContourSet {
    io::read_contours(name, &fixture(name)).unwrap()
}

/// Largest distance from a point of `a` to the nearest point of `b` on the same surface.
fn farthest(a: &ContourSet, b: &ContourSet) -> (f64, usize) {
    let mut worst = 0.0f64;
    let mut n = 0;
    for c in &a.contours {
        for p in c.points() {
            let d = b
                .contours
                .iter()
                .filter(|o| o.surface == c.surface)
                .flat_map(|o| o.points())
                .map(|q| (p - q).norm())
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
            n += 1;
        }
    }
    (worst, n)
}

#[test]
fn every_curve_lands_where_segments_conversion_puts_it() {
    for (frame, file, points) in [
        (None, "expected-ED.csv", 1659),
        (Some("10"), "expected-ES.csv", 1422),
    ] {
        let seg = read_segment(frame);
        let want = expected(file);
        let (there, n) = farthest(&seg, &want);
        let (back, m) = farthest(&want, &seg);
        eprintln!("SEGMENT {file}: {n} points, farthest {there:.2e} / {back:.2e} mm");
        assert_eq!((n, m), (points, points));
        assert!(there < 1e-6 && back < 1e-6, "{there} {back}");
        for s in ["LV_ENDO", "RV_ENDO"] {
            let count = |set: &ContourSet| surface_contours(set, s).len();
            assert_eq!(count(&seg), count(&want), "{s}");
        }
    }
}

#[test]
fn the_study_reads_its_end_diastole_and_lists_its_phases() {
    let seg = read_segment(None);
    let tf = seg.time_frames.as_ref().unwrap();
    assert_eq!(tf.frames, ["1", "10"]);
    assert_eq!(tf.read, ["1"]);
    assert_eq!(
        (tf.end_diastole.as_deref(), tf.end_systole.as_deref()),
        (Some("1"), Some("10"))
    );
    let notes: Vec<&String> = seg
        .warnings
        .iter()
        .filter(|w| io::is_reading_note(w))
        .collect();
    assert_eq!(notes.len(), 2, "{:?}", seg.warnings);
    assert!(
        notes[0].contains("180 images: contours on 17 of them, in 9 cine slices"),
        "{}",
        notes[0]
    );
    assert!(notes[1]
        .contains("end-diastole is frame 1, its end-systole frame 10 (stack 1 (Short-axis))"));
    assert!(seg
        .warnings
        .iter()
        .any(|w| w.starts_with("stack 7 (2CH): a rotated (radial) stack")));
    // Both RV insertions of each of the five slices at end-diastole, one placed in all frames.
    assert_eq!(
        seg.landmarks.iter().filter(|l| l.0 == "RV_INSERT").count(),
        10
    );
    assert!(read_segment(Some("10")).landmarks.is_empty());
}

#[test]
fn the_meshes_match_those_of_the_same_curves_in_millimetres() {
    for (frame, file) in [(None, "expected-ED.csv"), (Some("10"), "expected-ES.csv")] {
        let seg = read_segment(frame);
        let want = expected(file);
        for surface in ["LV_ENDO", "LV_EPI", "RV_ENDO"] {
            let params = Params {
                surface: Some(surface.into()),
                ..Params::default()
            };
            let (a, _) = reconstruct(&seg, params.clone());
            let (b, _) = reconstruct(&want, params);
            check_closed_manifold_outward(&a).unwrap();
            let c2m = surface_to_mesh(&seg, surface, &a);
            eprintln!(
                "SEGMENT {file} {surface}: {:.2} ml (millimetre file {:.2} ml), contour-to-mesh \
                 mean {:.3} max {:.3} mm",
                a.volume_ml(),
                b.volume_ml(),
                mean(&c2m),
                max(&c2m)
            );
            assert!(mean(&c2m) <= 1.0);
            // The same points, in another order of contours: the same cavity to sampling.
            assert!((a.volume_ml() / b.volume_ml() - 1.0).abs() < 0.01);
        }
    }
}
