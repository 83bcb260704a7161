//! A cvi42 workspace through the session: the core reads it with its images (`io::cvi42`) and
//! its note on what it read comes first among the app's notes.

fn fixture() -> (Vec<u8>, Vec<(String, Vec<u8>)>) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../heartmesh-core/tests/data/cvi42-patient1");
    let wsx = std::fs::read(dir.join("Contours.cvi42wsx")).unwrap();
    let mut images: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir.join("dicom"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&p).unwrap())
        })
        .collect();
    images.sort();
    (wsx, images)
}

/// The session reads the workspace with its images: the four ventricular surfaces of biv-me
/// patient 1 at frame 0 (as `heartmesh info` reads them: 32 contours, 8 per surface), the core's
/// note first among the notes, its warnings on skipped types kept; frame 9 is read when asked for.
#[test]
fn the_session_loads_a_workspace_with_its_images_at_either_frame() {
    let (wsx, images) = fixture();
    let files: Vec<(&str, &[u8])> = images
        .iter()
        .map(|(n, b)| (n.as_str(), b.as_slice()))
        .collect();
    let mut s = crate::Session::new();
    let load = |s: &mut crate::Session, frame: Option<&str>| -> serde_json::Value {
        let json = s
            .load_with_views("Contours.cvi42wsx", &wsx, &files, frame.map(str::to_string))
            .unwrap();
        serde_json::from_str(&json).unwrap()
    };
    let points = |v: &serde_json::Value, surface: &str| -> (usize, u64) {
        let cs: Vec<_> = v["contours"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|c| c["surface"] == surface)
            .collect();
        let count = |c: &&serde_json::Value| -> u64 {
            c["pieces"]
                .as_array()
                .unwrap()
                .iter()
                .map(|p| p["count"].as_u64().unwrap())
                .sum()
        };
        (cs.len(), cs.iter().map(count).sum())
    };
    let first = load(&mut s, None);
    assert_eq!(points(&first, "LV_ENDO"), (8, 441));
    assert_eq!(points(&first, "LV_EPI"), (8, 416));
    // One point more on each RV surface than `heartmesh info` counts per surface: info counts
    // the points a run uses, after cleaning; its total (1791 in 32 contours) is of all read.
    assert_eq!(points(&first, "RV_ENDO"), (8, 473));
    assert_eq!(points(&first, "RV_EPI"), (8, 461));
    assert_eq!(first["contours"].as_array().unwrap().len(), 32);
    assert_eq!(first["timeFrames"]["frames"], serde_json::json!(["0", "9"]));
    let note = first["notes"][0].as_str().unwrap();
    assert!(
        note.starts_with(
            "workspace read with 110 DICOM images: contours on 17 of them, in 9 cine slices"
        ),
        "{note}"
    );
    let warnings = first["warnings"].to_string();
    assert!(warnings.contains("saPapMuscContour"), "{warnings}");
    assert!(
        warnings.contains("choose another with the Frame picker"),
        "{warnings}"
    );
    let nine = load(&mut s, Some("9"));
    assert_eq!(points(&nine, "LV_ENDO"), (7, 269));
    assert_eq!(nine["timeFrames"]["read"], serde_json::json!(["9"]));
}
