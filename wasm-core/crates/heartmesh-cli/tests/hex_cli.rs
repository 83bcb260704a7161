//! `myocardium --hex-mesh`: the LV wall as layers of hexahedra for simulation, on the real
//! biv-me patient 1: the file's structure read back (points, cells, types, arrays), its volume
//! against the wall solid's, no inverted cell, every AHA segment; the layout and layer options;
//! and the refusals, before any run.

mod common;
use common::{bin, data, run, scratch};
use serde_json::Value;
use std::path::Path;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The legacy file's blocks: (points, cells as point lists, cell types, named arrays).
struct Grid {
    points: usize,
    coords: Vec<[f64; 3]>,
    cells: Vec<Vec<usize>>,
    types: Vec<u8>,
    arrays: Vec<(String, Vec<f64>)>,
    vectors: Vec<(String, Vec<[f64; 3]>)>,
}

/// Three numbers of one line.
fn triple(line: &str) -> [f64; 3] {
    let x: Vec<f64> = line
        .split_whitespace()
        .map(|c| c.parse().unwrap())
        .collect();
    [x[0], x[1], x[2]]
}

fn read_grid(path: &Path) -> Grid {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let mut grid = Grid {
        points: 0,
        coords: Vec::new(),
        cells: Vec::new(),
        types: Vec::new(),
        arrays: Vec::new(),
        vectors: Vec::new(),
    };
    assert_eq!(lines.next(), Some("# vtk DataFile Version 3.0"));
    let count_of = |line: &str, key: &str| -> Option<usize> {
        line.strip_prefix(key)?
            .split_whitespace()
            .next()?
            .parse()
            .ok()
    };
    let mut block = 0;
    while let Some(line) = lines.next() {
        if let Some(n) = count_of(line, "POINTS ") {
            grid.points = n;
            grid.coords = lines.by_ref().take(n).map(triple).collect();
        } else if let Some(n) = count_of(line, "CELLS ") {
            for _ in 0..n {
                let ids: Vec<usize> = lines
                    .next()
                    .unwrap()
                    .split_whitespace()
                    .map(|v| v.parse().unwrap())
                    .collect();
                assert_eq!(ids[0], ids.len() - 1);
                grid.cells.push(ids[1..].to_vec());
            }
        } else if let Some(n) = count_of(line, "CELL_TYPES ") {
            grid.types = lines.by_ref().take(n).map(|v| v.parse().unwrap()).collect();
        } else if let Some(n) = count_of(line, "POINT_DATA ") {
            block = n;
        } else if let Some(n) = count_of(line, "CELL_DATA ") {
            block = n;
        } else if let Some(rest) = line.strip_prefix("VECTORS ") {
            let name = rest.split_whitespace().next().unwrap().to_string();
            let values = lines.by_ref().take(block).map(triple).collect();
            grid.vectors.push((name, values));
        } else if let Some(rest) = line.strip_prefix("SCALARS ") {
            let name = rest.split_whitespace().next().unwrap().to_string();
            assert_eq!(lines.next(), Some("LOOKUP_TABLE default"));
            let values = lines
                .by_ref()
                .take(block)
                .map(|v| v.parse().unwrap())
                .collect();
            grid.arrays.push((name, values));
        }
    }
    grid
}

fn array<'a>(g: &'a Grid, name: &str) -> &'a [f64] {
    &g.arrays.iter().find(|(n, _)| n == name).unwrap().1
}

fn myocardium(dir: &Path, extra: &[&str]) -> (Value, Grid, String) {
    let input = data("contours/bivme-example-patient1/GPFile_000.txt");
    let [wall, report, hex] = ["wall.vtk", "wall.json", "hex.vtk"].map(|f| dir.join(f));
    let mut args = vec![
        "myocardium",
        s(&input),
        "-o",
        s(&wall),
        "--report",
        s(&report),
        "--hex-mesh",
        s(&hex),
    ];
    args.extend_from_slice(extra);
    let (code, out, err) = run(bin().args(&args));
    assert_eq!(code, 0, "{err}");
    let rep: Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    (rep, read_grid(&hex), out)
}

