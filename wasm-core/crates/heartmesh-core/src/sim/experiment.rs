//! Runs the validation experiments of Villard, Grau & Zacur (J. Imaging 2018, section 3): for each
//! trial of a [`Design`], slice the truth like a scanner ([`simulate`]), reconstruct, and measure
//! the result against the truth both ways, clipped at the most basal SAX plane as the paper does
//! ([`compare`]), plus the contour-to-mesh distance that is all one has on real data.
//!
//! Built for every caller: no threads, no files, no wall clock of its own (the caller may inject
//! one, as wasm must), and work is handed out in small steps ([`Experiment::step`]: one
//! reconstruction iteration at a time) so a browser worker can report progress and cancel between
//! steps. Results depend only on the trials (every acquisition is seeded); only `seconds` varies.

use super::experiment_design::{Subject, Trial};
use super::planes::{simulate, Acquisition};
use crate::clock::{Clock, DefaultClock};
use crate::error::Result;
use crate::mesh::quality::quality;
use crate::mesh::topology::validity;
use crate::metrics::compare::{compare, DistanceStats};
use crate::pipeline::Reconstruction;
use serde::Serialize;

pub use super::experiment_design::{trials, Design, RV_JOIN_GAP_MM};

/// The measures of one finished trial (mm and ml).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Metrics {
    pub mesh_to_truth: DistanceStats,
    pub truth_to_mesh: DistanceStats,
    pub hausdorff: f64,
    /// Volumes below the clip plane, capped flat.
    pub volume_truth_ml: f64,
    pub volume_mesh_ml: f64,
    /// Mesh minus truth.
    pub volume_diff_ml: f64,
    pub volume_diff_percent: f64,
    /// Distances of the simulated contour points to the reconstruction (what real data offers).
    pub contour_to_mesh_mean: f64,
    pub contour_to_mesh_max: f64,
    /// Where the truth is farthest from the reconstruction: height along the long axis, 0 at the
    /// truth's apex, 1 at its top (NaN if the axis gives no extent).
    pub worst_height: f64,
    /// Enclosed volume of the whole reconstruction, not clipped: what a user of real data gets,
    /// including any part extrapolated past an end no curve closes.
    pub volume_mesh_unclipped_ml: f64,
    /// How far the reconstruction reaches past the highest / lowest contour point along the long
    /// axis ([`crate::metrics::extent`]), and the same for the truth: their difference is the
    /// overrun (or shortfall) at an open end, which the clipped measures above cannot see.
    pub past_base_mm: f64,
    pub past_apex_mm: f64,
    pub truth_past_base_mm: f64,
    pub truth_past_apex_mm: f64,
    /// Creased edges of the reconstruction (dihedral > 90 degrees, [`quality`]).
    pub folded_edges: usize,
    /// Pairs of triangles passing through each other ([`crate::mesh::intersect`]).
    pub self_intersections: usize,
    /// Closed, manifold, consistently oriented and enclosing a positive volume (outward).
    pub closed_manifold_outward: bool,
}

/// One line of an experiment's table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Row {
    /// Index of the trial in the experiment.
    pub trial: usize,
    pub shape: String,
    /// The varied settings, as in [`Trial::settings`].
    pub settings: Vec<(String, f64)>,
    /// Contours actually obtained (a plane may miss the shape).
    pub sax: usize,
    pub lax: usize,
    /// Deformation iterations run.
    pub iterations: usize,
    /// None when the trial failed (see `error`). Boxed: rows travel through progress reports.
    pub metrics: Option<Box<Metrics>>,
    /// Reconstruction time by the experiment's clock (0 on wasm without an injected clock).
    pub seconds: f64,
    pub error: Option<String>,
}

/// What one [`Experiment::step`] did.
#[derive(Debug, Clone, PartialEq)]
pub enum Progress {
    /// Trial `trial` advanced its reconstruction to `iteration` of `total`.
    Working {
        trial: usize,
        iteration: usize,
        total: usize,
    },
    /// Trial finished (successfully or not).
    Finished(Row),
}

struct Running {
    trial: usize,
    acq: Acquisition,
    rec: Reconstruction,
    ms: f64,
}

/// A runnable list of trials. Iterating yields one [`Row`] per trial, in order.
pub struct Experiment {
    subjects: Vec<Subject>,
    trials: Vec<Trial>,
    next: usize,
    running: Option<Running>,
    clock: Box<dyn Clock>,
}

