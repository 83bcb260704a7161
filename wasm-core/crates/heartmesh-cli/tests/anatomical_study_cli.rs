//! `volumes --anatomical-meshes`: every phase's LV surfaces on the anatomical layout, all turned
//! by the LV end-diastole's septum. On the real biv-me patient 1 (ED and ES): the reference
//! phase's layout is `reconstruct --anatomical-mesh`'s; the other phase's grid starts at the
//! reference septum across its own axis (its own file's septum lies `septum_turn_deg` away, as
//! `reconstruct` on that file alone shows); the files' displacement_mm is each vertex's distance
//! from the reference's; a phase whose file cannot place the septum still gets its layout; and
//! the refusals, before any run.

mod common;
use common::{bin, data, moved_csv, run, scratch, with_grid};
use heartmesh_core::geometry::{v3, Vec3};
use heartmesh_core::io::{read_mesh, MeshData};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn read(path: &Path) -> MeshData {
    read_mesh(s(path), &std::fs::read(path).unwrap()).unwrap()
}

fn patient1(phase: &str) -> PathBuf {
    data(&format!(
        "contours/bivme-example-patient1/patient1-{phase}.csv"
    ))
}

fn vector(v: &Value) -> Vec3 {
    v3(
        v[0].as_f64().unwrap(),
        v[1].as_f64().unwrap(),
        v[2].as_f64().unwrap(),
    )
}

/// `volumes PHASES --surface LV_ENDO,LV_EPI --anatomical-meshes DIR/lay --json`: (JSON, stdout).
fn volumes(phases: &[&Path], dir: &Path, extra: &[&str]) -> (Value, String) {
    let json = dir.join("v.json");
    let lay = dir.join("lay");
    let mut args = vec!["volumes"];
    args.extend(phases.iter().map(|p| s(p)));
    args.extend([
        "--surface",
        "LV_ENDO,LV_EPI",
        "--anatomical-meshes",
        s(&lay),
        "--json",
        s(&json),
    ]);
    args.extend_from_slice(extra);
    let (code, out, err) = run(bin().args(&args));
    assert_eq!(code, 0, "{err}");
    let doc: Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    (doc["anatomical_meshes"].clone(), out)
}

/// The entry of `phase`'s `surface` among the JSON's layouts.
fn entry<'a>(a: &'a Value, phase: &str, surface: &str) -> &'a Value {
    a["layouts"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["phase"] == phase && l["surface"] == surface)
        .unwrap_or_else(|| panic!("no {phase} {surface} in {a}"))
}

