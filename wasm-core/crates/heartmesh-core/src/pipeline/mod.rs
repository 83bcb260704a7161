//! The reconstruction pipeline of Villard, Grau & Zacur, "Surface Mesh Reconstruction from Cardiac
//! MRI Contours", J. Imaging 2018, 4(1):16, as a stepping state machine: `new` validates everything,
//! `step` advances one iteration (so callers can show and cancel every step), `run` loops.
//!
//! The deformation runs in normalised units (centred on the contour points, divided by their largest
//! inter-point distance) so that lambda, beta and the stop threshold do not depend on the size of the
//! heart; everything handed out is converted back to millimetres.

pub mod apex_floor;
pub mod budget;
pub mod crescent;
mod diameter;
pub mod dome;
mod end_data;
pub mod ends;
pub mod growth;
mod lid_disc;
pub mod lid_pull;
pub mod lid_tips;
mod phases;
#[cfg(test)]
mod precision;
mod prepare;
mod remesh_guard;
#[cfg(test)]
mod reuse;
mod rim_lid;
pub mod solve_cost;
pub mod tube;

use crate::clock::{Clock, DefaultClock};
use crate::contours::align::{
    align_slices_with, anchored_beyond_rv, crossing_residual, left_out_shifts, Alignment,
    Options as AlignOptions, SUGGEST_ALIGNMENT_ABOVE_MM,
};
use crate::contours::axis::Layout;
use crate::contours::biv_epi;
use crate::contours::clean::{contour_spikes, resample_spacing, ContourSpikes};
use crate::contours::far_pieces::{contour_far, ContourFar};
use crate::contours::off_plane::{self, ContourOffPlane};
use crate::contours::set_aside::{self, SetAside};
use crate::contours::valve_chord::open_valve_chords;
use crate::contours::{Contour, ContourKind, ContourSet};
use crate::deform::attractors::{conflict_weights, Budget};
use crate::deform::tps::TpsSolver;
use crate::error::{CoreError, Result};
use crate::geometry::{order_free_centroid, Vec3};
use crate::mesh::TriMesh;
use crate::metrics::{
    contour_points_to_mesh, contour_to_mesh, per_contour_stats, vertex_to_contours,
    ContourDistances, Stats,
};
use crate::parallel;
use crate::params::{AttractorMode, Params};
use crate::spatial::{Bvh, ClosestHit};
use diameter::diameter;
pub use remesh_guard::SkippedRemesh;
use serde::Serialize;

/// Spacing (mm) of the contour resampling that feeds attractor selection.
const CANDIDATE_SPACING_MM: f64 = 1.0;
/// Attractors of different contours closer than this (mm) are compared for conflicts: twice the
/// largest disagreement between contours that is normal in cine CMR (1-5 mm of segmentation and
/// breath-hold error, METHOD.md), so any two data points such an error can pull apart are paired.
const CONFLICT_RADIUS_MM: f64 = 10.0;
/// Displacement gradient above which conflicting attractors are down-weighted. A map x -> x + d(x)
/// is one-to-one while the gradient of d stays below 1; the gradient here is a difference quotient
/// between attractors 5-10 mm apart, which underestimates the peak of the field between them, so
/// the limit is half that bound (1 itself left 19 folded edges on the real cases instead of 8:
/// docs/VALIDATION.md, session 4).
const CONFLICT_GRADIENT_LIMIT: f64 = 0.5;
/// The fewest attractors a thin-plate spline in 3D can use (4 affine terms + 1).
const MIN_ATTRACTORS: usize = 5;

/// Cap of the automatic attractor count max(150, 25 x contours): the largest count the
/// `attractors` parameter allows, so that many contours cannot ask for an unsolvable TPS.
const MAX_AUTO_ATTRACTORS: usize = 5000;

/// What the last step did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Phase {
    /// Step 0: the ruled tube (after its first remesh) was built.
    InitialTube,
    /// A thin-plate-spline deformation step.
    Deform,
    /// A deformation step followed by subdivide + smooth + decimate.
    Remesh,
    /// Finished (iterations exhausted or converged); further steps do nothing.
    Done,
}

/// Moves each of `contours` (left out of an aligned run of `file`) as the alignment moved the
/// image it lies in ([`left_out_shifts`]).
fn shift_with_images(contours: &mut [Contour], file: &ContourSet, alignment: &Alignment) {
    let named: Vec<(&str, usize)> = contours
        .iter()
        .map(|c| (c.id.as_str(), c.first_line))
        .collect();
    let shifts = left_out_shifts(file, &named, alignment);
    for (c, t) in contours.iter_mut().zip(shifts) {
        for p in c.pieces.iter_mut().flat_map(|p| p.points.iter_mut()) {
            *p += t;
        }
    }
}

/// `contours` without those `set_aside` names (by identifier and file line).
fn without_set_aside(contours: Vec<Contour>, set_aside: &[SetAside]) -> Vec<Contour> {
    contours
        .into_iter()
        .filter(|c| {
            !set_aside
                .iter()
                .any(|s| s.id == c.id && s.line == c.first_line)
        })
        .collect()
}

