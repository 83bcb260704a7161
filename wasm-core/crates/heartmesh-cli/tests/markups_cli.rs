//! 3D Slicer markups end to end on real contours: biv-me patient 1's ED curves redrawn as a user
//! draws them in Slicer (one `.mrk.json` per curve, a control point every 8 mm along it, closed
//! curves where the file's are closed), given as a folder, reconstructed surface by surface and
//! measured against the file's own dense curves and its own meshes.

mod common;
use common::{bin, data, read_mesh_file, reconstruct_report, run, scratch};
use heartmesh_core::contours::Polyline;
use heartmesh_core::io::read_contours;
use heartmesh_core::metrics::contour_to_mesh;
use heartmesh_core::ContourSet;
use std::path::{Path, PathBuf};

const SCHEMA: &str = "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/markups-schema-v1.0.3.json#";

/// Control points every `step` mm of arc along a piece (an open one's last point too), one run
/// per stretch between the file's jumps (steps over 5 x the median spacing: the gaps real files
/// leave, which the core's cleaning splits at; a Slicer user draws two curves there).
fn control_points(piece: &Polyline, step: f64) -> Vec<(Vec<[f64; 3]>, bool)> {
    let p = &piece.points;
    let mut gaps: Vec<f64> = p.windows(2).map(|w| (w[1] - w[0]).norm()).collect();
    gaps.sort_by(f64::total_cmp);
    let jump = 5.0 * gaps[gaps.len() / 2];
    let mut runs = vec![vec![p[0]]];
    let mut since = 0.0;
    for w in p.windows(2) {
        let d = (w[1] - w[0]).norm();
        let run = runs.last_mut().unwrap();
        if d > jump {
            if run.last() != Some(&w[0]) {
                run.push(w[0]);
            }
            runs.push(vec![w[1]]);
            since = 0.0;
            continue;
        }
        since += d;
        if since >= step {
            run.push(w[1]);
            since = 0.0;
        }
    }
    // Every stretch keeps its last point (an open curve's end; where a closed one comes round).
    let end = p[p.len() - 1];
    let tail = runs.last_mut().unwrap();
    if tail.last() != Some(&end) {
        tail.push(end);
    }
    // A run that starts mid-curve (its last point beside its first, the jump elsewhere) is one
    // curve from the jump round to the jump: its last stretch goes on into its first.
    let closed = piece.closed && runs.len() == 1;
    if runs.len() > 1 && (p[p.len() - 1] - p[0]).norm() <= jump {
        let first = runs.remove(0);
        runs.last_mut().unwrap().extend(first);
    }
    let tail = runs.last_mut().unwrap();
    if closed && tail.len() > 3 && (tail[tail.len() - 1] - p[0]).norm() < step / 2.0 {
        tail.pop();
    }
    runs.into_iter()
        .map(|r| (r.iter().map(|v| [v.x, v.y, v.z]).collect(), closed))
        .collect()
}

/// One file per contour of `set` (a markup per piece), named after the contour.
fn write_folder(set: &ContourSet, dir: &Path, step: f64) {
    std::fs::create_dir_all(dir).unwrap();
    for c in &set.contours {
        let markups: Vec<serde_json::Value> = c
            .pieces
            .iter()
            .flat_map(|piece| control_points(piece, step))
            .map(|(run, closed)| {
                let points: Vec<serde_json::Value> = run
                    .iter()
                    .enumerate()
                    .map(|(k, p)| serde_json::json!({"id": format!("{}", k + 1), "label": format!("{}-{}", c.id, k + 1), "position": p, "positionStatus": "defined"}))
                    .collect();
                serde_json::json!({
                    "type": if closed { "ClosedCurve" } else { "Curve" },
                    "name": c.id, "coordinateSystem": "LPS", "coordinateUnits": "mm",
                    "controlPoints": points,
                })
            })
            .collect();
        let file = serde_json::json!({"@schema": SCHEMA, "markups": markups});
        std::fs::write(dir.join(format!("{}.mrk.json", c.id)), file.to_string()).unwrap();
    }
}

/// One legacy point list file (`.fcsv`, as Slicer 4 saved a point list) per stretch of each contour
/// of `set`, a point every `step` mm clicked along it: a contour's first stretch named after it,
/// any other `<id>_2`, ... (a point list holds one stretch). The file does not say whether a
/// list closes; the reader tells it from where its ends are.
fn write_fcsv_folder(set: &ContourSet, dir: &Path, step: f64) {
    std::fs::create_dir_all(dir).unwrap();
    for c in &set.contours {
        let runs: Vec<_> = c
            .pieces
            .iter()
            .flat_map(|p| control_points(p, step))
            .collect();
        for (k, (run, _)) in runs.iter().enumerate() {
            let name = if k == 0 {
                c.id.clone()
            } else {
                format!("{}_{}", c.id, k + 1)
            };
            let mut text = String::from(
                "# Markups fiducial file version = 4.10\n# CoordinateSystem = 1\n\
                 # columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n",
            );
            for (i, [x, y, z]) in run.iter().enumerate() {
                text.push_str(&format!(
                    "vtkMRMLMarkupsFiducialNode_{i},{x},{y},{z},0,0,0,1,1,1,0,{name}-{},,\n",
                    i + 1
                ));
            }
            std::fs::write(dir.join(format!("{name}.fcsv")), text).unwrap();
        }
    }
}

