//! The phases batch: every surface of one heart reconstructed in each of its phases (one file per
//! phase, or the time frames of one file holding a sequence) at the same parameters, as the CLI's
//! `heartmesh volumes` does, so that the page can show each cavity's EDV/ESV/SV/EF and the LV mass
//! (core `metrics::function`). A phase that cannot be read, a surface a phase lacks and a run that
//! fails are cells of the table like the others: one bad phase must not cost the rest.
//!
//! The finished meshes stay here until the batch is done: the LV mass's biventricular check reads
//! the epicardium and the RV cavity together.

use heartmesh_core::clock::Clock;
use heartmesh_core::contours::ContourSet;
use heartmesh_core::error::{CoreError, Result};
use heartmesh_core::metrics::function::{summarise, surfaces_of, Measured, Outcome, UNLABELLED};
use heartmesh_core::pipeline::Reconstruction;
use heartmesh_core::Params;
use serde_json::{json, Value};

/// One phase as the page names it, with its contours or why they could not be read.
pub struct PhaseInput {
    pub name: String,
    pub contours: std::result::Result<ContourSet, String>,
}

/// What one (phase, surface) cell came to.
#[derive(Default)]
struct Cell {
    out: Outcome,
    seconds: f64,
    error: Option<String>,
}

/// The plan and the results of a phases batch; jobs run phase by phase, surfaces in order.
pub struct Phases {
    names: Vec<String>,
    surfaces: Vec<Option<String>>,
    /// Why a cell will not run (`absent`, or the phase's read error), by job index.
    blocked: Vec<Option<(&'static str, Option<String>)>>,
    cells: Vec<Cell>,
    clock: Box<dyn Clock>,
    started_ms: f64,
}

/// The phases' jobs (contours and parameters, one per cell) and their bookkeeping.
pub fn plan(
    inputs: Vec<PhaseInput>,
    params: &Params,
    clock: Box<dyn Clock>,
) -> Result<(Phases, Vec<(ContourSet, Params)>)> {
    if inputs.len() < 2 {
        return Err(CoreError::ParamInvalid {
            name: "phases".into(),
            message: format!(
                "{} phase(s): function needs two or more (end-diastole and end-systole)",
                inputs.len()
            ),
        });
    }
    let surfaces = surfaces_of(inputs.iter().filter_map(|i| i.contours.as_ref().ok()));
    let mut blocked = Vec::new();
    let mut jobs = Vec::new();
    for input in &inputs {
        for surface in &surfaces {
            let (set, why) = match &input.contours {
                Err(e) => (ContourSet::default(), Some(("failed", Some(e.clone())))),
                Ok(set) if holds(set, surface.as_deref()) => (set.clone(), None),
                Ok(_) => (ContourSet::default(), Some(("absent", None))),
            };
            let mut p = params.clone();
            p.surface = surface.clone();
            jobs.push((set, p));
            blocked.push(why);
        }
    }
    let phases = Phases {
        names: inputs.into_iter().map(|i| i.name).collect(),
        cells: (0..jobs.len()).map(|_| Cell::default()).collect(),
        surfaces,
        blocked,
        clock,
        started_ms: 0.0,
    };
    Ok((phases, jobs))
}

fn holds(set: &ContourSet, surface: Option<&str>) -> bool {
    surface.is_none_or(|s| set.surfaces().iter().any(|k| k == s))
}

fn label(surface: &Option<String>) -> &str {
    surface.as_deref().unwrap_or(UNLABELLED)
}

impl Phases {
    /// `{phases, surfaces}` for the page's table before any result.
    pub fn layout(&self) -> Value {
        let surfaces: Vec<&str> = self.surfaces.iter().map(label).collect();
        json!({ "phases": self.names, "surfaces": surfaces })
    }

    /// A cell that will not run, settled at once (its item); None for one to reconstruct.
    pub fn settle_blocked(&mut self, index: usize) -> Option<Value> {
        let (missing, error) = self.blocked.get(index).cloned().flatten()?;
        self.cells[index] = Cell {
            out: Outcome::none(missing),
            seconds: 0.0,
            error,
        };
        Some(self.item(index))
    }

    pub fn job_started(&mut self) {
        self.started_ms = self.clock.now_ms();
    }

    /// Keeps what the finished (or failed) job of cell `index` gave; returns its item.
    pub fn finish(
        &mut self,
        index: usize,
        rec: Option<&Reconstruction>,
        outcome: Result<()>,
    ) -> Value {
        let seconds = (self.clock.now_ms() - self.started_ms) / 1000.0;
        self.cells[index] = match (rec, outcome) {
            (Some(rec), Ok(())) => Cell {
                out: Outcome::of(rec),
                seconds,
                error: None,
            },
            (_, outcome) => Cell {
                out: Outcome::none("failed"),
                seconds,
                error: Some(
                    outcome
                        .err()
                        .map_or("no mesh".to_string(), |e| e.to_string()),
                ),
            },
        };
        self.item(index)
    }

    fn item(&self, index: usize) -> Value {
        let n = self.surfaces.len().max(1);
        let c = &self.cells[index];
        json!({
            "index": index,
            "phase": self.names.get(index / n),
            "surface": self.surfaces.get(index % n).map(label),
            "volume_ml": c.out.volume_ml,
            "watertight": c.out.watertight,
            "contour_to_mesh_mean": c.out.contour_to_mesh_mean,
            "seconds": c.seconds,
            "missing": c.out.missing,
            "error": c.error,
        })
    }

    /// The core's `function::summarise` of the cells (`{ventricles, single, lv_mass}`).
    pub fn summary(&self) -> Value {
        let labels: Vec<String> = self.surfaces.iter().map(|s| label(s).to_string()).collect();
        let n = labels.len().max(1);
        let measured: Vec<Vec<Measured>> = self
            .cells
            .chunks(n)
            .map(|row| row.iter().map(|c| c.out.measured()).collect())
            .collect();
        serde_json::to_value(summarise(&self.names, &labels, &measured)).unwrap_or(Value::Null)
    }
}
