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

/// The patient's RV insertion landmarks (the GPFile's first frame) named by side as cvi42 marks
/// them: of each slice's two, the more anterior (lower y: LPS) is the anterior (cvi42's
/// superior) one.
fn insertions_by_side(gpfile: &Path) -> Vec<(&'static str, [f64; 3])> {
    let text = std::fs::read_to_string(gpfile).unwrap();
    let mut by_slice: std::collections::BTreeMap<String, Vec<[f64; 3]>> = Default::default();
    let mut frame = None;
    for f in text.lines().map(|l| l.split('\t').collect::<Vec<_>>()) {
        if f.len() > 6 && f[3] == "RV_INSERT" && *frame.get_or_insert(f[6]) == f[6] {
            let p = [0, 1, 2].map(|i| f[i].parse::<f64>().unwrap());
            by_slice.entry(f[4].to_string()).or_default().push(p);
        }
    }
    let mut out = Vec::new();
    for mut pair in by_slice.into_values() {
        assert_eq!(pair.len(), 2);
        pair.sort_by(|a, b| a[1].total_cmp(&b[1]));
        out.push(("RV_INSERT_ANTERIOR", pair[0]));
        out.push(("RV_INSERT_INFERIOR", pair[1]));
    }
    out
}

fn degrees(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3)
        .map(|i| a[i] * b[i])
        .sum::<f64>()
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

