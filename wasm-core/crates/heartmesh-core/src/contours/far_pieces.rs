//! Far pieces: a point or a few of a curve, cut off from it by a jump, lying apart from
//! everything else of their surface (a damaged value at an open curve's end).
//!
//! A damaged value inside a curve comes straight back and is a spike ([`super::clean::spikes`]);
//! at an open curve's first or last row it cannot come back, so it only splits the curve, and
//! the per-contour stray rule ([`super::clean::stray_pieces`]) takes it only beyond 100 mm (and
//! twice the curve's extent), since real long-axis curves keep lone end points ~26 mm from the
//! rest of the curve. Under that it stayed data and grew a finger with no warning: one row put
//! 60 mm past the end of biv-me patient 1 ED's long-axis LV endocardium s07 took the mesh from
//! 173.7 to 206.0 ml and 16,775 to 20,573 mm2.
//!
//! Judged against the whole surface rather than the curve alone, such a piece is told apart the
//! way the stray rule for whole contours tells a stray group ([`super::strays`]): further than
//! [`SPAN_SHARE`] of the span of the rest of its surface from every point of it. A surface's
//! curves cover it within a slice gap or two; the real lone pieces lie at most 26 mm from their
//! curve and 30 mm from every other curve of their surface, which spans ~100 mm (biv-me patients
//! 1 and 2, ED and ES, every surface), and stay.

use super::clean::cleaned_contours;
use super::strays::SPAN_SHARE;
use super::{remove_pieces, surface_indices, Contour, Polyline};
use crate::geometry::Vec3;
use crate::spatial::SegmentTree;
use serde::Serialize;

/// A piece of a contour left out as far from its surface.
#[derive(Debug, Clone, PartialEq)]
pub struct FarPiece {
    /// Index of the contour in the list judged.
    pub contour: usize,
    /// Index of the piece in that contour.
    pub piece: usize,
    /// Its points.
    pub points: usize,
    /// Distance from its nearest point to the nearest point of the rest of the surface (mm).
    pub gap_mm: f64,
    /// Largest side of the box of the rest of the surface (mm).
    pub span_mm: f64,
}

/// Which of a contour's `pieces` are judged as far pieces: every piece but its biggest (all of
/// the biggest size, when several share it). Unlike a plane fit of the rest of the curve
/// ([`super::off_plane`]), the surface does not need the contour to keep most of its points to
/// tell: three damaged rows of a nine-point septum thrown 82 mm stayed as data as a third of
/// their curve, and took biv-me patient 1 ES's RV from 71.6 to 83.9 ml.
fn lesser_pieces(pieces: &[Polyline]) -> Vec<bool> {
    let most = pieces.iter().map(|p| p.points.len()).max().unwrap_or(0);
    pieces.iter().map(|p| p.points.len() < most).collect()
}

/// Most points of a contour whose spacing cannot tell a jump: two points have one segment, its
/// own median, and of three the median of two is the longer. Nothing splits a damaged row off
/// such a contour (a two-point septum at the apex, one of its values times ten, 185 mm out, took
/// biv-me patient 1 ES's RV from 71.6 to 78.3 ml), so [`far_pieces`] judges its points one by one.
const TINY_POINTS: usize = 3;

fn is_tiny(c: &Contour) -> bool {
    c.point_count() <= TINY_POINTS
}

/// `c` with each of its points a piece of its own: a tiny contour as [`far_pieces_by_surface`]
/// judges it.
fn one_piece_per_point(c: &Contour) -> Contour {
    Contour {
        pieces: c
            .points()
            .map(|p| Polyline {
                points: vec![*p],
                closed: false,
            })
            .collect(),
        ..c.clone()
    }
}

