//! Loading contours for the commands: format detection, the GPFile companions
//! (`SliceInfoFile.txt` next to it), the time frame (`--frame`, a number or a label), and a
//! session's saved parameters.

use std::path::Path;

use heartmesh_core::io::{self, session, ContourFormat, ContourOptions, FrameChoice};
use heartmesh_core::{ContourSet, Params};

use crate::error::CliError;
use crate::files;

/// Contours read from a file, with the parameters a session file carries.
pub struct Loaded {
    pub set: ContourSet,
    pub format: ContourFormat,
    pub session_params: Option<Params>,
}

pub fn load(path: &str, frame: Option<FrameChoice>) -> Result<Loaded, CliError> {
    let bytes = files::read(path)?;
    let format = io::detect_contour_format(path, &bytes);
    if format == ContourFormat::Session {
        let s = session::read_session(&bytes).map_err(|e| CliError::input(path, e))?;
        let params = s.params().map_err(|e| CliError::input(path, e))?;
        return Ok(Loaded {
            set: s.contours,
            format,
            session_params: Some(params),
        });
    }
    let slice_info = if format == ContourFormat::GpFile {
        let sibling = Path::new(path).with_file_name("SliceInfoFile.txt");
        std::fs::read(sibling).ok()
    } else {
        None
    };
    let options = ContourOptions {
        frame,
        slice_info: slice_info.as_deref(),
        ..ContourOptions::default()
    };
    let set =
        io::read_contours_with(path, &bytes, &options).map_err(|e| CliError::input(path, e))?;
    Ok(Loaded {
        set,
        format,
        session_params: None,
    })
}

/// Contours of one file, or of a study given as several: a NIfTI short-axis label map and its
/// long-axis views (single-slice label maps), in any order; or a cvi42 workspace with the DICOM
/// images it was drawn on (files, folders or ZIP archives, or one folder or archive holding
/// both); or Slicer markups files (several, or a folder of them); or a 3D Slicer scene (its
/// folder, or its `.mrb` bundle: its markups curves, else its segmentation). Returns the path
/// given of the file the contours are named after (the stack's, or the folder or archive holding
/// it), for messages and the report.
pub fn load_all(paths: &[String], frame: Option<FrameChoice>) -> Result<(&str, Loaded), CliError> {
    let [first, rest @ ..] = paths else {
        return Err(CliError::usage("no contour file given"));
    };
    // One file is read as it is; one archive (or a folder holding a workspace, or a Slicer scene)
    // for its files; any other folder is refused saying which files it holds.
    let archive = |p: &String| files::read(p).is_ok_and(|b| io::zip::is_zip(&b));
    let slicer_folder = rest.is_empty() && holds_slicer_scene(first);
    if rest.is_empty() && !archive(first) && !is_workspace_study(paths) && !slicer_folder {
        return load(first, frame).map(|l| (first.as_str(), l));
    }
    // A Slicer scene's other files (scene file, images) are set aside by the core, named.
    let entries = expand(paths)?;
    let named: Vec<(&str, &[u8])> = entries
        .iter()
        .map(|e| (e.name.as_str(), e.bytes.as_slice()))
        .collect();
    let options = ContourOptions {
        frame,
        ..ContourOptions::default()
    };
    // Each error names the file it is about itself; one about the set as a whole (its folders,
    // no curve in any file) is said of the paths given.
    let (stack, set) = io::read_study(&named, &options).map_err(|e| {
        let text = e.to_string();
        if entries.iter().any(|x| text.contains(x.name.as_str())) || text.contains(first.as_str()) {
            CliError::param(e)
        } else {
            CliError::input(&paths.join(" "), e)
        }
    })?;
    let e = &entries[stack];
    Ok((
        paths[e.origin].as_str(),
        Loaded {
            set,
            format: io::detect_contour_format(&e.name, &e.bytes),
            session_params: None,
        },
    ))
}

