//! The contours a reconstruction leaves out, and the one warning line per kind that names them.
//!
//! The method reconstructs one cavity per surface, and every contour of the surface shapes it
//! twice: its slice's ring seeds the initial tube and its points attract the surface. Three kinds
//! of contour cannot be a section of that cavity, and following them spoils the mesh where the
//! data are good:
//! - a stray ([`super::strays`]): a contour, or a small group of them, further from the rest than
//!   half the span of the rest (another series, a typo in a coordinate), which the tube threads with
//!   the real rings, so that the mesh passes through itself (`sim-stray-200mm` in
//!   scripts/hostile.py);
//! - a speck ([`super::specks`]): a short-axis slice whose ring is under a tenth of the ring one
//!   slice away, anywhere but at the apex (a slice past the base grazing the rim, a stray click),
//!   where the tube narrows to a point (Hausdorff 1.7 -> 14.5 mm in the held-out study);
//! - a long-axis speck ([`super::lax_specks`]): a curve in a long-axis plane under a tenth of the
//!   data's extent along the axis (a click in a 2- or 4-chamber view), which pulls a spike of the
//!   wall towards itself (27 mm on SurFCo, session 15).
//!
//! All are left out by default (`Params::keep_specks` keeps them: the paper's method, where
//! every contour is data) and the load-time warning says so, naming each with its file line, so
//! nothing is lost silently (docs/VALIDATION.md, "Session 14: specks and stray contours" and
//! session 15). No rule fires on any real file or on the planner's acquisitions, whose meshes are unchanged.

use super::axis::analyse;
use super::checks::{one_line, surface_groups};
use super::clean::contour_length;
use super::lax_specks::lax_specks;
use super::specks::{specks, SPECK_RATIO};
use super::strays::strays;
use super::undamaged::cleaned_undamaged;
use super::{Contour, ContourSet};
use serde::Serialize;

/// Above this many contours per surface the load-time check is skipped (the layout is quadratic
/// in the count; a reconstruction refuses more than `pipeline::prepare::MAX_CONTOURS` anyway).
const MAX_CONTOURS: usize = 2000;

/// Why a contour was left out.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum Why {
    /// In a group (often of one) further than the span of the rest of its surface from the
    /// nearest contour kept: `gap_mm`, bounding box to bounding box.
    Stray { gap_mm: f64 },
    /// Its slice's ring (`perimeter_mm` around) is under `specks::SPECK_RATIO` of the ring of
    /// contour `next_id` one slice away (`next_perimeter_mm`).
    Speck {
        perimeter_mm: f64,
        next_id: String,
        next_perimeter_mm: f64,
    },
    /// A long-axis curve `length_mm` long, under `specks::SPECK_RATIO` of its surface's
    /// `extent_mm` along the axis ([`super::lax_specks`]).
    LaxSpeck { length_mm: f64, extent_mm: f64 },
    /// Named by the user (`Params::leave_out`): no rule's figures, the user's reason.
    ByUser,
}

/// One contour left out of a reconstruction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SetAside {
    pub id: String,
    /// 1-based line of its first point in its file (0 if not from a file).
    pub line: usize,
    #[serde(flatten)]
    pub why: Why,
}

impl SetAside {
    pub(crate) fn of(c: &Contour, why: Why) -> Self {
        SetAside {
            id: c.id.clone(),
            line: c.first_line,
            why,
        }
    }

    /// How the warning names it, with why (`"id" (line N, DETAIL)`, see [`super::cite`]).
    fn name(&self, detail: &str) -> String {
        super::cite(&self.id, self.line, detail)
    }

    /// The start of [`Self::name`] whatever the detail: how a warning already said is found.
    fn key(&self) -> String {
        let named = self.name("~");
        named.trim_end_matches("~)").to_string()
    }
}

