//! How far below the most apical short-axis ring a dome ends, from the areas of the most apical
//! rings (`apex_floor`; docs/VALIDATION.md, "Session 14: a dome model for the apex floor").
//!
//! Every quadric of revolution about the long axis has a section AREA that is a quadratic in the
//! height: a paraboloid's is linear (A ~ h), an ellipsoid's concave (A = pi a b (1 - ((h - c) /
//! r)^2)), a cone's a perfect square (A ~ h^2), a hyperboloid's convex. So three or more rings
//! tell the families apart: the quadratic of area on height fitted to their (height, area) pairs
//! (least squares: `apex_floor::DOME_RINGS` says how many rings), and its zero nearest below the
//! apical ring ([`quadric_depth`]). Two rings only support the straight line, the
//! paraboloid of session 13 ([`paraboloid_depth`]), which on an ellipsoidal dome lies too deep:
//! the area's slope falls with height there, so the secant between two rings is shallower than
//! the slope near the tip (CAP LV epi: +2.4 mm past the truth).
//!
//! Which of the two ([`tip_depth`]): the shallower. Where the area is concave in height (an
//! ellipsoid's shoulder) that is the quadric (through three rings always, fitted to more as a
//! rule), exact for an ellipsoid. Where it is convex (a
//! cone's flank) the quadric carries the convexity on to a cusp, deeper than the line; but an apex
//! is smooth, and a smooth tip is locally a sphere or paraboloid whose area is linear or concave
//! in height, so a convex flank rounds off before the cone's virtual apex (a cone with a
//! spherical tip ends short of it by rho (1 / sin(alpha) - 1)), and the line is the nearer
//! answer. The choice is also the safe one: the floor this predicts is one-sided (it pulls only
//! while the mesh stops short of it), so a depth that is too small costs nothing against the
//! paper's extrapolation, and one that is too large pulls the apex past the truth. Measured on the
//! LV truths (biv-me patient 1 LV endo, convex: the three-ring quadric up to 6.5 mm past the
//! truth, the line within 1.6 mm; docs/VALIDATION.md, session 14).

/// A short-axis section: its height above the most apical ring along the axis towards the base
/// (mm; 0 for the apical ring itself) and its enclosed area (mm^2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    pub height: f64,
    pub area: f64,
}

/// Which family the rings supported.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DomeFit {
    /// Area linear in height through the two most apical rings (session 13's model).
    Paraboloid,
    /// Area quadratic in height, fitted to three or more of the most apical rings: any quadric
    /// dome.
    Quadric,
}

/// Depth (mm, > 0) below the apical ring at which the line through the first two `sections`
/// reaches zero area: d A1 / (A2 - A1). None unless the area grows towards the base.
pub fn paraboloid_depth(first: &Section, second: &Section) -> Option<f64> {
    let gap = second.height - first.height;
    let rise = second.area - first.area;
    let depth = gap * first.area / rise;
    (gap > 0.0 && rise > 0.0 && first.area > 0.0 && depth.is_finite()).then_some(depth)
}

/// Relative size of a discriminant that is 0 up to rounding (against b^2): far above the ~1e-16
/// of the f64 operations of the fit, far below any neck a slice could show (a hyperboloid gives
/// -(waist radius / apical ring radius)^2: -1e-6 for a waist of 0.1 %).
const SQUARE_ROUNDING: f64 = 1e-12;

/// Depth (mm, > 0) below the first of `sections` (at least three, heights strictly increasing)
/// of the nearest zero of the least-squares quadratic of area on height through them (through
/// three it is the interpolating quadratic); None when the quadratic has no zero below the first
/// section with the area rising from it (no dome: see the module note).
///
/// With the apical ring at height 0 the fit is A(h) = a + b h + c h^2 (heights scaled by the
/// span for the normal equations' conditioning); below the ring A(-t) = a - b t + c t^2 = 0 at
/// t = 2 a / (b + sqrt(b^2 - 4 c a)), the smaller root (no cancellation as c -> 0, where it
/// becomes the tangent line's a / b).
pub fn quadric_depth(sections: &[Section]) -> Option<f64> {
    let first = sections.first()?;
    // Strictly rising heights (false for NaN) also make the span positive.
    let rising = sections.windows(2).all(|w| w[1].height > w[0].height);
    if sections.len() < 3 || !rising {
        return None;
    }
    let span = sections.last()?.height - first.height;
    let mut normal = nalgebra::Matrix3::<f64>::zeros();
    let mut rhs = nalgebra::Vector3::<f64>::zeros();
    for s in sections {
        let t = (s.height - first.height) / span;
        let row = nalgebra::Vector3::new(1.0, t, t * t);
        normal += row * row.transpose();
        rhs += row * s.area;
    }
    let fit = normal.lu().solve(&rhs)?;
    let (a, b, c) = (fit.x, fit.y / span, fit.z / (span * span));
    let disc = b * b - 4.0 * c * a;
    // A cone's area is a perfect square (discriminant 0), which rounding leaves a few ulps either
    // side of 0: within [`SQUARE_ROUNDING`] of b^2 it is the double root, not a neck.
    if !(a > 0.0 && b > 0.0 && disc >= -SQUARE_ROUNDING * b * b) {
        return None;
    }
    let depth = 2.0 * a / (b + disc.max(0.0).sqrt());
    (depth.is_finite() && depth > 0.0).then_some(depth)
}

