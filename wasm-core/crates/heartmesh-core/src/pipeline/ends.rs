//! End caps: synthetic lid attractors at the ends of the cavity that no curve closes.
//!
//! Where no contour closes an end (the base of almost every file: long-axis curves stop at the
//! valve plane; both ends of an RV without RV long-axis curves; short-axis-only files), nothing
//! holds the mesh there: the attractors are contour points, each remesh's affine shrink correction
//! and the smooth spline carry the unconstrained cap on past the data, by 0.4 ring radii on the
//! phantoms (docs/VALIDATION.md, "Session 9: overrun past the data"). METHOD.md section 2 intends
//! the lid to be where the mesh ends ("without LAX ... mesh ends flat there"), so such an end gets
//! attractor points filling the end ring's outline in the lid's plane: perpendicular to the long
//! axis at the tube's lid, or through the tips of the long-axis curves that stop beyond the ring
//! (the valve plane, [`TipPlane`]). They are sampled at about the real attractors' spacing, kept
//! two spacings in from the rim (the rim is the wall data's, and the wall needs room to turn into
//! the lid: [`RIM_INSET_PER_SPACING`]), on a finer grid where a narrow outline would hold fewer
//! than [`MIN_LID_POINTS`] (`covering_disc`), and pull with a weight below 1 so that real
//! contours win where they disagree, and only from outside: a lid point pulls while the mesh runs
//! on past its plane, never into it (`lid_pull`, the one-sided lid; the disc's grid is `lid_disc`). They are
//! never data: contour distances, per-contour tables, colour maps and the step report ignore them.
//!
//! Per end, from what the long-axis data say ([`end_lid`], session 12): where curves reach the end
//! the lid lies where they stop; where none does (short-axis-only files, an RV without RV views)
//! the apex gets no lid (its dome runs on below the last slice, and the paper's extrapolation
//! follows it better than a flat cut) and the base a ceiling at the next slice position. With
//! `Params::apex_floor` (sessions 13-14; the default since session 14) such an apex gets one floor
//! point instead, at the tip the slices' taper predicts (`dome`), pulling only while the mesh
//! stops short of it (`apex_floor`).
//!
//! Why a flat disc rather than the cone spanned by the ring and the lid point: the lid is above
//! the ring only where long-axis curves run on past the ring along the wall (the LV base, 10-20 mm
//! up to the valve plane); a cone from the basal ring to that height would pull the wall between
//! the long-axis planes inwards, against the data, while the disc at the lid's height caps the
//! wall the curves describe (the tube's extra basal ring, `tube::extend_to_base`, is the same
//! outline).

use super::apex_floor::floor_point;
use super::end_data::EndRing;
pub use super::end_data::{closed_by_data, reached_by_lax};
pub use super::lid_disc::disc_points;
use super::lid_pull::{lid_normal, LidSide, ONE_SIDED_TOLERANCE_PER_SPACING};
use super::lid_tips::{valve_plane, Tip, RIDGE_PER_RADIUS_SQ};
use super::tube::Lids;
use crate::contours::plane::fit_plane;
use crate::contours::{Contour, ContourKind};
use crate::geometry::{centroid, Vec3};
use crate::params::EndCapMode;
use serde::Serialize;

/// Which ends got synthetic lid points, and how many (per attractor resampling: the points are the
/// same at every resampling). All false / 0 when end caps are off.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EndCapsReport {
    pub mode: &'static str,
    pub base: bool,
    pub apex: bool,
    pub points: usize,
    /// Whether the apex got a floor at the slices' taper tip (`apex_floor`; only with
    /// `Params::apex_floor`, and only at an apex no long-axis curve reaches). Left out of the JSON
    /// when false, so a file whose apex a long-axis curve reaches (every real file measured)
    /// reports exactly as before the floor existed; whether the floor was on is the run's
    /// parameters' `apex_floor`.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub apex_floor: bool,
    /// Whether the base lid is the ceiling of a base no long-axis curve reaches
    /// ([`EndLid::OpenBase`]: one slice spacing beyond the basal ring, by design), so the mesh's
    /// part past the top ring is a bound, not data; the app says so instead of flagging the
    /// overrun. Left out of the JSON when false, like `apex_floor`.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub base_ceiling: bool,
    /// Whether the base needed a lid (no contour closes it) but its outline has no room for lid
    /// points two attractor spacings in from its rim (an RV crescent, or any outline at a hundred
    /// attractors or fewer), so the spline carries the base as with end caps off. Reported,
    /// rather than as "no lid needed", because such a base may run on past the data and the
    /// volume with it (biv-me patient 1 ED RV: 218 ml at 100 attractors, 183 ml at the defaults)
    /// until its late rim lid stops it ([`Self::base_rim_lid_at`]), or not (the RV phantom sliced
    /// from the same patient's model: 0-2 mm at the defaults, its long-axis curve holding it);
    /// [`Self::note`] speaks only of an overrun with no rim lid. Left out of the JSON when false.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub base_too_narrow: bool,
    /// The iteration at which such a base got its late rim lid ([`super::rim_lid`]: laid nearer
    /// the rim once the base ran on past the data); `base` and `points` then count it. Left out of
    /// the JSON when none was laid.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub base_rim_lid_at: Option<usize>,
    /// The attractor spacing (mm) the lids were laid at: for the note of a base too narrow.
    #[serde(skip)]
    pub spacing_mm: f64,
}

impl EndCapsReport {
    pub fn none(mode: EndCapMode) -> Self {
        EndCapsReport {
            mode: mode.name(),
            base: false,
            apex: false,
            points: 0,
            apex_floor: false,
            base_ceiling: false,
            base_too_narrow: false,
            base_rim_lid_at: None,
            spacing_mm: 0.0,
        }
    }

    /// A sentence for a base left without a lid for want of room ([`Self::base_too_narrow`])
    /// that runs on more than [`OPEN_BASE_NOTE_MM`] past the data (`past_base_mm`, the run's
    /// `past_data.base_mm`), saying what lays one. None for a base that stops near its data.
    pub fn note(&self, past_base_mm: f64) -> Option<String> {
        let open = self.base_too_narrow && self.base_rim_lid_at.is_none();
        (open && past_base_mm > OPEN_BASE_NOTE_MM).then(|| {
            format!(
                "no contour closes the base, and at this attractor spacing ({:.1} mm) its outline \
                 has no room for lid points, even near its rim: nothing holds the base and it \
                 runs on {:.1} mm past the data; more attractors (or a smaller attractor \
                 spacing) lay a lid",
                self.spacing_mm, past_base_mm
            )
        })
    }
}

/// How far past the data a base left without a lid ([`EndCapsReport::base_too_narrow`]) must
/// run for the run to say so: the app's "Past the data" turns amber at the same 5 mm
/// (`PAST_DATA_NOTE_MM` in web/src/ui/runText.ts), where the end's share of the volume is
/// extrapolated rather than a rim's rounding.
pub const OPEN_BASE_NOTE_MM: f64 = 5.0;

