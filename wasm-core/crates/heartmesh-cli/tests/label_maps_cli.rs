//! Segmentations on the command line (session 21): `heartmesh segment` paints reference surfaces
//! as a NIfTI label map, `heartmesh reconstruct SEG.nii.gz` makes a mesh of each structure and
//! `convert` turns the label map into contours; a damaged or non-label NIfTI is refused in one
//! line naming the file.

mod common;
use common::{bin, data, run, scratch};

fn mesh(name: &str) -> String {
    data(&format!("meshes/{name}"))
        .to_str()
        .unwrap()
        .to_string()
}

/// `heartmesh segment` of the SPASM LV (cavity and epicardium) and its RV free wall to `seg`,
/// with `extra` arguments: the painted study of three structures the tests read back.
fn segment_spasm(seg: &str, extra: &[&str]) -> (i32, String, String) {
    run(bin()
        .args([
            "segment",
            "--lv-endo",
            &mesh("cardiomesh-spasm-LV_endo.obj"),
            "--lv-epi",
            &mesh("cardiomesh-spasm-LV_epi.obj"),
            "--rv-free-wall",
            &mesh("cardiomesh-spasm-RV_endo.obj"),
            "-o",
            seg,
        ])
        .args(extra))
}

/// `heartmesh reconstruct FILES --surface SURFACE` with the mesh and report `dir/NAME.*`: the
/// report and stderr (the notes), the run required to succeed.
fn reconstruct(
    dir: &std::path::Path,
    files: &[std::path::PathBuf],
    surface: &str,
    name: &str,
) -> (serde_json::Value, String) {
    let report = dir.join(format!("{name}.json"));
    let (code, _, err) = run(bin()
        .arg("reconstruct")
        .args(files)
        .args(["--surface", surface, "-o"])
        .arg(dir.join(format!("{name}.obj")))
        .arg("--report")
        .arg(&report));
    assert_eq!(code, 0, "{err}");
    let r = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    (r, err)
}

/// How many of a report's contours are long-axis ones.
fn lax_count(r: &serde_json::Value) -> usize {
    r["per_contour"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["kind"] == "LAX")
        .count()
}

