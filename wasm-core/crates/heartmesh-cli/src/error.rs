//! How the CLI fails: one line on stderr and an exit status scripts can rely on
//! (2 = bad input or usage, 1 = the tool itself failed).

use heartmesh_core::CoreError;

/// A failure of a command, already knowing how to present itself.
#[derive(Debug)]
pub enum CliError {
    /// Wrong command line (exit 2).
    Usage(String),
    /// A problem with an input file or a parameter (exit 2): `file` is None for parameters.
    Input {
        file: Option<String>,
        error: CoreError,
    },
    /// A file could not be read (exit 2).
    Read { file: String, message: String },
    /// An output could not be written, found before any work (exit 2): a missing directory, a
    /// directory given as a file, no permission, or an output that would overwrite an input.
    Unwritable { file: String, message: String },
    /// Reconstruction or writing failed (exit 1).
    Failed(String),
    /// Another error with a reading warning that may explain it (e.g. coordinates in metres),
    /// kept on the same single line.
    Hinted(Box<CliError>, String),
    /// One surface's failure in a `--surface all` run, named (`surface RV_EPI: FILE: problem`).
    Surface(Box<CliError>, String),
}

impl CliError {
    pub fn usage(msg: impl Into<String>) -> Self {
        CliError::Usage(msg.into())
    }

    pub fn input(file: &str, error: CoreError) -> Self {
        CliError::Input {
            file: Some(file.to_string()),
            error,
        }
    }

    pub fn param(error: CoreError) -> Self {
        CliError::Input { file: None, error }
    }

    /// Appends the first of `warnings` (if any) to the message, unless the message already says
    /// it (the unit refusal repeats the unit warning).
    pub fn with_hint(self, warnings: &[String]) -> Self {
        match warnings.first() {
            Some(w) if !self.message().contains(w.as_str()) => {
                CliError::Hinted(Box::new(self), w.clone())
            }
            _ => self,
        }
    }

    pub fn exit_code(&self) -> i32 {
        match self {
            CliError::Failed(_) => 1,
            CliError::Hinted(inner, _) | CliError::Surface(inner, _) => inner.exit_code(),
            _ => 2,
        }
    }

    /// The single stderr line (without the `heartmesh: ` prefix): `FILE:LINE: problem` for parse
    /// errors with a line, `FILE: problem` otherwise.
    pub fn message(&self) -> String {
        // One line whatever a file put in the message: line breaks become spaces, and other
        // control characters (a vertical tab quoted from a damaged header) are shown escaped.
        let one_line = |s: String| -> String {
            s.chars()
                .map(|c| match c {
                    '\n' | '\r' => " ".to_string(),
                    c if c.is_control() => c.escape_default().to_string(),
                    c => c.to_string(),
                })
                .collect()
        };
        one_line(match self {
            CliError::Usage(m) => format!("{m} (see heartmesh --help)"),
            CliError::Read { file, message } | CliError::Unwritable { file, message } => {
                format!("{file}: {message}")
            }
            CliError::Failed(m) => m.clone(),
            CliError::Hinted(inner, hint) => format!("{} (warning: {hint})", inner.message()),
            CliError::Surface(inner, surface) => format!("surface {surface}: {}", inner.message()),
            CliError::Input { file, error } => {
                let problem = match error {
                    CoreError::Parse { message, .. } => message.clone(),
                    CoreError::SurfaceRequired { .. } => {
                        format!("{error} (use --surface, or --surface all for each in turn)")
                    }
                    // A file without a surface column is one surface: the core's "available: "
                    // would end in nothing.
                    CoreError::UnknownSurface {
                        requested,
                        available,
                    } if available.is_empty() => format!(
                        "surface {requested:?} not found: the file names no surfaces (no surface \
                         column: it is one surface; leave out --surface)"
                    ),
                    // Given on the command line: named as the option the user typed.
                    CoreError::ParamOutOfRange {
                        name,
                        value,
                        min,
                        max,
                    } if file.is_none() && option_of(name).is_some() => format!(
                        "{} {value} is out of range (allowed {min} to {max})",
                        option_of(name).unwrap_or_default()
                    ),
                    CoreError::ParamInvalid { name, message }
                        if file.is_none() && option_of(name).is_some() =>
                    {
                        format!("{}: {message}", option_of(name).unwrap_or_default())
                    }
                    other => other.to_string(),
                };
                match (file, error.line()) {
                    (Some(f), Some(line)) => format!("{f}:{line}: {problem}"),
                    (Some(f), None) => format!("{f}: {problem}"),
                    (None, _) => problem,
                }
            }
        })
    }
}

/// The command-line option that sets the core parameter `name` (`ring_points` ->
/// `--ring-points`), for the parameters `reconstruct` takes as options; None for the others
/// (a study's `sax`, the app-only `stop_threshold`), which keep the core's wording.
fn option_of(name: &str) -> Option<String> {
    let flag = name.replace('_', "-");
    let known = heartmesh_core::params::Params::schema()
        .iter()
        .any(|s| s.name == name)
        || crate::cmd_reconstruct::PARAM_VALUE_FLAGS.contains(&flag.as_str());
    known.then(|| format!("--{flag}"))
}
