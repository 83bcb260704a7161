//! A cvi42 workspace on the command line: `reconstruct Contours.cvi42wsx DICOM_DIR/ ...` (a folder
//! stands for the images under it), `info`, `--frame`, and the refusals a user meets first (the
//! workspace alone, images of another study). The fixture is biv-me's patient 1 in pixels
//! (scripts/cvi42_fixture.py; heartmesh-core/tests/cvi42.rs checks its points).

mod common;
use common::{bin, data, run, scratch};
use serde_json::Value;
use std::path::Path;

fn fixture(sub: &str) -> String {
    common::core_data(&format!("cvi42-patient1/{sub}"))
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn report(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn a_workspace_and_its_image_folder_reconstruct_each_frame() {
    let dir = scratch("cvi42_reconstruct");
    let (mesh, json) = (dir.join("lv.vtk"), dir.join("lv.json"));
    let mut contours_seen = Vec::new();
    for frame in [None, Some("9")] {
        let mut cmd = bin();
        cmd.args([
            "reconstruct",
            &fixture("Contours.cvi42wsx"),
            &fixture("dicom"),
        ])
        .args(["--surface", "LV_ENDO", "-o", s(&mesh), "--report", s(&json)]);
        if let Some(f) = frame {
            cmd.args(["--frame", f]);
        }
        let (code, _, err) = run(&mut cmd);
        assert_eq!(code, 0, "{err}");
        let r = report(&json);
        let mean = r["contour_to_mesh"]["mean"].as_f64().unwrap();
        let ml = r["volume_ml"].as_f64().unwrap();
        eprintln!("CVI42 CLI frame {frame:?}: contour-to-mesh mean {mean:.3} mm, {ml:.1} ml");
        assert_eq!(r["watertight"], true);
        assert!(mean <= 1.0, "{mean}");
        contours_seen.push((r["per_contour"].as_array().unwrap().len(), ml));
        if frame.is_none() {
            // The reader's account on stderr: the other frame, the two types it skipped.
            assert!(err.contains("frame 0 read"), "{err}");
            assert!(err.contains("saPapMuscContour skipped"), "{err}");
        }
    }
    // End-diastole: 8 curves, end-systole 7 (no ES contour on the most basal slice), and the
    // cavity is smaller at end-systole.
    assert_eq!(contours_seen[0].0, 8);
    assert_eq!(contours_seen[1].0, 7);
    assert!(
        contours_seen[1].1 < 0.6 * contours_seen[0].1,
        "{contours_seen:?}"
    );
}

#[test]
fn info_names_the_format_the_frames_and_the_surfaces() {
    let (code, out, err) = run(bin().args([
        "info",
        &fixture("Contours.cvi42wsx"),
        &fixture("dicom"),
        "--json",
    ]));
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["format"], "cvi42 workspace");
    let expected = [
        ("LV_ENDO", 441),
        ("LV_EPI", 416),
        ("RV_ENDO", 472),
        ("RV_EPI", 460),
    ];
    for (surface, _) in expected {
        assert!(out.contains(surface), "{surface}");
    }
    common::assert_surface_points(&v, &expected);
}

#[test]
fn the_workspace_alone_or_with_other_images_is_refused_in_one_line() {
    let dir = scratch("cvi42_refused");
    let out = dir.join("m.obj");
    let (code, _, err) =
        run(bin().args(["reconstruct", &fixture("Contours.cvi42wsx"), "-o", s(&out)]));
    assert_eq!(code, 2);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("together with the DICOM images"), "{err}");

    // Images of another acquisition (two of the fixture's, their UIDs changed) and a note.
    let other = dir.join("other");
    std::fs::create_dir_all(&other).unwrap();
    for name in ["IM_02_00.dcm", "IM_03_00.dcm"] {
        let mut bytes = std::fs::read(fixture(&format!("dicom/{name}"))).unwrap();
        // Same length: every UID of the file (SOP instance, and in the meta group) moved.
        for at in 0..bytes.len() - 9 {
            if &bytes[at..at + 9] == b"1.2.826.0" {
                bytes[at..at + 9].copy_from_slice(b"1.2.999.0");
            }
        }
        std::fs::write(other.join(name), bytes).unwrap();
    }
    std::fs::write(other.join("README.txt"), "exported from cvi42").unwrap();
    let (code, _, err) = run(bin().args([
        "reconstruct",
        &fixture("Contours.cvi42wsx"),
        s(&other),
        "-o",
        s(&out),
    ]));
    assert_eq!(code, 2);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("none of the 17 images its ventricular contours were drawn on is among the 2 DICOM images given"),
        "{err}"
    );
}

