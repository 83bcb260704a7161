//! One closed ring per short-axis slice, the cross-sections of the initial tube
//! (Villard et al. 2018, section 2.2).
//!
//! A slice may hold one closed contour, one open curve (a ring with a gap, or a curve stored in two
//! pieces) or several pieces of one surface (RV free wall + septum). The pieces are chained end to
//! nearest end into a single loop, which is then oriented counter-clockwise about the long axis.

use super::clean::{length, resample_count};
use super::{Contour, Polyline};
use crate::geometry::Vec3;

/// Most open pieces [`join_pieces`] chains end to nearest end: the search is quadratic in their
/// count, and a slice of a real file has a handful (a hostile contour cleaned into a hundred
/// thousand bits spent half a minute here); past it they are chained in the order given.
const MAX_CHAINED: usize = 4096;

/// Chains the pieces of one slice into one closed loop of points (not resampled).
pub fn join_pieces(pieces: &[&Polyline]) -> Vec<Vec3> {
    let mut usable: Vec<&Polyline> = pieces
        .iter()
        .copied()
        .filter(|p| !p.points.is_empty())
        .collect();
    if usable.is_empty() {
        return Vec::new();
    }
    // A closed piece is a ring already: take the longest one.
    if let Some(closed) = usable
        .iter()
        .filter(|p| p.closed && p.points.len() >= 3)
        .max_by(|a, b| length(&a.points, true).total_cmp(&length(&b.points, true)))
    {
        return closed.points.clone();
    }
    if usable.len() > MAX_CHAINED {
        return usable
            .iter()
            .flat_map(|p| p.points.iter().copied())
            .collect();
    }
    // Start from the longest open piece and keep appending the piece whose nearer end is closest
    // to the current tail.
    usable.sort_by(|a, b| length(&b.points, false).total_cmp(&length(&a.points, false)));
    let mut chain: Vec<Vec3> = usable[0].points.clone();
    let mut rest: Vec<&Polyline> = usable[1..].to_vec();
    while !rest.is_empty() {
        let tail = chain[chain.len() - 1];
        let mut best = (f64::INFINITY, 0usize, false);
        for (k, p) in rest.iter().enumerate() {
            let (first, last) = (p.points[0], p.points[p.points.len() - 1]);
            let (df, dl) = ((first - tail).norm(), (last - tail).norm());
            if df < best.0 {
                best = (df, k, false);
            }
            if dl < best.0 {
                best = (dl, k, true);
            }
        }
        let piece = rest.remove(best.1);
        if best.2 {
            chain.extend(piece.points.iter().rev());
        } else {
            chain.extend(piece.points.iter());
        }
    }
    chain
}

/// Signed area of a loop projected on the plane orthogonal to `axis` (positive: counter-clockwise
/// seen from the tip of `axis`).
pub fn signed_area(points: &[Vec3], axis: &Vec3) -> f64 {
    let n = points.len();
    (0..n)
        .map(|i| points[i].cross(&points[(i + 1) % n]).dot(axis))
        .sum::<f64>()
        * 0.5
}

/// Builds the `k`-point rings of the initial tube, one per slice (apex to base): joined,
/// counter-clockwise about `axis`, each started at the point nearest the previous ring's start so that
/// the tube does not twist.
pub fn tube_rings(
    contours: &[Contour],
    slices: &[Vec<usize>],
    axis: &Vec3,
    k: usize,
) -> Vec<Vec<Vec3>> {
    tube_rings_of(contours, slices, axis, k).0
}

/// [`tube_rings`] and, per ring, the index of its slice in `slices` (slices whose pieces join to
/// fewer than 3 points give no ring), so that a fault of the tube can name its contours.
pub fn tube_rings_of(
    contours: &[Contour],
    slices: &[Vec<usize>],
    axis: &Vec3,
    k: usize,
) -> (Vec<Vec<Vec3>>, Vec<usize>) {
    let mut rings: Vec<Vec<Vec3>> = Vec::with_capacity(slices.len());
    let mut of: Vec<usize> = Vec::with_capacity(slices.len());
    let mut prev_start: Option<Vec3> = None;
    for (index, slice) in slices.iter().enumerate() {
        let pieces: Vec<&Polyline> = slice
            .iter()
            .flat_map(|&j| contours[j].pieces.iter())
            .collect();
        let mut loop_pts = join_pieces(&pieces);
        if loop_pts.len() < 3 {
            continue;
        }
        // First ring: start at its first point as delineated. A direction fixed in scanner
        // coordinates would make the mesh depend on how the patient lies in the scanner frame;
        // the file's own order moves with the contours under any rotation or translation.
        let first_point = loop_pts[0];
        if signed_area(&loop_pts, axis) < 0.0 {
            loop_pts.reverse();
        }
        let start = nearest_on_loop(&loop_pts, &prev_start.unwrap_or(first_point));
        let rotated = rotate_loop_to(&loop_pts, start);
        let ring = resample_count(&rotated, true, k);
        prev_start = ring.first().copied();
        rings.push(ring);
        of.push(index);
    }
    (rings, of)
}