#[test]
fn every_phase_is_laid_out_on_the_end_diastolic_septum() {
    let dir = scratch("study-patient1");
    // ES first: the reference is the LV's end-diastole, not the first file.
    let (a, out) = volumes(&[&patient1("ES"), &patient1("ED")], &dir, &[]);
    assert_eq!(a["septum"]["phase"], "patient1-ED");
    assert_eq!(a["displacement_from_phase"], "patient1-ED");
    assert_eq!(a["layouts"].as_array().unwrap().len(), 4);
    assert!(out.contains("anatomical meshes 24x48"), "{out}");
    assert!(out.contains("4 of 4 layouts"), "{out}");
    let file = |phase: &str, surface: &str| dir.join("lay").join(format!("{phase}-{surface}.vtk"));
    let grids: Vec<MeshData> = ["ED", "ES"]
        .iter()
        .flat_map(|p| ["LV_ENDO", "LV_EPI"].map(|sf| read(&file(&format!("patient1-{p}"), sf))))
        .collect();
    for g in &grids {
        assert_eq!(g.mesh.positions.len(), 24 * 48 + 2);
        assert_eq!(
            g.mesh.triangles, grids[0].mesh.triangles,
            "one layout for all"
        );
    }

    // The reference phase's endocardium is exactly reconstruct's layout of that file.
    let (_, _, single) = with_grid(&patient1("ED"), &dir, "ed", &[]);
    let worst = single
        .positions
        .iter()
        .zip(&grids[0].mesh.positions)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0f64, f64::max);
    assert!(worst < 1e-9, "ED differs from reconstruct's by {worst} mm");

    // ES starts every ring at ED's septum taken across ES's axis; its own file's septum (what
    // reconstruct on it alone uses) lies septum_turn_deg away.
    let es = entry(&a, "patient1-ES", "LV_ENDO");
    let ed_septum = vector(&a["septum"]["direction"]);
    let es_axis = vector(&es["summary"]["axis"]);
    let across = (ed_septum - es_axis * ed_septum.dot(&es_axis)).normalize();
    let used = vector(&es["summary"]["septum_direction"]);
    assert!(used.dot(&across) > 1.0 - 1e-12, "{used:?} vs {across:?}");
    let es_grid = &grids[2].mesh;
    let lid = es_grid.positions[es_grid.positions.len() - 1];
    let top0 = (es_grid.positions[1 + 23 * 48] - lid).normalize();
    assert!(
        top0.dot(&used) > 0.9999,
        "the top ring starts at the septum"
    );
    let (own, _, _) = with_grid(&patient1("ES"), &dir, "es", &[]);
    let own = vector(&own["anatomical_mesh"]["septum_direction"]);
    let turn = own.dot(&used).clamp(-1.0, 1.0).acos().to_degrees();
    let said = es["septum_turn_deg"].as_f64().unwrap();
    println!("patient 1: ES's own septum {turn:.2} degrees from ED's (reported {said:.2})");
    assert!((turn - said).abs() < 1e-6, "{turn} vs {said}");
    assert!(said > 0.5 && said < 10.0, "{said}");

    // displacement_mm: each vertex's distance from the same vertex at ED, in the file and JSON.
    for (k, surface) in ["LV_ENDO", "LV_EPI"].iter().enumerate() {
        let (ed, es) = (&grids[k], &grids[2 + k]);
        let (name, shift) = es.point_data.as_ref().unwrap();
        assert_eq!(name, "displacement_mm");
        let mut sum = 0.0;
        for ((d, p), q) in shift.iter().zip(&es.mesh.positions).zip(&ed.mesh.positions) {
            assert!((d - (p - q).norm()).abs() < 1e-9);
            sum += d;
        }
        let mean = sum / shift.len() as f64;
        let e = entry(&a, "patient1-ES", surface);
        assert!((e["displacement_mean_mm"].as_f64().unwrap() - mean).abs() < 1e-9);
        // The cavity contracts: its vertices move several millimetres on average.
        assert!(mean > 3.0, "{surface}: {mean} mm");
        let (_, at_ed) = ed.point_data.as_ref().unwrap();
        assert!(at_ed.iter().all(|&d| d == 0.0));
    }
}

#[test]
fn a_phase_drawn_without_the_rv_is_laid_out_on_the_study_septum() {
    let dir = scratch("study-lv-only");
    // ES without its RV contours: its file alone cannot place the septum.
    let text = std::fs::read_to_string(patient1("ES")).unwrap();
    let lv_only: String = text
        .lines()
        .filter(|l| !l.contains("RV_"))
        .map(|l| format!("{l}\n"))
        .collect();
    let es = dir.join("es-lv.csv");
    std::fs::write(&es, lv_only).unwrap();
    let (code, _, err) = run(bin().args([
        "reconstruct",
        s(&es),
        "--surface",
        "LV_ENDO",
        "-o",
        s(&dir.join("x.obj")),
        "--anatomical-mesh",
        s(&dir.join("x.vtk")),
    ]));
    assert_eq!(code, 2, "alone it is refused: {err}");
    let (a, _) = volumes(
        &[&patient1("ED"), &es],
        &dir,
        &["--anatomical-format", "ply"],
    );
    assert_eq!(a["format"], "ply");
    let e = entry(&a, "es-lv", "LV_ENDO");
    assert_eq!(e["file"], "es-lv-LV_ENDO.ply");
    assert!(e["septum_turn_deg"].is_null(), "{e}");
    let grid = read(&dir.join("lay/es-lv-LV_ENDO.ply"));
    assert_eq!(grid.mesh.positions.len(), 1154);
    assert!(grid.point_data.is_some());
}

