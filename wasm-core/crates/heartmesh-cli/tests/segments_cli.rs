//! `heartmesh myocardium`'s AHA segments (the report's `segments`, `--bullseye`) on the real
//! biv-me patients: placed from the RV insertion landmarks of a GPFile or the RV contours of a
//! CSV, anterior where the patient's anterior is (biv-me files are in DICOM patient
//! coordinates, LPS: anterior is -y, the patient's right -x), and the refusals where a file says
//! nothing of the septum.

mod common;
use common::{bin, data, run, scratch};
use serde_json::Value;
use std::path::Path;

/// `myocardium INPUT -o DIR/NAME.vtk --report DIR/NAME.json --bullseye DIR/NAME.svg`: the report
/// and the bullseye's text.
fn with_bullseye(input: &Path, dir: &Path, name: &str) -> (Value, String) {
    let [out, report, svg] = ["vtk", "json", "svg"].map(|e| dir.join(format!("{name}.{e}")));
    let (code, _, err) = run(bin().args([
        "myocardium",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
        "--bullseye",
        svg.to_str().unwrap(),
        "--quiet",
    ]));
    assert_eq!(code, 0, "{err}");
    let rep = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    (rep, std::fs::read_to_string(svg).unwrap())
}

fn vector(v: &Value) -> [f64; 3] {
    let a: Vec<f64> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    [a[0], a[1], a[2]]
}

fn means(segments: &Value) -> Vec<f64> {
    segments["segments"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["mean_mm"].as_f64().unwrap())
        .collect()
}

#[test]
fn real_patients_have_their_septum_on_the_right_and_thickest() {
    let dir = scratch("segments-real");
    for (folder, gp, csv) in [
        (
            "bivme-example-patient1",
            "GPFile_000.txt",
            "patient1-ED.csv",
        ),
        ("bivme-test-patient2", "GPFile_000.txt", "patient2-ED.csv"),
    ] {
        let (from_gp, svg) = with_bullseye(&data(&format!("contours/{folder}/{gp}")), &dir, folder);
        let s = &from_gp["segments"];
        assert_eq!(s["septum_from"], "RV_INSERT landmarks (10)", "{folder}");
        let septum = vector(&s["septum_direction"]);
        let anterior = vector(&s["anterior_direction"]);
        // LPS: the septum faces the patient's right and front, the anterior wall the front.
        assert!(septum[0] < -0.5 && septum[1] < 0.0, "{folder}: {septum:?}");
        assert!(anterior[1] < -0.3, "{folder}: {anterior:?}");
        let m = means(s);
        assert_eq!(m.len(), 17);
        for (k, mm) in m.iter().enumerate() {
            assert!(
                (3.0..16.0).contains(mm),
                "{folder}: segment {} {mm} mm",
                k + 1
            );
        }
        // The septum (2, 3 and 8, 9) thicker than the lateral wall (5, 6 and 11, 12), the apex
        // (17) thinner than the basal ring: an adult LV.
        let sum = |ids: &[usize]| ids.iter().map(|&i| m[i - 1]).sum::<f64>();
        assert!(
            sum(&[2, 3, 8, 9]) > sum(&[5, 6, 11, 12]) + 4.0,
            "{folder}: {m:?}"
        );
        assert!(m[16] < sum(&[1, 2, 3, 4, 5, 6]) / 6.0, "{folder}: {m:?}");
        // The segments tile the wall: their areas add up to the epicardium and endocardium.
        let area: f64 = s["segments"]
            .as_array()
            .unwrap()
            .iter()
            .map(|g| g["area_mm2"].as_f64().unwrap())
            .sum();
        assert!(area > 10_000.0, "{folder}: {area}");
        // The bullseye: 17 sectors, each labelled with its mean to 0.1 mm.
        assert_eq!(svg.matches("<path ").count(), 17, "{folder}");
        for (k, mm) in m.iter().enumerate() {
            let label = format!(
                "<title>{} {}: {mm:.1} mm</title>",
                k + 1,
                s["segments"][k]["name"].as_str().unwrap()
            );
            assert!(svg.contains(&label), "{folder}: no {label}");
        }
        // The CSV has no insertion points: the RV contours' centre places the septum within
        // 15 degrees of them (10.2 on patient 2), and no segment's mean moves by more than 1 mm.
        let (from_csv, _) = with_bullseye(&data(&format!("contours/{folder}/{csv}")), &dir, csv);
        let c = &from_csv["segments"];
        assert!(
            c["septum_from"]
                .as_str()
                .unwrap()
                .starts_with("the RV contours' centre"),
            "{c}"
        );
        let other = vector(&c["septum_direction"]);
        let cos: f64 = (0..3).map(|i| septum[i] * other[i]).sum();
        assert!(
            cos > 15f64.to_radians().cos(),
            "{folder}: {} degrees",
            cos.acos().to_degrees()
        );
        for (a, b) in m.iter().zip(means(c)) {
            assert!((a - b).abs() < 1.0, "{folder}: {a} vs {b}");
        }
    }
}

#[test]
fn a_file_without_the_rv_has_no_segments_and_no_bullseye() {
    let dir = scratch("segments-lv-only");
    let full =
        std::fs::read_to_string(data("contours/bivme-example-patient1/patient1-ED.csv")).unwrap();
    let lv_only: String = full
        .lines()
        .filter(|l| !l.ends_with(",RV_ENDO") && !l.ends_with(",RV_EPI"))
        .map(|l| format!("{l}\n"))
        .collect();
    assert!(
        lv_only.len() < full.len() / 2 + full.len() / 4,
        "the RV rows went"
    );
    let input = dir.join("lv-only.csv");
    std::fs::write(&input, lv_only).unwrap();
    let input = input.to_str().unwrap();
    let [out, report, svg] =
        ["vtk", "json", "svg"].map(|e| dir.join(format!("w.{e}")).to_str().unwrap().to_string());
    let (code, _, err) = run(bin().args(["myocardium", input, "-o", &out, "--report", &report]));
    assert_eq!(code, 0, "{err}");
    let rep: Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    assert_eq!(rep["segments"], Value::Null);
    assert!(rep["segments_note"]
        .as_str()
        .unwrap()
        .contains("no RV_INSERT landmarks and no RV contours"));
    // Asked for a bullseye, it says why before any run, and writes nothing.
    let (code, _, err) = run(bin().args(["myocardium", input, "-o", &out, "--bullseye", &svg]));
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("--bullseye needs the septum's direction"),
        "{err}"
    );
    assert!(!Path::new(&svg).exists());
    // Nor does a biventricular wall have them.
    let p1 = data("contours/bivme-example-patient1/patient1-ED.csv");
    let (code, _, err) = run(bin().args([
        "myocardium",
        p1.to_str().unwrap(),
        "-o",
        &out,
        "--biventricular",
        "--bullseye",
        &svg,
    ]));
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("leave out --biventricular"), "{err}");
}
