//! Cleaning contour polylines: non-finite points, consecutive duplicates, jumps that reveal a curve
//! stored in several pieces, and arc-length resampling.
//!
//! Villard et al. 2018 (section 2) assume each contour is a clean ordered polyline at roughly 1 mm
//! spacing; real exports are not, so this is the first thing the pipeline does.

use super::{Contour, Polyline};
use crate::geometry::Vec3;
use crate::spatial::SegmentTree;
use serde::Serialize;

/// A jump longer than this many times the median spacing splits a curve into pieces.
pub const JUMP_FACTOR: f64 = 5.0;

/// Most points [`resample_spacing`] makes of one polyline (a 1,000 km curve at 1 mm).
pub const MAX_RESAMPLED: usize = 1 << 20;

/// Points closer than this (mm) to their predecessor are duplicates.
const DUPLICATE_MM: f64 = 1e-6;

/// Drops non-finite points and consecutive duplicates, and, for closed curves, a repeated first point
/// at the end.
pub fn clean_points(points: &[Vec3], closed: bool) -> Vec<Vec3> {
    let mut out: Vec<Vec3> = Vec::with_capacity(points.len());
    for p in points.iter().filter(|p| p.iter().all(|c| c.is_finite())) {
        if out
            .last()
            .is_none_or(|q: &Vec3| (p - q).norm() > DUPLICATE_MM)
        {
            out.push(*p);
        }
    }
    if closed && out.len() > 1 && (out[0] - out[out.len() - 1]).norm() <= DUPLICATE_MM {
        out.pop();
    }
    out
}

/// Median of the consecutive spacings of an open run of points (0 for fewer than 2 points).
pub fn median_spacing(points: &[Vec3]) -> f64 {
    let mut d: Vec<f64> = points.windows(2).map(|w| (w[1] - w[0]).norm()).collect();
    if d.is_empty() {
        return 0.0;
    }
    d.sort_by(f64::total_cmp);
    d[d.len() / 2]
}

/// Farther than this (mm) from every other point of its contour, a small piece lies outside any
/// heart: damaged coordinates, not a lone point of the curve. Real files carry lone points up to
/// ~50 mm before the rest of a curve (biv-me's long-axis curves), which stay.
pub const STRAY_POINT_MM: f64 = 100.0;

/// A piece of at most this share of its contour's points (or two points) is small enough to be
/// the stray part; a bigger one might be the curve itself.
pub const STRAY_SHARE: f64 = 0.25;

