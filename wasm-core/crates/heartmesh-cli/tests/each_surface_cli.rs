//! `reconstruct --surface all` (session 19): every surface of a biventricular file in one command,
//! each to files named after it, each mesh the one `--surface X` gives; a surface that cannot be
//! built is named and does not stop the others; a note about the whole file is said once.

mod common;
use common::{bin, data, ellipsoid_lv_csv, mesh_lines, run, scratch};
use std::path::Path;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn every_surface_of_a_biventricular_file_gets_the_mesh_its_own_run_gives() {
    let dir = scratch("all");
    let input = data("contours/bivme-example-patient1/patient1-ED.csv");
    let out = dir.join("p1.obj");
    let report = dir.join("p1.json");
    let (code, stdout, err) = run(bin().args([
        "reconstruct",
        s(&input),
        "-o",
        s(&out),
        "--report",
        s(&report),
        "--surface",
        "all",
    ]));
    assert_eq!(code, 0, "{err}");
    let surfaces = ["RV_ENDO", "RV_EPI", "LV_EPI", "LV_ENDO"];
    // One summary line per surface, in the file's order.
    let named: Vec<&str> = stdout
        .lines()
        .map(|l| l.split(':').next().unwrap_or(""))
        .collect();
    let want: Vec<String> = surfaces
        .iter()
        .map(|x| s(&dir.join(format!("p1-{x}.obj"))).to_string())
        .collect();
    assert_eq!(named, want, "{stdout}");
    // The crossing-gap note is about the file: said once, not four times.
    let notes = err
        .lines()
        .filter(|l| l.contains("where their planes cross"))
        .count();
    assert_eq!(notes, 1, "{err}");
    for x in surfaces {
        let one = dir.join(format!("one-{x}.obj"));
        let (code, _, e) = run(bin().args([
            "reconstruct",
            s(&input),
            "-o",
            s(&one),
            "--surface",
            x,
            "--quiet",
        ]));
        assert_eq!(code, 0, "{x}: {e}");
        let (all, own) = (
            mesh_lines(&dir.join(format!("p1-{x}.obj"))),
            mesh_lines(&one),
        );
        assert!(
            all.len() > 1000 && all == own,
            "{x}: another mesh than --surface {x}"
        );
        let rep: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.join(format!("p1-{x}.json"))).unwrap(),
        )
        .unwrap();
        assert_eq!(rep["surface"].as_str(), Some(x));
        let mean = rep["contour_to_mesh"]["mean"].as_f64().unwrap();
        assert!(
            mean > 0.0 && mean < 1.0,
            "{x}: contour-to-mesh mean {mean} mm"
        );
    }
    assert!(
        !out.exists() && !report.exists(),
        "the unsuffixed names are not written"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_surface_that_cannot_be_built_is_named_and_the_others_are_still_written() {
    let dir = scratch("all-one-fails");
    // The ellipsoid LV plus an "RV" of two points: too little for a surface.
    let mut csv = ellipsoid_lv_csv(true);
    csv.push_str("rv1,0,40,0,RV_ENDO\nrv1,1,41,0,RV_ENDO\n");
    let input = dir.join("two.csv");
    std::fs::write(&input, csv).unwrap();
    let out = dir.join("m.stl");
    let (code, stdout, err) =
        run(bin().args(["reconstruct", s(&input), "-o", s(&out), "--surface", "ALL"]));
    assert_eq!(code, 2, "{err}");
    let lines: Vec<&str> = err
        .lines()
        .filter(|l| l.contains("surface RV_ENDO:"))
        .collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(
        lines[0].starts_with(&format!("heartmesh: surface RV_ENDO: {}", s(&input))),
        "{err}"
    );
    assert!(
        stdout.starts_with(s(&dir.join("m-LV_ENDO.stl"))),
        "{stdout}"
    );
    let stl = std::fs::metadata(dir.join("m-LV_ENDO.stl")).unwrap().len();
    assert!(stl > 50_000, "LV mesh of {stl} bytes");
    assert!(!dir.join("m-RV_ENDO.stl").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn all_on_a_file_without_surface_labels_is_its_one_surface() {
    let dir = scratch("all-unlabelled");
    let input = data("contours/surfco-example.csv");
    let (a, b) = (dir.join("a.obj"), dir.join("b.obj"));
    let (code, _, err) = run(bin().args([
        "reconstruct",
        s(&input),
        "-o",
        s(&a),
        "--surface",
        "all",
        "--quiet",
    ]));
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = run(bin().args(["reconstruct", s(&input), "-o", s(&b), "--quiet"]));
    assert_eq!(code, 0, "{err}");
    let (ma, mb) = (mesh_lines(&a), mesh_lines(&b));
    assert!(ma.len() > 1000 && ma == mb);
    let _ = std::fs::remove_dir_all(&dir);
}
