//! The apex floor through the binary (sessions 13-14; the default since session 14): an apex no
//! long-axis curve reaches is floored at the slices' taper tip (`pipeline::apex_floor`, the dome
//! model of `pipeline::dome`, on crescents `pipeline::crescent`), `--no-apex-floor` leaves it to
//! the paper's extrapolation, and
//! `--apex-floor` (the default) is still accepted. Where a long-axis curve reaches the apex the
//! switch must change nothing but the header; on short-axis-only stacks (an ellipsoidal LV, and a
//! simulated acquisition of a real LV shape, and of a real RV crescent) the report says the floor
//! was placed and the mesh ends nearer the truth's apex, while `--no-apex-floor` gives the mesh of
//! before.

mod common;
use common::{bin, data, ellipsoid_lv_csv as lv_csv, run, scratch};
use heartmesh_core::geometry::{centroid, Vec3};
use heartmesh_core::io;

/// An OBJ as written: its header (`#` lines) and its vertex and face lines.
struct Obj {
    header: String,
    body: Vec<String>,
}

/// Runs reconstruct on `input` with `extra` flags: the OBJ and the report.
fn reconstruct_file(
    dir: &std::path::Path,
    input: &std::path::Path,
    extra: &[&str],
) -> (Obj, serde_json::Value) {
    let stem = format!(
        "{}{}",
        input.file_stem().and_then(|s| s.to_str()).unwrap_or("in"),
        extra.join("")
    );
    let out = dir.join(format!("{stem}.obj"));
    let report = dir.join(format!("{stem}.json"));
    let (code, _, err) = run(bin()
        .args(["reconstruct", input.to_str().unwrap(), "-o"])
        .arg(&out)
        .arg("--report")
        .arg(&report)
        .arg("--quiet")
        .args(extra));
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&out).unwrap();
    let (header, body): (Vec<&str>, Vec<&str>) = text.lines().partition(|l| l.starts_with('#'));
    let obj = Obj {
        header: header.join("\n"),
        body: body.into_iter().map(str::to_string).collect(),
    };
    let rep = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    (obj, rep)
}

/// `reconstruct_file` on `lv_csv(lax)`.
fn reconstruct(dir: &std::path::Path, lax: bool, extra: &[&str]) -> (Obj, serde_json::Value) {
    let file = dir.join(format!("lv-{lax}.csv"));
    std::fs::write(&file, lv_csv(lax)).unwrap();
    reconstruct_file(dir, &file, extra)
}

