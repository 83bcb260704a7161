//! Helpers shared by the CLI integration tests: the built binary, the shared data directory,
//! per-test scratch directories and the (status, stdout, stderr) triple every contract test reads.
#![allow(dead_code)] // each test crate uses a subset

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_heartmesh"))
}

/// `shared/data` is ../../../../shared/data from this crate in the main checkout (one level more
/// from a worktree): the nearest ancestor holding it.
pub fn data(rel: &str) -> PathBuf {
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = here
        .ancestors()
        .map(|a| a.join("shared/data"))
        .find(|d| d.join("README.md").is_file())
        .expect("shared/data not found above CARGO_MANIFEST_DIR");
    dir.join(rel)
}

/// A fresh scratch directory per test (named after the test crate, so suites running at the same
/// time never share one).
pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "heartmesh-{}-{}-{name}",
        env!("CARGO_CRATE_NAME"),
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Exit status (-1 when killed), stdout and stderr of a finished command.
pub fn run(cmd: &mut Command) -> (i32, String, String) {
    let Output {
        status,
        stdout,
        stderr,
    } = cmd.output().unwrap();
    (
        status.code().unwrap_or(-1),
        String::from_utf8_lossy(&stdout).into_owned(),
        String::from_utf8_lossy(&stderr).into_owned(),
    )
}

/// An ellipsoidal LV endocardium (semi-axes 25 and 60 mm) as canonical CSV: short-axis rings every
/// 8 mm from z = -48 up to its equator and, when `lax`, two long-axis curves through the apex
/// (open at the rim, as real long-axis curves are).
pub fn ellipsoid_lv_csv(lax: bool) -> String {
    use std::f64::consts::{PI, TAU};
    use std::fmt::Write;
    let mut out = String::from("contour,x,y,z,surface\n");
    for k in 0..7 {
        let z = -48.0 + 8.0 * k as f64;
        let r = 25.0 * (1.0 - (z / 60.0) * (z / 60.0)).sqrt();
        for i in 0..60 {
            let t = TAU * i as f64 / 60.0;
            let _ = writeln!(out, "sax{k},{},{},{z},LV_ENDO", r * t.cos(), r * t.sin());
        }
    }
    if lax {
        for (j, phi) in [0.3f64, 1.9].iter().enumerate() {
            for i in 0..=60 {
                let t = PI * i as f64 / 60.0; // from one rim through the apex
                let (u, z) = (25.0 * t.sin(), -60.0 * t.cos().abs());
                let side = if i <= 30 { 1.0 } else { -1.0 };
                let _ = writeln!(
                    out,
                    "lax{j},{},{},{z},LV_ENDO",
                    side * u * phi.cos(),
                    side * u * phi.sin()
                );
            }
        }
    }
    out
}

/// A mesh file's vertex and face lines, without its `#` header comments (which name the input
/// and parameters, so two runs on different files of one set of contours differ there only); an
/// empty list when the file is missing (a refused run).
pub fn mesh_lines(path: &Path) -> Vec<String> {
    std::fs::read_to_string(path)
        .unwrap_or_default()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(str::to_string)
        .collect()
}

/// The canonical CSV `input` (contour,x,y,z[,surface]) with every point moved: LV points (a
/// `surface` starting with LV_) by `lv`, the others by `other`.
pub fn moved_csv(
    input: &Path,
    out: &Path,
    lv: impl Fn(heartmesh_core::geometry::Vec3) -> heartmesh_core::geometry::Vec3,
    other: impl Fn(heartmesh_core::geometry::Vec3) -> heartmesh_core::geometry::Vec3,
) {
    let text = std::fs::read_to_string(input).unwrap();
    let mut lines = Vec::new();
    for line in text.lines() {
        let cells: Vec<&str> = line.split(',').collect();
        let xyz: Option<Vec<f64>> = cells
            .get(1..4)
            .and_then(|c| c.iter().map(|v| v.parse::<f64>().ok()).collect());
        match xyz {
            Some(p) => {
                let p = heartmesh_core::geometry::v3(p[0], p[1], p[2]);
                let q = if line.contains(",LV_") {
                    lv(p)
                } else {
                    other(p)
                };
                let mut c: Vec<String> = cells.iter().map(|c| c.to_string()).collect();
                c[1] = format!("{:.9}", q.x);
                c[2] = format!("{:.9}", q.y);
                c[3] = format!("{:.9}", q.z);
                lines.push(c.join(","));
            }
            None => lines.push(line.to_string()),
        }
    }
    std::fs::write(out, lines.join("\n") + "\n").unwrap();
}

/// A mesh file read back.
pub fn read_mesh_file(path: &Path) -> heartmesh_core::TriMesh {
    let name = path.to_str().unwrap();
    heartmesh_core::io::read_mesh(name, &std::fs::read(path).unwrap())
        .unwrap()
        .mesh
}