impl Experiment {
    /// An experiment of `design` over `subjects`, every reconstruction starting from `params`.
    /// Fails (before any work) on an invalid design or parameter.
    pub fn new(
        design: &Design,
        subjects: Vec<Subject>,
        params: &crate::params::Params,
    ) -> Result<Experiment> {
        let trials = trials(design, &subjects, params)?;
        Ok(Experiment::from_trials(subjects, trials))
    }

    /// An experiment of explicit trials (each names its subject by index; a trial whose index
    /// is out of range finishes with an error row).
    pub fn from_trials(subjects: Vec<Subject>, trials: Vec<Trial>) -> Experiment {
        Experiment {
            subjects,
            trials,
            next: 0,
            running: None,
            clock: Box::new(DefaultClock::default()),
        }
    }

    /// Replaces the clock used for `seconds` (wasm: one backed by `performance.now()`).
    pub fn set_clock(&mut self, clock: Box<dyn Clock>) {
        self.clock = clock;
    }

    pub fn trials(&self) -> &[Trial] {
        &self.trials
    }

    pub fn subjects(&self) -> &[Subject] {
        &self.subjects
    }

    /// Number of trials finished so far.
    pub fn finished(&self) -> usize {
        self.next
    }

    pub fn is_done(&self) -> bool {
        self.next >= self.trials.len()
    }

    /// Does one small piece of work: starts a trial (simulation, set-up and the initial tube),
    /// runs one reconstruction iteration, or measures a finished reconstruction. None when every
    /// trial is done. Stopping between calls cancels cleanly.
    pub fn step(&mut self) -> Option<Progress> {
        let mut run = match self.running.take() {
            Some(r) => r,
            None => {
                if self.is_done() {
                    return None;
                }
                match self.start(self.next) {
                    Ok(r) => r,
                    Err(row) => return Some(self.finish_with(row)),
                }
            }
        };
        let t0 = self.clock.now_ms();
        let stepped = run.rec.step();
        run.ms += self.clock.now_ms() - t0;
        match stepped {
            Err(e) => {
                let row = self.error_row(run.trial, Some(&run.acq), e.to_string());
                Some(self.finish_with(row))
            }
            Ok(report) if report.done => {
                let row = self.measure(&run);
                Some(self.finish_with(row))
            }
            Ok(report) => {
                let progress = Progress::Working {
                    trial: run.trial,
                    iteration: report.iteration,
                    total: run.rec.total_iterations(),
                };
                self.running = Some(run);
                Some(progress)
            }
        }
    }

    /// Runs every remaining trial; `on_progress` sees every step and returns false to cancel.
    /// Returns the rows finished by this call.
    pub fn run(&mut self, mut on_progress: impl FnMut(&Progress) -> bool) -> Vec<Row> {
        let mut rows = Vec::new();
        while let Some(p) = self.step() {
            let go_on = on_progress(&p);
            if let Progress::Finished(row) = p {
                rows.push(row);
            }
            if !go_on {
                break;
            }
        }
        rows
    }

    fn start(&self, t: usize) -> std::result::Result<Running, Row> {
        let trial = &self.trials[t];
        let subject = self
            .subjects
            .get(trial.subject)
            .ok_or_else(|| self.error_row(t, None, "no such subject".into()))?;
        let acq = simulate(&subject.mesh, &trial.spec)
            .map_err(|e| self.error_row(t, None, format!("simulate: {e}")))?;
        let rec = Reconstruction::new(&acq.contours, trial.params.clone())
            .map_err(|e| self.error_row(t, Some(&acq), e.to_string()))?;
        Ok(Running {
            trial: t,
            acq,
            rec,
            ms: 0.0,
        })
    }

    fn finish_with(&mut self, row: Row) -> Progress {
        self.next += 1;
        Progress::Finished(row)
    }

    fn blank_row(&self, t: usize, acq: Option<&Acquisition>) -> Row {
        let trial = &self.trials[t];
        let count = |prefix: &str| {
            acq.map_or(0, |a| {
                a.contours
                    .contours
                    .iter()
                    .filter(|c| c.id.starts_with(prefix))
                    .count()
            })
        };
        Row {
            trial: t,
            shape: self
                .subjects
                .get(trial.subject)
                .map_or_else(|| format!("subject {}", trial.subject), |s| s.name.clone()),
            settings: trial.settings.clone(),
            sax: count("sax"),
            lax: count("lax"),
            iterations: 0,
            metrics: None,
            seconds: 0.0,
            error: None,
        }
    }

