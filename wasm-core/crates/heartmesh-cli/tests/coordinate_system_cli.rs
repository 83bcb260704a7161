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
