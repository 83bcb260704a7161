//! From a user's contour set to the cleaned contours of one surface (Villard et al. 2018, section 2:
//! "one surface at a time"; cleaning as in METHOD.md's Input section).

use crate::contours::axis::{analyse, Layout};
use crate::contours::checks::check_units;
use crate::contours::set_aside::{SetAside, Why};
use crate::contours::slice_loops::without_second_loops;
use crate::contours::undamaged::cleaned_undamaged;
use crate::contours::{biv_epi, Contour, ContourSet};
use crate::error::{CoreError, Result};
use crate::params::Params;

/// Picks the contours of the requested surface: the only surface by default, an error listing the
/// surfaces when there are several and none was chosen.
pub fn select_surface<'a>(
    set: &'a ContourSet,
    requested: Option<&str>,
) -> Result<Vec<&'a Contour>> {
    let available = set.surfaces();
    match requested {
        Some(name) => {
            let chosen: Vec<&Contour> = set
                .contours
                .iter()
                .filter(|c| {
                    c.surface
                        .as_deref()
                        .is_some_and(|s| s.eq_ignore_ascii_case(name))
                })
                .collect();
            if chosen.is_empty() {
                return Err(CoreError::UnknownSurface {
                    requested: crate::contours::biv_epi::requested_name(name),
                    available,
                });
            }
            Ok(chosen)
        }
        None if available.len() > 1 => Err(CoreError::SurfaceRequired { available }),
        None => Ok(set.contours.iter().collect()),
    }
}

/// Cleans every piece (non-finite points, duplicates, jumps), drops contours left empty and
/// leaves out the damaged pieces: far from the rest of their surface (`contours::far_pieces`) or
/// off their contour's plane (`contours::off_plane`).
pub fn clean_contours(contours: &[&Contour]) -> Vec<Contour> {
    cleaned_undamaged(contours).1
}

/// Most contours of one surface a reconstruction takes: real acquisitions have tens; the SAX/LAX
/// analysis is quadratic in the count (100,000 one-point "contours" never finished).
pub const MAX_CONTOURS: usize = 1000;

/// Refuses, before the SAX/LAX split, what the split would handle badly: more contours than any
/// acquisition (it would seem to hang) and coordinates that cannot be millimetres (its mm
/// tolerances would fail with a misleading "no short-axis group").
pub fn check_count_and_units(contours: &[Contour]) -> Result<()> {
    if contours.len() > MAX_CONTOURS {
        return Err(CoreError::TooManyContours {
            found: contours.len(),
            max: MAX_CONTOURS,
        });
    }
    check_units(contours)
}

/// `contours` (one surface) without those whose id `ids` names, and those, as left out by the
/// user, in `contours`' order. Every id must name a contour of `file` (else
/// [`CoreError::UnknownContour`] listing this surface's ids); one of another surface is no
/// error and leaves nothing out here.
pub fn leave_out(
    contours: Vec<Contour>,
    ids: &[String],
    file: &ContourSet,
) -> Result<(Vec<Contour>, Vec<SetAside>)> {
    if ids.is_empty() {
        return Ok((contours, Vec::new()));
    }
    if let Some(unknown) = ids
        .iter()
        .find(|id| !file.contours.iter().any(|c| &c.id == *id))
    {
        let mut available: Vec<String> = Vec::new();
        for c in &contours {
            if !available.contains(&c.id) {
                available.push(c.id.clone());
            }
        }
        return Err(CoreError::UnknownContour {
            id: unknown.clone(),
            available,
        });
    }
    let (out, kept): (Vec<Contour>, Vec<Contour>) =
        contours.into_iter().partition(|c| ids.contains(&c.id));
    let asked = out.iter().map(|c| SetAside::of(c, Why::ByUser)).collect();
    Ok((kept, asked))
}