    fn error_row(&self, t: usize, acq: Option<&Acquisition>, error: String) -> Row {
        Row {
            error: Some(error),
            ..self.blank_row(t, acq)
        }
    }

    fn measure(&self, run: &Running) -> Row {
        let mut row = self.blank_row(run.trial, Some(&run.acq));
        row.iterations = run.rec.iteration();
        row.seconds = run.ms / 1e3;
        let truth = &self.subjects[self.trials[run.trial].subject].mesh;
        match compare(truth, run.rec.mesh(), Some(&run.acq.clip)) {
            Ok(r) => {
                let c2m = run.rec.contour_distances().overall;
                let nan = crate::metrics::extent::PastData {
                    base_mm: f64::NAN,
                    apex_mm: f64::NAN,
                };
                let past = run.rec.past_data().unwrap_or(nan);
                let truth_past = run.rec.past_data_of(&truth.positions).unwrap_or(nan);
                let diff = r.volume_mesh_ml - r.volume_truth_ml;
                let q = quality(run.rec.mesh());
                row.metrics = Some(Box::new(Metrics {
                    mesh_to_truth: r.mesh_to_truth,
                    truth_to_mesh: r.truth_to_mesh,
                    hausdorff: r.hausdorff,
                    volume_truth_ml: r.volume_truth_ml,
                    volume_mesh_ml: r.volume_mesh_ml,
                    volume_diff_ml: diff,
                    volume_diff_percent: if r.volume_truth_ml > 0.0 {
                        100.0 * diff / r.volume_truth_ml
                    } else {
                        f64::NAN
                    },
                    contour_to_mesh_mean: c2m.mean,
                    contour_to_mesh_max: c2m.max,
                    worst_height: height_fraction(&run.acq, truth, r.truth_to_mesh.max_at),
                    volume_mesh_unclipped_ml: run.rec.mesh().volume_ml(),
                    past_base_mm: past.base_mm,
                    past_apex_mm: past.apex_mm,
                    truth_past_base_mm: truth_past.base_mm,
                    truth_past_apex_mm: truth_past.apex_mm,
                    folded_edges: q.folded_edges,
                    self_intersections: q.self_intersections,
                    closed_manifold_outward: validity(run.rec.mesh()).is_closed_manifold()
                        && run.rec.mesh().signed_volume() > 0.0,
                }));
            }
            Err(e) => row.error = Some(format!("compare: {e}")),
        }
        row
    }
}

/// Height of `p` along the acquisition's long axis, 0 at the truth's lowest point, 1 at its top.
fn height_fraction(acq: &Acquisition, truth: &crate::mesh::TriMesh, p: [f64; 3]) -> f64 {
    match acq.axis.extent(truth) {
        Some((lo, hi, _)) if hi > lo => {
            (acq.axis
                .height(&crate::geometry::Vec3::new(p[0], p[1], p[2]))
                - lo)
                / (hi - lo)
        }
        _ => f64::NAN,
    }
}

impl Iterator for Experiment {
    type Item = Row;

    /// Runs steps until the next trial finishes.
    fn next(&mut self) -> Option<Row> {
        loop {
            if let Progress::Finished(row) = self.step()? {
                return Some(row);
            }
        }
    }
}

/// Metric columns of [`to_csv`], after the settings.
pub const METRIC_COLUMNS: [&str; 26] = [
    "mesh_to_truth_mean",
    "mesh_to_truth_median",
    "mesh_to_truth_p95",
    "mesh_to_truth_max",
    "truth_to_mesh_mean",
    "truth_to_mesh_median",
    "truth_to_mesh_p95",
    "truth_to_mesh_max",
    "hausdorff",
    "volume_truth_ml",
    "volume_mesh_ml",
    "volume_diff_ml",
    "volume_diff_percent",
    "contour_to_mesh_mean",
    "contour_to_mesh_max",
    "worst_height",
    "volume_mesh_unclipped_ml",
    "past_base_mm",
    "past_apex_mm",
    "truth_past_base_mm",
    "truth_past_apex_mm",
    "folded_edges",
    "self_intersections",
    "closed_manifold_outward",
    "seconds",
    "error",
];

/// Index of the first [`Metrics::values`] entry that is a whole number (folds, self-intersections,
/// the validity flag).
const COUNT_COLUMNS_FROM: usize = 21;

