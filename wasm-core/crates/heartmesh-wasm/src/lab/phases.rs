//! The phases batch: every surface of one heart reconstructed in each of its phases (one file per
//! phase, or the time frames of one file holding a sequence) at the same parameters, as the CLI's
//! `heartmesh volumes` does, so that the page can show each cavity's EDV/ESV/SV/EF and the LV mass
//! (core `metrics::function`). A phase that cannot be read, a surface a phase lacks and a run that
//! fails are cells of the table like the others: one bad phase must not cost the rest.
//!
//! The finished meshes stay here until the batch is done: the LV mass's biventricular check reads
//! the epicardium and the RV cavity together. The Lab keeps a finished batch (its meshes, contours
//! and base planes) for the study's anatomical layouts ([`Phases::anatomical`], the CLI's
//! `volumes --anatomical-meshes`).

use heartmesh_core::clock::Clock;
use heartmesh_core::contours::ContourSet;
use heartmesh_core::error::{CoreError, Result};
use heartmesh_core::io::MeshFormat;
use heartmesh_core::metrics::anatomical::{self, Layout};
use heartmesh_core::metrics::anatomical_study::{self, PhaseSurface};
use heartmesh_core::metrics::bullseye;
use heartmesh_core::metrics::compare::{basal_plane, ClipPlane};
use heartmesh_core::metrics::function::{
    file_stem, summarise, Function, Measured, Outcome, UNLABELLED,
};
use heartmesh_core::metrics::septum;
use heartmesh_core::metrics::thickening::{self, PhaseLv, Thickening};
use heartmesh_core::pipeline::Reconstruction;
use heartmesh_core::Params;
use serde_json::{json, Value};

/// Where a phase's contours come from.
pub enum Source {
    /// Read already (a file the session holds), or why not (boxed: a contour set is large beside
    /// a frame's label).
    Read(std::result::Result<Box<ContourSet>, String>),
    /// A time frame of the [`Sequence`], read when its first cell runs: reading every frame of a
    /// long cine up front would hold the worker for seconds before the first progress, with no
    /// way to stop it.
    Frame(String),
}

/// One phase as the page names it.
pub struct PhaseInput {
    pub name: String,
    /// The file it is read from (a sequence's, for a frame): named in the anatomical files' header.
    pub file: String,
    pub source: Source,
    /// Contours the user left out of this phase (`Params::leave_out`; empty: the batch's list):
    /// its volumes must be those of the runs on screen.
    pub leave_out: Vec<String>,
}

/// The file whose time frames are phases: its bytes and long-axis views, kept to read the frames
/// one by one, and the surfaces of the frame the session holds (the table's columns before any
/// other frame is read).
pub struct Sequence {
    pub file: String,
    pub bytes: Vec<u8>,
    pub views: Vec<(String, Vec<u8>)>,
    pub surfaces: Vec<String>,
}

/// What one (phase, surface) cell came to.
#[derive(Default)]
struct Cell {
    out: Outcome,
    seconds: f64,
    error: Option<String>,
    /// The run's most basal short-axis plane (the anatomical layouts stop there).
    base: Option<ClipPlane>,
}

/// The plan and the results of a phases batch; jobs run phase by phase, surfaces in order.
pub struct Phases {
    names: Vec<String>,
    /// Each phase's file name (the anatomical files' header names it).
    files: Vec<String>,
    surfaces: Vec<Option<String>>,
    /// Per phase: its contours, or the frame still to read.
    sources: Vec<Source>,
    sequence: Option<Sequence>,
    cells: Vec<Cell>,
    /// Each cell's parameters (the walls of the thickening are built at them).
    params: Vec<Params>,
    clock: Box<dyn Clock>,
    started_ms: f64,
}

