//! File access for the CLI (the core never touches the file system).

use std::path::{Path, PathBuf};

use crate::error::CliError;

/// Largest input accepted: far beyond any contour or mesh file, small enough to fail cleanly.
const MAX_INPUT_BYTES: u64 = 1 << 30;

pub fn read(path: &str) -> Result<Vec<u8>, CliError> {
    let fail = |message: String| CliError::Read {
        file: path.to_string(),
        message,
    };
    if path.is_empty() {
        return Err(CliError::Read {
            file: "\"\"".into(),
            message: "empty file name".into(),
        });
    }
    let meta = std::fs::metadata(path).map_err(|e| fail(describe(&e)))?;
    if meta.is_dir() {
        return Err(fail(format!(
            "is a directory, not a file{}",
            files_in(Path::new(path))
        )));
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

/// The files a directory holds, at any depth, in name order (hidden entries left out): a DICOM
/// study is a folder of images, often in subfolders per series.
pub fn files_under(dir: &str) -> Result<Vec<String>, CliError> {
    let mut out = Vec::new();
    let mut pending = vec![PathBuf::from(dir)];
    while let Some(d) = pending.pop() {
        let entries = std::fs::read_dir(&d).map_err(|e| CliError::Read {
            file: d.display().to_string(),
            message: describe(&e),
        })?;
        for entry in entries.flatten() {
            let path = entry.path();
            let hidden = entry.file_name().to_string_lossy().starts_with('.');
            if hidden {
                continue;
            }
            if path.is_dir() {
                pending.push(path);
            } else {
                out.push(path.display().to_string());
            }
        }
    }
    out.sort();
    Ok(out)
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

/// Checks, before any work is done, that `path` can be written as [`write`] writes it (a
/// temporary file beside it, renamed): its directory exists and takes a new file, and the path
/// is not a directory. A mistyped output directory is then a usage error (exit 2) at once, not
/// a failure after a long reconstruction whose result is lost.
pub fn check_output(path: &str) -> Result<(), CliError> {
    let fail = |message: String| CliError::Unwritable {
        file: if path.is_empty() {
            "\"\"".into()
        } else {
            path.to_string()
        },
        message,
    };
    let p = Path::new(path);
    let name = match p.file_name().and_then(|n| n.to_str()) {
        Some(n) if !path.ends_with(['/', '\\']) => n,
        _ if p.is_dir() => {
            return Err(fail(
                "cannot write: is a directory; give a file name in it".into(),
            ))
        }
        _ => return Err(fail("cannot write: not a file name".into())),
    };
    if p.is_dir() {
        return Err(fail(
            "cannot write: is a directory; give a file name in it".into(),
        ));
    }
    let parent = match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    match std::fs::metadata(parent) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => {
            return Err(fail(format!(
                "cannot write: {} is not a directory",
                parent.display()
            )))
        }
        Err(_) => {
            return Err(fail(format!(
                "cannot write: no directory {}",
                parent.display()
            )))
        }
    }
    // Permissions (and read-only file systems) are only known by trying.
    let probe = p.with_file_name(format!(".{name}.heartmesh-tmp"));
    try_create(&probe).map_err(|e| fail(format!("cannot write: {}", describe(&e))))
}

/// Creates and removes `probe`, a file name no one else uses; one left over by an interrupted
/// run counts as success ([`write`] replaces it).
fn try_create(probe: &Path) -> std::io::Result<()> {
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(probe)
    {
        Ok(_) => {
            let _ = std::fs::remove_file(probe);
            Ok(())
        }
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Ok(()),
        Err(e) => Err(e),
    }
}

/// Creates the output directory `dir` (and its parents) before any work is done; a usage error
/// (exit 2) naming it when it cannot be.
pub fn create_dir(dir: &str) -> Result<(), CliError> {
    let fail = |message: String| CliError::Unwritable {
        file: dir.to_string(),
        message,
    };
    if Path::new(dir).exists() && !Path::new(dir).is_dir() {
        return Err(fail("is a file, not a directory".into()));
    }
    std::fs::create_dir_all(dir)
        .map_err(|e| fail(format!("cannot create the directory: {}", describe(&e))))?;
    // There, but maybe not writable (permissions, read-only file system).
    try_create(&Path::new(dir).join(".heartmesh-probe"))
        .map_err(|e| fail(format!("cannot write in the directory: {}", describe(&e))))
}

/// Refuses outputs that would overwrite an input or each other (`-o m.obj --report m.obj`, or
/// `align a.csv -o a.csv`): the file would be lost, or the mesh overwritten by the report.
/// `outputs` are (option, path) pairs, named in the message.
pub fn check_distinct(inputs: &[&str], outputs: &[(&str, &str)]) -> Result<(), CliError> {
    let inputs: Vec<(&str, Option<PathBuf>)> = inputs.iter().map(|i| (*i, identity(i))).collect();
    let mut seen: Vec<(&str, PathBuf)> = Vec::new();
    for &(option, path) in outputs {
        let Some(id) = identity(path) else { continue };
        if let Some((input, _)) = inputs.iter().find(|(_, i)| i.as_ref() == Some(&id)) {
            return Err(CliError::Unwritable {
                file: path.to_string(),
                message: format!(
                    "{option} would overwrite the input file {input}; give another output name"
                ),
            });
        }
        if let Some((other, _)) = seen.iter().find(|(_, s)| *s == id) {
            return Err(CliError::Unwritable {
                file: path.to_string(),
                message: format!(
                    "given as both {other} and {option}; give each output its own file"
                ),
            });
        }
        seen.push((option, id));
    }
    Ok(())
}

/// The file `path` names, for comparing paths: the canonical path of an existing file (through
/// links), else its canonical directory and its name; None when neither can be known.
fn identity(path: &str) -> Option<PathBuf> {
    let p = Path::new(path);
    if let Ok(c) = std::fs::canonicalize(p) {
        return Some(c);
    }
    let parent = match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    Some(std::fs::canonicalize(parent).ok()?.join(p.file_name()?))
}

/// For a directory given as an input: the contour files in it worth naming (a biv-me patient
/// folder's GPFiles first), as a hint; empty when there are none.
fn files_in(dir: &Path) -> String {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return String::new();
    };
    let readable = [
        ".csv", ".txt", ".mat", ".json", ".vtk", ".vtp", ".dcm", ".nii", ".nii.gz", ".nrrd", ".gz",
    ];
    let mut names: Vec<String> = entries
        .filter_map(|e| e.ok())
        .filter(|e| e.path().is_file())
        .filter_map(|e| e.file_name().into_string().ok())
        .filter(|n| {
            let l = n.to_ascii_lowercase();
            !l.starts_with('.')
                && l != "sliceinfofile.txt"
                && readable.iter().any(|x| l.ends_with(x))
        })
        .collect();
    if names.is_empty() {
        return String::new();
    }
    // GPFiles first, then by name.
    names.sort_by_key(|n| (!n.starts_with("GPFile"), n.clone()));
    let shown: Vec<String> = names
        .iter()
        .take(3)
        .map(|n| dir.join(n).display().to_string())
        .collect();
    let more = if names.len() > 3 { ", ..." } else { "" };
    format!(
        " (give the contour files in it, e.g. {}{more})",
        shown.join(" ")
    )
}

/// An io::Error without Rust's "(os error 2)" suffix.
fn describe(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file or directory".into(),
        std::io::ErrorKind::PermissionDenied => "permission denied".into(),
        _ => {
            let s = e.to_string();
            let s = match s.find(" (os error") {
                Some(i) => &s[..i],
                None => s.as_str(),
            };
            // "Read-only file system" reads as the rest of the line does.
            let mut c = s.chars();
            c.next()
                .map(|f| f.to_lowercase().chain(c).collect())
                .unwrap_or_default()
        }
    }
}
