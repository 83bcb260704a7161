//! The late rim lid: a base left without a lid for want of room gets one nearer its rim once the
//! run shows it running on past the data.
//!
//! Lid points stay two attractor spacings in from the rim (`ends::RIM_INSET_PER_SPACING`: the
//! wall's shoulder needs room to turn into the lid), so at a few dozen to a hundred attractors an
//! RV crescent's outline holds none and nothing holds that base: on the real files it then runs
//! on 5-6 mm past the data and the RV's volume by a fifth (biv-me patient 1 ED RV: 218 ml at 100
//! attractors, 183 ml at the defaults). Laying a nearer-rim lid from the start costs the rim
//! corner where the base would have stopped anyway (the held-out RV phantom, whose long-axis
//! curve holds its base within 0-2 mm: Hausdorff median 4.0 -> 5.7 mm; docs/VALIDATION.md,
//! "Session 55"). So the lid is laid only where the base is seen to run on: at an attractor
//! resampling, once the surface has had [`FROM_ITERATION`] iterations to reach its data, if
//! the base runs more than `ends::OPEN_BASE_NOTE_MM` past the data (the threshold of the note
//! and of the app's amber "Past the data"). The lid is one-sided (`lid_pull`) like every other:
//! it pulls only the part of the mesh beyond its plane.

use super::ends::{self, OPEN_BASE_NOTE_MM};
use super::tube::Lids;
use super::Reconstruction;
use crate::geometry::Vec3;

/// Resamplings after this iteration may lay the rim lid (iteration 51 at the defaults, the second
/// resampling). Counted in iterations, not resamplings, so that a run resampling every few steps
/// does not lay it while the surface is still on its way from the tube to the data (the tube's
/// base ring, extended to the lid, may lie past the data for a while). Fifty steps leave margin:
/// the app's distance plot of patient 1's RV shows the attractors' mean distance near 1 mm
/// within ten.
pub const FROM_ITERATION: usize = 50;

/// What the late rim lid needs of the run's start: the tube's short-axis rings (mm, apex to
/// base, before the basal extension), its lids, and the attractor spacing and count the first
/// lids were laid at.
#[derive(Debug, Clone)]
pub struct OpenBase {
    pub rings: Vec<Vec<Vec3>>,
    pub lids: Lids,
    pub spacing_mm: f64,
    pub attractors: usize,
}

/// Whether the resampling at iteration `it` may lay the rim lid of a base `past_base_mm` past the
/// data.
pub fn due(it: usize, past_base_mm: f64) -> bool {
    it > FROM_ITERATION && past_base_mm > OPEN_BASE_NOTE_MM
}

impl Reconstruction {
    /// Lays the late rim lid before the resampling at iteration `it` if it is due (once per
    /// run: an outline without room even near its rim keeps its note).
    pub(super) fn lay_rim_lid(&mut self, it: usize) {
        if self.open_base.is_none() {
            return;
        }
        let Some(past) = self.past_data() else {
            return;
        };
        if !due(it, past.base_mm) {
            return;
        }
        let Some(open) = self.open_base.take() else {
            return;
        };
        let (points, sides, ceiling) = ends::relaxed_base_points(&ends::LidInput {
            rings: &open.rings,
            lids: &open.lids,
            contours: &self.fitted,
            kinds: &self.layout.kinds,
            axis: &self.layout.axis,
            spacing: open.spacing_mm,
            real_attractors: open.attractors,
        });
        if points.is_empty() {
            return;
        }
        self.add_cap_points(&points, &sides);
        let report = &mut self.end_caps;
        report.base = true;
        report.base_ceiling = ceiling;
        report.points += points.len();
        report.base_rim_lid_at = Some(it);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn due_after_iteration_50_past_five_mm() {
        assert!(!due(26, 9.0));
        assert!(!due(50, 9.0));
        assert!(due(51, 9.0));
        assert!(!due(51, OPEN_BASE_NOTE_MM));
        assert!(due(52, 5.1));
        assert!(!due(usize::MAX, f64::NAN));
    }
}
