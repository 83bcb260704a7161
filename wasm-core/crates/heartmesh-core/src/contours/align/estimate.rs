//! The joint estimate of every group's in-plane shift (docs/VALIDATION.md, sessions 8 and 9).
//!
//! Where a long-axis curve crosses a short-axis plane it must meet that slice's curve of the same
//! surface, and the other way round. Each round, every group takes half of a damped Gauss-Newton
//! step towards agreeing with the other kind's crossings of its plane (the other half of a
//! disagreement is the other group's to move: both are misaligned), and the short-axis stack's
//! mean shift is removed. Slices and views are estimated together; moving only the slices onto
//! fixed views was worse (session 8), because the views are misaligned too.

use super::groups::{Group, Piece, CHUNK};
use super::through::{self, Through};
use crate::contours::ContourKind;
use crate::geometry::Vec3;
use nalgebra::{Matrix2, Matrix3, Vector2};

/// A group needs this many matched crossings with a closed ring on either side to move: fewer
/// cannot tell a shift from a bad match. Crossings between open curves only (an RV crescent
/// against an RV-only view) still count once a group moves, but cannot move one on their own:
/// where an open curve ends, or which of its sides a crossing belongs to, is far less certain
/// than for the LV's rings (aligning an RV on its own made real RVs worse, session 8).
const MIN_CROSSINGS: usize = 2;

/// Rounds at most. Shifts the crossings determine settle within about 20 rounds (each round
/// moves a group half way towards agreeing with the others); the rest only slides slowly along
/// directions the crossings barely see (see [`DAMPING`]).
const MAX_ROUNDS: usize = 50;

/// Rounds stop once no group's shift changes by more than this (mm), or differs by no more than
/// this from two rounds before (real contours can leave a crossing switching between two curve
/// segments, a cycle of a few hundredths of a mm): a hundredth of a ~1 mm pixel.
const CONVERGED_MM: f64 = 0.01;

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
    /// Whether each group could move (enough crossings with a ring, [`MIN_CROSSINGS`]).
    pub moving: Vec<bool>,
    pub rounds: usize,
    /// Mean in-plane distance of matched crossings to their curves, before and after (mm; 0 when
    /// nothing matched).
    pub before_mm: f64,
    pub after_mm: f64,
    /// Per group, the weighted normal matrix of its shift from the crossings at the start
    /// (`information::Information` splits it along and across the axis).
    pub normal_matrices: Vec<Matrix3<f64>>,
    /// Per group, the information on its through-plane offset at the start (weighted crossings;
    /// 0 for a view).
    pub through_information: Vec<f64>,
}

/// Damping of each group's Gauss-Newton step, in crossings: each crossing says how far its curve
/// lies off along the curve's normal (one direction); the damping adds this much "crossing" in
/// every direction, against moving at all in one round. Where the crossings determine a shift the
/// step is nearly the full Gauss-Newton step; where they leave a direction nearly undetermined
/// (a long-axis view sliding along the axis past straight walls, where contour noise alone would
/// set the shift) the group moves slowly that way. The fixed point is unchanged (no bias).
const DAMPING: f64 = 1.0;

/// One group's residuals in one round.
#[derive(Debug, Clone, Copy, Default)]
struct Residual {
    count: usize,
    /// Crossings with a closed ring on either side.
    rings: usize,
    /// Sum of the residuals' lengths.
    length: f64,
    /// Normal equations of the group's shift: sum of n n^T and of n (n . r) over the crossings,
    /// n the unit in-plane normal of the matched curve, r the residual.
    h: Matrix3<f64>,
    b: Vec3,
    /// A slice's through-plane part of the normal equations (zero for a view).
    through: Through,
}

/// Mean length of the matched residuals (mm; 0 when nothing matched).
fn mean_length(rs: &[Residual]) -> f64 {
    let (l, n) = rs
        .iter()
        .fold((0.0, 0usize), |(l, n), r| (l + r.length, n + r.count));
    if n > 0 {
        l / n as f64
    } else {
        0.0
    }
}

