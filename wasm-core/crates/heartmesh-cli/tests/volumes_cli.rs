//! `heartmesh volumes` (session 23): cardiac function from the phases of one heart. Against known
//! truth (a reference shape and a contracted copy of it, each sliced like a CMR acquisition), on
//! the real patients (myocardial mass is conserved over the cycle), on a file holding a sequence,
//! and on bad input.
//!
//! Tolerances: CMR's own scan-rescan reproducibility is about 3-5 % for ventricular volumes and
//! 2-3 points for ejection fraction, so the reconstruction's error must stay below that (3 %, 2
//! points) to be no part of a clinical difference; myocardial mass measured at end-diastole and
//! end-systole differs by up to ~10 % in clinical series (the mass is the same muscle).

mod common;
use common::{bin, data, run, scratch};

use heartmesh_core::geometry::Vec3;
use heartmesh_core::io::{self, MeshFormat};
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::sim::planes::anatomical_axis;
use serde_json::Value;
use std::path::Path;

const VOLUME_TOLERANCE: f64 = 0.03;
const EF_TOLERANCE_POINTS: f64 = 2.0;
const MASS_ED_ES_TOLERANCE: f64 = 0.10;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn read_mesh(path: &Path) -> TriMesh {
    let bytes = std::fs::read(path).unwrap();
    io::read_mesh(s(path), &bytes).unwrap().mesh
}

fn write_mesh(path: &Path, mesh: &TriMesh) {
    let bytes = io::write_mesh(mesh, MeshFormat::Obj, None, "test").unwrap();
    std::fs::write(path, bytes).unwrap();
}

/// An end-systolic copy of `mesh`: contracted about its centre along its long axis by `along` and
/// across it by `across` (the ventricle shortens less than it narrows).
fn contracted(mesh: &TriMesh, axis_of: &TriMesh, along: f64, across: f64) -> TriMesh {
    let axis = anatomical_axis(axis_of, 0.0).unwrap();
    let n = mesh.positions.len() as f64;
    let c: Vec3 = mesh.positions.iter().sum::<Vec3>() / n;
    let d = axis.direction;
    TriMesh {
        positions: mesh
            .positions
            .iter()
            .map(|p| {
                let q = p - c;
                let a = d * q.dot(&d);
                c + a * along + (q - a) * across
            })
            .collect(),
        ..mesh.clone()
    }
}

fn simulate(truth: &Path, out: &Path, extra: &[&str]) {
    let (code, _, err) = run(bin()
        .args(["simulate", s(truth), "-o", s(out), "--quiet"])
        .args(extra));
    assert_eq!(code, 0, "simulate {}: {err}", truth.display());
}

fn volumes(args: &[&str], json: &Path) -> (Value, String) {
    let (code, out, err) = run(bin().arg("volumes").args(args).args(["--json", s(json)]));
    assert_eq!(code, 0, "volumes {args:?}: {err}");
    let doc = serde_json::from_slice(&std::fs::read(json).unwrap()).unwrap();
    (doc, out)
}

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// The truth's volume below the most basal short-axis plane of `contours` (what the contours
/// cover), from `compare --clip-contours`.
fn clipped_truth_ml(truth: &Path, mesh: &Path, contours: &Path) -> f64 {
    let (code, out, err) = run(bin().args([
        "compare",
        s(truth),
        s(mesh),
        "--clip-contours",
        s(contours),
        "--json",
    ]));
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    num(&v["volume_truth_ml"])
}

fn check(name: &str, got: f64, want: f64) {
    let rel = (got - want).abs() / want;
    eprintln!(
        "{name}: {got:.2} ml, truth {want:.2} ml ({:+.2} %)",
        100.0 * (got - want) / want
    );
    assert!(
        rel <= VOLUME_TOLERANCE,
        "{name}: {got} ml against {want} ml"
    );
}