fn s(p: &Path) -> String {
    p.display().to_string()
}

/// Biv-me patient 1 (ED) redrawn by `write` as a Slicer user leaves it (a point every 8 mm along
/// each curve), each surface reconstructed from that folder: closed, in LPS, within 1 mm (mean) of
/// the file's own dense curves (not the splines through their points) and within 2 % of the
/// volume the CSV itself gives.
fn redrawn_surfaces_match_the_csv(name: &str, write: fn(&ContourSet, &Path, f64)) {
    let dir = scratch(name);
    let csv = data("contours/bivme-example-patient1/patient1-ED.csv");
    let set = read_contours("patient1-ED.csv", &std::fs::read(&csv).unwrap()).unwrap();
    let folder = dir.join("patient1-ED");
    write(&set, &folder, 8.0);
    for surface in ["LV_ENDO", "LV_EPI", "RV_ENDO"] {
        let (code, err, report) =
            reconstruct_report(&[s(&folder)], &["--surface", surface, "--quiet"], &dir);
        assert_eq!(code, 0, "{surface}: {err}");
        let report = report.unwrap();
        assert_eq!(report["watertight"], true, "{surface}");
        assert_eq!(report["coordinate_system"], "LPS", "{surface}");
        let mesh = read_mesh_file(&dir.join("m.obj"));
        let volume = report["volume_ml"].as_f64().unwrap();
        let (code, err, from_csv) =
            reconstruct_report(&[s(&csv)], &["--surface", surface, "--quiet"], &dir);
        assert_eq!(code, 0, "{surface} csv: {err}");
        let csv_volume = from_csv.unwrap()["volume_ml"].as_f64().unwrap();
        let drawn: Vec<_> = set
            .contours
            .iter()
            .filter(|c| c.surface.as_deref() == Some(surface))
            .cloned()
            .collect();
        let d = contour_to_mesh(&drawn, &[], &mesh).overall;
        let change = (volume / csv_volume - 1.0) * 100.0;
        eprintln!(
            "{name} {surface}: {} curves; to the file's curves mean {:.3} max {:.2} mm; volume {volume:.1} ml (csv {csv_volume:.1}, {change:+.1} %)",
            drawn.len(),
            d.mean,
            d.max
        );
        assert!(d.mean <= 1.0, "{surface}: mean {} mm", d.mean);
        assert!(change.abs() <= 2.0, "{surface}: volume {change:+.1} %");
    }
}

#[test]
fn a_folder_of_slicer_curves_reconstructs_each_surface_as_its_csv_does() {
    // The splines through 8 mm points follow the curves (measured: volumes +0.4, +0.4, +0.2 %;
    // the control points' polygon alone gives LV_ENDO -1.8 %).
    redrawn_surfaces_match_the_csv("markups-patient1", write_folder);
}

#[test]
fn a_folder_of_slicer_4_point_lists_reconstructs_each_surface_as_its_csv_does() {
    // Every list is read as the curve it was clicked along (closed rings closed, splined as Slicer
    // draws a curve): measured, RV_ENDO is the .mrk.json folder's mesh to the figure and the LVs'
    // volumes are within 1.2 % of the CSV's. A stretch of two points in a list of its own is a
    // speck, left out (LV_ENDO's max 6.6 mm, at that stretch).
    redrawn_surfaces_match_the_csv("fcsv-patient1", write_fcsv_folder);
}