/// Estimates the shifts of `groups`; `scale_mm` is the ring radius the caps are relative to.
/// With `through_plane` each short-axis slice also moves along its normal ([`through`]).
pub(super) fn estimate(groups: &[Group], scale_mm: f64, through_plane: bool) -> Estimate {
    let g = groups.len();
    let residual_cap = RESIDUAL_CAP_OF_RADIUS * scale_mm;
    let shift_cap = SHIFT_CAP_OF_RADIUS * scale_mm;
    let through_cap = if through_plane {
        through::cap(groups).min(shift_cap)
    } else {
        0.0
    };
    let mut t = vec![Vec3::zeros(); g];
    let candidates = candidates(groups, (shift_cap + through_cap) * 1.01);
    let start = residuals(groups, &candidates, &t, residual_cap);
    let crossings: Vec<usize> = start.iter().map(|r| r.count).collect();
    let active: Vec<bool> = start.iter().map(|r| r.rings >= MIN_CROSSINGS).collect();
    let n_active = active.iter().filter(|&&a| a).count();
    let mut rounds = 0;
    let mut current = start.clone();
    let mut before = t.clone();
    // Lowest mean residual seen so far (its shifts and residuals; None while it is the latest). A
    // round may raise the residual where the crossings barely determine a direction (a view
    // sliding along a capsule's straight walls went 2.7 mm and raised the residual 0.033 ->
    // 0.074 mm on exact data): the result is the best round, never worse than the start.
    let mut best_mm = mean_length(&start);
    let mut best: Option<(Vec<Vec3>, Vec<Residual>)> = None;
    if n_active > 0 && residual_cap.is_finite() && residual_cap > 0.0 {
        for round in 1..=MAX_ROUNDS {
            let mut next = t.clone();
            for k in 0..g {
                let r = &current[k];
                if active[k] && r.count >= MIN_CROSSINGS {
                    next[k] += if through_cap > 0.0 && groups[k].kind == ContourKind::Sax {
                        through::step(
                            &groups[k],
                            &r.h,
                            &r.b,
                            &r.through,
                            DAMPING,
                            t[k].dot(&groups[k].normal),
                        )
                    } else {
                        step(&groups[k], r)
                    };
                }
            }
            // The gauge: moving every image together across the long axis changes the residuals
            // only to second order (a view through the axis of a round ventricle hardly changes
            // when the heart slides sideways), so nothing pins that drift down. The short-axis
            // stack, on average, stays where it was: the mean shift of its moving slices is
            // removed from every group. Along the axis nothing is removed: views moving along it
            // against the slices is what the apex and the tapering walls measure. With
            // through-plane offsets the stack's mean offset is removed the same way: moving every
            // slice and view together along the axis changes no crossing.
            let sax: Vec<usize> = (0..g)
                .filter(|&k| active[k] && groups[k].kind == ContourKind::Sax)
                .collect();
            let mean =
                sax.iter().fold(Vec3::zeros(), |s, &k| s + next[k]) / sax.len().max(1) as f64;
            let (mut change, mut cycle) = (0.0f64, 0.0f64);
            for k in (0..g).filter(|&k| active[k]) {
                let moved = next[k] - mean;
                let mut w = groups[k].in_plane(&moved);
                let len = w.norm();
                if len > shift_cap {
                    w *= shift_cap / len;
                }
                if through_cap > 0.0 && groups[k].kind == ContourKind::Sax {
                    let n = groups[k].normal;
                    w += n * moved.dot(&n).clamp(-through_cap, through_cap);
                }
                change = change.max((w - t[k]).norm());
                cycle = cycle.max((w - before[k]).norm());
                next[k] = w;
            }
            before = std::mem::replace(&mut t, next);
            rounds = round;
            let previous = std::mem::replace(
                &mut current,
                residuals(groups, &candidates, &t, residual_cap),
            );
            let now_mm = mean_length(&current);
            if now_mm <= best_mm {
                best_mm = now_mm;
                best = None;
            } else if best.is_none() {
                best = Some((before.clone(), previous));
            }
            if change < CONVERGED_MM || cycle < CONVERGED_MM {
                break;
            }
        }
    }
    // The best round, if a later one drifted off it (see the loop).
    if let Some((shifts, residuals)) = best {
        t = shifts;
        current = residuals;
    }
    Estimate {
        before_mm: mean_length(&start),
        after_mm: mean_length(&current),
        shifts: t,
        normal_matrices: start.iter().map(|r| r.h).collect(),
        through_information: start.iter().map(|r| r.through.info).collect(),
        crossings,
        moving: active,
        rounds,
    }
}