/// The phases' bookkeeping and one set of parameters per cell (phase by phase, surfaces in
/// order); the cells' contours come from [`Phases::contours_for`] when each runs.
pub fn plan(
    inputs: Vec<PhaseInput>,
    params: &Params,
    sequence: Option<Sequence>,
    clock: Box<dyn Clock>,
) -> Result<(Phases, Vec<Params>)> {
    if inputs.len() < 2 {
        return Err(CoreError::ParamInvalid {
            name: "phases".into(),
            message: format!(
                "{} phase(s): function needs two or more (end-diastole and end-systole)",
                inputs.len()
            ),
        });
    }
    let mut leave_out: Vec<Vec<String>> = Vec::with_capacity(inputs.len());
    let mut files: Vec<String> = Vec::with_capacity(inputs.len());
    let (names, mut sources): (Vec<String>, Vec<Source>) = inputs
        .into_iter()
        .map(|i| {
            leave_out.push(i.leave_out);
            files.push(i.file);
            (i.name, i.source)
        })
        .unzip();
    if sources.iter().any(|s| matches!(s, Source::Frame(_))) && sequence.is_none() {
        return Err(CoreError::ParamInvalid {
            name: "phases".into(),
            message: "a phase names a time frame, but no file holding a sequence was given".into(),
        });
    }
    let known: Vec<String> = sequence.iter().flat_map(|q| q.surfaces.clone()).collect();
    let mut phases = Phases {
        names,
        files,
        surfaces: Vec::new(),
        sources: Vec::new(),
        sequence,
        cells: Vec::new(),
        params: Vec::new(),
        clock,
        started_ms: 0.0,
    };
    // A sequence the session does not hold: its first frame names the columns (one read).
    if known.is_empty() {
        if let Some(i) = sources.iter().position(|s| matches!(s, Source::Frame(_))) {
            sources[i] = phases.read(&sources[i]);
        }
    }
    // Columns in order of first appearance over the phases, as the CLI's (a frame not read yet
    // counts with the surfaces of the frame the session holds).
    let mut labels: Vec<String> = Vec::new();
    for source in &sources {
        let of_phase = match source {
            Source::Read(Ok(set)) => set.surfaces(),
            Source::Frame(_) => known.clone(),
            Source::Read(Err(_)) => Vec::new(),
        };
        for l in of_phase {
            if !labels.contains(&l) {
                labels.push(l);
            }
        }
    }
    let surfaces: Vec<Option<String>> = if labels.is_empty() {
        vec![None]
    } else {
        labels.into_iter().map(Some).collect()
    };
    let jobs: Vec<Params> = leave_out
        .iter()
        .flat_map(|ids| {
            surfaces.iter().map(|surface| Params {
                surface: surface.clone(),
                leave_out: if ids.is_empty() {
                    params.leave_out.clone()
                } else {
                    ids.clone()
                },
                ..params.clone()
            })
        })
        .collect();
    phases.cells = (0..jobs.len()).map(|_| Cell::default()).collect();
    phases.params = jobs.clone();
    phases.surfaces = surfaces;
    phases.sources = sources;
    Ok((phases, jobs))
}

/// A finished phases batch's anatomical layouts ([`Phases::anatomical`]).
pub struct StudyFiles {
    /// `Study::report`: the layout, the septum and each layout's entry (its `file` or `note`).
    pub report: Value,
    /// The files written, in the report's order: name and bytes.
    pub files: Vec<(String, Vec<u8>)>,
}

/// Whether a surface label is one of the LV's (the layout's surfaces): the command line's
/// `anatomical_study_out::is_lv`.
pub fn is_lv(surface: &str) -> bool {
    surface.to_ascii_uppercase().starts_with("LV") && anatomical::surface_refusal(surface).is_none()
}