#[test]
fn the_files_order_does_not_matter_and_a_bad_file_is_named() {
    let dir = scratch("markups-order");
    let csv = data("contours/bivme-example-patient1/patient1-ED.csv");
    let set = read_contours("patient1-ED.csv", &std::fs::read(&csv).unwrap()).unwrap();
    let lv = ContourSet {
        contours: set
            .contours
            .iter()
            .filter(|c| c.surface.as_deref() == Some("LV_ENDO"))
            .cloned()
            .collect(),
        ..ContourSet::default()
    };
    let folder = dir.join("lv");
    write_folder(&lv, &folder, 8.0);
    let mut files: Vec<String> = std::fs::read_dir(&folder)
        .unwrap()
        .map(|e| s(&e.unwrap().path()))
        .collect();
    files.sort();
    // The mesh's vertices and triangles (the header names the file given first).
    let mesh_of = |inputs: &[String], out: &str| {
        let path = dir.join(out);
        let (code, _, err) = run(bin()
            .arg("reconstruct")
            .args(inputs)
            .arg("-o")
            .arg(&path)
            .arg("--quiet"));
        assert_eq!(code, 0, "{err}");
        let body: Vec<String> = std::fs::read_to_string(path)
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(str::to_string)
            .collect();
        assert!(body.len() > 1000, "{} lines", body.len());
        body
    };
    let forward = mesh_of(&files, "forward.obj");
    files.reverse();
    let reverse = mesh_of(&files, "reverse.obj");
    assert!(reverse == forward, "the files' order changed the mesh");
    let whole = mesh_of(&[s(&folder)], "folder.obj");
    assert!(whole == forward, "the folder differs from its files");
    // Saved as a Slicer scene, the folder holds the scene file and the images too: set aside.
    std::fs::write(
        folder.join("Scene.mrml"),
        "<MRML version=\"Slicer5.6\"></MRML>\n",
    )
    .unwrap();
    std::fs::write(folder.join("cine.nrrd"), "NRRD0004\ntype: short\n").unwrap();
    let path = dir.join("scene.obj");
    let (code, _, err) = run(bin().arg("reconstruct").arg(&folder).arg("-o").arg(&path));
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("2 other file(s) of the Slicer scene set aside (the contours come from the Slicer markups): ")
            && err.contains("Scene.mrml")
            && err.contains("cine.nrrd"),
        "{err}"
    );
    assert!(
        mesh_of(&[s(&folder)], "scene2.obj") == forward,
        "the scene's folder differs"
    );
    // A damaged file among them: exit 2 and one line naming it.
    std::fs::write(folder.join("s05_SAX_LV_ENDOCARDIAL.mrk.json"), format!("{{\"@schema\": \"{SCHEMA}\", \"markups\": [{{\"type\": \"ClosedCurve\", \"controlPoints\": [")).unwrap();
    let (code, _, err) = run(bin()
        .arg("reconstruct")
        .arg(&folder)
        .arg("-o")
        .arg(dir.join("x.obj")));
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("s05_SAX_LV_ENDOCARDIAL.mrk.json") && err.contains("not valid JSON"),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1, "{err}");
}

#[test]
fn volumes_takes_a_folder_of_markups_per_phase() {
    let dir = scratch("markups-volumes");
    let fixture = PathBuf::from(common::core_data("slicer-markups-patient1"));
    // A second phase: the same curves without the most apical short-axis ring.
    let other = dir.join("without-s06");
    std::fs::create_dir_all(&other).unwrap();
    for e in std::fs::read_dir(&fixture).unwrap() {
        let path = e.unwrap().path();
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        if !name.starts_with("s06_SAX_LV_ENDOCARDIAL") {
            std::fs::copy(&path, other.join(name)).unwrap();
        }
    }
    let json = dir.join("v.json");
    let (code, _, err) = run(bin()
        .arg("volumes")
        .arg(&fixture)
        .arg(&other)
        .arg("--json")
        .arg(&json)
        .arg("--quiet"));
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let lv = v["function"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["surface"] == "LV_ENDO")
        .unwrap();
    assert_eq!(lv["phases_used"], 2);
    // Each phase's volume is its folder's reconstruction.
    for (folder, key) in [(&fixture, "edv_ml"), (&other, "esv_ml")] {
        let (code, err, report) =
            reconstruct_report(&[s(folder)], &["--surface", "LV_ENDO", "--quiet"], &dir);
        assert_eq!(code, 0, "{err}");
        let ml = report.unwrap()["volume_ml"].as_f64().unwrap();
        assert!(
            (lv[key].as_f64().unwrap() - ml).abs() < 1e-9,
            "{key}: {lv} vs {ml}"
        );
    }
    // Two phases, not one read twice.
    assert!(
        (lv["edv_ml"].as_f64().unwrap() - lv["esv_ml"].as_f64().unwrap()).abs() > 0.1,
        "{lv}"
    );
    // The two phases' folders given as one (their parent): refused in one line naming them, not
    // joined into rings of both phases.
    let patient = dir.join("patient");
    for (from, phase) in [(&fixture, "ED"), (&other, "ES")] {
        std::fs::create_dir_all(patient.join(phase)).unwrap();
        for e in std::fs::read_dir(from).unwrap() {
            let path = e.unwrap().path();
            std::fs::copy(&path, patient.join(phase).join(path.file_name().unwrap())).unwrap();
        }
    }
    let (code, _, err) = run(bin()
        .arg("reconstruct")
        .arg(&patient)
        .arg("-o")
        .arg(dir.join("both.obj")));
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.starts_with("heartmesh: Slicer markups from 2 folders (")
            && err.contains("hold curves of the same names (s02_SAX_LV_ENDOCARDIAL")
            && err.contains("open one folder at a time"),
        "{err}"
    );
}