/// The contours of the surface `params` selects that its `leave_out` names, as left out by the
/// user (the run's `set_aside` entries), with those contours (cleaned, as the file gives them,
/// one per entry: how far the mesh passes from them is measured on these); checks every id as
/// [`leave_out`] does. Empty without a list.
pub fn asked(file: &ContourSet, params: &Params) -> Result<(Vec<SetAside>, Vec<Contour>)> {
    if params.leave_out.is_empty() {
        return Ok((Vec::new(), Vec::new()));
    }
    let derived = biv_epi::with_derived(file, params.surface.as_deref());
    let source = derived.as_ref().unwrap_or(file);
    let cleaned = clean_contours(&select_surface(source, params.surface.as_deref())?);
    let pool = cleaned.clone();
    let entries = leave_out(cleaned, &params.leave_out, file)?.1;
    let contours = crate::contours::set_aside::named(&pool, &entries);
    Ok((entries, contours))
}

/// `file` without every contour whose id `ids` names, whatever its surface (None: no ids, the
/// file as it is): what the run, its alignment and its measures see.
pub fn without_ids(file: &ContourSet, ids: &[String]) -> Option<ContourSet> {
    if ids.is_empty() {
        return None;
    }
    let mut out = file.clone();
    out.contours.retain(|c| !ids.contains(&c.id));
    Some(out)
}

/// `contours` without the strays and specks a reconstruction leaves out (`contours::set_aside`),
/// unless `keep_specks`, and what was left out.
pub fn set_aside(contours: Vec<Contour>, keep_specks: bool) -> (Vec<Contour>, Vec<SetAside>) {
    if keep_specks {
        return (contours, Vec::new());
    }
    crate::contours::set_aside::set_aside(contours)
}

/// The layout of `contours`; with `drop_second_loops`, the closed loops lying apart from their
/// slice's main loop (`contours::slice_loops`) are left out first and what is left is laid out.
pub fn layout(contours: Vec<Contour>, drop_second_loops: bool) -> Result<(Vec<Contour>, Layout)> {
    let layout = analyse(&contours)?;
    if !drop_second_loops {
        return Ok((contours, layout));
    }
    let (kept, dropped) = without_second_loops(&contours, &layout);
    if dropped == 0 {
        return Ok((contours, layout));
    }
    let layout = analyse(&kept)?;
    Ok((kept, layout))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contours::Polyline;
    use crate::geometry::v3;

    fn contour(id: &str, surface: &str, line: usize) -> Contour {
        Contour {
            id: id.into(),
            surface: Some(surface.into()),
            pieces: vec![Polyline {
                points: vec![v3(0.0, 0.0, 0.0), v3(1.0, 0.0, 0.0), v3(0.0, 1.0, 0.0)],
                closed: true,
            }],
            first_line: line,
        }
    }

    /// Ids of this surface are left out in its order, one of another surface leaves nothing out
    /// here, one of no surface is an error listing this surface's ids (at most eight, then a
    /// count).
    #[test]
    fn leave_out_takes_this_surfaces_ids_and_refuses_unknown_ones() {
        let lv: Vec<Contour> = (0..10)
            .map(|k| contour(&format!("s{k}"), "LV", 2 + k))
            .collect();
        let file = ContourSet {
            contours: lv
                .iter()
                .cloned()
                .chain([contour("rv1", "RV", 40)])
                .collect(),
            ..ContourSet::default()
        };
        let ids = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let (kept, out) = leave_out(lv.clone(), &ids(&["s7", "rv1", "s2"]), &file).unwrap();
        assert_eq!(kept.len(), 8);
        let named: Vec<(&str, usize)> = out.iter().map(|s| (s.id.as_str(), s.line)).collect();
        assert_eq!(named, [("s2", 4), ("s7", 9)]);
        assert!(out.iter().all(|s| s.why == Why::ByUser));
        let (kept, out) = leave_out(lv.clone(), &ids(&["rv1"]), &file).unwrap();
        assert_eq!((kept.len(), out.len()), (10, 0));
        let e = leave_out(lv, &ids(&["s2", "S3"]), &file).unwrap_err();
        assert_eq!(e.code(), "unknown_contour");
        assert_eq!(
            e.to_string(),
            "no contour \"S3\" to leave out; the contours are \"s0\", \"s1\", \"s2\", \"s3\", \
             \"s4\", \"s5\", \"s6\", \"s7\" and 2 more"
        );
    }
}
