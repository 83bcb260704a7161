//! Integration tests of the validation commands (issue 5 contract): `simulate`, `compare --json`
//! on an analytic case, and `leave-one-out --json`.

use heartmesh_core::io::obj::write_obj;
use heartmesh_core::sim::shapes::{uv_sphere, ParametricLv};
use heartmesh_core::TriMesh;
mod common;
use common::{bin, run, scratch};
use std::path::Path;

fn write_mesh(dir: &Path, name: &str, m: &TriMesh) -> String {
    let p = dir.join(name);
    std::fs::write(&p, write_obj(m, "test")).unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn compare_concentric_spheres_json() {
    let d = scratch("spheres");
    let inner = write_mesh(
        &d,
        "inner.obj",
        &uv_sphere([0.0, 0.0, 0.0].into(), 10.0, 128, 64),
    );
    let outer = write_mesh(
        &d,
        "outer.obj",
        &uv_sphere([0.0, 0.0, 0.0].into(), 11.0, 128, 64),
    );
    let (code, out, err) = run(bin().args(["compare", &inner, &outer, "--json"]));
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for key in ["mesh_to_truth", "truth_to_mesh"] {
        for stat in ["mean", "median", "p95", "max"] {
            let x = v[key][stat].as_f64().unwrap();
            assert!((x - 1.0).abs() < 0.02, "{key}.{stat} = {x}");
        }
    }
    assert!((v["hausdorff"].as_f64().unwrap() - 1.0).abs() < 0.02);
    let vt = v["volume_truth_ml"].as_f64().unwrap();
    let vm = v["volume_mesh_ml"].as_f64().unwrap();
    assert!(
        (vt - 4.18879).abs() < 0.05 && (vm - 5.57528).abs() < 0.06,
        "{vt} {vm}"
    );
}

#[test]
fn simulate_then_compare_clipped_and_errors() {
    let d = scratch("simulate");
    let truth = write_mesh(&d, "lv.obj", &ParametricLv::default().mesh(96, 60).unwrap());
    let csv = d.join("c.csv");
    let csv = csv.to_str().unwrap();
    let simulate = |out: &str| {
        run(bin().args([
            "simulate",
            &truth,
            "-o",
            out,
            "--sax",
            "6",
            "--lax",
            "2",
            "--misalign",
            "2,2",
            "--noise",
            "0.2",
            "--seed",
            "5",
        ]))
    };
    let (code, out, err) = simulate(csv);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("6 SAX + 2 LAX"), "{out}");
    let text = std::fs::read_to_string(csv).unwrap();
    assert!(text.starts_with("contour,x,y,z\n"));
    assert!(text.contains("\nsax06,") && text.contains("\nlax02,"));
    // Same seed, same bytes.
    let csv2 = d.join("c2.csv");
    let csv2 = csv2.to_str().unwrap();
    simulate(csv2);
    assert_eq!(text, std::fs::read_to_string(csv2).unwrap());
    // The truth against itself, clipped at the most basal SAX plane of the contours.
    let (code, out, err) =
        run(bin().args(["compare", &truth, &truth, "--clip-contours", csv, "--json"]));
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v["hausdorff"].as_f64().unwrap() < 1e-9);
    assert_eq!(v["clipped"], serde_json::Value::Bool(true));
    let clipped = v["volume_truth_ml"].as_f64().unwrap();
    let full = ParametricLv {
        closed_base: true,
        ..ParametricLv::default()
    }
    .mesh(96, 60)
    .unwrap()
    .volume_ml();
    assert!(
        clipped > 0.5 * full && clipped < full,
        "{clipped} of {full}"
    );
    // Bad usage: exit 2 and one line.
    let (code, _, err) = run(bin().args([
        "simulate",
        &truth,
        "-o",
        csv,
        "--sax",
        "3",
        "--sax-spacing",
        "8",
    ]));
    assert_eq!(code, 2);
    assert_eq!(err.lines().count(), 1, "{err}");
    let (code, _, err) = run(bin().args(["compare", &truth]));
    assert_eq!(code, 2, "{err}");
}

#[test]
fn leave_one_out_json() {
    let d = scratch("loo");
    let truth = write_mesh(&d, "lv.obj", &ParametricLv::default().mesh(64, 40).unwrap());
    let csv = d.join("c.csv");
    let csv = csv.to_str().unwrap();
    let (code, _, err) =
        run(bin().args(["simulate", &truth, "-o", csv, "--sax", "5", "--lax", "2"]));
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = run(bin().args(["leave-one-out", csv, "--json"]));
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let contours = v["contours"].as_array().unwrap();
    assert_eq!(contours.len(), 7);
    for c in contours {
        let mean = c["stats"]["mean"].as_f64().unwrap_or(f64::NAN);
        // A smooth shape: every left-out slice is predicted within a few mm by the others.
        assert!(mean < 3.0, "{c}");
    }
    assert!(v["worst"].as_str().is_some());
}
