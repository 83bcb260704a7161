//! Regional function (`heartmesh volumes`): the LV wall's systolic thickening in each AHA segment,
//! from the wall at the LV's end-diastole to the wall at its end-systole. Each phase's wall is
//! the one `heartmesh myocardium` builds of that phase's LV_ENDO and LV_EPI (its base plane from
//! the phase's contours, 1 mm minimum thickness), and its segments are placed in that phase
//! (core `metrics::segments`): thickening is what a cardiologist reads after the ejection
//! fraction, where the ventricle contracts and where it does not.

use super::compare::common_basal_plane_of;
use super::function::Function;
use super::segments::{self, SegmentThickening, Segments};
use crate::contours::ContourSet;
use crate::mesh::wall::build_wall;
use crate::mesh::TriMesh;
use crate::params::Params;
use serde::Serialize;

/// The minimum wall thickness the walls are built with: `myocardium`'s default.
const MIN_THICKNESS_MM: f64 = 1.0;

/// One phase's LV, as `volumes` holds it.
pub struct PhaseLv<'a> {
    pub name: &'a str,
    pub set: &'a ContourSet,
    /// The parameters the phase's surfaces ran with.
    pub params: Params,
    pub endo: Option<&'a TriMesh>,
    pub epi: Option<&'a TriMesh>,
}

/// The thickening between the LV's end-diastole and end-systole.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Thickening {
    pub ed_phase: String,
    pub es_phase: String,
    /// Where each phase's septum direction came from.
    pub septum_from: [String; 2],
    /// Wall surface-weighted mean over the 17 segments' values (%).
    pub mean_percent: f64,
    pub segments: Vec<SegmentThickening>,
}

/// The thickening of the study's LV, or why there is none; None when the study has no LV
/// epicardium to measure a wall by (nothing to say).
pub fn of_study(phases: &[PhaseLv], f: &Function) -> Option<Result<Thickening, String>> {
    if phases.iter().all(|p| p.epi.is_none()) {
        return None;
    }
    let Some(lv) = f.ventricles.iter().find(|v| v.surface == "LV_ENDO") else {
        return Some(Err(
            "no LV end-diastole and end-systole (LV_ENDO needs a volume in two phases)".into(),
        ));
    };
    if lv.ed_phase == lv.es_phase {
        return Some(Err(format!(
            "end-diastole and end-systole are the same phase ({}): the LV volume does not change",
            lv.ed_phase
        )));
    }
    if let Some(mass) = &f.lv_mass {
        if let Some(why) = mass
            .per_phase
            .iter()
            .filter(|m| m.phase == lv.ed_phase || m.phase == lv.es_phase)
            .find_map(|m| m.why_none)
        {
            return Some(Err(why.to_string()));
        }
    }
    let walls = [&lv.ed_phase, &lv.es_phase].map(|name| {
        phases
            .iter()
            .find(|p| p.name == name.as_str())
            .ok_or_else(|| format!("no phase {name}"))
            .and_then(segments_of)
    });
    let [ed, es] = walls;
    Some(ed.and_then(|ed| {
        let es = es?;
        let segments = segments::thickening(&ed, &es);
        Ok(Thickening {
            ed_phase: lv.ed_phase.clone(),
            es_phase: lv.es_phase.clone(),
            septum_from: [ed.septum_from.clone(), es.septum_from.clone()],
            mean_percent: weighted_mean(&ed, &segments),
            segments,
        })
    }))
}

/// One phase's wall segments, as `myocardium` gives them.
fn segments_of(p: &PhaseLv) -> Result<Segments, String> {
    let (Some(endo), Some(epi)) = (p.endo, p.epi) else {
        return Err(format!(
            "phase {} has no closed LV_ENDO and LV_EPI meshes",
            p.name
        ));
    };
    let base = common_basal_plane_of(p.set, &p.params, "LV_ENDO", "LV_EPI")
        .map_err(|e| format!("phase {}: no base plane: {e}", p.name))?;
    let wall = build_wall(endo, epi, &base, Some(MIN_THICKNESS_MM))
        .map_err(|e| format!("phase {}: the wall: {e}", p.name))?;
    segments::of_file(p.set, &wall).map_err(|why| format!("phase {}: {why}", p.name))
}

/// The segments' thickening weighted by their end-diastolic wall area.
fn weighted_mean(ed: &Segments, changes: &[SegmentThickening]) -> f64 {
    let (mut sum, mut area) = (0.0, 0.0);
    for (s, c) in ed.segments.iter().zip(changes) {
        if let Some(t) = c.thickening_percent {
            sum += s.area_mm2 * t;
            area += s.area_mm2;
        }
    }
    if area > 0.0 {
        sum / area
    } else {
        f64::NAN
    }
}
