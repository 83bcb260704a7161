//! From a user's contour set to the cleaned contours of one surface (Villard et al. 2018, section 2:
//! "one surface at a time"; cleaning as in METHOD.md's Input section).

use crate::contours::axis::{analyse, Layout};
use crate::contours::checks::check_units;
use crate::contours::clean::cleaned_contour;
use crate::contours::set_aside::SetAside;
use crate::contours::slice_loops::without_second_loops;
use crate::contours::{Contour, ContourSet};
use crate::error::{CoreError, Result};

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

/// Cleans every piece (non-finite points, duplicates, jumps) and drops contours left empty.
pub fn clean_contours(contours: &[&Contour]) -> Vec<Contour> {
    contours.iter().filter_map(|c| cleaned_contour(c)).collect()
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
