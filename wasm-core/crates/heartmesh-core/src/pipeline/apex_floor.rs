//! An apex floor for short-axis-only stacks (`Params::apex_floor`, on by default since session
//! 14; docs/VALIDATION.md, "Session 13: an apex floor from the taper of the slices" and "Session
//! 14: a dome model for the apex floor"; session 17: "the apex floor on RV crescents").
//!
//! With no long-axis curve at the apex (`ends::EndLid::OpenApex`) the mesh's apex is the paper's
//! extrapolation, which session 12 measured short of the truth by 0.3-4.3 mm. The slices say more:
//! the area of the most apical rings against height predicts where the area reaches zero (`dome`:
//! the shallower of the paraboloid through two rings, session 13, and the quadric fitted to up to
//! [`DOME_RINGS`], session 14, which follows an ellipsoidal dome where the paraboloid overshoots
//! it; and, where the rings grow rounder towards the apex as an RV crescent's do, the shallower
//! tip of the same dome on their length, `crescent`, session 17). So one lid point goes there, one-sided the other way round from the base's
//! ceiling: it pulls only while the mesh stops SHORT of the tip's plane (`lid_pull` with the
//! normal pointing back up the axis), never pushes a mesh that already reaches past it.

use super::crescent::{shallower_tip, TaperMeasure};
use super::dome::{paraboloid_depth, DomeFit, Section};
use super::end_data::EndRing;
use super::lid_pull::LidSide;
use crate::contours::rings::signed_area;
use crate::geometry::Vec3;

/// No floor when the two most apical rings' taper puts the tip more than this many slice gaps
/// below the apical ring. Read on the two-ring depth d A1 / (A2 - A1), whatever family then
/// places the tip (session 14: the dome's quadric is never deeper): it grows without bound as the
/// two rings' areas approach each other (a cylinder-like apical segment, a slice cutting the wall
/// obliquely, noise), where the linear-area model says nothing; the truths' apices lay 0.3-1.3 gaps below the apical ring
/// (3.1-13.3 mm at 7-14 mm spacing), so two gaps leave room for every taper seen and refuse the
/// ill-posed ones (the paper's extrapolation decides there, as without the floor).
pub const MAX_DEPTH_PER_SLICE_GAP: f64 = 2.0;

/// No floor unless the rings' area-weighted mean height lies this share of a slice gap above the
/// stack's middle (towards the base): a symmetric stack gives 0 up to rounding, while two rings at
/// the weakest taper the depth guard accepts (A2 = 1.5 A1) give a tenth of a gap.
pub const MIN_AREA_LEAN_PER_GAP: f64 = 0.05;

/// How many of the most apical rings the dome is fitted to (`dome::quadric_depth`, least
/// squares): four, the fewest that over-determine a quadratic (three coefficients). Through three
/// the fit interpolates, so its curvature rests on one second difference, and a breath-hold that
/// moves one slice along its normal (its section then lies up to 2 mm off its drawn height) moves
/// the tip with it; a fourth ring averages that (`dome` test `four_rings_average_a_moved_slice`:
/// 2.70 -> 0.81 mm past). Rings further up the wall are nearer a cylinder than the dome is,
/// which the fit mostly reads as more concavity, a shallower tip: the side on which the
/// one-sided floor costs nothing (the mesh is left to the extrapolation). Not always: where the
/// curvature jumps (a hemisphere on a cylinder) the wall's rings pull the fit deeper (test
/// `capped_cylinder_tip`). Measured on the LV truths sliced short-axis only at 7-14 mm
/// (docs/VALIDATION.md, session 14), four against three: more than 2 mm past the truth in 0 of
/// 48 stacks (three: 2) and 9 of 192 misaligned ones (three: 25); five rings trade that for more
/// stacks short. A stack of three rings gets the interpolating quadric, one of two the paraboloid.
pub const DOME_RINGS: usize = 4;

/// The apical sections of the first `count` of `rings` (apex first) along `axis`: each ring's
/// enclosed area (projected on the axis, about its centroid) at its centroid's height above the
/// apical ring's, measured towards the second ring; cut at the first ring that is not finite or
/// not above the one before (the fit needs rising heights; the two-ring taper of session 13 only
/// the first two). None unless the first two qualify.
pub fn apical_sections(rings: &[Vec<Vec3>], axis: &Vec3, count: usize) -> Option<Vec<Section>> {
    let (e1, e2) = (
        EndRing::of(rings.first()?, axis)?,
        EndRing::of(rings.get(1)?, axis)?,
    );
    let up_sign = (e2.height - e1.height).signum();
    let mut sections: Vec<Section> = Vec::with_capacity(count);
    for r in rings.iter().take(count) {
        let Some(e) = EndRing::of(r, axis) else {
            break;
        };
        let s = Section {
            height: (e.height - e1.height) * up_sign,
            area: ring_area(r, &e.centre, axis),
        };
        let rising = sections.last().is_none_or(|last| s.height > last.height);
        if !(s.height.is_finite() && s.area.is_finite() && rising) {
            break;
        }
        sections.push(s);
    }
    (sections.len() >= 2).then_some(sections)
}