/// The far pieces of one surface's cleaned `contours`: the [`lesser_pieces`] further than
/// [`SPAN_SHARE`] of the span of the rest (every contour's biggest pieces) from all of it, and
/// the pieces of a tiny contour ([`TINY_POINTS`], no part of the rest) so far, as long as one is
/// not. Nothing is judged against fewer than two contours' worth of rest.
pub fn far_pieces(contours: &[Contour]) -> Vec<FarPiece> {
    let flags: Vec<Vec<bool>> = contours
        .iter()
        .map(|c| match is_tiny(c) {
            true => vec![true; c.pieces.len()],
            false => lesser_pieces(&c.pieces),
        })
        .collect();
    let mut rest: Vec<Vec3> = Vec::new();
    let mut rest_contours = 0;
    for (c, flags) in contours.iter().zip(&flags) {
        let before = rest.len();
        for (p, _) in c.pieces.iter().zip(flags).filter(|(_, f)| !**f) {
            rest.extend(p.points.iter().copied());
        }
        rest_contours += usize::from(rest.len() > before);
    }
    if rest_contours < 2 || rest.len() < 3 {
        return Vec::new();
    }
    let (lo, hi) = rest
        .iter()
        .fold((rest[0], rest[0]), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
    let span_mm = (hi - lo).amax();
    let limit = SPAN_SHARE * span_mm;
    if limit <= 0.0 {
        return Vec::new();
    }
    let tree = SegmentTree::new(rest.into_iter().map(|p| (p, p)).collect());
    let mut out = Vec::new();
    for (i, (c, flags)) in contours.iter().zip(&flags).enumerate() {
        let mut found: Vec<FarPiece> = Vec::new();
        for (k, (p, _)) in c
            .pieces
            .iter()
            .zip(flags)
            .enumerate()
            .filter(|(_, (_, f))| **f)
        {
            let gap_mm = p
                .points
                .iter()
                .map(|q| tree.distance(q))
                .fold(f64::INFINITY, f64::min);
            if gap_mm > limit {
                found.push(FarPiece {
                    contour: i,
                    piece: k,
                    points: p.points.len(),
                    gap_mm,
                    span_mm,
                });
            }
        }
        // A tiny contour far all of it is a stray, the whole-contour rules' business.
        if found.len() < c.pieces.len() {
            out.extend(found);
        }
    }
    out
}

/// The far pieces of cleaned `contours` of any surfaces, each surface judged on its own, with
/// contour indices into `contours`.
pub fn far_pieces_by_surface(contours: &[Contour]) -> Vec<FarPiece> {
    let mut out = Vec::new();
    for group in surface_indices(contours) {
        let members: Vec<Contour> = group
            .iter()
            .map(|&i| match is_tiny(&contours[i]) {
                true => one_piece_per_point(&contours[i]),
                false => contours[i].clone(),
            })
            .collect();
        out.extend(far_pieces(&members).into_iter().map(|mut f| {
            f.contour = group[f.contour];
            f
        }));
    }
    out.sort_by_key(|f| (f.contour, f.piece));
    out
}

/// Leaves the far pieces out of cleaned `contours` (each surface judged on its own) and returns
/// them, per contour. A contour keeps its bigger pieces (a tiny one some of its points), so none
/// is emptied and indices stay as they were.
pub fn take_far_pieces(contours: &mut [Contour]) -> Vec<Vec<LeftOut>> {
    let mut taken = vec![Vec::new(); contours.len()];
    let mut out: Vec<Vec<usize>> = vec![Vec::new(); contours.len()];
    for f in far_pieces_by_surface(contours) {
        let Some(c) = contours.get(f.contour) else {
            continue;
        };
        // A tiny contour's pieces were judged one point each.
        let points: Option<Vec<Vec3>> = match is_tiny(c) {
            true => c.points().nth(f.piece).map(|p| vec![*p]),
            false => c.pieces.get(f.piece).map(|p| p.points.clone()),
        };
        if let Some(points) = points {
            taken[f.contour].push(LeftOut {
                points,
                gap_mm: f.gap_mm,
                span_mm: f.span_mm,
            });
            out[f.contour].push(f.piece);
        }
    }
    for (c, out) in contours.iter_mut().zip(out) {
        if out.is_empty() {
            continue;
        }
        if is_tiny(c) {
            let mut j = 0;
            for p in &mut c.pieces {
                p.points.retain(|_| {
                    j += 1;
                    !out.contains(&(j - 1))
                });
            }
            c.pieces.retain(|p| !p.points.is_empty());
        } else {
            remove_pieces(&mut c.pieces, out);
        }
    }
    taken
}

/// A far piece as the warnings and the per-contour summaries see it: its points (as cleaned),
/// its gap and its surface's span (mm).
#[derive(Debug, Clone, PartialEq)]
pub struct LeftOut {
    pub points: Vec<Vec3>,
    pub gap_mm: f64,
    pub span_mm: f64,
}

/// The far pieces a run leaves out of each of `contours` (as given, any surfaces; cleaned as a
/// run cleans them), indexed like `contours`.
pub fn left_out(contours: &[&Contour]) -> Vec<Vec<LeftOut>> {
    let (index, mut cleaned) = cleaned_contours(contours);
    let mut out = vec![Vec::new(); contours.len()];
    for (i, taken) in index.into_iter().zip(take_far_pieces(&mut cleaned)) {
        out[i] = taken;
    }
    out
}

/// What a run leaves out of one contour as far pieces: how many points, the nearest's gap to
/// the rest of the surface and that surface's span (mm). The warning line, the report's
/// `per_contour` and the app's Contours panel say it from this.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContourFar {
    /// The contour's id (not serialised: the row the summary sits in names it).
    #[serde(skip_serializing)]
    pub id: String,
    pub points: usize,
    pub gap_mm: f64,
    pub span_mm: f64,
}