/// A contour left out of the run ([`SetAside`]: its id, line and why) and the distances (mm) of
/// its points to the finished mesh: mean, median and max, as the report's `per_contour` has them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SetAsideDistance {
    #[serde(flatten)]
    pub contour: SetAside,
    pub mean: f64,
    pub median: f64,
    pub max: f64,
}

/// Milliseconds spent per phase in the last step.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct PhaseTimings {
    pub attractors_ms: f64,
    pub closest_ms: f64,
    pub solve_ms: f64,
    pub apply_ms: f64,
    pub remesh_ms: f64,
    pub total_ms: f64,
}

impl std::ops::AddAssign for PhaseTimings {
    fn add_assign(&mut self, o: Self) {
        self.attractors_ms += o.attractors_ms;
        self.closest_ms += o.closest_ms;
        self.solve_ms += o.solve_ms;
        self.apply_ms += o.apply_ms;
        self.remesh_ms += o.remesh_ms;
        self.total_ms += o.total_ms;
    }
}

/// Report of one step, small enough to send to the browser every frame.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepReport {
    /// 0 for the initial tube, then 1..=iterations.
    pub iteration: usize,
    pub total_iterations: usize,
    pub phase: Phase,
    /// The vertex/triangle arrays were rebuilt (remesh, initial tube): renderers rebuild geometry.
    pub topology_changed: bool,
    /// The attractors were re-sampled in this step.
    pub attractors_changed: bool,
    /// Max and mean attractor-to-mesh distance in mm, measured before this step's deformation.
    pub max_distance_mm: f64,
    pub mean_distance_mm: f64,
    pub vertices: usize,
    pub triangles: usize,
    pub attractors: usize,
    pub timings: PhaseTimings,
    pub done: bool,
}

/// Maps millimetres to the scale-free units of the deformation loop and back.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Normalisation {
    centre: Vec3,
    scale: f64,
}

impl Normalisation {
    fn to_unit(self, p: &Vec3) -> Vec3 {
        (p - self.centre) / self.scale
    }
    fn to_mm(self, p: &Vec3) -> Vec3 {
        p * self.scale + self.centre
    }
}

/// A reconstruction in progress. See the module docs for the method.
pub struct Reconstruction {
    params: Params,
    contours: Vec<Contour>,
    /// The selected surface's contours with points left out as spikes (damaged values,
    /// `contours::clean::spikes`), in the file's order.
    spikes: Vec<ContourSpikes>,
    /// What the cleaning left out of each contour as far from its surface (`far_pieces`).
    far: Vec<ContourFar>,
    /// What the cleaning left out of each contour as off its plane (`off_plane`).
    off_plane: Vec<ContourOffPlane>,
    /// What the mesh is fitted to: `contours` with long-axis curves closed across the valve opened
    /// there (`valve_chord`); measured distances stay those to `contours`, as drawn.
    fitted: Vec<Contour>,
    /// The ids of the long-axis curves opened at their valve chord.
    valve_chords: Vec<String>,
    /// The selected surface's contours left out of the run: the user's (`Params::leave_out`),
    /// then the rules' (strays, specks: `set_aside`).
    set_aside: Vec<SetAside>,
    /// The contours `set_aside` names (cleaned, in mm), one per entry in its order: the mesh is
    /// measured against them once built ([`Reconstruction::set_aside_distances`]).
    set_aside_contours: Vec<Contour>,
    /// With `align_slices`: what the alignment did, and the selected contours as the file gave
    /// them (cleaned; None if cleaning split them differently from the shifted ones).
    alignment: Option<Alignment>,
    contours_as_given: Option<Vec<Contour>>,
    /// How far apart the file's images are where their planes cross (mm, whole file, before any
    /// alignment; None when no curves of one surface cross).
    crossing_residual_mm: Option<f64>,
    /// Some surface of the file is not the RV's ([`anchored_beyond_rv`]): the alignment is only
    /// suggested then.
    alignment_anchored: bool,
    layout: Layout,
    norm: Normalisation,
    /// Contour points resampled at ~1 mm, normalised: the attractor candidates.
    candidates: Vec<Vec3>,
    /// Kind of the contour each candidate comes from (0 short axis, 1 long axis).
    candidate_owner: Vec<u32>,
    attractor_budget: Budget,
    /// The contour attractors first, then the end caps' lid points (`ends`; normalised).
    attractors: Vec<Vec3>,
    /// How many of `attractors` are contour points (the rest are lid points, never data).
    real_attractors: usize,
    /// Lid points of the ends no curve closes (normalised), appended at every resampling.
    cap_points: Vec<Vec3>,
    /// Each lid point's plane normal and tolerance (normalised units): `lid_pull`.
    cap_sides: Vec<lid_pull::LidSide>,
    /// The lid points' weights of the last step (`lid_pull::decide`: which pulled).
    cap_weights: Vec<f64>,
    end_caps: ends::EndCapsReport,
    /// A base left without a lid for want of room (`end_caps.base_too_narrow`), until its late
    /// rim lid is laid or tried (`rim_lid`).
    open_base: Option<rim_lid::OpenBase>,
    attractor_owner: Vec<u32>,
    /// Per-attractor data weights of the current step (conflict softening).
    weights: Vec<f64>,
    /// The last fit used `weights` (some attractors conflicted).
    weighted: bool,
    /// Fewest triangles a remesh may leave: the initial tube's ([`capped_reduction`]).
    min_triangles: usize,
    /// Both ends of the tube are lidded: the mesh is closed and encloses a volume.
    lidded: bool,
    /// Working mesh in normalised units, and its copy in mm handed to callers.
    mesh_unit: TriMesh,
    mesh_mm: TriMesh,
    bvh: Option<Bvh>,
    tps: TpsSolver,
    /// Scratch buffers reused every iteration.
    closest: Vec<Vec3>,
    /// Per attractor, the triangle of its last closest point: the starting candidate of the next
    /// query (same answer, fewer boxes visited).
    hints: Vec<u32>,
    /// Per attractor, its closest-point query's answer (scratch of `closest_points`).
    hits: Vec<Option<ClosestHit>>,
    targets: Vec<Vec3>,
    fps_scratch: Vec<f64>,
    /// Seed and result of the last farthest-point sampling: the candidates never change, so the
    /// same seed gives the same attractors without the O(candidates x attractors) pass.
    fps_last: Option<(usize, Vec<usize>)>,
    iteration: usize,
    /// Iteration of the last remesh (0: the initial tube).
    last_remesh: usize,
    /// The remeshes skipped because they would have wrecked the surface (`remesh_guard`).
    skipped_remeshes: Vec<SkippedRemesh>,
    /// First iteration at which the method's stop rule held ([`Reconstruction::step`]).
    converged_at: Option<usize>,
    started: bool,
    done: bool,
    clock: Box<dyn Clock>,
    totals: PhaseTimings,
}