/// Data weight of a lid point (contour points have 1, before conflict softening): enough to hold
/// an end no curve closes, low enough that real contours win where they disagree. Swept on the
/// phantoms and the real files (docs/VALIDATION.md, "Session 10: closing open ends": 1.0 doubles
/// the folded edges on the real files, 0.05 lets the ends run on further; the spline is nearly
/// interpolating, so the weight trades folds against hold rather than setting who wins).
pub const END_CAP_WEIGHT: f64 = 0.3;

/// Lid points stay this many attractor spacings in from the end ring: the rim belongs to the wall
/// data, and the surface needs room to turn from the wall into the lid. At one spacing (session
/// 10) the outermost lid points held the rounded shoulder down at the lid's plane, which pulled
/// the wall in above the basal ring and, the ring being held by its data, pushed it out by ~0.5 mm
/// a third of a slice below it, where the accuracy maxima with caps sat; two spacings leave the
/// shoulder free (docs/VALIDATION.md, "Session 11: the cap-to-wall corner"). The price: the
/// rim's band may rise a little past the data (phantoms: 1.2 -> 2.0 mm median).
pub const RIM_INSET_PER_SPACING: f64 = 2.0;
/// At most this share of the real attractor count per end (a large explicit count asks for ~1 mm
/// spacing: a dense disc would double the spline's size for no gain).
const MAX_POINTS_PER_REAL: f64 = 0.25;

/// A lid of fewer points than this cannot hold its outline: one point, or a short row, holds a
/// spot or a line, and the spline bulges the rest of the lid out past the data. Seven spread
/// both ways across the outline (a grid point with neighbours on every side); it is also the
/// fewest any LV lid of the real files gets at the defaults (7-12), which this leaves as they
/// were. RV bases, crescents too narrow for two pitches of inset on each side, got 1-4 points at
/// the defaults and none below ~150 attractors, so their volumes depended on the attractor count
/// by up to a fifth (docs/VALIDATION.md, "Session 54: lids that hold a crescent").
const MIN_LID_POINTS: usize = 7;

/// Each retry of a lid too sparse for its outline takes this share of the last pitch, and of the
/// inset with it ([`RIM_INSET_PER_SPACING`] pitches) down to two of the attractors' spacings, the
/// rim room the wall's shoulder needs (session 11: at one spacing the lid held the shoulder down
/// and pushed the wall out below the basal ring).
const LID_PITCH_SHRINK: f64 = 0.8;

/// The finest a lid's pitch gets, in the real attractors' spacings: lid points closer together
/// than the wall's attractors would outweigh the data beside them, and an outline too small for
/// a lid at this pitch (the apex ring of a tapering stack, a few mm across) is closed well enough
/// by its wall's own points.
const LID_PITCH_FLOOR_PER_SPACING: f64 = 0.5;

/// Retries at most (0.8^24 is a 200th of the first pitch): a bound for a spacing of 0.
const LID_PITCH_TRIES: usize = 24;

/// The lid's points at `pitch` (inset [`RIM_INSET_PER_SPACING`] pitches from the rim); where the
/// outline is too narrow for that to give [`MIN_LID_POINTS`] (an RV crescent, whose pitch the
/// area cap of `most` has stretched past the attractors' `spacing`), at the coarsest finer pitch
/// that does (or `most`, the end's share of the attractors, if that is fewer), the inset never
/// under [`RIM_INSET_PER_SPACING`] spacings and the pitch never under
/// [`LID_PITCH_FLOOR_PER_SPACING`] of one. Lids that hold enough points at the first pitch are as
/// before; an outline without room inside two spacings of rim (a few dozen attractors in all:
/// spacings of 15 mm and more) still gets none.
fn covering_disc(
    ring: &[Vec3],
    lid: &Vec3,
    axis: &Vec3,
    pitch: f64,
    spacing: f64,
    most: f64,
) -> Vec<Vec3> {
    let wanted = (MIN_LID_POINTS as f64).min(most.floor()).max(1.0) as usize;
    let floor = LID_PITCH_FLOOR_PER_SPACING * spacing;
    let mut p = pitch;
    let mut disc = disc_points(ring, lid, axis, p, RIM_INSET_PER_SPACING * p);
    for _ in 0..LID_PITCH_TRIES {
        if disc.len() >= wanted || p * LID_PITCH_SHRINK < floor {
            break;
        }
        p *= LID_PITCH_SHRINK;
        let inset = RIM_INSET_PER_SPACING * p.max(spacing);
        let finer = disc_points(ring, lid, axis, p, inset);
        if finer.len() >= disc.len() {
            disc = finer;
        }
    }
    disc
}

/// The plane of the tips of the long-axis curves that stop at an end (the valve plane, often tilted
/// against the short-axis planes): heights along the axis as a linear function of the in-plane
/// position. Their least-squares plane, unless some tips lie alone far under the others (an empty
/// band of depth wider than [`SHORT_TIP_PER_SLICE_GAP`] slice spacings under the lowest plane
/// over them: curves that stopped short); then that lowest plane over every tip, so that the lid
/// pulls the wall down nowhere a curve runs on ([`super::lid_tips`], session 16: the least-squares
/// plane tilted towards a curve cut short and dipped up to 17.5 mm under the truth's rim).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TipPlane {
    /// A point of the plane (its height at the ring's centroid).
    pub origin: Vec3,
    /// Height change per mm across the axis (perpendicular to it).
    pub gradient: Vec3,
    /// The floor: heights never fall back inside this plane, the end ring's own plane moved out
    /// by a margin ([`tip_plane`]), so the lid stays beyond the ring.
    floor_origin: Vec3,
    /// The floor plane's unit normal, pointing out of the cavity's end.
    floor_normal: Vec3,
    outward: f64,
}

impl TipPlane {
    pub fn height_at(&self, p: &Vec3, axis: &Vec3) -> f64 {
        self.lid_at(p, axis).0
    }

    /// The lid's height along the axis over `p`'s position across it, and the lid's outward
    /// normal there: the tips' plane, or the floor where that plane falls inside it.
    pub fn lid_at(&self, p: &Vec3, axis: &Vec3) -> (f64, Vec3) {
        let h = self.tips_height(p, axis);
        // Where the line along the axis through p meets the floor plane (the normal is within
        // 60 degrees of the axis: `tip_plane`).
        let floor = p.dot(axis)
            + (self.floor_origin - p).dot(&self.floor_normal) / axis.dot(&self.floor_normal);
        if self.outward * (h - floor) < 0.0 {
            (floor, self.floor_normal)
        } else {
            (h, lid_normal(axis, &self.gradient, self.outward))
        }
    }