/// The summary of contour `c`'s far pieces `found` ([`left_out`]); None without any.
pub fn contour_far(c: &Contour, found: &[LeftOut]) -> Option<ContourFar> {
    let gap_mm = found.iter().map(|f| f.gap_mm).reduce(f64::min)?;
    Some(ContourFar {
        id: c.id.clone(),
        points: found.iter().map(|f| f.points.len()).sum(),
        gap_mm,
        span_mm: found[0].span_mm,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contours::specks::fixtures::{contour, ring};

    /// Three rings of radius 20 mm 10 mm apart and a long-axis curve through them (x = 0 plane)
    /// from the apex up past the base.
    fn heart() -> Vec<Contour> {
        let mut c: Vec<Contour> = (0..3)
            .map(|k| {
                ring(
                    &format!("sax{k}"),
                    20.0,
                    10.0 * k as f64,
                    0.0,
                    40,
                    10 + 40 * k,
                )
            })
            .collect();
        let lax: Vec<Vec3> = (0..=60)
            .map(|j| {
                let t = std::f64::consts::PI * j as f64 / 60.0;
                Vec3::new(0.0, 20.0 * t.cos(), 20.0 - 40.0 * t.sin().max(0.0) + 5.0)
            })
            .collect();
        c.push(contour("lax", lax, false, 200));
        c
    }

    fn with_end_row(mut c: Vec<Contour>, at: Vec3) -> Vec<Contour> {
        if let Some(last) = c.last_mut() {
            last.pieces[0].points.push(at);
        }
        c.iter()
            .filter_map(crate::contours::clean::cleaned_contour)
            .collect()
    }

    #[test]
    fn a_damaged_last_row_far_from_the_surface_is_left_out_and_a_near_one_stays() {
        // The curve ends at (0, -20, 25); the surface spans 40 mm (rings and curve 40 mm across
        // and along the axis), so the limit is 20 mm from everything.
        let far = with_end_row(heart(), Vec3::new(0.0, -20.0, 85.0));
        let found = far_pieces(&far);
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!((found[0].contour, found[0].points), (3, 1));
        assert!((found[0].gap_mm - 60.0).abs() < 0.5, "{found:?}");
        assert!((found[0].span_mm - 40.0).abs() < 0.5, "{found:?}");
        let mut dropped = far.clone();
        take_far_pieces(&mut dropped);
        assert_eq!(dropped[3].point_count(), 61);
        // 15 mm past the curve's end, 20 mm above the top ring: a lone end point as real files
        // have them (a valve point), kept.
        let near = with_end_row(heart(), Vec3::new(0.0, -20.0, 40.0));
        assert_eq!(near[3].pieces.len(), 2, "the row is split off as a piece");
        assert!(far_pieces(&near).is_empty());
    }

    #[test]
    fn a_third_of_a_short_curve_thrown_far_is_left_out() {
        // A nine-point curve (a septum arc beside the top ring, 2.5 mm steps) whose first three
        // rows are thrown 80 mm above the heart: a third of their curve, more than the quarter a
        // plane fit of the rest needs, but 60 mm from all of a surface spanning 40.
        let mut c = heart();
        let mut arc: Vec<Vec3> = (0..9)
            .map(|j| Vec3::new(-10.0 + 2.5 * j as f64, 15.0, 22.0))
            .collect();
        for p in &mut arc[..3] {
            p.z += 80.0;
        }
        c.push(contour("septum", arc, false, 300));
        let cleaned: Vec<Contour> = c
            .iter()
            .filter_map(crate::contours::clean::cleaned_contour)
            .collect();
        assert_eq!(cleaned[4].pieces.len(), 2);
        let found = far_pieces(&cleaned);
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!((found[0].contour, found[0].points), (4, 3));
        assert!(found[0].gap_mm > 55.0, "{found:?}");
    }

    #[test]
    fn a_far_point_of_a_tiny_contour_is_left_out_and_a_tiny_stray_is_not() {
        // A two-point curve beside the top ring, its second row 80 mm above the heart: one
        // segment, its own median, so no jump splits it; judged point by point.
        let mut c = heart();
        let pair = vec![Vec3::new(0.0, 15.0, 20.0), Vec3::new(2.0, 15.0, 100.0)];
        c.push(contour("septum", pair, false, 300));
        let cleaned: Vec<Contour> = c
            .iter()
            .filter_map(crate::contours::clean::cleaned_contour)
            .collect();
        assert_eq!(cleaned[4].pieces.len(), 1);
        let mut taken = cleaned.clone();
        let left = take_far_pieces(&mut taken);
        assert_eq!(left[4].len(), 1, "{left:?}");
        assert_eq!(left[4][0].points, vec![Vec3::new(2.0, 15.0, 100.0)]);
        assert!(left[4][0].gap_mm > 70.0, "{left:?}");
        assert_eq!(taken[4].point_count(), 1);
        assert_eq!(taken[4].pieces[0].points[0], Vec3::new(0.0, 15.0, 20.0));
        assert!(left.iter().take(4).all(Vec::is_empty));
        // Both points far: the whole contour is a stray, left to the whole-contour rules.
        let mut c = heart();
        let pair = vec![Vec3::new(0.0, 15.0, 100.0), Vec3::new(2.0, 15.0, 101.0)];
        c.push(contour("stray", pair, false, 300));
        let mut cleaned: Vec<Contour> = c
            .iter()
            .filter_map(crate::contours::clean::cleaned_contour)
            .collect();
        assert!(take_far_pieces(&mut cleaned).iter().all(Vec::is_empty));
        assert_eq!(cleaned[4].point_count(), 2);
    }

    #[test]
    fn big_pieces_lone_contours_and_other_surfaces_are_not_judged() {
        // A second half of a curve far away is not small: both halves stay.
        let mut c = heart();
        let mut half: Vec<Vec3> = c[3].pieces[0].points[..30].to_vec();
        half.extend((0..30).map(|j| Vec3::new(0.0, 200.0 + j as f64, 0.0)));
        c[3].pieces[0].points = half;
        let c: Vec<Contour> = c
            .iter()
            .filter_map(crate::contours::clean::cleaned_contour)
            .collect();
        assert_eq!(c[3].pieces.len(), 2);
        assert!(far_pieces(&c).is_empty());
        // A lone point contour far out is a whole contour (the strays' business), not a piece.
        let mut c = heart();
        c.push(contour(
            "landmark",
            vec![Vec3::new(0.0, 0.0, 300.0)],
            false,
            400,
        ));
        assert!(far_pieces(&c).is_empty());
        // Each surface is judged on its own: the same far row in a surface of its own curve and
        // one ring is judged against that ring.
        let mut c = with_end_row(heart(), Vec3::new(0.0, -20.0, 85.0));
        for (k, x) in c.iter_mut().enumerate() {
            x.surface = Some(if k == 0 || k == 3 { "A" } else { "B" }.into());
        }
        let found = far_pieces_by_surface(&c);
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].contour, 3);
        assert!((found[0].span_mm - 40.0).abs() < 0.5, "{found:?}");
    }
}
