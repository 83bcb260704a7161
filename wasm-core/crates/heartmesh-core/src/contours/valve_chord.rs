//! Long-axis curves closed across the valve: the straight run across the top of a closed long-axis
//! curve is the valve plane's trace, not wall, so the mesh is fitted to the curve opened there.
//!
//! Segment closes every long-axis curve by a line across the valve, and a curve traced round a
//! label map's long-axis section does the same along the mask's top edge. As wall data such a chord
//! says nothing its two ends do not (it is the straight line between them), but it pulls the mesh
//! at full weight across the whole valve: where views disagree in height (every real acquisition,
//! one breath-hold per view) the chords of two or three views cross near the valve's centre at
//! different heights and the top folds between them. Measured (docs/VALIDATION.md, "Session 45"):
//! simulated LV truths with 3-5 mm breath-hold shifts per view, 20 folded edges and one 11 mm
//! Hausdorff with the chords fitted against 5 and at most 5.8 mm opened; the Segment fixture's LV
//! endocardium at end-diastole 4 folded edges against 0. Opened, the curve's two ends are
//! long-axis tips like those of any open curve: the lid goes through them (`pipeline::lid_tips`),
//! one-sided, as the method closes every file whose curves stop at the valve. Which surfaces and
//! files keep their chords anyway is the pipeline's call (`pipeline::fitted_contours`).
//!
//! Only the mesh's fit sees the opened curve: distances, colour maps and per-contour tables are
//! measured to the curve as drawn, chord included.

use super::clean::{length, median_spacing};
use super::{Contour, ContourKind, Polyline};
use crate::geometry::Vec3;

/// Points more than this many times the curve's own median spacing (or [`MIN_TOLERANCE_MM`]) off
/// the line through a run's two ends break its straightness: a traced mask's staircase stays
/// within about half a pixel of its line, a drawn wall bends well past this over a valve's width.
const TOLERANCE_PER_SPACING: f64 = 0.75;
const MIN_TOLERANCE_MM: f64 = 0.5;
/// ... and never more than this: a sparsely sampled curve's gentle dome is not a line.
const MAX_TOLERANCE_MM: f64 = 1.5;
/// A chord runs across the axis: at least this angle (degrees) from it. The valve plane tilts
/// against the short-axis planes by 10-30 degrees; the walls beside the valve run along the axis.
const MIN_ANGLE_TO_AXIS_DEG: f64 = 45.0;
/// A chord spans most of the cavity: at least this share of the curve's extent across the axis.
/// (A valve's width is 60-100 % of the cavity's at the base; a straight stretch of wall at the
/// top of a curve open at the valve turns inwards by a small part of it.)
const MIN_SPAN_PER_WIDTH: f64 = 0.35;
/// The search looks at the curve resampled to about this spacing (mm) ...
const SEARCH_SPACING_MM: f64 = 1.0;
/// ... with at most this many points, so that its cost is bounded whatever the file's density.
const MAX_SEARCH_POINTS: usize = 2048;
/// A chord has at least this many search points (a run of two or three is straight by definition).
const MIN_CHORD_POINTS: usize = 4;
/// ... and at most this many (at least 256 mm: no valve is wider), which bounds the search.
const MAX_CHORD_POINTS: usize = 256;

/// The contours the mesh is fitted to: `contours` with each closed long-axis curve that crosses
/// its top in a straight run opened there. Also the ids of the curves opened.
pub fn open_valve_chords(
    contours: &[Contour],
    kinds: &[ContourKind],
    axis: &Vec3,
    basal_height: f64,
) -> (Vec<Contour>, Vec<String>) {
    let mut opened = Vec::new();
    let fitted = contours
        .iter()
        .zip(kinds)
        .map(|(c, kind)| {
            if *kind != ContourKind::Lax {
                return c.clone();
            }
            let mut out = c.clone();
            let mut any = false;
            for piece in &mut out.pieces {
                if let Some(open) = opened_piece(piece, axis, basal_height) {
                    *piece = open;
                    any = true;
                }
            }
            if any {
                opened.push(c.id.clone());
            }
            out
        })
        .collect();
    (fitted, opened)
}

/// A closed piece opened at its valve chord, or None when it has none.
fn opened_piece(piece: &Polyline, axis: &Vec3, basal_height: f64) -> Option<Polyline> {
    if !piece.closed || piece.points.len() < 2 * MIN_CHORD_POINTS {
        return None;
    }
    let total = length(&piece.points, true);
    if !(total.is_finite() && total > 0.0) {
        return None;
    }
    let spacing = SEARCH_SPACING_MM.max(total / MAX_SEARCH_POINTS as f64);
    let count = ((total / spacing).round() as usize).clamp(3, MAX_SEARCH_POINTS);
    let q = super::clean::resample_count(&piece.points, true, count);
    let step = total / count as f64;
    let tol = (TOLERANCE_PER_SPACING * median_spacing(&piece.points))
        .clamp(MIN_TOLERANCE_MM, MAX_TOLERANCE_MM);
    let (first, last) = chord(&q, axis, basal_height, tol)?;
    let points = open_between(
        &piece.points,
        first as f64 * step,
        last as f64 * step,
        total,
    );
    (points.len() >= 3).then_some(Polyline {
        points,
        closed: false,
    })
}