    /// The tips' plane's height along the axis over `p`'s position across it (no floor).
    fn tips_height(&self, p: &Vec3, axis: &Vec3) -> f64 {
        let d = p - self.origin;
        let across = d - axis * d.dot(axis);
        self.origin.dot(axis) + self.gradient.dot(&across)
    }

    /// How far (mm along the axis) the tips' plane falls inside the floor at its deepest over
    /// `points` (0 when it stays beyond it).
    fn depth_inside(&self, points: &[Vec3], axis: &Vec3) -> f64 {
        points
            .iter()
            .map(|p| self.outward * (self.lid_at(p, axis).0 - self.tips_height(p, axis)))
            .fold(0.0, f64::max)
    }
}

/// Steepest lid: beyond 45 degrees from the short-axis plane an end is more wall than lid.
const MAX_TIP_GRADIENT: f64 = 1.0;

/// The [`TipPlane`] of the open long-axis curves' endpoints at or beyond `ring` (None without
/// any); `short` (mm) is the widest empty band of depths under the ceiling over them that still
/// reads as one rim. Heights are measured outwards (down the axis at the apex), so "over" means
/// past the data at either end. Its floor is the ring's own plane (tilted with the slice) moved
/// `margin` mm out: a closed short-axis ring is a section through the cavity, so the whole disc
/// it bounds is inside, and a lid that the tips' plane would put at or inside it there (tips
/// lower than the ring: curves drawn short of the slice) would hold the mesh across that disc.
#[allow(clippy::too_many_arguments)]
pub fn tip_plane(
    ring: &[Vec3],
    contours: &[Contour],
    kinds: &[ContourKind],
    axis: &Vec3,
    outward: f64,
    short: f64,
    margin: f64,
) -> Option<TipPlane> {
    let EndRing {
        centre: c,
        radius,
        height: h0,
        tolerance,
    } = EndRing::of(ring, axis)?;
    // Any in-plane basis: the fitted gradient, a vector, does not depend on it.
    let u = axis.cross(&Vec3::new(1.0, 0.0, 0.0));
    let u = if u.norm() > 0.5 {
        u.normalize()
    } else {
        axis.cross(&Vec3::new(0.0, 1.0, 0.0)).normalize()
    };
    let v = axis.cross(&u);
    let mut tips: Vec<Tip> = contours
        .iter()
        .zip(kinds)
        .filter(|(_, k)| **k == ContourKind::Lax)
        .flat_map(|(c, _)| &c.pieces)
        .filter(|piece| !piece.closed)
        .flat_map(|piece| [piece.points.first(), piece.points.last()])
        .flatten()
        .filter(|p| outward * (p.dot(axis) - h0) >= -tolerance)
        .map(|p| {
            let d = p - c;
            Tip {
                x: d.dot(&u),
                y: d.dot(&v),
                h: outward * p.dot(axis),
            }
        })
        .collect();
    // In an order of their own, so the fit's sums do not depend on the file's order of curves.
    tips.sort_by(|a, b| {
        a.h.total_cmp(&b.h)
            .then(a.x.total_cmp(&b.x))
            .then(a.y.total_cmp(&b.y))
    });
    let plane = valve_plane(
        &tips,
        short,
        RIDGE_PER_RADIUS_SQ * radius * radius,
        MAX_TIP_GRADIENT,
    )?;
    let out = axis * outward;
    // The ring's fitted plane; a ring more than 60 degrees off the axis (no short-axis slice)
    // or too degenerate to fit gets the plane across the axis at its centroid.
    let floor_normal = fit_plane(ring.iter())
        .map(|f| f.normal * f.normal.dot(&out).signum())
        .filter(|n| n.dot(&out) >= 0.5)
        .unwrap_or(out);
    let mut tip_plane = TipPlane {
        origin: c + axis * (outward * plane.a - h0),
        gradient: (u * plane.gx + v * plane.gy) * outward,
        floor_origin: c,
        floor_normal,
        outward,
    };
    // Tips at the ring (curves that end at the slice: the cavity ends there) keep the lid in the
    // ring's plane; only a tips' plane that cuts into the disc moves the floor out.
    if tip_plane.depth_inside(ring, axis) > margin {
        tip_plane.floor_origin = c + floor_normal * margin;
    }
    Some(tip_plane)
}

/// Long-axis tips whose depths under the ceiling over them ([`super::lid_tips::valve_plane`])
/// leave an empty band wider than this many slice spacings end curves that stopped short: the
/// stack resolves the cavity along the axis to a slice spacing, the same scale as the ceiling of
/// a base no curve reaches ([`OPEN_BASE_PER_SLICE_GAP`]). Measured (docs/VALIDATION.md, "Session
/// 16"): complete curves on the simulated shapes leave no such band (the spasm shapes' irregular
/// rims spread their tips 0-15 mm under the ceiling with 10 mm slices), so their lids are as
/// before.
pub const SHORT_TIP_PER_SLICE_GAP: f64 = 1.0;

/// Where the lid of an end no curve closes goes, from what the long-axis data say about it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EndLid {
    /// Long-axis curves reach the end (tips beyond the ring, or points past it): the lid lies
    /// where they stop, through their tips ([`TipPlane`]) or flat at the tube's lid (their
    /// farthest point).
    Reached,
    /// An apex no long-axis curve reaches: no lid points. The true apex runs on below the lowest
    /// slice, rounding to a tip; a flat lid at the slice cut that dome off
    /// (docs/VALIDATION.md, "Session 11: the cap-to-wall corner", lead's decision: CAP LV epi
    /// truth->mesh max 0.82 -> 6.32 mm), while the paper's extrapolation came close there.
    OpenApex,
    /// A base no long-axis curve reaches: a flat lid this far (mm) beyond the basal ring's plane.
    OpenBase(f64),
}

/// A short-axis stack is planned to cover the cavity, so where no long-axis curve reaches the base
/// the cavity stops before the next slice position (one slice spacing beyond the basal ring), or
/// that slice would have been drawn. The lid is one-sided, a ceiling that stops the mesh running on
/// and never pulls it out to the plane ([`super::lid_pull`]), so it goes at that bound, not at an
/// estimate of where the base is: below the bound the paper's extrapolation decides, as with caps
/// off. Scale-free: a share of the data's own spacing. Measured (docs/VALIDATION.md, "Session 12:
/// end caps where no long-axis curve reaches"): the true base lies 0.55-2.3 spacings (median 0.9)
/// past the basal slice in the simulated population and the long-axis tips 1.25-1.8 spacings past
/// it on the real LV files (the bound is optimistic), so the ceiling binds only where the
/// extrapolation ran on past the next slice position, and lids nearer the ring (half a spacing,
/// just outside the plane) cut the base shorter still and lost clipped accuracy. A lid at the
/// ring's own plane (session 11) settled a fraction of a mm inside it, where the paper's clipped
/// comparison keeps it (mesh->truth maxima of 18-26 mm).
pub const OPEN_BASE_PER_SLICE_GAP: f64 = 1.0;

