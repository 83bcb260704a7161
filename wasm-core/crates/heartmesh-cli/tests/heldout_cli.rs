//! Held-out acquisitions through the binary (session 13, EVAL13; the study that found them is
//! scripts/heldout.py). A basal short-axis slice that also cuts another structure gives a second
//! closed loop of the same surface in one slice: the run goes ahead, and the user is told which
//! loop lies apart and how far (docs/VALIDATION.md, "Session 13: held-out acquisitions");
//! `--drop-second-loops` leaves such loops out.

mod common;
use common::{bin, ellipsoid_lv_csv, mesh_lines, run, scratch};
use std::f64::consts::TAU;
use std::fmt::Write;

/// An ellipsoidal LV (semi-axes 25 and 60 mm) sliced every 8 mm up to its equator, two long-axis
/// curves through the apex, and optionally a 6 mm loop 10 mm beside the basal ring.
fn lv_csv(second_loop: bool) -> String {
    let mut out = ellipsoid_lv_csv(true);
    if second_loop {
        for i in 0..30 {
            let t = TAU * i as f64 / 30.0;
            let _ = writeln!(
                out,
                "sax6b,{},{},0,LV_ENDO",
                41.0 + 6.0 * t.cos(),
                6.0 * t.sin()
            );
        }
    }
    out
}

#[test]
fn a_second_loop_in_the_basal_slice_is_named_with_its_distance() {
    let dir = scratch("heldout-second-loop");
    for (second, expect) in [(false, 0usize), (true, 1)] {
        let file = dir.join(format!("lv-{second}.csv"));
        std::fs::write(&file, lv_csv(second)).unwrap();
        let report = dir.join("r.json");
        let (code, _, err) = run(bin()
            .args(["reconstruct", file.to_str().unwrap(), "-o"])
            .arg(dir.join("out.obj"))
            .arg("--report")
            .arg(&report));
        assert_eq!(code, 0, "{err}");
        let rep: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
        let found: Vec<&str> = rep["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|w| w.as_str())
            .filter(|w| w.contains("second closed loop"))
            .collect();
        assert_eq!(found.len(), expect, "{found:?}");
        if second {
            assert!(
                found[0].starts_with("contour \"sax6b\" (line 544, 17 mm from \"sax6\")"),
                "{found:?}"
            );
            assert_eq!(err.matches("second closed loop").count(), 1, "{err}");
            // A note says which option leaves it out; with the option, that it is left out.
            assert!(
                err.contains(": --drop-second-loops leaves such loops out, so the surface follows each slice's main loop"),
                "{err}"
            );
            let (code, _, dropped) = run(bin()
                .args(["reconstruct", file.to_str().unwrap(), "-o"])
                .arg(dir.join("out.obj"))
                .arg("--drop-second-loops"));
            assert_eq!(code, 0, "{dropped}");
            assert!(
                dropped.contains(": --drop-second-loops: the loops named above are left out of the reconstruction"),
                "{dropped}"
            );
        } else {
            assert!(!err.contains("--drop-second-loops"), "{err}");
        }
    }
}

#[test]
fn drop_second_loops_gives_the_mesh_of_the_file_without_the_loop() {
    let dir = scratch("heldout-drop-second-loop");
    let mesh = |second: bool, extra: &[&str]| {
        let file = dir.join(format!("lv-{second}.csv"));
        std::fs::write(&file, lv_csv(second)).unwrap();
        let out = dir.join(format!("out-{second}-{}.obj", extra.len()));
        let (code, _, err) = run(bin()
            .args(["reconstruct", file.to_str().unwrap(), "-o"])
            .arg(&out)
            .arg("--quiet")
            .args(extra));
        assert_eq!(code, 0, "{err}");
        mesh_lines(&out)
    };
    let without = mesh(false, &[]);
    let with_loop = mesh(true, &[]);
    let dropped = mesh(true, &["--drop-second-loops"]);
    assert_ne!(with_loop, without, "the loop pulls the surface by default");
    assert_eq!(dropped, without);
    // And on a file without such loops the option changes nothing.
    assert_eq!(mesh(false, &["--drop-second-loops"]), without);
}
