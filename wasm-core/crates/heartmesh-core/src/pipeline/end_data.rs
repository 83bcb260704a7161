//! What the long-axis data say about an end of the cavity (`ends`): whether a curve closes it
//! (passes over its centre or across it), or at least reaches it (a point at or beyond the end
//! ring's plane). An end closed by data needs no lid; one that curves reach but do not close gets
//! a lid where they stop; one that no curve reaches is the short-axis stack's open end, where only
//! the slices' spacing says how far the cavity may run on (`ends::end_cap_points`).

use crate::contours::{Contour, ContourKind};
use crate::geometry::{centroid, Vec3};

/// A long-axis curve closes an end when, at or beyond the end ring's plane, it passes within this
/// share of the ring's mean radius of the ring's centre (a curve through the apex) ...
pub const CLOSE_CENTRE_PER_RADIUS: f64 = 0.25;
/// ... or moves across the end by at least this share of the radius (a curve over an off-centre
/// apex, a segment across the top). Open long-axis curves that stop at the valve plane stay near
/// the wall: they climb past the basal ring but move inwards by well under a radius.
pub const CLOSE_SPAN_PER_RADIUS: f64 = 1.0;
/// "At or beyond the plane" allows this share of the radius of rounding (as `tube`'s lid gap).
const PLANE_TOLERANCE_PER_RADIUS: f64 = 1e-3;

/// An end ring's centre, mean radius, height along the axis and the "at or beyond its plane"
/// tolerance: what deciding whether data close or reach the end and fitting the tips' plane
/// measure from.
pub(super) struct EndRing {
    pub centre: Vec3,
    pub radius: f64,
    pub height: f64,
    pub tolerance: f64,
}

impl EndRing {
    pub fn of(ring: &[Vec3], axis: &Vec3) -> Option<EndRing> {
        if ring.is_empty() {
            return None;
        }
        let centre = centroid(ring);
        let radius = ring.iter().map(|p| (p - centre).norm()).sum::<f64>() / ring.len() as f64;
        Some(EndRing {
            centre,
            radius,
            height: centre.dot(axis),
            tolerance: PLANE_TOLERANCE_PER_RADIUS * radius,
        })
    }
}

/// Whether long-axis data close the end at `ring` (`outward` = +1: the base, beyond the ring is
/// up the axis; -1: the apex). See [`CLOSE_CENTRE_PER_RADIUS`] and [`CLOSE_SPAN_PER_RADIUS`].
pub fn closed_by_data(
    ring: &[Vec3],
    contours: &[Contour],
    kinds: &[ContourKind],
    axis: &Vec3,
    outward: f64,
) -> bool {
    let Some(EndRing {
        centre: c,
        radius,
        height: h0,
        tolerance,
    }) = EndRing::of(ring, axis)
    else {
        return false;
    };
    let in_plane = |p: &Vec3| {
        let d = p - c;
        d - axis * d.dot(axis)
    };
    let beyond = |p: &Vec3| outward * (p.dot(axis) - h0) >= -tolerance;
    contours
        .iter()
        .zip(kinds)
        .filter(|(_, k)| **k == ContourKind::Lax)
        .flat_map(|(c, _)| &c.pieces)
        .any(|piece| {
            runs(&piece.points, piece.closed, &beyond)
                .into_iter()
                .any(|run| {
                    let q: Vec<Vec3> = run.iter().map(|&i| in_plane(&piece.points[i])).collect();
                    let near_centre = q
                        .iter()
                        .any(|d| d.norm() < CLOSE_CENTRE_PER_RADIUS * radius);
                    near_centre || span(&q) >= CLOSE_SPAN_PER_RADIUS * radius
                })
        })
}

/// Whether any long-axis point lies at or beyond the end ring's plane (within its rounding
/// tolerance; `outward` as in [`closed_by_data`]): a curve that reaches the end says where the
/// cavity stops there, even when it does not close it. With none, only the short-axis slices
/// bound the end.
pub fn reached_by_lax(
    ring: &[Vec3],
    contours: &[Contour],
    kinds: &[ContourKind],
    axis: &Vec3,
    outward: f64,
) -> bool {
    let Some(end) = EndRing::of(ring, axis) else {
        return false;
    };
    contours
        .iter()
        .zip(kinds)
        .filter(|(_, k)| **k == ContourKind::Lax)
        .flat_map(|(c, _)| c.points())
        .any(|p| outward * (p.dot(axis) - end.height) >= -end.tolerance)
}

/// Maximal runs of consecutive indices whose points satisfy `keep` (wrapping round a closed piece).
fn runs(points: &[Vec3], closed: bool, keep: &dyn Fn(&Vec3) -> bool) -> Vec<Vec<usize>> {
    let n = points.len();
    let flags: Vec<bool> = points.iter().map(keep).collect();
    if flags.iter().all(|&f| f) {
        return if n == 0 {
            Vec::new()
        } else {
            vec![(0..n).collect()]
        };
    }
    // A closed piece starts its walk just after a point outside, so no run is cut at index 0.
    let start = if closed {
        flags.iter().position(|&f| !f).map_or(0, |i| i + 1)
    } else {
        0
    };
    let mut out = Vec::new();
    let mut run = Vec::new();
    for k in 0..n {
        let i = (start + k) % n;
        if flags[i] {
            run.push(i);
        } else if !run.is_empty() {
            out.push(std::mem::take(&mut run));
        }
    }
    if !run.is_empty() {
        out.push(run);
    }
    out
}

