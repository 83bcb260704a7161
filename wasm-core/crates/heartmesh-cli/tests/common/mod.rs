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
