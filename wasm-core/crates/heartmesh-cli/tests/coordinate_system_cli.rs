//! The patient frame of a mesh file: 3D Slicer places a mesh by the `SPACE=LPS` / `SPACE=RAS` it
//! finds in the file (VTK title line, STL header, PLY and OBJ comments, VTP field data `SPACE`)
//! and takes LPS without one, which mirrors a mesh made from a NIfTI (RAS) in x and y. Every mesh
//! the command line writes from a format that fixes its frame says it there, and the report
//! gives it (`coordinate_system`); a CSV, whose frame is the user's, says nothing.

mod common;
use common::{bin, core_data, data, read_mesh_file, run, scratch};
use std::path::Path;

/// The first header line every mesh file starts with.
const VERSION: &str = concat!("heartmesh ", env!("CARGO_PKG_VERSION"));

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `reconstruct INPUT --surface LV_ENDO -o OUT --report R`: the report.
fn reconstruct(input: &str, out: &Path) -> serde_json::Value {
    let report = out.with_extension("json");
    let (code, _, err) = run(bin().args([
        "reconstruct",
        input,
        "--surface",
        "LV_ENDO",
        "-o",
        s(out),
        "--report",
        s(&report),
        "--quiet",
    ]));
    assert_eq!(code, 0, "{input}: {err}");
    json(&report)
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn text(path: &Path) -> String {
    String::from_utf8_lossy(&std::fs::read(path).unwrap()).into_owned()
}

#[test]
fn each_format_says_the_patient_frame_where_slicer_reads_it() {
    let dir = scratch("coordinate-system-formats");
    let gpfile = data("contours/bivme-example-patient1/GPFile_000.txt");
    let gp = gpfile.to_str().unwrap();
    for ext in ["obj", "ply", "vtk", "vtp", "stl"] {
        let out = dir.join(format!("gp.{ext}"));
        let rep = reconstruct(gp, &out);
        assert_eq!(rep["coordinate_system"], "LPS", "{ext}");
        let body = text(&out);
        match ext {
            "obj" => assert_eq!(
                body.lines().take(2).collect::<Vec<_>>(),
                [format!("# {VERSION}"), "# SPACE=LPS".to_string()]
            ),
            "ply" => assert!(body.contains("\ncomment SPACE=LPS\n"), "{ext}"),
            "vtk" => {
                let title = body.lines().nth(1).unwrap();
                assert!(title.starts_with(&format!("{VERSION} | SPACE=LPS | ")), "{title}");
            }
            "vtp" => assert!(
                body.contains(
                    "<PolyData>\n<FieldData>\n<Array type=\"String\" Name=\"SPACE\" \
                     NumberOfTuples=\"1\" format=\"ascii\">\n76 80 83 0\n</Array>\n</FieldData>\n<Piece "
                ),
                "{}",
                &body[..600.min(body.len())]
            ),
            _ => {
                let header = &std::fs::read(&out).unwrap()[..80];
                let header = String::from_utf8_lossy(header);
                assert!(header.starts_with(&format!("{VERSION} | SPACE=LPS | ")), "{header}");
            }
        }
        // The file reads back as before (the field data is not in the way of our reader).
        assert_eq!(
            read_mesh_file(&out).triangles.len() as u64,
            rep["triangles"].as_u64().unwrap(),
            "{ext}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn label_maps_say_their_own_frame_and_a_csv_none() {
    let dir = scratch("coordinate-system-inputs");
    let truth = |n: &str| data(&format!("meshes/{n}")).to_str().unwrap().to_string();
    let (endo, epi) = (
        truth("cardiomesh-spasm-LV_endo.obj"),
        truth("cardiomesh-spasm-LV_epi.obj"),
    );
    // The same segmentation as NIfTI (RAS) and as 3D Slicer's NRRD (LPS).
    for (name, want) in [("seg.nii.gz", "RAS"), ("seg.seg.nrrd", "LPS")] {
        let seg = dir.join(name);
        let (code, _, err) = run(bin().args([
            "segment",
            "--lv-endo",
            &endo,
            "--lv-epi",
            &epi,
            "-o",
            s(&seg),
            "--quiet",
        ]));
        assert_eq!(code, 0, "{err}");
        let out = dir.join(format!("{name}.vtk"));
        let rep = reconstruct(s(&seg), &out);
        assert_eq!(rep["coordinate_system"], want, "{name}");
        // `info` says it too, in its JSON and on its coordinates line.
        let (code, info, err) = run(bin().args(["info", s(&seg), "--json"]));
        assert_eq!(code, 0, "{err}");
        let info: serde_json::Value = serde_json::from_str(&info).unwrap();
        assert_eq!(info["coordinate_system"], want, "{name}");
        let (_, lines, _) = run(bin().args(["info", s(&seg)]));
        assert!(
            lines.contains(&format!("\n  coordinates (mm, {want}): x ")),
            "{lines}"
        );
        let title = text(&out).lines().nth(1).unwrap().to_string();
        assert!(
            title.starts_with(&format!("{VERSION} | SPACE={want} | ")),
            "{title}"
        );
    }
    // A DICOM SEG: DICOM's frame.
    let out = dir.join("dicom-seg.obj");
    let rep = reconstruct(&core_data("spasm-seg.dcm"), &out);
    assert_eq!(rep["coordinate_system"], "LPS");
    assert!(text(&out).contains("\n# SPACE=LPS\n"));
    // A CSV's frame is whatever its writer used: nothing said, null in the report.
    let csv = data("contours/surfco-example.csv");
    let out = dir.join("surfco.vtk");
    let (code, _, err) = run(bin().args([
        "reconstruct",
        csv.to_str().unwrap(),
        "-o",
        s(&out),
        "--report",
        s(&dir.join("surfco.json")),
        "--quiet",
    ]));
    assert_eq!(code, 0, "{err}");
    let rep = json(&dir.join("surfco.json"));
    assert!(rep["coordinate_system"].is_null(), "{rep}");
    assert!(!text(&out).contains("SPACE="));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn walls_say_it_too() {
    let dir = scratch("coordinate-system-wall");
    let gpfile = data("contours/bivme-example-patient1/GPFile_000.txt");
    let out = dir.join("wall.ply");
    let report = dir.join("wall.json");
    let (code, _, err) = run(bin().args([
        "myocardium",
        gpfile.to_str().unwrap(),
        "-o",
        s(&out),
        "--report",
        s(&report),
        "--quiet",
    ]));
    assert_eq!(code, 0, "{err}");
    assert!(text(&out).contains("\ncomment SPACE=LPS\n"));
    let rep = json(&report);
    assert_eq!(rep["coordinate_system"], "LPS");
    assert_eq!(rep["surfaces"]["LV_EPI"]["coordinate_system"], "LPS");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `path`'s text with every OBJ vertex mirrored into the other frame (x and y negated) and its
/// `SPACE=` line replaced by `space` (dropped when None).
fn mirrored_obj(path: &Path, space: Option<&str>) -> String {
    let mut out = String::new();
    for line in text(path).lines() {
        if let Some(rest) = line.strip_prefix("v ") {
            let v: Vec<f64> = rest
                .split_whitespace()
                .map(|t| t.parse().unwrap())
                .collect();
            out += &format!("v {} {} {}\n", -v[0], -v[1], v[2]);
        } else if line.starts_with("# SPACE=") {
            if let Some(s) = space {
                out += &format!("# SPACE={s}\n");
            }
        } else {
            out += line;
            out.push('\n');
        }
    }
    out
}

/// `compare TRUTH MESH [ARGS] --json`: the report and stderr.
fn compare(truth: &Path, mesh: &Path, more: &[&str]) -> (serde_json::Value, String) {
    let (code, out, err) = run(bin()
        .args(["compare", s(truth), s(mesh), "--json"])
        .args(more));
    assert_eq!(code, 0, "{err}");
    (serde_json::from_str(&out).unwrap(), err)
}

/// A mesh file's frame survives `convert` into every other mesh format (the readers take the tag
/// back), `info` states it, and `compare` takes a mesh in the mirrored frame into the truth's
/// before measuring: mirrored in x and y, the two copies of one mesh are otherwise centimetres
/// apart.
#[test]
fn convert_keeps_the_frame_and_compare_measures_in_one() {
    let dir = scratch("coordinate-system-convert");
    let gpfile = data("contours/bivme-example-patient1/GPFile_000.txt");
    let gp = gpfile.to_str().unwrap();
    let stl = dir.join("gp.stl");
    reconstruct(gp, &stl);
    for ext in ["obj", "ply", "vtk", "vtp", "stl"] {
        let out = dir.join(format!("converted.{ext}"));
        let (code, _, err) = run(bin().args(["convert", s(&stl), s(&out), "--quiet"]));
        assert_eq!(code, 0, "{ext}: {err}");
        let (code, info, err) = run(bin().args(["info", s(&out), "--json"]));
        assert_eq!(code, 0, "{ext}: {err}");
        let info: serde_json::Value = serde_json::from_str(&info).unwrap();
        assert_eq!(info["coordinate_system"], "LPS", "{ext}");
        let (_, lines, _) = run(bin().args(["info", s(&out)]));
        assert!(lines.contains("\n  coordinates (mm, LPS): x "), "{lines}");
    }
    let lps = dir.join("converted.obj");
    let ras = dir.join("ras.obj");
    std::fs::write(&ras, mirrored_obj(&lps, Some("RAS"))).unwrap();
    let untagged = dir.join("untagged.obj");
    std::fs::write(&untagged, mirrored_obj(&lps, None)).unwrap();

    let (same, err) = compare(&stl, &ras, &[]);
    assert!(
        err.contains("ras.obj is in RAS and") && err.contains("taken into LPS"),
        "{err}"
    );
    assert_eq!(same["coordinate_system"], "LPS");
    assert_eq!(same["mesh_converted_from"], "RAS");
    let d = same["mesh_to_truth"]["mean"].as_f64().unwrap();
    let h = same["hausdorff"].as_f64().unwrap();
    assert!(d < 1e-4 && h < 1e-3, "mean {d} mm, Hausdorff {h} mm");
    // Untagged, the mirrored copy is measured as it stands: far apart.
    let (apart, err) = compare(&stl, &untagged, &[]);
    assert!(!err.contains("taken into"), "{err}");
    assert_eq!(apart["coordinate_system"], "LPS");
    assert!(apart["mesh_converted_from"].is_null());
    let far = apart["mesh_to_truth"]["mean"].as_f64().unwrap();
    assert!(far > 10.0, "mirrored copy only {far} mm away");

    // Clipping contours in LPS against a truth in RAS are taken into RAS too: the clipped
    // volumes match those of the LPS pair.
    let (lps_pair, _) = compare(&stl, &lps, &["--clip-contours", gp, "--surface", "LV_ENDO"]);
    let (ras_pair, err) = compare(&ras, &stl, &["--clip-contours", gp, "--surface", "LV_ENDO"]);
    assert!(err.contains("GPFile_000.txt is in LPS"), "{err}");
    for key in ["volume_truth_ml", "volume_mesh_ml"] {
        let (a, b) = (
            lps_pair[key].as_f64().unwrap(),
            ras_pair[key].as_f64().unwrap(),
        );
        assert!((a - b).abs() < 1e-3 * a, "{key}: {a} vs {b} ml");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_csv_made_of_framed_contours_says_the_frame_and_is_read_back_in_it() {
    let dir = scratch("coordinate-system-csv");
    let gpfile = data("contours/bivme-example-patient1/GPFile_000.txt");
    let csv = dir.join("patient1.csv");
    let (code, _, err) = run(bin().args(["convert", s(&gpfile), s(&csv)]));
    assert_eq!(code, 0, "{err}");
    let body = text(&csv);
    assert!(
        body.starts_with("# SPACE=LPS\ncontour,x,y,z,surface\n"),
        "{}",
        &body[..60]
    );
    // Read back: the mesh and the report say LPS, as the GPFile's do, and the same mesh.
    let from_csv = reconstruct(s(&csv), &dir.join("from-csv.obj"));
    let from_gp = reconstruct(s(&gpfile), &dir.join("from-gp.obj"));
    assert_eq!(from_csv["coordinate_system"], "LPS");
    assert!(text(&dir.join("from-csv.obj")).contains("\n# SPACE=LPS\n"));
    let (a, b) = (
        from_csv["volume_ml"].as_f64().unwrap(),
        from_gp["volume_ml"].as_f64().unwrap(),
    );
    assert!((a - b).abs() < 1e-6 * b, "{a} vs {b} ml");
    // `info` says it on its coordinates line.
    let (_, lines, _) = run(bin().args(["info", s(&csv)]));
    assert!(lines.contains("\n  coordinates (mm, LPS): x "), "{lines}");
    let _ = std::fs::remove_dir_all(&dir);
}