/// The small pieces (at most two points, or [`STRAY_SHARE`] of the contour's points) of a
/// contour's cleaned and split pieces that lie farther than [`STRAY_POINT_MM`], and than twice
/// the extent of the rest, from every point of the rest of the contour, with that distance (mm).
/// A corrupted value throws a point hundreds of millimetres out, a damaged run of rows a few;
/// kept, they pull the surface into a spike through everything, which the remesh then flattens
/// (three points 300 mm out on the SurFCo example: 264 ml to 3.8 ml at iteration 140).
pub fn stray_pieces(pieces: &[Polyline]) -> Vec<(usize, f64)> {
    let total: usize = pieces.iter().map(|p| p.points.len()).sum();
    let most = 2.max((STRAY_SHARE * total as f64) as usize);
    let small = |p: &Polyline| p.points.len() <= most;
    // The rest is the same for every small piece (the big pieces): gathered once, so that a
    // contour split into a hundred thousand bits is not gathered a hundred thousand times.
    let rest: Vec<&Vec3> = pieces
        .iter()
        .filter(|p| !small(p))
        .flat_map(|p| p.points.iter())
        .collect();
    if rest.len() < 3 {
        return Vec::new();
    }
    let (mut lo, mut hi) = (*rest[0], *rest[0]);
    for p in &rest {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    let extent = (hi - lo).norm();
    let limit = STRAY_POINT_MM.max(2.0 * extent);
    // A point this near the rest's box is within `limit` of a point of the rest (the box's
    // diagonal is `extent`): no stray, and no scan of the rest.
    let near_box = |p: &Vec3| (p.sup(&lo).inf(&hi) - p).norm() <= limit - extent;
    let mut out = Vec::new();
    // Built at the first piece that needs it: a tree walk per point rather than a scan of the
    // rest (a hostile contour of 200,000 points and 100,000 bits took minutes).
    let mut tree: Option<SegmentTree> = None;
    for (k, piece) in pieces.iter().enumerate().filter(|(_, p)| small(p)) {
        if piece.points.iter().any(near_box) {
            continue;
        }
        let tree =
            tree.get_or_insert_with(|| SegmentTree::new(rest.iter().map(|p| (**p, **p)).collect()));
        let gap = piece
            .points
            .iter()
            .map(|p| tree.distance(p))
            .fold(f64::INFINITY, f64::min);
        if gap > limit {
            out.push((k, gap));
        }
    }
    out
}

/// The contour with every piece cleaned and split ([`clean_and_split`]), stray points
/// ([`stray_pieces`]) left out; None when nothing is left. The axis search and the alignment
/// both look at contours this way before fitting planes.
pub fn cleaned_contour(c: &Contour) -> Option<Contour> {
    let mut pieces: Vec<_> = c.pieces.iter().flat_map(clean_and_split).collect();
    let strays: Vec<usize> = stray_pieces(&pieces).into_iter().map(|(k, _)| k).collect();
    super::remove_pieces(&mut pieces, strays);
    (!pieces.is_empty()).then(|| Contour {
        id: c.id.clone(),
        surface: c.surface.clone(),
        pieces,
        first_line: c.first_line,
    })
}

/// The [`cleaned_contour`]s of `contours` with, for each, its index in `contours` (those left
/// empty are dropped): the per-contour summaries of what a run leaves out index back by it.
pub fn cleaned_contours(contours: &[&Contour]) -> (Vec<usize>, Vec<Contour>) {
    contours
        .iter()
        .enumerate()
        .filter_map(|(i, c)| cleaned_contour(c).map(|c| (i, c)))
        .unzip()
}

/// Longest run of points [`spikes`] takes for damaged values: one corrupted coordinate moves one
/// point, a damaged row or two a couple; a longer excursion may be drawn.
pub const SPIKE_POINTS: usize = 3;

/// A spike reaches at least this many times as far out as the points either side of it lie
/// apart (an apex under ~28 degrees). A damaged value lands anywhere, mostly far; a hand-clicked
/// outline whose one click at a crescent's tip is far from its neighbours is wider than that, and
/// keeps its tip.
pub const SPIKE_SHARPNESS: f64 = 2.0;

/// A run of points that leaves its curve by a jump and comes straight back by another.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spike {
    /// Index of the run's first point in the cleaned points.
    pub start: usize,
    /// Points in the run (at most [`SPIKE_POINTS`]).
    pub len: usize,
    /// How far the run goes out: its farthest point's distance from the nearer of the two points
    /// either side (mm).
    pub offset: f64,
}

/// The jump limit of a cleaned curve: [`JUMP_FACTOR`] x its median segment length (closing
/// segment included when closed); None under two points.
fn jump_limit(pts: &[Vec3], closed: bool) -> Option<f64> {
    let n = pts.len();
    if n < 2 {
        return None;
    }
    let segs = if closed { n } else { n - 1 };
    let mut lens: Vec<f64> = (0..segs)
        .map(|i| (pts[(i + 1) % n] - pts[i]).norm())
        .collect();
    lens.sort_by(f64::total_cmp);
    Some(JUMP_FACTOR * lens[lens.len() / 2])
}

