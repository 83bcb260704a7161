//! `reconstruct --surface BIV_EPI` (session 20): the biventricular epicardium of a file with LV and
//! RV epicardial curves, one closed surface around both ventricles; a file without them is told
//! what the surface needs.

mod common;
use common::{bin, data, run, scratch};

fn volume_and_report(input: &str, surface: &str, dir: &std::path::Path) -> serde_json::Value {
    let report = dir.join(format!("{surface}.json"));
    let out = dir.join(format!("{surface}.obj"));
    let (code, _, err) = run(bin().args([
        "reconstruct",
        input,
        "-o",
        out.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
        "--surface",
        surface,
        "--quiet",
    ]));
    assert_eq!(code, 0, "{surface}: {err}");
    serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap()
}

#[test]
fn the_biventricular_epicardium_wraps_both_ventricles() {
    let dir = scratch("biv-epi");
    let input = data("contours/bivme-example-patient1/patient1-ED.csv");
    let input = input.to_str().unwrap();
    let biv = volume_and_report(input, "BIV_EPI", &dir);
    assert_eq!(biv["surface"], "BIV_EPI");
    assert_eq!(biv["watertight"], true, "{biv}");
    assert_eq!(biv["quality"]["self_intersections"], 0, "{biv}");
    let c2m = biv["contour_to_mesh"]["mean"].as_f64().unwrap();
    assert!(c2m < 1.0, "contour-to-mesh mean {c2m}");
    // Every LV and RV epicardial curve is one of its contours.
    let ids: Vec<&str> = biv["per_contour"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["id"].as_str().unwrap())
        .collect();
    assert!(
        ids.iter().any(|i| i.contains("LV_EPICARDIAL"))
            && ids.iter().any(|i| i.contains("RV_EPICARDIAL")),
        "{ids:?}"
    );
    let v = biv["volume_ml"].as_f64().unwrap();
    for part in ["LV_EPI", "RV_EPI"] {
        let r = volume_and_report(input, part, &dir);
        assert!(v > 1.2 * r["volume_ml"].as_f64().unwrap(), "{part}: {v} ml");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_file_without_rv_epicardium_is_told_what_the_surface_needs() {
    let dir = scratch("biv-epi-none");
    let input = data("contours/bivme-test-patient2/patient2-ED.csv");
    let (code, _, err) = run(bin().args([
        "reconstruct",
        input.to_str().unwrap(),
        "-o",
        dir.join("m.obj").to_str().unwrap(),
        "--surface",
        "biv_epi",
    ]));
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(
            "made of LV_EPI and RV_EPI curves) not found; available: LV_ENDO, LV_EPI, RV_ENDO"
        ),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