/// The width of a point set, to within a factor of 2 from below (two farthest-point sweeps: exact
/// for points along a curve without sharp turns back).
fn span(q: &[Vec3]) -> f64 {
    let Some(first) = q.first() else {
        return 0.0;
    };
    let far = |from: &Vec3| {
        q.iter()
            .map(|p| ((p - from).norm(), *p))
            .fold((0.0, *from), |a, b| if b.0 > a.0 { b } else { a })
    };
    let (_, a) = far(first);
    far(&a).0
}

/// Shapes the end tests of this module and of `ends` build on: a ring, an open long-axis curve.
#[cfg(test)]
pub(super) mod fixtures {
    use crate::contours::{Contour, Polyline};
    use crate::geometry::{v3, Vec3};

    /// `n` points of a circle of radius `r` about the z axis at height `z`.
    pub fn circle(r: f64, z: f64, n: usize) -> Vec<Vec3> {
        (0..n)
            .map(|i| {
                let a = i as f64 / n as f64 * std::f64::consts::TAU;
                v3(r * a.cos(), r * a.sin(), z)
            })
            .collect()
    }

    /// An open long-axis curve through `points`.
    pub fn lax(points: Vec<Vec3>) -> Contour {
        Contour {
            id: "lax".into(),
            surface: None,
            pieces: vec![Polyline {
                points,
                closed: false,
            }],
            first_line: 0,
        }
    }

    /// The axis of those shapes.
    pub const Z: Vec3 = Vec3::new(0.0, 0.0, 1.0);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    use super::fixtures::{circle, lax, Z};

    /// A radius-10 ring at z = 0 as the apex end, with long-axis curves of each kind.
    #[test]
    fn which_curves_close_an_end() {
        let ring = circle(10.0, 0.0, 40);
        let kinds = [ContourKind::Lax];
        // A U through the apex (x = -10 .. 10, down to z = -8 on the axis): closed.
        let u: Vec<Vec3> = (0..=20)
            .map(|i| {
                let x = -10.0 + i as f64;
                v3(
                    x,
                    0.0,
                    -8.0 * (1.0 - (x / 10.0).powi(2)) + 5.0 * (x.abs() / 10.0),
                )
            })
            .collect();
        assert!(closed_by_data(&ring, &[lax(u.clone())], &kinds, &Z, -1.0));
        // The same curve seen from the base end (z = 20 ring): nothing beyond it.
        let top = circle(10.0, 20.0, 40);
        assert!(!closed_by_data(&top, &[lax(u)], &kinds, &Z, 1.0));
        // One wall climbing 15 mm past the basal ring and ending 7 mm from the axis (a valve
        // hinge): the LV base, not closed.
        let wall: Vec<Vec3> = (0..=15)
            .map(|i| v3(10.0 - 0.2 * i as f64, 0.0, 10.0 + i as f64))
            .collect();
        assert!(!closed_by_data(&top, &[lax(wall)], &kinds, &Z, 1.0));
        // A segment lying in the top plane from wall to wall: closed (span 20 >= radius 10).
        let segment = vec![v3(-9.0, 1.0, 20.0), v3(9.0, 1.0, 20.0)];
        assert!(closed_by_data(
            &top,
            &[lax(segment.clone())],
            &kinds,
            &Z,
            1.0
        ));
        // The same segment 1e-2 below the plane (beyond the 1e-3 x radius tolerance): not.
        let low: Vec<Vec3> = segment.iter().map(|p| p - Z * 1e-2).collect();
        assert!(!closed_by_data(&top, &[lax(low)], &kinds, &Z, 1.0));
        // A curve ending 2 mm from the axis just past the ring: closed (2 < 0.25 x 10).
        let tip = vec![v3(10.0, 0.0, 18.0), v3(2.0, 0.0, 20.5)];
        assert!(closed_by_data(&top, &[lax(tip.clone())], &kinds, &Z, 1.0));
        // Short-axis curves never close an end.
        assert!(!closed_by_data(
            &top,
            &[lax(tip)],
            &[ContourKind::Sax],
            &Z,
            1.0
        ));
    }

    /// A radius-10 ring at z = 20 (the base; "at or beyond" allows 1e-3 x 10 = 0.01 mm) and one at
    /// z = 0 (the apex).
    #[test]
    fn which_curves_reach_an_end() {
        let top = circle(10.0, 20.0, 40);
        let bottom = circle(10.0, 0.0, 40);
        let kinds = [ContourKind::Lax];
        let wall = |z0: f64, z1: f64| lax(vec![v3(9.0, 0.0, z0), v3(9.5, 0.0, z1)]);
        // A wall curve from 5 up to 19.995: within the tolerance of the basal plane, reaches it.
        assert!(reached_by_lax(&top, &[wall(5.0, 19.995)], &kinds, &Z, 1.0));
        // Up to 19.98: 0.02 short, beyond the tolerance: does not (nor the apex, from 5 up).
        assert!(!reached_by_lax(&top, &[wall(5.0, 19.98)], &kinds, &Z, 1.0));
        assert!(!reached_by_lax(
            &bottom,
            &[wall(5.0, 19.98)],
            &kinds,
            &Z,
            -1.0
        ));
        // Down to -0.5 below the apical ring: reaches the apex (without closing it: it stays
        // at the wall).
        let low = [wall(5.0, -0.5)];
        assert!(reached_by_lax(&bottom, &low, &kinds, &Z, -1.0));
        assert!(!closed_by_data(&bottom, &low, &kinds, &Z, -1.0));
        // Short-axis curves, no curves or an empty ring: nothing reaches.
        assert!(!reached_by_lax(
            &bottom,
            &low,
            &[ContourKind::Sax],
            &Z,
            -1.0
        ));
        assert!(!reached_by_lax(&bottom, &[], &[], &Z, -1.0));
        assert!(!reached_by_lax(&[], &low, &kinds, &Z, -1.0));
    }
}
