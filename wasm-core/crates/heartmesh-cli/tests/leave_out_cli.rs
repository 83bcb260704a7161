//! `--leave-out ID[,ID...]` through the binary (session 31): the user leaves a contour out by id
//! (a slice drawn badly, a view of another phase). The mesh must be the one of the file without
//! that contour, the report and a note must say what was left out, a typo must fail with the ids
//! there are, and ids of other surfaces must leave those surfaces as they were.

mod common;
use common::{bin, data, mesh_lines, run, scratch};
use serde_json::Value;
use std::path::{Path, PathBuf};

const LAX: &str = "s09_LAX_LV_ENDOCARDIAL";

fn patient1() -> PathBuf {
    data("contours/bivme-example-patient1/patient1-ED.csv")
}

struct Run {
    code: i32,
    stderr: String,
    mesh: Vec<String>,
    report: Value,
}

fn reconstruct(dir: &Path, name: &str, input: &Path, extra: &[&str]) -> Run {
    let out = dir.join(format!("{name}.obj"));
    let report = dir.join(format!("{name}.json"));
    let (code, _, stderr) = run(bin()
        .arg("reconstruct")
        .arg(input)
        .arg("-o")
        .arg(&out)
        .arg("--report")
        .arg(&report)
        .args(extra));
    let report = std::fs::read_to_string(&report)
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .unwrap_or(Value::Null);
    Run {
        code,
        stderr,
        mesh: mesh_lines(&out),
        report,
    }
}

/// patient1-ED.csv without the rows of contour `id`.
fn without(dir: &Path, id: &str) -> PathBuf {
    cut(&patient1(), dir, id, &format!("without-{id}.csv"))
}

/// The contour file `src` without the rows of contour `id`, as `dir/name`.
fn cut(src: &Path, dir: &Path, id: &str, name: &str) -> PathBuf {
    let text = std::fs::read_to_string(src).unwrap();
    let kept: Vec<&str> = text
        .lines()
        .filter(|l| l.split(',').next() != Some(id))
        .collect();
    assert!(kept.len() < text.lines().count(), "{id} is in the file");
    let path = dir.join(name);
    std::fs::write(&path, kept.join("\n") + "\n").unwrap();
    path
}

/// Patient 1 with `args`: with `--leave-out LAX`, the file without LAX's rows, and the whole
/// file, each run to completion (asked, cut, all).
fn three_runs(name: &str, args: &[&str]) -> [Run; 3] {
    let dir = scratch(name);
    let asked = reconstruct(
        &dir,
        "asked",
        &patient1(),
        &[args, &["--leave-out", LAX]].concat(),
    );
    let cut = reconstruct(&dir, "cut", &without(&dir, LAX), args);
    let all = reconstruct(&dir, "all", &patient1(), args);
    for r in [&asked, &cut, &all] {
        assert_eq!(r.code, 0, "{}", r.stderr);
    }
    [asked, cut, all]
}

/// The 1-based line of the first row of contour `id` in patient1-ED.csv.
fn first_line(id: &str) -> usize {
    let text = std::fs::read_to_string(patient1()).unwrap();
    1 + text
        .lines()
        .position(|l| l.split(',').next() == Some(id))
        .unwrap()
}