/// Runs of at most [`SPIKE_POINTS`] points entered and left by a jump (longer than `limit`)
/// whose neighbours either side are no jump apart, and sharp ([`SPIKE_SHARPNESS`]). A damaged
/// value throws a point out of its curve and the next row comes straight back: split at both
/// jumps (a curve in pieces), the point would stay a piece of its own, and one 90 mm out pulls
/// the surface into a spike through everything (a corrupt Segment file: 144 crossing triangle
/// pairs, `scripts/hostile.py`). A curve really stored in pieces does not come back to where it
/// left off, so it is still split.
fn spikes(pts: &[Vec3], closed: bool, limit: f64) -> Vec<Spike> {
    let n = pts.len();
    let segs = if closed { n } else { n.saturating_sub(1) };
    let jumps: Vec<usize> = (0..segs)
        .filter(|&i| (pts[(i + 1) % n] - pts[i]).norm() > limit)
        .collect();
    let mut out: Vec<Spike> = Vec::new();
    for (k, &leave) in jumps.iter().enumerate() {
        // The next jump along the curve (round the loop when closed) ends the run.
        let back = match jumps.get(k + 1) {
            Some(&b) => b,
            None if closed && jumps.len() > 1 => jumps[0] + n,
            None => continue,
        };
        let len = back - leave;
        let before = leave;
        let after = back + 1;
        // An open curve's run must have a point on each side; at least three points stay.
        if len > SPIKE_POINTS || n < len + 3 || (!closed && after >= n) {
            continue;
        }
        let (a, b) = (pts[before % n], pts[after % n]);
        let chord = (b - a).norm();
        if chord > limit {
            continue;
        }
        let start = (leave + 1) % n;
        let offset = (0..len)
            .map(|j| {
                let p = pts[(start + j) % n];
                (p - a).norm().min((p - b).norm())
            })
            .fold(0.0, f64::max);
        if offset >= SPIKE_SHARPNESS * chord {
            out.push(Spike { start, len, offset });
        }
    }
    out
}

/// The points without their spikes ([`spikes`]), and the spikes left out. The points either
/// side of a spike may coincide (out and back to the same place): cleaned again. A handful of
/// points in two clumps are each other's spikes: then neither is one, and nothing is left out.
fn without_spikes(pts: Vec<Vec3>, closed: bool, limit: f64) -> (Vec<Vec3>, Vec<Spike>) {
    let found = spikes(&pts, closed, limit);
    if found.is_empty() {
        return (pts, found);
    }
    let n = pts.len();
    let mut keep = vec![true; n];
    for s in &found {
        for j in 0..s.len {
            keep[(s.start + j) % n] = false;
        }
    }
    let kept: Vec<Vec3> = pts
        .iter()
        .zip(&keep)
        .filter(|(_, k)| **k)
        .map(|(p, _)| *p)
        .collect();
    let kept = clean_points(&kept, closed);
    if kept.len() < 3 {
        return (pts, Vec::new());
    }
    (kept, found)
}

/// A polyline's cleaned points ([`clean_points`]) without the spikes [`clean_and_split`] leaves
/// out of it, and those spikes (indices into the cleaned points). Checks that look at a curve's
/// shape (its plane) look at it this way, so that a damaged value is named once, as a spike.
pub fn despike(piece: &Polyline) -> (Vec<Vec3>, Vec<Spike>) {
    let pts = clean_points(&piece.points, piece.closed);
    match jump_limit(&pts, piece.closed) {
        Some(limit) => without_spikes(pts, piece.closed, limit),
        None => (pts, Vec::new()),
    }
}

/// What [`clean_and_split`] leaves out of one contour as spikes: how many points, and how far
/// the farthest reaches (mm). The warning line, the report's `per_contour` and the app's
/// Contours panel say it from this.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContourSpikes {
    /// The contour's id (not serialised: the row the summary sits in names it).
    #[serde(skip_serializing)]
    pub id: String,
    pub points: usize,
    pub reach_mm: f64,
}

/// The spikes of a contour's pieces ([`despike`]); None without any.
pub fn contour_spikes(c: &Contour) -> Option<ContourSpikes> {
    let spikes: Vec<Spike> = c.pieces.iter().flat_map(|p| despike(p).1).collect();
    let reach_mm = spikes.iter().map(|s| s.offset).reduce(f64::max)?;
    Some(ContourSpikes {
        id: c.id.clone(),
        points: spikes.iter().map(|s| s.len).sum(),
        reach_mm,
    })
}