/// The mean distance of the matched crossings to their curves with nothing moved (mm; 0 when
/// nothing matched), and how many matched: [`estimate`]'s `before_mm` without the estimate.
pub(super) fn residual_as_given(groups: &[Group], scale_mm: f64) -> (f64, usize) {
    let residual_cap = RESIDUAL_CAP_OF_RADIUS * scale_mm;
    // The estimate's band is wider (shifts may bring curves across a plane); at rest only the
    // segments crossing it count, and a band of 0 keeps exactly those.
    let candidates = candidates(groups, 0.0);
    let rest = residuals(
        groups,
        &candidates,
        &vec![Vec3::zeros(); groups.len()],
        residual_cap,
    );
    (mean_length(&rest), rest.iter().map(|r| r.count).sum())
}

/// Half of the damped Gauss-Newton step of a group's shift (the other half of a disagreement is
/// the other group's to move): in the group's plane, (H + w I) d = b.
fn step(g: &Group, r: &Residual) -> Vec3 {
    let (u, v) = crate::contours::axis::frame_for(&g.normal);
    let hu = r.h * u;
    let hv = r.h * v;
    let a = Matrix2::new(
        u.dot(&hu) + DAMPING,
        u.dot(&hv),
        v.dot(&hu),
        v.dot(&hv) + DAMPING,
    );
    let rhs = Vector2::new(u.dot(&r.b), v.dot(&r.b));
    match a.try_inverse() {
        Some(inv) => {
            let d = inv * rhs;
            (u * d.x + v * d.y) * 0.5
        }
        None => Vec3::zeros(),
    }
}

/// A segment of another group's curve that may cross a group's plane: its ends' signed
/// distances to the plane before any shift.
#[derive(Debug, Clone, Copy)]
struct Candidate {
    group: u32,
    piece: u32,
    segment: u32,
    dp: f64,
    dq: f64,
}

/// Per group, the other kind's segments that can cross its plane under any allowed shifts: the
/// other group's shift moves its curves along this plane's normal by at most `band` mm (the shift
/// cap), so segments entirely farther than that never cross. Computed once; each round then
/// only tests these (the signed distances are the same expressions as a full scan, so the
/// crossings are bit for bit the same).
fn candidates(groups: &[Group], band: f64) -> Vec<Vec<Candidate>> {
    groups
        .iter()
        .enumerate()
        .map(|(a, ga)| {
            let (n, c) = (ga.normal, ga.centroid);
            let mut out = Vec::new();
            for (b, gb) in groups.iter().enumerate() {
                if gb.kind == ga.kind || b == a {
                    continue;
                }
                for (k, piece) in gb.pieces.iter().enumerate() {
                    let m = piece.points.len();
                    let segments = if piece.closed && m > 2 {
                        m
                    } else {
                        m.saturating_sub(1)
                    };
                    for i in 0..segments {
                        let dp = (piece.points[i] - c).dot(&n);
                        let dq = (piece.points[(i + 1) % m] - c).dot(&n);
                        if dp.min(dq) <= band && dp.max(dq) >= -band {
                            out.push(Candidate {
                                group: b as u32,
                                piece: k as u32,
                                segment: i as u32,
                                dp,
                                dq,
                            });
                        }
                    }
                }
            }
            out
        })
        .collect()
}