/// Position on a closed loop nearest to `q`: (segment index, parameter in [0, 1]).
fn nearest_on_loop(points: &[Vec3], q: &Vec3) -> (usize, f64) {
    let n = points.len();
    let mut best = (f64::INFINITY, 0usize, 0.0);
    for i in 0..n {
        let a = points[i];
        let b = points[(i + 1) % n];
        let ab = b - a;
        let l2 = ab.norm_squared();
        let t = if l2 > 0.0 {
            ((q - a).dot(&ab) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let d = (a + ab * t - q).norm_squared();
        if d < best.0 {
            best = (d, i, t);
        }
    }
    (best.1, best.2)
}

/// The loop re-started at a point on segment `seg` at parameter `t`.
fn rotate_loop_to(points: &[Vec3], (seg, t): (usize, f64)) -> Vec<Vec3> {
    let n = points.len();
    let a = points[seg];
    let b = points[(seg + 1) % n];
    let start = a + (b - a) * t;
    let mut out = Vec::with_capacity(n + 1);
    out.push(start);
    for k in 1..=n {
        let p = points[(seg + k) % n];
        if (p - start).norm() > 1e-9 && !(k == n && (p - start).norm() < 1e-9) {
            out.push(p);
        }
    }
    // The last pushed point is `a` again (seg + n): drop it when it coincides with the start region.
    if out.len() > 1 && (out[out.len() - 1] - start).norm() < 1e-9 {
        out.pop();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    fn arc(r: f64, z: f64, from: f64, to: f64, n: usize) -> Polyline {
        Polyline {
            points: (0..n)
                .map(|i| {
                    let a = from + (to - from) * i as f64 / (n - 1) as f64;
                    v3(r * a.cos(), r * a.sin(), z)
                })
                .collect(),
            closed: false,
        }
    }

    #[test]
    fn past_the_most_pieces_chained_they_are_joined_in_the_order_given() {
        // A hostile contour cleaned into bits: every point kept, in the order given, at once.
        let bits: Vec<Polyline> = (0..MAX_CHAINED + 1)
            .map(|i| arc(20.0, i as f64, 0.0, 1.0, 2))
            .collect();
        let refs: Vec<&Polyline> = bits.iter().collect();
        let joined = join_pieces(&refs);
        assert_eq!(joined.len(), 2 * (MAX_CHAINED + 1));
        assert_eq!(joined[2].z, 1.0);
        assert_eq!(joined.last().map(|p| p.z), Some(MAX_CHAINED as f64));
    }

    #[test]
    fn joins_two_arcs_into_a_ring() {
        let a = arc(10.0, 0.0, 0.0, 3.0, 20);
        // The second arc is stored clockwise: the join must reverse it.
        let b = arc(10.0, 0.0, std::f64::consts::TAU - 0.1, 3.2, 20);
        let ring = join_pieces(&[&a, &b]);
        assert_eq!(ring.len(), 40);
        let area = signed_area(&ring, &v3(0., 0., 1.)).abs();
        assert!((area - std::f64::consts::PI * 100.0).abs() < 15.0, "{area}");
    }

    #[test]
    fn rings_are_ccw_and_untwisted() {
        let mk = |z: f64, rev: bool, phase: f64| {
            let mut p = arc(10.0, z, phase, phase + std::f64::consts::TAU * 0.98, 60);
            p.closed = true;
            if rev {
                p.points.reverse();
            }
            Contour {
                id: format!("{z}"),
                surface: None,
                pieces: vec![p],
                first_line: 0,
            }
        };
        let cs = vec![
            mk(0.0, false, 0.0),
            mk(10.0, true, 2.0),
            mk(20.0, false, 4.0),
        ];
        let rings = tube_rings(&cs, &[vec![0], vec![1], vec![2]], &v3(0., 0., 1.), 50);
        assert_eq!(rings.len(), 3);
        for r in &rings {
            assert_eq!(r.len(), 50);
            assert!(signed_area(r, &v3(0., 0., 1.)) > 0.0);
        }
        for w in rings.windows(2) {
            let d = (w[1][0] - w[0][0]) - v3(0., 0., 10.0);
            assert!(d.norm() < 0.5, "start points drift by {}", d.norm());
        }
    }
}