/// `contours` (one surface, cleaned) without their strays and then their specks, and what was
/// left out, strays first, specks in file order.
pub fn set_aside(contours: Vec<Contour>) -> (Vec<Contour>, Vec<SetAside>) {
    let mut out: Vec<SetAside> = Vec::new();
    let stray = strays(&contours);
    let mut kept: Vec<Contour> = Vec::with_capacity(contours.len());
    for (i, c) in contours.into_iter().enumerate() {
        match stray.iter().find(|(j, _)| *j == i) {
            Some(&(_, gap_mm)) => out.push(SetAside::of(&c, Why::Stray { gap_mm })),
            None => kept.push(c),
        }
    }
    let mut specks_out: Vec<SetAside> = Vec::new();
    let (k, lax_out) = without_lax_specks(kept);
    kept = k;
    specks_out.extend(lax_out);
    // Each round lays out what is left; a slice can hide a speck behind another (the tube takes
    // a slice's longest closed loop, however short, before its open curves).
    while let Some((k, left_out)) = one_round(&kept) {
        specks_out.extend(left_out);
        kept = k;
    }
    specks_out.sort_by_key(|s| s.line);
    out.extend(specks_out);
    (kept, out)
}

/// The specks of one layout of `contours` left out: in each speck's slice, the contours shorter
/// than [`SPECK_RATIO`] of the adjacent ring (all of the slice's if none is: its ring is short
/// only once joined). None when there is no speck (or no layout).
fn one_round(contours: &[Contour]) -> Option<(Vec<Contour>, Vec<SetAside>)> {
    let layout = analyse(contours).ok()?;
    let found = specks(contours, &layout);
    if found.is_empty() {
        return None;
    }
    let members = |slice: usize| -> Vec<usize> {
        layout
            .slices
            .get(slice)
            .map(|s| s.contours.clone())
            .unwrap_or_default()
    };
    let mut left_out = vec![false; contours.len()];
    let mut out = Vec::new();
    for s in found {
        let next_id = members(s.next.slice)
            .first()
            .and_then(|&j| contours.get(j))
            .map(|c| c.id.clone())
            .unwrap_or_default();
        let slice = members(s.ring.slice);
        let short: Vec<usize> = slice
            .iter()
            .copied()
            .filter(|&j| {
                contours
                    .get(j)
                    .is_some_and(|c| contour_length(c) < SPECK_RATIO * s.next.perimeter_mm)
            })
            .collect();
        for j in if short.is_empty() { slice } else { short } {
            let (Some(c), Some(flag)) = (contours.get(j), left_out.get_mut(j)) else {
                continue;
            };
            *flag = true;
            let why = Why::Speck {
                perimeter_mm: contour_length(c),
                next_id: next_id.clone(),
                next_perimeter_mm: s.next.perimeter_mm,
            };
            out.push(SetAside::of(c, why));
        }
    }
    let kept = contours
        .iter()
        .zip(&left_out)
        .filter(|(_, out)| !**out)
        .map(|(c, _)| c.clone())
        .collect();
    Some((kept, out))
}

/// `contours` without their long-axis specks, and those left out.
fn without_lax_specks(contours: Vec<Contour>) -> (Vec<Contour>, Vec<SetAside>) {
    let Ok(layout) = analyse(&contours) else {
        return (contours, Vec::new());
    };
    let found = lax_specks(&contours, &layout);
    if found.is_empty() {
        return (contours, Vec::new());
    }
    let mut out = Vec::new();
    let mut kept = Vec::with_capacity(contours.len());
    for (i, c) in contours.into_iter().enumerate() {
        match found.iter().find(|s| s.index == i) {
            Some(s) => out.push(SetAside::of(
                &c,
                Why::LaxSpeck {
                    length_mm: s.length_mm,
                    extent_mm: s.extent_mm,
                },
            )),
            None => kept.push(c),
        }
    }
    (kept, out)
}

/// What a reconstruction of each surface of `set` would leave out (at the defaults).
pub fn found_in(set: &ContourSet) -> Vec<SetAside> {
    surface_groups(set)
        .into_iter()
        .filter(|g| g.len() <= MAX_CONTOURS)
        .flat_map(|g| set_aside(cleaned_undamaged(&g).1).1)
        .collect()
}

/// The load-time warnings: one line for the strays and one for the specks of every surface.
pub fn set_aside_warnings(set: &ContourSet) -> Vec<String> {
    warnings(&found_in(set))
}