#[test]
fn a_painted_segmentation_reconstructs_every_structure() {
    let dir = scratch("label-maps");
    let seg = dir.join("spasm.nii.gz");
    let seg = seg.to_str().unwrap();
    let (code, out, err) = segment_spasm(seg, &[]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("1.25 x 1.25 mm pixels, 10.0 mm slices"),
        "{out}"
    );
    let out_mesh = dir.join("m.obj");
    let report = dir.join("r.json");
    let (code, _, err) = run(bin().args([
        "reconstruct",
        seg,
        "--surface",
        "all",
        "-o",
        out_mesh.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
    ]));
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("3 LV cavity (LV_ENDO)") && err.contains("1 RV cavity"),
        "{err}"
    );
    let mut volumes = Vec::new();
    for surface in ["LV_ENDO", "LV_EPI", "RV_ENDO"] {
        let r: serde_json::Value =
            serde_json::from_slice(&std::fs::read(dir.join(format!("r-{surface}.json"))).unwrap())
                .unwrap();
        assert_eq!(r["watertight"], true, "{surface}: {r}");
        assert_eq!(r["quality"]["self_intersections"], 0, "{surface}");
        let c2m = r["contour_to_mesh"]["mean"].as_f64().unwrap();
        assert!(c2m < 1.0, "{surface}: contour-to-mesh mean {c2m}");
        assert!(r["per_contour"].as_array().unwrap().len() >= 4, "{surface}");
        volumes.push(r["volume_ml"].as_f64().unwrap());
    }
    // The epicardium holds cavity and wall: the wall of an adult LV is as large as its cavity.
    assert!(volumes[1] > 1.8 * volumes[0], "{volumes:?}");
    assert!(volumes[2] > 20.0, "{volumes:?}");
    // The same contours as CSV, in mm.
    let csv = dir.join("c.csv");
    let (code, _, err) = run(bin().args(["convert", seg, csv.to_str().unwrap()]));
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(
        text.contains("LV_EPI") && text.contains("slice "),
        "{}",
        &text[..200]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn damaged_and_foreign_nifti_files_are_refused_in_one_line() {
    let dir = scratch("label-maps-bad");
    let seg = dir.join("lv.nii.gz");
    let (code, _, err) = run(bin().args([
        "segment",
        "--lv-endo",
        &mesh("cardiomesh-spasm-LV_endo.obj"),
        "-o",
        seg.to_str().unwrap(),
        "--quiet",
    ]));
    assert_eq!(code, 0, "{err}");
    let bytes = std::fs::read(&seg).unwrap();
    let cut = dir.join("cut.nii.gz");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    // A raw NIfTI whose voxels are MRI intensities (float), not labels.
    let mut image = vec![0u8; 352];
    image[0..4].copy_from_slice(&348i32.to_le_bytes());
    for (n, d) in [3i16, 2, 2, 2, 1, 1, 1, 1].iter().enumerate() {
        image[40 + 2 * n..42 + 2 * n].copy_from_slice(&d.to_le_bytes());
    }
    image[70..72].copy_from_slice(&16i16.to_le_bytes());
    image[72..74].copy_from_slice(&32i16.to_le_bytes());
    for n in 1..4 {
        image[76 + 4 * n..80 + 4 * n].copy_from_slice(&1.5f32.to_le_bytes());
    }
    image[108..112].copy_from_slice(&352f32.to_le_bytes());
    image[344..348].copy_from_slice(b"n+1\0");
    for v in 0..8 {
        image.extend_from_slice(&(v as f32 * 37.3).to_le_bytes());
    }
    let mri = dir.join("cine.nii");
    std::fs::write(&mri, &image).unwrap();
    for (file, says) in [(&cut, "gzip"), (&mri, "not a label map")] {
        let path = file.to_str().unwrap();
        let (code, _, err) = run(bin().args(["reconstruct", path, "-o", "x.obj"]));
        assert_eq!(code, 2, "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(path) && err.contains(says), "{err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A segmented study with long-axis views (session 22): `segment --lax 3` writes three
/// single-slice views beside the stack; `reconstruct` reads the four files together in any order
/// (a view first), each view adding one long-axis curve to the LV surfaces; the reading is
/// printed as notes; two stacks, views alone, a damaged view and a contour file among label maps
/// are refused in one line naming the file.
#[test]
fn a_stack_with_long_axis_views() {
    let dir = scratch("label-map-views");
    let seg = dir.join("seg.nii.gz");
    let seg = seg.to_str().unwrap();
    let (code, out, err) = segment_spasm(seg, &["--lax", "3"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.matches("long-axis view").count(), 3, "{out}");
    let view = |n: u32| {
        dir.join(format!("seg_lax{n}.nii.gz"))
            .to_str()
            .unwrap()
            .to_string()
    };
    let report = dir.join("r.json");
    let (code, _, err) = run(bin().args([
        "reconstruct",
        &view(2),
        seg,
        &view(1),
        &view(3),
        "--surface",
        "LV_EPI",
        "-o",
        dir.join("epi.obj").to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
    ]));
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        err.matches("seg.nii.gz: long-axis view seg_lax").count(),
        3,
        "{err}"
    );
    // The header's note, the three views' and the valve chords': a mask's long-axis section is
    // closed along its top edge, which the fit opens (contours::valve_chord).
    assert_eq!(err.matches("heartmesh: note: ").count(), 5, "{err}");
    assert!(
        err.contains(
            "\"seg_lax1 LV_EPI\", \"seg_lax2 LV_EPI\", \"seg_lax3 LV_EPI\" closed across the valve"
        ),
        "{err}"
    );
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    assert_eq!(r["watertight"], true, "{r}");
    assert_eq!(r["valve_chords"].as_array().map(Vec::len), Some(3), "{r}");
    let lax: Vec<&serde_json::Value> = r["per_contour"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["kind"] == "LAX")
        .collect();
    assert_eq!(lax.len(), 3, "{r}");
    for c in &lax {
        assert!(c["id"].as_str().unwrap().starts_with("seg_lax"), "{c}");
        assert!(c["mean"].as_f64().unwrap() < 1.0, "{c}");
    }
    assert!(r["contour_to_mesh"]["mean"].as_f64().unwrap() < 1.0, "{r}");

    let out_mesh = dir.join("x.obj");
    let out_mesh = out_mesh.to_str().unwrap();
    let bad = dir.join("bad_lax.nii.gz");
    std::fs::write(&bad, &std::fs::read(view(1)).unwrap()[..60]).unwrap();
    let csv = dir.join("c.csv");
    std::fs::write(&csv, "contour,x,y,z\n1,0,0,0\n").unwrap();
    for (files, says) in [
        (vec![seg.to_string(), seg.to_string()], "are both stacks"),
        (vec![view(1), view(2)], "every file is a single slice"),
        (
            vec![seg.to_string(), bad.to_str().unwrap().to_string()],
            "bad_lax.nii.gz",
        ),
        (
            vec![seg.to_string(), csv.to_str().unwrap().to_string()],
            "c.csv is not a label map (NIfTI-1, NRRD or DICOM SEG)",
        ),
    ] {
        let mut args = vec!["reconstruct".to_string()];
        args.extend(files);
        args.extend(["-o".to_string(), out_mesh.to_string()]);
        let (code, _, err) = run(bin().args(&args));
        assert_eq!(code, 2, "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(says), "{err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// 3D Slicer's segmentation format (session 22): `segment -o X.seg.nrrd` writes a gzip-encoded
/// NRRD in LPS with named segments; `reconstruct` reads it as the NIfTI of the same map (same
/// volume to 0.1 ml), its note naming the space and segments; a detached-data header is refused in
/// one line; with `--lax` the views are NRRDs too, and the study reads as the NIfTI one (session
/// 38).
#[test]
fn a_slicer_segmentation() {
    let dir = scratch("label-map-nrrd");
    let args = |out: &str| {
        vec![
            "segment".to_string(),
            "--lv-endo".into(),
            mesh("cardiomesh-spasm-LV_endo.obj"),
            "--lv-epi".into(),
            mesh("cardiomesh-spasm-LV_epi.obj"),
            "-o".into(),
            dir.join(out).to_str().unwrap().to_string(),
        ]
    };
    for out in ["s.seg.nrrd", "s.nii.gz"] {
        let (code, _, err) = run(bin().args(args(out)));
        assert_eq!(code, 0, "{err}");
    }
    let mut volumes = Vec::new();
    for input in ["s.seg.nrrd", "s.nii.gz"] {
        let (r, err) = reconstruct(&dir, &[dir.join(input)], "LV_EPI", input);
        if input.ends_with("nrrd") {
            assert!(
                err.contains("(LPS, as 3D Slicer saves); segments 3 LV, 2 Myocardium"),
                "{err}"
            );
        }
        assert_eq!(r["watertight"], true);
        volumes.push(r["volume_ml"].as_f64().unwrap());
    }
    assert!((volumes[0] - volumes[1]).abs() < 0.1, "{volumes:?}");
    let detached = dir.join("d.nrrd");
    std::fs::write(
        &detached,
        "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\ndata file: d.raw\n\n",
    )
    .unwrap();
    let (code, _, err) = run(bin().args([
        "reconstruct",
        detached.to_str().unwrap(),
        "-o",
        dir.join("d.obj").to_str().unwrap(),
    ]));
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("d.nrrd") && err.contains("in another file (d.raw)"),
        "{err}"
    );
    // With long-axis views: written in the stack's format (a NRRD's LPS), read with it, the
    // same study as the NIfTI one.
    let mut lax_volumes = Vec::new();
    for out in ["v.seg.nrrd", "v.nii.gz"] {
        let mut with = args(out);
        with.extend(["--lax".to_string(), "2".to_string()]);
        let (code, stdout, err) = run(bin().args(with));
        assert_eq!(code, 0, "{err}");
        assert_eq!(stdout.matches("long-axis view").count(), 2, "{stdout}");
        let ext = out.split_once('.').map(|(_, e)| e).unwrap();
        let files = [
            format!("v_lax2.{ext}"),
            out.to_string(),
            format!("v_lax1.{ext}"),
        ];
        let files: Vec<_> = files.iter().map(|f| dir.join(f)).collect();
        let (r, err) = reconstruct(&dir, &files, "LV_EPI", &format!("lax-{ext}"));
        assert_eq!(err.matches(": long-axis view v_lax").count(), 2, "{err}");
        assert_eq!(lax_count(&r), 2, "{r}");
        lax_volumes.push(r["volume_ml"].as_f64().unwrap());
    }
    eprintln!("NRRD and NIfTI studies with 2 views: {lax_volumes:?} ml");
    assert!(
        (lax_volumes[0] - lax_volumes[1]).abs() < 0.1,
        "{lax_volumes:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_dicom_seg_gives_the_mesh_of_the_label_map_it_holds() {
    // The fixture is the app's example NIfTI written as a DICOM SEG (scripts/seg_fixture.py: LPS,
    // one binary frame per slice and label present): its contours are the NIfTI's turned half a
    // turn about z, to the 4e-5 mm of the NIfTI's float sform and the SEG's decimal strings. The
    // method does not depend on the frame (tests/invariance.rs), but pixel-traced curves are full
    // of exactly tied distances that such differences break another way (which attractor the
    // farthest-point sampling takes), so the meshes agree as two samplings do: volume within
    // 1 % (0.2-0.5 % here), contour-to-mesh mean within 0.02 mm.
    let dir = scratch("label-map-dicom-seg");
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../..");
    let seg = root.join("wasm-core/crates/heartmesh-core/tests/data/spasm-seg.dcm");
    let nifti = root.join("public/samples/cardiomesh-spasm-seg.nii.gz");
    for surface in ["LV_ENDO", "LV_EPI", "RV_ENDO"] {
        let mut figures = Vec::new();
        for (input, name) in [(&seg, "seg"), (&nifti, "nifti")] {
            let (r, err) = reconstruct(
                &dir,
                std::slice::from_ref(input),
                surface,
                &format!("{name}-{surface}"),
            );
            if name == "seg" {
                assert!(
                    err.contains("frame positions (DICOM SEG, LPS); segments 1 label 1"),
                    "{err}"
                );
            }
            assert_eq!(r["watertight"], true);
            figures.push((
                r["vertices"].as_u64().unwrap(),
                r["volume_ml"].as_f64().unwrap(),
                r["contour_to_mesh"]["mean"].as_f64().unwrap(),
            ));
        }
        eprintln!("DICOM SEG {surface}: {figures:?} (SEG, NIfTI)");
        let ((_, ml1, c1), (_, ml2, c2)) = (figures[0], figures[1]);
        assert!(
            (ml1 - ml2).abs() < 1e-2 * ml2,
            "{surface}: {ml1} vs {ml2} ml"
        );
        assert!((c1 - c2).abs() < 0.02, "{surface}: {c1} vs {c2} mm");
    }
    // Cut inside its pixel data: one line naming the file and what is missing.
    let bytes = std::fs::read(&seg).unwrap();
    let cut = dir.join("cut.dcm");
    std::fs::write(&cut, &bytes[..bytes.len() - 4000]).unwrap();
    let (code, _, err) = run(bin().args([
        "reconstruct",
        cut.to_str().unwrap(),
        "-o",
        dir.join("cut.obj").to_str().unwrap(),
    ]));
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("cut.dcm") && err.contains("truncated"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Views and stacks of different formats (session 38): the DICOM SEG fixture (the example in
/// LPS) with the NIfTI long-axis views `segment --lax 3` writes of the same heart (RAS): each
/// view turned into the stack's LPS, matched and traced, the mesh the NIfTI study's to the spread
/// of two samplings of pixel-traced curves (as above).
#[test]
fn a_dicom_seg_stack_with_nifti_views() {
    let dir = scratch("label-map-seg-views");
    let seg = dir.join("seg.nii.gz");
    let (code, _, err) = segment_spasm(seg.to_str().unwrap(), &["--lax", "3"]);
    assert_eq!(code, 0, "{err}");
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../..");
    let dicom = root.join("wasm-core/crates/heartmesh-core/tests/data/spasm-seg.dcm");
    let views = (1..=3).map(|n| dir.join(format!("seg_lax{n}.nii.gz")));
    let mut figures = Vec::new();
    for (name, stack) in [("dicom", dicom.clone()), ("nifti", seg.clone())] {
        let files: Vec<_> = std::iter::once(stack).chain(views.clone()).collect();
        let (r, err) = reconstruct(&dir, &files, "LV_EPI", name);
        assert_eq!(err.matches(": long-axis view seg_lax").count(), 3, "{err}");
        assert!(!err.contains("none of its labels"), "{err}");
        assert_eq!(lax_count(&r), 3, "{r}");
        assert_eq!(r["watertight"], true);
        figures.push((
            r["volume_ml"].as_f64().unwrap(),
            r["contour_to_mesh"]["mean"].as_f64().unwrap(),
        ));
    }
    // `info` reads them as one study too (a SEG first on the command line).
    let (code, out, err) = run(bin().arg("info").arg(&dicom).args(views.clone()));
    assert_eq!(code, 0, "{err}");
    for line in [
        "LV_ENDO: 9 contours (6 short-axis, 3 long-axis)",
        "LV_EPI: 11 contours (8 short-axis, 3 long-axis)",
        "RV_ENDO: 9 contours (7 short-axis, 2 long-axis)",
    ] {
        assert!(out.contains(line), "{out}");
    }
    eprintln!("LV_EPI with 3 NIfTI views: DICOM SEG stack, NIfTI stack {figures:?}");
    let ((ml1, c1), (ml2, c2)) = (figures[0], figures[1]);
    assert!((ml1 - ml2).abs() < 1e-2 * ml2, "{ml1} vs {ml2} ml");
    assert!((c1 - c2).abs() < 0.05, "{c1} vs {c2} mm");
    let _ = std::fs::remove_dir_all(&dir);
}
