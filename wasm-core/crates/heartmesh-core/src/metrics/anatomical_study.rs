//! Anatomical layouts of a whole study (`heartmesh volumes --anatomical-meshes`): every phase's
//! LV surfaces on the grid of [`super::anatomical`], all turned by ONE septum direction.
//!
//! Why one: each phase's file places its own septum from its own RV contours or landmarks, and
//! those are drawn anew in every frame; patient 1's ED and ES septa lie ~2 degrees apart, so
//! layouts each on its own septum carry that drawing noise as a twist of every ring, and
//! per-vertex motion from ED to ES would show a rotation the heart did not make. The heart's
//! coordinates are the scanner's in every frame of one study, so the direction found once, at
//! the reference phase (the LV's end-diastole, the usual reference for motion and strain), is
//! projected across each phase's own long axis and used for all. A phase whose file says nothing
//! of the septum (an ES file drawn without the RV) then gets a layout too.
//!
//! Each layout also carries its vertices' displacement from the reference phase's layout of the
//! same surface (mm): the motion of each grid point over the cycle, the number a motion study
//! reads first.

use super::anatomical::{self, Anatomical, Layout, REGION_NAMES};
use super::compare::ClipPlane;
use super::segments::Orientation;
use super::septum;
use crate::contours::ContourSet;
use crate::error::Result as CoreResult;
use crate::geometry::Vec3;
use crate::io::{self, MeshFormat, Regions};
use crate::mesh::TriMesh;
use serde::Serialize;
use serde_json::{json, Value};

/// One surface of one phase as the study holds it.
#[derive(Debug, Clone, Copy)]
pub struct PhaseSurface<'a> {
    pub phase: &'a str,
    /// LV_ENDO or LV_EPI (others are refused per layout, with the reason).
    pub surface: &'a str,
    pub set: &'a ContourSet,
    /// The finished closed surface and its base plane (the run's most basal short-axis plane,
    /// normal towards the base); None when the run failed, left it open or the phase lacks it.
    pub mesh: Option<(&'a TriMesh, &'a ClipPlane)>,
}

/// The septum every layout of the study is turned by.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StudySeptum {
    /// The phase and surface it was found on.
    pub phase: String,
    pub surface: String,
    /// Unit vector across that phase's long axis (file coordinates).
    pub direction: [f64; 3],
    /// What it was found from, as a layout's `septum_from` says it.
    pub source: String,
}

/// One phase's layout of one surface.
#[derive(Debug, Clone)]
pub struct PhaseLayout {
    pub phase: String,
    pub surface: String,
    /// The layout, or why there is none.
    pub built: Result<Anatomical, String>,
    /// How far the septum this phase's own file gives lies from the study's (degrees, across
    /// the phase's axis); None when the file gives none.
    pub septum_turn_deg: Option<f64>,
    /// Per vertex, the distance (mm) from the same vertex of the reference phase's layout of
    /// the same surface; None without that layout.
    pub displacement_mm: Option<Vec<f64>>,
}

impl PhaseLayout {
    /// The mean and the largest displacement (mm).
    pub fn displacement_stats(&self) -> Option<(f64, f64)> {
        let d = self.displacement_mm.as_ref().filter(|d| !d.is_empty())?;
        let mean = d.iter().sum::<f64>() / d.len() as f64;
        Some((mean, d.iter().copied().fold(0.0, f64::max)))
    }
}

impl PhaseLayout {
    /// The layout's file in `format` (None when there is no layout): regions `wall` and `base`,
    /// point data `displacement_mm`, and a header saying what every vertex is, which septum
    /// turned it and what the displacement is from (`input`: the phase's contour file's name).
    pub fn file(
        &self,
        study: &Study,
        format: MeshFormat,
        input: &str,
    ) -> Option<CoreResult<Vec<u8>>> {
        let a = self.built.as_ref().ok()?;
        let mut comment = anatomical::header_comment(&a.summary, &self.surface, input);
        comment.push_str(&format!(
            "; phase {}; every phase of the study turned by one septum ({})",
            self.phase, study.septum.source
        ));
        let shift = self.displacement_mm.as_deref();
        if shift.is_some() {
            comment.push_str(&format!(
                "; point data displacement_mm: from the same vertex in phase {}",
                study.septum.phase
            ));
        }
        let regions = Regions {
            array: "region",
            ids: &a.regions,
            names: &REGION_NAMES,
        };
        let point_data = shift.map(|d| ("displacement_mm", d));
        Some(io::write_mesh_with(
            &a.mesh,
            format,
            point_data,
            Some(&regions),
            &comment,
        ))
    }

    /// The layout's entry in a report: its `file` name and figures, or a `note` saying why
    /// there is none.
    pub fn entry(&self, file: Option<&str>) -> Value {
        let (mean, max) = self.displacement_stats().unzip();
        match &self.built {
            Ok(a) => json!({
                "phase": self.phase,
                "surface": self.surface,
                "file": file,
                "summary": a.summary,
                "septum_turn_deg": self.septum_turn_deg,
                "displacement_mean_mm": mean,
                "displacement_max_mm": max,
            }),
            Err(why) => json!({
                "phase": self.phase,
                "surface": self.surface,
                "file": Value::Null,
                "note": why,
            }),
        }
    }
}

/// The study's layouts, in the order of the surfaces given.
#[derive(Debug, Clone)]
pub struct Study {
    pub layout: Layout,
    pub septum: StudySeptum,
    pub layouts: Vec<PhaseLayout>,
}

