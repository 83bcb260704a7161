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