/// The rule for one end of the short-axis `rings` (apex to base; `outward` +1: the base, the last
/// ring; -1: the apex, the first), `None` when data close it. `tolerance` (mm) is the lid's
/// one-sided tolerance: an open base's lid lies at least two of them out, so that the mesh it holds
/// (within one tolerance of the plane, [`super::lid_pull`]) stays outside the ring's plane even for
/// closely spaced slices.
pub fn end_lid(
    rings: &[Vec<Vec3>],
    contours: &[Contour],
    kinds: &[ContourKind],
    axis: &Vec3,
    outward: f64,
    tolerance: f64,
) -> Option<EndLid> {
    let (ring, next) = end_rings(rings, outward)?;
    if closed_by_data(ring, contours, kinds, axis, outward) {
        return None;
    }
    if reached_by_lax(ring, contours, kinds, axis, outward) {
        return Some(EndLid::Reached);
    }
    if outward < 0.0 {
        return Some(EndLid::OpenApex);
    }
    let gap = slice_gap(ring, next, axis);
    Some(EndLid::OpenBase(
        (OPEN_BASE_PER_SLICE_GAP * gap).max(2.0 * tolerance),
    ))
}

/// The end `ring` and the ring one slice in from it (`outward` as in [`end_lid`]).
fn end_rings(rings: &[Vec<Vec3>], outward: f64) -> Option<(&[Vec3], Option<&[Vec3]>)> {
    if outward > 0.0 {
        let k = rings.len().checked_sub(1)?;
        Some((&rings[k], k.checked_sub(1).map(|j| rings[j].as_slice())))
    } else {
        Some((rings.first()?, rings.get(1).map(|r| r.as_slice())))
    }
}

/// The slice spacing at an end: the distance along the axis between the end ring's centroid and
/// the next ring's (0 with a single ring).
fn slice_gap(ring: &[Vec3], next: Option<&[Vec3]>, axis: &Vec3) -> f64 {
    let height = |r: &[Vec3]| EndRing::of(r, axis).map(|e| e.height);
    match (height(ring), next.and_then(height)) {
        (Some(a), Some(b)) if (a - b).is_finite() => (a - b).abs(),
        _ => 0.0,
    }
}

/// What the lids of a run are laid from: the tube's short-axis `rings` (mm, apex to base, before
/// the basal extension) and `lids`, the curves the mesh is fitted to with their `kinds`, the long
/// `axis` (apex to base), and the real attractors' `spacing` (mm) and count (`real_attractors`).
#[derive(Debug, Clone, Copy)]
pub struct LidInput<'a> {
    pub rings: &'a [Vec<Vec3>],
    pub lids: &'a Lids,
    pub contours: &'a [Contour],
    pub kinds: &'a [ContourKind],
    pub axis: &'a Vec3,
    pub spacing: f64,
    pub real_attractors: usize,
}

/// How far in from its rim a lid's points stay.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RimRoom {
    /// [`RIM_INSET_PER_SPACING`] attractor spacings: the wall's shoulder turns freely into the lid
    /// (`covering_disc`). Every lid laid at the run's start.
    TwoSpacings,
    /// The late rim lid of a base left open ([`super::rim_lid`]): half a spacing's pitch, the
    /// first of [`RELAXED_INSETS_PER_SPACING`] that holds [`MIN_LID_POINTS`] (`relaxed_disc`).
    Relaxed,
}

/// The insets (attractor spacings, widest first) a late rim lid tries: the two spacings' room
/// of [`RIM_INSET_PER_SPACING`] is what an outline without a lid lacked, so the lid gives some
/// of the shoulder's room back for a base that would otherwise run on unheld.
pub const RELAXED_INSETS_PER_SPACING: [f64; 3] = [1.5, 1.0, 0.5];

/// The late rim lid's points: at [`LID_PITCH_FLOOR_PER_SPACING`] of the attractors' `spacing`,
/// at the widest of [`RELAXED_INSETS_PER_SPACING`] that gives `wanted` points (else the
/// narrowest's, which gives the most).
fn relaxed_disc(ring: &[Vec3], lid: &Vec3, axis: &Vec3, spacing: f64, wanted: usize) -> Vec<Vec3> {
    let pitch = LID_PITCH_FLOOR_PER_SPACING * spacing;
    let mut disc = Vec::new();
    for inset in RELAXED_INSETS_PER_SPACING {
        disc = disc_points(ring, lid, axis, pitch, inset * spacing);
        if disc.len() >= wanted {
            break;
        }
    }
    disc
}

/// One end's lid points and their sides, and what kind of lid it is.
struct EndPoints {
    points: Vec<Vec3>,
    sides: Vec<LidSide>,
    /// The base lid is the ceiling of a base no long-axis curve reaches ([`EndLid::OpenBase`]).
    ceiling: bool,
    /// The apex got its floor point instead of a lid.
    floor: bool,
}

/// What the lid of the end `ring` (`outward` as in [`end_lid`]) holds, laid `room` in from its
/// rim; None where the end needs none (data close it, or an open apex without a floor). Empty
/// points where the outline has no room for any.
fn end_points(
    room: RimRoom,
    apex_floor: bool,
    (ring, lid, outward): (&[Vec3], Vec3, f64),
    input: &LidInput,
) -> Option<EndPoints> {
    let LidInput {
        rings,
        contours,
        kinds,
        axis,
        spacing,
        real_attractors,
        ..
    } = *input;
    // Enough spacing that one end holds at most a share of the real attractors.
    let c = centroid(ring);
    let radius = ring.iter().map(|p| (p - c).norm()).sum::<f64>() / ring.len().max(1) as f64;
    let area = std::f64::consts::PI * radius * radius;
    let most = (MAX_POINTS_PER_REAL * real_attractors as f64).max(1.0);
    let pitch = spacing.max((area / most).sqrt());
    let tolerance = ONE_SIDED_TOLERANCE_PER_SPACING * pitch;
    let mut ceiling = false;
    let lid = match end_lid(rings, contours, kinds, axis, outward, tolerance)? {
        EndLid::OpenApex if apex_floor => {
            let (q, side) = floor_point(rings, axis, tolerance, END_CAP_WEIGHT)?;
            return Some(EndPoints {
                points: vec![q],
                sides: vec![side],
                ceiling: false,
                floor: true,
            });
        }
        EndLid::OpenApex => return None,
        EndLid::Reached => lid,
        // The tube's lid of an end no curve reaches lies at the ring's centroid.
        EndLid::OpenBase(out) => {
            ceiling = true;
            c + axis * (outward * out)
        }
    };
    let mut disc = match room {
        RimRoom::TwoSpacings => covering_disc(ring, &lid, axis, pitch, spacing, most),
        RimRoom::Relaxed => {
            let wanted = (MIN_LID_POINTS as f64).min(most.floor()).max(1.0) as usize;
            relaxed_disc(ring, &lid, axis, spacing, wanted)
        }
    };
    // Without a second ring there is no spacing to read a gap against: least squares.
    let short = match end_rings(rings, outward).map(|(r, next)| slice_gap(r, next, axis)) {
        Some(gap) if gap > 0.0 => SHORT_TIP_PER_SLICE_GAP * gap,
        _ => f64::INFINITY,
    };
    // Two tolerances out, as an open base's lid: the mesh a lid holds (within one tolerance of
    // it) then stays outside the ring's plane.
    let plane = tip_plane(ring, contours, kinds, axis, outward, short, 2.0 * tolerance);
    let mut sides = Vec::with_capacity(disc.len());
    for p in &mut disc {
        let mut normal = axis * outward;
        if let Some(plane) = &plane {
            let (h, n) = plane.lid_at(p, axis);
            normal = n;
            *p += axis * (h - p.dot(axis));
        }
        sides.push(LidSide {
            normal,
            tolerance,
            weight: END_CAP_WEIGHT,
        });
    }
    Some(EndPoints {
        points: disc,
        sides,
        ceiling,
        floor: false,
    })
}