/// The longest straight run `first..=last` (indices into the closed curve `q`, `last` may pass
/// `q.len()`: taken modulo) that crosses the top of the curve as a valve chord does: across the
/// axis, spanning much of the curve's width, above the basal slice, and with no part of the curve
/// above it within its span (a wall may rise beside it, to the other valve of a three-chamber
/// view or past a tip the section cut lower).
fn chord(q: &[Vec3], axis: &Vec3, basal_height: f64, tol: f64) -> Option<(usize, usize)> {
    let m = q.len();
    let height = |i: usize| q[i % m].dot(axis);
    let top_height = (0..m).map(height).fold(f64::NEG_INFINITY, f64::max);
    if top_height <= basal_height {
        return None;
    }
    let width = extent_across(q, axis);
    let min_cos_axis = MIN_ANGLE_TO_AXIS_DEG.to_radians().cos();
    let reach = (m / 2).min(MAX_CHORD_POINTS);
    let mut best: Option<(usize, usize, f64)> = None;
    for first in 0..m {
        let mut last = first + 2;
        while last - first < reach && straight(q, first, last + 1, tol) {
            last += 1;
        }
        if last - first + 1 < MIN_CHORD_POINTS || !straight(q, first, last, tol) {
            continue;
        }
        let d = q[last % m] - q[first % m];
        let len = d.norm();
        if best.is_some_and(|(_, _, l)| len <= l) || len <= 0.0 {
            continue;
        }
        let across = d - axis * d.dot(axis);
        let is_chord = (d / len).dot(axis).abs() <= min_cos_axis
            && across.norm() >= MIN_SPAN_PER_WIDTH * width
            && (first..=last).any(|i| height(i) > basal_height)
            && nothing_above(q, first, last, axis, tol);
        if is_chord {
            best = Some((first, last, len));
        }
    }
    best.map(|(first, last, _)| (first, last))
}

/// Whether no point of the closed curve `q` outside the run `first..=last` lies above the run's
/// line (up the axis, by more than `tol`) within the middle of the run's span across the axis.
fn nothing_above(q: &[Vec3], first: usize, last: usize, axis: &Vec3, tol: f64) -> bool {
    let m = q.len();
    let a = q[first % m];
    let d = q[last % m] - a;
    let across = d - axis * d.dot(axis);
    let span = across.norm();
    if span <= 0.0 {
        return false;
    }
    let u = across / span;
    // The chord's height at a point's position across the axis: a + d t, t = (p - a).u / span.
    let margin = 0.1;
    (0..m)
        .filter(|i| {
            let k = (i + m - first % m) % m;
            k > last - first
        })
        .all(|i| {
            let p = q[i];
            let t = (p - a).dot(&u) / span;
            if !(margin..=1.0 - margin).contains(&t) {
                return true;
            }
            let line_height = (a + d * t).dot(axis);
            p.dot(axis) <= line_height + tol
        })
}

/// Whether every point strictly between `first` and `last` of the closed curve `q` lies within
/// `tol` of the line through those two.
fn straight(q: &[Vec3], first: usize, last: usize, tol: f64) -> bool {
    let m = q.len();
    let a = q[first % m];
    let d = q[last % m] - a;
    let len = d.norm();
    if len <= 0.0 {
        return false;
    }
    let u = d / len;
    ((first + 1)..last).all(|i| {
        let v = q[i % m] - a;
        (v - u * v.dot(&u)).norm() <= tol
    })
}

/// The curve's extent across the axis (the largest distance between two of its points once the
/// axis component is removed, along the direction of its widest pair found from the centroid).
fn extent_across(q: &[Vec3], axis: &Vec3) -> f64 {
    let flat: Vec<Vec3> = q.iter().map(|p| p - axis * p.dot(axis)).collect();
    let c = flat.iter().sum::<Vec3>() / flat.len().max(1) as f64;
    let Some(far) = flat
        .iter()
        .max_by(|a, b| (*a - c).norm().total_cmp(&(*b - c).norm()))
    else {
        return 0.0;
    };
    flat.iter().map(|p| (p - far).norm()).fold(0.0, f64::max)
}