impl Reconstruction {
    /// Validates contours and parameters and prepares the run (no mesh yet: the first `step`
    /// builds the initial tube).
    pub fn new(set: &ContourSet, params: Params) -> Result<Self> {
        params.validate()?;
        // The contours the user leaves out (checked against the file, named as it gives them)
        // are out of everything from here on, the alignment included: a slice drawn badly must
        // not shift the others. The run is then the file's without them.
        let (asked, mut asked_contours) = prepare::asked(set, &params)?;
        let file = set;
        let without = prepare::without_ids(set, &params.leave_out);
        let set = without.as_ref().unwrap_or(set);
        // The whole file is aligned before a surface is chosen: one breath-hold moves every
        // surface of an image, and the LV's rings fix the shifts better than an RV alone.
        let (aligned, alignment) = if params.align_slices {
            let options = AlignOptions {
                through_plane: params.align_through_plane,
            };
            let (s, a) = align_slices_with(set, options);
            // The contours left out move with their images, so that the distance from the mesh
            // to each is measured in the run's frame.
            if !asked_contours.is_empty() {
                shift_with_images(&mut asked_contours, file, &a);
            }
            (Some(s), Some(a))
        } else {
            (None, None)
        };
        let crossing_residual_mm = crossing_residual(set);
        let alignment_anchored = anchored_beyond_rv(set);
        let source = aligned.as_ref().unwrap_or(set);
        // A biventricular epicardium asked for is made of the file's LV and RV epicardia.
        let derived = biv_epi::with_derived(source, params.surface.as_deref());
        let source = derived.as_ref().unwrap_or(source);
        let selected = prepare::select_surface(source, params.surface.as_deref())?;
        let spikes: Vec<ContourSpikes> =
            selected.iter().filter_map(|c| contour_spikes(c)).collect();
        let (far, off_plane) = off_plane::left_out_with_far(&selected);
        let far: Vec<ContourFar> = selected
            .iter()
            .zip(far)
            .filter_map(|(c, found)| contour_far(c, &found))
            .collect();
        let off_plane: Vec<ContourOffPlane> = selected
            .iter()
            .zip(off_plane)
            .filter_map(|(c, found)| off_plane::contour_off_plane(c, &found))
            .collect();
        let contours = prepare::clean_contours(&selected);
        let contours_as_given = match aligned {
            Some(_) => {
                let derived_given = biv_epi::with_derived(set, params.surface.as_deref());
                let given = prepare::clean_contours(&prepare::select_surface(
                    derived_given.as_ref().unwrap_or(set),
                    params.surface.as_deref(),
                )?);
                same_structure(&given, &contours).then_some(given)
            }
            None => None,
        };
        // The user's choice comes before the rules: what they leave out is not data for any rule.
        let mut set_aside = asked;
        let mut set_aside_contours = asked_contours;
        if contours.len() < 2 {
            return Err(CoreError::TooFewContours {
                found: contours.len(),
                needed: 2,
            });
        }
        prepare::check_count_and_units(&contours)?;
        let before_rules = (!params.keep_specks).then(|| contours.clone());
        let (contours, by_rule) = prepare::set_aside(contours, params.keep_specks);
        if let Some(pool) = before_rules {
            set_aside_contours.extend(set_aside::named(&pool, &by_rule));
        }
        set_aside.extend(by_rule);
        let (contours, layout) = prepare::layout(contours, params.drop_second_loops)?;
        // The contours left out go from the file's curves too; loops left out (second loops)
        // leave them with another structure.
        let contours_as_given = contours_as_given
            .map(|g| without_set_aside(g, &set_aside))
            .filter(|g| same_structure(g, &contours));
        let (fitted, valve_chords) = fitted_contours(&contours, &layout);

        let mut candidates_mm: Vec<Vec3> = Vec::new();
        let mut candidate_owner: Vec<u32> = Vec::new();
        for (k, c) in fitted.iter().enumerate() {
            for p in &c.pieces {
                let r = resample_spacing(&p.points, p.closed, CANDIDATE_SPACING_MM);
                // Short- and long-axis curves are compared for conflicts, never two curves of one
                // kind: a slice's RV free wall and septum meet at sharp corners that are data.
                let group = u32::from(layout.kinds.get(k) == Some(&ContourKind::Lax));
                candidate_owner.extend(std::iter::repeat_n(group, r.len()));
                candidates_mm.extend(r);
            }
        }
        let centre = order_free_centroid(&candidates_mm);
        let scale = diameter(&candidates_mm);
        if !(scale.is_finite() && scale > 1e-9) {
            return Err(CoreError::Degenerate(
                "the contour points have no extent".into(),
            ));
        }
        let norm = Normalisation { centre, scale };
        let candidates: Vec<Vec3> = candidates_mm.iter().map(|p| norm.to_unit(p)).collect();
        let attractor_budget = match params.attractors {
            AttractorMode::Auto => Budget::Count(budget::auto_attractors(
                &fitted,
                &layout,
                MAX_AUTO_ATTRACTORS,
            )),
            AttractorMode::Count(n) => Budget::Count(n.max(MIN_ATTRACTORS)),
            AttractorMode::SpacingMm(mm) => Budget::Spacing(mm / scale),
        };
        if candidates.len() < MIN_ATTRACTORS {
            return Err(CoreError::TooFewContours {
                found: contours.len(),
                needed: MIN_ATTRACTORS,
            });
        }
        let end_caps = ends::EndCapsReport::none(params.end_caps);
        Ok(Reconstruction {
            params,
            contours,
            spikes,
            far,
            off_plane,
            fitted,
            valve_chords,
            set_aside,
            set_aside_contours,
            alignment,
            contours_as_given,
            crossing_residual_mm,
            alignment_anchored,
            layout,
            norm,
            candidates,
            candidate_owner,
            attractor_budget,
            attractors: Vec::new(),
            real_attractors: 0,
            cap_points: Vec::new(),
            cap_sides: Vec::new(),
            cap_weights: Vec::new(),
            end_caps,
            open_base: None,
            attractor_owner: Vec::new(),
            weights: Vec::new(),
            weighted: false,
            min_triangles: 0,
            lidded: false,
            mesh_unit: TriMesh::default(),
            mesh_mm: TriMesh::default(),
            bvh: None,
            tps: TpsSolver::new(),
            closest: Vec::new(),
            hints: Vec::new(),
            hits: Vec::new(),
            targets: Vec::new(),
            fps_scratch: Vec::new(),
            fps_last: None,
            iteration: 0,
            last_remesh: 0,
            skipped_remeshes: Vec::new(),
            converged_at: None,
            started: false,
            done: false,
            clock: Box::new(DefaultClock::default()),
            totals: PhaseTimings::default(),
        })
    }