/// The lid points of every end that no curve closes (mm), and what was done. Per end ([`end_lid`]): where
/// long-axis curves reach it, the lid lies where they stop; a short-axis-only apex gets none; a
/// short-axis-only base a flat lid one slice spacing out (the next slice position). With
/// `apex_floor`, a short-axis-only apex gets one floor point at the slices' taper tip
/// ([`super::apex_floor`]).
pub fn end_cap_points(
    mode: EndCapMode,
    apex_floor: bool,
    input: &LidInput,
) -> (Vec<Vec3>, Vec<LidSide>, EndCapsReport) {
    let LidInput { rings, lids, .. } = *input;
    let mut report = EndCapsReport::none(mode);
    let mut points = Vec::new();
    let mut sides = Vec::new();
    if mode == EndCapMode::Off {
        return (points, sides, report);
    }
    report.spacing_mm = input.spacing;
    let ends = [
        (rings.first(), lids.apex, -1.0),
        (rings.last(), lids.base, 1.0),
    ];
    for (ring, lid, outward) in ends {
        let (Some(ring), Some(lid)) = (ring, lid) else {
            continue;
        };
        let Some(end) = end_points(
            RimRoom::TwoSpacings,
            apex_floor,
            (ring, lid, outward),
            input,
        ) else {
            continue;
        };
        if end.points.is_empty() {
            // An apex ring too small for a lid is closed by its own wall points; a base is not.
            report.base_too_narrow |= outward > 0.0;
            continue;
        }
        if end.floor {
            report.apex = true;
            report.apex_floor = true;
        } else if outward > 0.0 {
            report.base = true;
            report.base_ceiling = end.ceiling;
        } else {
            report.apex = true;
        }
        points.extend(end.points);
        sides.extend(end.sides);
    }
    report.points = points.len();
    (points, sides, report)
}