/// A ring's enclosed area projected on `axis`, about its centroid `centre` (mm^2).
fn ring_area(ring: &[Vec3], centre: &Vec3, axis: &Vec3) -> f64 {
    let centred: Vec<Vec3> = ring.iter().map(|p| p - centre).collect();
    signed_area(&centred, axis).abs()
}

/// The apex predicted from the taper of the most apical `rings` (apex first) along `axis`
/// (pointing from apex to base): the dome fitted to up to [`DOME_RINGS`] of them (`dome`: the
/// shallower of the paraboloid through two rings and the quadric of area on height; `crescent`:
/// the shallower of that and the same dome on the rings' length times the square root of their
/// area, which differs only where the rings change shape towards the apex), at the
/// apical ring's centroid moved along the axis (its in-plane position: an extrapolated centroid
/// line would carry a misaligned slice's shift twice as far). None when the rings do not taper
/// towards the apex (A2 <= A1), the gap is zero, the tip lies more than
/// [`MAX_DEPTH_PER_SLICE_GAP`] gaps below the apical ring, or the stack is not wider towards its
/// base ([`MIN_AREA_LEAN_PER_GAP`]: which end is the apex is then a guess).
pub fn taper_tip(rings: &[Vec<Vec3>], axis: &Vec3) -> Option<Vec3> {
    taper(rings, axis).map(|t| t.tip)
}

/// A predicted apex: where, the unit vector up the axis from it (towards the second ring), which
/// dome family gave it and on which measure of the rings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Taper {
    pub tip: Vec3,
    pub up: Vec3,
    pub fit: DomeFit,
    pub measure: TaperMeasure,
}

/// [`taper_tip`] with its direction, dome family and measure.
pub fn taper(rings: &[Vec<Vec3>], axis: &Vec3) -> Option<Taper> {
    let sections = apical_sections(rings, axis, DOME_RINGS)?;
    let (first, second) = (rings.first()?, rings.get(1)?);
    let (e1, e2) = (EndRing::of(first, axis)?, EndRing::of(second, axis)?);
    let gap = sections.get(1)?.height;
    if gap <= 0.0 {
        return None;
    }
    // The stack's area-weighted mean height above its middle: a cavity that tapers to an apex is
    // wider towards its base, which backs the layout's apex-to-base order. Where the stack is
    // symmetric (a sphere cut past its equator) which end is the apex is the layout's guess
    // (`contours::axis` decides by the slope of radius on height, a coin toss there), and a floor
    // pulls out the wrong end (phantom sphere-sax-only: 13 mm past its open top). Not "the apical
    // ring is the narrowest": an RV sliced up into its outflow narrows again at the base (biv-me
    // patient 1: the basal ring has 0.44 of the apical one's area) and its apex is still the apex.
    // The margin, [`MIN_AREA_LEAN_PER_GAP`], is far above rounding.
    let up_sign = (e2.height - e1.height).signum();
    let (mut sum_a, mut sum_ah) = (0.0, 0.0);
    for r in rings {
        let e = EndRing::of(r, axis)?;
        let a = ring_area(r, &e.centre, axis);
        sum_a += a;
        sum_ah += a * (e.height - e1.height) * up_sign;
    }
    let last = EndRing::of(rings.last()?, axis)?;
    let half = 0.5 * (last.height - e1.height) * up_sign;
    let lean = sum_ah / sum_a - half;
    if lean.is_nan() || lean <= MIN_AREA_LEAN_PER_GAP * gap {
        return None;
    }
    // The guard reads the two rings' taper, whichever family then places the tip (the quadric's
    // is never deeper): a taper too weak to say anything stays refused.
    let line = paraboloid_depth(sections.first()?, sections.get(1)?)?;
    if !line.is_finite() || line > MAX_DEPTH_PER_SLICE_GAP * gap {
        return None;
    }
    let (depth, fit, measure) = shallower_tip(&sections, rings, axis)?;
    // Below the apical ring: against the direction from it towards the second ring.
    let up = if e2.height >= e1.height { *axis } else { -axis };
    Some(Taper {
        tip: e1.centre - up * depth,
        up,
        fit,
        measure,
    })
}

