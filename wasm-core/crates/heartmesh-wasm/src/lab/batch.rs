//! Many reconstructions in a row, advanced one pipeline step per call so the worker can report
//! progress and honour a cancel between steps: leave-one-out (Villard, Grau & Zacur, J. Imaging
//! 2018, section 3.3, Figures 10-11: rebuild without contour j, measure contour j against the new
//! mesh), a parameter sweep (the same contours rebuilt over a small grid of parameters, each
//! result measured against its contours and, when a truth is known, against the truth), and the
//! phases of one heart (every surface in every phase, for its function: `phases.rs`).
//!
//! The per-job measures are the core's (`metrics::points_to_mesh`, `metrics::compare`); this file
//! only schedules the jobs and describes each finished one as JSON.

use heartmesh_core::contours::{Contour, ContourKind, ContourSet};
use heartmesh_core::error::{CoreError, Result};
use heartmesh_core::metrics::compare::{compare, ClipPlane};
use heartmesh_core::pipeline::Reconstruction;
use heartmesh_core::sim::leave_one_out;
use heartmesh_core::{Params, TriMesh};
use serde_json::{json, Value};

use super::phases::{self, PhaseInput, Phases, Sequence};

/// Largest sweep grid accepted (each point is a full reconstruction).
pub const MAX_SWEEP_JOBS: usize = 256;

/// The four swept parameters, in the order of the plot's axes.
pub const SWEEP_NAMES: [&str; 4] = [
    "lambda",
    "smoothing_iterations",
    "target_reduction",
    "attractor_spacing",
];

enum Kind {
    /// The contour left out of each job, with its kind.
    LeaveOneOut {
        left_out: Vec<(Contour, ContourKind)>,
    },
    /// Each job's swept values (in `SWEEP_NAMES` order), and the truth to measure against.
    Sweep {
        values: Vec<[f64; 4]>,
        truth: Option<(TriMesh, Option<ClipPlane>)>,
    },
    /// Every surface of every phase (the cells' results stay until the summary).
    Phases(Phases),
}

struct Job {
    contours: ContourSet,
    params: Params,
}

/// A queue of reconstructions and the one in progress.
pub struct Batch {
    kind: Kind,
    jobs: Vec<Job>,
    next: usize,
    current: Option<Reconstruction>,
}

/// What one call to [`Batch::step`] did.
pub struct Progress {
    /// Jobs finished so far.
    pub completed: usize,
    pub total: usize,
    /// The job that just finished, described for the page.
    pub item: Option<Value>,
}

impl Batch {
    /// Leave-one-out over the cleaned contours of `set` (the surface `params` selects). Fails only
    /// when the full set cannot be reconstructed.
    pub fn leave_one_out(
        set: &ContourSet,
        params: &Params,
    ) -> Result<(Batch, Vec<Contour>, Vec<ContourKind>)> {
        let plan = leave_one_out::plan(set, params)?;
        let mut left_out = Vec::with_capacity(plan.jobs.len());
        let mut jobs = Vec::with_capacity(plan.jobs.len());
        for held in plan.jobs {
            jobs.push(Job {
                contours: held.rest,
                params: held.params,
            });
            left_out.push((held.contour, held.kind));
        }
        let batch = Batch {
            kind: Kind::LeaveOneOut { left_out },
            jobs,
            next: 0,
            current: None,
        };
        Ok((batch, plan.cleaned, plan.kinds))
    }

    /// Every combination of `grid` (values per swept name; an empty list keeps `base`'s value).
    /// Each combination is validated up front, so a bad value fails before any work.
    pub fn sweep(
        set: &ContourSet,
        base: &Params,
        grid: &[Vec<f64>; 4],
        truth: Option<(TriMesh, Option<ClipPlane>)>,
    ) -> Result<Batch> {
        // Checks the contours once (and selects the surface) before queueing many jobs.
        drop(Reconstruction::new(set, base.clone())?);
        let axes: Vec<Vec<f64>> = SWEEP_NAMES
            .iter()
            .zip(grid)
            .map(|(name, vals)| {
                if vals.is_empty() {
                    vec![base.get(name).unwrap_or(0.0)]
                } else {
                    vals.clone()
                }
            })
            .collect();
        let total: usize = axes.iter().map(Vec::len).product();
        if total > MAX_SWEEP_JOBS {
            return Err(CoreError::ParamInvalid {
                name: "sweep".into(),
                message: format!("{total} combinations; at most {MAX_SWEEP_JOBS}"),
            });
        }
        let mut values = Vec::with_capacity(total);
        let mut jobs = Vec::with_capacity(total);
        for i in 0..total {
            let mut rest = i;
            let mut combo = [0.0; 4];
            // The last axis varies fastest.
            for (k, axis) in axes.iter().enumerate().rev() {
                combo[k] = axis[rest % axis.len()];
                rest /= axis.len();
            }
            let mut params = base.clone();
            for (name, v) in SWEEP_NAMES.iter().zip(combo) {
                params.set(name, v)?;
            }
            params.validate()?;
            values.push(combo);
            jobs.push(Job {
                contours: set.clone(),
                params,
            });
        }
        Ok(Batch {
            kind: Kind::Sweep { values, truth },
            jobs,
            next: 0,
            current: None,
        })
    }

