//! The apex floor on crescents (docs/VALIDATION.md, "Session 17: the apex floor on RV crescents").
//!
//! The dome model (`dome`) reads a ring's AREA as the square of a radius: a quadric of revolution
//! has sections whose area is quadratic in height, and its zero is the tip. On a round ring the
//! half-perimeter L measures the same radius (A = pi r^2, L = pi r), so A, L^2 and their geometric
//! mean L sqrt(A) are all proportional to r^2 and give the same tip. They differ only where the
//! ring's SHAPE changes from ring to ring (its isoperimetric ratio L^2 / A, pi for a circle and
//! larger for anything else). An LV's apical rings keep their shape as they taper, and the floor
//! is unchanged there. An RV's do not: its apical ring is a compact blob and the ring above it a
//! crescent wrapped around the septum, whose length falls much faster towards the apex than its
//! width (the spasm RV's population members: L^2 / A about 4 at the apical ring, 6 at the next;
//! the length grows 1.2-1.7 times from one to the other, the width 1.1-1.3 times). Read as the
//! square of a radius, the area then tapers too slowly and the dome's tip lies too deep (session
//! 14: 10 of 50 short-axis-only RV meshes more than 2 mm past the truth, up to +5.7 mm), while the
//! length alone tapers too fast and the tip falls short (offline, median -1.3 to -2.2 mm over the
//! reference RVs and three populations).
//!
//! So the floor also fits the dome to L sqrt(A), the unweighted middle of the two readings (its
//! growth from ring to ring is the geometric mean of the area's and of L^2's), and takes the
//! SHALLOWER of that tip and the area's ([`shallower_tip`]). The result is never deeper than
//! session 14's floor, so the rule can only take overshoot away: where rings keep their shape it
//! changes nothing, and where they grow more elongated towards the apex (a slice cutting the wall
//! obliquely) the measure's tip lies deeper and the area's is kept. No constant was fitted: the
//! middle of the two readings was taken as it is, not searched for (docs/VALIDATION.md, session
//! 17, has the paired study and two populations it was not chosen on).

use super::dome::{tip_depth, DomeFit, Section};
use crate::geometry::Vec3;

/// Which quantity of the rings placed the floor's tip.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TaperMeasure {
    /// The ring's area (session 14's dome).
    Area,
    /// The ring's half-perimeter times the square root of its area: shallower than the area's
    /// where the rings grow rounder towards the apex (an RV crescent).
    LengthArea,
}

/// How much shallower (relative) the L sqrt(A) tip must be to be taken: on rings of one shape
/// the two tips agree up to the rounding of the fit (about 1e-13 of the depth), so a round stack
/// keeps reporting [`TaperMeasure::Area`]; any real change of shape moves the tip by far more
/// (the RVs: 5 to 60 % of the depth).
const SHALLOWER_BY: f64 = 1e-9;

/// Half the perimeter of `ring` projected on the plane normal to `axis` (unit; mm): a thin
/// crescent's length, pi r for a circle.
pub fn half_perimeter(ring: &[Vec3], axis: &Vec3) -> f64 {
    let n = ring.len();
    0.5 * (0..n)
        .map(|i| {
            let d = ring[(i + 1) % n] - ring[i];
            (d - axis * d.dot(axis)).norm()
        })
        .sum::<f64>()
}

/// `sections` (the apical sections of `rings`, one per ring in order, as
/// `apex_floor::apical_sections` makes them) with each ring's L sqrt(A) in place of its area.
pub fn length_area_sections(
    sections: &[Section],
    rings: &[Vec<Vec3>],
    axis: &Vec3,
) -> Vec<Section> {
    sections
        .iter()
        .zip(rings)
        .map(|(s, ring)| Section {
            height: s.height,
            area: half_perimeter(ring, axis) * s.area.max(0.0).sqrt(),
        })
        .collect()
}