#[test]
fn simulated_phases_give_the_truth_volumes_and_ejection_fraction() {
    let dir = scratch("truth");
    let lv_ed = data("meshes/bivme-patient1-ED-LV_ENDO-closed.obj");
    let rv_ed = data("meshes/bivme-patient1-ED-RV_ENDO-closed.obj");
    let lv = read_mesh(&lv_ed);
    let rv = read_mesh(&rv_ed);
    let (lv_es, rv_es) = (dir.join("lv-es.obj"), dir.join("rv-es.obj"));
    write_mesh(&lv_es, &contracted(&lv, &lv, 0.9, 0.78));
    write_mesh(&rv_es, &contracted(&rv, &lv, 0.9, 0.78));

    // LV: three long-axis views reach the valve, so the contours cover the whole cavity.
    let (ed_csv, es_csv) = (dir.join("lv-ED.csv"), dir.join("lv-ES.csv"));
    simulate(&lv_ed, &ed_csv, &[]);
    simulate(&lv_es, &es_csv, &[]);
    let (doc, out) = volumes(&[s(&ed_csv), s(&es_csv)], &dir.join("lv.json"));
    print!("{out}");
    let f = &doc["function"][0];
    assert_eq!(
        (f["ed_phase"].as_str(), f["es_phase"].as_str()),
        (Some("lv-ED"), Some("lv-ES"))
    );
    let (edv_true, esv_true) = (lv.volume_ml(), read_mesh(&lv_es).volume_ml());
    check("LV EDV", num(&f["edv_ml"]), edv_true);
    check("LV ESV", num(&f["esv_ml"]), esv_true);
    let ef_true = 100.0 * (edv_true - esv_true) / edv_true;
    let ef = num(&f["ef_percent"]);
    eprintln!("LV EF {ef:.2} %, truth {ef_true:.2} %");
    assert!(
        (ef - ef_true).abs() <= EF_TOLERANCE_POINTS,
        "LV EF {ef} against {ef_true}"
    );
    assert!(out.contains(&format!("EF {ef:.1} %")), "{out}");

    // RV: one long-axis view, planned on the LV; the outflow tract above the basal slice is seen
    // by no contour, so the truth is what lies below the basal plane.
    let (ed_csv, es_csv) = (dir.join("rv-ED.csv"), dir.join("rv-ES.csv"));
    let lax = ["--lax", "1", "--axis-from"];
    simulate(&rv_ed, &ed_csv, &[&lax[..], &[s(&lv_ed)]].concat());
    write_mesh(&dir.join("lv-es-axis.obj"), &read_mesh(&lv_es));
    simulate(
        &rv_es,
        &es_csv,
        &[&lax[..], &[s(&dir.join("lv-es-axis.obj"))]].concat(),
    );
    let meshes = dir.join("meshes");
    let (doc, _) = volumes(
        &[s(&ed_csv), s(&es_csv), "--meshes", s(&meshes), "--quiet"],
        &dir.join("rv.json"),
    );
    let f = &doc["function"][0];
    assert_eq!(f["ed_phase"], "rv-ED");
    let edv_true = clipped_truth_ml(&rv_ed, &meshes.join("rv-ED-surface.obj"), &ed_csv);
    let esv_true = clipped_truth_ml(&rv_es, &meshes.join("rv-ES-surface.obj"), &es_csv);
    check("RV EDV", num(&f["edv_ml"]), edv_true);
    check("RV ESV", num(&f["esv_ml"]), esv_true);
    let ef_true = 100.0 * (edv_true - esv_true) / edv_true;
    let ef = num(&f["ef_percent"]);
    eprintln!("RV EF {ef:.2} %, truth {ef_true:.2} %");
    assert!(
        (ef - ef_true).abs() <= EF_TOLERANCE_POINTS,
        "RV EF {ef} against {ef_true}"
    );
    // The meshes written are the ones measured.
    let written = read_mesh(&meshes.join("rv-ED-surface.obj")).volume_ml();
    assert!((written - num(&f["edv_ml"])).abs() < 1e-3, "{written}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn real_patients_keep_their_myocardial_mass_over_the_cycle() {
    let dir = scratch("patients");
    for (folder, p) in [
        ("bivme-example-patient1", "patient1"),
        ("bivme-test-patient2", "patient2"),
    ] {
        let ed = data(&format!("contours/{folder}/{p}-ED.csv"));
        let es = data(&format!("contours/{folder}/{p}-ES.csv"));
        let plot = dir.join("curve.svg");
        let (doc, out) = volumes(
            &[
                s(&es),
                s(&ed),
                "--surface",
                "LV_ENDO,LV_EPI,RV_ENDO",
                "--plot",
                s(&plot),
            ],
            &dir.join("v.json"),
        );
        print!("{out}");
        assert_eq!(
            doc["phases"],
            serde_json::json!([format!("{p}-ES"), format!("{p}-ED")])
        );
        for f in doc["function"].as_array().unwrap() {
            // End-diastole is the larger volume whichever file comes first.
            assert_eq!(f["ed_phase"], format!("{p}-ED"), "{f}");
            assert_eq!(f["es_phase"], format!("{p}-ES"), "{f}");
            let ef = num(&f["ef_percent"]);
            assert!((0.0..100.0).contains(&ef), "{f}");
        }
        let surfaces: Vec<&str> = doc["function"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f["surface"].as_str().unwrap())
            .collect();
        assert_eq!(surfaces, ["LV_ENDO", "RV_ENDO"], "epicardia get no EF");
        let m = &doc["lv_mass"];
        let (ed_g, es_g) = (num(&m["ed_g"]), num(&m["es_g"]));
        eprintln!("{p}: LV mass ED {ed_g:.1} g, ES {es_g:.1} g");
        assert!(
            (ed_g - es_g).abs() / ed_g <= MASS_ED_ES_TOLERANCE,
            "{p}: {ed_g} / {es_g}"
        );
        // Mass = 1.05 x the wall volume of the same phase.
        let vol = |phase: &str, surface: &str| {
            doc["volumes"]
                .as_array()
                .unwrap()
                .iter()
                .find(|v| v["phase"] == phase && v["surface"] == surface)
                .map(|v| num(&v["volume_ml"]))
                .unwrap()
        };
        let ed = format!("{p}-ED");
        let wall = vol(&ed, "LV_EPI") - vol(&ed, "LV_ENDO");
        assert!((ed_g - 1.05 * wall).abs() < 1e-9, "{ed_g} {wall}");
        assert!(out.contains("LV mass, 1.05 g/ml"), "{out}");
        check_plot(&std::fs::read_to_string(&plot).unwrap(), &doc);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--plot`: the cavities' curves only (no epicardium), one dot per phase and cavity, each at its
/// volume on the chart's y scale, and each ventricle's EF as the JSON gives it.
fn check_plot(svg: &str, doc: &Value) {
    assert!(svg.starts_with("<?xml") && svg.trim_end().ends_with("</svg>"));
    let dots: Vec<f64> = svg
        .lines()
        .filter(|l| l.starts_with("<circle"))
        .map(|l| attr(l, "cy"))
        .collect();
    assert_eq!(dots.len(), 4, "2 phases x LV_ENDO, RV_ENDO");
    for f in doc["function"].as_array().unwrap() {
        let text = format!(
            "{} EF {:.1} %",
            f["surface"].as_str().unwrap(),
            num(&f["ef_percent"])
        );
        assert!(svg.contains(&text), "{text}");
    }
    assert!(!svg.contains(">LV_EPI<"), "an epicardium is no cavity");
    // Higher volumes are higher up: the dots' order by height is the volumes' order.
    let mut ml: Vec<f64> = doc["volumes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|v| v["surface"] != "LV_EPI")
        .map(|v| num(&v["volume_ml"]))
        .collect();
    ml.sort_by(f64::total_cmp);
    let mut by_height = dots.clone();
    by_height.sort_by(|a, b| b.total_cmp(a));
    // Linear scale: equal volume steps are equal pixel steps.
    let px_per_ml = (by_height[0] - by_height[3]) / (ml[3] - ml[0]);
    for k in 1..3 {
        let want = by_height[0] - (ml[k] - ml[0]) * px_per_ml;
        assert!((by_height[k] - want).abs() < 0.15, "{by_height:?} {ml:?}");
    }
}

/// The number in attribute `name="..."` of an SVG element line.
fn attr(line: &str, name: &str) -> f64 {
    let start = line.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
    let end = start + line[start..].find('"').unwrap();
    line[start..end].parse().unwrap()
}

/// The same two phases in one file with a phase column: every frame a phase, named as written,
/// and the same volumes as the two files give (the reconstruction is deterministic).
#[test]
fn one_file_holding_a_sequence() {
    let dir = scratch("sequence");
    let mut cine = String::from("contour,x,y,z,surface,phase\n");
    let mut files = Vec::new();
    for phase in ["ED", "ES"] {
        let path = data(&format!(
            "contours/bivme-example-patient1/patient1-{phase}.csv"
        ));
        let text = std::fs::read_to_string(&path).unwrap();
        for line in text
            .lines()
            .skip(1)
            .filter(|l| !l.is_empty() && !l.starts_with('#'))
        {
            cine.push_str(&format!("{line},{phase}\n"));
        }
        files.push(path);
    }
    let cine_path = dir.join("cine.csv");
    std::fs::write(&cine_path, cine).unwrap();
    let args = ["--surface", "LV_ENDO", "--quiet"];
    let (one, _) = volumes(
        &[&[s(&cine_path)], &args[..]].concat(),
        &dir.join("one.json"),
    );
    let (two, _) = volumes(
        &[&[s(&files[0]), s(&files[1])], &args[..]].concat(),
        &dir.join("two.json"),
    );
    assert_eq!(one["phases"], serde_json::json!(["ED", "ES"]));
    for i in 0..2 {
        let (a, b) = (
            num(&one["volumes"][i]["volume_ml"]),
            num(&two["volumes"][i]["volume_ml"]),
        );
        assert!((a - b).abs() <= 1e-9 * b, "phase {i}: {a} / {b}");
    }
    assert_eq!(one["function"][0]["ed_phase"], "ED");

    // --frames takes some frames, as the file names them (any case); an unknown one is refused.
    let (es, _) = volumes(
        &[
            s(&cine_path),
            "--frames",
            "es",
            "--surface",
            "LV_ENDO",
            "-q",
        ],
        &dir.join("es.json"),
    );
    assert_eq!(es["phases"], serde_json::json!(["ES"]));
    assert!(es["function"].as_array().unwrap().is_empty());
    let (code, _, err) = run(bin().args(["volumes", s(&cine_path), "--frames", "ED,XX"]));
    assert_eq!(code, 2);
    assert!(
        err.contains("no time frame \"XX\"") && err.contains("ED, ES"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_biventricular_epicardium_gives_no_lv_mass() {
    let dir = scratch("biv");
    let seg = dir.join("biv.nii.gz");
    let m = |f: &str| data(&format!("meshes/bivme-patient1-ED-{f}-closed.obj"));
    let (code, _, err) = run(bin().args([
        "segment",
        "--lv-endo",
        s(&m("LV_ENDO")),
        "--lv-epi",
        s(&m("EPI")),
        "--rv",
        s(&m("RV_ENDO")),
        "-o",
        s(&seg),
        "--quiet",
    ]));
    assert_eq!(code, 0, "{err}");
    let (doc, out) = volumes(&[s(&seg)], &dir.join("v.json"));
    // The RV cavity inside the biventricular wall is painted as a cavity, not as myocardium.
    assert_eq!(
        doc["surfaces"],
        serde_json::json!(["LV_ENDO", "LV_EPI", "RV_ENDO"]),
        "{doc}"
    );
    let rv = num(&doc["volumes"][2]["volume_ml"]);
    let truth = read_mesh(&m("RV_ENDO")).volume_ml();
    assert!(rv > 0.5 * truth, "RV {rv} ml, truth {truth} ml");
    let row = &doc["lv_mass"]["per_phase"][0];
    assert!(row["grams"].is_null(), "{row}");
    assert!(
        row["why_none"].as_str().unwrap().contains("biventricular"),
        "{row}"
    );
    assert!(out.contains("biventricular epicardium"), "{out}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_input_is_named_and_the_other_runs_go_on() {
    let dir = scratch("bad");
    let ed = data("contours/bivme-example-patient1/patient1-ED.csv");
    let fail = |args: &[&str], want: &str| {
        let (code, _, err) = run(bin().arg("volumes").args(args));
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
    };
    fail(&[], "volumes needs contour files");
    fail(
        &[s(&ed), "--surface", "LA"],
        "no phase holds surface \"LA\"",
    );
    fail(
        &[s(&ed), s(&ed), "--frames", "0"],
        "one file holding a sequence",
    );
    fail(&[s(&ed), "--frames", "3"], "holds one phase");
    fail(&[s(&ed), "--beta", "3"], "allowed");
    let broken = dir.join("broken.csv");
    std::fs::write(&broken, "contour,x,y,z\na,1,2\n").unwrap();
    fail(&[s(&ed), s(&broken)], "broken.csv:2");

    // A phase whose surface cannot be reconstructed (one ring): named, the others still measured.
    let one_ring = dir.join("one-ring.csv");
    let mut text = String::from("contour,x,y,z,surface\n");
    for i in 0..40 {
        let t = std::f64::consts::TAU * i as f64 / 40.0;
        text.push_str(&format!(
            "r,{},{},0,LV_ENDO\n",
            20.0 * t.cos(),
            20.0 * t.sin()
        ));
    }
    std::fs::write(&one_ring, text).unwrap();
    let csv = dir.join("v.csv");
    let (code, out, err) = run(bin().args([
        "volumes",
        s(&ed),
        s(&one_ring),
        "--surface",
        "LV_ENDO",
        "--csv",
        s(&csv),
    ]));
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("LV_ENDO, phase one-ring") && err.contains("one-ring.csv"),
        "{err}"
    );
    assert!(out.contains("failed"), "{out}");
    let rows = std::fs::read_to_string(&csv).unwrap();
    let ed_row = rows
        .lines()
        .find(|l| l.starts_with("patient1-ED,LV_ENDO,"))
        .unwrap();
    let v: f64 = ed_row.split(',').nth(2).unwrap().parse().unwrap();
    assert!((v - 173.7).abs() < 1.0, "{ed_row}");
    assert!(rows.contains("one-ring,LV_ENDO,,false"), "{rows}");
    let _ = std::fs::remove_dir_all(&dir);
}