    /// Every surface of each phase at `params` (surfaces in order of first appearance).
    pub fn phases(
        inputs: Vec<PhaseInput>,
        params: &Params,
        sequence: Option<Sequence>,
        clock: Box<dyn heartmesh_core::clock::Clock>,
    ) -> Result<Batch> {
        let (plan, jobs) = phases::plan(inputs, params, sequence, clock)?;
        Ok(Batch {
            kind: Kind::Phases(plan),
            // Each cell's contours are its phase's, read when it starts (`Phases::contours_for`).
            jobs: jobs
                .into_iter()
                .map(|params| Job {
                    contours: ContourSet::default(),
                    params,
                })
                .collect(),
            next: 0,
            current: None,
        })
    }

    /// What the page lays its table out by before any result (phases batch only).
    pub fn layout(&self) -> Option<Value> {
        match &self.kind {
            Kind::Phases(p) => Some(p.layout()),
            _ => None,
        }
    }

    /// The phases' function (`metrics::function::summarise`), once every cell is settled.
    pub fn summary(&self) -> Option<Value> {
        match &self.kind {
            Kind::Phases(p) if self.is_done() => Some(p.summary()),
            _ => None,
        }
    }

    /// The phases batch's plan and results (None for the other batches), for what is made of a
    /// finished one (the study's anatomical layouts).
    pub fn into_phases(self) -> Option<Phases> {
        match self.kind {
            Kind::Phases(p) => Some(p),
            _ => None,
        }
    }

    pub fn total(&self) -> usize {
        self.jobs.len()
    }

    pub fn is_done(&self) -> bool {
        self.current.is_none() && self.next >= self.jobs.len()
    }

    /// Starts the next job or advances the current one by one pipeline step. A job that fails
    /// (e.g. too few contours once one is left out) is reported as an item with an error.
    pub fn step(&mut self) -> Progress {
        let mut item = None;
        if let Some(rec) = self.current.as_mut() {
            let outcome = match rec.step() {
                Ok(report) if report.done => Some(Ok(())),
                Ok(_) => None,
                Err(e) => Some(Err(e)),
            };
            if let Some(outcome) = outcome {
                let rec = self.current.take();
                item = Some(self.describe(self.next - 1, rec.as_ref(), outcome));
            }
        } else if self.next < self.jobs.len() {
            let index = self.next;
            self.next += 1;
            let contours = match &mut self.kind {
                Kind::Phases(p) => {
                    let set = p.contours_for(index).map(Some);
                    p.job_started();
                    set
                }
                _ => Ok(None),
            };
            match contours {
                Err(settled) => item = Some(settled),
                Ok(phase_set) => {
                    let job = &self.jobs[index];
                    let set = phase_set.as_ref().unwrap_or(&job.contours);
                    match Reconstruction::new(set, job.params.clone()) {
                        Ok(rec) => self.current = Some(rec),
                        Err(e) => item = Some(self.describe(index, None, Err(e))),
                    }
                }
            }
        }
        let completed = self.next - usize::from(self.current.is_some());
        Progress {
            completed,
            total: self.jobs.len(),
            item,
        }
    }