impl Metrics {
    /// Values in the order of [`METRIC_COLUMNS`] (without seconds and error).
    pub fn values(&self) -> [f64; 24] {
        let (a, b) = (&self.mesh_to_truth, &self.truth_to_mesh);
        [
            a.mean,
            a.median,
            a.p95,
            a.max,
            b.mean,
            b.median,
            b.p95,
            b.max,
            self.hausdorff,
            self.volume_truth_ml,
            self.volume_mesh_ml,
            self.volume_diff_ml,
            self.volume_diff_percent,
            self.contour_to_mesh_mean,
            self.contour_to_mesh_max,
            self.worst_height,
            self.volume_mesh_unclipped_ml,
            self.past_base_mm,
            self.past_apex_mm,
            self.truth_past_base_mm,
            self.truth_past_apex_mm,
            self.folded_edges as f64,
            self.self_intersections as f64,
            if self.closed_manifold_outward {
                1.0
            } else {
                0.0
            },
        ]
    }
}

impl Row {
    /// A metric by its column name ([`METRIC_COLUMNS`], or `seconds`); None for a failed trial.
    pub fn metric(&self, name: &str) -> Option<f64> {
        if name == "seconds" {
            return Some(self.seconds);
        }
        let k = METRIC_COLUMNS.iter().position(|c| *c == name)?;
        self.metrics
            .as_ref()
            .and_then(|m| m.values().get(k).copied())
    }

    /// The value of a varied setting.
    pub fn setting(&self, name: &str) -> Option<f64> {
        self.settings
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| *v)
    }
}

/// The rows as CSV: `trial,shape,<settings...>,sax_contours,lax_contours,iterations,<METRIC_COLUMNS>`, one line per
/// row; distances in mm with 4 decimals, volumes in ml; failed trials have empty metrics and the
/// error text.
pub fn to_csv(rows: &[Row]) -> String {
    let mut setting_names: Vec<&str> = Vec::new();
    for r in rows {
        for (n, _) in &r.settings {
            if !setting_names.contains(&n.as_str()) {
                setting_names.push(n);
            }
        }
    }
    let mut out = String::from("trial,shape");
    for n in &setting_names {
        out.push(',');
        out.push_str(&quote(n));
    }
    out.push_str(",sax_contours,lax_contours,iterations");
    for c in METRIC_COLUMNS {
        out.push(',');
        out.push_str(c);
    }
    out.push('\n');
    for r in rows {
        out.push_str(&format!("{},{}", r.trial, quote(&r.shape)));
        for n in &setting_names {
            out.push(',');
            if let Some(v) = r.setting(n) {
                out.push_str(&format!("{v}"));
            }
        }
        out.push_str(&format!(",{},{},{}", r.sax, r.lax, r.iterations));
        match &r.metrics {
            Some(m) => {
                for (k, v) in m.values().into_iter().enumerate() {
                    // The last two are a count and a 0/1 flag.
                    if k >= COUNT_COLUMNS_FROM {
                        out.push_str(&format!(",{v}"));
                    } else {
                        out.push_str(&format!(",{v:.4}"));
                    }
                }
            }
            None => out.push_str(&",".repeat(23)),
        }
        out.push_str(&format!(
            ",{:.3},{}\n",
            r.seconds,
            r.error.as_deref().map(quote).unwrap_or_default()
        ));
    }
    out
}