/// The floor's lid point and its side: pulls with `weight` while its closest mesh point lies more
/// than `tolerance` above the tip's plane (the normal points up the axis, into the cavity).
pub fn floor_point(
    rings: &[Vec<Vec3>],
    axis: &Vec3,
    tolerance: f64,
    weight: f64,
) -> Option<(Vec3, LidSide)> {
    let Taper { tip, up, .. } = taper(rings, axis)?;
    Some((
        tip,
        LidSide {
            normal: up,
            tolerance,
            weight,
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;
    use crate::pipeline::end_data::fixtures::{circle, Z};
    use crate::pipeline::lid_pull::past_lid;

    /// Rings of radius 5 at z = 0 and radius 10 at z = 10 (areas in the ratio 1 : 4, up to the
    /// same polygon factor): the tip lies 10 x 1 / (4 - 1) = 3.333 mm below the apical ring.
    #[test]
    fn tip_from_two_discs() {
        let rings = vec![circle(5.0, 0.0, 64), circle(10.0, 10.0, 64)];
        let tip = taper_tip(&rings, &Z).unwrap();
        assert!((tip - v3(0.0, 0.0, -10.0 / 3.0)).norm() < 1e-9, "{tip:?}");
        // The same rings with the axis the other way (apex at the top): the tip above z = 0.
        let flipped = vec![circle(5.0, 0.0, 64), circle(10.0, -10.0, 64)];
        let tip = taper_tip(&flipped, &Z).unwrap();
        assert!((tip - v3(0.0, 0.0, 10.0 / 3.0)).norm() < 1e-9, "{tip:?}");
        // The floor point there pulls a mesh stopping 1 mm short of it (above), not one reaching
        // 1 mm past it (below).
        let (q, side) = floor_point(&rings, &Z, 0.2, 0.3).unwrap();
        assert_eq!(side.normal, Z);
        assert_eq!((side.tolerance, side.weight), (0.2, 0.3));
        assert!(past_lid(&q, &(q + Z), &side));
        assert!(!past_lid(&q, &(q - Z), &side));
    }

    /// No floor where the model says nothing: equal rings (no taper), a widening apex, one ring,
    /// rings at one height, and a taper so slight that the tip would lie over two gaps down
    /// (radius 9 then 10: 10 x 81 / 19 = 42.6 mm, over 20); radius 8 then 10 (17.8 mm) is kept.
    #[test]
    fn guard_refuses_ill_posed_tapers() {
        let r = |a: f64, b: f64| vec![circle(a, 0.0, 64), circle(b, 10.0, 64)];
        assert_eq!(taper_tip(&r(10.0, 10.0), &Z), None);
        assert_eq!(taper_tip(&r(10.0, 8.0), &Z), None);
        assert_eq!(taper_tip(&r(9.0, 10.0), &Z), None);
        let kept = taper_tip(&r(8.0, 10.0), &Z).unwrap();
        assert!((kept.z + 10.0 * 64.0 / 36.0).abs() < 1e-9, "{kept:?}");
        assert_eq!(taper_tip(&r(5.0, 10.0)[..1], &Z), None);
        let flat = vec![circle(5.0, 0.0, 64), circle(10.0, 0.0, 64)];
        assert_eq!(taper_tip(&flat, &Z), None);
        assert_eq!(floor_point(&r(10.0, 10.0), &Z, 0.2, 0.3), None);
        // A symmetric stack (a sphere cut past its equator: radii 5, 10, 12, 10, 5 at z = 0 ..
        // 40): which end is the apex is a guess, no floor; one wider towards the base that
        // narrows again there (an RV into its outflow: 5, 10, 12, 14, 4): the floor is back, at
        // the two-ring paraboloid's tip (the quadric fitted to the four apical rings lies deeper,
        // so the shallower of the two is the line).
        let ring = |rs: &[f64]| -> Vec<Vec<Vec3>> {
            rs.iter()
                .enumerate()
                .map(|(k, &a)| circle(a, 10.0 * k as f64, 64))
                .collect()
        };
        assert_eq!(taper_tip(&ring(&[5.0, 10.0, 12.0, 10.0, 5.0]), &Z), None);
        let back = taper(&ring(&[5.0, 10.0, 12.0, 14.0, 4.0]), &Z).unwrap();
        assert_eq!(back.fit, DomeFit::Paraboloid);
        assert!((back.tip.z + 10.0 / 3.0).abs() < 1e-9, "{back:?}");
    }

    /// The rings of an ellipsoidal LV (semi-axes 25 across, 60 along, apex at z = -60; rings every
    /// 8 mm from z = -48, as `tests/apex_floor_cli.rs` draws them): the tip at the analytic apex
    /// within 1e-6 mm, from the quadric (the paraboloid of session 13: 2.7 mm past, z = -62.7).
    #[test]
    fn tip_of_an_ellipsoid_stack() {
        let rings: Vec<Vec<Vec3>> = (0..7)
            .map(|k| {
                let z = -48.0 + 8.0 * k as f64;
                circle(25.0 * (1.0 - (z / 60.0).powi(2)).sqrt(), z, 60)
            })
            .collect();
        let t = taper(&rings, &Z).unwrap();
        assert_eq!((t.fit, t.measure), (DomeFit::Quadric, TaperMeasure::Area));
        assert!((t.tip - v3(0.0, 0.0, -60.0)).norm() < 1e-6, "{:?}", t.tip);
        assert_eq!(t.up, Z);
        let s = apical_sections(&rings, &Z, 2).unwrap();
        let line = paraboloid_depth(&s[0], &s[1]).unwrap();
        assert!((line - 14.73).abs() < 0.01, "{line}");
        // A ring below the one before it ends the sections there (the fit needs rising heights).
        let mut shuffled = rings.clone();
        shuffled.swap(2, 3);
        assert_eq!(apical_sections(&shuffled, &Z, 4).unwrap().len(), 3);
    }
}