#[test]
fn a_contour_left_out_gives_the_mesh_of_the_file_without_it() {
    let [asked, cut, all] = three_runs("leave-out-same-mesh", &["--surface", "LV_ENDO"]);
    assert_eq!(asked.mesh, cut.mesh);
    assert_ne!(asked.mesh, all.mesh, "the long-axis curve shapes the mesh");
    let vol = |r: &Run| r.report["volume_ml"].as_f64().unwrap();
    assert!((vol(&asked) - vol(&cut)).abs() < 1e-9);
    assert!(
        (vol(&asked) - vol(&all)).abs() > 0.1,
        "{} vs {}",
        vol(&asked),
        vol(&all)
    );

    // The report: set_aside names it with its line and the reason and says how far the mesh
    // passes from it (here 1.8 mm on average: the curve disagrees with the rest, which is why the
    // mesh changes), the parameters list it, and the distances are to the contours used (7 of 8).
    let line = first_line(LAX);
    let entry = &asked.report["set_aside"][0];
    assert_eq!(asked.report["set_aside"].as_array().unwrap().len(), 1);
    assert_eq!(entry["id"], LAX);
    assert_eq!(entry["line"], line);
    assert_eq!(entry["reason"], "by_user");
    let mm = |k: &str| entry[k].as_f64().unwrap();
    assert!(
        mm("median") <= mm("max") && mm("mean") <= mm("max"),
        "{entry}"
    );
    assert!(mm("mean") > 0.5 && mm("max") < 20.0, "{entry}");
    assert_eq!(
        asked.report["parameters"]["leave_out"],
        serde_json::json!([LAX])
    );
    let per = asked.report["per_contour"].as_array().unwrap();
    assert_eq!(per.len(), 7);
    assert!(per.iter().all(|c| c["id"] != LAX));
    assert_eq!(all.report["per_contour"].as_array().unwrap().len(), 8);
    assert!(all.report.get("set_aside").is_none());
    assert!(all.report["parameters"].get("leave_out").is_none());
    // A note names it, once.
    let note = format!(
        "--leave-out: \"{LAX}\" (line {line}, the mesh {:.2} mm from it on average, {:.2} mm at \
         most) is left out of the reconstruction",
        mm("mean"),
        mm("max")
    );
    assert_eq!(asked.stderr.matches(&note).count(), 1, "{}", asked.stderr);
    assert!(!all.stderr.contains("--leave-out"), "{}", all.stderr);
}

/// With the breath-hold alignment too: the contour left out shifts nothing (the alignment is of
/// the file without it), so the run is the one of the file without it, shifts and all.
#[test]
fn a_contour_left_out_does_not_move_the_alignment() {
    let [asked, cut, all] = three_runs(
        "leave-out-aligned",
        &["--surface", "LV_ENDO", "--align-slices"],
    );
    assert_eq!(asked.mesh, cut.mesh);
    assert_ne!(asked.mesh, all.mesh);
    for key in [
        "alignment",
        "crossing_residual_mm",
        "contour_to_mesh_as_given",
    ] {
        assert_eq!(asked.report[key], cut.report[key], "{key}");
    }
    assert_ne!(
        asked.report["alignment"], all.report["alignment"],
        "the curve moved the shifts"
    );
    assert_eq!(asked.report["set_aside"][0]["reason"], "by_user");
}

#[test]
fn ids_may_be_repeated_or_joined_by_commas() {
    let dir = scratch("leave-out-forms");
    let two = ["s02_SAX_LV_ENDOCARDIAL", LAX];
    let joined = reconstruct(
        &dir,
        "joined",
        &patient1(),
        &["--surface", "LV_ENDO", "--leave-out", &two.join(",")],
    );
    let repeated = reconstruct(
        &dir,
        "repeated",
        &patient1(),
        &[
            "--surface",
            "LV_ENDO",
            "--leave-out",
            two[0],
            "--leave-out",
            two[1],
        ],
    );
    assert_eq!(joined.code, 0, "{}", joined.stderr);
    assert_eq!(joined.mesh, repeated.mesh);
    let ids: Vec<&str> = joined.report["set_aside"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["id"].as_str().unwrap())
        .collect();
    assert_eq!(ids, two);
    assert_eq!(joined.report["per_contour"].as_array().unwrap().len(), 6);
    assert!(
        joined.stderr.contains("are left out of the reconstruction"),
        "{}",
        joined.stderr
    );
}

#[test]
fn an_unknown_id_fails_with_the_surfaces_ids() {
    let dir = scratch("leave-out-unknown");
    let r = reconstruct(
        &dir,
        "typo",
        &patient1(),
        &["--surface", "LV_ENDO", "--leave-out", "s09_LAX_LV_ENDO"],
    );
    assert_eq!(r.code, 2);
    assert_eq!(r.stderr.lines().count(), 1, "{}", r.stderr);
    assert!(r.stderr.contains("patient1-ED.csv"), "{}", r.stderr);
    assert!(
        r.stderr
            .contains("no contour \"s09_LAX_LV_ENDO\" to leave out"),
        "{}",
        r.stderr
    );
    assert!(r.stderr.contains(&format!("\"{LAX}\"")), "{}", r.stderr);
    assert!(r.mesh.is_empty(), "nothing written");
    // An empty id is a usage error naming the option.
    let (code, _, err) = run(bin()
        .arg("reconstruct")
        .arg(patient1())
        .args(["--surface", "LV_ENDO", "-o"])
        .arg(dir.join("e.obj"))
        .args(["--leave-out", "a,,b"]));
    assert_eq!(code, 2);
    assert!(err.contains("--leave-out: an empty contour id"), "{err}");
}

