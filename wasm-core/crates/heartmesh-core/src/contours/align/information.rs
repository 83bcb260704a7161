//! How well the crossings determine each group's shift, direction by direction: the weighted
//! Gauss-Newton normal matrix of the group's in-plane shift, split along and across the long axis.
//! A long-axis view sees its slide along the axis only through how the wall's radius changes with
//! height (the taper, the apex); its slide across the axis through every wall crossing. A study
//! figure (examples/lax_axis.rs; docs/VALIDATION.md, "Session 10: long-axis views along the
//! axis"): on simulated LVs a view's along-axis information is 0.08-0.29 of its across-axis one.

use crate::geometry::Vec3;
use nalgebra::Matrix3;

/// The information (sum over the matched crossings of weight x (normal . direction)^2; in
/// crossings, each weighted by sin^2 of its angle to the plane, so at most 1 per crossing) a
/// group's crossings give about its shift.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Information {
    /// Along the long axis as seen in the group's plane (0 for a short-axis slice, whose plane
    /// is across the axis).
    pub along_axis: f64,
    /// Across the axis in the group's plane (a slice, both of whose in-plane directions are
    /// across the axis: the mean of its two eigenvalues).
    pub across_axis: f64,
    /// Eigenvalues of the 2 x 2 in-plane normal matrix.
    pub smallest: f64,
    pub largest: f64,
}

impl Information {
    /// The in-plane information of the 3 x 3 normal matrix `h` of a group with plane normal
    /// `normal`, the long axis being `axis`.
    pub(super) fn of(h: &Matrix3<f64>, normal: &Vec3, axis: &Vec3) -> Information {
        let (u, v) = crate::contours::axis::frame_for(normal);
        let (a, b, c) = (u.dot(&(h * u)), u.dot(&(h * v)), v.dot(&(h * v)));
        let mean = 0.5 * (a + c);
        let spread = (0.25 * (a - c).powi(2) + b * b).sqrt();
        let along = axis - normal * axis.dot(normal);
        let (along_axis, across_axis) = if along.norm() > 0.5 {
            let e = along.normalize();
            let f = normal.cross(&e);
            (e.dot(&(h * e)), f.dot(&(h * f)))
        } else {
            (0.0, mean)
        };
        Information {
            along_axis,
            across_axis,
            smallest: mean - spread,
            largest: mean + spread,
        }
    }
}
