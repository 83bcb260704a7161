//! Small geometric vocabulary shared by every module.

/// A point or vector in millimetres (or in normalised units inside the deformation loop).
pub type Vec3 = nalgebra::Vector3<f64>;

/// Builds a [`Vec3`] from three coordinates.
#[inline]
pub fn v3(x: f64, y: f64, z: f64) -> Vec3 {
    Vec3::new(x, y, z)
}

/// The mean of `points` (the origin for none: callers check emptiness where it matters).
pub fn centroid(points: &[Vec3]) -> Vec3 {
    points.iter().fold(Vec3::zeros(), |a, p| a + p) / points.len().max(1) as f64
}