#[test]
fn leaving_out_all_but_one_contour_is_too_few() {
    let dir = scratch("leave-out-too-few");
    let ids: Vec<String> = ["s02", "s03", "s04", "s05", "s06"]
        .iter()
        .map(|s| format!("{s}_SAX_LV_ENDOCARDIAL"))
        .chain(["s08_LAX_LV_ENDOCARDIAL".to_string(), LAX.to_string()])
        .collect();
    let r = reconstruct(
        &dir,
        "one",
        &patient1(),
        &["--surface", "LV_ENDO", "--leave-out", &ids.join(",")],
    );
    assert_eq!(r.code, 2, "{}", r.stderr);
    assert!(
        r.stderr.contains("too few contours: 1 usable"),
        "{}",
        r.stderr
    );
}

#[test]
fn an_id_of_another_surface_leaves_this_one_as_it_was() {
    let dir = scratch("leave-out-other-surface");
    let plain = dir.join("plain");
    let asked = dir.join("asked");
    std::fs::create_dir_all(&plain).unwrap();
    std::fs::create_dir_all(&asked).unwrap();
    let a = reconstruct(&plain, "m", &patient1(), &["--surface", "all", "--quiet"]);
    let b = reconstruct(
        &asked,
        "m",
        &patient1(),
        &["--surface", "all", "--leave-out", LAX, "--quiet"],
    );
    assert_eq!((a.code, b.code), (0, 0), "{} {}", a.stderr, b.stderr);
    for surface in ["RV_ENDO", "LV_EPI", "RV_EPI"] {
        let name = format!("m-{surface}.obj");
        assert_eq!(
            mesh_lines(&plain.join(&name)),
            mesh_lines(&asked.join(&name)),
            "{surface} does not hold {LAX}"
        );
    }
    assert_ne!(
        mesh_lines(&plain.join("m-LV_ENDO.obj")),
        mesh_lines(&asked.join("m-LV_ENDO.obj"))
    );
}

#[test]
fn volumes_take_the_same_list() {
    let dir = scratch("leave-out-volumes");
    let json = dir.join("v.json");
    let (code, _, err) = run(bin()
        .arg("volumes")
        .arg(patient1())
        .args([
            "--surface",
            "LV_ENDO",
            "--leave-out",
            LAX,
            "--quiet",
            "--json",
        ])
        .arg(&json));
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&json).unwrap();
    let r = reconstruct(
        &dir,
        "r",
        &patient1(),
        &["--surface", "LV_ENDO", "--leave-out", LAX, "--quiet"],
    );
    let want = r.report["volume_ml"].as_f64().unwrap();
    let shown = format!("{want:.1}");
    // The volumes JSON holds the phase's LV_ENDO volume, equal to the reconstruction's.
    let v: Value = serde_json::from_str(&text).unwrap();
    let found = find_number(&v, want);
    assert!(found, "{want} ({shown}) not in {text}");
}