/// The dome's depth below the first of `sections` (apex first, heights increasing) and the
/// family that gave it: the shallower of the paraboloid through the two most apical sections and,
/// where there are three or more, the quadric fitted to all of them (see the module note: the
/// quadric where the area is concave in height, the paraboloid where it is linear or convex).
/// None when the two most apical sections do not taper towards the apex (the paraboloid's
/// condition, which the quadric keeps: it only refines a taper that the two rings already show).
pub fn tip_depth(sections: &[Section]) -> Option<(f64, DomeFit)> {
    let (first, second) = (sections.first()?, sections.get(1)?);
    let line = paraboloid_depth(first, second)?;
    match quadric_depth(sections) {
        Some(depth) if depth < line => Some((depth, DomeFit::Quadric)),
        _ => Some((line, DomeFit::Paraboloid)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Sections of a solid of revolution of radius `r(z)` (z up, the apex at the lowest z) at
    /// `heights`, measured from the first height.
    fn sections(heights: &[f64], r: impl Fn(f64) -> f64) -> Vec<Section> {
        heights
            .iter()
            .map(|&z| Section {
                height: z - heights[0],
                area: PI * r(z) * r(z),
            })
            .collect()
    }

    /// A paraboloid with its tip at z = 0 (r^2 = 20 z): both fits give the analytic depth
    /// (within 1e-9 mm), so either family may be the "shallower" one.
    #[test]
    fn paraboloid_tip() {
        let s = sections(&[6.0, 16.0, 26.0], |z| (20.0 * z).sqrt());
        assert!((paraboloid_depth(&s[0], &s[1]).unwrap() - 6.0).abs() < 1e-9);
        assert!((quadric_depth(&s).unwrap() - 6.0).abs() < 1e-9);
        let (d, _) = tip_depth(&s).unwrap();
        assert!((d - 6.0).abs() < 1e-9, "{d}");
    }

    /// A prolate half-spheroid (semi-axes 25 mm across and 80 mm along, tip at z = 0, an LV-like
    /// dome) sliced at 10 mm from 7 mm up. The straight line through two rings overshoots the tip
    /// (the session-13 failure); the quadric gives it within 1e-6 mm.
    #[test]
    fn ellipsoid_tip() {
        let r = |z: f64| 25.0 * (1.0 - ((z - 80.0) / 80.0).powi(2)).sqrt();
        let s = sections(&[7.0, 17.0, 27.0, 37.0], r);
        let line = paraboloid_depth(&s[0], &s[1]).unwrap();
        assert!(line > 7.0 + 0.5, "the paraboloid overshoots: {line}");
        let (d, fit) = tip_depth(&s).unwrap();
        assert_eq!(fit, DomeFit::Quadric);
        assert!((d - 7.0).abs() < 1e-6, "{d}");
        // Uneven gaps (a slice missing) change nothing.
        let (d, _) = tip_depth(&sections(&[7.0, 19.0, 38.0], r)).unwrap();
        assert!((d - 7.0).abs() < 1e-6, "{d}");
    }

    /// A cone (r = 0.5 z, tip at z = 0): the area is a perfect square, and the quadric's double
    /// root is the cusp (within 1e-3 mm: the discriminant is 0 up to rounding). The model takes
    /// the shallower paraboloid, which stops short of a cusp (9 - 10 x 81 / 280 = 6.1 mm short)
    /// and never past it.
    #[test]
    fn cone_tip() {
        let s = sections(&[9.0, 19.0, 29.0], |z| 0.5 * z);
        let quadric = quadric_depth(&s).unwrap();
        assert!((quadric - 9.0).abs() < 1e-3, "{quadric}");
        let (d, fit) = tip_depth(&s).unwrap();
        assert_eq!(fit, DomeFit::Paraboloid);
        assert!((d - 810.0 / 280.0).abs() < 1e-9, "{d}");
    }

    /// Why not the quadric on a convex flank: a 30-degree cone (r = z tan 30) rounded by a
    /// sphere of radius 10 tangent to it (centre z = 20, tip z = 10, the cap below z = 15),
    /// sliced on the cone at z = 16, 26, 36. The quadric finds the virtual cusp, 10 mm past the
    /// smooth tip; the model's paraboloid lies within 0.1 mm of it (0.095 past).
    #[test]
    fn rounded_cone_tip() {
        let r = |z: f64| {
            if z < 15.0 {
                (100.0 - (z - 20.0) * (z - 20.0)).sqrt()
            } else {
                z * (30.0f64).to_radians().tan()
            }
        };
        let s = sections(&[16.0, 26.0, 36.0], r);
        let quadric = quadric_depth(&s).unwrap();
        assert!(quadric > 6.0 + 9.9, "{quadric}");
        let (d, fit) = tip_depth(&s).unwrap();
        assert_eq!(fit, DomeFit::Paraboloid);
        assert!((d - 6.0).abs() < 0.1, "{d}");
    }

    /// Four rings of an exact quadric: the least-squares fit is exact too (ellipsoid within 1e-6
    /// mm, cone's cusp within 1e-3 mm).
    #[test]
    fn four_rings_of_a_quadric() {
        let r = |z: f64| 25.0 * (1.0 - ((z - 80.0) / 80.0).powi(2)).sqrt();
        let (d, fit) = tip_depth(&sections(&[7.0, 17.0, 27.0, 37.0], r)).unwrap();
        assert_eq!(fit, DomeFit::Quadric);
        assert!((d - 7.0).abs() < 1e-6, "{d}");
        let cone = sections(&[9.0, 19.0, 29.0, 39.0], |z| 0.5 * z);
        assert!((quadric_depth(&cone).unwrap() - 9.0).abs() < 1e-3);
    }

    /// Why four rings: a breath-hold moves a slice along its normal, so its section lies off its
    /// drawn height. The half-spheroid above (tip 7 mm below the apical ring, rings drawn at
    /// 7, 17, 27, 37) with the second ring's section taken 2 mm lower (z = 15): the paraboloid
    /// and the three-ring fit (the quadratic now convex: the paraboloid) put the tip 2.70 mm
    /// past; the four-ring least squares averages the shift out to 0.81 mm past.
    #[test]
    fn four_rings_average_a_moved_slice() {
        let r = |z: f64| 25.0 * (1.0 - ((z - 80.0) / 80.0).powi(2)).sqrt();
        let drawn = [7.0, 17.0, 27.0, 37.0];
        let cut = [7.0, 15.0, 27.0, 37.0];
        let s: Vec<Section> = drawn
            .iter()
            .zip(cut)
            .map(|(&h, z)| Section {
                height: h - 7.0,
                area: PI * r(z) * r(z),
            })
            .collect();
        let (three, _) = tip_depth(&s[..3]).unwrap();
        assert!((three - 7.0 - 2.70).abs() < 0.01, "{three}");
        let (four, fit) = tip_depth(&s).unwrap();
        assert_eq!(fit, DomeFit::Quadric);
        assert!((four - 7.0 - 0.81).abs() < 0.01, "{four}");
    }

    /// The limit: a hemispherical apex on a cylinder (radius 20, tip at z = 0, the cylinder from
    /// z = 20: a jump in curvature no smooth LV has), sliced at z = 5, 15, 25, 35. The paraboloid
    /// lies 3.75 mm past the tip (10 x 175 / 200 = 8.75 against 5), the three-ring quadric
    /// 0.25 mm past, the four-ring least squares 2.14 mm past: its two cylinder rings pull the
    /// fit's value at the apical ring above the ring's own area.
    #[test]
    fn capped_cylinder_tip() {
        let r = |z: f64| (400.0 - (z - 20.0).min(0.0).powi(2)).sqrt();
        let s = sections(&[5.0, 15.0, 25.0, 35.0], r);
        let line = paraboloid_depth(&s[0], &s[1]).unwrap();
        assert!((line - 8.75).abs() < 1e-9, "{line}");
        let three = quadric_depth(&s[..3]).unwrap();
        assert!((three - 5.25).abs() < 0.01, "{three}");
        let (four, fit) = tip_depth(&s).unwrap();
        assert_eq!(fit, DomeFit::Quadric);
        assert!((four - 7.14).abs() < 0.01, "{four}");
    }

    /// No quadric dome, the paraboloid instead: a hyperboloid neck (r^2 = 25 + z^2 / 4 about
    /// z = 0: no zero below), and an area that grows again below the apical ring (strongly
    /// convex). No taper between the two apical rings: nothing, whatever the third says.
    #[test]
    fn falls_back_where_the_quadratic_is_no_dome() {
        let neck = sections(&[2.0, 12.0, 22.0], |z| (25.0 + z * z / 4.0).sqrt());
        assert_eq!(quadric_depth(&neck), None);
        let (d, fit) = tip_depth(&neck).unwrap();
        assert_eq!(fit, DomeFit::Paraboloid);
        assert_eq!(Some(d), paraboloid_depth(&neck[0], &neck[1]));
        let regrow = [(0.0, 100.0), (10.0, 110.0), (20.0, 400.0)]
            .map(|(height, area)| Section { height, area });
        assert_eq!(quadric_depth(&regrow), None);
        assert_eq!(tip_depth(&regrow).unwrap().1, DomeFit::Paraboloid);
        let flat = [(0.0, 100.0), (10.0, 100.0), (20.0, 50.0)]
            .map(|(height, area)| Section { height, area });
        assert_eq!(tip_depth(&flat), None);
        assert_eq!(tip_depth(&flat[..1]), None);
        // Two sections: the paraboloid.
        let two = sections(&[6.0, 16.0], |z| (20.0 * z).sqrt());
        let (d, fit) = tip_depth(&two).unwrap();
        assert_eq!(fit, DomeFit::Paraboloid);
        assert!((d - 6.0).abs() < 1e-9);
    }
}
