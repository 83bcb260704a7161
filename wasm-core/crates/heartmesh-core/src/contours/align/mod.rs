//! Breath-hold slice alignment (an option, `Params::align_slices`; off by default because the
//! method of Villard et al. 2018 reconstructs the contours as given).
//!
//! Every image of a cine CMR study is acquired in its own breath-hold, and the heart never sits in
//! quite the same place: each short-axis slice and each long-axis view is shifted in its own plane
//! by a few mm. The reconstruction approximates the contours as given and so inherits the
//! offsets. This module moves every slice and view (all surfaces in it together) in its plane
//! until the short- and long-axis curves meet where their planes cross ([`estimate`]), and returns
//! the shifted contours with the shifts found ([`Alignment`]); each short-axis slice also moves
//! along its own normal where the long-axis curves' slopes see that ([`through`], since session
//! 12). Measured in docs/VALIDATION.md, "Session 9: breath-hold alignment (option)", "Session 11:
//! through-plane alignment" and "Session 12: through-plane alignment, paired".

mod estimate;
mod groups;
mod information;
#[cfg(test)]
mod tests;
mod through;

use super::{ContourKind, ContourSet};
use crate::geometry::Vec3;
pub use information::Information;
use serde::Serialize;

/// The shift found for one short-axis slice or long-axis view.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GroupShift {
    /// "SAX" or "LAX".
    pub kind: ContourKind,
    /// "SAX 3" (slices numbered apex to base from 1), or the ids of a view's contours joined
    /// by ", ".
    pub label: String,
    pub contour_ids: Vec<String>,
    /// Shift applied to every point of the group's contours (mm, in the group's plane).
    pub shift_mm: [f64; 3],
    /// Crossings of the other kind's curves matched to this group's curves before alignment. A
    /// group moves only when at least two of them involve a closed ring (an LV ring or a view's
    /// curve crossing one); views and slices of open curves alone (e.g. an RV-only view) stay
    /// put.
    pub crossings: usize,
    /// How well the crossings determine the shift, along and across the long axis (a study
    /// figure, not in the report).
    #[serde(skip)]
    pub information: Information,
    /// A short-axis slice's shift along its own normal, the long axis (mm, + towards the base;
    /// part of `shift_mm`; 0 for a view, or without [`Options::through_plane`]).
    pub through_plane_mm: f64,
    /// How well the crossings determine that offset (weighted crossings, each at most the squared
    /// cosine of its curve's angle to the plane; 0 for a view). Not in the report.
    #[serde(skip)]
    pub through_information: f64,
}

/// How the alignment runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Also move each short-axis slice along its own normal (docs/VALIDATION.md, "Session 11:
    /// through-plane alignment"). On by default since session 12: paired over 192 misaligned
    /// acquisitions it lowers the Hausdorff distance by 0.09 mm (median) and changes nothing
    /// measurable on aligned ones; off is the session-9 in-plane alignment, kept for studies.
    pub through_plane: bool,
}

impl Options {
    /// The session-9 alignment: shifts in each image's own plane only.
    pub const IN_PLANE: Options = Options {
        through_plane: false,
    };
}

impl Default for Options {
    fn default() -> Self {
        Options {
            through_plane: true,
        }
    }
}

/// What the alignment did.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Alignment {
    pub groups: Vec<GroupShift>,
    /// Estimation rounds run.
    pub rounds: usize,
    /// Mean in-plane distance (mm) from where a curve crosses another image's plane to that
    /// image's curve of the same surface, before and after the shifts (0 when nothing crossed).
    pub residual_before_mm: f64,
    pub residual_after_mm: f64,
    /// Why nothing moved, when nothing could (no long-axis views, no crossings, ...).
    pub note: Option<String>,
    /// The short-axis stack's axis (unit; zero when nothing was aligned). Not in the report.
    #[serde(skip)]
    pub axis: [f64; 3],
}

impl Alignment {
    /// No shifts, with the reason.
    fn unchanged(note: String) -> Alignment {
        Alignment {
            groups: Vec::new(),
            rounds: 0,
            residual_before_mm: 0.0,
            residual_after_mm: 0.0,
            note: Some(note),
            axis: [0.0; 3],
        }
    }

    /// Largest shift applied (mm).
    pub fn max_shift_mm(&self) -> f64 {
        self.groups
            .iter()
            .map(|g| g.shift_mm.iter().map(|c| c * c).sum::<f64>().sqrt())
            .fold(0.0, f64::max)
    }
}

/// Aligns the whole set (every surface: one breath-hold moves them all). Returns the shifted
/// contours (landmarks and warnings as they were) and what was done. Never fails: a set with
/// nothing to align comes back unchanged with a note saying why.
pub fn align_slices(set: &ContourSet) -> (ContourSet, Alignment) {
    align_slices_with(set, Options::default())
}

/// Above this crossing residual (mm) a run suggests the alignment: consistent contours give a few
/// hundredths of a mm or less (simulated sections 0.01, the SurFCo example 3e-6), hand-traced
/// real studies with breath-hold offsets 1.9-2.3 mm (the biv-me files; docs/VALIDATION.md,
/// session 9). Between, tracing noise and small offsets cannot be told apart: no suggestion.
pub const SUGGEST_ALIGNMENT_ABOVE_MM: f64 = 1.0;