/// Cleans a polyline, leaves out its spikes ([`spikes`]) and splits it where consecutive points
/// jump by more than [`JUMP_FACTOR`] x its median spacing. A closed curve with a jump is no longer
/// closed: it is rotated to start after the first jump so that the wrap-around joins its two ends
/// into one piece.
pub fn clean_and_split(piece: &Polyline) -> Vec<Polyline> {
    let pts = clean_points(&piece.points, piece.closed);
    let Some(limit) = jump_limit(&pts, piece.closed) else {
        return if pts.is_empty() {
            Vec::new()
        } else {
            vec![Polyline {
                points: pts,
                closed: false,
            }]
        };
    };
    let pts = without_spikes(pts, piece.closed, limit).0;
    let n = pts.len();
    let segs = if piece.closed { n } else { n.saturating_sub(1) };
    let seg_len = |i: usize| (pts[(i + 1) % n] - pts[i]).norm();
    // The limit of the curve as given: the spikes' own segments barely move a median.
    let jumps: Vec<usize> = (0..segs).filter(|&i| seg_len(i) > limit).collect();
    // Looked up per point: a hostile run with a jump every few points has a hundred thousand.
    let mut is_jump = vec![false; n];
    for &i in &jumps {
        is_jump[i] = true;
    }
    if jumps.is_empty() {
        return vec![Polyline {
            points: pts,
            closed: piece.closed,
        }];
    }
    // Walk the curve from just after the first jump; every further jump starts a new piece.
    let start = if piece.closed { (jumps[0] + 1) % n } else { 0 };
    let mut pieces = Vec::new();
    let mut current: Vec<Vec3> = Vec::new();
    for k in 0..n {
        let i = (start + k) % n;
        current.push(pts[i]);
        let is_last = k + 1 == n;
        if (is_last || is_jump[i]) && !current.is_empty() {
            pieces.push(Polyline {
                points: std::mem::take(&mut current),
                closed: false,
            });
        }
    }
    pieces
}

/// Total length of a polyline (including the closing segment when closed).
pub fn length(points: &[Vec3], closed: bool) -> f64 {
    let open: f64 = points.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    if closed && points.len() > 2 {
        open + (points[0] - points[points.len() - 1]).norm()
    } else {
        open
    }
}

/// Length of all of a contour's pieces (closed ones with their closing segment), mm.
pub fn contour_length(c: &Contour) -> f64 {
    c.pieces.iter().map(|p| length(&p.points, p.closed)).sum()
}

