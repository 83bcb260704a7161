//! `heartmesh myocardium`: the LV wall as one closed, labelled solid from a biventricular file,
//! in every mesh format, and the refusals a user meets with the wrong file or options.

mod common;
use common::{bin, data, run, scratch};
use serde_json::Value;

fn patient1() -> String {
    data("contours/bivme-example-patient1/patient1-ED.csv")
        .to_str()
        .unwrap()
        .to_string()
}

/// Runs `myocardium INPUT -o OUT --report OUT.json` (plus `extra`) and returns the report and
/// stderr.
fn wall(input: &str, out: &std::path::Path, extra: &[&str]) -> (Value, String) {
    let report = out.with_extension("json");
    let (code, _, err) = run(bin()
        .args([
            "myocardium",
            input,
            "-o",
            out.to_str().unwrap(),
            "--report",
            report.to_str().unwrap(),
        ])
        .args(extra));
    assert_eq!(code, 0, "{err}");
    let rep = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    (rep, err)
}

#[test]
fn patient1_gives_a_closed_labelled_wall() {
    let dir = scratch("myocardium-vtk");
    let out = dir.join("wall.vtk");
    let (rep, _) = wall(&patient1(), &out, &[]);
    assert_eq!(rep["watertight"], true);
    assert_eq!(rep["endo_epi_crossings"], 0);
    assert_eq!(rep["quality"]["self_intersections"], 0);
    let triangles = rep["triangles"].as_u64().unwrap();
    let regions = rep["regions"].as_array().unwrap();
    let names: Vec<&str> = regions
        .iter()
        .map(|r| r["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["epicardium", "endocardium", "base"]);
    let counts: Vec<u64> = regions
        .iter()
        .map(|r| r["triangles"].as_u64().unwrap())
        .collect();
    assert_eq!(counts.iter().sum::<u64>(), triangles);
    assert!(counts.iter().all(|&c| c > 50), "{counts:?}");
    // The wall's volume is the closed mesh's; the mass is 1.05 g/ml of it.
    let vol = rep["wall_volume_ml"].as_f64().unwrap();
    assert!((vol - rep["volume_ml"].as_f64().unwrap()).abs() < 1e-9);
    let mass = rep["myocardial_mass_g"].as_f64().unwrap();
    assert!((mass - 1.05 * vol).abs() < 1e-9);
    // An adult LV below its basal slice: 60-150 g, walls 4-12 mm on average.
    assert!((60.0..150.0).contains(&mass), "{mass}");
    let t = &rep["thickness_mm"];
    let mean_t = t["mean"].as_f64().unwrap();
    assert!((4.0..12.0).contains(&mean_t), "{t}");
    assert!(t["min"].as_f64().unwrap() >= 0.99, "{t}");
    // The cavity below the base is part of the closed LV_ENDO mesh's volume.
    let cavity = rep["cavity_volume_ml"].as_f64().unwrap();
    let endo_closed = rep["surfaces"]["LV_ENDO"]["volume_ml"].as_f64().unwrap();
    assert!(
        cavity > 0.5 * endo_closed && cavity < endo_closed,
        "{cavity} {endo_closed}"
    );
    // Each surface's own report, as reconstruct writes it.
    for s in ["LV_ENDO", "LV_EPI"] {
        let m = rep["surfaces"][s]["contour_to_mesh"]["mean"]
            .as_f64()
            .unwrap();
        assert!(m < 1.0, "{s}: {m}");
    }
    let n: f64 = rep["base_plane"]["normal"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap().powi(2))
        .sum();
    assert!((n - 1.0).abs() < 1e-12);

    // The file: one region value per triangle, in 1..=3, and the thickness per vertex.
    let text = std::fs::read_to_string(&out).unwrap();
    let cell = text.split("CELL_DATA").nth(1).unwrap();
    let values: Vec<i64> = cell
        .lines()
        .skip(3)
        .take(triangles as usize)
        .map(|l| l.trim().parse().unwrap())
        .collect();
    assert_eq!(values.len() as u64, triangles);
    for (id, want) in [(1, counts[0]), (2, counts[1]), (3, counts[2])] {
        assert_eq!(values.iter().filter(|&&v| v == id).count() as u64, want);
    }
    assert!(text.contains("SCALARS thickness double 1"));

    // `info` reads the wall back as closed and outward, with the same volume.
    let (code, info, err) = run(bin().args(["info", out.to_str().unwrap(), "--json"]));
    assert_eq!(code, 0, "{err}");
    let info: Value = serde_json::from_str(&info).unwrap();
    assert_eq!(info["watertight"], true);
    assert!((info["volume_ml"].as_f64().unwrap() - vol).abs() < 1e-3);
}

#[test]
fn obj_groups_name_the_regions_and_every_format_is_closed() {
    let dir = scratch("myocardium-formats");
    let (rep, _) = wall(&patient1(), &dir.join("wall.obj"), &["--quiet"]);
    let text = std::fs::read_to_string(dir.join("wall.obj")).unwrap();
    let groups: Vec<&str> = text.lines().filter(|l| l.starts_with("g ")).collect();
    assert_eq!(groups, ["g epicardium", "g endocardium", "g base"]);
    let volume = rep["wall_volume_ml"].as_f64().unwrap();
    for ext in ["stl", "ply", "vtp"] {
        let out = dir.join(format!("wall.{ext}"));
        let (r, _) = wall(&patient1(), &out, &["--quiet"]);
        assert_eq!(r["wall_volume_ml"].as_f64().unwrap(), volume, "{ext}");
        let (code, info, err) = run(bin().args(["info", out.to_str().unwrap(), "--json"]));
        assert_eq!(code, 0, "{ext}: {err}");
        let info: Value = serde_json::from_str(&info).unwrap();
        assert_eq!(info["watertight"], true, "{ext}");
        assert!(
            (info["volume_ml"].as_f64().unwrap() - volume).abs() / volume < 1e-4,
            "{ext}"
        );
    }
}

#[test]
fn the_minimum_thickness_can_be_raised_or_turned_off() {
    let dir = scratch("myocardium-thickness");
    let (off, _) = wall(
        &patient1(),
        &dir.join("off.obj"),
        &["--min-thickness", "off", "--quiet"],
    );
    assert_eq!(off["endocardium_moved"]["vertices"], 0);
    assert_eq!(off["endocardium_moved"]["min_thickness_mm"], Value::Null);
    let thinnest = off["thickness_mm"]["min"].as_f64().unwrap();
    // Asking for more than the thinnest place moves the endocardium there, and says so.
    let want = (thinnest + 1.0).min(10.0);
    let (thick, err) = wall(
        &patient1(),
        &dir.join("thick.obj"),
        &["--min-thickness", &format!("{want}")],
    );
    let moved = thick["endocardium_moved"]["vertices"].as_u64().unwrap();
    assert!(moved > 0, "{thick}");
    assert!(err.contains("endocardial vert"), "{err}");
    assert!(thick["thickness_mm"]["min"].as_f64().unwrap() > thinnest + 0.5);
    assert!(thick["wall_volume_ml"].as_f64().unwrap() > off["wall_volume_ml"].as_f64().unwrap());
    assert_eq!(thick["watertight"], true);
}

#[test]
fn wrong_files_and_options_are_refused_with_one_line() {
    let dir = scratch("myocardium-refusals");
    let out = dir.join("w.obj");
    let out = out.to_str().unwrap();
    let surfco = data("contours/surfco-example.csv");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec![surfco.to_str().unwrap().into(), "-o".into(), out.into()],
            "needs LV_ENDO and LV_EPI",
        ),
        (
            vec![
                patient1(),
                "-o".into(),
                out.into(),
                "--surface".into(),
                "LV_ENDO".into(),
            ],
            "not --surface",
        ),
        (
            vec![
                patient1(),
                "-o".into(),
                out.into(),
                "--min-thickness".into(),
                "20".into(),
            ],
            "from 0 to 10",
        ),
        (
            vec![
                patient1(),
                "-o".into(),
                out.into(),
                "--epi".into(),
                "LV_ENDO".into(),
            ],
            "the same surface",
        ),
        (
            vec![
                patient1(),
                "-o".into(),
                out.into(),
                "--epi".into(),
                "XX".into(),
            ],
            "no XX",
        ),
        (vec![patient1()], "needs -o"),
    ];
    for (args, says) in cases {
        let (code, _, err) = run(bin().arg("myocardium").args(&args));
        assert_eq!(code, 2, "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(says), "{args:?}: {err}");
    }
    assert!(!std::path::Path::new(out).exists());
    // Surfaces named the wrong way round: the run happens, the wall cannot be (exit 1).
    let (code, _, err) = run(bin().args([
        "myocardium",
        &patient1(),
        "-o",
        out,
        "--endo",
        "LV_EPI",
        "--epi",
        "LV_ENDO",
    ]));
    assert_eq!(code, 1, "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("swapped"), "{err}");
    assert!(!std::path::Path::new(out).exists());
}
