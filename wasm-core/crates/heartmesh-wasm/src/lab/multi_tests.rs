//! The Lab with several truths: labels (refused when invalid or taken), one acquisition of all of
//! them equal to the core's `simulate_surfaces`, comparisons with the truth of the reconstructed
//! surface only, and a lone truth's acquisition unchanged (`simulate`, no surface column).

use super::*;
use heartmesh_core::sim::AcquisitionSpec;

use crate::test_data::data;

const LV: &str = "bivme-patient1-ED-LV_ENDO-closed.obj";
const RV: &str = "bivme-patient1-ED-RV_ENDO-closed.obj";
const ACQ: &str = r#"{"sax_count": 8, "lax_count": 2}"#;

fn bytes(name: &str) -> Vec<u8> {
    std::fs::read(data(&format!("meshes/{name}"))).unwrap()
}

fn json(s: &str) -> serde_json::Value {
    serde_json::from_str(s).unwrap()
}

fn code(e: LabError) -> &'static str {
    match e {
        LabError::Usage { code, .. } => code,
        LabError::Core(e) => e.code(),
    }
}

/// LV_ENDO then RV_ENDO, as the page adds two dropped files.
fn two() -> Lab {
    let mut lab = Lab::new();
    let lv = json(
        &lab.load_truth_with(LV, Some("LV_ENDO".into()), &bytes(LV))
            .unwrap(),
    );
    assert_eq!(
        (lv["index"].as_u64(), lv["label"].as_str()),
        (Some(0), Some("LV_ENDO"))
    );
    let rv = json(
        &lab.add_truth_with(RV, Some("RV_ENDO".into()), &bytes(RV))
            .unwrap(),
    );
    assert_eq!(
        (rv["index"].as_u64(), rv["label"].as_str()),
        (Some(1), Some("RV_ENDO"))
    );
    assert_eq!(rv["closed"], true);
    lab
}

#[test]
fn labels_are_checked_and_a_refusal_keeps_the_truths() {
    let mut lab = two();
    // Taken (without case, as the CLI), invalid, or a file that is no mesh: refused, nothing added.
    let e = lab
        .add_truth_with("other.obj", Some("lv_endo".into()), &bytes(LV))
        .unwrap_err();
    assert!(
        e.to_string()
            .contains("already bivme-patient1-ED-LV_ENDO-closed.obj's"),
        "{e}"
    );
    assert_eq!(code(e), "label_taken");
    let e = lab
        .add_truth_with("x.obj", Some("LV ENDO".into()), &bytes(LV))
        .unwrap_err();
    assert_eq!(code(e), "label_invalid");
    let e = lab
        .add_truth_with("broken.stl", None, b"solid x\nnonsense\n")
        .unwrap_err();
    assert!(matches!(e, LabError::Core(_)), "{e}");
    assert_eq!(lab.truths.len(), 2);
    let e = lab
        .set_truth_label_with(1, Some("LV_ENDO".into()))
        .unwrap_err();
    assert_eq!(code(e), "label_taken");
    assert!(lab.set_truth_label_with(5, None).is_err());
    // Any label the CLI takes; an unlabelled truth among several stops the acquisition.
    let list = json(
        &lab.set_truth_label_with(1, Some("RV-cavity_2".into()))
            .unwrap(),
    );
    assert_eq!(list[1]["label"], "RV-cavity_2");
    lab.set_truth_label_with(1, None).unwrap();
    let e = lab.simulate_with(ACQ).unwrap_err();
    assert!(
        e.to_string()
            .contains("RV_ENDO-closed.obj has no surface label"),
        "{e}"
    );
    assert_eq!(code(e), "label_required");
    // Removing one leaves a lone truth, simulated as one (no label needed).
    let list = json(&lab.remove_truth_with(0).unwrap());
    assert_eq!(list.as_array().map(Vec::len), Some(1));
    assert_eq!(list[0]["name"], RV);
    lab.simulate_with(ACQ).unwrap();
    assert!(lab.remove_truth_with(3).is_err());
}

