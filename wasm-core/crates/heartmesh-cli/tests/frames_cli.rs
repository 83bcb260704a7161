//! Time frames chosen by label on the command line (session 17): biv-me patient 1's ED and ES
//! contours in one CSV with a `phase` column of `ED` and `ES` (built here from the shared
//! patient1-ED.csv and patient1-ES.csv, so no fixture is committed). `--frame ES` (in any case)
//! gives exactly the mesh of patient1-ES.csv alone, on reconstruct, convert and align, and the
//! report's `frame` says which frame was read: the label, the list of first frames when contours
//! start in different frames, null without a frame column.

mod common;
use common::{bin, data, mesh_lines, run, scratch};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn patient1(name: &str) -> PathBuf {
    data(&format!("contours/bivme-example-patient1/{name}"))
}

/// patient1-ED.csv's rows labelled `ED` then patient1-ES.csv's labelled `ES`, in a `phase` column.
fn ed_es_csv(dir: &Path) -> PathBuf {
    let mut out = String::from("contour,x,y,z,surface,phase\n");
    for (name, label) in [("patient1-ED.csv", "ED"), ("patient1-ES.csv", "ES")] {
        let text = std::fs::read_to_string(patient1(name)).unwrap();
        for row in text.lines().skip(1).filter(|r| !r.is_empty()) {
            out.push_str(&format!("{row},{label}\n"));
        }
    }
    let f = dir.join("patient1-ED-ES.csv");
    std::fs::write(&f, out).unwrap();
    f
}

/// `reconstruct FILE --surface LV_ENDO` with `extra`: status, stderr, the mesh's vertex and face
/// lines, and the report.
fn reconstruct(dir: &Path, file: &Path, extra: &[&str]) -> (i32, String, Vec<String>, Value) {
    let (out, report) = (dir.join("out.obj"), dir.join("report.json"));
    let _ = std::fs::remove_file(&out);
    let _ = std::fs::remove_file(&report);
    let (code, _, err) = run(bin()
        .args([
            "reconstruct",
            s(file),
            "-o",
            s(&out),
            "--report",
            s(&report),
        ])
        .args(["--surface", "LV_ENDO"])
        .args(extra));
    let body = mesh_lines(&out);
    let rep = std::fs::read(&report)
        .ok()
        .and_then(|b| serde_json::from_slice(&b).ok())
        .unwrap_or(Value::Null);
    (code, err, body, rep)
}

/// The mesh file's "reconstructed from" comment line (its second line).
fn header(dir: &Path) -> String {
    std::fs::read_to_string(dir.join("out.obj"))
        .unwrap_or_default()
        .lines()
        .nth(1)
        .unwrap_or_default()
        .to_string()
}

fn file_name(p: &Path) -> &str {
    p.file_name().and_then(|n| n.to_str()).unwrap_or_default()
}

