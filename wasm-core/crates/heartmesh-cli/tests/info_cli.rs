//! `heartmesh info`: what a file holds and what reconstruct would make of it. Its per-surface
//! figures must be the ones a reconstruction then reports (same contours, ends, crossing gap and
//! contours left out), or a user planning a batch from it is misled.

mod common;
use common::{bin, data, run, scratch};
use serde_json::Value;

fn info_json(args: &[&str]) -> Value {
    let (code, out, err) = run(bin().arg("info").args(args).arg("--json"));
    assert_eq!(code, 0, "{args:?}: {err}");
    serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}"))
}

/// Runs `reconstruct ARGS -o MESH --report MESH.json` and returns the report.
fn reconstruct_report(args: &[&str], mesh: &std::path::Path) -> Value {
    let report = mesh.with_extension("json");
    let (code, _, err) = run(bin().arg("reconstruct").args(args).args([
        "-o",
        mesh.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
        "--quiet",
    ]));
    assert_eq!(code, 0, "{args:?}: {err}");
    serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap()
}

fn surface<'a>(info: &'a Value, name: &str) -> &'a Value {
    info["surfaces"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["surface"] == name)
        .unwrap_or_else(|| panic!("no {name} in {info}"))
}

#[test]
fn a_biventricular_file_is_described_as_reconstruct_then_reports_it() {
    let file = data("contours/bivme-example-patient1/patient1-ED.csv");
    let path = file.to_str().unwrap();
    let info = info_json(&[path]);
    assert_eq!(
        (info["contours"].as_u64(), info["points"].as_u64()),
        (Some(40), Some(1791))
    );
    assert_eq!(info["format"], "CSV");
    let names: Vec<&str> = info["surfaces"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["surface"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["RV_ENDO", "RV_EPI", "LV_EPI", "LV_ENDO"]);
    let lv = surface(&info, "LV_ENDO");
    assert_eq!(
        (
            lv["contours"].as_u64(),
            lv["sax"].as_u64(),
            lv["lax"].as_u64(),
            lv["slices"].as_u64()
        ),
        (Some(8), Some(5), Some(3), Some(5))
    );
    // SliceInfoFile.txt: the short-axis slices are 17.7 mm apart.
    let spacing = lv["slice_spacing_mm"]["median"].as_f64().unwrap();
    assert!((spacing - 17.7).abs() < 0.1, "{spacing}");
    assert!((lv["stack_height_mm"].as_f64().unwrap() - 4.0 * spacing).abs() < 0.5);

    let dir = scratch("same-as-run");
    for name in ["LV_ENDO", "RV_ENDO"] {
        let mesh = dir.join(format!("{name}.obj"));
        let rep = reconstruct_report(&[path, "--surface", name], &mesh);
        let s = surface(&info, name);
        assert_eq!(s["end_caps"], rep["end_caps"], "{name}");
        assert_eq!(
            s["alignment_suggested"], rep["alignment_suggested"],
            "{name}"
        );
        let (a, b) = (
            s["crossing_residual_mm"].as_f64().unwrap(),
            rep["crossing_residual_mm"].as_f64().unwrap(),
        );
        assert!((a - b).abs() < 1e-9 && a > 1.0, "{name}: {a} vs {b}");
        assert_eq!(
            s["contours"].as_u64().unwrap() as usize,
            rep["per_contour"].as_array().unwrap().len(),
            "{name}"
        );
        let sax = rep["per_contour"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|c| c["kind"] == "SAX")
            .count();
        assert_eq!(s["sax"].as_u64().unwrap() as usize, sax, "{name}");
    }

    let (code, text, _) = run(bin().args(["info", path]));
    assert_eq!(code, 0);
    assert!(
        text.starts_with("patient1-ED.csv: CSV, 40 contours, 1791 points\n"),
        "{text}"
    );
    assert!(
        text.contains("LV_ENDO: 8 contours (5 short-axis, 3 long-axis; 3 open), 441 points"),
        "{text}"
    );
    // The crossing gap is the file's: said once, with the advice.
    assert_eq!(text.matches("--align-slices").count(), 1, "{text}");
}

#[test]
fn contours_a_run_would_leave_out_and_surfaces_it_cannot_build_are_named() {
    let file = data("contours/bivme-example-patient1/patient1-ED.csv");
    let csv = std::fs::read_to_string(&file).unwrap();
    let mut out = csv.clone();
    // A copy of a basal ring 300 mm away (another series), and a surface of one curve.
    let ring: Vec<&str> = csv
        .lines()
        .filter(|l| l.starts_with("s03_SAX_LV_ENDOCARDIAL,"))
        .collect();
    assert!(ring.len() > 20);
    for l in &ring {
        let c: Vec<&str> = l.split(',').collect();
        let x: f64 = c[1].parse().unwrap();
        out += &format!("far_ring,{},{},{},LV_ENDO\n", x + 300.0, c[2], c[3]);
    }
    for l in &ring {
        let c: Vec<&str> = l.split(',').collect();
        out += &format!("atrium,{},{},{},RA\n", c[1], c[2], c[3]);
    }
    let dir = scratch("left-out");
    let path = dir.join("extra.csv");
    std::fs::write(&path, out).unwrap();
    let info = info_json(&[path.to_str().unwrap()]);
    let lv = surface(&info, "LV_ENDO");
    assert_eq!(lv["contours"].as_u64(), Some(8), "the far ring is not used");
    let aside = lv["set_aside"].as_array().unwrap();
    assert_eq!(aside.len(), 1, "{aside:?}");
    assert_eq!(
        (aside[0]["id"].as_str(), aside[0]["reason"].as_str()),
        (Some("far_ring"), Some("stray"))
    );
    assert!(aside[0]["gap_mm"].as_f64().unwrap() > 200.0);
    let ra = surface(&info, "RA");
    assert!(
        ra["error"].as_str().unwrap().contains("too few contours"),
        "{ra}"
    );
    assert_eq!(ra["contours"].as_u64(), Some(1));

    let (code, text, err) = run(bin().args(["info", path.to_str().unwrap()]));
    assert_eq!(code, 0, "the file was read: {err}");
    assert!(text.contains("\"far_ring\""), "{text}");
    assert!(
        text.contains("RA: 1 contour; cannot be reconstructed: too few contours"),
        "{text}"
    );
}

#[test]
fn a_short_axis_stack_gets_its_apex_floor_and_bad_input_exits_2() {
    let dir = scratch("sax-only");
    let truth = data("meshes/bivme-patient1-ED-LV_ENDO-closed.obj");
    let csv = dir.join("sax.csv");
    let (code, _, err) = run(bin().args([
        "simulate",
        truth.to_str().unwrap(),
        "-o",
        csv.to_str().unwrap(),
        "--lax",
        "0",
        "--quiet",
    ]));
    assert_eq!(code, 0, "{err}");
    let info = info_json(&[csv.to_str().unwrap()]);
    let s = &info["surfaces"][0];
    assert_eq!(
        (s["lax"].as_u64(), s["slices"].as_u64()),
        (Some(0), Some(10))
    );
    assert!((s["slice_spacing_mm"]["median"].as_f64().unwrap() - 10.0).abs() < 1e-6);
    assert_eq!(
        (
            s["end_caps"]["apex"].as_bool(),
            s["end_caps"]["apex_floor"].as_bool()
        ),
        (Some(true), Some(true))
    );
    for args in [
        vec![],
        vec!["/no/such/file.csv"],
        vec![csv.to_str().unwrap(), "--frame"],
    ] {
        let (code, out, err) = run(bin().arg("info").args(&args));
        assert_eq!(code, 2, "{args:?}");
        assert!(
            out.is_empty() && err.lines().count() == 1,
            "{args:?}: {err}"
        );
    }
}

#[test]
fn a_file_of_two_phases_names_its_frames_and_reads_the_one_asked_for() {
    let dir = scratch("frames");
    let mut csv = String::from("contour,x,y,z,surface,phase\n");
    for phase in ["ED", "ES"] {
        let file = data(&format!(
            "contours/bivme-example-patient1/patient1-{phase}.csv"
        ));
        for line in std::fs::read_to_string(file).unwrap().lines().skip(1) {
            if !line.starts_with('#') && !line.is_empty() {
                csv += &format!("{line},{phase}\n");
            }
        }
    }
    let path = dir.join("cine.csv");
    std::fs::write(&path, csv).unwrap();
    let p = path.to_str().unwrap();
    let ed = info_json(&[p]);
    assert_eq!(ed["time_frames"]["listed"], serde_json::json!(["ED", "ES"]));
    assert_eq!(
        (
            ed["time_frames"]["read"].as_str(),
            ed["time_frames"]["sequence"].as_bool()
        ),
        (Some("ED"), Some(true))
    );
    assert_eq!(ed["contours"].as_u64(), Some(40));
    let es = info_json(&[p, "--frame", "ES"]);
    assert_eq!(
        (es["contours"].as_u64(), es["points"].as_u64()),
        (Some(35), Some(1204))
    );
    let (_, text, _) = run(bin().args(["info", p, "--frame", "es"]));
    assert!(text.contains("time frames: 2 (ED, ES); read: ES"), "{text}");
}

#[test]
fn a_mesh_file_gets_the_facts_a_report_gives_for_it() {
    let dir = scratch("mesh");
    let surfco = data("contours/surfco-example.csv");
    let mesh = dir.join("m.vtp");
    let rep = reconstruct_report(&[surfco.to_str().unwrap()], &mesh);
    let info = info_json(&[mesh.to_str().unwrap()]);
    for key in [
        "vertices",
        "triangles",
        "watertight",
        "manifold",
        "oriented",
        "boundary_edges",
        "euler_characteristic",
    ] {
        assert_eq!(info[key], rep[key], "{key}");
    }
    // VTP keeps f64 coordinates: the volume and area are the report's.
    for key in ["volume_ml", "area_mm2"] {
        let (a, b) = (info[key].as_f64().unwrap(), rep[key].as_f64().unwrap());
        assert!((a - b).abs() <= 1e-9 * b, "{key}: {a} vs {b}");
    }
    assert_eq!(
        info["quality"]["folded_edges"],
        rep["quality"]["folded_edges"]
    );
    assert_eq!(info["point_data"]["name"], "distance");
    assert!(
        info["point_data"]["max"].as_f64().unwrap() > info["point_data"]["min"].as_f64().unwrap()
    );

    // An open surface: no enclosed volume claimed.
    let open = data("meshes/cap-atlas-mean-ED-LV_ENDO-open.obj");
    let (code, text, _) = run(bin().args(["info", open.to_str().unwrap()]));
    assert_eq!(code, 0);
    assert!(
        text.contains("not closed: ") && text.contains("(open: no enclosed volume)"),
        "{text}"
    );
    let o = info_json(&[open.to_str().unwrap()]);
    assert_eq!(o["watertight"], false);
    assert!(o["boundary_edges"].as_u64().unwrap() > 0);

    // A .vtp of contour lines is still contours.
    let lines = dir.join("c.vtp");
    let (code, _, err) = run(bin().args([
        "convert",
        surfco.to_str().unwrap(),
        lines.to_str().unwrap(),
        "--quiet",
    ]));
    assert_eq!(code, 0, "{err}");
    let c = info_json(&[lines.to_str().unwrap()]);
    assert_eq!(
        (c["contours"].as_u64(), c["points"].as_u64()),
        (Some(8), Some(3008))
    );
}

#[test]
fn several_files_are_described_in_turn_and_one_unreadable_file_does_not_stop_the_others() {
    let surfco = data("contours/surfco-example.csv");
    let p2 = data("contours/bivme-test-patient2/patient2-ES.csv");
    let info_file = data("contours/bivme-example-patient1/SliceInfoFile.txt");
    let (code, out, err) = run(bin().args([
        "info",
        surfco.to_str().unwrap(),
        info_file.to_str().unwrap(),
        p2.to_str().unwrap(),
        "--json",
    ]));
    assert_eq!(code, 2, "the SliceInfoFile is not contours");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("SliceInfoFile") && err.contains("not contours"),
        "{err}"
    );
    let all: Value = serde_json::from_str(&out).unwrap();
    let names: Vec<&str> = all
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i["input"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["surfco-example.csv", "patient2-ES.csv"]);
    assert_eq!(all[0]["points"].as_u64(), Some(3008));
    // Each entry is the one file's own description.
    assert_eq!(all[1], info_json(&[p2.to_str().unwrap()]));
    let (code, text, _) = run(bin().args(["info", surfco.to_str().unwrap(), p2.to_str().unwrap()]));
    assert_eq!(code, 0);
    assert!(
        text.contains("surfco-example.csv: CSV") && text.contains("\n\npatient2-ES.csv: CSV"),
        "{text}"
    );
}
