//! Quadric error metric of Garland & Heckbert, "Surface simplification using quadric error
//! metrics", SIGGRAPH 1997: the sum of squared distances to a set of planes, as a symmetric 4x4
//! matrix, so merging two vertices' plane sets is one addition and the best merged position is one
//! 3x3 solve.

use crate::geometry::Vec3;

/// Symmetric 4x4 quadric sum w (n.p + d)^2, stored as its upper triangle.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Quadric([f64; 10]);

impl Quadric {
    pub fn plane(n: Vec3, d: f64, w: f64) -> Quadric {
        let (a, b, c) = (n.x, n.y, n.z);
        Quadric(
            [
                a * a,
                a * b,
                a * c,
                a * d,
                b * b,
                b * c,
                b * d,
                c * c,
                c * d,
                d * d,
            ]
            .map(|x| x * w),
        )
    }

    #[inline(always)]
    pub fn add(&mut self, o: &Quadric) {
        for (x, y) in self.0.iter_mut().zip(&o.0) {
            *x += y;
        }
    }

    #[inline(always)]
    pub fn sum(&self, o: &Quadric) -> Quadric {
        let mut s = *self;
        s.add(o);
        s
    }

    #[inline(always)]
    pub fn error(&self, p: Vec3) -> f64 {
        let [a2, ab, ac, ad, b2, bc, bd, c2, cd, d2] = self.0;
        let (x, y, z) = (p.x, p.y, p.z);
        let e = x * (a2 * x + 2.0 * (ab * y + ac * z + ad))
            + y * (b2 * y + 2.0 * (bc * z + bd))
            + z * (c2 * z + 2.0 * cd)
            + d2;
        e.max(0.0)
    }

    /// The point of least error, or None when the 3x3 part is (nearly) singular: flat or
    /// cylindrical neighbourhoods, where the minimum is a plane or a line.
    #[inline(always)]
    pub fn optimum(&self) -> Option<Vec3> {
        let [a2, ab, ac, ad, b2, bc, bd, c2, cd, _] = self.0;
        let c00 = b2 * c2 - bc * bc;
        let c01 = ac * bc - ab * c2;
        let c02 = ab * bc - ac * b2;
        let det = a2 * c00 + ab * c01 + ac * c02;
        let trace = a2 + b2 + c2;
        if det.is_nan() || det.abs() <= 1e-9 * trace * trace * trace {
            return None;
        }
        let c11 = a2 * c2 - ac * ac;
        let c12 = ab * ac - a2 * bc;
        let c22 = a2 * b2 - ab * ab;
        let (rx, ry, rz) = (-ad, -bd, -cd);
        let p = Vec3::new(
            c00 * rx + c01 * ry + c02 * rz,
            c01 * rx + c11 * ry + c12 * rz,
            c02 * rx + c12 * ry + c22 * rz,
        ) / det;
        p.iter().all(|c| c.is_finite()).then_some(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadric_optimum_of_three_planes_is_their_corner() {
        let mut q = Quadric::default();
        q.add(&Quadric::plane(Vec3::x(), -1.0, 1.0));
        q.add(&Quadric::plane(Vec3::y(), -2.0, 1.0));
        q.add(&Quadric::plane(Vec3::z(), -3.0, 1.0));
        let p = q.optimum().unwrap();
        assert!((p - Vec3::new(1.0, 2.0, 3.0)).norm() < 1e-12);
        assert!(q.error(p) < 1e-12);
        assert!((q.error(Vec3::new(2.0, 2.0, 3.0)) - 1.0).abs() < 1e-12);
        // One plane: singular.
        assert!(Quadric::plane(Vec3::z(), 0.0, 1.0).optimum().is_none());
    }
}