/// One list for every phase: an id only some phases have is left out of those and the others run
/// as they are (a view drawn at end-diastole only); an id no phase has fails before any run,
/// with the ids there are.
#[test]
fn volumes_leave_each_phase_its_own_ids() {
    let dir = scratch("leave-out-volumes-phases");
    let es = data("contours/bivme-example-patient1/patient1-ES.csv");
    let es_cut = cut(&es, &dir, LAX, "patient1-ES.csv");
    let json = dir.join("v.json");
    let volumes = |ids: &str| {
        run(bin()
            .arg("volumes")
            .arg(patient1())
            .arg(&es_cut)
            .args(["--surface", "LV_ENDO", "--leave-out", ids, "--quiet"])
            .arg("--json")
            .arg(&json))
    };
    let (code, _, err) = volumes(LAX);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let cell = |phase: &str| {
        v["volumes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["phase"] == phase)
            .and_then(|c| c["volume_ml"].as_f64())
            .unwrap()
    };
    let ed = reconstruct(
        &dir,
        "ed",
        &patient1(),
        &["--surface", "LV_ENDO", "--leave-out", LAX, "--quiet"],
    );
    let es = reconstruct(&dir, "es", &es_cut, &["--surface", "LV_ENDO", "--quiet"]);
    let volume = |r: &Run| r.report["volume_ml"].as_f64().unwrap();
    assert!((cell("patient1-ED") - volume(&ed)).abs() < 1e-9, "{v}");
    assert!((cell("patient1-ES") - volume(&es)).abs() < 1e-9, "{v}");
    // An id of no phase: status 2, one line naming it and the ids there are, before any run.
    let (code, out, err) = volumes(&format!("{LAX},s99_typo"));
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("no contour \"s99_typo\" to leave out"),
        "{err}"
    );
    assert!(err.contains("s02_SAX_LV_ENDOCARDIAL"), "{err}");
    assert!(out.is_empty(), "{out}");
}

/// `myocardium` takes the list as reconstruct does: its LV_ENDO is reconstruct's with the contour
/// left out (same volume, same distances from it), LV_EPI (which has no such id) is untouched, and
/// a note names it under its surface.
#[test]
fn myocardium_takes_the_same_list() {
    let dir = scratch("leave-out-myocardium");
    let report = dir.join("wall.json");
    let (code, _, err) = run(bin()
        .arg("myocardium")
        .arg(patient1())
        .arg("-o")
        .arg(dir.join("wall.vtk"))
        .arg("--report")
        .arg(&report)
        .args(["--leave-out", LAX]));
    assert_eq!(code, 0, "{err}");
    let wall: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let endo = &wall["surfaces"]["LV_ENDO"];
    let r = reconstruct(
        &dir,
        "r",
        &patient1(),
        &["--surface", "LV_ENDO", "--leave-out", LAX, "--quiet"],
    );
    assert_eq!(endo["set_aside"], r.report["set_aside"]);
    let volume = |v: &Value| v["volume_ml"].as_f64().unwrap();
    assert!((volume(endo) - volume(&r.report)).abs() < 1e-9);
    assert!(wall["surfaces"]["LV_EPI"].get("set_aside").is_none());
    let note = format!(
        "LV_ENDO: --leave-out: \"{LAX}\" (line {}, the mesh {:.2} mm from it on average",
        first_line(LAX),
        r.report["set_aside"][0]["mean"].as_f64().unwrap()
    );
    assert_eq!(err.matches(&note).count(), 1, "{err}");
}

/// `leave-one-out` takes reconstruct's parameter options, and with `--align-slices` its figure
/// for a contour is still `reconstruct --align-slices --leave-out` of it (each rebuild aligns the
/// file without the contour and measures it where its slice moved), where it differs from the
/// unaligned figure.
#[test]
fn leave_one_out_takes_the_parameters_and_the_alignment() {
    const RING: &str = "s04_SAX_LV_EPICARDIAL";
    let dir = scratch("leave-out-loo-aligned");
    let loo = |extra: &[&str]| -> Value {
        let (code, out, err) = run(bin()
            .arg("leave-one-out")
            .arg(patient1())
            .args(["--surface", "LV_EPI", "--json"])
            .args(extra));
        assert_eq!(code, 0, "{err}");
        let v: Value = serde_json::from_str(&out).unwrap();
        v["contours"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["id"] == RING)
            .unwrap()["stats"]
            .clone()
    };
    let aligned = loo(&["--align-slices"]);
    let plain = loo(&[]);
    let asked = reconstruct(
        &dir,
        "asked",
        &patient1(),
        &["--surface", "LV_EPI", "--align-slices", "--leave-out", RING],
    );
    assert_eq!(asked.code, 0, "{}", asked.stderr);
    for key in ["mean", "median", "max"] {
        let a = asked.report["set_aside"][0][key].as_f64().unwrap();
        let b = aligned[key].as_f64().unwrap();
        assert!(
            (a - b).abs() <= 1e-9 * b.abs().max(1.0),
            "{key}: {a} vs {b}"
        );
    }
    assert_ne!(aligned["mean"], plain["mean"]);
    // A parameter out of range is refused as reconstruct refuses it.
    let (code, _, err) = run(bin()
        .arg("leave-one-out")
        .arg(patient1())
        .args(["--iterations", "0"]));
    assert_eq!(code, 2);
    assert!(err.contains("--iterations 0 is out of range"), "{err}");
}

