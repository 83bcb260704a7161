//! File access for the CLI (the core never touches the file system).

use std::path::Path;

use crate::error::CliError;

/// Largest input accepted: far beyond any contour or mesh file, small enough to fail cleanly.
const MAX_INPUT_BYTES: u64 = 1 << 30;

pub fn read(path: &str) -> Result<Vec<u8>, CliError> {
    let fail = |message: String| CliError::Read {
        file: path.to_string(),
        message,
    };
    let meta = std::fs::metadata(path).map_err(|e| fail(describe(&e)))?;
    if meta.is_dir() {
        return Err(fail("is a directory, not a file".into()));
    }
    if meta.len() > MAX_INPUT_BYTES {
        return Err(fail(format!(
            "file of {} bytes is larger than the {} byte limit",
            meta.len(),
            MAX_INPUT_BYTES
        )));
    }
    std::fs::read(path).map_err(|e| fail(describe(&e)))
}

/// Writes through a temporary file in the same directory and renames it, so that a failed run
/// never leaves a half-written mesh behind (or destroys the previous one).
pub fn write(path: &str, bytes: &[u8]) -> Result<(), CliError> {
    let fail =
        |e: std::io::Error| CliError::Failed(format!("{path}: cannot write: {}", describe(&e)));
    let p = Path::new(path);
    let name = p
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or_else(|| CliError::usage(format!("{path} is not a file name")))?;
    let tmp = p.with_file_name(format!(".{name}.heartmesh-tmp"));
    std::fs::write(&tmp, bytes).map_err(fail)?;
    std::fs::rename(&tmp, p).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        fail(e)
    })
}

/// An io::Error without Rust's "(os error 2)" suffix.
fn describe(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file or directory".into(),
        std::io::ErrorKind::PermissionDenied => "permission denied".into(),
        _ => {
            let s = e.to_string();
            match s.find(" (os error") {
                Some(i) => s[..i].to_string(),
                None => s,
            }
        }
    }
}