/// `reconstruct INPUT --surface LV_ENDO --anatomical-mesh` (its own septum) into `dir` as
/// NAME.obj, NAME.json, NAME-grid.vtk: (report, mesh, grid).
pub fn with_grid(
    input: &Path,
    dir: &Path,
    name: &str,
    extra: &[&str],
) -> (
    serde_json::Value,
    heartmesh_core::TriMesh,
    heartmesh_core::TriMesh,
) {
    let [out, report, grid] =
        [".obj", ".json", "-grid.vtk"].map(|e| dir.join(format!("{name}{e}")));
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let mut args: Vec<String> = vec![
        "reconstruct".into(),
        s(input),
        "--surface".into(),
        "LV_ENDO".into(),
        "-o".into(),
        s(&out),
        "--report".into(),
        s(&report),
        "--anatomical-mesh".into(),
        s(&grid),
        "--quiet".into(),
    ];
    args.extend(extra.iter().map(|a| a.to_string()));
    let (code, _, err) = run(bin().args(&args));
    assert_eq!(code, 0, "{err}");
    let rep = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    (rep, read_mesh_file(&out), read_mesh_file(&grid))
}

/// Asserts that `info --json`'s `surfaces` entry for each surface holds that many points.
pub fn assert_surface_points(info: &serde_json::Value, expected: &[(&str, u64)]) {
    for &(surface, points) in expected {
        let s = info["surfaces"]
            .as_array()
            .unwrap()
            .iter()
            .find(|s| s["surface"] == surface)
            .unwrap_or_else(|| panic!("{surface}: {info}"));
        assert_eq!(s["points"], points, "{surface}");
    }
}

/// LV ejection fraction (%) of `volumes INPUTS... --surface LV_ENDO --json`, and the phases' names.
pub fn lv_ef(inputs: &[String], dir: &Path) -> (f64, Vec<String>) {
    let json = dir.join("v.json");
    let (code, _, err) = run(bin().arg("volumes").args(inputs).args([
        "--surface",
        "LV_ENDO",
        "--json",
        json.to_str().unwrap(),
        "--quiet",
    ]));
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let phases = v["phases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            p.as_str()
                .map_or_else(|| p["name"].to_string(), str::to_string)
        })
        .collect();
    (v["function"][0]["ef_percent"].as_f64().unwrap(), phases)
}

/// A file or folder of the core's test data (`heartmesh-core/tests/data/<rel>`), as a path string.
pub fn core_data(rel: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../heartmesh-core/tests/data")
        .join(rel)
        .display()
        .to_string()
}

/// `reconstruct INPUTS... -o DIR/m.obj --report DIR/r.json EXTRA...`: (status, stderr, the
/// report when one was written).
pub fn reconstruct_report(
    inputs: &[String],
    extra: &[&str],
    dir: &Path,
) -> (i32, String, Option<serde_json::Value>) {
    let (mesh, json) = (dir.join("m.obj"), dir.join("r.json"));
    let _ = std::fs::remove_file(&json);
    let mut cmd = bin();
    cmd.arg("reconstruct")
        .args(inputs)
        .arg("-o")
        .arg(&mesh)
        .arg("--report")
        .arg(&json)
        .args(extra);
    let (code, _, err) = run(&mut cmd);
    let report = json
        .exists()
        .then(|| serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap());
    (code, err, report)
}

/// A ZIP archive of `files` (name, contents), stored uncompressed, as a packer may write one (a
/// Slicer `.mrb` bundle, a UK Biobank download): the reader's input in the archive tests.
pub fn stored_zip(files: &[(String, Vec<u8>)]) -> Vec<u8> {
    let (mut out, mut dir) = (Vec::new(), Vec::new());
    let le16 = |v: usize| (v as u16).to_le_bytes();
    let le32 = |v: usize| (v as u32).to_le_bytes();
    for (name, data) in files {
        let at = out.len();
        out.extend_from_slice(b"PK\x03\x04\x14\0\0\0\0\0\0\0\0\0\0\0\0\0");
        out.extend_from_slice(&le32(data.len()));
        out.extend_from_slice(&le32(data.len()));
        out.extend_from_slice(&le16(name.len()));
        out.extend_from_slice(&[0, 0]);
        out.extend_from_slice(name.as_bytes());
        out.extend_from_slice(data);
        dir.extend_from_slice(b"PK\x01\x02\x14\0\x14\0\0\0\0\0\0\0\0\0\0\0\0\0");
        dir.extend_from_slice(&le32(data.len()));
        dir.extend_from_slice(&le32(data.len()));
        dir.extend_from_slice(&le16(name.len()));
        dir.extend_from_slice(&[0; 12]);
        dir.extend_from_slice(&le32(at));
        dir.extend_from_slice(name.as_bytes());
    }
    let dir_at = out.len();
    out.extend_from_slice(&dir);
    out.extend_from_slice(b"PK\x05\x06\0\0\0\0");
    out.extend_from_slice(&le16(files.len()));
    out.extend_from_slice(&le16(files.len()));
    out.extend_from_slice(&le32(dir.len()));
    out.extend_from_slice(&le32(dir_at));
    out.extend_from_slice(&[0, 0]);
    out
}

/// Every file under `root` (path relative to it with `/`, contents), in name order.
pub fn files_under(root: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut todo = vec![root.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                todo.push(p);
            } else {
                let rel = p
                    .strip_prefix(root)
                    .unwrap()
                    .to_string_lossy()
                    .replace('\\', "/");
                out.push((rel, std::fs::read(&p).unwrap()));
            }
        }
    }
    out.sort();
    out
}
