//! Sunnybrook Cardiac Data contours on the command line: a case's contours folder with its cine
//! series folder (or the case folder holding both), `--frame`, `info`, `volumes`, and the
//! refusals a user meets first (the contours alone, the wrong series). The fixture is biv-me's
//! patient 1 laid out as a Sunnybrook case (scripts/sunnybrook_fixture.py;
//! heartmesh-core/tests/sunnybrook.rs checks its points).

mod common;
use common::{bin, run, scratch};
use serde_json::Value;
use std::path::Path;

fn fixture(sub: &str) -> String {
    common::core_data(&format!("sunnybrook-patient1/{sub}"))
}

const CONTOURS: &str = "contours-manual/IRCCI-expert";

/// `reconstruct INPUTS... --surface LV_ENDO [--frame F]`: (status, stderr, report).
fn lv(inputs: &[String], frame: Option<&str>, dir: &Path) -> (i32, String, Option<Value>) {
    let mut extra = vec!["--surface", "LV_ENDO"];
    if let Some(f) = frame {
        extra.extend(["--frame", f]);
    }
    common::reconstruct_report(inputs, &extra, dir)
}

#[test]
fn the_contours_folder_and_the_series_folder_reconstruct_each_frame() {
    let dir = scratch("sunnybrook_reconstruct");
    let two = [fixture(CONTOURS), fixture("CINESAX_300")];
    let mut seen = Vec::new();
    for frame in [None, Some("9")] {
        let (code, err, r) = lv(&two, frame, &dir);
        assert_eq!(code, 0, "{err}");
        let r = r.unwrap();
        let mean = r["contour_to_mesh"]["mean"].as_f64().unwrap();
        let ml = r["volume_ml"].as_f64().unwrap();
        eprintln!("SUNNYBROOK CLI frame {frame:?}: contour-to-mesh mean {mean:.3} mm, {ml:.2} ml");
        assert_eq!(r["watertight"], true);
        assert!(mean <= 0.5, "{mean}");
        assert!(
            err.contains("note: ")
                && err.contains("Sunnybrook contours read with 100 DICOM images"),
            "{err}"
        );
        assert!(
            err.contains("p1contour skipped: papillary muscles"),
            "{err}"
        );
        seen.push((r["per_contour"].as_array().unwrap().len(), ml));
    }
    // End-diastole: 5 rings; end-systole 4 (none drawn on the first slice), a smaller cavity.
    assert_eq!((seen[0].0, seen[1].0), (5, 4));
    assert!(
        (seen[0].1 - 158.5).abs() < 1.0 && (seen[1].1 - 48.9).abs() < 1.0,
        "{seen:?}"
    );
    // The case folder (both series and the contours): the short-axis series chosen by its numbers.
    let (code, err, r) = lv(&[fixture("")], None, &dir);
    assert_eq!(code, 0, "{err}");
    let ml = r.unwrap()["volume_ml"].as_f64().unwrap();
    assert!((ml - seen[0].1).abs() < 1e-9, "{ml} vs {}", seen[0].1);
}

#[test]
fn info_and_volumes_read_the_case() {
    let (code, out, err) = run(bin().args([
        "info",
        &fixture(CONTOURS),
        &fixture("CINESAX_300"),
        "--json",
    ]));
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["format"], "Sunnybrook contours");
    common::assert_surface_points(&v, &[("LV_ENDO", 233), ("LV_EPI", 216)]);
    let dir = scratch("sunnybrook_volumes");
    let (ef, phases) = common::lv_ef(&[fixture("")], &dir);
    assert_eq!(phases.len(), 2, "{phases:?}");
    let (ed, es) = (159.05, 48.83);
    eprintln!("SUNNYBROOK volumes: LV EF {ef:.2} %");
    assert!((ef - 100.0 * (ed - es) / ed).abs() < 1.0, "{ef}");
}

#[test]
fn the_contours_alone_or_with_the_wrong_series_are_refused_in_one_line() {
    let dir = scratch("sunnybrook_refused");
    for (inputs, want) in [
        (
            vec![fixture(CONTOURS)],
            "together with the DICOM images they were drawn on",
        ),
        (
            vec![fixture(CONTOURS), fixture("CINE2CH_400")],
            "the DICOM images given hold only 1 of the 9 images the contour files were drawn on",
        ),
    ] {
        let (code, err, _) = lv(&inputs, None, &dir);
        assert_eq!(code, 2, "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(want), "{err}");
    }
}
