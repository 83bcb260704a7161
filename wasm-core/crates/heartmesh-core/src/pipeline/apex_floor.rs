//! An apex floor for short-axis-only stacks (opt-in, `Params::apex_floor`; docs/VALIDATION.md,
//! "Session 13: an apex floor from the taper of the slices").
//!
//! With no long-axis curve at the apex (`ends::EndLid::OpenApex`) the mesh's apex is the paper's
//! extrapolation, which session 12 measured short of the truth by 0.3-4.3 mm. The slices say more:
//! near the apex a cavity tapers like a paraboloid, whose section AREA is linear in height, so the
//! two most apical rings predict where the area reaches zero. On the LV truths sliced short-axis
//! only at 7-14 mm that tip lay within a median 0.65 mm of the truth's apex (90th percentile 2.2,
//! worst 3.7 mm). So one lid point goes there, one-sided the other way round from the base's
//! ceiling: it pulls only while the mesh stops SHORT of the tip's plane (`lid_pull` with the
//! normal pointing back up the axis), never pushes a mesh that already reaches past it.

use super::end_data::EndRing;
use super::lid_pull::LidSide;
use crate::contours::rings::signed_area;
use crate::geometry::Vec3;

/// No floor when the predicted tip lies more than this many slice gaps below the apical ring.
/// The depth is d A1 / (A2 - A1): it grows without bound as the two rings' areas approach each
/// other (a cylinder-like apical segment, a slice cutting the wall obliquely, noise), where the
/// linear-area model says nothing; the truths' apices lay 0.3-1.3 gaps below the apical ring
/// (3.1-13.3 mm at 7-14 mm spacing), so two gaps leave room for every taper seen and refuse the
/// ill-posed ones (the paper's extrapolation decides there, as without the floor).
pub const MAX_DEPTH_PER_SLICE_GAP: f64 = 2.0;

/// No floor unless the rings' area-weighted mean height lies this share of a slice gap above the
/// stack's middle (towards the base): a symmetric stack gives 0 up to rounding, while two rings at
/// the weakest taper the depth guard accepts (A2 = 1.5 A1) give a tenth of a gap.
pub const MIN_AREA_LEAN_PER_GAP: f64 = 0.05;

/// The apex predicted from the taper of the two most apical `rings` (apex first): area linear in
/// height, h_tip = h1 - d A1 / (A2 - A1) with d the rings' height gap along `axis` (pointing from
/// apex to base), at the apical ring's centroid moved along the axis (its in-plane position: an
/// extrapolated centroid line would carry a misaligned slice's shift twice as far). None when the
/// rings do not taper towards the apex (A2 <= A1), the gap is zero, the tip lies more than
/// [`MAX_DEPTH_PER_SLICE_GAP`] gaps below the apical ring, or the stack is not wider towards its
/// base ([`MIN_AREA_LEAN_PER_GAP`]: which end is the apex is then a guess).
pub fn taper_tip(rings: &[Vec<Vec3>], axis: &Vec3) -> Option<Vec3> {
    taper(rings, axis).map(|(tip, _)| tip)
}

/// [`taper_tip`] and the unit vector up the axis from it (towards the second ring).
fn taper(rings: &[Vec<Vec3>], axis: &Vec3) -> Option<(Vec3, Vec3)> {
    let (first, second) = (rings.first()?, rings.get(1)?);
    let (e1, e2) = (EndRing::of(first, axis)?, EndRing::of(second, axis)?);
    let area = |r: &[Vec3], c: &Vec3| {
        let centred: Vec<Vec3> = r.iter().map(|p| p - c).collect();
        signed_area(&centred, axis).abs()
    };
    let (a1, a2) = (area(first, &e1.centre), area(second, &e2.centre));
    let gap = (e2.height - e1.height).abs();
    if !(a1.is_finite() && a2.is_finite() && gap.is_finite()) || gap <= 0.0 || a2 <= a1 {
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
        let a = area(r, &e.centre);
        sum_a += a;
        sum_ah += a * (e.height - e1.height) * up_sign;
    }
    let last = EndRing::of(rings.last()?, axis)?;
    let half = 0.5 * (last.height - e1.height) * up_sign;
    let lean = sum_ah / sum_a - half;
    if lean.is_nan() || lean <= MIN_AREA_LEAN_PER_GAP * gap {
        return None;
    }
    let depth = gap * a1 / (a2 - a1);
    if !depth.is_finite() || depth > MAX_DEPTH_PER_SLICE_GAP * gap {
        return None;
    }
    // Below the apical ring: against the direction from it towards the second ring.
    let up = if e2.height >= e1.height { *axis } else { -axis };
    Some((e1.centre - up * depth, up))
}

/// The floor's lid point and its side: pulls with `weight` while its closest mesh point lies more
/// than `tolerance` above the tip's plane (the normal points up the axis, into the cavity).
pub fn floor_point(
    rings: &[Vec<Vec3>],
    axis: &Vec3,
    tolerance: f64,
    weight: f64,
) -> Option<(Vec3, LidSide)> {
    let (tip, up) = taper(rings, axis)?;
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
        // the two-ring tip.
        let ring = |rs: &[f64]| -> Vec<Vec<Vec3>> {
            rs.iter()
                .enumerate()
                .map(|(k, &a)| circle(a, 10.0 * k as f64, 64))
                .collect()
        };
        assert_eq!(taper_tip(&ring(&[5.0, 10.0, 12.0, 10.0, 5.0]), &Z), None);
        let back = taper_tip(&ring(&[5.0, 10.0, 12.0, 14.0, 4.0]), &Z).unwrap();
        assert!((back.z + 10.0 / 3.0).abs() < 1e-9, "{back:?}");
    }
}