#[test]
fn frame_es_by_label_is_the_es_file_and_the_report_says_so() {
    let dir = scratch("frames-es");
    let both = ed_es_csv(&dir);
    let (code, err, es, es_rep) = reconstruct(&dir, &patient1("patient1-ES.csv"), &[]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(es_rep["frame"], Value::Null, "no frame column");
    assert!(!header(&dir).contains("(frame"), "{}", header(&dir));
    let (code, err, ed, ed_rep) = reconstruct(&dir, &patient1("patient1-ED.csv"), &[]);
    assert_eq!(code, 0, "{err}");

    // Without a choice: ED, the frame every contour starts in, with the warning naming ES.
    let (code, err, first, rep) = reconstruct(&dir, &both, &[]);
    assert_eq!(code, 0, "{err}");
    assert!(first == ed, "the file's own reading is the ED file");
    assert_eq!(rep["frame"], "ED");
    assert!(header(&dir).contains(" (frame ED); "), "{}", header(&dir));
    assert_eq!(rep["vertices"], ed_rep["vertices"]);
    let warning = format!(
        "heartmesh: warning: {}: the file holds 2 time frames (ED, ES): frame ED read, 1204 \
         points of other frames left out; save one frame per file, or choose one with the \
         command line's --frame (e.g. --frame ES)",
        s(&both)
    );
    assert!(err.lines().any(|l| l == warning), "{err}");

    for asked in ["ES", "es", " Es "] {
        let (code, err, got, rep) = reconstruct(&dir, &both, &["--frame", asked]);
        assert_eq!(code, 0, "{asked:?}: {err}");
        assert!(
            !err.contains("time frames"),
            "{asked:?}: chosen, no warning: {err}"
        );
        assert!(got == es, "{asked:?}: frame ES is patient1-ES.csv");
        assert_eq!(rep["frame"], "ES", "{asked:?}: as the file writes it");
        assert!(
            header(&dir).starts_with(&format!(
                "# reconstructed from {} (frame ES); ",
                file_name(&both)
            )),
            "{asked:?}: the mesh file names its frame: {}",
            header(&dir)
        );
        for key in ["vertices", "triangles", "volume_ml"] {
            assert_eq!(rep[key], es_rep[key], "{asked:?}: {key}");
        }
        assert_eq!(
            rep["contour_to_mesh"]["mean"],
            es_rep["contour_to_mesh"]["mean"]
        );
    }
    assert_ne!(es_rep["volume_ml"], ed_rep["volume_ml"], "two phases");
    println!(
        "# patient 1 LV endo: ED {} vertices {:.2} ml, ES {} vertices {:.2} ml",
        ed_rep["vertices"],
        ed_rep["volume_ml"].as_f64().unwrap(),
        es_rep["vertices"],
        es_rep["volume_ml"].as_f64().unwrap()
    );

    // A frame the file lacks: one line naming the frames it has, no mesh.
    let (code, err, got, _) = reconstruct(&dir, &both, &["--frame", "ES2"]);
    assert_eq!((code, err.lines().count(), got.len()), (2, 1, 0), "{err}");
    assert!(
        err.contains("no contour points in frame ES2 (frames in the file: ED, ES)"),
        "{err}"
    );
    // A blank frame is a usage error, not the file's own reading.
    let (code, err, _, _) = reconstruct(&dir, &both, &["--frame", ""]);
    assert_eq!(code, 2);
    assert!(err.contains("--frame: \"\" names no frame"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// convert and align take the label too: the ES frame converts to the ES file's contours, and
/// aligns as that file does.
#[test]
fn convert_and_align_read_a_labelled_frame() {
    let dir = scratch("frames-convert");
    let both = ed_es_csv(&dir);
    let (es_csv, got_csv) = (dir.join("es.csv"), dir.join("got.csv"));
    let (code, _, err) = run(bin().args(["convert", s(&patient1("patient1-ES.csv")), s(&es_csv)]));
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = run(bin().args(["convert", s(&both), s(&got_csv), "--frame", "es"]));
    assert_eq!(code, 0, "{err}");
    assert!(err.is_empty(), "{err}");
    assert!(out.contains("35 contours, 1204 points"), "{out}");
    assert_eq!(
        std::fs::read_to_string(&got_csv).unwrap(),
        std::fs::read_to_string(&es_csv).unwrap()
    );
    let align = |input: &Path, out: &str, extra: &[&str]| -> Value {
        let rep = dir.join(format!("{out}.json"));
        let (code, _, err) = run(bin()
            .args([
                "align",
                s(input),
                "-o",
                s(&dir.join(out)),
                "--report",
                s(&rep),
                "-q",
            ])
            .args(extra));
        assert_eq!(code, 0, "{err}");
        serde_json::from_slice(&std::fs::read(rep).unwrap()).unwrap()
    };
    let alone = align(&patient1("patient1-ES.csv"), "alone.csv", &[]);
    let chosen = align(&both, "chosen.csv", &["--frame", "ES"]);
    assert_eq!(chosen["residual_after_mm"], alone["residual_after_mm"]);
    assert_eq!(
        (&chosen["frame"], &alone["frame"]),
        (&Value::from("ES"), &Value::Null)
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("chosen.csv")).unwrap(),
        std::fs::read_to_string(dir.join("alone.csv")).unwrap()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// GPFiles: the file's own reading of patient 1's ED GPFile takes slice 8 from its own frame 1
/// (the example labels it `1.0`), so the report lists both; `--frame 0.0` asks for frame 0 alone.
#[test]
fn the_report_lists_first_frames_that_differ() {
    let dir = scratch("frames-gpfile");
    let gp = patient1("GPFile_000.txt");
    let (code, err, _, rep) = reconstruct(&dir, &gp, &[]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(rep["frame"], serde_json::json!(["0", "1"]));
    let (code, err, _, rep) = reconstruct(&dir, &gp, &["--frame", "0.0"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(rep["frame"], "0", "as numbers print");
    let _ = std::fs::remove_dir_all(&dir);
}
