//! Load-time checks of a contour set: units, contours that are not curves, and identifiers reused
//! for curves in different planes (contours far from the rest: `contours::strays`).
//!
//! Each check turns a suspicious but usable input into one warning line for the user (the run goes
//! ahead); only coordinates whose span cannot be a heart in millimetres stop the reconstruction
//! ([`check_units`]), because the method's fixed spacings (1 mm resampling, 1.5 mm slice
//! tolerance) would then either merge every slice (metres) or multiply the work a thousandfold
//! (micrometres) and the user would get a misleading error or a run that seems to hang.

use crate::contours::far_pieces::{contour_far, left_out};
use crate::contours::plane::fit_plane;
use crate::contours::{Contour, ContourSet};
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;

/// Bounding-box spans outside this range (file units) get a "which units?" warning: a human heart
/// spans 50-150 mm; a small-animal heart about 10 mm.
const WARN_MIN_EXTENT_MM: f64 = 20.0;
const WARN_MAX_EXTENT_MM: f64 = 2000.0;

/// Spans outside this range are refused: below it the 1.5 mm same-slice tolerance merges slices
/// (a heart in metres spans about 0.1), above it the 1 mm resampling explodes (micrometres).
const MIN_EXTENT_MM: f64 = 3.0;
const MAX_EXTENT_MM: f64 = 10_000.0;

/// Pieces of one contour whose planes are further apart than this (mm, plus three times the first
/// piece's residual) are not one curve: the slice tolerance of the SAX grouping is 1.5 mm.
const REUSED_ID_GAP_MM: f64 = 3.0;