#[test]
fn patient1s_wall_as_hexahedra() {
    let dir = scratch("hex-patient1");
    let (rep, g, out) = myocardium(&dir, &[]);
    let h = &rep["hex_mesh"];
    // 24 rings x 48 points + the apex, 4 layers of points; 48 wedges and 23 x 48 hexahedra a layer.
    assert_eq!(g.points, 4 * (24 * 48 + 1));
    assert_eq!(g.cells.len(), 3 * 48 * 24);
    assert_eq!(g.types.iter().filter(|&&t| t == 13).count(), 3 * 48);
    assert_eq!(g.types.iter().filter(|&&t| t == 12).count(), 3 * 23 * 48);
    for (c, t) in g.cells.iter().zip(&g.types) {
        assert_eq!(c.len(), if *t == 12 { 8 } else { 6 });
        assert!(c.iter().all(|&i| i < g.points));
    }
    assert_eq!(h["hexahedra"], 3 * 23 * 48);
    assert_eq!(h["inverted_cells"], 0, "{h}");
    // Patient 1's wall is thicker than 1 mm along every ray: no endocardial vertex moved.
    assert_eq!(h["endocardium_moved"], 0, "{h}");
    assert!(h["min_scaled_jacobian"].as_f64().unwrap() > 0.0, "{h}");
    // The cells fill the wall: their volume within 1 % of the solid's (cut at the same base).
    let (v, wall) = (
        h["volume_ml"].as_f64().unwrap(),
        rep["wall_volume_ml"].as_f64().unwrap(),
    );
    assert!((v - wall).abs() < 0.01 * wall, "{v} vs {wall} ml");
    // Coordinates: transmural 0 then 1 on the outer layer, longitudinal 0 at the apex and 1 on
    // the base ring, circumferential from 0 to 352.5 degrees.
    let t = array(&g, "transmural");
    assert_eq!((t[0], t[g.points - 1]), (0.0, 1.0));
    let l = array(&g, "longitudinal");
    assert_eq!((l[0], l[24 * 48]), (0.0, 1.0));
    let c = array(&g, "circumferential_deg");
    assert_eq!(c.iter().cloned().fold(0.0, f64::max), 352.5);
    let segments = array(&g, "aha_segment");
    assert_eq!(segments.len(), g.cells.len());
    for k in 1..=17 {
        assert!(segments.contains(&(k as f64)), "segment {k}");
    }
    assert!(
        out.contains("hex.vtk: 3312 hexahedra + 144 wedges in 3 layers"),
        "{out}"
    );
    // Fibres: unit vectors in the wall (across the sheet), turning through it from a
    // right-handed helix at the endocardium to a left-handed one at the epicardium.
    let vectors = |name: &str| &g.vectors.iter().find(|(n, _)| n == name).unwrap().1;
    let (fibre, sheet) = (vectors("fibre"), vectors("sheet"));
    assert_eq!((fibre.len(), sheet.len()), (g.points, g.points));
    let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    for (f, s) in fibre.iter().zip(sheet) {
        assert!((dot(f, f) - 1.0).abs() < 1e-9 && (dot(s, s) - 1.0).abs() < 1e-9);
        assert!(dot(f, s).abs() < 1e-9);
    }
    assert_eq!(h["helix_deg"], serde_json::json!([60.0, -60.0]));
    // The fibre's component along the long axis: up at the endocardium, down at the
    // epicardium, on a mid-ventricular ring (ring 16), every vertex round it.
    let n: Vec<f64> = rep["base_plane"]["normal"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let n = [n[0], n[1], n[2]];
    let per_layer = 24 * 48 + 1;
    for j in 0..48 {
        let v = 1 + 15 * 48 + j;
        let (endo, epi) = (dot(&fibre[v], &n), dot(&fibre[3 * per_layer + v], &n));
        assert!(endo > 0.5 && epi < -0.5, "vertex {j}: {endo:.2} / {epi:.2}");
    }
}

#[test]
fn the_layout_and_the_layers_shape_the_cells() {
    let dir = scratch("hex-layers");
    let (rep, g, _) = myocardium(
        &dir,
        &[
            "--hex-layout",
            "8x16",
            "--layers",
            "1",
            "--helix-angles",
            "50,-70",
            "--quiet",
        ],
    );
    assert_eq!(
        rep["hex_mesh"]["helix_deg"],
        serde_json::json!([50.0, -70.0])
    );
    assert_eq!(g.points, 2 * (8 * 16 + 1));
    assert_eq!(g.cells.len(), 8 * 16);
    assert_eq!(rep["hex_mesh"]["layers"], 1);
    // Coarser cells chord the surfaces more: still within 5 % of the wall.
    let (v, wall) = (
        rep["hex_mesh"]["volume_ml"].as_f64().unwrap(),
        rep["wall_volume_ml"].as_f64().unwrap(),
    );
    assert!((v - wall).abs() < 0.05 * wall, "{v} vs {wall} ml");
}

#[test]
fn what_has_no_cells_is_refused_before_the_run() {
    let dir = scratch("hex-refused");
    let [wall, hex] = ["w.vtk", "h.vtk"].map(|f| dir.join(f));
    let refused = |input: &Path, extra: &[&str], says: &str| {
        let mut args = vec!["myocardium", s(input), "-o", s(&wall)];
        args.extend_from_slice(extra);
        let (code, _, err) = run(bin().args(&args));
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(says), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(
            !wall.exists() && !hex.exists(),
            "nothing written before a refusal"
        );
    };
    let p1 = data("contours/bivme-example-patient1/patient1-ED.csv");
    refused(
        &p1,
        &["--hex-mesh", s(&hex), "--biventricular"],
        "leave out --biventricular",
    );
    refused(&p1, &["--layers", "3"], "add --hex-mesh");
    refused(
        &p1,
        &["--hex-mesh", s(&hex), "--layers", "0"],
        "1-20 cells through the wall",
    );
    refused(
        &p1,
        &["--hex-mesh", s(&hex), "--hex-layout", "2x4"],
        "8-720 points",
    );
    refused(&p1, &["--hex-mesh", s(&dir.join("h.vtu"))], "(.vtk)");
    refused(
        &p1,
        &["--hex-mesh", s(&hex), "--helix-angles", "60"],
        "ENDO,EPI in degrees",
    );
    refused(
        &p1,
        &["--hex-mesh", s(&hex), "--helix-angles", "100,-60"],
        "from -90 to 90",
    );
    refused(&p1, &["--helix-angles", "60,-60"], "add --hex-mesh");
    // A file with LV contours only says nothing of where the septum is.
    let lv_only = dir.join("lv-only.csv");
    let text = std::fs::read_to_string(&p1).unwrap();
    let kept: Vec<&str> = text.lines().filter(|l| !l.contains("RV_")).collect();
    std::fs::write(&lv_only, kept.join("\n") + "\n").unwrap();
    refused(
        &lv_only,
        &["--hex-mesh", s(&hex)],
        "no RV_INSERT landmarks and no RV contours",
    );
}

/// `info hex.vtk` describes the volume mesh (it refused the unstructured grid before): the
/// counts, the volume and cell quality the report gave, the arrays and their ranges.
#[test]
fn info_describes_the_hexahedra() {
    let dir = scratch("hex-info");
    let (rep, _, _) = myocardium(&dir, &[]);
    let h = &rep["hex_mesh"];
    let hex = dir.join("hex.vtk");
    let (code, out, err) = run(bin().args(["info", s(&hex), "--json"]));
    assert_eq!(code, 0, "{err}");
    let info: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(info["format"], "VTK unstructured grid");
    assert_eq!(info["points"], h["points"]);
    assert_eq!(info["cells"], 3456);
    assert_eq!(info["measured_cells"], 3456);
    assert_eq!(info["inverted_cells"], 0);
    let close = |a: &Value, b: &Value| (a.as_f64().unwrap() - b.as_f64().unwrap()).abs();
    assert!(close(&info["volume_ml"], &h["volume_ml"]) < 1e-9, "{info}");
    assert!(close(&info["min_scaled_jacobian"], &h["min_scaled_jacobian"]) < 1e-9);
    let names: Vec<&str> = info["point_data"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "transmural",
            "longitudinal",
            "circumferential_deg",
            "fibre",
            "sheet"
        ]
    );
    let segments = &info["cell_data"][0];
    assert_eq!(segments["name"], "aha_segment");
    assert_eq!(
        (segments["min"].as_f64(), segments["max"].as_f64()),
        (Some(1.0), Some(17.0))
    );
    let fibre = &info["point_data"][3];
    assert_eq!(fibre["components"], 3);
    assert!(
        close(&fibre["min"], &serde_json::json!(1.0)) < 1e-9,
        "unit fibres"
    );
    let (code, text, err) = run(bin().args(["info", s(&hex)]));
    assert_eq!(code, 0, "{err}");
    assert!(
        text.contains("3456 cells: 144 wedges, 3312 hexahedra")
            && text.contains("no inverted cell")
            && text.contains("cell data: aha_segment 1.000 to 17.000"),
        "{text}"
    );
    // A broken grid: one line naming the file and the problem, status 2.
    let bytes = std::fs::read_to_string(&hex).unwrap();
    let broken = dir.join("broken.vtk");
    std::fs::write(
        &broken,
        bytes.replacen("CELL_TYPES 3456", "CELL_TYPES 3455", 1),
    )
    .unwrap();
    let (code, _, err) = run(bin().args(["info", s(&broken)]));
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("broken.vtk"), "{err}");
}