#[test]
fn volumes_reads_the_workspaces_frames_as_the_phases() {
    let dir = scratch("cvi42_volumes");
    let (ef, phases) = common::lv_ef(&[fixture("Contours.cvi42wsx"), fixture("dicom")], &dir);
    assert_eq!(phases.len(), 2, "{phases:?}");
    let gp = |f: &str| {
        common::data(&format!("contours/bivme-example-patient1/{f}"))
            .display()
            .to_string()
    };
    let (theirs, _) = common::lv_ef(&[gp("GPFile_000.txt"), gp("GPFile_009.txt")], &dir);
    eprintln!("CVI42 volumes: LV EF {ef:.2} % (the GPFiles' {theirs:.2} %)");
    assert!((ef - theirs).abs() < 1.0, "{ef} vs {theirs}");
}

/// The report of `reconstruct INPUTS... --surface LV_ENDO`: (status, stderr, report).
fn lv_report(inputs: &[String], dir: &Path) -> (i32, String, Option<Value>) {
    let (mesh, json) = (dir.join("lv.obj"), dir.join("lv.json"));
    let _ = std::fs::remove_file(&json);
    let (code, _, err) = run(bin().arg("reconstruct").args(inputs).args([
        "--surface",
        "LV_ENDO",
        "-o",
        s(&mesh),
        "--report",
        s(&json),
    ]));
    (code, err, json.exists().then(|| report(&json)))
}

#[test]
fn zip_archives_as_uk_biobank_hands_them_out_give_the_same_mesh() {
    let dir = scratch("cvi42_zipped");
    let (_, _, plain) = lv_report(&[fixture("Contours.cvi42wsx"), fixture("dicom")], &dir);
    let plain = plain.unwrap();
    let zips = [
        fixture("zipped/1000001_cvi42.zip"),
        fixture("zipped/1000001_images.zip"),
    ];
    // The two archives, or the one folder holding both.
    for inputs in [zips.to_vec(), vec![fixture("zipped")]] {
        let (code, err, r) = lv_report(&inputs, &dir);
        assert_eq!(code, 0, "{err}");
        let r = r.unwrap();
        for key in ["vertices", "triangles", "volume_ml"] {
            assert_eq!(r[key], plain[key], "{key} of {inputs:?}");
        }
        assert_eq!(
            r["contour_to_mesh"]["mean"],
            plain["contour_to_mesh"]["mean"]
        );
        assert!(
            err.contains("workspace read with 110 DICOM images"),
            "{err}"
        );
    }
    // A damaged archive: one line naming it, status 2.
    let bytes = std::fs::read(&zips[1]).unwrap();
    let cut = dir.join("cut.zip");
    std::fs::write(&cut, &bytes[..bytes.len() - 40]).unwrap();
    let (code, err, _) = lv_report(&[zips[0].clone(), s(&cut).to_string()], &dir);
    assert_eq!(code, 2);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("cut.zip") && err.contains("ZIP archive: no end of central directory"),
        "{err}"
    );
}

