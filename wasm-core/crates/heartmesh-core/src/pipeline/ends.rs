//! End caps: synthetic lid attractors at the ends of the cavity that no curve closes.
//!
//! Where no contour closes an end (the base of almost every file: long-axis curves stop at the
//! valve plane; both ends of an RV without RV long-axis curves; short-axis-only files), nothing
//! holds the mesh there: the attractors are contour points, each remesh's affine shrink correction
//! and the smooth spline carry the unconstrained cap on past the data, by 0.4 ring radii on the
//! phantoms (docs/VALIDATION.md, "Session 9: overrun past the data"). METHOD.md section 2 intends
//! the lid to be where the mesh ends ("without LAX ... mesh ends flat there"), so such an end gets
//! attractor points filling the end ring's outline in the plane of the tube's lid, perpendicular to
//! the long axis: the flat section the ruled tube's lid spans. They are sampled at about the real
//! attractors' spacing, kept a spacing in from the rim (the rim is the wall data's), and pull with a
//! weight below 1 so that real contours win where they disagree. They are never data: contour
//! distances, per-contour tables, colour maps and the step report ignore them.
//!
//! Why a flat disc rather than the cone spanned by the ring and the lid point: the lid is above
//! the ring only where long-axis curves run on past the ring along the wall (the LV base, 10-20 mm
//! up to the valve plane); a cone from the basal ring to that height would pull the wall between
//! the long-axis planes inwards, against the data, while the disc at the lid's height caps the
//! wall the curves describe (the tube's extra basal ring, `tube::extend_to_base`, is the same
//! outline).

use super::tube::Lids;
use crate::contours::{Contour, ContourKind};
use crate::geometry::Vec3;
use crate::params::EndCapMode;
use serde::Serialize;

/// Which ends got synthetic lid points, and how many (per attractor resampling: the points are the
/// same at every resampling). All false / 0 when end caps are off.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct EndCapsReport {
    pub mode: &'static str,
    pub base: bool,
    pub apex: bool,
    pub points: usize,
}

impl EndCapsReport {
    pub fn none(mode: EndCapMode) -> Self {
        EndCapsReport {
            mode: mode.name(),
            base: false,
            apex: false,
            points: 0,
        }
    }
}

/// Data weight of a lid point (contour points have 1, before conflict softening): enough to hold
/// an end no curve closes, low enough that real contours win where they disagree. Swept on the
/// phantoms and the population study (docs/VALIDATION.md, "Session 10: closing open ends").
pub const END_CAP_WEIGHT: f64 = 0.3;

/// A long-axis curve closes an end when, at or beyond the end ring's plane, it passes within this
/// share of the ring's mean radius of the ring's centre (a curve through the apex) ...
pub const CLOSE_CENTRE_PER_RADIUS: f64 = 0.25;
/// ... or moves across the end by at least this share of the radius (a curve over an off-centre
/// apex, a segment across the top). Open long-axis curves that stop at the valve plane stay near
/// the wall: they climb past the basal ring but move inwards by well under a radius.
pub const CLOSE_SPAN_PER_RADIUS: f64 = 1.0;
/// "At or beyond the plane" allows this share of the radius of rounding (as `tube`'s lid gap).
const PLANE_TOLERANCE_PER_RADIUS: f64 = 1e-3;
/// Lid points stay this many attractor spacings in from the end ring: the rim belongs to the wall
/// data, and a lid point closer to the wall than the wall attractors are to each other would
/// fight them for the same triangles.
pub const RIM_INSET_PER_SPACING: f64 = 1.0;
/// At most this share of the real attractor count per end (a large explicit count asks for ~1 mm
/// spacing: a dense disc would double the spline's size for no gain).
const MAX_POINTS_PER_REAL: f64 = 0.25;