    /// The JSON item of job `index`, measured on its finished reconstruction `rec`.
    fn describe(
        &mut self,
        index: usize,
        rec: Option<&Reconstruction>,
        outcome: Result<()>,
    ) -> Value {
        let rec = rec.filter(|_| outcome.is_ok());
        if let Kind::Phases(p) = &mut self.kind {
            return p.finish(index, rec, outcome);
        }
        let error = outcome.err().map(|e| e.to_string());
        match &self.kind {
            Kind::LeaveOneOut { left_out } => {
                let (contour, kind) = match left_out.get(index) {
                    Some((c, k)) => (Some(c), *k),
                    None => (None, ContourKind::Sax),
                };
                let stats = rec
                    .zip(contour)
                    .map(|(r, c)| leave_one_out::held_out_stats(c, r));
                json!({
                    "index": index,
                    "id": contour.map(|c| c.id.clone()),
                    "kind": kind,
                    "stats": stats,
                    "error": error,
                })
            }
            Kind::Sweep { values, truth } => {
                let combo = values.get(index).copied().unwrap_or([f64::NAN; 4]);
                let mut out = json!({
                    "index": index,
                    "lambda": combo[0],
                    "smoothing_iterations": combo[1],
                    "target_reduction": combo[2],
                    "attractor_spacing": combo[3],
                    "error": error,
                });
                if let Some(r) = rec {
                    let mesh = r.mesh();
                    out["contour_mean"] = json!(r.contour_distances().overall.mean);
                    out["contour_max"] = json!(r.contour_distances().overall.max);
                    out["volume_ml"] = json!(mesh.volume_ml());
                    out["triangles"] = json!(mesh.triangles.len());
                    if let Some((t, clip)) = truth {
                        match compare(t, mesh, clip.as_ref()) {
                            Ok(c) => {
                                out["truth_mean"] = json!(c.mesh_to_truth.mean);
                                out["hausdorff"] = json!(c.hausdorff);
                            }
                            Err(e) => out["error"] = json!(e.to_string()),
                        }
                    }
                }
                out
            }
            // Described by `Phases::finish` above.
            Kind::Phases(_) => Value::Null,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use heartmesh_core::sim::shapes::ParametricLv;
    use heartmesh_core::sim::{simulate, AcquisitionSpec, SaxStack};

    fn lv_contours() -> ContourSet {
        let truth = ParametricLv::default().mesh(64, 48).unwrap();
        let spec = AcquisitionSpec {
            sax: SaxStack::Count(5),
            lax_count: 2,
            ..AcquisitionSpec::default()
        };
        simulate(&truth, &spec).unwrap().contours
    }

    fn fast() -> Params {
        let mut p = Params::default();
        p.set("iterations", 40.0).unwrap();
        p
    }

    fn drain(b: &mut Batch) -> Vec<Value> {
        let mut items = Vec::new();
        let mut guard = 0;
        while !b.is_done() {
            if let Some(i) = b.step().item {
                items.push(i);
            }
            guard += 1;
            assert!(guard < 100_000, "batch does not finish");
        }
        items
    }

    #[test]
    fn leave_one_out_reports_every_contour() {
        let set = lv_contours();
        let (mut b, cleaned, kinds) = Batch::leave_one_out(&set, &fast()).unwrap();
        assert_eq!(cleaned.len(), 7);
        assert_eq!(kinds.iter().filter(|k| **k == ContourKind::Lax).count(), 2);
        let items = drain(&mut b);
        assert_eq!(items.len(), 7);
        for (j, it) in items.iter().enumerate() {
            assert_eq!(it["index"], j);
            let mean = it["stats"]["mean"].as_f64().unwrap_or(f64::NAN);
            println!("leave-one-out contour {j}: mean {mean:.3} mm");
            // A smooth spheroid predicts its missing inner slices to well under a millimetre; the
            // most apical SAX sits close to the tip, so without it the apex is extrapolated from
            // the long-axis curves alone (3.3 mm measured).
            let limit = if j == 0 { 5.0 } else { 1.0 };
            assert!(mean.is_finite() && mean < limit, "contour {j}: {it}");
        }
    }

    /// A contour the user left out is out of every rebuild and not held out in turn: six jobs,
    /// none failing (the rebuilds' sets lack it, so they must not name it again).
    #[test]
    fn leave_one_out_keeps_the_users_contours_out() {
        let set = lv_contours();
        let lax = set
            .contours
            .iter()
            .rev()
            .map(|c| c.id.clone())
            .next()
            .unwrap();
        let params = Params {
            leave_out: vec![lax.clone()],
            ..fast()
        };
        let (mut b, cleaned, _) = Batch::leave_one_out(&set, &params).unwrap();
        assert_eq!(cleaned.len(), 6);
        assert!(cleaned.iter().all(|c| c.id != lax));
        let items = drain(&mut b);
        assert_eq!(items.len(), 6);
        for it in &items {
            assert!(it["error"].is_null(), "{it}");
            assert!(
                it["stats"]["mean"].as_f64().is_some_and(f64::is_finite),
                "{it}"
            );
        }
    }

    #[test]
    fn sweep_covers_the_grid_in_order() {
        let set = lv_contours();
        let grid = [vec![1e3, 1e5], vec![], vec![0.5, 0.72], vec![]];
        let mut b = Batch::sweep(&set, &fast(), &grid, None).unwrap();
        assert_eq!(b.total(), 4);
        let items = drain(&mut b);
        assert_eq!(items.len(), 4);
        assert_eq!(items[1]["lambda"], 1e3);
        assert_eq!(items[1]["target_reduction"], 0.72);
        assert_eq!(items[2]["lambda"], 1e5);
        for it in &items {
            let m = it["contour_mean"].as_f64().unwrap();
            assert!(m > 0.0 && m < 2.0, "{it}");
        }
        let too_big = [vec![1.0; 10], vec![1.0; 10], vec![0.5; 10], vec![]];
        assert!(Batch::sweep(&set, &fast(), &too_big, None).is_err());
        let bad = [vec![-1.0], vec![], vec![], vec![]];
        assert!(Batch::sweep(&set, &fast(), &bad, None).is_err());
    }
}