/// Lowest z of an OBJ's vertices (mm).
fn lowest(obj: &Obj) -> f64 {
    obj.body
        .iter()
        .filter_map(|l| l.strip_prefix("v "))
        .filter_map(|l| l.split_whitespace().nth(2)?.parse::<f64>().ok())
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn apex_floor_changes_nothing_where_a_long_axis_curve_reaches_the_apex() {
    let dir = scratch("apex-floor-lax");
    let (floored, rep) = reconstruct(&dir, true, &[]);
    let (plain, rep_plain) = reconstruct(&dir, true, &["--no-apex-floor"]);
    let (again, _) = reconstruct(&dir, true, &["--apex-floor"]);
    assert_eq!(plain.body, floored.body);
    assert_eq!(again.body, floored.body);
    // Placed nowhere, on or off; the parameters say which ran.
    for r in [&rep, &rep_plain] {
        assert!(
            r["end_caps"].get("apex_floor").is_none(),
            "{}",
            r["end_caps"]
        );
    }
    assert_eq!(rep["parameters"]["apex_floor"], true);
    assert_eq!(rep_plain["parameters"]["apex_floor"], false);
    // Long-axis curves reach the base: its lid lies where they stop, not at a ceiling.
    assert!(rep["end_caps"].get("base_ceiling").is_none());
    // The header names it only where it differs from the default (default headers keep their
    // bytes), as it names the other switches.
    assert!(!floored.header.contains("apex_floor"), "{}", floored.header);
    assert_eq!(again.header, floored.header);
    assert!(
        plain.header.contains("\"apex_floor\":false"),
        "{}",
        plain.header
    );
}

#[test]
fn apex_floor_on_a_short_axis_only_file() {
    let dir = scratch("apex-floor-sax");
    let (plain, rep) = reconstruct(&dir, false, &["--no-apex-floor"]);
    let (floored, rep_floored) = reconstruct(&dir, false, &[]);
    let (again, _) = reconstruct(&dir, false, &["--apex-floor"]);
    assert_eq!(again.body, floored.body);
    assert_eq!(rep["end_caps"]["apex"], false);
    assert!(rep["end_caps"].get("apex_floor").is_none());
    assert_eq!(rep_floored["end_caps"]["apex"], true);
    assert_eq!(rep_floored["end_caps"]["apex_floor"], true);
    // No long-axis curve reaches the base: it gets the ceiling one slice spacing out, and the
    // report says so (the app does not flag that overrun as extrapolated).
    assert_eq!(rep["end_caps"]["base"], true);
    assert_eq!(rep["end_caps"]["base_ceiling"], true);
    assert_eq!(rep_floored["end_caps"]["base_ceiling"], true);
    // One floor point more than the base's lid.
    assert_eq!(
        rep_floored["end_caps"]["points"].as_u64(),
        rep["end_caps"]["points"].as_u64().map(|n| n + 1)
    );
    // The ellipsoid's apex is z = -60, 12 mm below the apical ring (z = -48). Without the floor
    // the paper's extrapolation stops 3.45 mm short of it. The session-13 paraboloid through the
    // two apical rings (radius 15 at z = -48, 18.63 at z = -40: 8 x 225 / 122.2 = 14.7 mm below)
    // pulled the mesh 2.6 mm past it, to z = -62.6; the dome model's quadric, fitted to the four
    // apical rings of an ellipsoid, is exact (`pipeline::dome`), and the mesh ends within 0.06 mm
    // of the apex: asserted within 0.5 mm either way.
    let (low, low_floored) = (lowest(&plain), lowest(&floored));
    assert!(low > -60.0 + 3.0, "the extrapolation stops short: {low}");
    assert!(
        (low_floored + 60.0).abs() < 0.5,
        "apex error: {}",
        low_floored + 60.0
    );
}

/// The short-axis stack's normal, from apex to base (the rings grow towards the base), and the
/// height of its lowest contour point along it.
fn stack_axis(contours: &[heartmesh_core::contours::Contour]) -> (Vec3, f64) {
    let ring = |c: &heartmesh_core::contours::Contour| c.points().copied().collect::<Vec<Vec3>>();
    let first = ring(&contours[0]);
    let n = first.len();
    let normal = (first[n / 3] - first[0])
        .cross(&(first[2 * n / 3] - first[0]))
        .normalize();
    let (height, radius): (Vec<f64>, Vec<f64>) = contours
        .iter()
        .map(|c| {
            let r = ring(c);
            let m = centroid(&r);
            let radius = r.iter().map(|p| (p - m).norm()).sum::<f64>() / r.len() as f64;
            (m.dot(&normal), radius)
        })
        .unzip();
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let (hm, rm) = (mean(&height), mean(&radius));
    let trend: f64 = height
        .iter()
        .zip(&radius)
        .map(|(h, r)| (h - hm) * (r - rm))
        .sum();
    let axis = if trend < 0.0 { -normal } else { normal };
    let lowest = contours
        .iter()
        .flat_map(|c| c.points())
        .map(|p| p.dot(&axis))
        .fold(f64::INFINITY, f64::min);
    (axis, lowest)
}

/// Lowest height along `axis` of a mesh file's vertices (mm).
fn lowest_along(path: &std::path::Path, axis: &Vec3) -> f64 {
    let bytes = std::fs::read(path).unwrap();
    let data = io::read_mesh(path.to_str().unwrap(), &bytes).unwrap();
    data.mesh
        .positions
        .iter()
        .map(|p| p.dot(axis))
        .fold(f64::INFINITY, f64::min)
}

/// A simulated short-axis-only acquisition at the defaults (session 14's decision): the spasm LV
/// endocardium sliced every 8 mm with no long-axis view, whose apex lies 3.25 mm below the apical
/// slice. At the defaults the report says the floor was placed, and the mesh ends 0.31 mm short
/// of the truth's apex (along the slices' normal); with `--no-apex-floor` 1.16 mm short, exactly
/// the mesh main's binary wrote before the floor became the default (its vertex and face lines
/// compared byte for byte when this test was written; -1.16 mm measured with that binary).
/// Asserted: within 0.6 mm at the defaults, -1.16 +- 0.05 mm without, the floor nearer.
#[test]
fn a_simulated_short_axis_only_lv_gets_the_floor_by_default() {
    let dir = scratch("apex-floor-sim");
    let truth = data("meshes/cardiomesh-spasm-LV_endo.obj");
    let csv = dir.join("spasm.csv");
    let (code, _, err) = run(bin()
        .args(["simulate", truth.to_str().unwrap(), "-o"])
        .arg(&csv)
        .args(["--lax", "0", "--sax-spacing", "8", "--quiet"]));
    assert_eq!(code, 0, "{err}");
    let (floored, rep) = reconstruct_file(&dir, &csv, &[]);
    let (plain, rep_plain) = reconstruct_file(&dir, &csv, &["--no-apex-floor"]);
    assert_eq!(rep["end_caps"]["apex_floor"], true, "{}", rep["end_caps"]);
    assert_eq!(rep["parameters"]["apex_floor"], true);
    assert!(rep_plain["end_caps"].get("apex_floor").is_none());
    assert_eq!(rep_plain["parameters"]["apex_floor"], false);
    assert_eq!(rep_plain["end_caps"]["apex"], false);
    assert_ne!(floored.body, plain.body);

    let set = io::read_contours("spasm.csv", &std::fs::read(&csv).unwrap()).unwrap();
    assert!(set.contours.iter().all(|c| c.id.starts_with("sax")));
    let (axis, data_lowest) = stack_axis(&set.contours);
    let truth_lowest = lowest_along(&truth, &axis);
    let below = data_lowest - truth_lowest;
    assert!((below - 3.25).abs() < 0.1, "truth {below:.2} mm below");
    // Apex error: + past the truth's apex, - short of it.
    let error = |stem: &str| truth_lowest - lowest_along(&dir.join(format!("{stem}.obj")), &axis);
    let (with, without) = (error("spasm"), error("spasm--no-apex-floor"));
    eprintln!("apex error: floor {with:+.2} mm, extrapolation {without:+.2} mm");
    assert!(with.abs() < 0.6, "with the floor: {with:+.2} mm");
    assert!(
        (without + 1.16).abs() < 0.05,
        "without the floor: {without:+.2} mm (main's binary: -1.16)"
    );
    assert!(with.abs() < without.abs());
}

/// Session 17 (docs/VALIDATION.md "Session 17: the apex floor on RV crescents"): the spasm RV
/// cavity (free wall + septum, planned on its LV's axis) sliced short-axis only, as the paired
/// study's reference run slices it (`experiment misalignment WALL+SEPTUM@LV --levels 0:0 --seeds 1
/// --lax 0`). Its apical ring is a compact blob under a long crescent, so the rings' area tapers
/// too slowly: session 14's floor ended the mesh 3.81 mm past the truth's apex. The floor now
/// takes the shallower tip of the rings' length times the root of their area: -0.13 mm; without
/// a floor the extrapolation stops 3.74 mm short. Asserted: within 0.5 mm with the floor, more
/// than 3 mm short without.
#[test]
fn a_simulated_short_axis_only_rv_crescent_is_not_floored_past_its_apex() {
    let dir = scratch("apex-floor-rv");
    let cavity = format!(
        "{}+{}@{}",
        data("meshes/cardiomesh-spasm-RV_endo.obj").display(),
        data("meshes/cardiomesh-spasm-LV_epi.obj").display(),
        data("meshes/cardiomesh-spasm-LV_endo.obj").display()
    );
    let mut error = Vec::new();
    for (tag, extra) in [("floor", None), ("plain", Some("--no-apex-floor"))] {
        let (code, _, err) = run(bin()
            .args(["experiment", "misalignment", &cavity, "-o"])
            .arg(&dir)
            .args(["--levels", "0:0", "--seeds", "1", "--lax", "0", "--quiet"])
            .args(["--tag", tag])
            .args(extra));
        assert_eq!(code, 0, "{err}");
        let text = std::fs::read_to_string(dir.join(format!("misalignment-{tag}.csv"))).unwrap();
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let row: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert!(lines.next().is_none(), "one run");
        let col = |name: &str| -> f64 {
            let i = header.iter().position(|h| *h == name).unwrap();
            row[i].parse().unwrap()
        };
        error.push(col("past_apex_mm") - col("truth_past_apex_mm"));
    }
    let (with, without) = (error[0], error[1]);
    eprintln!("spasm RV apex error: floor {with:+.2} mm, extrapolation {without:+.2} mm");
    assert!(
        with.abs() < 0.5,
        "with the floor: {with:+.2} mm (session 14: +3.81)"
    );
    assert!(without < -3.0, "without the floor: {without:+.2} mm");
}
