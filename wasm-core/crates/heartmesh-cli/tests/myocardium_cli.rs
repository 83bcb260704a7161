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
    // ... and its labels: the same regions, triangles and (within regions) folded edges as the
    // report, the regions' areas adding up to the mesh's.
    let back = info["regions"]["list"].as_array().unwrap();
    let read: Vec<(i64, &str, u64)> = back
        .iter()
        .map(|r| {
            let f = (
                r["label"].as_i64(),
                r["name"].as_str(),
                r["triangles"].as_u64(),
            );
            (f.0.unwrap(), f.1.unwrap(), f.2.unwrap())
        })
        .collect();
    assert_eq!(
        read,
        [
            (1, "epicardium", counts[0]),
            (2, "endocardium", counts[1]),
            (3, "base", counts[2])
        ]
    );
    let area: f64 = back.iter().map(|r| r["area_mm2"].as_f64().unwrap()).sum();
    assert!(
        (area - info["area_mm2"].as_f64().unwrap()).abs() < 1e-6,
        "{area}"
    );
    assert_eq!(
        info["regions"]["folded_edges_within"],
        rep["quality"]["folded_edges"]
    );
}

/// `convert` keeps the labels in every format that has a place for them and says that STL has
/// none; `info` words them.
#[test]
fn convert_keeps_the_regions_and_info_lists_them() {
    let dir = scratch("myocardium-convert");
    let vtk = dir.join("wall.vtk");
    let (rep, _) = wall(&patient1(), &vtk, &["--quiet"]);
    let counts: Vec<u64> = rep["regions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["triangles"].as_u64().unwrap())
        .collect();
    let mut from = vtk;
    for ext in ["ply", "obj", "vtp", "vtk"] {
        let out = dir.join(format!("converted-{ext}.{ext}"));
        let (code, said, err) =
            run(bin().args(["convert", from.to_str().unwrap(), out.to_str().unwrap()]));
        assert_eq!(code, 0, "{ext}: {err}");
        assert!(
            said.contains(", 3 regions (epicardium, endocardium, base)"),
            "{ext}: {said}"
        );
        let (code, text, err) = run(bin().args(["info", out.to_str().unwrap()]));
        assert_eq!(code, 0, "{ext}: {err}");
        let line = text
            .lines()
            .find(|l| l.contains("regions ("))
            .unwrap_or_else(|| panic!("{text}"));
        for (k, name) in ["epicardium", "endocardium", "base"].iter().enumerate() {
            let want = format!("{} {name} ({} triangles, ", k + 1, counts[k]);
            assert!(line.contains(&want), "{ext}: {line} lacks {want}");
        }
        assert!(
            line.ends_with(&format!(
                "; {} folded edges within them",
                rep["quality"]["folded_edges"]
            )),
            "{line}"
        );
        from = out;
    }
    let stl = dir.join("wall.stl");
    let (code, said, err) =
        run(bin().args(["convert", from.to_str().unwrap(), stl.to_str().unwrap()]));
    assert_eq!(code, 0, "{err}");
    assert!(!said.contains("regions"), "{said}");
    assert!(
        err.contains("STL has no place for region labels; the input's 3 regions (epicardium, endocardium, base) are left out"),
        "{err}"
    );
    let (_, info, _) = run(bin().args(["info", stl.to_str().unwrap(), "--json"]));
    let info: Value = serde_json::from_str(&info).unwrap();
    assert_eq!(info["regions"], Value::Null);
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
        (
            vec![
                data("contours/bivme-test-patient2/patient2-ED.csv")
                    .to_str()
                    .unwrap()
                    .into(),
                "-o".into(),
                out.into(),
                "--biventricular".into(),
            ],
            "a biventricular myocardium needs LV_ENDO, BIV_EPI and RV_ENDO contours; the file \
             has no BIV_EPI (the biventricular epicardium, made of LV_EPI and RV_EPI curves)",
        ),
        (
            vec![
                patient1(),
                "-o".into(),
                out.into(),
                "--rv-endo".into(),
                "RV_ENDO".into(),
            ],
            "add --biventricular",
        ),
        (
            vec![
                patient1(),
                "-o".into(),
                out.into(),
                "--biventricular".into(),
                "--rv-endo".into(),
                "lv_endo".into(),
            ],
            "--endo and --rv-endo name the same surface (lv_endo)",
        ),
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

/// `--biventricular`: patient 1's whole myocardium (the biventricular epicardium less both
/// cavities) as one closed solid with four regions, read back by `info`.
#[test]
fn biventricular_wall_has_four_regions_and_two_cavities() {
    let dir = scratch("myocardium-biv");
    let out = dir.join("biv.vtk");
    let (rep, err) = wall(&patient1(), &out, &["--biventricular"]);
    assert_eq!(rep["watertight"], true);
    assert_eq!(rep["endo_epi_crossings"], 0, "{err}");
    assert_eq!(rep["crossings"].as_array().unwrap().len(), 0);
    let names: Vec<&str> = rep["regions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        ["epicardium", "lv_endocardium", "rv_endocardium", "base"]
    );
    let cavities = rep["cavities"].as_array().unwrap();
    let ml = |k: usize| cavities[k]["volume_ml"].as_f64().unwrap();
    assert_eq!(cavities[1]["region"], "rv_endocardium");
    // Both cavities below the base: an adult's are 50-250 ml at end-diastole, each less than
    // its closed surface (which runs on to the lid).
    for (k, s) in [(0, "LV_ENDO"), (1, "RV_ENDO")] {
        let closed = rep["surfaces"][s]["volume_ml"].as_f64().unwrap();
        assert!(ml(k) > 50.0 && ml(k) < closed, "{s}: {} vs {closed}", ml(k));
    }
    assert!(rep["surfaces"]["BIV_EPI"]["watertight"] == true);
    assert_eq!(rep["cavity_volume_ml"].as_f64().unwrap(), ml(0));
    // More myocardium than the LV wall alone (the RV free wall), within adult bounds.
    let (lv_rep, _) = wall(&patient1(), &dir.join("lv.vtk"), &["--quiet"]);
    let (biv, lv) = (
        rep["wall_volume_ml"].as_f64().unwrap(),
        lv_rep["wall_volume_ml"].as_f64().unwrap(),
    );
    assert!(biv > 1.1 * lv && biv < 2.0 * lv, "{biv} vs {lv}");
    // The summary line and the file's own labels.
    let (code, said, err) = run(bin().args([
        "myocardium",
        &patient1(),
        "-o",
        out.to_str().unwrap(),
        "--biventricular",
    ]));
    assert_eq!(code, 0, "{err}");
    assert!(said.contains("biventricular myocardium"), "{said}");
    assert!(
        said.contains(&format!("cavities LV {:.1} ml, RV {:.1} ml", ml(0), ml(1))),
        "{said}"
    );
    let (_, info, _) = run(bin().args(["info", out.to_str().unwrap(), "--json"]));
    let info: Value = serde_json::from_str(&info).unwrap();
    let back: Vec<&str> = info["regions"]["list"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["name"].as_str().unwrap())
        .collect();
    assert_eq!(back, names);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.lines()
            .nth(1)
            .unwrap()
            .contains("biventricular myocardium of patient1-ED.csv (LV_ENDO + BIV_EPI + RV_ENDO)"),
        "{}",
        text.lines().nth(1).unwrap()
    );
}

/// The validation path for a biventricular model: `simulate LABEL=TRUTH ...` slices biv-me's
/// model of patient 1 (LV and RV cavities, biventricular epicardium) on ONE misaligned
/// acquisition, and `myocardium --biventricular` builds one solid from the file, with and
/// without breath-hold alignment, its wall volume near the model's (biv-me's model: 138.7 ml
/// 10 mm below the top slice, so a wall cut higher is larger, not smaller, and by less than a
/// quarter).
#[test]
fn a_simulated_misaligned_biventricular_file_gives_one_solid() {
    let d = scratch("biv-sim");
    let mesh = |name: &str| {
        data(&format!("meshes/bivme-patient1-ED-{name}-closed.obj"))
            .to_str()
            .unwrap()
            .to_string()
    };
    let csv = d.join("biv.csv");
    let csv = csv.to_str().unwrap();
    let (code, out, err) = run(bin().args([
        "simulate",
        &format!("LV_ENDO={}", mesh("LV_ENDO")),
        &format!("RV_ENDO={}", mesh("RV_ENDO")),
        &format!("BIV_EPI={}", mesh("EPI")),
        "-o",
        csv,
        "--misalign",
        "2,2",
        "--seed",
        "3",
    ]));
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("SAX + 3 LAX images"), "{out}");
    let text = std::fs::read_to_string(csv).unwrap();
    assert!(
        text.starts_with("contour,x,y,z,surface\n"),
        "{}",
        &text[..40]
    );
    // Every image is drawn for every surface it cuts, under one id per image and surface.
    for label in ["LV_ENDO", "RV_ENDO", "BIV_EPI"] {
        for image in ["sax05", "lax01", "lax03"] {
            assert!(
                text.contains(&format!("\n{image}_{label},")),
                "{image}_{label} missing"
            );
        }
    }
    for extra in [&[][..], &["--align-slices"][..]] {
        let args: Vec<&str> = ["--biventricular"]
            .into_iter()
            .chain(extra.iter().copied())
            .collect();
        let (rep, err) = wall(csv, &d.join("biv.vtk"), &args);
        let ml = rep["wall_volume_ml"].as_f64().unwrap();
        assert!((138.0..173.0).contains(&ml), "{extra:?}: {ml} ml\n{err}");
        assert_eq!(
            rep["crossings"].as_array().unwrap().len(),
            0,
            "{extra:?}: {rep}"
        );
        assert_eq!(rep["cavities"].as_array().unwrap().len(), 2);
        assert!(!err.contains("warning"), "{extra:?}: {err}");
    }
}