/// One line per kind naming the contours left out, why, and that they are left out.
pub fn warnings(list: &[SetAside]) -> Vec<String> {
    let mut stray: Vec<String> = Vec::new();
    let mut speck: Vec<String> = Vec::new();
    for s in list {
        match &s.why {
            Why::Stray { gap_mm } => {
                stray.push(s.name(&format!("{gap_mm:.0} mm from the nearest contour kept")))
            }
            Why::Speck {
                perimeter_mm,
                next_id,
                next_perimeter_mm,
            } => {
                let pct = 100.0 * perimeter_mm / next_perimeter_mm;
                let digits = usize::from(pct < 1.0);
                speck.push(s.name(&format!(
                    "{perimeter_mm:.1} mm around, {pct:.digits$} % of the ring of {next_id:?} \
                     one slice away"
                )));
            }
            Why::LaxSpeck {
                length_mm,
                extent_mm,
            } => speck.push(s.name(&format!(
                "{length_mm:.1} mm long in a long-axis plane, where the data span {extent_mm:.0} \
                 mm along the axis"
            ))),
            // Asked for, so no warning: the caller says it as a note ([`asked`]).
            Why::ByUser => {}
        }
    }
    let mut out = one_line(
        stray,
        "lies far from the rest (another series or a wrong coordinate?); it is left out of the \
         reconstruction",
        "lie far from the rest (another series or wrong coordinates?); they are left out of the \
         reconstruction",
    );
    out.extend(one_line(
        speck,
        "is a speck, not a section of the cavity; it is left out of the reconstruction",
        "are specks, not sections of the cavity; they are left out of the reconstruction",
    ));
    out
}

/// The contours of `contours` that `list` names (by identifier and first line, as the core
/// leaves them out), in `list`'s order, one per entry (an entry naming none is skipped); two
/// entries alike (line 0: not from a file) take two contours alike in turn.
pub fn named(contours: &[Contour], list: &[SetAside]) -> Vec<Contour> {
    let mut taken = vec![false; contours.len()];
    list.iter()
        .filter_map(|s| {
            let i = (0..contours.len()).find(|&i| {
                !taken[i] && contours[i].id == s.id && contours[i].first_line == s.line
            })?;
            taken[i] = true;
            Some(contours[i].clone())
        })
        .collect()
}

