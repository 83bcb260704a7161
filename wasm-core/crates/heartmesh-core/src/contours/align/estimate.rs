//! The joint estimate of every group's in-plane shift (docs/VALIDATION.md, sessions 8 and 9).
//!
//! Where a long-axis curve crosses a short-axis plane it must meet that slice's curve of the same
//! surface, and the other way round. Each round, every group measures the mean in-plane residual
//! from the other kind's crossings of its plane to its own curves and moves half of it (the other
//! half is the other group's to move: both are misaligned). Slices and views are estimated
//! together; moving only the slices onto fixed views was worse (session 8), because the views are
//! misaligned too.

use super::groups::{Group, Piece};
use crate::geometry::Vec3;

/// A group needs this many matched crossings to move: fewer cannot tell a shift from a bad match.
pub(super) const MIN_CROSSINGS: usize = 2;

/// Rounds at most. Each round halves the disagreement between two groups; 100 rounds leave
/// nothing of any realistic shift even when many groups share the correction.
const MAX_ROUNDS: usize = 100;

/// Rounds stop once no group's shift changes by more than this (mm): far below the contours'
/// own precision (~1 mm pixels).
const CONVERGED_MM: f64 = 1e-3;

/// Residuals larger than this fraction of the ventricle's ring radius are ignored: a crossing
/// farther than half a radius from its own surface's curve may be nearer the opposite wall, so
/// the match says nothing about the shift (a wrong curve, or no curve of that surface there).
const RESIDUAL_CAP_OF_RADIUS: f64 = 0.5;

/// No shift beyond this fraction of the ring radius: breath-hold errors are a few mm, a small
/// part of the ventricle; larger corrections would come from bad matches, not from breathing.
const SHIFT_CAP_OF_RADIUS: f64 = 0.4;

/// The estimate: per group its shift (mm, in its plane) and its matched crossings at the start.
#[derive(Debug, Clone)]
pub(super) struct Estimate {
    pub shifts: Vec<Vec3>,
    pub crossings: Vec<usize>,
    pub rounds: usize,
    /// Mean in-plane distance of matched crossings to their curves, before and after (mm; 0 when
    /// nothing matched).
    pub before_mm: f64,
    pub after_mm: f64,
}

/// One group's residuals in one round.
#[derive(Debug, Clone, Copy, Default)]
struct Residual {
    sum: Vec3,
    count: usize,
    /// Sum of the residuals' lengths.
    length: f64,
}

/// Estimates the shifts of `groups`; `scale_mm` is the ring radius the caps are relative to.
pub(super) fn estimate(groups: &[Group], scale_mm: f64) -> Estimate {
    let g = groups.len();
    let residual_cap = RESIDUAL_CAP_OF_RADIUS * scale_mm;
    let shift_cap = SHIFT_CAP_OF_RADIUS * scale_mm;
    let mut t = vec![Vec3::zeros(); g];
    let start = residuals(groups, &t, residual_cap);
    let crossings: Vec<usize> = start.iter().map(|r| r.count).collect();
    let active: Vec<bool> = crossings.iter().map(|&c| c >= MIN_CROSSINGS).collect();
    let n_active = active.iter().filter(|&&a| a).count();
    let mut rounds = 0;
    let mut current = start.clone();
    if n_active > 0 && residual_cap.is_finite() && residual_cap > 0.0 {
        for round in 1..=MAX_ROUNDS {
            let mut next = t.clone();
            for k in 0..g {
                let r = &current[k];
                if active[k] && r.count >= MIN_CROSSINGS {
                    next[k] += r.sum * (0.5 / r.count as f64);
                }
            }
            // The gauge: moving everything together changes no residual, so the mean shift of
            // the moving groups is removed; each shift then goes back into its plane, capped.
            let mean = (0..g)
                .filter(|&k| active[k])
                .fold(Vec3::zeros(), |s, k| s + next[k])
                / n_active as f64;
            let mut change = 0.0f64;
            for k in (0..g).filter(|&k| active[k]) {
                let mut w = groups[k].in_plane(&(next[k] - mean));
                let len = w.norm();
                if len > shift_cap {
                    w *= shift_cap / len;
                }
                change = change.max((w - t[k]).norm());
                next[k] = w;
            }
            t = next;
            rounds = round;
            current = residuals(groups, &t, residual_cap);
            if change < CONVERGED_MM {
                break;
            }
        }
    }
    let mean_length = |rs: &[Residual]| {
        let (l, n) = rs
            .iter()
            .fold((0.0, 0usize), |(l, n), r| (l + r.length, n + r.count));
        if n > 0 {
            l / n as f64
        } else {
            0.0
        }
    };
    Estimate {
        before_mm: mean_length(&start),
        after_mm: mean_length(&current),
        shifts: t,
        crossings,
        rounds,
    }
}