/// Whether `v` holds a number within 1e-9 of `want` anywhere.
fn find_number(v: &Value, want: f64) -> bool {
    match v {
        Value::Number(n) => n.as_f64().is_some_and(|x| (x - want).abs() < 1e-9),
        Value::Array(a) => a.iter().any(|x| find_number(x, want)),
        Value::Object(o) => o.values().any(|x| find_number(x, want)),
        _ => false,
    }
}

/// `info` lists each surface's ids by kind, the names `--leave-out` takes.
#[test]
fn info_lists_the_ids_leave_out_takes() {
    let (code, out, err) = run(bin().arg("info").arg(patient1()));
    assert_eq!(code, 0, "{err}");
    let lv = out
        .split("\nLV_ENDO:")
        .nth(1)
        .and_then(|s| s.split("\nLV_EPI:").next())
        .unwrap_or_else(|| panic!("{out}"));
    let sax: Vec<String> = (2..=6)
        .map(|k| format!("s{k:02}_SAX_LV_ENDOCARDIAL"))
        .collect();
    assert!(
        lv.contains(&format!("\n  short-axis: {}\n", sax.join(", "))),
        "{lv}"
    );
    assert!(
        lv.contains(&format!(
            "\n  long-axis: {LAX}, s08_LAX_LV_ENDOCARDIAL, s07_LAX_LV_ENDOCARDIAL\n"
        )),
        "{lv}"
    );
    let (code, out, _) = run(bin().arg("info").arg(patient1()).arg("--json"));
    assert_eq!(code, 0);
    let v: Value = serde_json::from_str(&out).unwrap();
    let lv = v["surfaces"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["surface"] == "LV_ENDO")
        .unwrap();
    assert_eq!(lv["ids"]["sax"], serde_json::json!(sax));
    assert_eq!(lv["ids"]["lax"].as_array().unwrap().len(), 3);
}

/// `leave-one-out --leave-out X`: X is out of every rebuild and not held out in turn; every other
/// contour is rebuilt without error (the rebuilds must not name X again: their contours lack it).
#[test]
fn leave_one_out_keeps_the_contours_left_out_out() {
    let (code, out, err) = run(bin().arg("leave-one-out").arg(patient1()).args([
        "--surface",
        "LV_ENDO",
        "--json",
        "--leave-out",
        LAX,
    ]));
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    let rows = v["contours"].as_array().unwrap();
    assert_eq!(rows.len(), 7);
    assert!(
        rows.iter().all(|c| c["id"] != LAX && c["error"].is_null()),
        "{v}"
    );
    let (code, out, _) =
        run(bin()
            .arg("leave-one-out")
            .arg(patient1())
            .args(["--surface", "LV_ENDO", "--json"]));
    assert_eq!(code, 0);
    let all: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(all["contours"].as_array().unwrap().len(), 8);
    // Without LAX the others are predicted from less: their held-out means are not all the same.
    assert_ne!(v["mean_of_means"], all["mean_of_means"]);
    // A contour left out by hand is a held-out contour: the report's distances from it to the
    // mesh are leave-one-out's figures for it (the same rebuild, the same measure).
    let held = all["contours"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["id"] == LAX)
        .unwrap();
    let dir = scratch("leave-out-held");
    let asked = reconstruct(
        &dir,
        "asked",
        &patient1(),
        &["--surface", "LV_ENDO", "--leave-out", LAX],
    );
    assert_eq!(asked.code, 0, "{}", asked.stderr);
    for key in ["mean", "median", "max"] {
        let a = asked.report["set_aside"][0][key].as_f64().unwrap();
        let b = held["stats"][key].as_f64().unwrap();
        assert!(
            (a - b).abs() <= 1e-9 * b.abs().max(1.0),
            "{key}: {a} vs {b}"
        );
    }
}
