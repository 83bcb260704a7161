//! Specks and stray contours through the binary (session 14, SPECK14; docs/VALIDATION.md,
//! "Session 14: specks and stray contours"). A short-axis slice whose ring is under a tenth of the
//! ring one slice away, anywhere but at the apex, is left out of the reconstruction and named in one
//! warning line with its file line; `--keep-specks` keeps it (the paper's method).

mod common;
use common::{bin, ellipsoid_lv_csv, run, scratch};
use std::f64::consts::TAU;
use std::fmt::Write;
use std::path::Path;

/// The ellipsoidal LV of `common` (rings every 8 mm up to z = 0, two long-axis curves; the file's
/// rows end at line 543) plus `extra` rows.
fn lv_with(extra: &str) -> String {
    ellipsoid_lv_csv(true) + extra
}

/// A 3-point loop of radius `r` centred at (`cx`, `cy`) in the plane z = `z`.
fn speck(id: &str, cx: f64, cy: f64, z: f64, r: f64) -> String {
    let mut out = String::new();
    for i in 0..3 {
        let t = TAU * i as f64 / 3.0;
        let _ = writeln!(
            out,
            "{id},{},{},{z},LV_ENDO",
            cx + r * t.cos(),
            cy + r * t.sin()
        );
    }
    out
}

struct Run {
    stderr: String,
    report: serde_json::Value,
    /// Vertex and face lines of the OBJ (its header names the file and the flags).
    mesh: Vec<String>,
    vertices: Vec<[f64; 3]>,
}

fn reconstruct(dir: &Path, name: &str, csv: &str, extra: &[&str]) -> Run {
    let file = dir.join(format!("{name}.csv"));
    std::fs::write(&file, csv).unwrap();
    let out = dir.join(format!("{name}-{}.obj", extra.len()));
    let report = dir.join(format!("{name}-{}.json", extra.len()));
    let (code, _, stderr) = run(bin()
        .args(["reconstruct", file.to_str().unwrap(), "-o"])
        .arg(&out)
        .arg("--report")
        .arg(&report)
        .args(extra));
    assert_eq!(code, 0, "{stderr}");
    let mesh = common::mesh_lines(&out);
    let vertices = mesh
        .iter()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|t| t.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    let report = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    Run {
        stderr,
        report,
        mesh,
        vertices,
    }
}

fn top(v: &[[f64; 3]]) -> f64 {
    v.iter().map(|p| p[2]).fold(f64::NEG_INFINITY, f64::max)
}