/// A file name without its folders (the command line names its input files so).
fn base_name(path: &str) -> &str {
    path.rsplit(['/', '\\']).next().unwrap_or(path)
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

    /// The contours of cell `index`, reading its phase's frame if this is the phase's first
    /// cell; or, for a cell that will not run, its item (the surface absent from the phase, or
    /// the phase unreadable), the cell settled at once.
    pub fn contours_for(&mut self, index: usize) -> std::result::Result<ContourSet, Value> {
        let n = self.surfaces.len().max(1);
        let phase = index / n;
        if let Some(source @ Source::Frame(_)) = self.sources.get(phase) {
            let read = self.read(source);
            self.sources[phase] = read;
        }
        let surface = self.surfaces.get(index % n).cloned().flatten();
        let why = match self.sources.get(phase) {
            Some(Source::Read(Ok(set))) if holds(set, surface.as_deref()) => {
                return Ok(set.as_ref().clone())
            }
            Some(Source::Read(Ok(_))) => ("absent", None),
            Some(Source::Read(Err(e))) => ("failed", Some(e.clone())),
            _ => ("failed", Some("no contours".to_string())),
        };
        self.cells[index] = Cell {
            out: Outcome::none(why.0),
            seconds: 0.0,
            error: why.1,
            base: None,
        };
        Err(self.item(index))
    }

    /// A frame of the sequence read (or why not); any other source as it is.
    fn read(&self, source: &Source) -> Source {
        match (source, &self.sequence) {
            (Source::Frame(frame), Some(q)) => {
                let views = crate::convert::view_pairs(&q.views);
                Source::Read(
                    crate::read_contours(&q.file, &q.bytes, &views, Some(frame))
                        .map(Box::new)
                        .map_err(|e| e.to_string()),
                )
            }
            (Source::Frame(_), None) => Source::Read(Err("no sequence file".to_string())),
            (Source::Read(r), _) => Source::Read(r.clone()),
        }
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
                base: basal_plane(rec).ok(),
            },
            (_, outcome) => Cell {
                out: Outcome::none("failed"),
                seconds,
                error: Some(
                    outcome
                        .err()
                        .map_or("no mesh".to_string(), |e| e.to_string()),
                ),
                base: None,
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

    /// The core's `function::summarise` of the cells.
    fn function(&self) -> Function {
        let labels: Vec<String> = self.surfaces.iter().map(|s| label(s).to_string()).collect();
        let n = labels.len().max(1);
        let measured: Vec<Vec<Measured>> = self
            .cells
            .chunks(n)
            .map(|row| row.iter().map(|c| c.out.measured()).collect())
            .collect();
        summarise(&self.names, &labels, &measured)
    }

    /// The core's `function::summarise` of the cells (`{ventricles, single, lv_mass}`).
    pub fn summary(&self) -> Value {
        let function = self.function();
        let mut value = serde_json::to_value(&function).unwrap_or(Value::Null);
        if let (Some(t), Value::Object(map)) = (self.thickening(&function), &mut value) {
            // The LV wall's thickening by AHA segment, as `heartmesh volumes` gives it.
            match t {
                Ok(t) => {
                    let svg = bullseye::thickening_svg(&t);
                    map.insert("wall_thickening".into(), json!(t));
                    map.insert("thickening_svg".into(), json!(svg));
                }
                Err(why) => {
                    map.insert("wall_thickening".into(), Value::Null);
                    map.insert("wall_thickening_note".into(), json!(why));
                }
            }
        }
        value
    }

    /// The study's anatomical layouts, as `heartmesh volumes --anatomical-meshes` writes them
    /// (core `metrics::anatomical_study`): every phase's LV surfaces (LV_ENDO, LV_EPI, or the
    /// unlabelled column) on `layout`, all turned by the septum of the LV's end-diastole, each
    /// closed mesh with its run's base plane. Returns the report (`Study::report`) and the files,
    /// named `PHASE-SURFACE.ext` as the command line names them; or why there can be none, in the
    /// command line's words (no LV surface measured, no phase saying where the septum is, or the
    /// core's reason).
    pub fn anatomical(&self, layout: Layout, format: MeshFormat) -> Result<StudyFiles> {
        let refuse = |why: &str| Err(CoreError::Degenerate(why.to_string()));
        // What the command line checks before its runs (`anatomical_study_out::check`).
        if !self.surfaces.iter().any(|s| s.as_deref().is_none_or(is_lv)) {
            return refuse(
                "the layouts are of the LV's surfaces (LV_ENDO, LV_EPI), and none is among the \
                 surfaces measured",
            );
        }
        let sets: Vec<Option<&ContourSet>> = self
            .sources
            .iter()
            .map(|s| match s {
                Source::Read(Ok(set)) => Some(set.as_ref()),
                _ => None,
            })
            .collect();
        if !sets.iter().flatten().any(|set| septum::said(set)) {
            return refuse(
                "every layout starts at the septum, and no phase's file has RV_INSERT landmarks \
                 or RV contours to place it by",
            );
        }
        // The items as the command line's `anatomical_layouts` gathers them.
        let n = self.surfaces.len().max(1);
        let mut items = Vec::new();
        for (k, (name, set)) in self.names.iter().zip(&sets).enumerate() {
            let Some(set) = set else { continue };
            for (j, surface) in self.surfaces.iter().enumerate() {
                let s = match surface.as_deref() {
                    None => UNLABELLED,
                    Some(s) if is_lv(s) => s,
                    Some(_) => continue,
                };
                if surface.is_some() && !holds(set, Some(s)) {
                    continue;
                }
                let Some(cell) = self.cells.get(k * n + j) else {
                    continue;
                };
                let closed = cell.out.mesh.as_ref().filter(|_| cell.out.watertight);
                items.push(PhaseSurface {
                    phase: name,
                    surface: s,
                    set,
                    mesh: closed.zip(cell.base.as_ref()),
                });
            }
        }
        let function = self.function();
        let preferred = function
            .ventricles
            .iter()
            .find(|v| v.surface == "LV_ENDO")
            .map(|v| v.ed_phase.as_str());
        let study =
            anatomical_study::of_study(&items, preferred, layout).map_err(CoreError::Degenerate)?;
        let mut names = Vec::with_capacity(study.layouts.len());
        let mut files = Vec::new();
        for l in &study.layouts {
            let input = self
                .names
                .iter()
                .position(|p| *p == l.phase)
                .and_then(|k| self.files.get(k))
                .map(|f| base_name(f))
                .unwrap_or_default();
            match l.file(&study, format, input) {
                Some(bytes) => {
                    let name =
                        format!("{}.{}", file_stem(&l.phase, &l.surface), format.extension());
                    files.push((name.clone(), bytes?));
                    names.push(Some(name));
                }
                None => names.push(None),
            }
        }
        Ok(StudyFiles {
            report: study.report(format, &names),
            files,
        })
    }

    /// [`thickening::of_study`] of the finished cells; None without an LV epicardium.
    fn thickening(&self, f: &Function) -> Option<std::result::Result<Thickening, String>> {
        let n = self.surfaces.len().max(1);
        let column = |name: &str| {
            self.surfaces
                .iter()
                .position(|s| s.as_deref() == Some(name))
        };
        let (endo, epi) = (column("LV_ENDO")?, column("LV_EPI")?);
        let lvs: Vec<PhaseLv> = self
            .names
            .iter()
            .enumerate()
            .filter_map(|(k, name)| match self.sources.get(k) {
                Some(Source::Read(Ok(set))) => Some(PhaseLv {
                    name,
                    set,
                    params: self.params.get(k * n + endo).cloned().unwrap_or_default(),
                    endo: self
                        .cells
                        .get(k * n + endo)
                        .and_then(|c| c.out.mesh.as_ref()),
                    epi: self
                        .cells
                        .get(k * n + epi)
                        .and_then(|c| c.out.mesh.as_ref()),
                }),
                _ => None,
            })
            .collect();
        thickening::of_study(&lvs, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use heartmesh_core::clock::DefaultClock;

    /// A two-frame CSV sequence: the same ring stack twice, the second 0.8 times the size.
    fn cine() -> Vec<u8> {
        let mut out = String::from("contour,x,y,z,surface,phase\n");
        for (phase, scale) in [("ED", 1.0), ("ES", 0.8)] {
            for k in 0..6 {
                let z = -40.0 + 8.0 * k as f64;
                let r = scale * 20.0 * (1.0 - (z / 50.0) * (z / 50.0)).sqrt();
                for i in 0..40 {
                    let t = std::f64::consts::TAU * i as f64 / 40.0;
                    out.push_str(&format!(
                        "s{k},{},{},{z},LV_ENDO,{phase}\n",
                        r * t.cos(),
                        r * t.sin()
                    ));
                }
            }
        }
        out.into_bytes()
    }

    fn sequence(bytes: Vec<u8>) -> Sequence {
        Sequence {
            file: "cine.csv".into(),
            bytes,
            views: Vec::new(),
            surfaces: vec!["LV_ENDO".into()],
        }
    }

    fn frames(names: &[&str]) -> Vec<PhaseInput> {
        names
            .iter()
            .map(|f| PhaseInput {
                name: f.to_string(),
                file: "cine.csv".into(),
                source: Source::Frame(f.to_string()),
                leave_out: Vec::new(),
            })
            .collect()
    }

    /// Frames are read when their first cell runs, not when the batch is planned: planning a
    /// long cine must not hold the worker.
    #[test]
    fn frames_are_read_as_the_batch_reaches_them() {
        let clock = Box::new(DefaultClock::default());
        let (mut p, jobs) = plan(
            frames(&["ED", "ES"]),
            &Params::default(),
            Some(sequence(cine())),
            clock,
        )
        .unwrap();
        assert_eq!(jobs.len(), 2);
        assert!(p.sources.iter().all(|s| matches!(s, Source::Frame(_))));
        let ed = p.contours_for(0).unwrap();
        assert_eq!(ed.contours.len(), 6);
        assert!(matches!(p.sources[0], Source::Read(Ok(_))));
        assert!(matches!(p.sources[1], Source::Frame(_)));
        let es = p.contours_for(1).unwrap();
        let radius = |set: &ContourSet| {
            set.contours[3]
                .points()
                .next()
                .map_or(0.0, |p| p.xy().norm())
        };
        assert!((radius(&es) / radius(&ed) - 0.8).abs() < 1e-6);
    }

    /// An unreadable sequence fails its cells, each with the reason; the plan itself stands.
    #[test]
    fn an_unreadable_frame_fails_its_cells() {
        let clock = Box::new(DefaultClock::default());
        let (mut p, _) = plan(
            frames(&["ED", "ES"]),
            &Params::default(),
            Some(sequence(b"contour,x,y,z\nbroken".to_vec())),
            clock,
        )
        .unwrap();
        let item = p.contours_for(0).unwrap_err();
        assert_eq!(item["missing"], "failed");
        assert!(item["error"].as_str().unwrap().contains("line 2"), "{item}");
        // Frames without a file to read them from are refused at once.
        let clock = Box::new(DefaultClock::default());
        assert!(plan(frames(&["ED", "ES"]), &Params::default(), None, clock).is_err());
    }
}