/// Every group's residuals with the groups shifted by `t`.
fn residuals(
    groups: &[Group],
    candidates: &[Vec<Candidate>],
    t: &[Vec3],
    cap: f64,
) -> Vec<Residual> {
    let mut out = vec![Residual::default(); groups.len()];
    for (a, ga) in groups.iter().enumerate() {
        let n = ga.normal;
        let c = ga.centroid;
        let r = &mut out[a];
        for cand in &candidates[a] {
            let b = cand.group as usize;
            let piece = &groups[b].pieces[cand.piece as usize];
            // Group b's curves, shifted by t[b], are offset by t[b].n along a's normal.
            let offset = (t[b] - t[a]).dot(&n);
            let (dp, dq) = (cand.dp + offset, cand.dq + offset);
            // Half-open on one side so that a vertex exactly in the plane counts once.
            if (dp < 0.0) == (dq < 0.0) || dp == dq {
                continue;
            }
            let i = cand.segment as usize;
            let p = piece.points[i];
            let d = piece.points[(i + 1) % piece.points.len()] - p;
            // Weight: sin^2 of the angle between the curve and the plane. A curve crossing at a
            // shallow angle puts its crossing far off for any error across the planes (a tilt, a
            // shift through the plane, slice thickness): in-plane error ~ that error / tan, so
            // with errors of either kind alike the variance grows as 1 + cot^2 = 1 / sin^2.
            let w = (dp - dq).powi(2) / d.norm_squared();
            // The crossing relative to a's unshifted curves (a's shift moved them by t[a];
            // `offset` already took t[a] out along the normal).
            let x = p + d * (dp / (dp - dq)) + t[b] - t[a];
            let x = x - n * (x - c).dot(&n);
            if let Some((res, normal, ring)) = residual_to(ga, piece.surface, &x, &n, cap) {
                r.count += 1;
                r.rings += usize::from(ring || piece.closed);
                r.length += res.norm();
                r.h += normal * normal.transpose() * w;
                r.b += normal * (normal.dot(&res) * w);
                if ga.kind == ContourKind::Sax {
                    r.through
                        .add(w, &normal, &res, &through::crossing_rate(&d, &n));
                }
            }
        }
    }
    out
}

/// In-plane vector from the nearest point of the group's curves of `surface` to `x`, the curve's
/// unit in-plane normal there and whether the curve is closed, if that point is within `cap` and
/// is not the end of an open curve (a crossing beyond a curve's end, e.g. past a crescent's tip,
/// does not say where the curve is).
fn residual_to(
    g: &Group,
    surface: u32,
    x: &Vec3,
    n: &Vec3,
    cap: f64,
) -> Option<(Vec3, Vec3, bool)> {
    let mut best: Option<(f64, Vec3, bool, Vec3, bool)> = None;
    for piece in g.pieces.iter().filter(|p| p.surface == surface) {
        let bound = best.map_or(cap * cap, |b| b.0);
        if box_distance_sq(x, &piece.lo, &piece.hi) > bound {
            continue;
        }
        if let Some((d2, q, at_end, along)) = closest_on_piece(piece, x, bound) {
            if d2 <= bound && best.is_none_or(|b| d2 < b.0) {
                best = Some((d2, q, at_end, along, piece.closed));
            }
        }
    }
    let (_, q, at_end, along, closed) = best?;
    if at_end {
        return None;
    }
    let r = x - q;
    let r = r - n * r.dot(n);
    let normal = along.cross(n);
    let len = normal.norm();
    (r.norm() <= cap && len > 1e-12).then(|| (r, normal / len, closed))
}

fn box_distance_sq(x: &Vec3, lo: &Vec3, hi: &Vec3) -> f64 {
    (0..3)
        .map(|k| {
            let d = (lo[k] - x[k]).max(x[k] - hi[k]).max(0.0);
            d * d
        })
        .sum()
}

/// Squared distance, nearest point, whether that point is an end of an open piece, and the
/// direction of its segment; None when no segment is within `bound` (squared distance).
fn closest_on_piece(piece: &Piece, x: &Vec3, bound: f64) -> Option<(f64, Vec3, bool, Vec3)> {
    let pts = &piece.points;
    let m = pts.len();
    if m < 2 {
        return None;
    }
    let segments = if piece.closed && m > 2 { m } else { m - 1 };
    let mut best: Option<(f64, Vec3, bool, Vec3)> = None;
    for (c, (lo, hi)) in piece.chunks.iter().enumerate() {
        // Chunks farther than the best so far hold no nearer segment (same answer as a full scan).
        if box_distance_sq(x, lo, hi) > best.map_or(bound, |b| b.0) {
            continue;
        }
        let first = c * CHUNK;
        for i in first..(first + CHUNK).min(segments) {
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
                let at_end =
                    !piece.closed && ((i == 0 && s == 0.0) || (i + 1 == m - 1 && s == 1.0));
                best = Some((d2, q, at_end, ab));
            }
        }
    }
    best
}