#[test]
fn a_speck_past_the_base_is_left_out_and_named_with_its_line() {
    let dir = scratch("speck-past-base");
    // A 2.6 mm loop on the wall 5 mm past the basal ring (z = 0, radius 25 mm).
    let with = lv_with(&speck("speck", 24.0, 0.0, 5.0, 0.5));
    let without = reconstruct(&dir, "without", &ellipsoid_lv_csv(true), &[]);
    let dropped = reconstruct(&dir, "with", &with, &[]);
    let line = "contour \"speck\" (line 544, 2.6 mm around, 2 % of the ring of \"sax6\" one slice \
                away) is a speck, not a section of the cavity; it is left out of the reconstruction";
    assert!(
        dropped.stderr.contains(&format!("with.csv: {line}\n")),
        "{}",
        dropped.stderr
    );
    assert_eq!(dropped.stderr.lines().count(), 1, "{}", dropped.stderr);
    assert_eq!(dropped.report["warnings"], serde_json::json!([line]));
    let aside = &dropped.report["set_aside"];
    assert_eq!(aside.as_array().map(Vec::len), Some(1), "{aside}");
    assert_eq!(aside[0]["id"], "speck");
    assert_eq!(aside[0]["line"], 544);
    assert_eq!(aside[0]["reason"], "speck");
    assert_eq!(aside[0]["next_id"], "sax6");
    let perimeter = aside[0]["perimeter_mm"].as_f64().unwrap();
    assert!((perimeter - 1.5 * 3f64.sqrt()).abs() < 1e-9, "{perimeter}");
    assert_eq!(dropped.report["contours"], 9);
    // Left out: the mesh is the mesh of the file without it, line for line.
    assert_eq!(dropped.mesh, without.mesh);
    assert!(without.report.get("set_aside").is_none());
    // Kept (--keep-specks), the tube runs up to it and the mesh's top runs on past it: 14.4 mm
    // past the basal ring, against 2.0 mm (the lid) without it.
    let kept = reconstruct(&dir, "with", &with, &["--keep-specks"]);
    assert_ne!(kept.mesh, without.mesh);
    assert!(kept.report.get("set_aside").is_none());
    assert_eq!(kept.report["parameters"]["keep_specks"], true);
    assert!(kept.stderr.contains(
        "with.csv: --keep-specks: the contours named above as left out are kept in the \
         reconstruction"
    ));
    let (t_drop, t_keep) = (top(&dropped.vertices), top(&kept.vertices));
    assert!(t_drop < 2.5 && t_keep > 10.0, "{t_drop} {t_keep}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_stray_click_between_two_slices_no_longer_pinches_the_mesh() {
    let dir = scratch("speck-mid");
    // A 2.6 mm loop inside the cavity halfway between the rings at z = -24 and z = -16.
    let with = lv_with(&speck("click", 5.0, 3.0, -20.0, 0.5));
    let without = reconstruct(&dir, "without", &ellipsoid_lv_csv(true), &[]);
    let dropped = reconstruct(&dir, "with", &with, &[]);
    assert!(
        dropped.stderr.contains(
            "contour \"click\" (line 544, 2.6 mm around, 2 % of the ring of \"sax4\" one slice \
             away) is a speck"
        ),
        "{}",
        dropped.stderr
    );
    assert_eq!(dropped.mesh, without.mesh);
    // Radius of the mesh at the click's height (23.6 mm on the ellipsoid): 23.4 mm left out,
    // 5.8 mm kept (the tube pinches to the click).
    let waist = |v: &[[f64; 3]]| {
        v.iter()
            .filter(|p| (p[2] + 20.0).abs() < 1.5)
            .map(|p| p[0].hypot(p[1]))
            .fold(f64::INFINITY, f64::min)
    };
    let kept = reconstruct(&dir, "with", &with, &["--keep-specks"]);
    let (w_drop, w_keep) = (waist(&dropped.vertices), waist(&kept.vertices));
    assert!(w_drop > 22.5, "{w_drop}");
    assert!(w_keep < 15.0, "{w_keep}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_small_ring_grazing_the_apex_is_kept() {
    let dir = scratch("speck-apex");
    // The ellipsoid's section 0.1 mm above its tip: a 1.4 mm ring, 0.1 of the ring 12 mm above.
    let z = -59.9f64;
    let r = 25.0 * (1.0 - (z / 60.0) * (z / 60.0)).sqrt();
    let mut tip = String::new();
    for i in 0..8 {
        let t = TAU * i as f64 / 8.0;
        let _ = writeln!(tip, "tip,{},{},{z},LV_ENDO", r * t.cos(), r * t.sin());
    }
    let without = reconstruct(&dir, "without", &ellipsoid_lv_csv(true), &[]);
    let with = reconstruct(&dir, "with", &lv_with(&tip), &[]);
    assert!(!with.stderr.contains("speck"), "{}", with.stderr);
    assert!(with.report.get("set_aside").is_none());
    assert_eq!(with.report["contours"], 10);
    assert_ne!(with.mesh, without.mesh, "the apical ring is data");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A file of two surfaces with a speck in one: the run of the other says nothing of it (its
/// warnings are about the surface it reconstructs and the file as a whole).
#[test]
fn a_speck_of_one_surface_is_not_reported_on_the_other_surfaces_run() {
    let dir = scratch("speck-other-surface");
    let lv = lv_with(&speck("speck", 24.0, 0.0, 5.0, 0.5));
    // The same cavity as the RV, 120 mm along x (its rows after the LV's, under other names).
    let rv: String = ellipsoid_lv_csv(true)
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let x: f64 = f[1].parse().unwrap();
            format!("rv_{},{},{},{},RV_ENDO\n", f[0], x + 120.0, f[2], f[3])
        })
        .collect();
    let both = lv + &rv;
    let on_rv = reconstruct(&dir, "both", &both, &["--surface", "RV_ENDO"]);
    assert!(!on_rv.stderr.contains("speck"), "{}", on_rv.stderr);
    assert_eq!(on_rv.report["warnings"], serde_json::json!([]));
    let on_lv = reconstruct(&dir, "both", &both, &["--surface", "LV_ENDO"]);
    assert!(
        on_lv.stderr.contains("contour \"speck\" (line 544,"),
        "{}",
        on_lv.stderr
    );
    assert_eq!(on_lv.report["warnings"].as_array().map(Vec::len), Some(1));
    let _ = std::fs::remove_dir_all(&dir);
}
