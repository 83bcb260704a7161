//! The Lab's ground truths: one surface (the parametric LV, a reference shape, a dropped mesh) or
//! several surfaces of one heart, each with its surface label (LV_ENDO, RV_ENDO, ...), sliced
//! together on one acquisition as the CLI's `heartmesh simulate LV_ENDO=lv.obj RV_ENDO=rv.obj`
//! does. The labels are the `surface` column of the simulated file, so the reconstruction of a
//! surface is compared with the truth of the same label and never with another.
//!
//! A single truth needs no label (its acquisition is exactly `sim::simulate`'s, no surface
//! column, as before several truths existed); with several, each needs its own.

use heartmesh_core::contours::CoordinateSystem;
use heartmesh_core::error::CoreError;
use heartmesh_core::TriMesh;

/// One ground-truth surface.
pub struct Truth {
    /// The file it was read from, or "parametric LV".
    pub name: String,
    /// Its surface label; None until given (only a lone truth may go without).
    pub label: Option<String>,
    pub mesh: TriMesh,
    /// The patient frame its file states (`SPACE=`), after any conversion on adding.
    pub frame: Option<CoordinateSystem>,
    /// The frame its file stated when [`Truths::add`] took it into the first truth's.
    pub converted_from: Option<CoordinateSystem>,
}

impl Truth {
    /// A truth whose file states no frame (the parametric LV, most meshes).
    pub fn new(name: String, label: Option<String>, mesh: TriMesh) -> Self {
        Truth {
            name,
            label,
            mesh,
            frame: None,
            converted_from: None,
        }
    }
}

/// A Lab failure: a core error (keeps its code and line) or a usage error of the Lab itself.
#[derive(Debug)]
pub enum LabError {
    Core(CoreError),
    Usage { code: &'static str, message: String },
}

impl From<CoreError> for LabError {
    fn from(e: CoreError) -> Self {
        LabError::Core(e)
    }
}

impl std::fmt::Display for LabError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LabError::Core(e) => write!(f, "{e}"),
            LabError::Usage { message, .. } => f.write_str(message),
        }
    }
}

pub fn usage(code: &'static str, message: impl Into<String>) -> LabError {
    LabError::Usage {
        code,
        message: message.into(),
    }
}