/// Warning lines for the contours of `list` that none of `said` names (a run can leave out a
/// contour the load-time check did not name: its surface chosen case-insensitively, slices shifted
/// by the alignment, more than the three names a line shows).
pub fn unannounced(list: &[SetAside], said: &[String]) -> Vec<String> {
    let missing: Vec<SetAside> = list
        .iter()
        .filter(|s| !said.iter().any(|w| w.contains(&s.key())))
        .cloned()
        .collect();
    warnings(&missing)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contours::specks::fixtures::{dome, ring};

    /// Each entry takes its own contour, in the list's order, even two alike (id and line 0),
    /// and an entry naming none is skipped: the distances measured on them pair with the list.
    #[test]
    fn named_takes_one_contour_per_entry_in_order() {
        let a0 = ring("a", 10.0, 0.0, 0.0, 8, 0);
        let a1 = ring("a", 20.0, 10.0, 0.0, 8, 0);
        let b = ring("b", 30.0, 20.0, 0.0, 8, 40);
        let pool = vec![a0.clone(), b.clone(), a1.clone()];
        let entry = |c: &Contour| SetAside::of(c, Why::ByUser);
        let list = [
            entry(&b),
            entry(&a0),
            entry(&a1),
            entry(&ring("z", 1.0, 0.0, 0.0, 3, 9)),
        ];
        assert_eq!(named(&pool, &list), vec![b, a0, a1]);
    }

    #[test]
    fn a_speck_and_a_stray_are_left_out_and_named_once_each() {
        let mut c = dome();
        c.push(ring("past", 0.5, 45.0, 29.0, 3, 302));
        c.push(ring("far", 30.0, 0.0, 300.0, 60, 305));
        let (kept, out) = set_aside(c.clone());
        let ids: Vec<&str> = kept.iter().map(|c| c.id.as_str()).collect();
        assert_eq!(ids, ["s0", "s1", "s2", "s3", "s4"]);
        assert_eq!(out.len(), 2);
        assert_eq!(out[0].id, "far");
        // 240 mm across and 40 mm up to the box of the basal ring.
        let gap = 240f64.hypot(40.0);
        assert!(matches!(out[0].why, Why::Stray { gap_mm } if (gap_mm - gap).abs() < 1e-9));
        let w = warnings(&out);
        assert_eq!(
            w,
            [
                "contour \"far\" (line 305, 243 mm from the nearest contour kept) lies far from \
                 the rest (another series or a wrong coordinate?); it is left out of the \
                 reconstruction",
                "contour \"past\" (line 302, 2.6 mm around, 1 % of the ring of \"s4\" one slice \
                 away) is a speck, not a section of the cavity; it is left out of the \
                 reconstruction"
            ]
        );
        // The load-time check says the same; a run that left out the same says nothing more.
        let set = ContourSet {
            contours: c,
            ..ContourSet::default()
        };
        assert_eq!(set_aside_warnings(&set), w);
        assert!(unannounced(&out, &w).is_empty());
        assert_eq!(unannounced(&out, &w[..1]), w[1..]);
    }

    #[test]
    fn contours_of_files_without_lines_are_named_without_a_line() {
        // Label maps, MATLAB and DICOM files give every contour line 0: no "(line 0".
        let mut c = dome();
        c.push(ring("far", 30.0, 0.0, 300.0, 60, 0));
        let (_, out) = set_aside(c);
        let w = warnings(&out);
        assert_eq!(
            w,
            [
                "contour \"far\" (243 mm from the nearest contour kept) lies far from the rest \
              (another series or a wrong coordinate?); it is left out of the reconstruction"
            ]
        );
        assert!(unannounced(&out, &w).is_empty());
        assert_eq!(super::super::cite("s1", 0, ""), "\"s1\"");
        assert_eq!(super::super::cite("s1", 7, ""), "\"s1\" (line 7)");
    }

    #[test]
    fn a_dot_in_a_slice_of_open_curves_goes_and_the_curves_stay() {
        // The basal slice as two open halves and a 0.5 mm closed loop inside: the tube would take
        // the loop (a slice's closed loop comes first); only the loop is left out.
        let mut c = dome();
        let mut halves = ring("s4", 30.0, 40.0, 0.0, 60, 242);
        let tail = halves.pieces[0].points.split_off(30);
        halves.pieces[0].closed = false;
        let mut other = halves.clone();
        other.id = "s4b".into();
        other.first_line = 400;
        other.pieces[0].points = tail;
        c[4] = halves;
        c.push(other);
        c.push(ring("dot", 0.5, 40.0, 5.0, 3, 500));
        let (kept, out) = set_aside(c);
        let ids: Vec<&str> = out.iter().map(|s| s.id.as_str()).collect();
        assert_eq!(ids, ["dot"]);
        assert_eq!(kept.len(), 6);
    }

    #[test]
    fn every_contour_of_a_speck_slice_goes_and_a_clean_stack_keeps_all() {
        let (kept, out) = set_aside(dome());
        assert_eq!((kept.len(), out.len()), (5, 0));
        let mut c = dome();
        c.push(ring("pa", 0.3, 45.0, 29.0, 3, 400));
        c.push(ring("pb", 0.3, 45.0, 27.0, 3, 410));
        let (kept, out) = set_aside(c);
        assert_eq!(kept.len(), 5);
        let ids: Vec<&str> = out.iter().map(|s| s.id.as_str()).collect();
        assert_eq!(ids, ["pa", "pb"]);
        let w = warnings(&out);
        assert_eq!(w.len(), 1);
        assert!(
            w[0].starts_with("2 contours (\"pa\" (line 400, ")
                && w[0].ends_with("are specks, not sections of the cavity; they are left out of the reconstruction"),
            "{w:?}"
        );
    }
}