/// The floor's depth below the apical ring, its dome family and the measure that gave it: the
/// dome on the areas (`dome::tip_depth`), or the dome on L sqrt(A) where that is shallower by
/// more than rounding ([`SHALLOWER_BY`]). None when the areas give no tip (the session-14
/// condition, unchanged: the rule only ever moves a tip that the areas already place).
pub fn shallower_tip(
    sections: &[Section],
    rings: &[Vec<Vec3>],
    axis: &Vec3,
) -> Option<(f64, DomeFit, TaperMeasure)> {
    let (area_depth, area_fit) = tip_depth(sections)?;
    match tip_depth(&length_area_sections(sections, rings, axis)) {
        Some((depth, fit)) if depth < area_depth * (1.0 - SHALLOWER_BY) => {
            Some((depth, fit, TaperMeasure::LengthArea))
        }
        _ => Some((area_depth, area_fit, TaperMeasure::Area)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{ellipse, v3};
    use crate::pipeline::apex_floor::apical_sections;
    use crate::pipeline::end_data::fixtures::Z;

    /// An axis-aligned rectangle `length` x `width` at height `z`, counter-clockwise, with
    /// `per_side` points on each side.
    fn rectangle(length: f64, width: f64, z: f64, per_side: usize) -> Vec<Vec3> {
        let (a, b) = (0.5 * length, 0.5 * width);
        let corners = [v3(-a, -b, z), v3(a, -b, z), v3(a, b, z), v3(-a, b, z)];
        (0..4)
            .flat_map(|k| {
                let (p, q) = (corners[k], corners[(k + 1) % 4]);
                (0..per_side).map(move |i| p + (q - p) * (i as f64 / per_side as f64))
            })
            .collect()
    }

    /// Rings of one shape (ellipses of aspect 2, the half-spheroid of `dome`'s test, sliced at
    /// 7, 17, 27 and 37 mm above its tip) give the area's tip: L sqrt(A) is a fixed multiple of
    /// the area there, so both domes agree (within 1e-9 mm) and the area is reported.
    #[test]
    fn rings_of_one_shape_keep_the_area_tip() {
        let r = |z: f64| 25.0 * (1.0 - ((z - 80.0) / 80.0).powi(2)).sqrt();
        let rings: Vec<Vec<Vec3>> = [7.0, 17.0, 27.0, 37.0]
            .iter()
            .map(|&z| ellipse(2.0 * r(z), r(z), z, 200))
            .collect();
        let s = apical_sections(&rings, &Z, 4).unwrap();
        let (area_depth, _) = tip_depth(&s).unwrap();
        let (measure_depth, _) = tip_depth(&length_area_sections(&s, &rings, &Z)).unwrap();
        assert!(
            (measure_depth - area_depth).abs() < 1e-9,
            "{measure_depth} {area_depth}"
        );
        let (depth, fit, measure) = shallower_tip(&s, &rings, &Z).unwrap();
        assert_eq!(
            (depth, fit, measure),
            (area_depth, DomeFit::Quadric, TaperMeasure::Area)
        );
        // The spheroid's tip, 7 mm below the apical ring, to the polygon's precision.
        assert!((depth - 7.0).abs() < 0.01, "{depth}");
    }

    /// A crescent that shortens towards the apex at a constant width (rectangles 8 mm wide, 20
    /// then 40 mm long, 10 mm apart): the area doubles (the paraboloid's tip 10 x 160 / 160 = 10
    /// mm down), L sqrt(A) grows from 28 sqrt(160) to 48 sqrt(320) (its tip at
    /// 10 / (48 sqrt(2) / 28 - 1) = 7.02 mm down), and the floor takes the shallower. A ring that
    /// grows MORE elongated towards the apex (40 x 4 under 40 x 8: the same areas, L sqrt(A) from
    /// 44 sqrt(160) to 48 sqrt(320), 18.4 mm down) keeps the area's tip.
    #[test]
    fn a_shortening_crescent_takes_the_shallower_tip() {
        let rings = vec![
            rectangle(20.0, 8.0, 0.0, 16),
            rectangle(40.0, 8.0, 10.0, 16),
        ];
        let s = apical_sections(&rings, &Z, 4).unwrap();
        assert!((s[0].area - 160.0).abs() < 1e-9 && (s[1].area - 320.0).abs() < 1e-9);
        assert!((half_perimeter(&rings[0], &Z) - 28.0).abs() < 1e-9);
        let expected = 10.0 / (48.0 * 2f64.sqrt() / 28.0 - 1.0);
        let (depth, fit, measure) = shallower_tip(&s, &rings, &Z).unwrap();
        assert!((depth - expected).abs() < 1e-9, "{depth} {expected}");
        assert!((depth - 7.02).abs() < 0.005, "{depth}");
        assert_eq!(
            (fit, measure),
            (DomeFit::Paraboloid, TaperMeasure::LengthArea)
        );

        let rings = vec![
            rectangle(40.0, 4.0, 0.0, 16),
            rectangle(40.0, 8.0, 10.0, 16),
        ];
        let s = apical_sections(&rings, &Z, 4).unwrap();
        let (depth, _, measure) = shallower_tip(&s, &rings, &Z).unwrap();
        assert!((depth - 10.0).abs() < 1e-9, "{depth}");
        assert_eq!(measure, TaperMeasure::Area);
        let (deeper, _) = tip_depth(&length_area_sections(&s, &rings, &Z)).unwrap();
        let l = |len: f64, w: f64| (len + w) * (len * w).sqrt();
        let expected = 10.0 * l(40.0, 4.0) / (l(40.0, 8.0) - l(40.0, 4.0));
        assert!(
            (deeper - expected).abs() < 1e-9 && deeper > 18.0,
            "{deeper}"
        );
    }

    /// No tip from the areas, none from the rule: rings that do not taper towards the apex.
    #[test]
    fn no_area_tip_no_tip() {
        let rings = vec![
            rectangle(40.0, 8.0, 0.0, 16),
            rectangle(20.0, 16.0, 10.0, 16),
        ];
        let s = apical_sections(&rings, &Z, 4).unwrap();
        assert_eq!(shallower_tip(&s, &rings, &Z), None);
        assert_eq!(half_perimeter(&[], &Z), 0.0);
    }
}
