//! The phases of a reconstruction step: the initial tube, attractor sampling, closest points,
//! the remesh, and the step report.

use super::remesh_guard::{self, SkippedRemesh};
use super::tube;
use super::{
    capped_reduction, ends, Phase, PhaseTimings, Reconstruction, StepReport, CANDIDATE_SPACING_MM,
    MIN_ATTRACTORS,
};
use crate::contours::rings::tube_rings_of;
use crate::deform::attractors::farthest_point_sampling;
use crate::deform::attractors::Budget;
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::TriMesh;
use crate::parallel;
use crate::refine::remesh_with;
use crate::spatial::Bvh;

impl Reconstruction {
    /// Builds the initial tube, remeshes it once and picks the first attractors.
    pub(super) fn start(&mut self, timings: &mut PhaseTimings) -> Result<StepReport> {
        let slices: Vec<Vec<usize>> = self
            .layout
            .slices
            .iter()
            .map(|s| s.contours.clone())
            .collect();
        let (rings, ring_slice) = tube_rings_of(
            &self.contours,
            &slices,
            &self.layout.axis,
            self.params.ring_points,
        );
        if rings.len() < 2 {
            return Err(CoreError::Degenerate(format!(
                "only {} short-axis slice(s) form a ring of 3 or more points",
                rings.len()
            )));
        }
        let lids = tube::lids(&self.params.lids, &rings, &self.fitted, &self.layout);
        self.place_end_caps(&rings, &lids);
        let mut rings = rings;
        tube::extend_to_base(&mut rings, &lids, &self.layout.axis);
        let mut mesh = tube::ruled_tube(&rings, &lids);
        for p in &mut mesh.positions {
            *p = self.norm.to_unit(p);
        }
        if let Some((a, b)) = tube::zero_area_between(&mesh, rings.len(), self.params.ring_points) {
            let name = |r: usize| match ring_slice.get(r).and_then(|&s| slices.get(s)) {
                Some(contours) => contours
                    .iter()
                    .filter_map(|&j| self.contours.get(j))
                    .map(|c| c.cite(""))
                    .collect::<Vec<_>>()
                    .join(", "),
                None => "the lid".to_string(),
            };
            return Err(CoreError::Degenerate(format!(
                "the short-axis rings of {} and {} touch, so no tube passes between them; is \
                 each of these contours one slice's curve?",
                name(a),
                name(b.max(a + 1))
            )));
        }
        let closed = lids.apex.is_some() && lids.base.is_some();
        self.lidded = closed;
        if closed && mesh.signed_volume() < 0.0 {
            mesh.flip_orientation();
        }
        let t = self.clock.now_ms();
        self.min_triangles = mesh.triangles.len();
        // A smoothing that collapses the tube (a long run of a method without shrink correction)
        // leaves the tube itself to deform.
        self.mesh_unit = match self.checked_remesh(&mesh, 0)? {
            Ok(remeshed) => remeshed,
            Err(skipped) => {
                self.skipped_remeshes.push(skipped);
                mesh
            }
        };
        timings.remesh_ms = self.clock.now_ms() - t;
        self.bvh = Some(Bvh::build(&self.mesh_unit));
        let t = self.clock.now_ms();
        self.resample_attractors()?;
        timings.attractors_ms = self.clock.now_ms() - t;
        self.started = true;
        self.update_mesh_mm();
        Ok(self.report(Phase::InitialTube, true, true, (0.0, 0.0), *timings))
    }

    /// Lid points for the ends no curve closes (`ends`), at about the contour attractors' spacing:
    /// the contours' length (candidates lie ~1 mm apart) over the attractor count, or the spacing
    /// asked for.
    fn place_end_caps(&mut self, rings: &[Vec<Vec3>], lids: &tube::Lids) {
        let length_mm = self.candidates.len() as f64 * CANDIDATE_SPACING_MM;
        let (spacing_mm, count) = match self.attractor_budget {
            Budget::Count(n) => {
                let n = n.clamp(1, self.candidates.len().max(1));
                (length_mm / n as f64, n)
            }
            Budget::Spacing(s) => {
                let mm = s * self.norm.scale;
                (mm, (length_mm / mm.max(1e-9)).ceil() as usize)
            }
        };
        let (points, sides, report) = ends::end_cap_points(
            self.params.end_caps,
            self.params.apex_floor,
            &ends::LidInput {
                rings,
                lids,
                contours: &self.fitted,
                kinds: &self.layout.kinds,
                axis: &self.layout.axis,
                spacing: spacing_mm,
                real_attractors: count,
            },
        );
        self.cap_points.clear();
        self.cap_sides.clear();
        self.add_cap_points(&points, &sides);
        self.open_base = report.base_too_narrow.then(|| super::rim_lid::OpenBase {
            rings: rings.to_vec(),
            lids: *lids,
            spacing_mm,
            attractors: count,
        });
        self.end_caps = report;
    }

