//! Off-plane pieces: a point or a few of a contour, cut off from it by a jump, lying off the image
//! plane the rest of the contour lies in (a damaged value at an open curve's end, or any damaged
//! value that does not come straight back).
//!
//! A contour is a section in one image: every point a reader digitised lies in the image's plane
//! (biv-me's and SurFCo's to the last stored decimal, lone points and pieces included). A
//! damaged coordinate throws a point in any direction, mostly out of that plane. Inside a curve
//! it comes straight back and is a spike ([`super::clean::spikes`]); far from the whole surface
//! it is a far piece ([`super::far_pieces`]); but a row 20-60 mm out at an open curve's end is
//! neither, and stayed data: on an RV free wall or septum, joined into the slice's ring only when
//! the tube is built, three rows of biv-me patient 1 ES's free wall s03 moved 32 mm took the RV
//! from 71.6 to 94.0 ml with no warning. Out of the plane of the rest of its curve by more than
//! a slice's curve may leave it ([`NON_PLANAR_MM`]), such a piece is no part of the section.

use super::checks::NON_PLANAR_MM;
use super::clean::cleaned_contours;
use super::clean::STRAY_SHARE;
use super::far_pieces::{self, take_far_pieces};
use super::plane::fit_plane;
use super::{remove_pieces, Contour, Polyline};
use crate::geometry::Vec3;
use serde::Serialize;

/// Below this ratio of a curve's spread across its line to along it (standard deviations) the
/// rest of a contour is too near a straight line for its fitted plane to say which way is off it
/// (the flattest real curve measured, a 9 mm septum arc, spreads 0.06).
const MIN_SPREAD: f64 = 0.02;

/// Which of a contour's `pieces` are candidates for damage: small enough to be a damaged part of
/// it (at most two points or [`STRAY_SHARE`] of the contour's, as for
/// [`super::clean::stray_pieces`]) while the contour keeps a bigger piece (a contour in one piece
/// is its own curve, and one all in scattered bits is the whole-contour rules' business). One
/// pass: a hostile contour has a hundred thousand pieces.
fn small_pieces(pieces: &[Polyline]) -> Vec<bool> {
    let total: usize = pieces.iter().map(|p| p.points.len()).sum();
    let most = 2.max((STRAY_SHARE * total as f64) as usize);
    let small: Vec<bool> = pieces.iter().map(|p| p.points.len() <= most).collect();
    let has_big = small.iter().any(|s| !s);
    small.into_iter().map(|s| s && has_big).collect()
}

/// The small pieces ([`small_pieces`]) of a contour's cleaned and split `pieces` whose every
/// point lies off the plane of the rest (its bigger pieces) by more than [`NON_PLANAR_MM`] and
/// than twice the rest's own largest residual, each with its points' largest distance from that
/// plane (mm). Nothing is judged against a rest that is not one plane's, or is nearly straight.
pub fn off_plane_pieces(pieces: &[Polyline]) -> Vec<(usize, f64)> {
    let small = small_pieces(pieces);
    if !small.iter().any(|s| *s) {
        return Vec::new();
    }
    let rest = pieces
        .iter()
        .zip(&small)
        .filter(|(_, s)| !**s)
        .flat_map(|(p, _)| p.points.iter());
    let Some(fit) = fit_plane(rest) else {
        return Vec::new();
    };
    if fit.max_residual > NON_PLANAR_MM || fit.flatness_ratio < MIN_SPREAD {
        return Vec::new();
    }
    let limit = NON_PLANAR_MM.max(2.0 * fit.max_residual);
    let off = |p: &Polyline| {
        p.points
            .iter()
            .map(|q| (q - fit.centroid).dot(&fit.normal).abs())
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), d| {
                (lo.min(d), hi.max(d))
            })
    };
    pieces
        .iter()
        .enumerate()
        .filter(|(k, _)| small[*k])
        .filter_map(|(k, p)| {
            let (nearest, farthest) = off(p);
            (nearest > limit).then_some((k, farthest))
        })
        .collect()
}

/// Leaves the off-plane pieces out of cleaned `contours` and returns them, per contour. A
/// contour keeps its bigger pieces.
pub fn take_off_plane_pieces(contours: &mut [Contour]) -> Vec<Vec<LeftOut>> {
    contours
        .iter_mut()
        .map(|c| {
            let found = off_plane_pieces(&c.pieces);
            let taken: Vec<LeftOut> = found
                .iter()
                .map(|&(k, off_mm)| LeftOut {
                    points: c.pieces[k].points.clone(),
                    off_mm,
                })
                .collect();
            if !found.is_empty() {
                remove_pieces(&mut c.pieces, found.into_iter().map(|(k, _)| k));
            }
            taken
        })
        .collect()
}

/// What a run leaves out of one contour as off its plane: how many points and how far the
/// farthest lies from the plane of the rest (mm). The warning line, the report's `per_contour`
/// and the app's Contours panel say it from this.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContourOffPlane {
    /// The contour's id (not serialised: the row the summary sits in names it).
    #[serde(skip_serializing)]
    pub id: String,
    pub points: usize,
    pub off_mm: f64,
}