/// `volumes --hex-meshes`: every phase's wall with the same points and cells, on ED's septum,
/// each point's displacement from ED; the ED wall is `myocardium --hex-mesh`'s of that phase.
#[test]
fn every_phase_of_a_study_as_hexahedra_with_its_displacement() {
    let dir = scratch("hex-study");
    let folder = data("contours/bivme-example-patient1");
    let (ed, es) = (folder.join("GPFile_000.txt"), folder.join("GPFile_009.txt"));
    let [hx, json] = ["hx", "v.json"].map(|f| dir.join(f));
    let (code, out, err) = run(bin().args([
        "volumes",
        s(&es),
        s(&ed),
        "--surface",
        "LV_ENDO,LV_EPI",
        "--hex-meshes",
        s(&hx),
        "--layers",
        "2",
        "--json",
        s(&json),
    ]));
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("hexahedral walls 24x48x2"), "{out}");
    assert!(out.contains("2 of 2 phases"), "{out}");
    let doc: Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let h = &doc["hex_meshes"];
    assert_eq!(h["septum"]["phase"], "GPFile_000", "ED, not the first file");
    assert_eq!(h["layers"], 2);
    let [g_ed, g_es] =
        ["GPFile_000", "GPFile_009"].map(|p| read_grid(&hx.join(format!("{p}-LV_WALL.vtk"))));
    assert_eq!(g_ed.points, 3 * (24 * 48 + 1));
    assert_eq!(
        (g_ed.points, &g_ed.cells, &g_ed.types),
        (g_es.points, &g_es.cells, &g_es.types)
    );
    let vectors = |g: &Grid| {
        g.vectors
            .iter()
            .find(|(n, _)| n == "displacement")
            .unwrap()
            .1
            .clone()
    };
    assert!(vectors(&g_ed).iter().all(|d| *d == [0.0; 3]));
    let shift = vectors(&g_es);
    let mut sum = 0.0;
    for ((d, p), q) in shift.iter().zip(&g_es.coords).zip(&g_ed.coords) {
        for k in 0..3 {
            assert!((d[k] - (p[k] - q[k])).abs() < 1e-9);
        }
        sum += (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    }
    let mean = sum / shift.len() as f64;
    let entry = h["meshes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["phase"] == "GPFile_009")
        .unwrap();
    assert!((entry["displacement_mean_mm"].as_f64().unwrap() - mean).abs() < 1e-9);
    assert!(mean > 3.0, "the wall moves in systole: {mean} mm");
    assert_eq!(entry["summary"]["inverted_cells"], 0, "{entry}");
    // The ED wall is myocardium's of that file (its septum from the same landmarks).
    let single = dir.join("ed-hex.vtk");
    let (code, _, err) = run(bin().args([
        "myocardium",
        s(&ed),
        "-o",
        s(&dir.join("ed-wall.vtk")),
        "--hex-mesh",
        s(&single),
        "--layers",
        "2",
        "--quiet",
    ]));
    assert_eq!(code, 0, "{err}");
    let single = read_grid(&single);
    let worst = single
        .coords
        .iter()
        .zip(&g_ed.coords)
        .map(|(a, b)| (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max);
    println!(
        "hex study: ED wall vs myocardium's: {worst:.2e} mm; ES mean displacement {mean:.2} mm"
    );
    assert!(worst < 1e-9, "{worst} mm");
    // Refusals before any run.
    let refused = |extra: &[&str], says: &str| {
        let mut args = vec!["volumes", s(&ed), s(&es)];
        args.extend_from_slice(extra);
        let (code, _, err) = run(bin().args(&args));
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(says), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
    };
    let other = dir.join("other");
    refused(&["--layers", "2"], "add --hex-meshes DIR");
    refused(
        &["--surface", "LV_ENDO", "--hex-meshes", s(&other)],
        "measure both",
    );
    refused(&["--hex-meshes", s(&other), "--layers", "0"], "--layers 0");
    assert!(!other.exists());
}
