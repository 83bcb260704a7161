//! Typed errors of the core. Every failure on user data is one of these, never a panic.

use thiserror::Error;

/// Everything that can go wrong between reading contours and finishing a reconstruction.
///
/// Each variant has a stable [`CoreError::code`] so that the browser and scripts can react to the
/// kind of failure without parsing the message.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CoreError {
    /// A file could not be read; `line` is 1-based (0 when the problem is the whole file, and then
    /// the message names no line).
    #[error("{}", parse_text(*.line, .message))]
    Parse { line: usize, message: String },
    /// A parameter is outside its allowed range.
    #[error("parameter {name} = {value} is out of range (allowed {min} to {max})")]
    ParamOutOfRange {
        name: String,
        value: f64,
        min: f64,
        max: f64,
    },
    /// A parameter has an invalid form (not a number, unknown mode, ...).
    #[error("parameter {name}: {message}")]
    ParamInvalid { name: String, message: String },
    /// Not enough usable contours to build a surface.
    #[error("too few contours: {found} usable, at least {needed} needed")]
    TooFewContours { found: usize, needed: usize },
    /// More contours in one surface than any acquisition has (often a file whose contour column
    /// is a point index): refused before the quadratic SAX/LAX analysis would seem to hang.
    #[error("too many contours: {found} in one surface, at most {max}; is the contour column a point index?")]
    TooManyContours { found: usize, max: usize },
    /// No group of parallel (short-axis) contours could be found.
    #[error("no short-axis group: need at least 2 roughly parallel contours ({0})")]
    NoSaxGroup(String),
    /// The contour file holds several surfaces and none was chosen.
    #[error("the contours describe several surfaces; choose one of: {}", .available.join(", "))]
    SurfaceRequired { available: Vec<String> },
    /// The requested surface is not in the file.
    #[error("surface {requested} not found; available: {}", .available.join(", "))]
    UnknownSurface {
        requested: String,
        available: Vec<String>,
    },
    /// A contour asked to be left out (`Params::leave_out`) that the file does not have: a typo
    /// would otherwise leave the contour in without a word. `available` is what the message
    /// lists: the ids of the surface being reconstructed (or the file's).
    #[error("no contour {id:?} to leave out; the contours are {}", list_ids(.available))]
    UnknownContour { id: String, available: Vec<String> },
    /// Input geometry from which no surface can be built (all points coplanar, zero extent, ...).
    #[error("degenerate input: {0}")]
    Degenerate(String),
    /// A numerical step failed (factorisation, non-finite result).
    #[error("numerical failure: {0}")]
    Numerical(String),
    /// The mesh lost a property the method relies on (closed, manifold, oriented).
    #[error("invalid mesh: {0}")]
    InvalidMesh(String),
    /// Writing output failed.
    #[error("write failed: {0}")]
    Io(String),
}

impl CoreError {
    /// Stable machine-readable code of the error kind.
    pub fn code(&self) -> &'static str {
        match self {
            CoreError::Parse { .. } => "parse",
            CoreError::ParamOutOfRange { .. } => "param_out_of_range",
            CoreError::ParamInvalid { .. } => "param_invalid",
            CoreError::TooFewContours { .. } => "too_few_contours",
            CoreError::TooManyContours { .. } => "too_many_contours",
            CoreError::NoSaxGroup(_) => "no_sax_group",
            CoreError::SurfaceRequired { .. } => "surface_required",
            CoreError::UnknownSurface { .. } => "unknown_surface",
            CoreError::UnknownContour { .. } => "unknown_contour",
            CoreError::Degenerate(_) => "degenerate",
            CoreError::Numerical(_) => "numerical",
            CoreError::InvalidMesh(_) => "invalid_mesh",
            CoreError::Io(_) => "io",
        }
    }

    /// The 1-based line for parse errors, when known.
    pub fn line(&self) -> Option<usize> {
        match self {
            CoreError::Parse { line, .. } if *line > 0 => Some(*line),
            _ => None,
        }
    }

    /// Shorthand for a parse error at a line.
    pub fn parse(line: usize, message: impl Into<String>) -> Self {
        CoreError::Parse {
            line,
            message: message.into(),
        }
    }
}

fn parse_text(line: usize, message: &str) -> String {
    if line > 0 {
        format!("line {line}: {message}")
    } else {
        message.to_string()
    }
}

/// Result alias of the core.
pub type Result<T> = std::result::Result<T, CoreError>;

/// Up to eight ids quoted, then how many more: a file may have a hundred contours, the message is
/// one line.
fn list_ids(ids: &[String]) -> String {
    const SHOWN: usize = 8;
    let quoted: Vec<String> = ids.iter().take(SHOWN).map(|id| format!("{id:?}")).collect();
    match ids.len().saturating_sub(SHOWN) {
        0 => quoted.join(", "),
        more => format!("{} and {more} more", quoted.join(", ")),
    }
}