    /// Advances one step: the initial tube first, then one deformation iteration per call.
    pub fn step(&mut self) -> Result<StepReport> {
        // On a pool worker natively, the step's parallel loops start without a cross-thread
        // hand-over each (see `parallel`); in wasm this is a plain call.
        parallel::install(|| self.step_here())
    }

    fn step_here(&mut self) -> Result<StepReport> {
        if self.done {
            return Ok(self.report(
                Phase::Done,
                false,
                false,
                (0.0, 0.0),
                PhaseTimings::default(),
            ));
        }
        let t0 = self.clock.now_ms();
        let mut timings = PhaseTimings::default();
        if !self.started {
            let r = self.start(&mut timings);
            timings.total_ms = self.clock.now_ms() - t0;
            self.totals += timings;
            return r;
        }
        let it = self.iteration + 1;
        let resample = (it - 1).is_multiple_of(self.params.resample_attractors_every) && it > 1;
        if resample {
            let t = self.clock.now_ms();
            self.lay_rim_lid(it);
            self.resample_attractors()?;
            // New centres: the last factor says nothing about their system.
            self.tps.invalidate_factor();
            timings.attractors_ms = self.clock.now_ms() - t;
        }
        let t = self.clock.now_ms();
        let (max_d, mean_d) = self.closest_points()?;
        timings.closest_ms = self.clock.now_ms() - t;

        let beta = self.params.beta;
        self.targets.clear();
        self.targets.extend(
            self.closest
                .iter()
                .zip(&self.attractors)
                .map(|(p, q)| p + (q - p) * beta),
        );
        let t = self.clock.now_ms();
        // The data weight per contour attractor stays what it is without lid points.
        let n = self.real_attractors.min(self.attractors.len());
        let lambda_eff = self.params.lambda / n.max(1) as f64;
        // Conflicts are softened only in the final steps without remeshing: that is where folds
        // form (every remesh smooths them away), and earlier the full pull converges fastest.
        let final_phase = it + final_steps_without_remesh(&self.params) > self.params.iterations;
        let mut weighted = self.params.soften_conflicts
            && final_phase
            && conflict_weights(
                &self.attractors[..n],
                &self.closest[..n],
                &self.attractor_owner[..n],
                CONFLICT_RADIUS_MM / self.norm.scale,
                CONFLICT_GRADIENT_LIMIT,
                &mut self.weights,
            );
        if n < self.attractors.len() {
            // Lid points pull less than data, so real contours win where they disagree.
            if !weighted {
                self.weights.clear();
                self.weights.resize(n, 1.0);
            }
            self.weights
                .resize(self.attractors.len(), ends::END_CAP_WEIGHT);
            self.lid_weights();
            weighted = true;
        }
        self.tps.fit_weighted(
            &self.closest,
            &self.targets,
            lambda_eff,
            weighted.then_some(&self.weights[..]),
        )?;
        self.weighted = weighted;
        timings.solve_ms = self.clock.now_ms() - t;
        let t = self.clock.now_ms();
        // Each vertex is evaluated on its own (~1 ns per centre), so vertex ranges can go to
        // different threads with the same bits.
        let tps = &self.tps;
        let parts = parallel::parts_for(self.mesh_unit.positions.len(), self.attractors.len());
        parallel::for_each_chunk1(&mut self.mesh_unit.positions, parts, |_, part| {
            tps.apply(part)
        });
        timings.apply_ms = self.clock.now_ms() - t;
        if !self
            .mesh_unit
            .positions
            .iter()
            .all(|p| p.iter().all(|c| c.is_finite()))
        {
            return Err(CoreError::Numerical(format!(
                "the deformation produced non-finite vertices at iteration {it}"
            )));
        }
        self.iteration = it;
        // The method's stop rule (every attractor within the threshold) ends the run only once
        // the last remesh's smoothing offset has decayed as at the run's end: stopping the moment
        // the rule first holds, a few steps after a remesh, left the surface off its data by
        // whatever share of that offset was left (SurFCo's mean contour distance 0.06 or 0.09 mm
        // with 1e-4 mm of noise on its points, as the rule first held at iteration 240 or 224).
        // Once it holds, no more remeshes: the remaining steps only settle.
        let settle = final_steps_without_remesh(&self.params);
        if self.converged_at.is_none() && max_d * max_d < self.params.stop_threshold {
            self.converged_at = Some(it);
        }
        let settled = self.converged_at.is_some() && it >= self.last_remesh + settle;
        let last = it >= self.params.iterations || settled;
        let mut phase = Phase::Deform;
        if last {
            self.done = true;
        } else if self.converged_at.is_none()
            && it.is_multiple_of(self.params.remesh_every)
            && it + settle <= self.params.iterations
        {
            let t = self.clock.now_ms();
            if self.remesh(it)? {
                self.last_remesh = it;
                phase = Phase::Remesh;
            }
            timings.remesh_ms = self.clock.now_ms() - t;
        }
        if let Some(bvh) = self.bvh.as_mut() {
            if phase != Phase::Remesh {
                bvh.refit(&self.mesh_unit)?;
            }
        }
        self.update_mesh_mm();
        timings.total_ms = self.clock.now_ms() - t0;
        self.totals += timings;
        let s = self.norm.scale;
        Ok(self.report(
            phase,
            phase == Phase::Remesh,
            resample,
            (max_d * s, mean_d * s),
            timings,
        ))
    }