/// Resamples a polyline to `count` points equally spaced by arc length. Closed curves are sampled
/// over their full loop starting at the first point; open curves keep both end points.
pub fn resample_count(points: &[Vec3], closed: bool, count: usize) -> Vec<Vec3> {
    if points.len() < 2 || count == 0 {
        return points.iter().copied().take(count.max(1)).collect();
    }
    let n = points.len();
    let segs = if closed { n } else { n - 1 };
    let mut cum = Vec::with_capacity(segs + 1);
    cum.push(0.0);
    for i in 0..segs {
        let l = (points[(i + 1) % n] - points[i]).norm();
        cum.push(cum[i] + l);
    }
    let total = cum[segs];
    if total <= 0.0 {
        return vec![points[0]; count];
    }
    let denom = if closed {
        count as f64
    } else {
        (count.max(2) - 1) as f64
    };
    let mut out = Vec::with_capacity(count);
    let mut seg = 0usize;
    for k in 0..count {
        let s = total * k as f64 / denom;
        while seg + 1 < segs && cum[seg + 1] < s {
            seg += 1;
        }
        let l = cum[seg + 1] - cum[seg];
        let t = if l > 0.0 {
            ((s - cum[seg]) / l).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(points[seg] + (points[(seg + 1) % n] - points[seg]) * t);
    }
    out
}

/// Resamples to about `spacing` mm between consecutive points (at least 2 points, or 3 when closed).
pub fn resample_spacing(points: &[Vec3], closed: bool, spacing: f64) -> Vec<Vec3> {
    let len = length(points, closed);
    let min = if closed { 3 } else { 2 };
    if points.len() < 2 || spacing.is_nan() || spacing <= 0.0 {
        return points.to_vec();
    }
    // Capped, so that a curve of absurd length (coordinates near 1e308 make it infinite) cannot
    // ask for more memory than exists: a panic (capacity overflow) before this cap.
    let segments = (len / spacing).round().min(MAX_RESAMPLED as f64) as usize;
    let count = if closed { segments } else { segments + 1 };
    resample_count(points, closed, count.max(min))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    #[test]
    fn a_point_thrown_out_of_any_heart_is_a_stray_and_a_lone_point_near_its_curve_is_not() {
        let ring = |n: usize, r: f64| -> Vec<Vec3> {
            (0..n)
                .map(|i| {
                    let t = std::f64::consts::TAU * i as f64 / n as f64;
                    v3(r * t.cos(), r * t.sin(), 0.0)
                })
                .collect()
        };
        // A ring with its 10th point's x damaged to 830 mm, stored as a curve in two pieces: the
        // point alone is the stray. (Within one closed curve it is a spike, `spikes`.)
        let mut damaged = ring(60, 12.0);
        let far = v3(830.0, damaged[10].y, 0.0);
        damaged.remove(10);
        let pieces = vec![
            Polyline {
                points: vec![far],
                closed: false,
            },
            Polyline {
                points: damaged,
                closed: false,
            },
        ];
        let strays = stray_pieces(&pieces);
        assert_eq!(strays.len(), 1);
        assert_eq!(strays[0].0, 0);
        assert!((strays[0].1 - 818.2).abs() < 1.0, "{strays:?}");
        let c = Contour {
            id: "s02".into(),
            surface: None,
            pieces,
            first_line: 2,
        };
        let kept = cleaned_contour(&c).unwrap();
        assert_eq!(kept.pieces.len(), 1);
        assert!(kept.pieces[0].points.iter().all(|p| p.x < 13.0));
        // biv-me's long-axis curves carry a lone first point ~50 mm before the rest: it stays.
        let mut lax: Vec<Vec3> = (0..=100).map(|i| v3(0.0, 0.0, -(i as f64))).collect();
        lax.insert(0, v3(48.0, 0.0, 10.0));
        let pieces = clean_and_split(&Polyline {
            points: lax,
            closed: false,
        });
        assert_eq!(pieces.len(), 2);
        assert!(stray_pieces(&pieces).is_empty());
        // Two points 150 mm out beside a 20 mm ring: within twice nothing, beyond 100 mm: strays.
        let mut two = ring(40, 10.0);
        two.extend([v3(160.0, 0.0, 0.0), v3(161.0, 0.0, 0.0)]);
        let pieces = clean_and_split(&Polyline {
            points: two,
            closed: false,
        });
        let strays = stray_pieces(&pieces);
        assert_eq!(
            strays
                .iter()
                .map(|s| pieces[s.0].points.len())
                .sum::<usize>(),
            2
        );
    }

    /// A damaged value throws a point (or a few rows) out of a closed ring and the next row
    /// comes straight back: the ring stays one closed curve without them, however near the heart
    /// the point lands (90 mm: within reach of a heart, so no stray). Round the loop's start too.
    #[test]
    fn a_point_out_of_its_curve_and_straight_back_is_a_spike_left_out() {
        let ring = circle(60, 12.0);
        for (at, run, to) in [(10, 1, 90.0), (10, 3, 300.0), (0, 1, 830.0), (58, 2, 40.0)] {
            let mut damaged = ring.clone();
            for j in 0..run {
                damaged[(at + j) % 60].x = to + j as f64;
            }
            let piece = Polyline {
                points: damaged,
                closed: true,
            };
            let spikes = despike(&piece).1;
            assert_eq!(spikes.len(), 1, "{at} {run} {spikes:?}");
            assert_eq!((spikes[0].start, spikes[0].len), (at, run));
            assert!(spikes[0].offset > to - 13.0, "{spikes:?}");
            let pieces = clean_and_split(&piece);
            assert_eq!(pieces.len(), 1, "{at} {run}");
            assert!(pieces[0].closed);
            assert_eq!(pieces[0].points.len(), 60 - run);
            assert!(pieces[0].points.iter().all(|p| p.x < 12.1));
        }
        // A run of four is longer than a damaged row or two: split as a curve in pieces.
        let mut four = ring.clone();
        for p in &mut four[10..14] {
            p.x = 90.0;
        }
        let four = Polyline {
            points: four,
            closed: true,
        };
        assert!(despike(&four).1.is_empty());
        assert_eq!(clean_and_split(&four).len(), 2);
    }

    /// What is not a spike: a curve that leaves off and goes on elsewhere (a gap), a lone point
    /// at an open curve's end (biv-me's long-axis curves), and two clumps of points, each the
    /// other's excursion.
    #[test]
    fn a_gap_an_end_point_and_two_clumps_are_no_spikes() {
        let mut gap = circle(40, 20.0);
        gap.drain(5..15);
        let gap = Polyline {
            points: gap,
            closed: true,
        };
        assert!(despike(&gap).1.is_empty());
        let mut lax: Vec<Vec3> = (0..=100).map(|i| v3(0.0, 0.0, -(i as f64))).collect();
        lax.insert(0, v3(48.0, 0.0, 10.0));
        lax.push(v3(48.0, 0.0, -90.0));
        assert!(despike(&Polyline {
            points: lax,
            closed: false
        })
        .1
        .is_empty());
        let clumps: Vec<Vec3> = [0.0, 0.5, 1.0, 50.0, 50.5, 51.0]
            .iter()
            .map(|&x| v3(x, 0.0, 0.0))
            .collect();
        let clumps = Polyline {
            points: clumps,
            closed: true,
        };
        assert!(despike(&clumps).1.is_empty());
        // A hand-clicked crescent: clicks 2 mm apart along its walls, one at its tip 15.5 mm
        // from its neighbours, which lie 8 mm apart (a 30-degree tip): an outline, every point
        // kept (split at its jumps as before).
        let mut tip: Vec<Vec3> = (0..=20).map(|i| v3(f64::from(i) * 2.0, 0.0, 0.0)).collect();
        tip.push(v3(55.0, 4.0, 0.0));
        tip.extend((0..=20).rev().map(|i| v3(f64::from(i) * 2.0, 8.0, 0.0)));
        tip.extend([3.0, 2.0, 1.0].map(|k| v3(0.0, 2.0 * k, 0.0)));
        let tip = Polyline {
            points: tip,
            closed: true,
        };
        assert!(despike(&tip).1.is_empty());
        let kept = clean_and_split(&tip);
        assert_eq!(kept.iter().map(|p| p.points.len()).sum::<usize>(), 46);
        assert_eq!(
            clean_and_split(&clumps)
                .iter()
                .map(|p| p.points.len())
                .sum::<usize>(),
            6
        );
    }

    #[test]
    fn a_run_of_rows_thrown_out_is_a_stray_while_half_a_curve_is_not() {
        let arc = |n: usize, x0: f64| -> Vec<Vec3> {
            (0..n)
                .map(|i| {
                    let t = std::f64::consts::PI * i as f64 / n as f64;
                    v3(x0 + 20.0 * t.cos(), 20.0 * t.sin(), 0.0)
                })
                .collect()
        };
        let split = |points: Vec<Vec3>| {
            clean_and_split(&Polyline {
                points,
                closed: false,
            })
        };
        // Six damaged rows (of 46) 300 mm out, in the middle of the curve: a quarter at most.
        let mut points = arc(20, 0.0);
        points.extend((0..6).map(|i| v3(300.0 + i as f64, 0.0, 0.0)));
        points.extend(arc(20, 0.0).into_iter().map(|p| v3(p.x, -p.y, 0.0)));
        let pieces = split(points);
        let strays = stray_pieces(&pieces);
        assert_eq!(strays.len(), 1, "{strays:?}");
        assert_eq!(pieces[strays[0].0].points.len(), 6);
        assert!((strays[0].1 - 280.0).abs() < 1.0, "{strays:?}");
        // Two halves 300 mm apart: neither is the curve more than the other, both stay.
        let mut points = arc(20, 0.0);
        points.extend(arc(20, 300.0));
        assert!(stray_pieces(&split(points)).is_empty());
    }

    #[test]
    fn resampling_a_curve_of_overflowing_length_is_capped() {
        // Finite coordinates whose distances overflow to infinity (found by scripts/hostile.py).
        let pts = [
            v3(1e308, 1e308, 0.0),
            v3(-1e308, -1e308, 0.0),
            v3(1e308, -1e308, 0.0),
        ];
        let r = resample_spacing(&pts, true, 1.0);
        assert!(r.len() <= MAX_RESAMPLED, "{}", r.len());
        let r = resample_spacing(&[v3(0.0, 0.0, 0.0), v3(1e9, 0.0, 0.0)], false, 1.0);
        assert_eq!(r.len(), MAX_RESAMPLED + 1);
    }

    fn circle(n: usize, r: f64) -> Vec<Vec3> {
        (0..n)
            .map(|i| {
                let a = i as f64 / n as f64 * std::f64::consts::TAU;
                v3(r * a.cos(), r * a.sin(), 0.0)
            })
            .collect()
    }

    #[test]
    fn drops_nan_and_duplicates() {
        let pts = vec![
            v3(0., 0., 0.),
            v3(0., 0., 0.),
            v3(f64::NAN, 0., 0.),
            v3(1., 0., 0.),
            v3(0., 0., 0.),
        ];
        let c = clean_points(&pts, true);
        assert_eq!(c.len(), 2);
    }

    #[test]
    fn splits_closed_curve_with_one_jump_into_one_open_piece() {
        // A circle with a 90-degree arc missing: one big jump.
        let mut pts = circle(40, 20.0);
        pts.drain(5..15);
        let pieces = clean_and_split(&Polyline {
            points: pts.clone(),
            closed: true,
        });
        assert_eq!(pieces.len(), 1);
        assert!(!pieces[0].closed);
        assert_eq!(pieces[0].points.len(), 30);
        assert_eq!(pieces[0].points[0], pts[5]);
    }

    #[test]
    fn splits_open_curve_in_two() {
        let mut pts: Vec<Vec3> = (0..10).map(|i| v3(i as f64, 0., 0.)).collect();
        pts.extend((0..10).map(|i| v3(40.0 + i as f64, 0., 0.)));
        let pieces = clean_and_split(&Polyline {
            points: pts,
            closed: false,
        });
        assert_eq!(pieces.len(), 2);
        assert_eq!(pieces[0].points.len(), 10);
        assert_eq!(pieces[1].points.len(), 10);
    }

    /// A curve in many bits (a jump every third point) splits into every bit; a bit 300 mm out
    /// is still the stray, beside thousands of bits near the curve.
    #[test]
    fn many_jumps_split_into_every_bit_and_a_far_bit_is_the_stray() {
        let pts: Vec<Vec3> = (0..30_000)
            .map(|i| v3(f64::from(i / 3) * 20.0 + f64::from(i % 3) * 0.5, 0.0, 0.0))
            .collect();
        let pieces = clean_and_split(&Polyline {
            points: pts,
            closed: false,
        });
        assert_eq!(pieces.len(), 10_000);
        assert!(pieces.iter().all(|p| p.points.len() == 3));
        // Two thousand bits beside a long curve (within 5 mm of it), and one 300 mm out.
        let mut with_big: Vec<Polyline> = (0..2000)
            .map(|b| Polyline {
                points: (0..3)
                    .map(|k| v3(f64::from(b % 90) + 0.2 * f64::from(k), 0.0, 0.0))
                    .collect(),
                closed: false,
            })
            .collect();
        with_big.push(Polyline {
            points: (0..9000)
                .map(|i| v3(f64::from(i) * 0.01, 5.0, 0.0))
                .collect(),
            closed: false,
        });
        with_big.push(Polyline {
            points: vec![v3(0.0, 300.0, 0.0)],
            closed: false,
        });
        let strays = stray_pieces(&with_big);
        assert_eq!(strays.len(), 1, "{strays:?}");
        assert_eq!(strays[0].0, 2001);
    }

    #[test]
    fn resampling_is_equally_spaced() {
        let pts = circle(7, 10.0);
        let r = resample_count(&pts, true, 50);
        assert_eq!(r.len(), 50);
        let d: Vec<f64> = (0..50).map(|i| (r[(i + 1) % 50] - r[i]).norm()).collect();
        let (lo, hi) = d
            .iter()
            .fold((f64::MAX, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
        assert!(hi - lo < 0.35, "{lo} {hi}");
        let s = resample_spacing(&pts, true, 1.0);
        assert!((s.len() as f64 - length(&pts, true)).abs() <= 1.0);
    }
}
