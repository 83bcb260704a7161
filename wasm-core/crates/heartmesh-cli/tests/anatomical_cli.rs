//! `reconstruct --anatomical-mesh`: the LV surface on a fixed grid, one vertex layout for every
//! heart. On the real biv-me patient 1: every grid vertex on the reconstructed surface, the
//! triangles of ED and ES identical, vertex 0 of each ring towards the septum; a contraction
//! applied to the contour file moves each grid vertex where the contraction moves it (the
//! correspondence the layout is for); and the refusals, before any run.

mod common;
use common::{bin, data, moved_csv, run, scratch, with_grid};
use heartmesh_core::geometry::{v3, Vec3};
use heartmesh_core::io::read_mesh;
use heartmesh_core::metrics::points_to_mesh;
use heartmesh_core::TriMesh;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn mesh(path: &Path) -> TriMesh {
    read_mesh(s(path), &std::fs::read(path).unwrap())
        .unwrap()
        .mesh
}

fn vector(v: &Value) -> Vec3 {
    v3(
        v[0].as_f64().unwrap(),
        v[1].as_f64().unwrap(),
        v[2].as_f64().unwrap(),
    )
}

fn patient1(phase: &str) -> PathBuf {
    data(&format!(
        "contours/bivme-example-patient1/patient1-{phase}.csv"
    ))
}

#[test]
fn both_phases_of_a_patient_share_one_layout_on_their_surfaces() {
    let dir = scratch("anatomical-phases");
    let (ed_rep, ed_mesh, ed) = with_grid(&patient1("ED"), &dir, "ed", &[]);
    let (es_rep, es_mesh, es) = with_grid(&patient1("ES"), &dir, "es", &[]);
    assert_eq!(ed.positions.len(), 24 * 48 + 2);
    assert_eq!(ed.triangles, es.triangles, "one layout for both phases");
    for (rep, surface, grid) in [(&ed_rep, &ed_mesh, &ed), (&es_rep, &es_mesh, &es)] {
        let a = &rep["anatomical_mesh"];
        assert_eq!(a["vertices"], 1154);
        assert_eq!(
            a["file"],
            format!(
                "{}-grid.vtk",
                if std::ptr::eq(grid, &ed) { "ed" } else { "es" }
            )
        );
        // Every vertex but the lid's centre lies on the reconstructed surface.
        let off = points_to_mesh(&grid.positions[..grid.positions.len() - 1], surface);
        let worst = off.iter().fold(0.0f64, |m, &d| m.max(d));
        assert!(worst < 1e-6, "a grid vertex {worst} mm off the surface");
        // Its volume is the surface's below the base, less what the chords cut off (< 2 %).
        let (v, sv) = (
            a["volume_ml"].as_f64().unwrap(),
            a["surface_volume_ml"].as_f64().unwrap(),
        );
        assert!((grid.volume_ml() - v).abs() < 1e-9);
        assert!(v < sv && v > 0.98 * sv, "{v} vs {sv} ml");
        assert!(a["to_surface_mean_mm"].as_f64().unwrap() < 0.15, "{a}");
        // The top ring's vertex 0 lies from the lid's centre towards the septum.
        let lid = grid.positions[grid.positions.len() - 1];
        let top0 = grid.positions[1 + 23 * 48];
        let towards = (top0 - lid).normalize();
        let septum = vector(&a["septum_direction"]);
        assert!(towards.dot(&septum) > 0.9999, "{towards:?} vs {septum:?}");
        // biv-me files are in DICOM LPS: the septum lies to the patient's right (-x).
        assert!(septum.x < -0.5, "{septum:?}");
    }
    // The ventricle shortens from ED to ES (77.6 -> 54.4 mm on this patient).
    let len = |r: &Value| r["anatomical_mesh"]["length_mm"].as_f64().unwrap();
    assert!(len(&es_rep) < 0.8 * len(&ed_rep));
}