    /// Runs to the end.
    pub fn run(&mut self) -> Result<()> {
        parallel::install(|| {
            while !self.done {
                self.step_here()?;
            }
            Ok(())
        })
    }

    /// Current mesh in mm.
    pub fn mesh(&self) -> &TriMesh {
        &self.mesh_mm
    }

    /// Current attractor points in mm (contour points only: the end caps' lid points are not data).
    pub fn attractors(&self) -> Vec<Vec3> {
        let n = self.real_attractors.min(self.attractors.len());
        self.attractors[..n]
            .iter()
            .map(|p| self.norm.to_mm(p))
            .collect()
    }

    /// The end caps' lid points in mm (empty when off or when data close both ends).
    pub fn end_cap_points(&self) -> Vec<Vec3> {
        self.cap_points.iter().map(|p| self.norm.to_mm(p)).collect()
    }

    /// Which ends got lid points and how many (known after the first step).
    pub fn end_caps(&self) -> ends::EndCapsReport {
        self.end_caps
    }

    /// The sentence for a base its outline left without a lid that runs on past the data
    /// ([`ends::EndCapsReport::note`]); None otherwise.
    pub fn end_cap_note(&self) -> Option<String> {
        let past = self.past_data()?;
        self.end_caps.note(past.base_mm)
    }