/// Whether `path` is a folder holding a 3D Slicer scene file or markups files (read together, as
/// Slicer saves one curve per file; `io::slicer_scene` picks what to read).
fn holds_slicer_scene(path: &str) -> bool {
    let slicer =
        |b: &[u8]| io::markups::is_markups(&b[..b.len().min(4096)]) || io::slicer_scene::is_mrml(b);
    Path::new(path).is_dir()
        && expand(std::slice::from_ref(&path.to_string()))
            .is_ok_and(|entries| entries.iter().any(|e| slicer(&e.bytes)))
}

/// One file of the inputs: `origin` is the index of the path given that holds it (itself, a
/// folder, an archive).
struct Entry {
    origin: usize,
    name: String,
    bytes: Vec<u8>,
}

/// The files the paths stand for: a folder for the files under it, a ZIP archive for the files
/// in it (UK Biobank hands out each subject's workspace and each DICOM series as one).
fn expand(paths: &[String]) -> Result<Vec<Entry>, CliError> {
    let mut out = Vec::new();
    for (origin, p) in paths.iter().enumerate() {
        let names = if Path::new(p).is_dir() {
            files::files_under(p)?
        } else {
            vec![p.clone()]
        };
        for name in names {
            let bytes = files::read(&name)?;
            if io::zip::is_zip(&bytes) {
                let members = io::zip::members(&bytes).map_err(|e| CliError::input(&name, e))?;
                out.extend(members.into_iter().map(|m| Entry {
                    origin,
                    name: format!("{name}/{}", m.name),
                    bytes: m.bytes,
                }));
            } else {
                out.push(Entry {
                    origin,
                    name,
                    bytes,
                });
            }
        }
    }
    Ok(out)
}

/// Whether the inputs are contours drawn on images given with them (a cvi42 workspace, Sunnybrook
/// contour files; files, folders, archives; or one folder or archive holding both): one study,
/// which may hold a sequence, rather than one file per phase.
pub fn is_workspace_study(paths: &[String]) -> bool {
    let bundle =
        |p: &String| Path::new(p).is_dir() || files::read(p).is_ok_and(|b| io::zip::is_zip(&b));
    if paths.len() == 1 && !bundle(&paths[0]) {
        return false;
    }
    expand(paths).is_ok_and(|entries| {
        entries.iter().any(|e| {
            io::cvi42::is_cvi42(&e.bytes) || io::sunnybrook::is_contour_file(&e.name, &e.bytes)
        })
    })
}

/// A reader's warning as the commands print it: the label-map reader's account of what it read
/// is a note, the rest warnings.
pub fn warning_line(input: &str, w: &str) -> String {
    let kind = if io::is_reading_note(w) {
        "note"
    } else {
        "warning"
    };
    format!("heartmesh: {kind}: {input}: {w}")
}

/// `--frame N` or `--frame LABEL`: the frame as the file writes it (`9`, `9.0`, `ES`; text in any
/// case), compared as the core's readers compare frames (`io::FrameChoice`). Blank is refused
/// here rather than read as no choice: the user asked for a frame.
pub fn frame_flag(value: Option<&str>) -> Result<Option<FrameChoice>, CliError> {
    value
        .map(|v| {
            FrameChoice::new(v).ok_or_else(|| {
                CliError::usage(format!(
                    "--frame: {v:?} names no frame (give a frame number or label as the file \
                     writes it, e.g. --frame 9 or --frame ES)"
                ))
            })
        })
        .transpose()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_flag_takes_numbers_and_labels() {
        assert_eq!(frame_flag(None).unwrap(), None);
        let nine = frame_flag(Some("9")).unwrap().unwrap();
        assert!(nine.matches("9.0") && !nine.matches("90"));
        let es = frame_flag(Some(" ES")).unwrap().unwrap();
        assert_eq!(es.label(), "ES");
        assert!(es.matches("es"));
        let e = frame_flag(Some(" ")).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(e.message().contains("names no frame"), "{}", e.message());
    }
}