/// `myocardium WORKSPACE DICOM/ --bullseye`: the septum direction and its source.
fn septum(inputs: &[&str], frame: Option<&str>, dir: &Path, name: &str) -> (String, [f64; 3]) {
    let [out, json, svg] = ["vtk", "json", "svg"].map(|e| dir.join(format!("{name}.{e}")));
    let mut cmd = bin();
    cmd.arg("myocardium").args(inputs).args([
        "-o",
        s(&out),
        "--report",
        s(&json),
        "--bullseye",
        s(&svg),
        "--quiet",
    ]);
    if let Some(f) = frame {
        cmd.args(["--frame", f]);
    }
    let (code, _, err) = run(&mut cmd);
    assert_eq!(code, 0, "{err}");
    let seg = &report(&json)["segments"];
    let d: Vec<f64> = seg["septum_direction"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    (
        seg["septum_from"].as_str().unwrap().to_string(),
        [d[0], d[1], d[2]],
    )
}

#[test]
fn the_reference_points_place_the_segments() {
    // cvi42's superior and inferior SAX reference points are the RV insertions: the bullseye is
    // placed from them, as from the GPFile's unnamed pairs at frame 0 (paired by slice: 0.1
    // degrees apart) and within 5 degrees of it at frame 9 (the septum moves in systole).
    let dir = scratch("cvi42_segments");
    let (wsx, images) = (fixture("Contours.cvi42wsx"), fixture("dicom"));
    let gp = data("contours/bivme-example-patient1/GPFile_000.txt");
    let (gp_from, gp_septum) = septum(&[s(&gp)], None, &dir, "gp");
    assert_eq!(gp_from, "RV_INSERT landmarks (10)");
    for (frame, points) in [(None, 10), (Some("9"), 8)] {
        let (from, d) = septum(&[&wsx, &images], frame, &dir, "cvi42");
        assert_eq!(
            from,
            format!("anterior and inferior RV insertion points ({points})")
        );
        let off = (0..3)
            .map(|i| d[i] * gp_septum[i])
            .sum::<f64>()
            .acos()
            .to_degrees();
        eprintln!("CVI42 segments frame {frame:?}: septum {off:.1} degrees from the GPFile's ED");
        assert!(off < if frame.is_none() { 0.5 } else { 5.0 }, "{off}");
    }
}

#[test]
fn an_lv_only_analysis_gets_its_segments_from_the_reference_points() {
    // The clinical routine: LV endo- and epicardium drawn, the RV insertion reference points set,
    // no RV contours. The fixture's workspace without its RV types (the script writes each
    // contour as an item opened and closed at four spaces of indent).
    let dir = scratch("cvi42_lv_only");
    let full = std::fs::read_to_string(fixture("Contours.cvi42wsx")).unwrap();
    let mut kept = String::new();
    let mut skipping = false;
    for line in full.lines() {
        if line.starts_with("    <Hash:item Hash:key=\"sarv")
            || line.starts_with("    <Hash:item Hash:key=\"larv")
        {
            skipping = true;
        }
        if !skipping {
            kept.push_str(line);
            kept.push('\n');
        }
        if skipping && line == "    </Hash:item>" {
            skipping = false;
        }
    }
    assert!(!kept.contains("rvendocardial") && !kept.contains("rvepicardial"));
    assert!(kept.contains("sacardialRefPoint") && kept.contains("saendocardialContour"));
    let wsx = dir.join("lv-only.cvi42wsx");
    std::fs::write(&wsx, kept).unwrap();
    let (from, d) = septum(&[s(&wsx), &fixture("dicom")], None, &dir, "lv-only");
    assert_eq!(from, "anterior and inferior RV insertion points (10)");
    let (_, with_rv) = septum(
        &[&fixture("Contours.cvi42wsx"), &fixture("dicom")],
        None,
        &dir,
        "full",
    );
    let off = (0..3)
        .map(|i| d[i] * with_rv[i])
        .sum::<f64>()
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees();
    assert!(off < 1.0, "{off} degrees from the full study's");
}
