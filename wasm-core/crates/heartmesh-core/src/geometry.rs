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

/// The sum of `values` in an order of their own (ascending), so the same numbers listed in any
/// order sum to the same bits: a file's contours in another order then give the same mesh, where
/// a sum in file order would differ in its last bits and the iterations would carry that apart.
pub fn order_free_sum(values: impl IntoIterator<Item = f64>) -> f64 {
    let mut v: Vec<f64> = values.into_iter().collect();
    v.sort_by(f64::total_cmp);
    v.iter().sum()
}

/// [`order_free_sum`] of vectors (ordered by [`lexicographic`]).
pub fn order_free_vec_sum(values: impl IntoIterator<Item = Vec3>) -> Vec3 {
    let mut v: Vec<Vec3> = values.into_iter().collect();
    v.sort_by(lexicographic);
    v.iter().fold(Vec3::zeros(), |a, p| a + p)
}

/// A total order of points: by x, then y, then z.
pub fn lexicographic(a: &Vec3, b: &Vec3) -> std::cmp::Ordering {
    a.x.total_cmp(&b.x)
        .then(a.y.total_cmp(&b.y))
        .then(a.z.total_cmp(&b.z))
}

/// The mean of `points` whatever their order ([`order_free_vec_sum`]).
pub fn order_free_centroid(points: &[Vec3]) -> Vec3 {
    order_free_vec_sum(points.iter().copied()) / points.len().max(1) as f64
}

/// `n` points of an axis-aligned ellipse with semi-axes `a` (x) and `b` (y) at height `z`, from
/// the +x axis: the ring (or crescent-like outline) that many tests slice a ventricle into.
#[cfg(test)]
pub(crate) fn ellipse(a: f64, b: f64, z: f64, n: usize) -> Vec<Vec3> {
    (0..n)
        .map(|i| {
            let t = i as f64 / n as f64 * std::f64::consts::TAU;
            v3(a * t.cos(), b * t.sin(), z)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values whose sum in file order depends on that order in its last bits.
    #[test]
    fn sums_in_any_order_are_the_same_bits() {
        let values = [0.1, 1e16, 0.2, -1e16, 0.3, 7.25e-3];
        let reversed: Vec<f64> = values.iter().rev().copied().collect();
        let naive = |v: &[f64]| v.iter().sum::<f64>();
        assert_ne!(
            naive(&values),
            naive(&reversed),
            "a case where order matters"
        );
        assert_eq!(order_free_sum(values), order_free_sum(reversed));
        let points: Vec<Vec3> = values.iter().map(|&x| v3(x, -x, 0.5 * x)).collect();
        let back: Vec<Vec3> = points.iter().rev().copied().collect();
        assert_eq!(order_free_centroid(&points), order_free_centroid(&back));
    }
}