impl Study {
    /// A report's `anatomical_meshes`: the layout, the septum and each layout's entry
    /// ([`PhaseLayout::entry`], `files[i]` the file name of layout i, None where none was
    /// written).
    pub fn report(&self, format: MeshFormat, files: &[Option<String>]) -> Value {
        let entries: Vec<Value> = self
            .layouts
            .iter()
            .enumerate()
            .map(|(i, l)| l.entry(files.get(i).cloned().flatten().as_deref()))
            .collect();
        json!({
            "format": format.extension(),
            "layout": { "rings": self.layout.rings, "points": self.layout.points },
            "septum": self.septum,
            "displacement_from_phase": self.septum.phase,
            "layouts": entries,
        })
    }
}

/// The layouts of `items`, all on the septum of the `preferred` phase (the LV's end-diastole)
/// when its file says where the septum is, else of the first phase that does; an error when no
/// phase can give the septum (nothing could be laid out).
pub fn of_study(
    items: &[PhaseSurface],
    preferred: Option<&str>,
    layout: Layout,
) -> Result<Study, String> {
    Layout::new(layout.rings, layout.points)?;
    let septum = study_septum(items, preferred)?;
    let direction = Vec3::from(septum.direction);
    let mut layouts: Vec<PhaseLayout> = items
        .iter()
        .map(|item| layout_of(item, &direction, &septum.source, layout))
        .collect();
    let references: Vec<Option<Vec<Vec3>>> = layouts
        .iter()
        .map(|l| {
            let reference = layouts
                .iter()
                .find(|r| r.phase == septum.phase && r.surface == l.surface)?;
            reference
                .built
                .as_ref()
                .ok()
                .map(|a| a.mesh.positions.clone())
        })
        .collect();
    for (l, reference) in layouts.iter_mut().zip(references) {
        if let (Ok(a), Some(r)) = (&l.built, reference) {
            l.displacement_mm = (r.len() == a.mesh.positions.len()).then(|| {
                a.mesh
                    .positions
                    .iter()
                    .zip(&r)
                    .map(|(p, q)| (p - q).norm())
                    .collect()
            });
        }
    }
    Ok(Study {
        layout,
        septum,
        layouts,
    })
}

/// The septum of the first item that can give one, the `preferred` phase's first (its LV_ENDO
/// before its LV_EPI: the cavity's centre is the one the septum is seen from elsewhere): the one
/// direction every layout (and every hexahedral wall, `volumes --hex-meshes`) of a study is
/// turned by.
pub fn study_septum(
    items: &[PhaseSurface],
    preferred: Option<&str>,
) -> Result<StudySeptum, String> {
    let rank = |item: &PhaseSurface| {
        (
            Some(item.phase) != preferred,
            !item.surface.eq_ignore_ascii_case("LV_ENDO"),
        )
    };
    let mut order: Vec<&PhaseSurface> = items.iter().collect();
    // Stable: phases keep their order within a rank.
    order.sort_by_key(|item| rank(item));
    let mut why = None;
    for item in order {
        let Some((mesh, base)) = item.mesh else {
            continue;
        };
        if let Some(w) = anatomical::refusal(item.set, Some(item.surface)) {
            why.get_or_insert(w);
            continue;
        }
        match anatomical::orientation_of(item.set, mesh, base) {
            Ok(o) => {
                return Ok(StudySeptum {
                    phase: item.phase.to_string(),
                    surface: item.surface.to_string(),
                    direction: [o.septum.x, o.septum.y, o.septum.z],
                    source: format!("{} ({}) of phase {}", o.source, o.points, item.phase),
                })
            }
            Err(w) => {
                why.get_or_insert(w);
            }
        }
    }
    Err(why.unwrap_or_else(|| "no phase has a closed LV surface to lay out".to_string()))
}

/// One item's layout on the study's septum, `direction` taken across the item's own axis.
fn layout_of(item: &PhaseSurface, direction: &Vec3, source: &str, layout: Layout) -> PhaseLayout {
    let mut out = PhaseLayout {
        phase: item.phase.to_string(),
        surface: item.surface.to_string(),
        built: Err(String::new()),
        septum_turn_deg: None,
        displacement_mm: None,
    };
    out.built = match item.mesh {
        None => Err("no closed mesh of this surface in this phase".to_string()),
        Some((mesh, base)) => {
            if let Some(why) = anatomical::surface_refusal(item.surface) {
                Err(why)
            } else {
                let across = orientation_across(direction, &base.normal);
                out.septum_turn_deg =
                    across.and_then(|o| own_turn_deg(item, mesh, base, &o.septum));
                across
                    .ok_or_else(|| {
                        "the study's septum lies along this phase's long axis".to_string()
                    })
                    .and_then(|orientation| {
                        anatomical::build(mesh, base, &orientation, layout)
                            .map_err(|e| anatomical::reason(&e))
                    })
                    .map(|mut a| {
                        a.summary.septum_from = source.to_string();
                        a
                    })
            }
        }
    };
    out
}

/// The study's septum `direction` taken across one phase's `axis` (its part along the axis
/// removed): the orientation that phase is laid out by; None when the direction is the axis.
pub fn orientation_across(direction: &Vec3, axis: &Vec3) -> Option<Orientation> {
    let n = axis.try_normalize(1e-12)?;
    let septum = (direction - n * direction.dot(&n)).try_normalize(1e-6)?;
    Some(Orientation {
        septum,
        source: "the study's septum",
        points: 0,
    })
}

/// The angle between the study's septum and the one this phase's own file gives (degrees).
fn own_turn_deg(item: &PhaseSurface, mesh: &TriMesh, base: &ClipPlane, used: &Vec3) -> Option<f64> {
    if !septum::said(item.set) {
        return None;
    }
    let own = anatomical::orientation_of(item.set, mesh, base).ok()?;
    Some(own.septum.dot(used).clamp(-1.0, 1.0).acos().to_degrees())
}

#[cfg(test)]
mod tests;