/// Every group's residuals with the groups shifted by `t`.
fn residuals(groups: &[Group], t: &[Vec3], cap: f64) -> Vec<Residual> {
    let mut out = vec![Residual::default(); groups.len()];
    for (a, ga) in groups.iter().enumerate() {
        let n = ga.normal;
        let c = ga.centroid;
        let r = &mut out[a];
        for (b, gb) in groups.iter().enumerate() {
            if gb.kind == ga.kind || b == a {
                continue;
            }
            // Group b's curves, shifted by t[b], are offset by t[b].n along a's normal.
            let offset = (t[b] - t[a]).dot(&n);
            for piece in &gb.pieces {
                for x in plane_crossings(piece, &c, &n, offset) {
                    // The crossing relative to a's unshifted curves (a's shift moved them by t[a];
                    // `offset` already took t[a] out along the normal).
                    let x = x + t[b] - t[a];
                    let x = x - n * (x - c).dot(&n);
                    if let Some(d) = residual_to(ga, piece.surface, &x, &n, cap) {
                        r.sum += d;
                        r.count += 1;
                        r.length += d.norm();
                    }
                }
            }
        }
    }
    out
}

/// Points where `piece` (its points moved by `offset` along `n`) crosses the plane (c, n), on the
/// unshifted piece.
fn plane_crossings<'a>(
    piece: &'a Piece,
    c: &'a Vec3,
    n: &'a Vec3,
    offset: f64,
) -> impl Iterator<Item = Vec3> + 'a {
    let m = piece.points.len();
    let segments = if piece.closed && m > 2 {
        m
    } else {
        m.saturating_sub(1)
    };
    (0..segments).filter_map(move |i| {
        let p = piece.points[i];
        let q = piece.points[(i + 1) % m];
        let dp = (p - c).dot(n) + offset;
        let dq = (q - c).dot(n) + offset;
        // Half-open on one side so that a vertex exactly in the plane counts once.
        ((dp < 0.0) != (dq < 0.0) && dp != dq).then(|| p + (q - p) * (dp / (dp - dq)))
    })
}

/// In-plane vector from the nearest point of the group's curves of `surface` to `x`, if one is
/// within `cap` and is not the end of an open curve (a crossing beyond a curve's end, e.g. past a
/// crescent's tip, does not say where the curve is).
fn residual_to(g: &Group, surface: u32, x: &Vec3, n: &Vec3, cap: f64) -> Option<Vec3> {
    let mut best: Option<(f64, Vec3, bool)> = None;
    for piece in g.pieces.iter().filter(|p| p.surface == surface) {
        let bound = best.map_or(cap * cap, |b| b.0);
        if box_distance_sq(x, &piece.lo, &piece.hi) > bound {
            continue;
        }
        if let Some((d2, q, at_end)) = closest_on_piece(piece, x) {
            if d2 <= bound && best.is_none_or(|b| d2 < b.0) {
                best = Some((d2, q, at_end));
            }
        }
    }
    let (_, q, at_end) = best?;
    if at_end {
        return None;
    }
    let r = x - q;
    let r = r - n * r.dot(n);
    (r.norm() <= cap).then_some(r)
}

fn box_distance_sq(x: &Vec3, lo: &Vec3, hi: &Vec3) -> f64 {
    (0..3)
        .map(|k| {
            let d = (lo[k] - x[k]).max(x[k] - hi[k]).max(0.0);
            d * d
        })
        .sum()
}

/// Squared distance, nearest point, and whether that point is an end of an open piece.
fn closest_on_piece(piece: &Piece, x: &Vec3) -> Option<(f64, Vec3, bool)> {
    let pts = &piece.points;
    let m = pts.len();
    if m == 1 {
        return Some(((x - pts[0]).norm_squared(), pts[0], !piece.closed));
    }
    let segments = if piece.closed && m > 2 { m } else { m - 1 };
    let mut best: Option<(f64, Vec3, bool)> = None;
    for i in 0..segments {
        let a = pts[i];
        let ab = pts[(i + 1) % m] - a;
        let l2 = ab.norm_squared();
        let s = if l2 > 0.0 {
            ((x - a).dot(&ab) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = a + ab * s;
        let d2 = (x - q).norm_squared();
        if best.is_none_or(|b| d2 < b.0) {
            let at_end = !piece.closed && ((i == 0 && s == 0.0) || (i + 1 == m - 1 && s == 1.0));
            best = Some((d2, q, at_end));
        }
    }
    best
}