#[test]
fn what_has_no_layout_is_refused_before_the_runs() {
    let dir = scratch("study-refused");
    let lay = dir.join("lay");
    let refused = |extra: &[&str], inputs: &[&Path], says: &str| {
        let mut args = vec!["volumes"];
        args.extend(inputs.iter().map(|p| s(p)));
        args.extend(extra);
        let (code, _, err) = run(bin().args(&args));
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(says), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(!lay.exists(), "nothing written before a refusal");
    };
    let (ed, es) = (patient1("ED"), patient1("ES"));
    let surfco = data("contours/surfco-example.csv");
    refused(
        &["--anatomical-meshes", s(&lay)],
        &[&surfco, &surfco],
        "no phase's file has RV_INSERT landmarks or RV contours",
    );
    refused(
        &["--surface", "RV_ENDO", "--anatomical-meshes", s(&lay)],
        &[&ed, &es],
        "none is among the surfaces measured",
    );
    refused(
        &["--anatomical-layout", "24x48"],
        &[&ed, &es],
        "add --anatomical-meshes",
    );
    refused(
        &[
            "--anatomical-meshes",
            s(&lay),
            "--anatomical-layout",
            "1x48",
        ],
        &[&ed, &es],
        "2-200 rings",
    );
    refused(
        &["--anatomical-meshes", s(&lay), "--anatomical-format", "txt"],
        &[&ed, &es],
        "one of vtk, vtp, ply, obj, stl",
    );
}

/// The motion the layouts are for, against a known one: ED's contours contracted by a
/// systole-like map, and the RV of that "ES" drawn 4 degrees round the axis (the drawing noise
/// between frames). Laid out on the study's septum, each ES grid vertex lies where the map takes
/// the ED grid vertex; laid out on its own file's septum (reconstruct alone), the grid turns
/// with the RV's drawing and every vertex lands off.
#[test]
fn a_known_contraction_is_recovered_vertex_by_vertex_despite_the_rvs_drawing() {
    let dir = scratch("study-known-motion");
    let (rep, _, ed) = with_grid(&patient1("ED"), &dir, "ed", &[]);
    let n = vector(&rep["anatomical_mesh"]["axis"]);
    let centre = ed.positions[ed.positions.len() - 1];
    let contract = move |p: Vec3| {
        let d = p - centre;
        let h = d.dot(&n);
        centre + n * (0.9 * h) + (d - n * h) * 0.8
    };
    // 4 degrees about the axis through the base's centre (Rodrigues).
    let (sin, cos) = 4f64.to_radians().sin_cos();
    let turned = move |p: Vec3| {
        let v = contract(p) - centre;
        centre + v * cos + n.cross(&v) * sin + n * (n.dot(&v) * (1.0 - cos))
    };
    let es = dir.join("systole.csv");
    moved_csv(&patient1("ED"), &es, contract, turned);

    let (a, _) = volumes(&[&patient1("ED"), &es], &dir, &[]);
    let e = entry(&a, "systole", "LV_ENDO");
    let said = e["septum_turn_deg"].as_f64().unwrap();
    assert!(
        (said - 4.0).abs() < 0.5,
        "its own septum {said} degrees round"
    );
    let study = read(&dir.join("lay/systole-LV_ENDO.vtk")).mesh;
    let (_, _, own) = with_grid(&es, &dir, "own", &[]);
    let error = |grid: &heartmesh_core::TriMesh| {
        let d: Vec<f64> = (1..ed.positions.len() - 1)
            .map(|v| (grid.positions[v] - contract(ed.positions[v])).norm())
            .collect();
        d.iter().sum::<f64>() / d.len() as f64
    };
    let (on_study, on_own) = (error(&study), error(&own));
    println!(
        "known contraction, RV drawn 4 degrees round: grid vertex vs contracted ED grid, mean \
         {on_study:.3} mm on the study's septum, {on_own:.3} mm on the file's own"
    );
    assert!(on_study < 0.5, "{on_study} mm");
    assert!(on_own > 2.0 * on_study, "{on_own} vs {on_study} mm");
}

#[test]
fn the_readme_study_example_prints_as_shown() {
    let dir = scratch("study-readme");
    let folder = data("contours/bivme-example-patient1");
    let (ed, es) = (folder.join("GPFile_000.txt"), folder.join("GPFile_009.txt"));
    let (code, out, err) = run(bin().current_dir(&dir).args([
        "volumes",
        s(&ed),
        s(&es),
        "--surface",
        "LV_ENDO,LV_EPI",
        "--anatomical-meshes",
        "grids",
    ]));
    assert_eq!(code, 0, "{err}");
    let readme =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../README.md"))
            .unwrap();
    let shown = readme
        .split("--surface LV_ENDO,LV_EPI --anatomical-meshes grids\n...\n")
        .nth(1)
        .and_then(|rest| rest.split("```").next())
        .expect("the README's study example");
    assert!(out.ends_with(shown), "{out}\nvs the README:\n{shown}");
    assert_eq!(std::fs::read_dir(dir.join("grids")).unwrap().count(), 4);
}