/// An off-plane piece as the warnings and the per-contour summaries see it: its points (as
/// cleaned) and their largest distance from the plane of the rest of the contour (mm).
#[derive(Debug, Clone, PartialEq)]
pub struct LeftOut {
    pub points: Vec<Vec3>,
    pub off_mm: f64,
}

/// The off-plane pieces a run leaves out of each of `contours` (as given, any surfaces), indexed
/// like `contours`: judged as a run judges them, after the far pieces are left out.
pub fn left_out(contours: &[&Contour]) -> Vec<Vec<LeftOut>> {
    left_out_with_far(contours).1
}

/// The far pieces ([`far_pieces::left_out`]) and the off-plane pieces ([`left_out`]) a run
/// leaves out of each of `contours`, from one cleaning: a hostile contour of a hundred thousand
/// pieces takes seconds to clean.
pub fn left_out_with_far(
    contours: &[&Contour],
) -> (Vec<Vec<far_pieces::LeftOut>>, Vec<Vec<LeftOut>>) {
    let (index, mut cleaned) = cleaned_contours(contours);
    let far = take_far_pieces(&mut cleaned);
    let off = take_off_plane_pieces(&mut cleaned);
    let mut far_out = vec![Vec::new(); contours.len()];
    let mut off_out = vec![Vec::new(); contours.len()];
    for ((i, far), off) in index.into_iter().zip(far).zip(off) {
        far_out[i] = far;
        off_out[i] = off;
    }
    (far_out, off_out)
}

/// The summary of contour `c`'s off-plane pieces `found` ([`left_out`]); None without any.
pub fn contour_off_plane(c: &Contour, found: &[LeftOut]) -> Option<ContourOffPlane> {
    let off_mm = found.iter().map(|f| f.off_mm).reduce(f64::max)?;
    Some(ContourOffPlane {
        id: c.id.clone(),
        points: found.iter().map(|f| f.points.len()).sum(),
        off_mm,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    /// An open arc of `n` points at 1 mm steps round a circle of radius 30 in the plane z = 0
    /// tilted by 30 degrees about x.
    fn tilted_arc(n: usize) -> Vec<Vec3> {
        let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        (0..n)
            .map(|i| {
                let a = i as f64 / 30.0;
                let (x, y) = (30.0 * a.cos(), 30.0 * a.sin());
                v3(x, y * c, y * s)
            })
            .collect()
    }

    fn open(points: Vec<Vec3>) -> Polyline {
        Polyline {
            points,
            closed: false,
        }
    }

    #[test]
    fn an_end_piece_out_of_the_plane_is_found_and_one_in_it_is_not() {
        let arc = tilted_arc(60);
        let normal = v3(0.0, -30f64.to_radians().sin(), 30f64.to_radians().cos());
        let last = arc[59];
        // Three rows 12 mm past the end along the curve's plane, but 6 mm off it.
        let off: Vec<Vec3> = (1..=3)
            .map(|k| last + v3(12.0 + k as f64, 0.0, 0.0) + normal * 6.0)
            .collect();
        let pieces = vec![open(arc.clone()), open(off)];
        let found = off_plane_pieces(&pieces);
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].0, 1);
        assert!((found[0].1 - 6.0).abs() < 1e-9, "{}", found[0].1);
        // The same piece in the plane (a lone point of the curve, as real files have) stays.
        let along = v3(0.0, 30f64.to_radians().cos(), 30f64.to_radians().sin());
        let lone = vec![last + along * 20.0];
        assert!(off_plane_pieces(&[open(arc.clone()), open(lone)]).is_empty());
        // 2 mm off is within what a slice's curve may stray (NON_PLANAR_MM).
        let near = vec![last + v3(15.0, 0.0, 0.0) + normal * 2.0];
        assert!(off_plane_pieces(&[open(arc.clone()), open(near)]).is_empty());
        // A contour in one piece, or whose rest is a straight line, is not judged.
        assert!(off_plane_pieces(&[open(arc.clone())]).is_empty());
        let line: Vec<Vec3> = (0..40).map(|i| v3(i as f64, 0.0, 0.0)).collect();
        let bit = vec![v3(50.0, 0.0, 10.0)];
        assert!(off_plane_pieces(&[open(line), open(bit)]).is_empty());
    }

    #[test]
    fn a_run_leaves_the_piece_out_and_names_it_after_the_far_pieces() {
        let arc = tilted_arc(60);
        let normal = v3(0.0, -30f64.to_radians().sin(), 30f64.to_radians().cos());
        let mut points = arc.clone();
        points.push(arc[59] + v3(10.0, 0.0, 0.0) + normal * 8.0);
        let c = Contour {
            id: "lax".into(),
            surface: None,
            pieces: vec![open(points)],
            first_line: 2,
        };
        let found = left_out(&[&c]);
        let summary = contour_off_plane(&c, &found[0]).expect("the last row is off its plane");
        assert_eq!(summary.points, 1);
        assert!((summary.off_mm - 8.0).abs() < 1e-9, "{}", summary.off_mm);
        let mut cleaned = vec![crate::contours::clean::cleaned_contour(&c).expect("points")];
        take_off_plane_pieces(&mut cleaned);
        assert_eq!(cleaned[0].point_count(), 60);
    }
}
