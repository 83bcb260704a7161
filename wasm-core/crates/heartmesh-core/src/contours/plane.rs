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

/// Fits a plane by principal components; None for fewer than 3 points or (near-)collinear points.
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
    if large.is_nan() || large <= 0.0 || mid.sqrt() < 1e-6 * large.sqrt() {
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

    #[test]
    fn angles_ignore_sign() {
        assert!((axis_angle_deg(&v3(0., 0., 1.), &v3(0., 0., -1.))).abs() < 1e-9);
        assert!((axis_angle_deg(&v3(0., 0., 1.), &v3(1., 0., 0.)) - 90.0).abs() < 1e-9);
    }
}
