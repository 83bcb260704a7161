use super::*;
use crate::io::{detect_contour_format, read_contours, read_study, ContourFormat, ContourOptions};

const SCHEMA: &str = "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/markups-schema-v1.0.3.json#";

/// One markup's JSON: `points` as control points (each `[x, y, z]`, or `None` for a point not
/// placed yet), with `extra` fields spliced in.
fn markup(kind: &str, name: Option<&str>, points: &[Option<[f64; 3]>], extra: &str) -> String {
    let cps: Vec<String> = points
        .iter()
        .enumerate()
        .map(|(k, p)| match p {
            Some([x, y, z]) => format!(
                r#"{{"id":"{k}","label":"P-{k}","position":[{x},{y},{z}],"positionStatus":"defined"}}"#
            ),
            None => format!(r#"{{"id":"{k}","label":"P-{k}","position":[0,0,0],"positionStatus":"undefined"}}"#),
        })
        .collect();
    let name = name.map_or(String::new(), |n| format!(r#""name":"{n}","#));
    format!(
        r#"{{"type":"{kind}",{name}"coordinateSystem":"LPS","coordinateUnits":"mm"{extra},"controlPoints":[{}],"display":{{"visibility":true}}}}"#,
        cps.join(",")
    )
}

fn file(markups: &[String]) -> Vec<u8> {
    format!(
        r#"{{"@schema":"{SCHEMA}","markups":[{}]}}"#,
        markups.join(",")
    )
    .into_bytes()
}

/// `n` control points round a circle of radius `r` at height `z`.
fn ring(n: usize, r: f64, z: f64) -> Vec<Option<[f64; 3]>> {
    (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            Some([r * a.cos(), r * a.sin(), z])
        })
        .collect()
}

#[test]
fn a_closed_curve_follows_the_circle_through_its_control_points() {
    // 12 points round a 25 mm circle: the polygon's chords fall 0.85 mm inside at their middles.
    let bytes = file(&[markup(
        "ClosedCurve",
        Some("LV_ENDO_3"),
        &ring(12, 25.0, 40.0),
        "",
    )]);
    assert_eq!(
        detect_contour_format("c.mrk.json", &bytes),
        ContourFormat::SlicerMarkups
    );
    let set = read_contours("c.mrk.json", &bytes).unwrap();
    assert_eq!(set.contours.len(), 1);
    let c = &set.contours[0];
    assert_eq!(
        (c.id.as_str(), c.surface.as_deref()),
        ("LV_ENDO_3", Some("LV_ENDO"))
    );
    assert_eq!(c.pieces.len(), 1);
    assert!(c.pieces[0].closed);
    let pts = &c.pieces[0].points;
    // 12 segments of 12.9 mm, each in 13 steps of under 1 mm.
    assert_eq!(pts.len(), 12 * 13);
    let worst = pts
        .iter()
        .map(|p| ((p.x * p.x + p.y * p.y).sqrt() - 25.0).abs())
        .fold(0.0, f64::max);
    assert!(worst < 0.1, "spline {worst} mm off the circle");
    assert!(pts.iter().all(|p| (p.z - 40.0).abs() < 1e-12));
    let step = pts
        .iter()
        .zip(pts.iter().cycle().skip(1))
        .map(|(a, b)| (b - a).norm())
        .fold(0.0, f64::max);
    // Steps cut the chord in millimetres; the arc over it is a little longer.
    assert!(step <= 1.05, "step {step} mm");
    assert_eq!(set.coordinate_system, Some(CoordinateSystem::Lps));
    // One curve alone: the first warning says why a run will fail and what to open.
    assert!(
        set.warnings[0].starts_with("one curve (LV_ENDO_3): 3D Slicer saves each curve in a file"),
        "{:?}",
        set.warnings
    );
}

#[test]
fn an_open_curve_keeps_its_ends_and_undefined_points_are_skipped() {
    let mut pts = vec![
        Some([0.0, 0.0, 0.0]),
        Some([10.0, 5.0, 0.0]),
        None,
        Some([20.0, 0.0, 0.0]),
    ];
    pts.push(Some([30.0, -5.0, 0.0]));
    let bytes = file(&[markup("Curve", Some("LV endo 4CH"), &pts, "")]);
    let set = read_contours("x.json", &bytes).unwrap();
    let c = &set.contours[0];
    assert_eq!(c.surface.as_deref(), Some("LV_ENDO"));
    let p = &c.pieces[0];
    assert!(!p.closed);
    assert_eq!(p.points[0], v3(0.0, 0.0, 0.0));
    assert_eq!(*p.points.last().unwrap(), v3(30.0, -5.0, 0.0));
    // The undefined point at (0, 0, 0) is not between (10, 5) and (20, 0).
    assert!(p.points.iter().skip(1).all(|q| q.x > 0.5));
}

#[test]
fn names_give_surfaces_without_their_slice_tags() {
    for (name, surface) in [
        ("LV_ENDO_3", Some("LV_ENDO")),
        ("lv endo sax3", Some("LV_ENDO")),
        ("sax3-LV-endo", Some("LV_ENDO")),
        ("RV_ENDO_4CH", Some("RV_ENDO")),
        ("LV_EPI slice 12", Some("LV_EPI")),
        ("LV_EPI_LAX_2", Some("LV_EPI")),
        ("s02_SAX_LV_ENDOCARDIAL", Some("LV_ENDO")),
        ("s02_SAX_RV_FREEWALL", Some("RV_ENDO")),
        ("s02_SAX_RV_SEPTUM", Some("RV_ENDO")),
        ("RV free wall 5", Some("RV_ENDO")),
        ("LVEpi_4ch", Some("LV_EPI")),
        ("left ventricle endocardium", Some("LV_ENDO")),
        ("rv epi 2", Some("RV_EPI")),
        ("curve lv endo", Some("LV_ENDO")),
        ("myo_3", Some("MYO")),
        ("LV septum 3", Some("LV_SEPTUM")),
        ("CC_1", Some("CC")),
        ("CC", Some("CC")),
        ("3", None),
        ("SA 4", None),
    ] {
        assert_eq!(surface_of(name).as_deref(), surface, "{name}");
    }
}

#[test]
fn folders_whose_curves_share_names_are_studies_of_their_own() {
    let ring_file = |name: Option<&str>, r: f64, z: f64| {
        file(&[markup("ClosedCurve", name, &ring(10, r, z), "")])
    };
    let (ed1, ed2) = (
        ring_file(Some("LV_ENDO_1"), 20.0, 0.0),
        ring_file(Some("LV_ENDO_2"), 22.0, 10.0),
    );
    let (es1, es2) = (
        ring_file(Some("LV_ENDO_1"), 15.0, 0.0),
        ring_file(Some("LV_ENDO_2"), 17.0, 10.0),
    );
    // A patient's end-diastolic and end-systolic folders given together.
    let phases: [(&str, &[u8]); 4] = [
        ("p1/ED/LV_ENDO_1.mrk.json", &ed1),
        ("p1/ES/LV_ENDO_2.mrk.json", &es2),
        ("p1/ED/LV_ENDO_2.mrk.json", &ed2),
        ("p1/ES/LV_ENDO_1.mrk.json", &es1),
    ];
    let e = read_study(&phases, &ContourOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("Slicer markups from 2 folders (p1/ED, p1/ES) hold curves of the same names (LV_ENDO_1, LV_ENDO_2)")
            && e.contains("open one folder at a time"),
        "{e}"
    );
    // Unnamed markups are named by their files: the same file names in two folders meet too.
    let (u1, u2) = (ring_file(None, 20.0, 0.0), ring_file(None, 15.0, 0.0));
    let unnamed: [(&str, &[u8]); 2] = [
        ("ED/LV_ENDO_1.mrk.json", &u1),
        ("ES\\LV_ENDO_1.mrk.json", &u2),
    ];
    let e = read_study(&unnamed, &ContourOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("from 2 folders (ED, ES)"), "{e}");
    // Folders whose names do not meet are one set (the LV's curves beside the RV's).
    let rv = ring_file(Some("RV_ENDO_1"), 30.0, 0.0);
    let split: [(&str, &[u8]); 3] = [
        ("p1/LV/LV_ENDO_1.mrk.json", &ed1),
        ("p1/LV/LV_ENDO_2.mrk.json", &ed2),
        ("p1/RV/RV_ENDO_1.mrk.json", &rv),
    ];
    let (_, set) = read_study(&split, &ContourOptions::default()).unwrap();
    let ids: Vec<&str> = set.contours.iter().map(|c| c.id.as_str()).collect();
    assert_eq!(ids, ["LV_ENDO_1", "LV_ENDO_2", "RV_ENDO_1"]);
}

#[test]
fn a_folder_of_files_is_one_set_in_name_order_whatever_the_order_given() {
    let a = file(&[markup(
        "ClosedCurve",
        Some("LV_ENDO_1"),
        &ring(10, 20.0, 0.0),
        "",
    )]);
    let b = file(&[markup(
        "ClosedCurve",
        Some("LV_ENDO_2"),
        &ring(10, 22.0, 10.0),
        "",
    )]);
    // No name: the file's name is the id (Slicer names the node after the file it reads).
    let c = file(&[markup(
        "Curve",
        None,
        &[
            Some([0.0, -30.0, -20.0]),
            Some([0.0, 0.0, -30.0]),
            Some([0.0, 30.0, -20.0]),
        ],
        "",
    )]);
    let files: [(&str, &[u8]); 3] = [
        ("dir/LV_ENDO_2.mrk.json", &b),
        ("dir/LV_ENDO_4CH.mrk.json", &c),
        ("dir/LV_ENDO_1.mrk.json", &a),
    ];
    let (_, set) = read_study(&files, &ContourOptions::default()).unwrap();
    let ids: Vec<&str> = set.contours.iter().map(|c| c.id.as_str()).collect();
    assert_eq!(ids, ["LV_ENDO_1", "LV_ENDO_2", "LV_ENDO_4CH"]);
    assert!(set
        .contours
        .iter()
        .all(|c| c.surface.as_deref() == Some("LV_ENDO")));
    let reversed: Vec<(&str, &[u8])> = files.iter().rev().copied().collect();
    let (_, again) = read_study(&reversed, &ContourOptions::default()).unwrap();
    assert_eq!(again.contours, set.contours);
}

#[test]
fn one_name_on_two_slices_is_two_contours_and_other_markups_are_named_as_skipped() {
    let line = markup(
        "Line",
        Some("L"),
        &[Some([0.0, 0.0, 0.0]), Some([1.0, 0.0, 0.0])],
        "",
    );
    let fiducials = r#"{"type":"Fiducial","name":"F","controlPoints":[{"label":"RV_INSERT_ANTERIOR","position":[1,2,3]},{"label":"APEX_POINT","position":[4,5,6],"positionStatus":"preview"}]}"#;
    let bytes = file(&[
        markup("ClosedCurve", Some("CC"), &ring(8, 20.0, 0.0), ""),
        markup("ClosedCurve", Some("CC"), &ring(8, 20.0, 10.0), ""),
        line,
        fiducials.to_string(),
    ]);
    let set = read_contours("m.mrk.json", &bytes).unwrap();
    let ids: Vec<&str> = set.contours.iter().map(|c| c.id.as_str()).collect();
    // Two closed curves of one name 10 mm apart: each slice's curve is a contour (plane_split).
    assert_eq!(ids, ["CC", "CC (2)"]);
    assert!(set.contours.iter().all(|c| c.pieces.len() == 1));
    assert!(
        set.warnings
            .iter()
            .any(|w| w.starts_with("contour \"CC\" (2 image planes, read as \"CC\", \"CC (2)\")")),
        "{:?}",
        set.warnings
    );
    assert_eq!(
        set.landmarks,
        vec![("RV_INSERT_ANTERIOR".to_string(), v3(1.0, 2.0, 3.0))]
    );
    assert!(
        set.warnings.iter().any(|w| w.contains("skipped: L (Line)")),
        "{:?}",
        set.warnings
    );
}

#[test]
fn frames_and_units_come_to_the_first_markups_frame_in_millimetres() {
    let ras = markup("ClosedCurve", Some("B"), &ring(8, 20.0, 10.0), "")
        .replace(r#""coordinateSystem":"LPS""#, r#""coordinateSystem":"RAS""#);
    let um = markup("ClosedCurve", Some("C"), &ring(8, 20_000.0, 20_000.0), "").replace(
        r#""coordinateUnits":"mm""#,
        r#""coordinateUnits":["um","UCUM","micrometer"]"#,
    );
    let bytes = file(&[
        markup("ClosedCurve", Some("A"), &ring(8, 20.0, 0.0), ""),
        ras,
        um,
    ]);
    let set = read_contours("m.mrk.json", &bytes).unwrap();
    assert_eq!(set.coordinate_system, Some(CoordinateSystem::Lps));
    let first = |k: usize| set.contours[k].pieces[0].points[0];
    // B's first point (20, 0, 10) in RAS is (-20, 0, 10) in LPS.
    assert!(
        (first(1) - v3(-20.0, 0.0, 10.0)).norm() < 1e-9,
        "{:?}",
        first(1)
    );
    assert!(
        (first(2) - v3(20.0, 0.0, 20.0)).norm() < 1e-9,
        "{:?}",
        first(2)
    );
    assert!(set
        .warnings
        .iter()
        .any(|w| w.starts_with("B taken from the other patient frame into LPS")));
    // A file of RAS markups says RAS.
    let ras_only =
        file(&[markup("ClosedCurve", Some("A"), &ring(8, 20.0, 0.0), "").replace("LPS", "RAS")]);
    assert_eq!(
        read_contours("r.mrk.json", &ras_only)
            .unwrap()
            .coordinate_system,
        Some(CoordinateSystem::Ras)
    );
}

#[test]
fn bad_files_are_refused_with_what_is_wrong() {
    let err = |name: &str, bytes: &[u8]| read_contours(name, bytes).unwrap_err().to_string();
    let broken = format!("{{\"@schema\":\"{SCHEMA}\",\n\"markups\":[{{\"type\":\"ClosedCurve\",\n\"controlPoints\":[1,]}}]}}");
    let e = err("b.mrk.json", broken.as_bytes());
    assert!(e.contains("line 3") && e.contains("not valid JSON"), "{e}");
    let e = err(
        "n.mrk.json",
        format!(r#"{{"@schema":"{SCHEMA}"}}"#).as_bytes(),
    );
    assert!(e.contains("no \"markups\" list"), "{e}");
    let nopos = file(&[r#"{"type":"ClosedCurve","name":"S1","controlPoints":[{"position":[1,2]},{"position":[1,2,3]},{"position":[3,2,1]}]}"#.to_string()]);
    let e = err("p.mrk.json", &nopos);
    assert!(e.contains("S1: control point 1 has no position"), "{e}");
    let feet = file(&[
        markup("ClosedCurve", Some("A"), &ring(8, 20.0, 0.0), "").replace(r#""mm""#, r#""ft""#)
    ]);
    assert!(err("f.mrk.json", &feet).contains("coordinate units \"ft\""));
    let points_only = file(&[markup(
        "Line",
        Some("L"),
        &[Some([0.0, 0.0, 0.0]), Some([1.0, 0.0, 0.0])],
        "",
    )]);
    assert!(err("l.mrk.json", &points_only).contains("no curve or closed curve"));
    // A hostile segment 10 km long costs 64 points, not ten thousand.
    let far = file(&[markup(
        "Curve",
        Some("F"),
        &[Some([0.0, 0.0, 0.0]), Some([1e7, 0.0, 0.0])],
        "",
    )]);
    let set = read_contours("far.mrk.json", &far).unwrap();
    assert!(set.contours[0].point_count() <= MAX_SEGMENT_STEPS + 1);
    // Control points whose splines would pass the points limit are refused before any is made.
    let many: Vec<Option<[f64; 3]>> = (0..40_000)
        .map(|k| Some([k as f64 * 100.0, 0.0, 0.0]))
        .collect();
    let e = err(
        "many.mrk.json",
        &file(&[markup("Curve", Some("M"), &many, "")]),
    );
    assert!(e.contains("too many points"), "{e}");
    // In a folder, the error names its file.
    let good = file(&[markup("ClosedCurve", Some("A"), &ring(8, 20.0, 0.0), "")]);
    let files: [(&str, &[u8]); 2] = [("a.mrk.json", &good), ("p.mrk.json", &nopos)];
    let e = read_study(&files, &ContourOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("p.mrk.json: S1: control point 1"), "{e}");
}

#[test]
fn a_heartmesh_session_is_not_taken_for_markups() {
    let session = br#"{"heartmesh_session": 1, "contours": [{"id": "c1", "points": [[0,0,0],[1,0,0],[0,1,0]]}]}"#;
    assert_eq!(
        detect_contour_format("s.json", session),
        ContourFormat::Session
    );
    assert!(!is_markups(b"[1, 2, 3]"));
    assert!(is_markups(
        br#"{"markups": [{"type": "Curve", "controlPoints": []}]}"#
    ));
}

/// A markup as Slicer's legacy point list file (`.fcsv`, Slicer 5's rows with their two trailing
/// fields): what Slicer writes when a markup is saved in that format.
fn as_fcsv(markup: &Value) -> String {
    let mut out = format!(
        "# Markups fiducial file version = 5.6\n# CoordinateSystem = {}\n\
         # columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n",
        markup["coordinateSystem"].as_str().unwrap_or("LPS")
    );
    for (k, p) in defined(markup).enumerate() {
        let xyz: Vec<String> = p["position"]
            .as_array()
            .into_iter()
            .flatten()
            .map(|v| v.to_string())
            .collect();
        let label = p["label"].as_str().unwrap_or("");
        out.push_str(&format!(
            "{},{},0,0,0,1,1,1,0,{label},,,2,0\n",
            k + 1,
            xyz.join(",")
        ));
    }
    out
}

#[test]
fn point_lists_are_landmarks_unless_drawn_along_a_curve() {
    let named = |label: &str, points: &[[f64; 3]]| -> String {
        let cps: Vec<String> = points
            .iter()
            .enumerate()
            .map(|(k, [x, y, z])| format!(r#"{{"label":"{label}{k}","position":[{x},{y},{z}]}}"#))
            .collect();
        cps.join(",")
    };
    let ring12: Vec<[f64; 3]> = ring(12, 25.0, 40.0).into_iter().flatten().collect();
    let spread = [
        [0.0, 0.0, 0.0],
        [30.0, 0.0, 40.0],
        [0.0, 30.0, 80.0],
        [-30.0, 0.0, 20.0],
        [0.0, -30.0, 60.0],
    ];
    let septum = [[0.0, 0.0, 40.0], [3.0, 1.0, 40.0], [6.0, 3.0, 40.0]];
    let list = |name: &str, cps: String| {
        format!(
            r#"{{"type":"Fiducial","name":"{name}","coordinateSystem":"LPS","controlPoints":[{cps}]}}"#
        )
    };
    let bytes = file(&[
        // Twelve clicks round a ring, in its plane: a closed contour, splined as a curve is.
        list("F", named("F-", &ring12)),
        // The same clicks named as landmarks, or a list named so: landmarks.
        list("G", named("MITRAL_VALVE_", &ring12[..4])),
        list("Apex points", named("p", &ring12[..4])),
        // Five points over several images: landmarks.
        list("H", named("H-", &spread)),
        // Three clicks of a septum arc named after its wall: an open contour.
        list("s06_SAX_RV_SEPTUM", named("s-", &septum)),
    ]);
    let set = read_contours("m.mrk.json", &bytes).unwrap();
    let ids: Vec<&str> = set.contours.iter().map(|c| c.id.as_str()).collect();
    assert_eq!(ids, ["F", "s06_SAX_RV_SEPTUM"]);
    let f = &set.contours[0].pieces;
    assert!(
        f.len() == 1 && f[0].closed && f[0].points.len() > 100,
        "{f:?}"
    );
    let off = f[0]
        .points
        .iter()
        .map(|p| ((p.x * p.x + p.y * p.y).sqrt() - 25.0).abs())
        .fold(0.0, f64::max);
    assert!(off < 0.1, "the spline strays {off} mm off the ring");
    let s = &set.contours[1];
    assert_eq!(s.surface.as_deref(), Some("RV_ENDO"));
    assert!(!s.pieces[0].closed);
    assert_eq!(set.landmarks.len(), 4 + 4 + 5);
    assert!(
        set.warnings
            .iter()
            .any(|w| w.starts_with(POINT_CONTOURS) && w.ends_with("F, s06_SAX_RV_SEPTUM")),
        "{:?}",
        set.warnings
    );
    assert!(crate::io::is_reading_note(&format!(
        "{POINT_CONTOURS} (...)"
    )));
}

#[test]
fn a_folder_of_point_list_files_reads_as_its_markups_do() {
    let dir = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/slicer-markups-patient1"
    );
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".mrk.json"))
        .collect();
    names.sort();
    let json: Vec<(String, Vec<u8>)> = names
        .iter()
        .map(|n| {
            (
                format!("p1/{n}"),
                std::fs::read(format!("{dir}/{n}")).unwrap(),
            )
        })
        .collect();
    // Each markup as the file Slicer saves it in; a curve kept in several markups of one name
    // (a stretch each) is its first stretch only, as a point list holds one.
    let mut fcsv: Vec<(String, Vec<u8>)> = Vec::new();
    for (name, bytes) in &json {
        let root: Value = serde_json::from_slice(bytes).unwrap();
        let first = &root["markups"][0];
        let stem = name.trim_end_matches(".mrk.json");
        fcsv.push((format!("{stem}.fcsv"), as_fcsv(first).into_bytes()));
    }
    let study = |files: &[(String, Vec<u8>)]| {
        let refs: Vec<(&str, &[u8])> = files
            .iter()
            .map(|(n, b)| (n.as_str(), b.as_slice()))
            .collect();
        read_study(&refs, &ContourOptions::default()).unwrap().1
    };
    let (from_json, from_fcsv) = (study(&json), study(&fcsv));
    // The same markups as control points tables (Slicer's "export to table", saved as CSV; RAS
    // here, every point with its `defined` flag): the same contours as the point list files.
    let tables: Vec<(String, Vec<u8>)> = json
        .iter()
        .map(|(name, bytes)| {
            let root: Value = serde_json::from_slice(bytes).unwrap();
            let mut text =
                String::from("label,r,a,s,defined,selected,visible,locked,description\n");
            for p in root["markups"][0]["controlPoints"].as_array().unwrap() {
                let xyz: Vec<f64> = p["position"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .filter_map(Value::as_f64)
                    .collect();
                let placed = p["positionStatus"].as_str().is_none_or(|s| s == "defined");
                text.push_str(&format!(
                    "{},{},{},{},{},1,1,0,\n",
                    p["label"].as_str().unwrap_or(""),
                    -xyz[0],
                    -xyz[1],
                    xyz[2],
                    u8::from(placed)
                ));
            }
            let stem = name.trim_end_matches(".mrk.json");
            (format!("{stem}.csv"), text.into_bytes())
        })
        .collect();
    let from_tables = study(&tables);
    assert_eq!(from_tables.coordinate_system, Some(CoordinateSystem::Ras));
    assert_eq!(from_tables.contours.len(), from_fcsv.contours.len());
    for (a, b) in from_tables.contours.iter().zip(&from_fcsv.contours) {
        assert_eq!((&a.id, a.pieces.len()), (&b.id, b.pieces.len()));
        for (pa, pb) in a.pieces.iter().zip(&b.pieces) {
            assert_eq!(pa.closed, pb.closed, "{}", a.id);
            let off = pa
                .points
                .iter()
                .zip(&pb.points)
                .map(|(p, q)| (p - v3(-q.x, -q.y, q.z)).norm())
                .fold(0.0, f64::max);
            assert!(off < 1e-9, "{}: {off} mm", a.id);
        }
    }
    assert_eq!(
        detect_contour_format(&fcsv[0].0, &fcsv[0].1),
        ContourFormat::SlicerMarkups
    );
    assert_eq!(from_fcsv.coordinate_system, Some(CoordinateSystem::Lps));
    // The RV insertions stay landmarks; every curve is there, under its name and surface.
    assert_eq!(from_fcsv.landmarks, from_json.landmarks);
    assert_eq!(from_fcsv.landmarks.len(), 2);
    assert_eq!(from_fcsv.contours.len(), from_json.contours.len());
    let mut same = 0;
    for (a, b) in from_fcsv.contours.iter().zip(&from_json.contours) {
        assert_eq!((&a.id, &a.surface), (&b.id, &b.surface));
        // Closed where Slicer's curve is closed, point for point where it is one stretch.
        assert_eq!(a.pieces[0].closed, b.pieces[0].closed, "{}", a.id);
        if b.pieces.len() == 1 {
            assert_eq!(a.pieces, b.pieces, "{}", a.id);
            same += 1;
        }
    }
    assert_eq!(same, 35);
    assert!(from_fcsv
        .warnings
        .iter()
        .any(|w| w.starts_with(POINT_CONTOURS) && w.contains("(40 in all)")));
}

#[test]
fn a_point_list_file_alone_says_to_open_its_folder() {
    let list = "# Markups fiducial file version = 4.10\n# CoordinateSystem = 0\n\
                # columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n\
                1,10,0,5,0,0,0,1,1,1,0,F-1,,\n2,0,10,5,0,0,0,1,1,1,0,F-2,,\n\
                3,-10,0,5,0,0,0,1,1,1,0,F-3,,\n4,0,-10,5,0,0,0,1,1,1,0,F-4,,\n";
    // Numbered rows are no three-number point text: read as a point list, not as x y z.
    assert_eq!(
        detect_contour_format("LV_ENDO_3.fcsv", list.as_bytes()),
        ContourFormat::SlicerMarkups
    );
    let set = read_contours("LV_ENDO_3.fcsv", list.as_bytes()).unwrap();
    assert_eq!(set.coordinate_system, Some(CoordinateSystem::Ras));
    assert_eq!(set.contours.len(), 1);
    assert_eq!(set.contours[0].id, "LV_ENDO_3");
    assert!(set.contours[0].pieces[0].closed);
    assert!(
        set.warnings[0].contains(".fcsv) files together"),
        "{:?}",
        set.warnings
    );
    // A damaged row is refused with its file and line when read in a folder.
    let bad = list.replace("3,-10,0,5", "3,-10,zero,5");
    let files: [(&str, &[u8]); 2] = [("d/a.fcsv", list.as_bytes()), ("d/b.fcsv", bad.as_bytes())];
    match read_study(&files, &ContourOptions::default()) {
        Err(CoreError::Parse { line, message }) => {
            assert_eq!(line, 6, "{message}");
            assert!(message.starts_with("d/b.fcsv: y"), "{message}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn lists_taken_for_landmarks_are_named_when_no_contour_is_left() {
    let rows = |pts: &[[f64; 3]]| -> String {
        let mut t =
            String::from("# Markups fiducial file version = 4.10\n# CoordinateSystem = 1\n");
        for (k, [x, y, z]) in pts.iter().enumerate() {
            t.push_str(&format!("{k},{x},{y},{z},0,0,0,1,1,1,0,F-{},,\n", k + 1));
        }
        t
    };
    let three = rows(&[[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 10.0, 0.0]]);
    let bent = rows(&[
        [0.0, 0.0, 0.0],
        [10.0, 0.0, 5.0],
        [0.0, 10.0, 30.0],
        [5.0, 5.0, -20.0],
    ]);
    let files: [(&str, &[u8]); 2] = [
        ("d/F.fcsv", three.as_bytes()),
        ("d/G.fcsv", bent.as_bytes()),
    ];
    let e = read_study(&files, &ContourOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(
            "point lists read as landmarks: F (3 point(s), and its name says no wall), G (points \
             up to 5.1 mm off one plane)"
        ),
        "{e}"
    );
    // Landmarks in a folder of their own beside a folder of contours: one set, read whole.
    let ring = |z: f64| {
        rows(
            &ring(10, 20.0, z)
                .into_iter()
                .flatten()
                .collect::<Vec<[f64; 3]>>(),
        )
    };
    let (a, b) = (ring(0.0), ring(10.0));
    let files: [(&str, &[u8]); 3] = [
        ("landmarks/G.fcsv", bent.as_bytes()),
        ("curves/LV_ENDO_1.fcsv", a.as_bytes()),
        ("curves/LV_ENDO_2.fcsv", b.as_bytes()),
    ];
    let (_, set) = read_study(&files, &ContourOptions::default()).unwrap();
    assert_eq!(set.contours.len(), 2);
    assert_eq!(set.landmarks.len(), 4);
}

/// The app's scene rule (`web/src/io/slicerScene.ts`, `namesWall`) names the same lists as
/// contours: these names and points are its vitest case's.
#[test]
fn a_list_named_after_a_wall_is_a_contour_whatever_its_size() {
    let three: Vec<Vec3> = (0..3)
        .map(|k| {
            let k = f64::from(k);
            Vec3::new(10.0 * k.cos(), 10.0 * k.sin(), 12.0 * k)
        })
        .collect();
    let is = |name: &str| point_list_is_contour(name, &[], &three);
    assert!(!is("F"));
    for wall in [
        "LV_ENDO_s3",
        "lvendo 4",
        "RV free wall",
        "rv-septum",
        "Left epicardium",
        "RVfreewall",
        "lvepi",
    ] {
        assert!(is(wall), "{wall}");
    }
    for other in ["LV septum", "LV 3", "endocardium", "LV endo apex", "lvx"] {
        assert!(!is(other), "{other}");
    }
    assert!(!point_list_is_contour("LV_ENDO", &[], &[]));
}