fn centroid(points: &[Vec3]) -> Vec3 {
    points.iter().fold(Vec3::zeros(), |a, p| a + p) / points.len().max(1) as f64
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
    if ring.is_empty() {
        return false;
    }
    let c = centroid(ring);
    let radius = ring.iter().map(|p| (p - c).norm()).sum::<f64>() / ring.len() as f64;
    let h0 = c.dot(axis);
    let tolerance = PLANE_TOLERANCE_PER_RADIUS * radius;
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

/// Lid points filling `ring`'s outline moved along `axis` to the height of `lid`: a square grid of
/// pitch `spacing` anchored at the outline's centroid and turned to the ring's first point (the
/// tube's seam, so the points do not depend on the scanner frame), keeping the grid points inside
/// the outline and at least `inset` from it.
pub fn disc_points(ring: &[Vec3], lid: &Vec3, axis: &Vec3, spacing: f64, inset: f64) -> Vec<Vec3> {
    if ring.len() < 3 || !(spacing.is_finite() && spacing > 0.0) {
        return Vec::new();
    }
    let h = lid.dot(axis);
    let outline: Vec<Vec3> = ring.iter().map(|p| p + axis * (h - p.dot(axis))).collect();
    let c = centroid(&outline);
    let Some(u) = (outline[0] - c).try_normalize(1e-300) else {
        return Vec::new();
    };
    let v = axis.cross(&u);
    let flat: Vec<(f64, f64)> = outline
        .iter()
        .map(|p| ((p - c).dot(&u), (p - c).dot(&v)))
        .collect();
    let reach = flat.iter().map(|(x, y)| x.hypot(*y)).fold(0.0, f64::max);
    let steps = (reach / spacing).ceil();
    if !steps.is_finite() || steps > 1e4 {
        return Vec::new();
    }
    let steps = steps as i64;
    let mut out = Vec::new();
    for j in -steps..=steps {
        for i in -steps..=steps {
            let (x, y) = (i as f64 * spacing, j as f64 * spacing);
            if inside(&flat, x, y) && edge_distance(&flat, x, y) >= inset {
                out.push(c + u * x + v * y);
            }
        }
    }
    out
}

/// Even-odd point-in-polygon test.
fn inside(poly: &[(f64, f64)], x: f64, y: f64) -> bool {
    let mut odd = false;
    for (k, a) in poly.iter().enumerate() {
        let b = poly[(k + 1) % poly.len()];
        if (a.1 > y) != (b.1 > y) && x < a.0 + (y - a.1) / (b.1 - a.1) * (b.0 - a.0) {
            odd = !odd;
        }
    }
    odd
}

/// Distance from (x, y) to the polygon's edges.
fn edge_distance(poly: &[(f64, f64)], x: f64, y: f64) -> f64 {
    let mut best = f64::INFINITY;
    for (k, a) in poly.iter().enumerate() {
        let b = poly[(k + 1) % poly.len()];
        let (ex, ey) = (b.0 - a.0, b.1 - a.1);
        let len2 = ex * ex + ey * ey;
        let t = if len2 > 0.0 {
            (((x - a.0) * ex + (y - a.1) * ey) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        best = best.min((x - a.0 - t * ex).hypot(y - a.1 - t * ey));
    }
    best
}

/// The lid points of every end that no curve closes (mm), and what was done. `rings` are the
/// tube's short-axis rings, apex to base (before the basal extension); `spacing` is the real
/// attractors' spacing (mm) and `real_attractors` their count.
#[allow(clippy::too_many_arguments)]
pub fn end_cap_points(
    mode: EndCapMode,
    rings: &[Vec<Vec3>],
    lids: &Lids,
    contours: &[Contour],
    kinds: &[ContourKind],
    axis: &Vec3,
    spacing: f64,
    real_attractors: usize,
) -> (Vec<Vec3>, EndCapsReport) {
    let mut report = EndCapsReport::none(mode);
    let mut points = Vec::new();
    if mode == EndCapMode::Off {
        return (points, report);
    }
    let ends = [
        (rings.first(), lids.apex, -1.0),
        (rings.last(), lids.base, 1.0),
    ];
    for (ring, lid, outward) in ends {
        let (Some(ring), Some(lid)) = (ring, lid) else {
            continue;
        };
        if closed_by_data(ring, contours, kinds, axis, outward) {
            continue;
        }
        // Enough spacing that one end holds at most a share of the real attractors.
        let c = centroid(ring);
        let radius = ring.iter().map(|p| (p - c).norm()).sum::<f64>() / ring.len().max(1) as f64;
        let area = std::f64::consts::PI * radius * radius;
        let most = (MAX_POINTS_PER_REAL * real_attractors as f64).max(1.0);
        let pitch = spacing.max((area / most).sqrt());
        let disc = disc_points(ring, &lid, axis, pitch, RIM_INSET_PER_SPACING * pitch);
        if disc.is_empty() {
            continue;
        }
        if outward > 0.0 {
            report.base = true;
        } else {
            report.apex = true;
        }
        points.extend(disc);
    }
    report.points = points.len();
    (points, report)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contours::Polyline;
    use crate::geometry::v3;

    fn circle(r: f64, z: f64, n: usize) -> Vec<Vec3> {
        (0..n)
            .map(|i| {
                let a = i as f64 / n as f64 * std::f64::consts::TAU;
                v3(r * a.cos(), r * a.sin(), z)
            })
            .collect()
    }

    fn lax(points: Vec<Vec3>) -> Contour {
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

    const Z: Vec3 = Vec3::new(0.0, 0.0, 1.0);

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

    /// A radius-10 disc at pitch 2 with a 2 mm inset: the grid points within radius 8 of the
    /// centre (up to the 40-gon's flats), all in the lid's plane.
    #[test]
    fn disc_fills_the_ring_at_the_spacing() {
        let ring = circle(10.0, 0.0, 40);
        let lid = v3(0.0, 0.0, 5.0);
        let pts = disc_points(&ring, &lid, &Z, 2.0, 2.0);
        // Grid points (2i, 2j) with i^2 + j^2 <= 16 (radius 8): the 49 lattice points of the
        // radius-4 disc, less the 4 on the grid axes at radius 8, which point at vertices of the
        // 40-gon (the grid is turned to its first point) and lie 1.994 mm from the edges there.
        assert_eq!(pts.len(), 45);
        assert!(pts.iter().all(|p| (p.z - 5.0).abs() < 1e-12));
        assert!(pts.iter().any(|p| (p - lid).norm() < 1e-12));
        let far = pts.iter().map(|p| p.x.hypot(p.y)).fold(0.0, f64::max);
        assert!((far - 2.0 * 13f64.sqrt()).abs() < 1e-9, "{far}");
        // Nothing for a bad spacing or too few ring points.
        assert!(disc_points(&ring, &lid, &Z, 0.0, 0.0).is_empty());
        assert!(disc_points(&ring[..2], &lid, &Z, 1.0, 0.0).is_empty());
    }

    #[test]
    fn caps_only_where_no_curve_closes() {
        let rings = vec![circle(10.0, 0.0, 40), circle(10.0, 20.0, 40)];
        let lids = Lids {
            apex: Some(v3(0.0, 0.0, -8.0)),
            base: Some(v3(0.0, 0.0, 20.0)),
        };
        let u: Vec<Vec3> = (0..=20)
            .map(|i| {
                let x = -10.0 + i as f64;
                v3(
                    x,
                    0.0,
                    20.0 * (x / 10.0).powi(2) - 8.0 * (1.0 - (x / 10.0).powi(2)),
                )
            })
            .collect();
        let contours = [lax(u)];
        let kinds = [ContourKind::Lax];
        let (pts, report) = end_cap_points(
            EndCapMode::Auto,
            &rings,
            &lids,
            &contours,
            &kinds,
            &Z,
            2.0,
            400,
        );
        assert!(report.base && !report.apex);
        assert_eq!(report.points, pts.len());
        // Pitch 2, inset 2: the 45 points of the test above, at the base's height.
        assert_eq!(pts.len(), 45);
        assert!(pts.iter().all(|p| (p.z - 20.0).abs() < 1e-12));
        // Few real attractors: the pitch grows so one end holds at most a quarter of them
        // (100 x 0.25 = 25 points over pi x 100 mm^2: pitch 3.54, inset 3.54).
        let (few, _) = end_cap_points(
            EndCapMode::Auto,
            &rings,
            &lids,
            &contours,
            &kinds,
            &Z,
            2.0,
            100,
        );
        assert!(few.len() <= 25 && few.len() >= 9, "{}", few.len());
        let (none, off) = end_cap_points(
            EndCapMode::Off,
            &rings,
            &lids,
            &contours,
            &kinds,
            &Z,
            2.0,
            400,
        );
        assert!(none.is_empty());
        assert_eq!(off, EndCapsReport::none(EndCapMode::Off));
        assert_eq!(off.mode, "off");
    }
}
