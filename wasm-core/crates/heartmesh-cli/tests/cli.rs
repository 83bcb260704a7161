//! Integration tests of the `heartmesh` binary: the exit-status and stderr contract, conversion,
//! and a full reconstruction of the SurFCo example checked by its report.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_heartmesh"))
}

/// `shared/data` is ../../../../shared/data from this crate in the main checkout (one level more
/// from a worktree): the nearest ancestor holding it.
fn data(rel: &str) -> PathBuf {
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = here
        .ancestors()
        .map(|a| a.join("shared/data"))
        .find(|d| d.join("README.md").is_file())
        .expect("shared/data not found above CARGO_MANIFEST_DIR");
    dir.join(rel)
}

/// A fresh scratch directory per test.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("heartmesh-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn run(cmd: &mut Command) -> (i32, String, String) {
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

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn version_and_help() {
    let (code, out, _) = run(bin().arg("--version"));
    assert_eq!(code, 0);
    assert!(out.starts_with("heartmesh "), "{out}");
    let (code, out, _) = run(bin().arg("--help"));
    assert_eq!(code, 0);
    assert!(
        out.contains("heartmesh reconstruct CONTOURS -o MESH.obj"),
        "{out}"
    );
    assert!(out.contains("--target-reduction"), "{out}");
}

#[test]
fn usage_errors_exit_2_with_one_line() {
    for args in [
        vec![],
        vec!["frobnicate"],
        vec!["reconstruct"],
        vec!["reconstruct", "a.csv"],
        vec!["reconstruct", "a.csv", "-o", "m.xyz"],
        vec!["reconstruct", "a.csv", "-o", "m.obj", "--bogus", "1"],
        vec!["convert", "a.csv"],
    ] {
        let (code, out, err) = run(bin().args(&args));
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(out.is_empty(), "{args:?}: {out}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("heartmesh: "), "{args:?}: {err}");
    }
}

#[test]
fn bad_file_names_file_and_line() {
    let dir = scratch("bad");
    let f = dir.join("bad.csv");
    std::fs::write(&f, "contour,x,y,z\nc1,1,2,3\nc1,1,oops,3\n").unwrap();
    let (code, _, err) = run(bin().args(["reconstruct", s(&f), "-o", s(&dir.join("m.obj"))]));
    assert_eq!(code, 2);
    assert_eq!(
        err,
        format!(
            "heartmesh: {}:3: column \"y\": \"oops\" is not a number\n",
            s(&f)
        )
    );
    assert!(!dir.join("m.obj").exists(), "no output on failure");

    let missing = dir.join("missing.csv");
    let (code, _, err) = run(bin().args(["reconstruct", s(&missing), "-o", "m.obj"]));
    assert_eq!(code, 2);
    assert_eq!(
        err,
        format!("heartmesh: {}: no such file or directory\n", s(&missing))
    );

    std::fs::write(&f, [0x50u8, 0x4b, 0x03, 0x04, 0xff, 0x00, 0x12]).unwrap();
    let (code, _, err) = run(bin().args(["convert", s(&f), s(&dir.join("o.csv"))]));
    assert_eq!(code, 2);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("binary"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn out_of_range_parameter_names_the_range() {
    let input = data("contours/surfco-example.csv");
    let (code, _, err) =
        run(bin().args(["reconstruct", s(&input), "-o", "never.obj", "--beta", "1.5"]));
    assert_eq!(code, 2);
    assert_eq!(
        err,
        "heartmesh: parameter beta = 1.5 is out of range (allowed 0.01 to 1)\n"
    );
    let (code, _, err) = run(bin().args([
        "reconstruct",
        s(&input),
        "-o",
        "never.obj",
        "--iterations",
        "12.5",
    ]));
    assert_eq!(code, 2);
    assert!(err.contains("whole number"), "{err}");
}

#[test]
fn convert_contours_and_meshes() {
    let dir = scratch("convert");
    let out = dir.join("surfco.csv");
    let (code, stdout, err) =
        run(bin().args(["convert", s(&data("contours/surfco-example.csv")), s(&out)]));
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        stdout,
        format!("{}: 8 contours, 3008 points, 0 landmarks\n", s(&out))
    );

    let obj = data("meshes/bivme-patient1-ED-LV_ENDO-closed.obj");
    let ply = dir.join("lv.ply");
    let (code, stdout, err) = run(bin().args(["convert", s(&obj), s(&ply)]));
    assert_eq!(code, 0, "{err}");
    let counts = stdout.split_once(": ").unwrap().1.to_string();
    for ext in ["stl", "vtk", "vtp", "obj"] {
        let next = dir.join(format!("lv.{ext}"));
        let (code, stdout, err) = run(bin().args(["convert", s(&ply), s(&next)]));
        assert_eq!(code, 0, "{ext}: {err}");
        assert_eq!(stdout.split_once(": ").unwrap().1, counts, "{ext}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
