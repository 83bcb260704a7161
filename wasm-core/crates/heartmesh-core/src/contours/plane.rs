//! Least-squares plane of a contour (Villard et al. 2018, section 2.1: each contour's normal decides
//! whether it is short- or long-axis).

use crate::geometry::Vec3;
use nalgebra::{Matrix3, SymmetricEigen};

/// A fitted plane: centroid, unit normal (sign arbitrary) and how well the points fit it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneFit {
    pub centroid: Vec3,
    pub normal: Vec3,
    /// Root-mean-square distance of the points to the plane, mm.
    pub rms_residual: f64,
    /// Largest distance of a point to the plane, mm.
    pub max_residual: f64,
    /// Ratio of the two in-plane extents' smaller to larger (near 0: the points are almost collinear,
    /// so the normal is meaningless).
    pub flatness_ratio: f64,
}

/// Below this ratio of the points' spread across their line to their spread along it (standard
/// deviations) a contour is straight: whatever normal a fit gives it is set by the rounding of its
/// coordinates, not by the image plane. A 2.5 mm septum piece of biv-me's test patient 1, digitised
/// in a short-axis image and stored to 3 decimals, spreads 0.18 um across its line (a ratio of
/// 7e-5): its fitted normal lay 90 degrees from the image's, so the piece counted as a long-axis
/// curve and the slice's RV ring lost its septum. At 1e-3 a piece 20 mm long is straight when its
/// points stray under 6 um (sd) from a line, far below any image's pixel, while the flattest real
/// curve measured (a 9 mm septum arc, 0.06) keeps its plane.
pub const MIN_FLATNESS: f64 = 1e-3;

/// Fits a plane by principal components; None for fewer than 3 points or (near-)collinear points
/// ([`MIN_FLATNESS`]).
pub fn fit_plane<'a>(points: impl Iterator<Item = &'a Vec3> + Clone) -> Option<PlaneFit> {
    let mut n = 0usize;
    let mut sum = Vec3::zeros();
    for p in points.clone() {
        sum += p;
        n += 1;
    }
    if n < 3 {
        return None;
    }
    let centroid = sum / n as f64;
    let mut cov = Matrix3::zeros();
    for p in points.clone() {
        let d = p - centroid;
        cov += d * d.transpose();
    }
    cov /= n as f64;
    // nalgebra's eigen-solver never returns on non-finite input (overflowing coordinates can make
    // the covariance infinite even after cleaning), so check first and cap the iterations.
    if !cov.iter().all(|c| c.is_finite()) {
        return None;
    }
    let eig = SymmetricEigen::try_new(cov, f64::EPSILON, 200)?;
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    let (mid, large) = (
        eig.eigenvalues[order[1]].max(0.0),
        eig.eigenvalues[order[2]].max(0.0),
    );
    if large.is_nan() || large <= 0.0 || mid.sqrt() < MIN_FLATNESS * large.sqrt() {
        return None;
    }
    let normal = eig.eigenvectors.column(order[0]).into_owned().normalize();
    if !normal.iter().all(|c| c.is_finite()) {
        return None;
    }
    let (max_residual, sum_sq) = points.fold((0.0f64, 0.0), |(mx, ss), p| {
        let d = (p - centroid).dot(&normal);
        (mx.max(d.abs()), ss + d * d)
    });
    Some(PlaneFit {
        centroid,
        normal,
        rms_residual: (sum_sq / n as f64).sqrt(),
        max_residual,
        flatness_ratio: (mid / large).sqrt(),
    })
}

/// Acute angle in degrees between two directions, ignoring sign (n and -n are the same direction).
pub fn axis_angle_deg(a: &Vec3, b: &Vec3) -> f64 {
    a.dot(b).abs().clamp(0.0, 1.0).acos().to_degrees()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    #[test]
    fn tilted_circle_normal_and_residual() {
        let n = v3(0.0, 0.6, 0.8);
        let u = v3(1.0, 0.0, 0.0);
        let w = n.cross(&u);
        let pts: Vec<Vec3> = (0..36)
            .map(|i| {
                let a = i as f64 * 10f64.to_radians();
                v3(5., 5., 5.) + u * (20.0 * a.cos()) + w * (20.0 * a.sin())
            })
            .collect();
        let f = fit_plane(pts.iter()).unwrap();
        assert!(axis_angle_deg(&f.normal, &n) < 1e-6);
        assert!(f.rms_residual < 1e-9);
        assert!((f.centroid - v3(5., 5., 5.)).norm() < 1e-9);
    }

    #[test]
    fn overflowing_points_have_no_plane() {
        let pts = [v3(1e200, 0., 0.), v3(-1e200, 1e200, 0.), v3(0., 0., 1e200)];
        assert!(fit_plane(pts.iter()).is_none());
    }

    #[test]
    fn collinear_points_have_no_plane() {
        let pts: Vec<Vec3> = (0..10).map(|i| v3(i as f64, 2.0 * i as f64, 0.)).collect();
        assert!(fit_plane(pts.iter()).is_none());
    }

    /// The septum piece of biv-me's test patient 1 (slice 4, frame 0), as the file stores it: a
    /// straight line to the file's 3 decimals, whose fitted normal would be (0, 1, 0), 90 degrees
    /// from its short-axis image's; no plane. A 0.2 mm sag over 20 mm keeps it.
    #[test]
    fn a_straight_piece_rounded_to_3_decimals_has_no_plane() {
        let pts = [
            v3(29.067, -93.484, 84.786),
            v3(28.112, -93.484, 83.979),
            v3(27.157, -93.484, 83.172),
            v3(26.203, -93.484, 82.365),
            v3(25.248, -93.484, 81.558),
            v3(24.294, -93.484, 80.751),
            v3(23.339, -93.484, 79.944),
        ];
        assert!(fit_plane(pts.iter()).is_none());
        let sag: Vec<Vec3> = (0..=20)
            .map(|i| {
                let t = i as f64 / 20.0;
                v3(20.0 * t, 0.8 * t * (1.0 - t), 0.0)
            })
            .collect();
        let f = fit_plane(sag.iter()).unwrap();
        assert!(axis_angle_deg(&f.normal, &v3(0.0, 0.0, 1.0)) < 1e-6);
        assert!(
            f.flatness_ratio > 10.0 * MIN_FLATNESS,
            "{}",
            f.flatness_ratio
        );
    }

    #[test]
    fn angles_ignore_sign() {
        assert!((axis_angle_deg(&v3(0., 0., 1.), &v3(0., 0., -1.))).abs() < 1e-9);
        assert!((axis_angle_deg(&v3(0., 0., 1.), &v3(1., 0., 0.)) - 90.0).abs() < 1e-9);
    }
}
