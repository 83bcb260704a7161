//! Specks in long-axis planes: a curve in a long-axis view far too short to be a section of the
//! cavity through its long axis (a stray click in a 2- or 4-chamber image, an automatic
//! segmentation's island).
//!
//! Long-axis curves do not seed the tube; their points only attract the surface. A short-axis
//! speck narrows the tube ([`super::specks`]); a long-axis one pulls the wall towards itself
//! wherever it lies: a 3-point, 1 mm loop at the middle of the SurFCo cavity, in the plane of
//! one of its long-axis views, drew a spike 27 mm into the cavity (mesh-to-mesh Hausdorff against
//! the run without it; docs/VALIDATION.md, "Session 15: specks in long-axis planes"). A section
//! through the long axis runs the length of the cavity, so it is never shorter than that length
//! (a closed one twice over): a curve shorter than [`super::specks::SPECK_RATIO`] of the extent of
//! its surface's data along the axis is not one. Part of a view (a septal piece, the free wall
//! near the base) keeps a good share of that length; only a click-sized curve is left out.

use super::axis::Layout;
use super::clean::contour_length;
use super::specks::SPECK_RATIO;
use super::{Contour, ContourKind};

/// A long-axis speck: its index in the contours, its length and the data's extent along the axis.
#[derive(Debug, Clone, PartialEq)]
pub struct LaxSpeck {
    pub index: usize,
    pub length_mm: f64,
    pub extent_mm: f64,
}

/// The long-axis specks of one surface's cleaned `contours` laid out by `layout`. Single points
/// are not curves and stay data (landmarks, `checks::few_point_warnings` names them).
pub fn lax_specks(contours: &[Contour], layout: &Layout) -> Vec<LaxSpeck> {
    let Some(extent_mm) = extent(contours, layout) else {
        return Vec::new();
    };
    contours
        .iter()
        .zip(&layout.kinds)
        .enumerate()
        .filter(|(_, (c, kind))| **kind == ContourKind::Lax && c.point_count() >= 2)
        .map(|(index, (c, _))| LaxSpeck {
            index,
            length_mm: contour_length(c),
            extent_mm,
        })
        .filter(|s| s.length_mm < SPECK_RATIO * s.extent_mm)
        .collect()
}

/// How far the points of `contours` reach along the layout's axis, mm (None without points).
pub fn extent(contours: &[Contour], layout: &Layout) -> Option<f64> {
    let heights = contours
        .iter()
        .flat_map(|c| c.points())
        .map(|p| p.dot(&layout.axis));
    heights
        .fold(None, |acc: Option<(f64, f64)>, h| {
            Some(acc.map_or((h, h), |(lo, hi)| (lo.min(h), hi.max(h))))
        })
        .map(|(lo, hi)| hi - lo)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contours::axis::analyse;
    use crate::contours::specks::fixtures::{contour, dome, ring};
    use crate::geometry::{v3, Vec3};

    /// A long-axis curve in the plane y = `y`: a U from the top of the dome (z 40) down to z
    /// `bottom` and back, half-width `w`.
    fn lax(id: &str, y: f64, w: f64, bottom: f64) -> Contour {
        let points: Vec<Vec3> = (0..=40)
            .map(|k| {
                let t = std::f64::consts::PI * k as f64 / 40.0;
                v3(-w * t.cos(), y, 40.0 - (40.0 - bottom) * t.sin())
            })
            .collect();
        contour(id, points, false, 400)
    }

    #[test]
    fn a_click_in_a_long_axis_view_is_a_speck_and_the_views_are_not() {
        let mut c = dome();
        c.push(lax("lax1", 0.0, 29.0, -2.0));
        c.push(lax("lax2", 3.0, 28.0, -1.0));
        let layout = analyse(&c).unwrap();
        assert!(lax_specks(&c, &layout).is_empty());
        // Half a view (the septal side only, down to the apex) is no speck either.
        let mut half = lax("half", -3.0, 28.0, -1.0);
        half.pieces[0].points.truncate(21);
        c.push(half);
        // A 3-point loop 0.5 mm in radius in the plane of lax1 at the middle of the cavity
        // (2.6 mm around; the dome is only 42 mm tall).
        let mut click = ring("click", 0.5, 20.0, 0.0, 3, 450);
        for p in click.pieces.iter_mut().flat_map(|p| p.points.iter_mut()) {
            (p.y, p.z) = (0.0, 20.0 + p.y);
        }
        c.push(click);
        let layout = analyse(&c).unwrap();
        let found = lax_specks(&c, &layout);
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].index, c.len() - 1);
        assert!((found[0].length_mm - 1.5 * 3f64.sqrt()).abs() < 1e-9);
        // The dome's data reach from z -2 (lax1's bottom) to 40.
        assert!(
            (found[0].extent_mm - 42.0).abs() < 1e-9,
            "{}",
            found[0].extent_mm
        );
    }
}