/// A label for the `surface` column: what the readers accept as one (no separators or quotes).
/// The same rule as the CLI's `heartmesh simulate LABEL=FILE`.
pub fn is_label(s: &str) -> bool {
    !s.is_empty()
        && s.len() <= 64
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// The truths, in the order they were given (the first plans the acquisition, as in the CLI).
#[derive(Default)]
pub struct Truths {
    list: Vec<Truth>,
}

impl Truths {
    pub fn len(&self) -> usize {
        self.list.len()
    }

    pub fn get(&self, index: usize) -> Result<&Truth, LabError> {
        self.list.get(index).ok_or_else(|| {
            if self.list.is_empty() {
                usage("no_truth", "no truth surface: make or load one first")
            } else {
                usage(
                    "no_truth",
                    format!("no truth #{index}: the Lab holds {}", self.list.len()),
                )
            }
        })
    }

    /// Makes `truth` the only one (a new parametric LV, a reference shape, one dropped mesh).
    pub fn replace(&mut self, truth: Truth) -> Result<(), LabError> {
        if let Some(label) = &truth.label {
            check_label(label)?;
        }
        self.list = vec![truth];
        Ok(())
    }

    /// Adds `truth` beside the others; a label that is no label or is taken is refused and the
    /// truths stay as they were. Returns its index.
    ///
    /// Surfaces of one heart must share a frame: one whose file states the other frame than the
    /// first truth's (a NIfTI-made RAS mesh beside a DICOM-made LPS one) is taken into the first's,
    /// as `heartmesh compare` does, and says so (`converted_from`); sliced as they stood, the two
    /// would lie mirrored on opposite sides of the acquisition.
    pub fn add(&mut self, mut truth: Truth) -> Result<usize, LabError> {
        if let Some(label) = &truth.label {
            self.check_free(label, None, &truth.name)?;
        }
        let first = self.list.first().and_then(|t| t.frame);
        if let (Some(from), Some(to)) = (truth.frame, first) {
            if from != to {
                for p in &mut truth.mesh.positions {
                    *p = from.convert(to, p);
                }
                truth.frame = Some(to);
                truth.converted_from = Some(from);
            }
        }
        self.list.push(truth);
        Ok(self.list.len() - 1)
    }

    /// Gives truth `index` a label (None: takes it away), refusing one another truth has.
    pub fn relabel(&mut self, index: usize, label: Option<String>) -> Result<(), LabError> {
        let name = self.get(index)?.name.clone();
        if let Some(label) = &label {
            self.check_free(label, Some(index), &name)?;
        }
        self.list[index].label = label;
        Ok(())
    }

    pub fn remove(&mut self, index: usize) -> Result<Truth, LabError> {
        self.get(index)?;
        Ok(self.list.remove(index))
    }

    /// `[{name, label}]`, in order.
    pub fn summary(&self) -> serde_json::Value {
        serde_json::Value::Array(
            self.list
                .iter()
                .map(|t| serde_json::json!({ "name": t.name, "label": t.label }))
                .collect(),
        )
    }

    /// The truth a reconstruction of `surface` is measured against: the only one when there is
    /// one (its file has no surface column), else the one labelled `surface` (labels compare
    /// without case, as the CLI's clash check) — never another surface's. Returns its index.
    pub fn for_surface(&self, surface: Option<&str>) -> Result<usize, LabError> {
        match (self.list.len(), surface) {
            (0, _) => Err(usage(
                "no_truth",
                "no truth surface: make or load one first",
            )),
            (1, _) => Ok(0),
            (_, None) => Err(usage(
                "no_truth_for_surface",
                format!(
                    "the Lab holds {} truths ({}): pick the surface to compare",
                    self.list.len(),
                    self.labels_text()
                ),
            )),
            (_, Some(s)) => self
                .list
                .iter()
                .position(|t| {
                    t.label
                        .as_deref()
                        .is_some_and(|l| l.eq_ignore_ascii_case(s))
                })
                .ok_or_else(|| {
                    usage(
                        "no_truth_for_surface",
                        format!(
                            "no truth for {s}: the Lab's truths are {}",
                            self.labels_text()
                        ),
                    )
                }),
        }
    }

    /// `(label, mesh)` of every truth for `simulate_surfaces`; refuses a truth without a label.
    pub fn labelled(&self) -> Result<Vec<(&str, &TriMesh)>, LabError> {
        self.list
            .iter()
            .map(|t| match &t.label {
                Some(l) => Ok((l.as_str(), &t.mesh)),
                None => Err(usage(
                    "label_required",
                    format!(
                        "{} has no surface label: with several truths give each one \
                         (LV_ENDO, LV_EPI, RV_ENDO, RV_EPI, BIV_EPI, ...)",
                        t.name
                    ),
                )),
            })
            .collect()
    }

    /// Every truth's label, in order.
    pub fn labels(&self) -> Vec<Option<String>> {
        self.list.iter().map(|t| t.label.clone()).collect()
    }

    fn labels_text(&self) -> String {
        self.list
            .iter()
            .map(|t| t.label.as_deref().unwrap_or("(no label)"))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// A valid label no other truth than `except` has (the error names who has it).
    fn check_free(&self, label: &str, except: Option<usize>, name: &str) -> Result<(), LabError> {
        check_label(label)?;
        let taken = self.list.iter().enumerate().find(|(k, t)| {
            Some(*k) != except
                && t.label
                    .as_deref()
                    .is_some_and(|l| l.eq_ignore_ascii_case(label))
        });
        match taken {
            Some((_, other)) => Err(usage(
                "label_taken",
                format!(
                    "{name}: the label {label} is already {}'s; give each truth its own",
                    other.name
                ),
            )),
            None => Ok(()),
        }
    }
}

fn check_label(label: &str) -> Result<(), LabError> {
    if is_label(label) {
        Ok(())
    } else {
        Err(usage(
            "label_invalid",
            format!(
                "{label:?} is no surface label: letters, digits, _ and - only, at most 64 \
                 (e.g. LV_ENDO, RV_ENDO)"
            ),
        ))
    }
}