/// Several truths need a label each, labels must be labels and differ, and `--surface` cannot
/// name them too: exit 2, one line.
#[test]
fn simulate_refuses_unlabelled_or_clashing_surfaces() {
    let d = scratch("biv-sim-bad");
    let lv = data("meshes/bivme-patient1-ED-LV_ENDO-closed.obj");
    let lv = lv.to_str().unwrap();
    let rv = data("meshes/bivme-patient1-ED-RV_ENDO-closed.obj");
    let rv = rv.to_str().unwrap();
    let out = d.join("x.csv");
    let out = out.to_str().unwrap();
    for (args, says) in [
        (vec![lv.to_string(), rv.to_string()], "has no label"),
        (
            vec![format!("LV_ENDO={lv}"), format!("lv_endo={rv}")],
            "given twice",
        ),
        (
            vec![format!("LV ENDO={lv}"), format!("RV={rv}")],
            "no surface label",
        ),
        (
            vec![format!("LV_ENDO={lv}"), "RV=".into()],
            "no file after =",
        ),
        (
            vec![
                format!("LV_ENDO={lv}"),
                format!("RV_ENDO={rv}"),
                "--surface".into(),
                "X".into(),
            ],
            "not both",
        ),
    ] {
        let (code, _, err) = run(bin().arg("simulate").args(&args).args(["-o", out]));
        assert_eq!(code, 2, "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(!std::path::Path::new(out).exists());
    }
}

/// A surface whose sections close only far below the others' base (the spasm model's RV
/// endocardium is its free wall alone: no short-axis plane cuts it in one closed loop) does not
/// shorten the stack: the LV keeps every basal slice it gets alone, and the user is told the RV
/// has long-axis curves only.
#[test]
fn simulate_keeps_the_stack_of_the_planned_surface() {
    let d = scratch("sim-short-surface");
    let lv = data("meshes/cardiomesh-spasm-LV_endo.obj");
    let lv = lv.to_str().unwrap();
    let rv = data("meshes/cardiomesh-spasm-RV_endo.obj");
    let rv = rv.to_str().unwrap();
    let sax_ids = |path: &std::path::Path, suffix: &str| {
        let text = std::fs::read_to_string(path).unwrap();
        let mut ids: Vec<String> = text
            .lines()
            .skip(1)
            .filter_map(|l| l.split(',').next())
            .filter(|id| id.starts_with("sax") && id.ends_with(suffix))
            .map(str::to_string)
            .collect();
        ids.dedup();
        ids.len()
    };
    let alone = d.join("lv.csv");
    let (code, _, err) = run(bin().args(["simulate", lv, "-o", alone.to_str().unwrap()]));
    assert_eq!(code, 0, "{err}");
    let both = d.join("both.csv");
    let (code, _, err) = run(bin().args([
        "simulate",
        &format!("LV_ENDO={lv}"),
        &format!("RV_ENDO={rv}"),
        "-o",
        both.to_str().unwrap(),
    ]));
    assert_eq!(code, 0, "{err}");
    let lv_slices = sax_ids(&alone, "");
    assert!(lv_slices >= 5, "{lv_slices}");
    assert_eq!(sax_ids(&both, "_LV_ENDO"), lv_slices);
    assert_eq!(sax_ids(&both, "_RV_ENDO"), 0);
    assert!(
        err.contains("RV_ENDO: no short-axis slice cuts it in one closed loop"),
        "{err}"
    );
}
