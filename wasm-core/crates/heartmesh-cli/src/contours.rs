//! Loading contours for the commands: format detection, the GPFile companions
//! (`SliceInfoFile.txt` next to it, `--frame`), and a session's saved parameters.

use std::path::Path;

use heartmesh_core::io::{self, session, ContourFormat, ContourOptions};
use heartmesh_core::{ContourSet, Params};

use crate::error::CliError;
use crate::files;

/// Contours read from a file, with the parameters a session file carries.
pub struct Loaded {
    pub set: ContourSet,
    pub format: ContourFormat,
    pub session_params: Option<Params>,
}

pub fn load(path: &str, frame: Option<u32>) -> Result<Loaded, CliError> {
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
    };
    let set =
        io::read_contours_with(path, &bytes, &options).map_err(|e| CliError::input(path, e))?;
    Ok(Loaded {
        set,
        format,
        session_params: None,
    })
}

/// `--frame N`.
pub fn frame_flag(value: Option<&str>) -> Result<Option<u32>, CliError> {
    value
        .map(|v| {
            v.trim()
                .parse::<u32>()
                .map_err(|_| CliError::usage(format!("--frame: {v:?} is not a frame number")))
        })
        .transpose()
}
