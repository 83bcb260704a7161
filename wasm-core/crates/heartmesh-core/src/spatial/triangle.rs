//! Exact closest point on a triangle to a point.
//!
//! Reference: C. Ericson, "Real-Time Collision Detection", Morgan Kaufmann 2005, section 5.1.5
//! (Voronoi-region method). The query is classified against the Voronoi regions of the three
//! vertices, the three edges and the face using only dot products, so the common vertex and edge
//! cases never divide; the face case is a projection onto the plane (more accurate than Ericson's
//! barycentric form for thin triangles, see the comment there).
//!
//! Degenerate triangles (zero or near-zero area, coincident vertices) make the face projection
//! and the edge divisions by `|edge|^2` meaningless. A degenerate triangle is the union of its
//! three edges, so it is answered as the closest point over the three segments instead. Meshes in
//! the deformation loop do get sliver triangles between remesh steps, hence the care.

use crate::geometry::Vec3;

/// Threshold on `|n|^2 / max_edge^4` (about `sin^2` of the sliver angle): below it the triangle is
/// thinner than ~1e-8 of its size, so its edges are within 1e-8 of its size, while the face
/// projection's rounding error (~1e-16 / sin) would exceed that.
const DEGENERATE_SIN2: f64 = 1e-16;

/// Closest point of segment `[a, b]` to `p`; `a == b` is answered with `a`.
#[inline]
pub fn closest_point_on_segment(p: &Vec3, a: &Vec3, b: &Vec3) -> Vec3 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    if len2 <= 0.0 || !len2.is_finite() {
        return *a;
    }
    let t = ((p - a).dot(&ab) / len2).clamp(0.0, 1.0);
    a + ab * t
}

/// Closest point of triangle `(a, b, c)` to `p`. Always returns a point of the (closed) triangle;
/// for degenerate triangles, the closest point of its edges.
#[inline]
pub fn closest_point_on_triangle(p: &Vec3, a: &Vec3, b: &Vec3, c: &Vec3) -> Vec3 {
    if is_degenerate(a, b, c) {
        closest_on_edges(p, a, b, c)
    } else {
        closest_point_on_regular_triangle(p, a, b, c)
    }
}

/// Whether the triangle is too thin for the face formula (see [`DEGENERATE_SIN2`]); true for
/// coincident corners and for NaN coordinates. Callers that query one triangle many times (the
/// BVH) evaluate this once per refit.
#[inline]
pub fn is_degenerate(a: &Vec3, b: &Vec3, c: &Vec3) -> bool {
    let ab = b - a;
    let ac = c - a;
    let n2 = ab.cross(&ac).norm_squared();
    let bc = c - b;
    // Comparisons rather than f64::max, which is a libm call in wasm.
    let (e0, e1, e2) = (ab.norm_squared(), ac.norm_squared(), bc.norm_squared());
    let e01 = if e1 > e0 { e1 } else { e0 };
    let emax = if e2 > e01 { e2 } else { e01 };
    // Written so that NaN counts as degenerate and takes the (NaN-safe) segment path.
    n2.partial_cmp(&(DEGENERATE_SIN2 * emax * emax)) != Some(std::cmp::Ordering::Greater)
}

/// [`closest_point_on_triangle`] for a triangle known not to be degenerate.
#[inline(always)] // the BVH's leaf loop: a call per triangle test was measurable
pub fn closest_point_on_regular_triangle(p: &Vec3, a: &Vec3, b: &Vec3, c: &Vec3) -> Vec3 {
    let ab = b - a;
    let ac = c - a;
    let bc = c - b;

    // Vertex region A.
    let ap = p - a;
    let d1 = ab.dot(&ap);
    let d2 = ac.dot(&ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return *a;
    }
    // Vertex region B.
    let bp = p - b;
    let d3 = ab.dot(&bp);
    let d4 = ac.dot(&bp);
    if d3 >= 0.0 && d4 <= d3 {
        return *b;
    }
    // Edge region AB (d1 - d3 = |ab|^2 > 0 because the triangle is not degenerate).
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return a + ab * v;
    }
    // Vertex region C.
    let cp = p - c;
    let d5 = ab.dot(&cp);
    let d6 = ac.dot(&cp);
    if d6 >= 0.0 && d5 <= d6 {
        return *c;
    }
    // Edge region AC (d2 - d6 = |ac|^2 > 0).
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return a + ac * w;
    }
    // Edge region BC ((d4 - d3) + (d5 - d6) = |bc|^2 > 0).
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return b + bc * w;
    }
    // Face region. Ericson returns a + ab v + ac w with v = vb / |n|^2, w = vc / |n|^2, but for
    // a sliver va, vb and vc carry absolute errors of eps |d|^2 against |n|^2 = sin^2 |e|^4,
    // which moves that point along the long edges by up to O(eps / sin^2) of their length (0.2
    // of it at sin = 1e-7). Projecting onto the plane errs by O(eps / sin) instead; a wrong
    // face/edge decision near a boundary costs the same order.
    let n = ab.cross(&ac);
    p - n * (n.dot(&ap) / n.norm_squared())
}