#[test]
fn insertions_named_by_side_place_the_septum_of_an_lv_only_file() {
    // An LV-only analysis with cvi42's reference points (the common clinical case): the segments
    // come from the insertions alone, both or either. Both sides: the GPFile's own septum (its
    // unnamed insertions paired by slice: 0.0 degrees on both patients; session 38's grouping by
    // the RV's centre put patient 1's apical anterior insertion, which lies on the inferior side
    // of that centre, with the inferior ones: 8.5). One side: the standard's 60 degrees on, exact
    // for insertions 120 degrees apart; patient 1's are about 80 apart, so 20.7 (anterior) and
    // 20.8 (inferior), patient 2's about 110, 4.6 each.
    let dir = scratch("segments-named-insertions");
    for (folder, csv) in [
        ("bivme-example-patient1", "patient1-ED.csv"),
        ("bivme-test-patient2", "patient2-ED.csv"),
    ] {
        let gp = data(&format!("contours/{folder}/GPFile_000.txt"));
        let (from_gp, _) = with_bullseye(&gp, &dir, &format!("{folder}-gp"));
        let reference = vector(&from_gp["segments"]["septum_direction"]);
        let full = std::fs::read_to_string(data(&format!("contours/{folder}/{csv}"))).unwrap();
        let lv_only: String = full
            .lines()
            .filter(|l| !l.ends_with(",RV_ENDO") && !l.ends_with(",RV_EPI"))
            .map(|l| format!("{l}\n"))
            .collect();
        let inserts = insertions_by_side(&gp);
        assert_eq!(inserts.len(), 10, "{folder}");
        for (keep, source, points, within) in [
            ("", "anterior and inferior RV insertion points", 10, 0.5),
            (
                "RV_INSERT_ANTERIOR",
                "RV insertion points of one side, the septum 60 degrees on",
                5,
                35.0,
            ),
            (
                "RV_INSERT_INFERIOR",
                "RV insertion points of one side, the septum 60 degrees on",
                5,
                35.0,
            ),
        ] {
            let mut text = lv_only.clone();
            for (name, [x, y, z]) in inserts.iter().filter(|i| keep.is_empty() || i.0 == keep) {
                text += &format!("# landmark {name} {x} {y} {z}\n");
            }
            let name = format!("{folder}-{}", if keep.is_empty() { "both" } else { keep });
            let input = dir.join(format!("{name}.csv"));
            std::fs::write(&input, text).unwrap();
            let (rep, svg) = with_bullseye(&input, &dir, &name);
            let s = &rep["segments"];
            assert_eq!(s["septum_from"], format!("{source} ({points})"), "{name}");
            let off = degrees(vector(&s["septum_direction"]), reference);
            eprintln!("NAMED INSERTIONS {name}: septum {off:.1} degrees from the GPFile's");
            assert!(off < within, "{name}: {off:.1} degrees");
            assert_eq!(svg.matches("<path ").count(), 17, "{name}");
            // Anterior is the patient's front (LPS -y), whichever side placed it.
            assert!(vector(&s["anterior_direction"])[1] < -0.3, "{name}");
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

/// `volumes` of patient 1's ED and ES GPFiles: each segment's thickening is built from the walls
/// `myocardium` gives of the two phases (the same thicknesses to 1e-9), every segment of this
/// heart (EF 62 %) thickens, and `--thickening-plot` draws them.
#[test]
fn volumes_give_each_segments_systolic_thickening() {
    let dir = scratch("segments-thickening");
    let folder = "contours/bivme-example-patient1";
    let [ed, es] = ["GPFile_000.txt", "GPFile_009.txt"].map(|f| data(&format!("{folder}/{f}")));
    let [json, svg] = ["json", "svg"].map(|e| dir.join(format!("v.{e}")));
    let (code, out, err) = run(bin().args([
        "volumes",
        ed.to_str().unwrap(),
        es.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
        "--thickening-plot",
        svg.to_str().unwrap(),
    ]));
    assert_eq!(code, 0, "{err}");
    let doc: Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let t = &doc["wall_thickening"];
    assert_eq!(t["ed_phase"], "GPFile_000");
    assert_eq!(t["es_phase"], "GPFile_009");
    let (ed_walls, _) = with_bullseye(&ed, &dir, "ed");
    let (es_walls, _) = with_bullseye(&es, &dir, "es");
    let [ed_mm, es_mm] = [&ed_walls, &es_walls].map(|r| means(&r["segments"]));
    let plot = std::fs::read_to_string(&svg).unwrap();
    assert_eq!(plot.matches("<path ").count(), 17);
    for (k, seg) in t["segments"].as_array().unwrap().iter().enumerate() {
        let (a, b) = (
            seg["ed_mm"].as_f64().unwrap(),
            seg["es_mm"].as_f64().unwrap(),
        );
        assert!(
            (a - ed_mm[k]).abs() < 1e-9 * a,
            "segment {}: {a} vs {}",
            k + 1,
            ed_mm[k]
        );
        assert!(
            (b - es_mm[k]).abs() < 1e-9 * b,
            "segment {}: {b} vs {}",
            k + 1,
            es_mm[k]
        );
        let pct = seg["thickening_percent"].as_f64().unwrap();
        assert!(
            (pct - 100.0 * (b - a) / a).abs() < 1e-9,
            "segment {}",
            k + 1
        );
        assert!((5.0..150.0).contains(&pct), "segment {}: {pct} %", k + 1);
        let name = seg["name"].as_str().unwrap();
        assert!(plot.contains(&format!("<title>{} {name}: {pct:.0} %</title>", k + 1)));
    }
    let mean = t["mean_percent"].as_f64().unwrap();
    assert!((20.0..120.0).contains(&mean), "{mean}");
    assert!(out.contains(&format!("mean {mean:.0} %")), "{out}");
}

#[test]
fn a_thickening_plot_needs_two_phases_a_wall_and_a_septum() {
    let dir = scratch("segments-thickening-refusals");
    let svg = dir.join("t.svg");
    let svg = svg.to_str().unwrap();
    let p1 = |f: &str| {
        data(&format!("contours/bivme-example-patient1/{f}"))
            .to_str()
            .unwrap()
            .to_string()
    };
    let surfco = data("contours/surfco-example.csv");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec![p1("GPFile_000.txt")], "two phases or more"),
        (
            vec![
                surfco.to_str().unwrap().into(),
                surfco.to_str().unwrap().into(),
            ],
            "LV_ENDO and LV_EPI",
        ),
        (
            vec![
                p1("GPFile_000.txt"),
                p1("GPFile_009.txt"),
                "--surface".into(),
                "LV_ENDO,RV_ENDO".into(),
            ],
            "LV_ENDO and LV_EPI",
        ),
    ];
    for (args, said) in cases {
        let (code, _, err) = run(bin()
            .arg("volumes")
            .args(&args)
            .args(["--thickening-plot", svg]));
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(said), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(!Path::new(svg).exists());
    }
    // Without the plot, an LV-only study measures its volumes and says why there is no
    // thickening in the JSON.
    let full = std::fs::read_to_string(p1("patient1-ED.csv")).unwrap();
    let full_es = std::fs::read_to_string(p1("patient1-ES.csv")).unwrap();
    let lv_only = |text: &str| -> String {
        text.lines()
            .filter(|l| !l.ends_with(",RV_ENDO") && !l.ends_with(",RV_EPI"))
            .map(|l| format!("{l}\n"))
            .collect()
    };
    let (a, b) = (dir.join("ed.csv"), dir.join("es.csv"));
    std::fs::write(&a, lv_only(&full)).unwrap();
    std::fs::write(&b, lv_only(&full_es)).unwrap();
    let json = dir.join("v.json");
    let (code, _, err) = run(bin().args([
        "volumes",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
    ]));
    assert_eq!(code, 0, "{err}");
    let doc: Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    assert_eq!(doc["wall_thickening"], Value::Null);
    let note = doc["wall_thickening_note"].as_str().unwrap();
    assert!(
        note.contains("no RV_INSERT landmarks and no RV contours"),
        "{note}"
    );
    assert!(err.contains("no LV wall thickening"), "{err}");
    // One phase twice: its end-diastole is its end-systole, and nothing thickens.
    let (c, d) = (dir.join("one.csv"), dir.join("again.csv"));
    std::fs::write(&c, &full).unwrap();
    std::fs::write(&d, &full).unwrap();
    let (code, _, err) = run(bin().args([
        "volumes",
        c.to_str().unwrap(),
        d.to_str().unwrap(),
        "--surface",
        "LV_ENDO,LV_EPI",
        "--json",
        json.to_str().unwrap(),
    ]));
    assert_eq!(code, 0, "{err}");
    let doc: Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    assert_eq!(doc["wall_thickening"], Value::Null);
    let note = doc["wall_thickening_note"].as_str().unwrap();
    assert!(note.contains("the same phase"), "{note}");
}

/// A file whose "LV epicardium" rings both cavities (biv-me's biventricular epicardium simulated
/// under the LV_EPI label, as label maps painted from biventricular models have it): the LV wall
/// would count the RV cavity as septum, so it has no segments, and a warning says why.
#[test]
fn an_epicardium_around_the_rv_gives_no_segments() {
    let dir = scratch("segments-biv-epi");
    let mesh = |n: &str| data(&format!("meshes/{n}")).to_str().unwrap().to_string();
    let csv = dir.join("biv-as-lv.csv");
    let (code, _, err) = run(bin().args([
        "simulate",
        &format!("LV_ENDO={}", mesh("bivme-patient1-ED-LV_ENDO-closed.obj")),
        &format!("LV_EPI={}", mesh("bivme-patient1-ED-EPI-closed.obj")),
        &format!("RV_ENDO={}", mesh("bivme-patient1-ED-RV_ENDO-closed.obj")),
        "-o",
        csv.to_str().unwrap(),
        "--quiet",
    ]));
    assert_eq!(code, 0, "{err}");
    let [out, report] = ["vtk", "json"].map(|e| dir.join(format!("w.{e}")));
    let (code, _, err) = run(bin().args([
        "myocardium",
        csv.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
    ]));
    assert_eq!(code, 0, "{err}");
    let rep: Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    assert_eq!(rep["segments"], Value::Null);
    let note = rep["segments_note"].as_str().unwrap();
    assert!(note.contains("encloses the RV cavity"), "{note}");
    assert!(err.contains("LV_EPI encloses the RV cavity"), "{err}");
}
