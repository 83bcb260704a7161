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
/// images it was drawn on (files or folders). Returns the path of the file
/// the contours are named after (the stack's), for messages and the report.
pub fn load_all(paths: &[String], frame: Option<FrameChoice>) -> Result<(&str, Loaded), CliError> {
    let paths_given = paths;
    let [first, rest @ ..] = paths else {
        return Err(CliError::usage("no contour file given"));
    };
    if rest.is_empty() {
        return load(first, frame).map(|l| (first.as_str(), l));
    }
    // A folder among the files (a cvi42 workspace's DICOM images) stands for what it holds.
    let mut expanded = Vec::with_capacity(paths.len());
    for p in paths {
        if Path::new(p).is_dir() {
            expanded.extend(files::files_under(p)?);
        } else {
            expanded.push(p.clone());
        }
    }
    let paths = expanded.as_slice();
    let contents = paths
        .iter()
        .map(|p| files::read(p))
        .collect::<Result<Vec<_>, _>>()?;
    let named: Vec<(&str, &[u8])> = paths
        .iter()
        .map(String::as_str)
        .zip(contents.iter().map(Vec::as_slice))
        .collect();
    let options = ContourOptions {
        frame,
        ..ContourOptions::default()
    };
    // Each error names the file it is about itself.
    let (stack, set) = io::read_study(&named, &options).map_err(CliError::param)?;
    let format = io::detect_contour_format(&paths[stack], &contents[stack]);
    let input = first_named(paths_given, &paths[stack]);
    Ok((
        input,
        Loaded {
            set,
            format,
            session_params: None,
        },
    ))
}

/// Whether several inputs are a cvi42 workspace with its images (files or folders): one study,
/// which may hold a sequence, rather than one file per phase.
pub fn is_workspace_study(paths: &[String]) -> bool {
    paths.len() > 1
        && paths.iter().any(|p| {
            !Path::new(p).is_dir() && files::read(p).is_ok_and(|b| io::cvi42::is_cvi42(&b))
        })
}

/// The path given on the command line that is `stack` (the returned name must outlive the
/// expanded list; a stack is always given by name, never found inside a folder).
fn first_named<'a>(given: &'a [String], stack: &str) -> &'a str {
    given
        .iter()
        .find(|g| g.as_str() == stack)
        .map_or(given[0].as_str(), String::as_str)
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