    /// The selected surface's contours after cleaning, in mm (without those left out:
    /// [`Reconstruction::set_aside`]).
    pub fn contours(&self) -> &[Contour] {
        &self.contours
    }

    /// The points cleaning left out of the selected surface's contours as spikes, per contour
    /// (only those with any): the report's and the app's per-contour rows say so.
    pub fn spikes(&self) -> &[ContourSpikes] {
        &self.spikes
    }

    /// The spikes left out of the contour `id` (None: none).
    pub fn spikes_of(&self, id: &str) -> Option<&ContourSpikes> {
        self.spikes.iter().find(|s| s.id == id)
    }

    /// The points cleaning left out of the contour `id` as far from the rest of its surface
    /// (`contours::far_pieces`; None: none): the report's and the app's per-contour rows say so.
    pub fn far_of(&self, id: &str) -> Option<&ContourFar> {
        self.far.iter().find(|s| s.id == id)
    }

    /// What cleaning left out of the contour `id` as damaged values, as the report's and the
    /// app's per-contour rows carry it: `spikes`, `far` and `off_plane`, each only when there are
    /// any (empty: none).
    pub fn damage_of(&self, id: &str) -> serde_json::Map<String, serde_json::Value> {
        let mut out = serde_json::Map::new();
        let mut put = |key: &str, value: Option<serde_json::Value>| {
            if let Some(v) = value {
                out.insert(key.to_string(), v);
            }
        };
        put(
            "spikes",
            self.spikes_of(id)
                .and_then(|s| serde_json::to_value(s).ok()),
        );
        put(
            "far",
            self.far_of(id).and_then(|f| serde_json::to_value(f).ok()),
        );
        put(
            "off_plane",
            self.off_plane_of(id)
                .and_then(|o| serde_json::to_value(o).ok()),
        );
        out
    }

    /// The points cleaning left out of the contour `id` as off the plane of the rest of it
    /// (`contours::off_plane`; None: none): the report's and the app's per-contour rows say so.
    pub fn off_plane_of(&self, id: &str) -> Option<&ContourOffPlane> {
        self.off_plane.iter().find(|s| s.id == id)
    }

    /// The ids of the long-axis curves closed across the valve that the mesh was fitted to opened
    /// there (`contours::valve_chord`): their straight run across the top is the valve plane,
    /// where the lid goes, not wall. Their distances are still measured as drawn.
    pub fn valve_chords(&self) -> &[String] {
        &self.valve_chords
    }