/// CSV field quoting (RFC 4180) when needed.
fn quote(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Params;
    use crate::sim::shapes::ParametricLv;

    fn lv() -> Subject {
        Subject::new("param,lv", ParametricLv::default().mesh(64, 40).unwrap())
    }

    fn quick() -> Params {
        Params {
            iterations: 40,
            ..Params::default()
        }
    }

    #[test]
    fn more_sax_slices_reduce_the_error() {
        let design = Design::SaxCount {
            counts: vec![2, 8],
            lax: Some(0),
        };
        // Without end caps (the paper's method): open ends are extrapolated, which the overrun
        // columns below must show.
        let params = Params {
            end_caps: crate::params::EndCapMode::Off,
            ..quick()
        };
        let rows: Vec<Row> = Experiment::new(&design, vec![lv()], &params)
            .unwrap()
            .collect();
        assert_eq!(rows.len(), 2);
        let err = |r: &Row| {
            assert!(r.error.is_none(), "{:?}", r.error);
            r.metric("truth_to_mesh_mean").unwrap()
        };
        eprintln!(
            "EXPERIMENT truth->mesh mean: 2 SAX {:.3} mm, 8 SAX {:.3} mm",
            err(&rows[0]),
            err(&rows[1])
        );
        assert_eq!((rows[0].sax, rows[0].lax), (2, 0));
        assert_eq!((rows[1].sax, rows[1].lax), (8, 0));
        assert_eq!(rows[1].iterations, 40);
        // Two rings near the ends and no LAX: the straight tube between them misses the widest
        // part of the spheroid, at mid-height.
        let h = rows[0].metric("worst_height").unwrap();
        assert!((0.25..=0.75).contains(&h), "worst height {h}");
        // Two rings and flat lids miss the apex dome by millimetres; eight rings follow it.
        assert!(
            err(&rows[1]) < 0.5 * err(&rows[0]),
            "8 SAX {:.3} mm vs 2 SAX {:.3} mm",
            err(&rows[1]),
            err(&rows[0])
        );
        assert!(err(&rows[1]) < 1.0, "8 SAX {:.3} mm", err(&rows[1]));
        for r in &rows {
            let m = |k: &str| r.metric(k).unwrap();
            eprintln!(
                "EXPERIMENT {} SAX: volume clipped {:.2} unclipped {:.2} ml; past base {:.2} (truth \
                 {:.2}) apex {:.2} (truth {:.2}) mm",
                r.sax,
                m("volume_mesh_ml"),
                m("volume_mesh_unclipped_ml"),
                m("past_base_mm"),
                m("truth_past_base_mm"),
                m("past_apex_mm"),
                m("truth_past_apex_mm")
            );
            assert!(m("volume_mesh_unclipped_ml") >= m("volume_mesh_ml") - 1e-6);
        }
        // What the clipped measures cannot see: two rings and no long-axis curve leave both ends
        // to extrapolation, and the mesh runs on far past the truth's rim (session 9's overrun).
        let over =
            |r: &Row| r.metric("past_base_mm").unwrap() - r.metric("truth_past_base_mm").unwrap();
        assert!(
            over(&rows[0]) > 10.0,
            "2 SAX overrun {:.2} mm",
            over(&rows[0])
        );
        assert!(
            over(&rows[1]).abs() < 1.5,
            "8 SAX overrun {:.2} mm",
            over(&rows[1])
        );
        let csv = to_csv(&rows);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(lines[0].starts_with(
            "trial,shape,sax,sax_contours,lax_contours,iterations,mesh_to_truth_mean"
        ));
        assert!(lines[1].starts_with("0,\"param,lv\",2,2,0,40,"));
        assert_eq!(lines[1].split(',').count(), lines[0].split(',').count() + 1);
    }

    #[test]
    fn steps_report_progress_and_cancel() {
        let design = Design::LaxCount {
            counts: vec![1, 2],
            sax: 3,
        };
        let params = Params {
            iterations: 5,
            ..Params::default()
        };
        let mut exp = Experiment::new(&design, vec![lv()], &params).unwrap();
        let mut seen = Vec::new();
        let rows = exp.run(|p| {
            seen.push(p.clone());
            !matches!(p, Progress::Finished(_))
        });
        // Tube, then iterations 1..=5; the fifth finishes the first trial and cancels.
        assert_eq!(rows.len(), 1);
        assert_eq!(exp.finished(), 1);
        assert!(!exp.is_done());
        assert_eq!(
            seen[1],
            Progress::Working {
                trial: 0,
                iteration: 1,
                total: 5
            }
        );
        assert!(matches!(seen.last(), Some(Progress::Finished(r)) if r.lax == 1));
        let rest: Vec<Row> = exp.collect();
        assert_eq!(rest.len(), 1);
        assert_eq!((rest[0].trial, rest[0].lax, rest[0].sax), (1, 2, 3));
    }

    #[test]
    fn failures_become_rows() {
        let flat = Subject::new("tetrahedron", crate::mesh::shapes::unit_tetrahedron());
        let rows: Vec<Row> = Experiment::new(&Design::lax_count(), vec![flat], &quick())
            .unwrap()
            .collect();
        assert_eq!(rows.len(), 8);
        assert!(rows
            .iter()
            .all(|r| r.error.is_some() && r.metrics.is_none()));
        let csv = to_csv(&rows);
        assert_eq!(csv.lines().count(), 9);
        assert!(rows[0].metric("hausdorff").is_none());
    }
}
