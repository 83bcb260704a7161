//! Segment (Medviso) study files on the command line: `reconstruct` at the study's end-diastole
//! or `--frame 10`, `info` naming the format, `volumes` giving the EF of the study's phases, and
//! the refusals of a MATLAB 7.3 file and a damaged one. The fixture is biv-me's patient 1 saved
//! as Segment saves a study (scripts/segment_fixture.py; heartmesh-core/tests/segment.rs checks
//! its points).

mod common;
use common::{bin, run, scratch};
use serde_json::Value;

fn study() -> String {
    common::core_data("segment-patient1/patient1.mat")
}

/// `reconstruct FILE --surface S [--frame F]`: (status, stderr, report).
fn reconstruct(input: &str, surface: &str, frame: Option<&str>) -> (i32, String, Option<Value>) {
    let dir = scratch(&format!("segment_{surface}_{}", frame.unwrap_or("ed")));
    let mut extra = vec!["--surface", surface];
    if let Some(f) = frame {
        extra.extend(["--frame", f]);
    }
    common::reconstruct_report(&[input.to_string()], &extra, &dir)
}

#[test]
fn the_study_reconstructs_each_surface_at_each_phase() {
    let mut lv = Vec::new();
    for frame in [None, Some("10")] {
        for surface in ["LV_ENDO", "LV_EPI", "RV_ENDO"] {
            let (code, err, r) = reconstruct(&study(), surface, frame);
            assert_eq!(code, 0, "{err}");
            let r = r.unwrap();
            let mean = r["contour_to_mesh"]["mean"].as_f64().unwrap();
            let ml = r["volume_ml"].as_f64().unwrap();
            eprintln!("SEGMENT CLI {surface} frame {frame:?}: {ml:.2} ml, contour-to-mesh mean {mean:.3} mm");
            assert_eq!(r["watertight"], true);
            assert!(mean <= 1.0, "{mean}");
            assert!(
                err.contains("note: ") && err.contains("Segment study read with 180 images"),
                "{err}"
            );
            assert!(
                err.contains("stack 7 (2CH): a rotated (radial) stack"),
                "{err}"
            );
            if surface == "RV_ENDO" {
                // The RV's lines (tricuspid and pulmonary valves at their own heights) stay wall.
                assert_eq!(r["valve_chords"], serde_json::json!([]), "frame {frame:?}");
            }
            if surface == "LV_ENDO" {
                lv.push(ml);
                // Segment closes every long-axis curve across the valve: the fit opens the three
                // LV views there and says so; their distances stay those of the curves as drawn.
                let ids = ["s06_Endo", "s07_Endo", "s08_Endo"];
                assert_eq!(r["valve_chords"], serde_json::json!(ids), "frame {frame:?}");
                assert!(
                    err.contains(
                        "\"s06_Endo\", \"s07_Endo\", \"s08_Endo\" closed across the valve"
                    ),
                    "{err}"
                );
                let folds = r["quality"]["folded_edges"].as_u64().unwrap();
                assert!(folds <= 2, "frame {frame:?}: {folds} folded edges");
            }
        }
    }
    // The same cavity as the millimetre file of the same curves (heartmesh-core/tests/segment.rs):
    // 171.6 and 64.3 ml (with the valve chords as wall data, before session 45: 171.9 and 63.0).
    assert!(
        (lv[0] - 171.6).abs() < 1.0 && (lv[1] - 64.3).abs() < 1.0,
        "{lv:?}"
    );
}

#[test]
fn info_and_volumes_read_the_study() {
    let (code, out, err) = run(bin().args(["info", &study(), "--json"]));
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["format"], "Segment study");
    assert_eq!(
        (
            &v["time_frames"]["end_diastole"],
            &v["time_frames"]["end_systole"]
        ),
        (&Value::from("1"), &Value::from("10"))
    );
    let (_, text, _) = run(bin().args(["info", &study()]));
    assert!(
        text.contains("time frames: 2 (1, 10); read: 1 (--frame picks one); the file's end-diastole 1, end-systole 10"),
        "{text}"
    );
    common::assert_surface_points(&v, &[("LV_ENDO", 632), ("LV_EPI", 395), ("RV_ENDO", 632)]);
    let dir = scratch("segment_volumes");
    let (ef, phases) = common::lv_ef(&[study()], &dir);
    eprintln!("SEGMENT volumes: LV EF {ef:.2} % over {phases:?}");
    assert_eq!(phases.len(), 2, "{phases:?}");
    let (ed, es) = (171.6, 64.3);
    assert!((ef - 100.0 * (ed - es) / ed).abs() < 1.0, "{ef}");
}

#[test]
fn a_matlab_7_3_file_or_a_damaged_study_is_refused_in_one_line() {
    let dir = scratch("segment_refused");
    let hdf5 = dir.join("big.mat");
    let mut h = b"MATLAB 7.3 MAT-file, Platform: PCWIN64, Created on: Mon Jan  5 10:00:00 2026 HDF5 schema 1.00 .".to_vec();
    h.resize(4096, 0);
    std::fs::write(&hdf5, h).unwrap();
    let cut = dir.join("cut.mat");
    let bytes = std::fs::read(study()).unwrap();
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    for (file, want) in [(&hdf5, "MATLAB 7.3 (HDF5) MAT-file"), (&cut, "truncated")] {
        let (code, err, _) = reconstruct(file.to_str().unwrap(), "LV_ENDO", None);
        assert_eq!(code, 2, "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(
            err.contains(want) && err.contains(file.file_name().unwrap().to_str().unwrap()),
            "{err}"
        );
    }
}