#[test]
fn a_contracted_heart_moves_each_grid_vertex_with_it() {
    let dir = scratch("anatomical-contracted");
    let (rep, _, ed) = with_grid(&patient1("ED"), &dir, "ed", &[]);
    // A systole-like map about the long axis through the base's centre: 20 % in, 10 % shorter.
    let n = vector(&rep["anatomical_mesh"]["axis"]);
    let centre = ed.positions[ed.positions.len() - 1];
    let contract = |p: Vec3| {
        let d = p - centre;
        let h = d.dot(&n);
        centre + n * (0.9 * h) + (d - n * h) * 0.8
    };
    let input = dir.join("contracted.csv");
    moved_csv(&patient1("ED"), &input, contract, contract);
    let (_, _, es) = with_grid(&input, &dir, "contracted", &[]);
    assert_eq!(es.triangles, ed.triangles);
    let k = 48;
    let mut ours = Vec::new();
    let mut shifted = Vec::new();
    for ring in 0..24 {
        for j in 0..k {
            let at = |j: usize| 1 + ring * k + j % k;
            let expected = contract(ed.positions[at(j)]);
            ours.push((es.positions[at(j)] - expected).norm());
            // The same grid one vertex round: what a layout off by 7.5 degrees would give.
            shifted.push((es.positions[at(j + 1)] - expected).norm());
        }
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let (ours_mean, shifted_mean) = (mean(&ours), mean(&shifted));
    let ours_max = ours.iter().fold(0.0f64, |m, &d| m.max(d));
    println!("contracted: grid vertex vs contracted ED grid: mean {ours_mean:.3} max {ours_max:.3} mm; one vertex round {shifted_mean:.3} mm");
    assert!(ours_mean < 0.5, "{ours_mean} mm");
    assert!(
        ours_mean < 0.3 * shifted_mean,
        "{ours_mean} vs {shifted_mean} mm"
    );
    assert!(
        (es.positions[0] - contract(ed.positions[0])).norm() < 1.0,
        "the apex"
    );
}

#[test]
fn what_has_no_layout_is_refused_before_the_run() {
    let dir = scratch("anatomical-refused");
    let grid = dir.join("grid.obj");
    let out = dir.join("m.obj");
    let refused = |args: &[&str], says: &str| {
        let (code, _, err) = run(bin().args(args));
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(says), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(
            !out.exists() && !grid.exists(),
            "nothing written before a refusal"
        );
    };
    let surfco = data("contours/surfco-example.csv");
    refused(
        &[
            "reconstruct",
            s(&surfco),
            "-o",
            s(&out),
            "--anatomical-mesh",
            s(&grid),
        ],
        "no RV_INSERT landmarks and no RV contours",
    );
    let p1 = patient1("ED");
    refused(
        &[
            "reconstruct",
            s(&p1),
            "--surface",
            "RV_ENDO",
            "-o",
            s(&out),
            "--anatomical-mesh",
            s(&grid),
        ],
        "the LV's (LV_ENDO, LV_EPI)",
    );
    refused(
        &[
            "reconstruct",
            s(&p1),
            "-o",
            s(&out),
            "--anatomical-layout",
            "24x48",
        ],
        "add --anatomical-mesh",
    );
    refused(
        &[
            "reconstruct",
            s(&p1),
            "-o",
            s(&out),
            "--anatomical-mesh",
            s(&grid),
            "--anatomical-layout",
            "24x4",
        ],
        "8-720 points",
    );
    refused(
        &[
            "reconstruct",
            s(&p1),
            "-o",
            s(&out),
            "--anatomical-mesh",
            s(&dir.join("grid.txt")),
        ],
        "the extension must be",
    );
}

#[test]
fn every_surface_run_lays_out_the_lv_surfaces_and_names_the_others() {
    let dir = scratch("anatomical-all");
    let (code, _, err) = run(bin().args([
        "reconstruct",
        s(&patient1("ED")),
        "--surface",
        "all",
        "-o",
        s(&dir.join("m.obj")),
        "--report",
        s(&dir.join("r.json")),
        "--anatomical-mesh",
        s(&dir.join("g.ply")),
        "--anatomical-layout",
        "10x16",
    ]));
    assert_eq!(code, 0, "{err}");
    for lv in ["LV_ENDO", "LV_EPI"] {
        let g = mesh(&dir.join(format!("g-{lv}.ply")));
        assert_eq!(g.positions.len(), 10 * 16 + 2);
        let rep: Value =
            serde_json::from_slice(&std::fs::read(dir.join(format!("r-{lv}.json"))).unwrap())
                .unwrap();
        assert_eq!(rep["anatomical_mesh"]["rings"], 10);
    }
    for rv in ["RV_ENDO", "RV_EPI"] {
        assert!(!dir.join(format!("g-{rv}.ply")).exists());
        assert!(
            err.contains(&format!("no anatomical layout for {rv}")),
            "{err}"
        );
        let rep: Value =
            serde_json::from_slice(&std::fs::read(dir.join(format!("r-{rv}.json"))).unwrap())
                .unwrap();
        assert!(rep.get("anatomical_mesh").is_none());
    }
    // The epicardium encloses the endocardium: its grid's volume is the larger.
    let vol = |lv: &str| mesh(&dir.join(format!("g-{lv}.ply"))).volume_ml();
    assert!(vol("LV_EPI") > vol("LV_ENDO") + 50.0);
}