/// How far apart the images' curves are where their planes cross, as the file places them: the
/// mean in-plane distance (mm) from where a curve crosses another image's plane to that image's
/// curve of the same surface, as [`Alignment::residual_before_mm`] but without aligning. A run
/// reports it so that a user can see the images disagree (breath-hold misalignment, above about
/// 1 mm; consistent contours a few hundredths) and try the alignment. None when no short- and
/// long-axis curves of one surface cross.
pub fn crossing_residual(set: &ContourSet) -> Option<f64> {
    let grouping = groups::group(set).ok()?;
    let (mean, matched) = estimate::residual_as_given(&grouping.groups, grouping.scale_mm);
    (matched > 0).then_some(mean)
}

/// Whether some contour of `set` belongs to a surface other than the right ventricle's (an LV
/// surface, or an unlabelled one): what the alignment is worth suggesting for. On RV-only files
/// the long-axis planes, planned through the LV's axis, cut the RV crescent obliquely, so a
/// breath-hold's shift along a plane's normal changes the RV section there far more than an LV's,
/// and the in-plane shifts chase it: in the held-out study of session 13 `--align-slices` made all
/// four RV-only cases worse (mean 0.61 -> 0.77 mm; a long-axis view shifted 7.7 mm where 3.7 were
/// injected) while it improved every LV case (docs/VALIDATION.md, "Session 13: held-out
/// acquisitions"). With an LV in the file (the biv-me files) its rings anchor the shifts.
pub fn anchored_beyond_rv(set: &ContourSet) -> bool {
    set.contours.iter().any(|c| {
        c.surface
            .as_deref()
            .is_none_or(|s| !s.trim().to_ascii_uppercase().starts_with("RV"))
    })
}

/// How the alignment of a file without some contours moves each of those contours: with the
/// image (short-axis slice or long-axis view) it lies in, by the shift its other curves got, as
/// one breath-hold moves the whole image. `file` is the whole file, `alignment` the alignment of
/// the file without `left_out` (each named by id and first line); a contour alone in its image,
/// or one the file's grouping cannot place, does not move (zero). What a contour left out of an
/// aligned run is measured at: where the run's frame puts it, not where the file drew it.
pub fn left_out_shifts(
    file: &ContourSet,
    left_out: &[(&str, usize)],
    alignment: &Alignment,
) -> Vec<Vec3> {
    let zero = Vec3::zeros();
    let Ok(grouping) = groups::group(file) else {
        return vec![zero; left_out.len()];
    };
    let named = |i: usize, (id, line): (&str, usize)| {
        file.contours
            .get(i)
            .is_some_and(|c| c.id == id && c.first_line == line)
    };
    left_out
        .iter()
        .map(|&who| {
            // The image the contour lies in, and the ids of its other curves.
            let Some(image) = grouping
                .groups
                .iter()
                .find(|g| g.members.iter().any(|&i| named(i, who)))
            else {
                return zero;
            };
            let others: Vec<&str> = image
                .members
                .iter()
                .filter(|&&i| !left_out.iter().any(|&l| named(i, l)))
                .filter_map(|&i| file.contours.get(i).map(|c| c.id.as_str()))
                .collect();
            alignment
                .groups
                .iter()
                .find(|g| g.contour_ids.iter().any(|id| others.contains(&id.as_str())))
                .map_or(zero, |g| {
                    Vec3::new(g.shift_mm[0], g.shift_mm[1], g.shift_mm[2])
                })
        })
        .collect()
}

/// [`align_slices`] with `options`.
pub fn align_slices_with(set: &ContourSet, options: Options) -> (ContourSet, Alignment) {
    let grouping = match groups::group(set) {
        Ok(g) => g,
        Err(note) => return (set.clone(), Alignment::unchanged(note)),
    };
    let groups = &grouping.groups;
    let has = |k: ContourKind| groups.iter().any(|g| g.kind == k);
    if !has(ContourKind::Lax) {
        return (
            set.clone(),
            Alignment::unchanged("no long-axis views: nothing to align the slices to".into()),
        );
    }
    let est = estimate::estimate(groups, grouping.scale_mm, options.through_plane);
    let mut out = set.clone();
    let mut shifts = Vec::with_capacity(groups.len());
    for (g, t) in groups.iter().zip(&est.shifts) {
        for &i in &g.members {
            if let Some(c) = out.contours.get_mut(i) {
                for p in c.pieces.iter_mut().flat_map(|p| p.points.iter_mut()) {
                    *p += t;
                }
            }
        }
        shifts.push(GroupShift {
            kind: g.kind,
            label: g.label.clone(),
            contour_ids: g
                .members
                .iter()
                .filter_map(|&i| set.contours.get(i).map(|c| c.id.clone()))
                .collect(),
            shift_mm: [t.x, t.y, t.z],
            crossings: 0,
            information: Information::default(),
            through_plane_mm: if g.kind == ContourKind::Sax {
                t.dot(&g.normal)
            } else {
                0.0
            },
            through_information: 0.0,
        });
    }
    let axis = grouping.axis;
    for (((s, &c), (g, h)), &ti) in shifts
        .iter_mut()
        .zip(&est.crossings)
        .zip(groups.iter().zip(&est.normal_matrices))
        .zip(&est.through_information)
    {
        s.crossings = c;
        s.through_information = ti;
        s.information = Information::of(h, &g.normal, &axis);
    }
    let note = (!est.moving.contains(&true)).then(|| {
        "no short- and long-axis curves of one surface, one of them a closed ring, cross each \
         other's planes: nothing moved"
            .to_string()
    });
    let alignment = Alignment {
        groups: shifts,
        rounds: est.rounds,
        residual_before_mm: est.before_mm,
        residual_after_mm: est.after_mm,
        note,
        axis: [axis.x, axis.y, axis.z],
    };
    (out, alignment)
}