/// The base's lid laid [`RimRoom::Relaxed`] in from its rim: the late rim lid of a base whose outline had no room for one two spacings
/// in ([`super::rim_lid`]). Empty where even that leaves none, or the base needs no lid; the flag
/// says whether the lid is a ceiling ([`EndCapsReport::base_ceiling`]).
pub fn relaxed_base_points(input: &LidInput) -> (Vec<Vec3>, Vec<LidSide>, bool) {
    let (Some(ring), Some(lid)) = (input.rings.last(), input.lids.base) else {
        return (Vec::new(), Vec::new(), false);
    };
    match end_points(RimRoom::Relaxed, false, (ring, lid, 1.0), input) {
        Some(end) => (end.points, end.sides, end.ceiling),
        None => (Vec::new(), Vec::new(), false),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    use crate::pipeline::end_data::fixtures::{circle, lax, Z};

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

    /// The lid input of a test: the axis is z.
    fn input<'a>(
        rings: &'a [Vec<Vec3>],
        lids: &'a Lids,
        contours: &'a [Contour],
        kinds: &'a [ContourKind],
        spacing: f64,
        real_attractors: usize,
    ) -> LidInput<'a> {
        LidInput {
            rings,
            lids,
            contours,
            kinds,
            axis: &Z,
            spacing,
            real_attractors,
        }
    }

    /// An annular sector in z = 0, radii 20 and 40 mm, 200 degrees: 10 mm from its middle to
    /// each edge, an RV base's shape.
    fn crescent() -> Vec<Vec3> {
        let arc = |r: f64, from: f64, to: f64| {
            (0..=40).map(move |k| {
                let a = (from + (to - from) * k as f64 / 40.0).to_radians();
                v3(r * a.cos(), r * a.sin(), 0.0)
            })
        };
        arc(40.0, -100.0, 100.0)
            .chain(arc(20.0, 100.0, -100.0))
            .collect()
    }

    /// A crescent (annular sector, radii 20 and 40 mm, 200 degrees: 10 mm deep) with its pitch
    /// stretched to 8 by the count cap, the attractors 4 mm apart: two pitches of inset (16 mm)
    /// leave nothing, so the pitch shrinks (6.4, 5.12: still none) to 4.096, a band of points
    /// along the middle of the crescent, all at least two of those pitches from its edges.
    #[test]
    fn a_crescent_lid_is_made_fine_enough_to_hold_it() {
        let ring = crescent();
        let lid = v3(0.0, 0.0, 3.0);
        assert!(disc_points(&ring, &lid, &Z, 8.0, 16.0).is_empty());
        let pts = covering_disc(&ring, &lid, &Z, 8.0, 4.0, 50.0);
        assert!(pts.len() >= MIN_LID_POINTS, "{} points", pts.len());
        let p = 8.0 * LID_PITCH_SHRINK * LID_PITCH_SHRINK * LID_PITCH_SHRINK; // 4.096
        assert_eq!(pts, disc_points(&ring, &lid, &Z, p, 2.0 * p));
        for q in &pts {
            let r = q.x.hypot(q.y);
            assert!(
                (r - 30.0).abs() <= 10.0 - 2.0 * p + 1e-9,
                "{q:?} at radius {r}"
            );
            assert!((q.z - 3.0).abs() < 1e-12);
        }
        // A round outline with room for its lid keeps it as it was.
        let round = circle(30.0, 0.0, 60);
        let as_was = disc_points(&round, &lid, &Z, 4.0, 8.0);
        assert!(as_was.len() > 50);
        assert_eq!(covering_disc(&round, &lid, &Z, 4.0, 4.0, 50.0), as_was);
        // Never under two spacings of rim: with the attractors 8 mm apart the crescent gets none,
        // nor does an apex ring 3 mm in radius with them 2 mm apart.
        assert!(covering_disc(&ring, &lid, &Z, 8.0, 8.0, 50.0).is_empty());
        assert!(covering_disc(&circle(3.0, 0.0, 20), &lid, &Z, 5.0, 2.0, 50.0).is_empty());
        // Fewer than seven wanted when the end's share of the attractors is smaller.
        let few = covering_disc(&ring, &lid, &Z, 8.0, 4.0, 2.0);
        assert!(!few.is_empty() && few.len() < 100);
        // A spacing of 0 ends too (the tries are bounded), here on a ring of one repeated point.
        assert!(covering_disc(&[v3(1.0, 1.0, 0.0); 5], &lid, &Z, 5.0, 0.0, 50.0).is_empty());
    }

    /// The late rim lid's disc on the crescent above (10 mm from its middle to each edge) with
    /// the attractors 8 mm apart: two spacings of inset leave nothing, nor does 1.5 (12 mm); one
    /// spacing (8 mm) leaves a band 4 mm wide along the middle, filled at half a spacing's pitch.
    #[test]
    fn a_rim_lid_gives_a_narrow_outline_the_room_two_spacings_left_none() {
        let ring = crescent();
        let lid = v3(0.0, 0.0, 3.0);
        assert!(covering_disc(&ring, &lid, &Z, 8.0, 8.0, 50.0).is_empty());
        let pts = relaxed_disc(&ring, &lid, &Z, 8.0, MIN_LID_POINTS);
        assert!(pts.len() >= MIN_LID_POINTS, "{} points", pts.len());
        assert_eq!(pts, disc_points(&ring, &lid, &Z, 4.0, 8.0));
        for q in &pts {
            assert!((q.x.hypot(q.y) - 30.0).abs() <= 2.0 + 1e-9, "{q:?}");
        }
        // Wanting more than the narrowest inset gives: that one, the most there is.
        let most = relaxed_disc(&ring, &lid, &Z, 8.0, 10_000);
        assert_eq!(most, disc_points(&ring, &lid, &Z, 4.0, 4.0));
        assert!(most.len() > pts.len());
        // An outline with no room even half a spacing in: none.
        assert!(relaxed_disc(&circle(3.0, 0.0, 20), &lid, &Z, 8.0, 7).is_empty());
    }

    /// Two curves stopping at the base ring (z = 20): one with ends at 22 (x = 8) and 18 (x = -8),
    /// one with both ends at 20 (y = +-8). The end at 18 lies inside the ring's plane, so three
    /// tips, all within the 5 mm allowed under their ceiling: their least-squares plane, rising
    /// along x through 22 at x = 8 and 20 at y = +-8.
    #[test]
    fn tip_plane_follows_a_tilted_valve_plane() {
        let ring = circle(10.0, 20.0, 40);
        let curves = [
            lax(vec![
                v3(8.0, 0.0, 22.0),
                v3(10.0, 0.0, 10.0),
                v3(-8.0, 0.0, 18.0),
            ]),
            lax(vec![
                v3(0.0, 8.0, 20.0),
                v3(0.0, 10.0, 10.0),
                v3(0.0, -8.0, 20.0),
            ]),
        ];
        let kinds = [ContourKind::Lax; 2];
        let plane = tip_plane(&ring, &curves, &kinds, &Z, 1.0, 5.0, 0.0).unwrap();
        // Normal equations [3 8; 8 64 + r] (a, g) = (62, 176), ridge r = 1e-3 x 10^2 x 3 tips:
        // g = 32 / 128.9 (0.25 without the ridge), a = 2578.6 / 128.9.
        assert!(
            (plane.gradient - v3(32.0 / 128.9, 0.0, 0.0)).norm() < 1e-12,
            "{plane:?}"
        );
        let centre = plane.height_at(&v3(0.0, 0.0, 0.0), &Z);
        assert!((centre - 2578.6 / 128.9).abs() < 1e-9, "{centre}");
        // Allowing no tip under the ceiling (all three are on it): the ceiling through them,
        // 0.25 per mm, 20 at the centre.
        let top = tip_plane(&ring, &curves, &kinds, &Z, 1.0, -1.0, 0.0).unwrap();
        assert!(
            (top.gradient - v3(0.25, 0.0, 0.0)).norm() < 1e-12,
            "{top:?}"
        );
        // Far out along -x the plane would fall inside the ring's plane: floored at 20.
        assert_eq!(plane.height_at(&v3(-30.0, 0.0, 0.0), &Z), 20.0);
        // No open long-axis curve reaching the end: no plane.
        assert!(tip_plane(&circle(10.0, 40.0, 40), &curves, &kinds, &Z, 1.0, 5.0, 0.0).is_none());
    }

    /// Three views at 0, 90 and 45 degrees whose six tips lie 20 mm over a base ring at z = 0,
    /// one of them cut 12 mm short at its x = -10 end: the lid stays flat at 20. Least squares (what
    /// a 15 mm band allows: the short tip's 12 mm is then one rim) put it at 18 in the middle and
    /// 13.5 over the short tip, 6.5 under where the wall goes on.
    #[test]
    fn a_curve_drawn_short_does_not_tilt_the_lid() {
        let ring = circle(12.0, 0.0, 40);
        let view = |deg: f64, low: f64| {
            let (s, c) = deg.to_radians().sin_cos();
            lax(vec![
                v3(10.0 * c, 10.0 * s, 20.0),
                v3(0.0, 0.0, -30.0),
                v3(-10.0 * c, -10.0 * s, 20.0 - low),
            ])
        };
        let curves = [view(0.0, 12.0), view(90.0, 0.0), view(45.0, 0.0)];
        let kinds = [ContourKind::Lax; 3];
        let plane = tip_plane(&ring, &curves, &kinds, &Z, 1.0, 5.0, 0.0).unwrap();
        assert_eq!(plane.gradient, Vec3::zeros());
        assert_eq!(plane.height_at(&v3(-10.0, 0.0, 0.0), &Z), 20.0);
        let fit = tip_plane(&ring, &curves, &kinds, &Z, 1.0, 15.0, 0.0).unwrap();
        assert!((fit.height_at(&v3(0.0, 0.0, 0.0), &Z) - 18.0).abs() < 1e-9);
        // Slope: [300.864 100; 100 300.864] g = (120, 0) (sums of x^2, xy, y^2 plus the ridge
        // 1e-3 x 144 x 6; x dh, y dh): g = (0.4484, -0.1490), 13.52 over the short tip.
        let det = 300.864f64.powi(2) - 100.0f64.powi(2);
        let g = v3(120.0 * 300.864 / det, -120.0 * 100.0 / det, 0.0);
        assert!((fit.gradient - g).norm() < 1e-9, "{fit:?}");
        assert!((fit.height_at(&v3(-10.0, 0.0, 0.0), &Z) - (18.0 - 10.0 * g.x)).abs() < 1e-9);
    }

    /// Tips rising along x from 20.5 (x = -8) to 28 (x = 8) over a ring of radius 10 at z = 20:
    /// their plane falls 0.44 mm inside the ring's plane at x = -10 (curves drawn short of the
    /// slice on that side), so the lid there is floored `margin` out of the ring's plane, and
    /// follows that plane when the slice is tilted; with tips at the ring itself it stays in it.
    #[test]
    fn a_tips_plane_cutting_into_the_ring_is_floored_outside_it() {
        let view = |a: Vec3, b: Vec3| lax(vec![a, v3(0.0, 0.0, -30.0), b]);
        let curves = [
            view(v3(8.0, 0.0, 28.0), v3(-8.0, 0.0, 20.5)),
            view(v3(0.0, 8.0, 24.25), v3(0.0, -8.0, 24.25)),
        ];
        let kinds = [ContourKind::Lax; 2];
        let flat = circle(10.0, 20.0, 40);
        let plane = tip_plane(&flat, &curves, &kinds, &Z, 1.0, 50.0, 0.4).unwrap();
        assert!((plane.height_at(&v3(0.0, 0.0, 0.0), &Z) - 24.25).abs() < 1e-9);
        assert!((plane.height_at(&v3(-10.0, 0.0, 0.0), &Z) - 20.4).abs() < 1e-9);
        let (_, n) = plane.lid_at(&v3(-10.0, 0.0, 0.0), &Z);
        assert!((n - Z).norm() < 1e-12, "{n:?}");
        // The slice tilted 5 degrees about y (higher at -x): the floor is its plane, 0.4 out.
        let t = 5f64.to_radians().tan();
        let tilted: Vec<Vec3> = flat.iter().map(|p| v3(p.x, p.y, 20.0 - t * p.x)).collect();
        let plane = tip_plane(&tilted, &curves, &kinds, &Z, 1.0, 50.0, 0.4).unwrap();
        let floor = 20.0 + 0.4 / 5f64.to_radians().cos() + 10.0 * t;
        let h = plane.height_at(&v3(-10.0, 0.0, 0.0), &Z);
        assert!((h - floor).abs() < 1e-9, "{h} vs {floor}");
        // Tips at the ring (the cavity ends at the slice): the lid is the ring's plane.
        let level = [view(v3(8.0, 0.0, 20.0), v3(-8.0, 0.0, 20.0))];
        let plane = tip_plane(&flat, &level, &kinds[..1], &Z, 1.0, 50.0, 0.4).unwrap();
        assert!((plane.height_at(&v3(-10.0, 0.0, 0.0), &Z) - 20.0).abs() < 1e-9);
    }

    /// Two radius-10 rings 20 mm apart, the apex lid 8 mm below the lower, the base lid at the
    /// upper.
    fn two_rings() -> (Vec<Vec<Vec3>>, Lids) {
        let rings = vec![circle(10.0, 0.0, 40), circle(10.0, 20.0, 40)];
        let lids = Lids {
            apex: Some(v3(0.0, 0.0, -8.0)),
            base: Some(v3(0.0, 0.0, 20.0)),
        };
        (rings, lids)
    }

    #[test]
    fn caps_only_where_no_curve_closes() {
        let (rings, lids) = two_rings();
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
        let caps = |mode, real| {
            end_cap_points(
                mode,
                false,
                &input(&rings, &lids, &contours, &kinds, 2.0, real),
            )
        };
        let (pts, sides, report) = caps(EndCapMode::Auto, 400);
        assert!(report.base && !report.apex);
        // Long-axis curves reach this base: a lid where they stop, not a ceiling.
        assert!(!report.base_ceiling);
        assert_eq!(report.points, pts.len());
        // Pitch 2, inset 2 spacings (4 mm): the grid points (2i, 2j) within radius 6 of the centre
        // (i^2 + j^2 <= 9: 29), less the 4 on the grid axes at radius 6, which point at vertices of
        // the 40-gon and lie 3.988 mm from its edges (9.969 - 6 cos 4.5 deg): 25, at the base.
        assert_eq!(pts.len(), 25);
        assert!(pts.iter().all(|p| (p.z - 20.0).abs() < 1e-12));
        // One side per point: a flat lid facing up the axis, pulling 0.1 x pitch 2 past it.
        assert_eq!(sides.len(), 25);
        assert!(sides.iter().all(|s| s.normal == Z && s.tolerance == 0.2));
        assert!(sides.iter().all(|s| s.weight == END_CAP_WEIGHT));
        // Few real attractors: the pitch grows so one end holds at most a quarter of them
        // (100 x 0.25 = 25 points over pi x 100 mm^2: pitch 3.54, inset 7.09): only the centre
        // is 7.09 mm from the rim (its 4 neighbours, 3.54 out, are 6.4 mm from it). One point
        // holds a spot, not the lid (session 54): the pitch shrinks to 2.84 (inset 5.67), where
        // the centre's 3 x 3 block fits (its corners 4.0 mm out, 5.95 mm from the rim).
        let (few, _, _) = caps(EndCapMode::Auto, 100);
        assert_eq!(few.len(), 9);
        let far = few.iter().map(|p| p.x.hypot(p.y)).fold(0.0, f64::max);
        let pitch = 0.8 * (std::f64::consts::PI * 100.0 / 25.0).sqrt();
        assert!((far - pitch * 2f64.sqrt()).abs() < 0.05, "{far}");
        let (none, _, off) = caps(EndCapMode::Off, 400);
        assert!(none.is_empty());
        assert_eq!(off, EndCapsReport::none(EndCapMode::Off));
        assert_eq!(off.mode, "off");
        // A lid laid: nothing to say.
        assert!(!report.base_too_narrow && report.note(20.0).is_none());
        assert!(!serde_json::to_string(&report)
            .unwrap()
            .contains("too_narrow"));
    }

    /// Attractors 6 mm apart keep lid points 12 mm in from the rim: a radius-10 base has no room
    /// for any, and the report says so (not "no lid needed"); the note, only for a base that then
    /// runs on past the data, names the spacing. The apex, which its long-axis curve reaches, is
    /// closed by its wall's points and is not flagged.
    #[test]
    fn a_base_without_room_for_a_lid_is_reported_open() {
        let (rings, lids) = two_rings();
        let u: Vec<Vec3> = (0..=20)
            .map(|i| {
                v3(
                    -10.0 + i as f64,
                    0.0,
                    20.0 * ((i as f64 - 10.0) / 10.0).powi(2),
                )
            })
            .collect();
        let (contours, kinds) = ([lax(u)], [ContourKind::Lax]);
        let caps = |spacing| {
            end_cap_points(
                EndCapMode::Auto,
                false,
                &input(&rings, &lids, &contours, &kinds, spacing, 100),
            )
        };
        let (pts, _, report) = caps(6.0);
        assert!(pts.is_empty());
        assert!(!report.base && !report.apex && report.base_too_narrow);
        // Said when the base runs on past the data (past 5 mm), with the spacing and the overrun.
        let note = report.note(7.25).unwrap();
        assert!(
            note.contains("(6.0 mm)")
                && note.contains("runs on 7.2 mm past")
                && note.contains("more attractors"),
            "{note}"
        );
        assert!(report.note(OPEN_BASE_NOTE_MM).is_none());
        let json = serde_json::to_value(report).unwrap();
        assert_eq!(json["base_too_narrow"], true);
        assert!(json.get("spacing_mm").is_none());
        assert!(json.get("base_rim_lid_at").is_none());
        // Nearer the rim there is room (the late rim lid's points), each facing out of the base
        // at the lid's weight; once laid, no note.
        let (late, sides, _) =
            relaxed_base_points(&input(&rings, &lids, &contours, &kinds, 6.0, 100));
        assert!(late.len() >= MIN_LID_POINTS, "{}", late.len());
        assert_eq!(sides.len(), late.len());
        assert!(sides
            .iter()
            .all(|s| s.normal.z > 0.99 && s.weight == END_CAP_WEIGHT));
        let laid = EndCapsReport {
            base_rim_lid_at: Some(76),
            ..report
        };
        assert!(laid.note(7.25).is_none());
        assert_eq!(serde_json::to_value(laid).unwrap()["base_rim_lid_at"], 76);
        // At 2 mm the same base gets its lid.
        let (pts, _, report) = caps(2.0);
        assert!(report.base && !pts.is_empty() && !report.base_too_narrow);
    }

    /// Short-axis rings only (radius 10 at z = 0 and z = 20, no long-axis curve): the apex gets no
    /// lid points (the paper's extrapolation), the base a flat lid the 20 mm gap out (z = 40).
    #[test]
    fn short_axis_only_ends() {
        let rings = vec![circle(10.0, 0.0, 40), circle(10.0, 20.0, 40)];
        let lids = Lids {
            apex: Some(v3(0.0, 0.0, 0.0)),
            base: Some(v3(0.0, 0.0, 20.0)),
        };
        assert_eq!(
            end_lid(&rings, &[], &[], &Z, -1.0, 0.2),
            Some(EndLid::OpenApex)
        );
        assert_eq!(
            end_lid(&rings, &[], &[], &Z, 1.0, 0.2),
            Some(EndLid::OpenBase(20.0))
        );
        let (pts, sides, report) = end_cap_points(
            EndCapMode::Auto,
            false,
            &input(&rings, &lids, &[], &[], 2.0, 400),
        );
        assert!(report.base && !report.apex);
        // A ceiling, which the report names (the app does not flag its overrun).
        assert!(report.base_ceiling);
        // The same 25-point disc as a base the curves reach (`caps_only_where_no_curve_closes`),
        // 20 mm higher; flat, facing up the axis, pulling 0.1 x pitch 2 past its plane.
        assert_eq!((pts.len(), sides.len(), report.points), (25, 25, 25));
        assert!(pts.iter().all(|p| (p.z - 40.0).abs() < 1e-12));
        assert!(sides.iter().all(|s| s.normal == Z && s.tolerance == 0.2));
        // Slices 0.3 mm apart: the gap would leave the mesh the lid holds (within one tolerance,
        // 0.2 mm, of it) within 0.1 mm of the ring's plane; the lid goes two tolerances out.
        let close = vec![circle(10.0, 19.7, 40), circle(10.0, 20.0, 40)];
        assert_eq!(
            end_lid(&close, &[], &[], &Z, 1.0, 0.2),
            Some(EndLid::OpenBase(0.4))
        );
        // A single ring (no gap to measure) likewise; no ring: no rule.
        assert_eq!(
            end_lid(&rings[1..], &[], &[], &Z, 1.0, 0.2),
            Some(EndLid::OpenBase(0.4))
        );
        assert_eq!(end_lid(&[], &[], &[], &Z, 1.0, 0.2), None);
    }

    /// Long-axis curves decide per end: one along the wall from z = 2 to z = 18 reaches neither
    /// end of the rings at 0 and 20 (open apex, open base); one running on from the wall 3 mm below
    /// the apical ring reaches the apex without closing it (a lid where it stops) and leaves the
    /// base open; a U through the apex closes the apex.
    #[test]
    fn each_end_by_what_reaches_it() {
        let rings = vec![circle(10.0, 0.0, 40), circle(10.0, 20.0, 40)];
        let kinds = [ContourKind::Lax];
        let short = [lax(vec![v3(10.0, 0.0, 18.0), v3(10.0, 0.0, 2.0)])];
        let rule = |curves: &[Contour], outward| end_lid(&rings, curves, &kinds, &Z, outward, 0.2);
        assert_eq!(rule(&short, -1.0), Some(EndLid::OpenApex));
        assert_eq!(rule(&short, 1.0), Some(EndLid::OpenBase(20.0)));
        let low = [lax(vec![v3(10.0, 0.0, 18.0), v3(9.0, 0.0, -3.0)])];
        assert_eq!(rule(&low, -1.0), Some(EndLid::Reached));
        assert_eq!(rule(&low, 1.0), Some(EndLid::OpenBase(20.0)));
        // The apex lid of the reaching curve: 3 mm below the ring, through its one tip (a flat
        // plane there, up to rounding), the same 25-point disc; the base's, the gap out.
        let lids = Lids {
            apex: Some(v3(0.0, 0.0, -3.0)),
            base: Some(v3(0.0, 0.0, 20.0)),
        };
        let (pts, sides, report) = end_cap_points(
            EndCapMode::Auto,
            false,
            &input(&rings, &lids, &low, &kinds, 2.0, 400),
        );
        assert!(report.apex && report.base && report.base_ceiling);
        let apex: Vec<&Vec3> = pts.iter().filter(|p| p.z < 10.0).collect();
        assert_eq!(apex.len(), 25);
        assert!(apex.iter().all(|p| (p.z + 3.0).abs() < 1e-12));
        assert!(sides[..25].iter().all(|s| (s.normal + Z).norm() < 1e-12));
        assert!(pts[25..].iter().all(|p| (p.z - 40.0).abs() < 1e-12));
        let u: Vec<Vec3> = (0..=20)
            .map(|i| {
                let x = -10.0 + i as f64;
                v3(
                    x,
                    0.0,
                    18.0 * (x / 10.0).powi(2) - 8.0 * (1.0 - (x / 10.0).powi(2)),
                )
            })
            .collect();
        assert_eq!(rule(&[lax(u)], -1.0), None);
    }
}