    /// Appends lid points and their sides given in mm to the run's, in its normalised units.
    pub(super) fn add_cap_points(&mut self, points: &[Vec3], sides: &[super::lid_pull::LidSide]) {
        let norm = self.norm;
        self.cap_points
            .extend(points.iter().map(|p| norm.to_unit(p)));
        self.cap_sides
            .extend(sides.iter().map(|s| super::lid_pull::LidSide {
                tolerance: s.tolerance / norm.scale,
                ..*s
            }));
    }

    /// The one-sided lid (`lid_pull`): which lid points pull in this step, from its closest points
    /// and which pulled in the last one; the released ones are left out of the step's fit.
    pub(super) fn lid_weights(&mut self) {
        let n = self.real_attractors.min(self.attractors.len());
        super::lid_pull::decide(
            n,
            &self.attractors,
            &self.closest,
            &self.cap_sides,
            &mut self.cap_weights,
        );
        super::lid_pull::apply(
            n,
            &self.cap_weights,
            &mut self.closest,
            &mut self.targets,
            &mut self.weights,
        );
    }

    /// Farthest-point sampling of the attractors, seeded at the candidate farthest from the mesh.
    pub(super) fn resample_attractors(&mut self) -> Result<()> {
        let bvh = self
            .bvh
            .as_ref()
            .ok_or_else(|| CoreError::InvalidMesh("no mesh to measure against".into()))?;
        // The candidate farthest from the mesh (the first of equals), searched in contiguous
        // ranges on the threads: each range's own farthest, then the first of the farthest in
        // range order, which is the one a single pass finds.
        let (candidates, mesh) = (&self.candidates, &self.mesh_unit);
        let per_range = parallel::map_parts(
            candidates.len(),
            parallel::parts_for(candidates.len(), 1000),
            |range| farthest_from_mesh(bvh, mesh, candidates, range),
        );
        let mut seed = (f64::NEG_INFINITY, 0usize);
        for best in per_range {
            if best.0 > seed.0 {
                seed = best;
            }
        }
        let idx = match self.fps_last.take() {
            Some((last, idx)) if last == seed.1 => idx,
            _ => farthest_point_sampling(
                &self.candidates,
                seed.1,
                self.attractor_budget,
                MIN_ATTRACTORS,
                &mut self.fps_scratch,
            ),
        };
        if idx.len() < MIN_ATTRACTORS {
            return Err(CoreError::Degenerate(format!(
                "only {} distinct contour points; at least {MIN_ATTRACTORS} are needed",
                idx.len()
            )));
        }
        self.attractors.clear();
        self.attractors
            .extend(idx.iter().map(|&i| self.candidates[i]));
        self.attractor_owner.clear();
        self.attractor_owner
            .extend(idx.iter().map(|&i| self.candidate_owner[i]));
        self.real_attractors = self.attractors.len();
        self.attractors.extend_from_slice(&self.cap_points);
        self.attractor_owner
            .extend(std::iter::repeat_n(CAP_OWNER, self.cap_points.len()));
        self.hints.clear();
        self.hints.resize(self.attractors.len(), u32::MAX);
        self.fps_last = Some((seed.1, idx));
        Ok(())
    }

    /// Closest mesh point of every attractor into `self.closest`; returns (max, mean) distance.
    pub(super) fn closest_points(&mut self) -> Result<(f64, f64)> {
        let bvh = self
            .bvh
            .as_ref()
            .ok_or_else(|| CoreError::InvalidMesh("no mesh to measure against".into()))?;
        let n = self.attractors.len();
        self.hints.resize(n, u32::MAX);
        self.hits.clear();
        self.hits.resize(n, None);
        // Independent queries (each starts from its own attractor's last triangle): ranges of
        // attractors go to different threads (~1 us per query); the sums below stay in order.
        let (attractors, mesh) = (&self.attractors, &self.mesh_unit);
        parallel::for_each_chunk(
            &mut self.hits,
            &mut self.hints,
            parallel::parts_for(n, 1000),
            |start, hits, hints| {
                for ((q, hit), hint) in attractors[start..].iter().zip(hits).zip(hints) {
                    *hit = bvh.closest_point_near(mesh, *q, *hint);
                    if let Some(h) = hit {
                        *hint = h.triangle;
                    }
                }
            },
        );
        self.closest.clear();
        let (mut max_d, mut sum_d) = (0.0f64, 0.0);
        // Distances are to the data: lid points (after the first `real_attractors`) do not count.
        let real = self.real_attractors.min(n);
        for (k, hit) in self.hits.iter().enumerate() {
            let hit =
                hit.ok_or_else(|| CoreError::InvalidMesh("the mesh has no triangles".into()))?;
            if k < real {
                let d = hit.distance_sq.sqrt();
                max_d = max_d.max(d);
                sum_d += d;
            }
            self.closest.push(hit.point);
        }
        Ok((max_d, sum_d / real.max(1) as f64))
    }