    /// What the CLI and the app say when long-axis curves were opened at their valve chord
    /// ([`Reconstruction::valve_chords`]); None when none was.
    pub fn valve_chord_note(&self) -> Option<String> {
        let ids = &self.valve_chords;
        let (they, their) = if ids.len() == 1 {
            ("it", "its")
        } else {
            ("them", "their")
        };
        (!ids.is_empty()).then(|| {
            format!(
                "{} closed across the valve: the mesh is fitted to {they} opened there and the \
                 base's lid, through {their} ends, carries the valve plane (distances are to the \
                 curves as drawn)",
                ids.iter()
                    .map(|id| format!("{id:?}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })
    }

    /// The selected surface's contours left out of the run and why: those the user named
    /// (`Params::leave_out`), then strays and specks (`contours::set_aside`; none with
    /// `Params::keep_specks`).
    pub fn set_aside(&self) -> &[SetAside] {
        &self.set_aside
    }

    /// [`Reconstruction::set_aside`] with, for each contour left out, how far the mesh passes from
    /// it: the distances (mm) of its points to the mesh built without it, as `per_contour` gives
    /// them for the contours used. A contour left out by hand is then a held-out slice (the
    /// leave-one-out figure of that contour), so the user sees whether it disagreed with the rest;
    /// a stray's distance says how far off it lay. Infinite before the first step (no mesh).
    pub fn set_aside_distances(&self) -> Vec<SetAsideDistance> {
        self.set_aside
            .iter()
            .zip(self.set_aside_stats())
            .map(|(entry, s)| SetAsideDistance {
                contour: entry.clone(),
                mean: s.mean,
                median: s.median,
                max: s.max,
            })
            .collect()
    }

    /// The contours [`Reconstruction::set_aside`] names, one per entry in its order, as the run
    /// measures them: cleaned (points as the file gives them, less repeats and non-finite ones),
    /// and with the breath-hold alignment where their slice or view moved. Where the app draws
    /// them, so a contour left out is seen where its distance to the mesh was taken.
    pub fn set_aside_contours(&self) -> &[Contour] {
        &self.set_aside_contours
    }

    /// The distance (mm) of every point of [`Reconstruction::set_aside_contours`] to the mesh, in
    /// their order: what the app's hover reads on a contour left out.
    pub fn set_aside_point_distances(&self) -> Vec<f64> {
        contour_points_to_mesh(&self.set_aside_contours, &self.mesh_mm)
    }

    /// The summary (mean, median, p95, max, ...) of those distances, one per
    /// [`Reconstruction::set_aside`] entry (none when nothing was left out: no BVH built). With
    /// the alignment on, a contour left out by hand is measured where its image moved.
    pub fn set_aside_stats(&self) -> Vec<Stats> {
        if self.set_aside.is_empty() {
            return Vec::new();
        }
        per_contour_stats(&self.set_aside_contours, &self.mesh_mm)
    }

    /// What the breath-hold alignment did (None unless `Params::align_slices`).
    pub fn alignment(&self) -> Option<&Alignment> {
        self.alignment.as_ref()
    }

    /// How far apart the file's images are where their planes cross, as given (mm; see
    /// [`crossing_residual`]): above about 1 mm, the breath-hold alignment is worth a try.
    pub fn crossing_residual_mm(&self) -> Option<f64> {
        self.crossing_residual_mm
    }

    /// Alignment off, the images farther apart where they cross than
    /// [`SUGGEST_ALIGNMENT_ABOVE_MM`], and not an RV-only file ([`anchored_beyond_rv`]: there the
    /// alignment was measured to do harm): the CLI's note and the app's "align" button both ask
    /// this.
    pub fn alignment_suggested(&self) -> bool {
        !self.params.align_slices
            && self.alignment_anchored
            && self
                .crossing_residual_mm
                .is_some_and(|r| r > SUGGEST_ALIGNMENT_ABOVE_MM)
    }

    /// With alignment on: the selected contours as the file gave them (cleaned, unshifted), in
    /// the order of [`Reconstruction::contours`].
    pub fn contours_as_given(&self) -> Option<&[Contour]> {
        self.contours_as_given.as_deref()
    }

    /// With alignment on: contour-to-mesh distances to the unshifted contours (the mesh follows
    /// the shifted ones, so this measures how far it moved from the file's curves).
    pub fn contour_distances_as_given(&self) -> Option<ContourDistances> {
        let given = self.contours_as_given.as_deref()?;
        Some(contour_to_mesh(given, &self.layout.kinds, &self.mesh_mm))
    }

    /// SAX or LAX, per contour of [`Reconstruction::contours`].
    pub fn kinds(&self) -> &[ContourKind] {
        &self.layout.kinds
    }

    /// The long axis (unit, apex to base) found from the short-axis normals.
    pub fn long_axis(&self) -> Vec3 {
        self.layout.axis
    }

    /// Heights (mm along the long axis) of the short-axis slices, apex to base.
    pub fn slice_heights(&self) -> Vec<f64> {
        self.layout.slices.iter().map(|s| s.height).collect()
    }

    /// How far the current mesh reaches past the highest and lowest contour points along the long
    /// axis (mm): the extrapolated part of the volume where no curve closes an end.
    pub fn past_data(&self) -> Option<crate::metrics::extent::PastData> {
        self.past_data_of(&self.mesh_mm.positions)
    }

    /// The same measure for any points (a ground truth, to compare overruns), against this
    /// reconstruction's contours and long axis.
    pub fn past_data_of(&self, points: &[Vec3]) -> Option<crate::metrics::extent::PastData> {
        crate::metrics::extent::past_data(points, &self.contours, &self.layout.axis)
    }

    /// Contour-to-mesh distance of every contour point.
    pub fn contour_distances(&self) -> ContourDistances {
        contour_to_mesh(&self.contours, &self.layout.kinds, &self.mesh_mm)
    }

    /// Per mesh vertex, the distance (mm) to the nearest contour.
    pub fn vertex_distances(&self) -> Vec<f64> {
        vertex_to_contours(&self.mesh_mm, &self.contours)
    }

    pub fn is_done(&self) -> bool {
        self.done
    }

    /// The note before a long or coarse run, or None: its mesh would reach the remesh cap
    /// ([`growth::cap_note`]) or is held at the tube's triangles ([`growth::floor_note`]), or its
    /// attractors make the spline's solve long ([`solve_cost::long_solve_note`]); in one line
    /// when both hold. Known once step 0 has built the initial tube and sampled the attractors
    /// (None before).
    pub fn growth_note(&self) -> Option<String> {
        let mesh = growth::cap_note(&self.params, self.mesh_unit.triangles.len())
            .or_else(|| growth::floor_note(&self.params, self.min_triangles));
        let attractors = self.real_attractors.min(self.attractors.len());
        let solve = solve_cost::long_solve_note(attractors);
        match (mesh, solve) {
            (Some(a), Some(b)) => Some(format!("{a}; and {b}")),
            (a, b) => a.or(b),
        }
    }

    /// The remeshes this run skipped because each would have wrecked the surface
    /// (`remesh_guard`: the enclosed volume changed over twofold, or a stalled decimation); empty on
    /// sound data.
    pub fn skipped_remeshes(&self) -> &[SkippedRemesh] {
        &self.skipped_remeshes
    }

    /// The one-line note for a run that skipped remeshes ([`remesh_guard::note`]), or None.
    pub fn skipped_remesh_note(&self) -> Option<String> {
        remesh_guard::note(&self.skipped_remeshes)
    }

    pub fn iteration(&self) -> usize {
        self.iteration
    }

    pub fn total_iterations(&self) -> usize {
        self.params.iterations
    }

    pub fn params(&self) -> &Params {
        &self.params
    }

    /// Time spent per phase since the start.
    pub fn total_timings(&self) -> PhaseTimings {
        self.totals
    }

    pub fn set_clock(&mut self, clock: Box<dyn Clock>) {
        self.clock = clock;
    }
}

/// The contours the mesh is fitted to and the ids of the long-axis curves opened at their valve
/// chord (`contours::valve_chord`). A chord is opened to hand the valve to the lid through the
/// opened curves' tips; where other curves still close the base (an RV outflow curve over the
/// top) no lid goes there, an opened chord would leave the top to run free (9 mm past a chord on
/// the Segment fixture's ES RV), and the chords stay.
///
/// An RV's base holds two valves, tricuspid and pulmonary, 10-20 mm apart in height, each view's
/// line at its own; one lid plane through all their ends carries neither (a label map's spasm RV:
/// its lines 7.6 mm off the mesh opened, 1.4 mm as wall), so RV and biventricular surfaces (named
/// `RV...` or `BIV...`, as the alignment tells them) keep their lines as wall.
fn fitted_contours(contours: &[Contour], layout: &Layout) -> (Vec<Contour>, Vec<String>) {
    let two_valves = contours.iter().any(|c| {
        c.surface.as_deref().is_some_and(|s| {
            let s = s.trim().to_ascii_uppercase();
            s.starts_with("RV") || s.starts_with("BIV")
        })
    });
    let Some(basal) = layout.slices.last().filter(|_| !two_valves) else {
        return (contours.to_vec(), Vec::new());
    };
    let (fitted, opened) = open_valve_chords(contours, &layout.kinds, &layout.axis, basal.height);
    if opened.is_empty() {
        return (fitted, opened);
    }
    let ring: Vec<Vec3> = basal
        .contours
        .iter()
        .filter_map(|&j| contours.get(j))
        .flat_map(|c| c.points().copied())
        .collect();
    if ends::closed_by_data(&ring, &fitted, &layout.kinds, &layout.axis, 1.0) {
        (contours.to_vec(), Vec::new())
    } else {
        (fitted, opened)
    }
}

/// Same contours, pieces and point counts (cleaning shifted and unshifted copies of a contour
/// gives the same structure unless a spacing sits exactly on a cleaning threshold).
fn same_structure(a: &[Contour], b: &[Contour]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            x.id == y.id
                && x.pieces.len() == y.pieces.len()
                && x.pieces
                    .iter()
                    .zip(&y.pieces)
                    .all(|(p, q)| p.points.len() == q.points.len() && p.closed == q.closed)
        })
}

/// Most triangles a remesh may leave. Subdivision quadruples the triangle count, so any target
/// reduction below 0.75 grows the mesh geometrically over the run (0.5 doubles it at every remesh:
/// about 5 million triangles after ten remeshes, gigabytes in a browser tab). Twenty times the
/// default mesh is far beyond what the contours can resolve.
pub const MAX_REMESH_TRIANGLES: usize = 200_000;

/// The reduction a remesh applies: the user's, or more when the subdivided mesh would otherwise
/// end above [`MAX_REMESH_TRIANGLES`], or less when it would end below `floor` triangles (the
/// initial tube's count). A target reduction above 0.75 shrinks the mesh at every remesh (0.95
/// keeps 0.2x): unchecked, ten remeshes leave a tetrahedron far from every contour that still
/// reads "closed"; at the floor the mesh keeps the tube's resolution, which follows the contours.
fn capped_reduction(target_reduction: f64, triangles: usize, floor: usize) -> f64 {
    let subdivided = (4 * triangles).max(1) as f64;
    let needed = 1.0 - MAX_REMESH_TRIANGLES as f64 / subdivided;
    let allowed = (1.0 - floor as f64 / subdivided).max(0.0);
    target_reduction.max(needed).min(allowed)
}

/// Share of a remesh's displacement (the smoothing pulls the surface off the data) still left when
/// the run ends.
const FINAL_REMESH_RESIDUAL: f64 = 0.01;

/// No remesh within this many final iterations: each step moves the surface a fraction beta of the
/// way back to the data, so the smoothing offset of the last remesh decays as (1 - beta)^n and needs
/// n = ln(0.01) / ln(1 - beta) steps (44 at beta 0.1) to fall below 1%; at least one remesh
/// interval. Measured in docs/VALIDATION.md (accuracy section).
fn final_steps_without_remesh(p: &Params) -> usize {
    let decay = (1.0 - p.beta).clamp(0.0, 1.0);
    let n = if decay > 0.0 && decay < 1.0 {
        (FINAL_REMESH_RESIDUAL.ln() / decay.ln()).ceil()
    } else {
        0.0
    };
    // At most half the run: a tiny beta cannot recover within the run anyway, and the first half
    // still needs its remeshes to keep the triangles even.
    (n.min((p.iterations / 2) as f64) as usize).max(p.remesh_every)
}