/// The closed curve `points` (arc length `total`) without its part from arc length `from` to
/// `to` (`to` may pass `total`): an open curve from the point at `to` round to the point at `from`,
/// both interpolated on the curve, with every original point between.
fn open_between(points: &[Vec3], from: f64, to: f64, total: f64) -> Vec<Vec3> {
    let n = points.len();
    let mut cum = Vec::with_capacity(n + 1);
    cum.push(0.0);
    for i in 0..n {
        cum.push(cum[i] + (points[(i + 1) % n] - points[i]).norm());
    }
    let at = |s: f64| {
        let s = s.rem_euclid(total);
        let i = cum.partition_point(|&c| c <= s).clamp(1, n) - 1;
        let l = cum[i + 1] - cum[i];
        let t = if l > 0.0 { (s - cum[i]) / l } else { 0.0 };
        points[i] + (points[(i + 1) % n] - points[i]) * t.clamp(0.0, 1.0)
    };
    // Original points strictly inside the kept arc (from `to` round to `from + total`).
    let kept_from = to;
    let kept_to = from + total;
    let eps = 1e-9 * total.max(1.0);
    let mut out = vec![at(kept_from)];
    for lap in 0..2 {
        for (i, &c) in cum.iter().take(n).enumerate() {
            let s = c + lap as f64 * total;
            if s > kept_from + eps && s < kept_to - eps {
                out.push(points[i]);
            }
        }
    }
    out.push(at(kept_to));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    fn up() -> Vec3 {
        v3(0.0, 0.0, 1.0)
    }

    /// A U in the x-z plane: walls at x = +-r from z = 0 up to `top`, a half circle below; open
    /// at the top (from the left wall's top round the apex to the right wall's top).
    fn u_curve(r: f64, top: f64, spacing: f64) -> Vec<Vec3> {
        let mut pts = Vec::new();
        let wall = (top / spacing).round() as usize;
        for i in 0..wall {
            pts.push(v3(-r, 0.0, top - i as f64 * spacing));
        }
        let arc = (std::f64::consts::PI * r / spacing).round() as usize;
        for i in 0..arc {
            let a = std::f64::consts::PI * i as f64 / arc as f64;
            pts.push(v3(-r * a.cos(), 0.0, -r * a.sin()));
        }
        for i in 0..=wall {
            pts.push(v3(r, 0.0, i as f64 * spacing));
        }
        pts
    }

    /// The U closed by its chord, sampled at `spacing` across the top.
    fn closed_u(r: f64, top: f64, spacing: f64, tilt: f64) -> Vec<Vec3> {
        let mut pts = u_curve(r, top, spacing);
        // Tilt the valve: the right wall's top rises by `tilt` mm.
        if let Some(p) = pts.last_mut() {
            p.z += tilt;
        }
        let (a, b) = (pts[pts.len() - 1], pts[0]);
        let k = ((b - a).norm() / spacing).round() as usize;
        for i in 1..k {
            pts.push(a + (b - a) * (i as f64 / k as f64));
        }
        pts
    }

    fn lax(points: Vec<Vec3>, closed: bool) -> Contour {
        Contour {
            id: "lax1".into(),
            surface: None,
            pieces: vec![Polyline { points, closed }],
            first_line: 2,
        }
    }

    #[test]
    fn a_chord_across_the_top_is_opened_and_its_ends_kept() {
        for (tilt, spacing) in [(0.0, 1.0), (8.0, 0.5), (4.0, 2.0)] {
            let c = lax(closed_u(20.0, 15.0, spacing, tilt), true);
            let (fitted, opened) =
                open_valve_chords(std::slice::from_ref(&c), &[ContourKind::Lax], &up(), 5.0);
            assert_eq!(opened, vec!["lax1".to_string()], "tilt {tilt}");
            let p = &fitted[0].pieces[0];
            assert!(!p.closed);
            // No point left in the chord's interior: every point at least 2 mm below the chord
            // line or on the walls (|x| = r).
            let ends = [p.points[0], p.points[p.points.len() - 1]];
            for e in ends {
                assert!((e.x.abs() - 20.0).abs() < 1.5, "end {e:?} (tilt {tilt})");
                assert!(e.z > 12.0, "end {e:?} (tilt {tilt})");
            }
            let inside = p
                .points
                .iter()
                .filter(|q| q.x.abs() < 17.0 && q.z > 10.0)
                .count();
            assert_eq!(inside, 0, "tilt {tilt}");
            // The U kept: its length within 2 spacings of the open curve's.
            let u = u_curve(20.0, 15.0, spacing);
            let (lu, lp) = (length(&u, false), length(&p.points, false));
            assert!((lu - lp).abs() < 2.0 * spacing + tilt.abs(), "{lu} vs {lp}");
        }
    }

    #[test]
    fn open_curves_rings_and_rounded_tops_are_left_alone() {
        let u = lax(u_curve(20.0, 15.0, 1.0), false);
        // A closed ellipse in the long-axis plane (a curve over the top, no straight run).
        let ellipse: Vec<Vec3> = (0..160)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / 160.0;
                v3(20.0 * a.cos(), 0.0, 40.0 * a.sin())
            })
            .collect();
        let e = lax(ellipse, true);
        let (fitted, opened) = open_valve_chords(
            &[u.clone(), e.clone()],
            &[ContourKind::Lax, ContourKind::Lax],
            &up(),
            5.0,
        );
        assert!(opened.is_empty());
        assert_eq!(fitted, vec![u, e]);
        // A short-axis ring is never opened, whatever its shape.
        let c = lax(closed_u(20.0, 15.0, 1.0, 0.0), true);
        let (fitted, opened) =
            open_valve_chords(std::slice::from_ref(&c), &[ContourKind::Sax], &up(), 5.0);
        assert!(opened.is_empty());
        assert_eq!(fitted, vec![c]);
    }

    #[test]
    fn a_chord_below_the_basal_slice_or_under_the_curve_is_not_a_valve() {
        let c = lax(closed_u(20.0, 15.0, 1.0, 0.0), true);
        // The basal slice above the curve's top: the chord is not beyond the base.
        let (_, opened) =
            open_valve_chords(std::slice::from_ref(&c), &[ContourKind::Lax], &up(), 20.0);
        assert!(opened.is_empty());
        // Upside down (the axis reversed): the straight run is at the curve's bottom, with the
        // whole U above it.
        let down = v3(0.0, 0.0, -1.0);
        let (_, opened) = open_valve_chords(&[c], &[ContourKind::Lax], &down, -100.0);
        assert!(opened.is_empty(), "{opened:?}");
    }

    #[test]
    fn a_wall_rising_beside_the_chord_to_another_valve_does_not_hide_it() {
        // A three-chamber-like section: the right wall runs on 12 mm above the chord's end (the
        // outflow tract to the aortic valve) before the curve comes back down to it.
        let mut pts = u_curve(20.0, 15.0, 1.0);
        for i in 1..=12 {
            pts.push(v3(20.0, 0.0, 15.0 + i as f64));
        }
        for i in 1..=12 {
            pts.push(v3(20.0 - 0.5 * i as f64, 0.0, 27.0 - i as f64));
        }
        let (a, b) = (pts[pts.len() - 1], pts[0]);
        let k = (b - a).norm().round() as usize;
        for i in 1..k {
            pts.push(a + (b - a) * (i as f64 / k as f64));
        }
        let (fitted, opened) =
            open_valve_chords(&[lax(pts, true)], &[ContourKind::Lax], &up(), 5.0);
        assert_eq!(opened.len(), 1);
        let p = &fitted[0].pieces[0].points;
        let inside = p.iter().filter(|q| q.x.abs() < 10.0 && q.z > 14.0).count();
        assert_eq!(inside, 0);
    }

    #[test]
    fn a_staircase_chord_as_a_mask_traces_it_is_found() {
        // The chord tilted by 10 degrees and traced on a pixel grid: points 1.4 mm apart zigzagging
        // 0.4 mm either side of the line, as pixel edges' midpoints do.
        let mut pts = u_curve(20.0, 15.0, 1.4);
        let (a, b) = (pts[pts.len() - 1], pts[0]);
        let rise = (b.x - a.x) * 10f64.to_radians().tan();
        let steps = ((b.x - a.x).abs() / 1.4) as usize;
        for i in 1..steps {
            let x = a.x + (b.x - a.x) * i as f64 / steps as f64;
            let z = a.z + rise * i as f64 / steps as f64;
            pts.push(v3(x, 0.0, z + if i % 2 == 0 { 0.4 } else { -0.4 }));
        }
        let (_, opened) = open_valve_chords(&[lax(pts, true)], &[ContourKind::Lax], &up(), 5.0);
        assert_eq!(opened.len(), 1);
    }

    #[test]
    fn degenerate_pieces_do_not_panic() {
        let same = lax(vec![v3(1.0, 2.0, 3.0); 12], true);
        let line = lax((0..12).map(|i| v3(i as f64, 0.0, 10.0)).collect(), true);
        let huge = lax(
            (0..12)
                .map(|i| v3(1e300 * (i % 3) as f64, 1e300, -1e300 * (i % 2) as f64))
                .collect(),
            true,
        );
        let kinds = [ContourKind::Lax; 3];
        let (fitted, _) = open_valve_chords(&[same, line, huge], &kinds, &up(), 0.0);
        assert_eq!(fitted.len(), 3);
    }
}