    /// The remesh at `iteration`, unless it would wreck the surface (`remesh_guard`): then the
    /// mesh stays as it is and the skip is recorded. True when the mesh was remeshed.
    pub(super) fn remesh(&mut self, iteration: usize) -> Result<bool> {
        match self.checked_remesh(&self.mesh_unit, iteration)? {
            Ok(next) => self.mesh_unit = next,
            Err(skipped) => {
                self.skipped_remeshes.push(skipped);
                return Ok(false);
            }
        }
        self.bvh = Some(Bvh::build(&self.mesh_unit));
        // New triangles: the old indices would still give the same answers, only slower.
        self.hints.fill(u32::MAX);
        Ok(true)
    }

    /// `mesh` subdivided, smoothed and decimated (closed or open as it was), or the skip to
    /// record when the result would wreck the surface.
    fn checked_remesh(
        &self,
        mesh: &TriMesh,
        iteration: usize,
    ) -> Result<std::result::Result<TriMesh, SkippedRemesh>> {
        let p = &self.params;
        let reduction =
            capped_reduction(p.target_reduction, mesh.triangles.len(), self.min_triangles);
        // Subdivision quadruples the triangles; the decimation keeps (1 - reduction) of them.
        let asked = ((1.0 - reduction) * (4 * mesh.triangles.len()) as f64).round() as usize;
        // `remesh_with` checks that its result is manifold, oriented and as closed as its input.
        let remeshed = remesh_with(
            mesh,
            p.smoothing,
            p.smoothing_iterations,
            p.smoothing_factor,
            reduction,
        );
        let reason = match remeshed {
            Ok(next) => {
                match remesh_guard::refusal(mesh, &next, asked, self.lidded, self.norm.scale) {
                    None => return Ok(Ok(next)),
                    Some(why) => why,
                }
            }
            // Mid-run only the remesh's own check fails this way (the deformation keeps the
            // topology), and the mesh before it is still sound; the tube's is a real error.
            Err(CoreError::InvalidMesh(why)) if iteration > 0 => why,
            Err(e) => return Err(e),
        };
        Ok(Err(SkippedRemesh { iteration, reason }))
    }

    pub(super) fn update_mesh_mm(&mut self) {
        let norm = self.norm;
        self.mesh_mm.positions.clear();
        self.mesh_mm
            .positions
            .extend(self.mesh_unit.positions.iter().map(|p| norm.to_mm(p)));
        if self.mesh_mm.triangles != self.mesh_unit.triangles {
            self.mesh_mm.triangles.clone_from(&self.mesh_unit.triangles);
        }
    }

    pub(super) fn report(
        &self,
        phase: Phase,
        topology_changed: bool,
        attractors_changed: bool,
        (max_distance_mm, mean_distance_mm): (f64, f64),
        timings: PhaseTimings,
    ) -> StepReport {
        StepReport {
            iteration: self.iteration,
            total_iterations: self.params.iterations,
            phase,
            topology_changed,
            attractors_changed,
            max_distance_mm,
            mean_distance_mm,
            vertices: self.mesh_unit.positions.len(),
            triangles: self.mesh_unit.triangles.len(),
            attractors: self.real_attractors.min(self.attractors.len()),
            timings,
            done: self.done,
        }
    }
}

/// Attractor group of the lid points (0 and 1 are short- and long-axis contours).
const CAP_OWNER: u32 = 2;

/// Squared distance to the mesh and index of the first farthest candidate of `range`
/// ((-inf, range.start) if none has a distance).
fn farthest_from_mesh(
    bvh: &Bvh,
    mesh: &TriMesh,
    candidates: &[Vec3],
    range: std::ops::Range<usize>,
) -> (f64, usize) {
    let mut seed = (f64::NEG_INFINITY, range.start);
    // Consecutive candidates lie ~1 mm apart along a contour: each hit seeds the next query.
    let mut hint = u32::MAX;
    for (i, q) in candidates[range.clone()].iter().enumerate() {
        // Only the farthest candidate matters: one no farther from the previous hit's triangle
        // than the farthest so far cannot beat it (that distance bounds its own from above).
        if let Some(bound) = bvh.distance_sq_to_triangle(*q, hint) {
            if bound <= seed.0 {
                continue;
            }
        }
        let hit = bvh.closest_point_near(mesh, *q, hint);
        hint = hit.map_or(u32::MAX, |h| h.triangle);
        let d = hit.map_or(f64::INFINITY, |h| h.distance_sq);
        if d > seed.0 {
            seed = (d, range.start + i);
        }
    }
    seed
}