/// Largest side of the bounding box of the points (None without points).
pub fn extent<'a>(mut points: impl Iterator<Item = &'a Vec3>) -> Option<f64> {
    let first = *points.next()?;
    let (lo, hi) = points.fold((first, first), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
    Some((hi - lo).amax())
}

fn unit_question(extent: f64) -> Option<String> {
    let question = if extent < 1.0 {
        "metres?"
    } else if extent < WARN_MIN_EXTENT_MM {
        "centimetres, or a small-animal heart?"
    } else if extent > WARN_MAX_EXTENT_MM {
        "pixels or micrometres?"
    } else {
        return None;
    };
    Some(format!(
        "coordinates span {}; expected mm (a heart spans about 50-150 mm: {question})",
        span_text(extent)
    ))
}

/// A span as a person reads it: four decimals below 1, one below 100, whole numbers up to 1e5,
/// and beyond that in scientific notation (a file in nanometres or with values near 1e300 would
/// otherwise print hundreds of digits into one line of the app's status).
fn span_text(extent: f64) -> String {
    match extent {
        e if e < 1.0 => format!("{e:.4}"),
        e if e < 100.0 => format!("{e:.1}"),
        e if e < 1e5 => format!("{e:.0}"),
        e => format!("{e:.2e}"),
    }
}

/// The "which units?" warning, from the bounding box of the points of all contours that are curves
/// (a lone point or two say nothing about units; [`few_point_warnings`] reports them).
pub fn unit_warning(set: &ContourSet) -> Option<String> {
    let curves = set.contours.iter().filter(|c| !is_point_like(c));
    unit_question(extent(curves.flat_map(|c| c.points()))?)
}

/// Fewer than 3 points, or all points the same: not a curve.
fn is_point_like(c: &Contour) -> bool {
    c.point_count() < 3 || extent(c.points()) == Some(0.0)
}

/// Refuses contours whose span cannot be a heart in millimetres, saying which units they look like
/// and by how much to scale them.
pub fn check_units(contours: &[Contour]) -> Result<()> {
    let Some(e) = extent(contours.iter().flat_map(|c| c.points())) else {
        return Ok(());
    };
    if !e.is_finite() {
        // Finite coordinates whose differences overflow (near 1e308).
        return Err(CoreError::Degenerate(
            "coordinates too large: their span overflows (values near 1e308); heartmesh works \
             in millimetres"
                .into(),
        ));
    }
    if e <= 0.0 || (MIN_EXTENT_MM..=MAX_EXTENT_MM).contains(&e) {
        return Ok(());
    }
    let hint = unit_question(e).unwrap_or_default();
    let fix = if e < MIN_EXTENT_MM {
        "heartmesh works in millimetres: scale the coordinates by 1000 if they are metres"
    } else {
        "heartmesh works in millimetres: convert pixels with the pixel spacing, micrometres by 0.001"
    };
    Err(CoreError::Degenerate(format!("{hint}; {fix}")))
}

/// Contours that are not curves: a single point, or all points the same. (Two points are a
/// straight segment: real files draw a short RV septum that way, and it is used as one.)
pub fn few_point_warnings(set: &ContourSet) -> Vec<String> {
    let mut flagged: Vec<String> = Vec::new();
    for c in &set.contours {
        let n = c.point_count();
        let what = if n < 2 {
            "only 1 point".to_string()
        } else if extent(c.points()) == Some(0.0) {
            format!("{n} copies of one point")
        } else {
            continue;
        };
        flagged.push(named(c, &what));
    }
    one_line(
        flagged,
        "is not a curve; its points are used as single data points",
        "are not curves; their points are used as single data points",
    )
}

/// Contours grouped by surface label (None is a group of its own).
pub fn surface_groups(set: &ContourSet) -> Vec<Vec<&Contour>> {
    super::surface_indices(&set.contours)
        .into_iter()
        .map(|g| g.into_iter().map(|i| &set.contours[i]).collect())
        .collect()
}

/// Contours whose later pieces (the identifier reappearing after other contours) lie in another
/// plane than the first piece: two slices given the same name. Readers join such pieces into one
/// contour because real files split one curve into pieces, always within one plane.
pub fn reused_id_warnings(set: &ContourSet) -> Vec<String> {
    let mut flagged: Vec<String> = Vec::new();
    for c in set.contours.iter().filter(|c| c.pieces.len() > 1) {
        let Some(plane) = c.pieces.iter().find_map(|p| fit_plane(p.points.iter())) else {
            continue;
        };
        let tol = REUSED_ID_GAP_MM + 3.0 * plane.rms_residual;
        let worst = c
            .pieces
            .iter()
            .filter(|p| !p.points.is_empty())
            .map(|p| {
                let centroid =
                    p.points.iter().fold(Vec3::zeros(), |a, q| a + q) / p.points.len() as f64;
                (centroid - plane.centroid).dot(&plane.normal).abs()
            })
            .fold(0.0, f64::max);
        if worst > tol {
            flagged.push(named(c, &format!("pieces {worst:.1} mm apart")));
        }
    }
    one_line(
        flagged,
        "is named again later in the file in another plane; two slices with one name? They are \
         read as one contour",
        "are named again later in the file in other planes; slices with one name? Each is read \
         as one contour",
    )
}

/// A curve drawn on one image lies in that image's plane (to the exporter's rounding); one whose
/// points stray further than this (mm) from their best-fit plane is not one slice's curve: half
/// the thinnest slice spacing of a cardiac MR stack (5 mm), so points of two slices under one name
/// always exceed it.
pub(crate) const NON_PLANAR_MM: f64 = 2.5;

/// Contour pieces whose points do not lie in one plane (points of several slices read as one
/// curve: columns shifted, an export that lost its slice breaks). The tube and the short-/long-axis
/// split take every contour for a planar section, so such a contour can pull the surface through
/// itself or stop the run; the warning names it before that happens.
pub fn non_planar_warnings(set: &ContourSet) -> Vec<String> {
    let mut flagged: Vec<String> = Vec::new();
    let all: Vec<&Contour> = set.contours.iter().collect();
    let (far, off) = super::off_plane::left_out_with_far(&all);
    for ((c, far), off) in set.contours.iter().zip(far).zip(off) {
        // Without its spikes, far and off-plane pieces, which `spike_warnings`,
        // `far_piece_warnings` and `off_plane_warnings` name (a point thrown out of the plane is
        // a damaged value, not a second slice).
        let far: std::collections::HashSet<[u64; 3]> = far
            .iter()
            .flat_map(|f| f.points.iter().map(bits))
            .chain(off.iter().flat_map(|f| f.points.iter().map(bits)))
            .collect();
        let kept = |p: &&Vec3| far.is_empty() || !far.contains(&bits(p));
        let worst = c
            .pieces
            .iter()
            .filter_map(|p| fit_plane(super::clean::despike(p).0.iter().filter(kept)))
            .map(|f| f.max_residual)
            .fold(0.0, f64::max);
        if worst > NON_PLANAR_MM {
            flagged.push(named(
                c,
                &format!("points up to {worst:.1} mm from its plane"),
            ));
        }
    }
    one_line(
        flagged,
        "does not lie in one plane; points of several slices under one name? A contour is a \
         section in one image plane",
        "do not lie in one plane; points of several slices under one name? A contour is a \
         section in one image plane",
    )
}

/// Contours with a point (or two) far outside any heart, apart from the rest of the curve
/// ([`super::clean::stray_pieces`]): left out of the fit, named so the damaged value is found.
pub fn stray_point_warnings(set: &ContourSet) -> Vec<String> {
    let mut flagged: Vec<String> = Vec::new();
    for c in &set.contours {
        let pieces: Vec<_> = c
            .pieces
            .iter()
            .flat_map(super::clean::clean_and_split)
            .collect();
        let strays = super::clean::stray_pieces(&pieces);
        if let Some(far) = strays.iter().map(|s| s.1).reduce(f64::max) {
            let n: usize = strays.iter().map(|(k, _)| pieces[*k].points.len()).sum();
            let points = if n == 1 { "point" } else { "points" };
            flagged.push(named(
                c,
                &format!("{n} {points} {far:.0} mm from the rest of the curve"),
            ));
        }
    }
    one_line(
        flagged,
        "is fitted without them: no heart reaches that far (a damaged file?)",
        "are fitted without them: no heart reaches that far (a damaged file?)",
    )
}

/// Contours with a small piece cut off by a jump and lying apart from the rest of its surface
/// ([`super::far_pieces`]): left out of the fit, named so the damaged value is found.
pub fn far_piece_warnings(set: &ContourSet) -> Vec<String> {
    let mut flagged: Vec<String> = Vec::new();
    let all: Vec<&Contour> = set.contours.iter().collect();
    for (c, far) in set.contours.iter().zip(left_out(&all)) {
        let Some(f) = contour_far(c, &far) else {
            continue;
        };
        let (n, gap, span) = (f.points, f.gap_mm, f.span_mm);
        let points = if n == 1 { "point" } else { "points" };
        flagged.push(named(
            c,
            &format!(
                "{n} {points} {gap:.1} mm from every other point of its surface, which spans \
                 {span:.0} mm"
            ),
        ));
    }
    one_line(
        flagged,
        "is fitted without that piece: a surface's curves lie closer together (a damaged value?)",
        "are fitted without those pieces: a surface's curves lie closer together (damaged values?)",
    )
}

/// Contours with a small piece cut off by a jump and lying off the plane of the rest of the
/// contour ([`super::off_plane`]): left out of the fit, named so the damaged value is found.
pub fn off_plane_warnings(set: &ContourSet) -> Vec<String> {
    let all: Vec<&Contour> = set.contours.iter().collect();
    let flagged: Vec<String> = set
        .contours
        .iter()
        .zip(super::off_plane::left_out(&all))
        .filter_map(|(c, found)| {
            let f = super::off_plane::contour_off_plane(c, &found)?;
            let points = if f.points == 1 { "point" } else { "points" };
            Some(named(
                c,
                &format!(
                    "{} {points} up to {:.1} mm off the plane of the rest of the curve",
                    f.points, f.off_mm
                ),
            ))
        })
        .collect();
    one_line(
        flagged,
        "is fitted without that piece: a contour lies in its image's plane (a damaged value?)",
        "are fitted without those pieces: a contour lies in its image's plane (damaged values?)",
    )
}

/// Contours with a point (or a few) thrown out of the curve and straight back
/// ([`super::clean::contour_spikes`]): left out of the fit, named so the damaged value is found.
pub fn spike_warnings(set: &ContourSet) -> Vec<String> {
    let mut flagged: Vec<String> = Vec::new();
    for c in &set.contours {
        if let Some(s) = super::clean::contour_spikes(c) {
            let points = if s.points == 1 { "point" } else { "points" };
            flagged.push(named(
                c,
                &format!(
                    "{} {points} up to {:.1} mm out of the curve and straight back",
                    s.points, s.reach_mm
                ),
            ));
        }
    }
    one_line(
        flagged,
        "is fitted without the spike: a curve does not turn back like that (a damaged value?)",
        "are fitted without their spikes: a curve does not turn back like that (damaged values?)",
    )
}

/// A point's exact coordinates as a key (the far pieces' points are copies of the file's).
fn bits(p: &Vec3) -> [u64; 3] {
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
}

/// A contour as the warnings name it: its identifier, its first line in the file and what is
/// wrong with it (`"sax3" (line 62, only 1 point)`).
fn named(c: &Contour, detail: &str) -> String {
    c.cite(detail)
}

/// One warning line for all flagged contours (a user reads one line, not fifty).
pub(super) fn one_line(flagged: Vec<String>, one: &str, many: &str) -> Vec<String> {
    match flagged.as_slice() {
        [] => Vec::new(),
        [single] => vec![format!("contour {single} {one}")],
        more => {
            let shown: Vec<&str> = more.iter().take(3).map(String::as_str).collect();
            let rest = if more.len() > 3 { "; ..." } else { "" };
            vec![format!(
                "{} contours ({}{rest}) {many}",
                more.len(),
                shown.join("; ")
            )]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contours::Polyline;
    use crate::geometry::v3;

    fn ring(id: &str, centre: Vec3, r: f64) -> Contour {
        let points = (0..24)
            .map(|i| {
                let a = i as f64 / 24.0 * std::f64::consts::TAU;
                centre + v3(r * a.cos(), r * a.sin(), 0.0)
            })
            .collect();
        Contour {
            id: id.into(),
            surface: None,
            pieces: vec![Polyline {
                points,
                closed: true,
            }],
            first_line: 2,
        }
    }

    fn stack(scale: f64) -> ContourSet {
        ContourSet {
            contours: (0..5)
                .map(|k| {
                    ring(
                        &format!("s{k}"),
                        v3(0.0, 0.0, 10.0 * k as f64) * scale,
                        25.0 * scale,
                    )
                })
                .collect(),
            ..ContourSet::default()
        }
    }

    #[test]
    fn units_warn_and_refuse_by_span() {
        // Span 50 mm: nothing; 5 (cm?): warning only; 0.05 (m): warning and refusal; 5e4: both.
        for (scale, warns, refused) in [
            (1.0, false, false),
            (0.1, true, false),
            (0.001, true, true),
            (1000.0, true, true),
        ] {
            let set = stack(scale);
            assert_eq!(unit_warning(&set).is_some(), warns, "scale {scale}");
            let r = check_units(&set.contours);
            assert_eq!(r.is_err(), refused, "scale {scale}");
            if let Err(e) = r {
                assert_eq!(e.code(), "degenerate");
                assert!(e.to_string().contains("millimetres"), "{e}");
            }
        }
        let mut huge = stack(1.0);
        huge.contours[0].pieces[0].points[0] = v3(1e308, 1e308, 0.0);
        huge.contours[0].pieces[0].points[1] = v3(-1e308, -1e308, 0.0);
        let e = check_units(&huge.contours).err().map(|e| e.to_string());
        assert!(e.is_some_and(|e| e.contains("overflows")));
        let mut lone = ContourSet::default();
        let mut one = ring("one", v3(0.0, 0.0, 0.0), 25.0);
        one.pieces[0].points.truncate(2);
        lone.contours.push(one);
        assert_eq!(
            unit_warning(&lone),
            None,
            "two points say nothing about units"
        );
        assert!(unit_warning(&stack(0.001))
            .is_some_and(|w| w.contains("span 0.0500") && w.contains("metres?")));
    }

    #[test]
    fn few_points_and_identical_points_are_flagged_once() {
        let mut set = stack(1.0);
        assert!(few_point_warnings(&set).is_empty());
        let mut one = ring("one", v3(0.0, 0.0, 0.0), 25.0);
        one.pieces[0].points.truncate(1);
        let mut same = ring("same", v3(0.0, 0.0, 0.0), 25.0);
        same.pieces[0].points = vec![v3(1.0, 2.0, 3.0); 30];
        set.contours.push(one);
        assert_eq!(
            few_point_warnings(&set),
            vec![
                "contour \"one\" (line 2, only 1 point) is not a curve; its points are used as \
                  single data points"
            ]
        );
        set.contours.push(same);
        let w = few_point_warnings(&set);
        assert_eq!(w.len(), 1);
        assert!(w[0].starts_with("2 contours") && w[0].contains("30 copies of one point"));
    }

    #[test]
    fn pieces_in_other_planes_are_flagged_and_pieces_in_one_plane_are_not() {
        let mut set = stack(1.0);
        // The same plane: a curve split in two (biv-me RV free wall + septum style).
        let mut split = ring("split", v3(0.0, 0.0, 0.0), 25.0);
        let tail = split.pieces[0].points.split_off(12);
        split.pieces[0].closed = false;
        split.pieces.push(Polyline {
            points: tail,
            closed: false,
        });
        set.contours.push(split);
        assert!(reused_id_warnings(&set).is_empty());
        // A second ring named "s0" 30 mm above the first.
        let again = ring("s0", v3(0.0, 0.0, 30.0), 25.0);
        set.contours[0].pieces.push(again.pieces[0].clone());
        let w = reused_id_warnings(&set);
        assert_eq!(w.len(), 1);
        assert!(
            w[0].starts_with("contour \"s0\" (line 2, pieces 30.0 mm apart) is named again"),
            "{w:?}"
        );
    }

    #[test]
    fn spikes_are_named_with_their_count_and_reach() {
        let mut set = stack(1.0);
        assert!(spike_warnings(&set).is_empty());
        set.contours[1].pieces[0].points[5].x = 95.0;
        let w = spike_warnings(&set);
        assert_eq!(w.len(), 1);
        assert!(
            w[0].starts_with("contour \"s1\" (line 2, 1 point up to 8")
                && w[0]
                    .contains("mm out of the curve and straight back) is fitted without the spike"),
            "{w:?}"
        );
        set.contours[3].pieces[0].points[7].y = -60.0;
        set.contours[3].pieces[0].points[8].y = -61.0;
        let w = spike_warnings(&set);
        assert_eq!(w.len(), 1);
        assert!(
            w[0].starts_with("2 contours") && w[0].contains("\"s3\" (line 2, 2 points up to"),
            "{w:?}"
        );
        // Left out of the fit, the spike leaves nothing for the stray check to name, nor, thrown
        // out of its ring's plane, for the plane check.
        assert!(stray_point_warnings(&set).is_empty());
        set.contours[2].pieces[0].points[3].z += 40.0;
        assert!(spike_warnings(&set)[0].starts_with("3 contours"));
        assert!(non_planar_warnings(&set).is_empty());
        set.contours[2].pieces[0].points[3].z -= 30.0;
        set.contours[2].pieces[0].points[4].z += 10.0;
        set.contours[2].pieces[0].points[5].z += 10.0;
        set.contours[2].pieces[0].points[6].z += 10.0;
        assert!(spike_warnings(&set)[0].starts_with("2 contours"));
        assert_eq!(
            non_planar_warnings(&set).len(),
            1,
            "a bent ring is still named"
        );
    }

    #[test]
    fn a_piece_far_from_its_surface_is_named_with_its_gap_and_the_span() {
        // An open curve up the side of the stack (2 mm steps), then a damaged last row 60 mm
        // past its end: the rest spans 50 mm, so anything over 25 mm from all of it is far.
        let mut set = stack(1.0);
        let mut points: Vec<Vec3> = (0..=20).map(|j| v3(-25.0, 0.0, 2.0 * j as f64)).collect();
        set.contours.push(Contour {
            id: "lax".into(),
            surface: None,
            pieces: vec![Polyline {
                points: points.clone(),
                closed: false,
            }],
            first_line: 30,
        });
        assert!(far_piece_warnings(&set).is_empty());
        points.push(v3(-25.0, 0.0, 100.0));
        set.contours[5].pieces[0].points = points;
        let w = far_piece_warnings(&set);
        assert_eq!(
            w,
            [
                "contour \"lax\" (line 30, 1 point 60.0 mm from every other point of its surface, \
              which spans 50 mm) is fitted without that piece: a surface's curves lie closer \
              together (a damaged value?)"
            ],
        );
        // Under 100 mm from its curve, it is no stray of the curve alone.
        assert!(stray_point_warnings(&set).is_empty());
        // Within half the span of the rest (20 mm past the curve's end), it stays unnamed.
        set.contours[5].pieces[0].points[21].z = 60.0;
        assert!(far_piece_warnings(&set).is_empty());
    }

    #[test]
    fn huge_spans_print_in_scientific_notation() {
        assert_eq!(span_text(0.05), "0.0500");
        assert_eq!(span_text(12.34), "12.3");
        assert_eq!(span_text(2500.4), "2500");
        assert_eq!(span_text(114_356_900.0), "1.14e8");
        let line = unit_question(3.2e300).unwrap_or_default();
        assert!(
            line.starts_with("coordinates span 3.20e300; expected mm"),
            "{line}"
        );
        assert!(line.len() < 120, "{line}");
    }
}