/// Closest point over the three edges; exact for a degenerate (collinear) triangle.
#[inline(never)]
pub fn closest_on_edges(p: &Vec3, a: &Vec3, b: &Vec3, c: &Vec3) -> Vec3 {
    let mut best = closest_point_on_segment(p, a, b);
    let mut best_d = (p - best).norm_squared();
    for (s, e) in [(b, c), (c, a)] {
        let q = closest_point_on_segment(p, s, e);
        let d = (p - q).norm_squared();
        if d < best_d {
            best = q;
            best_d = d;
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;
    use crate::spatial::testutil::SplitMix64;

    fn tri() -> [Vec3; 3] {
        [v3(0., 0., 0.), v3(2., 0., 0.), v3(0., 2., 0.)]
    }

    #[test]
    fn all_seven_regions() {
        let [a, b, c] = tri();
        let cases = [
            (v3(-1., -1., 3.), v3(0., 0., 0.)),    // vertex A
            (v3(3., -1., -2.), v3(2., 0., 0.)),    // vertex B
            (v3(-1., 3., 1.), v3(0., 2., 0.)),     // vertex C
            (v3(1., -2., 5.), v3(1., 0., 0.)),     // edge AB
            (v3(-3., 1., 0.), v3(0., 1., 0.)),     // edge AC
            (v3(2., 2., 1.), v3(1., 1., 0.)),      // edge BC
            (v3(0.5, 0.5, -4.), v3(0.5, 0.5, 0.)), // face
        ];
        for (p, want) in cases {
            let got = closest_point_on_triangle(&p, &a, &b, &c);
            assert!(
                (got - want).norm() < 1e-15,
                "p={p:?} got={got:?} want={want:?}"
            );
        }
    }

    /// Dense sampling of the triangle never beats the exact answer by more than the sampling step.
    #[test]
    fn matches_dense_sampling() {
        let mut rng = SplitMix64::new(7);
        for _ in 0..200 {
            let a = rng.vec3(-1.0, 1.0);
            let b = rng.vec3(-1.0, 1.0);
            let c = rng.vec3(-1.0, 1.0);
            let p = rng.vec3(-2.0, 2.0);
            let exact = (p - closest_point_on_triangle(&p, &a, &b, &c)).norm();
            let steps = 100;
            let mut sampled = f64::INFINITY;
            for i in 0..=steps {
                for j in 0..=(steps - i) {
                    let (u, v) = (i as f64 / steps as f64, j as f64 / steps as f64);
                    let q = a + (b - a) * u + (c - a) * v;
                    sampled = sampled.min((p - q).norm());
                }
            }
            assert!(
                exact <= sampled + 1e-12,
                "exact {exact} > sampled {sampled}"
            );
            assert!(sampled - exact < 0.06, "exact {exact} sampled {sampled}");
        }
    }

    /// Slivers (height 1e-4 .. 1e-9 of their length), rotated arbitrarily: the distance must match
    /// an exact construction in the sliver's own frame, where the answer is a 2D problem.
    #[test]
    fn slivers_are_accurate() {
        let mut rng = SplitMix64::new(21);
        let mut worst: f64 = 0.0;
        for k in 0..2000 {
            let h = 10f64.powf(-4.0 - 5.0 * rng.unit());
            // Random rotation from a random unit quaternion, random offset.
            let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            ));
            let t = rng.vec3(-2.0, 2.0);
            let world = |l: Vec3| q * l + t;
            let apex = rng.range(0.0, 1.0);
            let (la, lb, lc) = (v3(0., 0., 0.), v3(1., 0., 0.), v3(apex, h, 0.));
            // Local query: near the sliver, inside its footprint half the time.
            let lp = if k % 2 == 0 {
                let x = rng.range(0.01, 0.99);
                let top = if x < apex {
                    h * x / apex
                } else {
                    h * (1.0 - x) / (1.0 - apex)
                };
                v3(x, rng.range(0.0, 1.0) * top, rng.range(-0.5, 0.5))
            } else {
                v3(
                    rng.range(-0.3, 1.3),
                    rng.range(-0.3, 0.3),
                    rng.range(-0.5, 0.5),
                )
            };
            // Exact answer in the local frame.
            let inside = lp.y >= 0.0
                && lp.x >= 0.0
                && lp.x <= 1.0
                && lp.y * apex <= h * lp.x
                && lp.y * (1.0 - apex) <= h * (1.0 - lp.x);
            let want = if inside {
                lp.z.abs()
            } else {
                [(la, lb), (lb, lc), (lc, la)]
                    .iter()
                    .map(|(s, e)| (lp - closest_point_on_segment(&lp, s, e)).norm())
                    .fold(f64::INFINITY, f64::min)
            };
            let (a, b, c, p) = (world(la), world(lb), world(lc), world(lp));
            let got = (p - closest_point_on_triangle(&p, &a, &b, &c)).norm();
            worst = worst.max((got - want).abs());
        }
        assert!(worst < 1e-9, "worst distance error {worst:e}");
    }

    #[test]
    fn degenerate_triangles() {
        let a = v3(0., 0., 0.);
        let b = v3(1., 0., 0.);
        let c = v3(3., 0., 0.); // collinear
        let p = v3(2., 1., 0.);
        assert!((closest_point_on_triangle(&p, &a, &b, &c) - v3(2., 0., 0.)).norm() < 1e-15);
        // two coincident vertices
        let q = closest_point_on_triangle(&v3(-1., 1., 0.), &a, &a, &b);
        assert!((q - a).norm() < 1e-15);
        // all three coincident
        let q = closest_point_on_triangle(&v3(5., 5., 5.), &b, &b, &b);
        assert_eq!(q, b);
        // non-finite corner: no panic, finite query point gives something or NaN but no crash
        let _ = closest_point_on_triangle(&p, &a, &b, &v3(f64::NAN, 0., 0.));
    }
}