#[test]
fn several_truths_are_one_acquisition_as_simulate_surfaces() {
    let mut lab = two();
    let info = json(&lab.simulate_with(ACQ).unwrap());
    let csv = lab.simulated_csv_with().unwrap();
    let spec = spec::acquisition(ACQ).unwrap();
    let (lv, rv) = (
        read_truth(LV, &bytes(LV)).unwrap().0,
        read_truth(RV, &bytes(RV)).unwrap().0,
    );
    let want = simulate_surfaces(&[("LV_ENDO", &lv), ("RV_ENDO", &rv)], &spec).unwrap();
    assert_eq!(csv, io::csv::write_csv(&want.contours, None).unwrap());
    let text = String::from_utf8(csv).unwrap();
    assert!(
        text.lines().next().unwrap().contains("surface"),
        "{}",
        &text[..200]
    );
    assert!(text.contains("sax03_LV_ENDO") && text.contains("sax03_RV_ENDO"));
    // Per surface: SAX and LAX contours and points adding up to the whole.
    assert_eq!(info["sax"], 8);
    assert_eq!(info["lax"], 2);
    let rows = info["surfaces"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    assert_eq!(
        (rows[0]["label"].as_str(), rows[1]["label"].as_str()),
        (Some("LV_ENDO"), Some("RV_ENDO"))
    );
    let mut points = 0;
    for (r, label) in rows.iter().zip(["LV_ENDO", "RV_ENDO"]) {
        let of = |prefix: &str| {
            want.contours
                .contours
                .iter()
                .filter(|c| c.surface.as_deref() == Some(label) && c.id.starts_with(prefix))
                .count()
        };
        assert_eq!(r["sax"].as_u64(), Some(of("sax") as u64), "{r}");
        assert_eq!(r["lax"].as_u64(), Some(of("lax") as u64), "{r}");
        assert!(r["sax"].as_u64().unwrap() >= 5 && r["lax"] == 2, "{r}");
        points += r["points"].as_u64().unwrap();
    }
    assert_eq!(info["points"].as_u64(), Some(points));
    // Each truth clipped at its own most basal SAX plane (`surface_clips`), said per row.
    assert_eq!(lab.clips, want.surface_clips);
    for (r, c) in rows.iter().zip(&want.surface_clips) {
        let z = r["clip"]["origin"][2].as_f64().unwrap();
        assert!((z - c.origin.z).abs() < 1e-12, "{r}");
    }
}

/// Mean mesh-to-truth distance of a report.
fn m2t(report: &serde_json::Value) -> f64 {
    report["mesh_to_truth"]["mean"].as_f64().unwrap()
}

#[test]
fn compare_measures_against_the_truth_of_the_same_surface() {
    let mut lab = two();
    lab.simulate_with(ACQ).unwrap();
    let (lv, rv) = (
        lab.truths.get(0).unwrap().mesh.clone(),
        lab.truths.get(1).unwrap().mesh.clone(),
    );
    let cmp = |lab: &mut Lab, s: Option<&str>, m: &TriMesh| {
        lab.compare_with(s, &m.positions_f32(), &m.indices_u32())
    };
    // The RV against the RV truth: itself, zero; the distances are the RV truth's vertices'.
    let r = json(&cmp(&mut lab, Some("RV_ENDO"), &rv).unwrap());
    assert!(
        m2t(&r) < 1e-4 && r["hausdorff"].as_f64().unwrap() < 1e-4,
        "{r}"
    );
    assert_eq!(
        (r["truth_index"].as_u64(), r["truth_label"].as_str()),
        (Some(1), Some("RV_ENDO"))
    );
    assert_eq!(r["truth_name"], RV);
    assert_eq!(lab.truth_distances().len(), rv.positions.len());
    // The LV mesh said to be the RV is measured against the RV truth: far (never the LV's zero).
    let wrong = json(&cmp(&mut lab, Some("rv_endo"), &lv).unwrap());
    assert!(m2t(&wrong) > 5.0, "{wrong}");
    let l = json(&cmp(&mut lab, Some("LV_ENDO"), &lv).unwrap());
    assert!(m2t(&l) < 1e-4, "{l}");
    assert_eq!(lab.truth_distances().len(), lv.positions.len());
    // A surface without truth, or no surface with several truths: said plainly, nothing kept.
    let e = cmp(&mut lab, Some("LV_EPI"), &lv).unwrap_err();
    assert_eq!(code(e), "no_truth_for_surface");
    let e = cmp(&mut lab, Some("LV_EPI"), &lv).unwrap_err().to_string();
    assert!(
        e.contains("no truth for LV_EPI: the Lab's truths are LV_ENDO, RV_ENDO"),
        "{e}"
    );
    assert!(cmp(&mut lab, None, &lv).is_err());
    // The sweep measures a surface against its own truth too.
    let (t, clip) = lab.sweep_truth(Some("RV_ENDO")).unwrap().unwrap();
    assert_eq!(t.positions, rv.positions);
    assert_eq!(clip, lab.clips.get(1).copied());
    assert!(clip.is_some());
}

#[test]
fn a_single_truth_is_simulated_exactly_as_before() {
    let spec: AcquisitionSpec = spec::acquisition(ACQ).unwrap();
    // One dropped mesh, labelled or not: `simulate`'s contours, byte for byte, no surface column.
    for label in [None, Some("LV_ENDO".to_string())] {
        let mut lab = Lab::new();
        lab.load_truth_with(LV, label, &bytes(LV)).unwrap();
        let info = json(&lab.simulate_with(ACQ).unwrap());
        let mesh = read_truth(LV, &bytes(LV)).unwrap().0;
        let want = simulate(&mesh, &spec).unwrap();
        let csv = lab.simulated_csv_with().unwrap();
        assert_eq!(csv, io::csv::write_csv(&want.contours, None).unwrap());
        assert!(!String::from_utf8(csv)
            .unwrap()
            .lines()
            .next()
            .unwrap()
            .contains("surface"));
        assert_eq!(info["sax"], 8);
        assert_eq!(info["lax"], 2);
        assert_eq!(info["surfaces"][0]["label"], serde_json::Value::Null);
        // Compared whatever the surface is called (the file has none).
        let r = json(
            &lab.compare_with(None, &mesh.positions_f32(), &mesh.indices_u32())
                .unwrap(),
        );
        assert!(m2t(&r) < 1e-4);
    }
    // The parametric LV: the same, and adding a truth after it makes two.
    let mut lab = Lab::new();
    lab.make_parametric_with("{}").unwrap();
    lab.simulate_with(ACQ).unwrap();
    let mesh = spec::parametric_lv("{}")
        .unwrap()
        .mesh(LV_AROUND, LV_ALONG)
        .unwrap();
    assert_eq!(
        lab.simulated_csv_with().unwrap(),
        io::csv::write_csv(&simulate(&mesh, &spec).unwrap().contours, None).unwrap()
    );
    lab.add_truth_with(RV, Some("RV_ENDO".into()), &bytes(RV))
        .unwrap();
    assert_eq!(lab.truths.len(), 2);
    assert!(
        lab.simulated_csv_with().is_err(),
        "the acquisition was of the other truths"
    );
}

/// `text` (an OBJ) with its patient frame stated first and, when `mirror`, every vertex taken to
/// the other frame (x and y negated): the same surface as a tool working in that frame saves it.
fn obj_in_frame(text: &[u8], space: &str, mirror: bool) -> Vec<u8> {
    let mut out = format!("# SPACE={space}\n");
    for line in String::from_utf8_lossy(text).lines() {
        match line.strip_prefix("v ") {
            Some(rest) if mirror => {
                let v: Vec<f64> = rest
                    .split_whitespace()
                    .map(|t| t.parse().unwrap())
                    .collect();
                out += &format!("v {} {} {}\n", -v[0], -v[1], v[2]);
            }
            _ => {
                out += line;
                out.push('\n');
            }
        }
    }
    out.into_bytes()
}

/// A Lab holding patient 1's LV as a file stating LPS, and what loading it returned.
fn lab_with_lps_lv() -> (Lab, serde_json::Value) {
    let mut lab = Lab::new();
    let info = lab
        .load_truth_with(
            LV,
            Some("LV_ENDO".into()),
            &obj_in_frame(&bytes(LV), "LPS", false),
        )
        .unwrap();
    (lab, json(&info))
}

/// Surfaces of one heart from tools in different frames: an RV saved in RAS beside an LV in LPS
/// is taken into LPS on adding (said as `convertedFrom`), so it lies where the LPS file of the
/// same RV would, and the acquisition is that of the two files in one frame.
#[test]
fn a_truth_stating_the_other_frame_is_taken_into_the_first_truths() {
    let (mut lab, lv) = lab_with_lps_lv();
    assert_eq!(lv["frame"], "LPS");
    assert!(lv["convertedFrom"].is_null());
    let rv = json(
        &lab.add_truth_with(
            RV,
            Some("RV_ENDO".into()),
            &obj_in_frame(&bytes(RV), "RAS", true),
        )
        .unwrap(),
    );
    assert_eq!(
        (rv["frame"].as_str(), rv["convertedFrom"].as_str()),
        (Some("LPS"), Some("RAS"))
    );
    let want = read_truth(RV, &bytes(RV)).unwrap().0;
    let got = &lab.truths.get(1).unwrap().mesh;
    assert_eq!(got.triangles, want.triangles);
    let worst = got
        .positions
        .iter()
        .zip(&want.positions)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "{worst} mm from the LPS file's RV");
    // The same RV untagged is taken as it stands: mirrored, far from the LV.
    let (mut plain, _) = lab_with_lps_lv();
    let untagged: Vec<u8> = obj_in_frame(&bytes(RV), "RAS", true)
        .into_iter()
        .skip("# SPACE=RAS\n".len())
        .collect();
    let rv = json(
        &plain
            .add_truth_with(RV, Some("RV_ENDO".into()), &untagged)
            .unwrap(),
    );
    assert!(
        rv["frame"].is_null() && rv["convertedFrom"].is_null(),
        "{rv}"
    );
    let far = plain.truths.get(1).unwrap().mesh.positions[0] - want.positions[0];
    assert!(far.norm() > 10.0, "{}", far.norm());
}
