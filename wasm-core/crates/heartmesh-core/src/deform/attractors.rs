//! Attractor selection by farthest-point sampling (Villard et al. 2018, section 2.3; the sampling
//! itself is the classic greedy k-centre heuristic of Gonzalez 1985).
//!
//! Farthest-point sampling spreads a fixed budget of thin-plate-spline centres evenly over all contour
//! points, whatever their original density, so dense and sparse contours pull equally.

use crate::geometry::Vec3;

/// How many attractors to pick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Budget {
    Count(usize),
    /// Keep adding points while the farthest remaining point is at least this far (same units as the
    /// points) from every chosen one.
    Spacing(f64),
}

/// Greedy farthest-point sampling starting at `seed`. Returns indices into `points`, in the order
/// chosen. `dist` is scratch space (resized as needed) so repeated calls do not allocate.
pub fn farthest_point_sampling(
    points: &[Vec3],
    seed: usize,
    budget: Budget,
    min_count: usize,
    dist: &mut Vec<f64>,
) -> Vec<usize> {
    if points.is_empty() {
        return Vec::new();
    }
    let seed = seed.min(points.len() - 1);
    dist.clear();
    dist.resize(points.len(), f64::INFINITY);
    let max_count = match budget {
        Budget::Count(n) => n.min(points.len()),
        Budget::Spacing(_) => points.len(),
    };
    let mut chosen = Vec::with_capacity(max_count.min(4096));
    // Structure of arrays, so the distance update (the bulk of the work) vectorises.
    let xs: Vec<f64> = points.iter().map(|p| p.x).collect();
    let ys: Vec<f64> = points.iter().map(|p| p.y).collect();
    let zs: Vec<f64> = points.iter().map(|p| p.z).collect();
    let mut next = seed;
    while chosen.len() < max_count {
        chosen.push(next);
        let c = points[next];
        update_nearest(dist, &xs, &ys, &zs, c);
        // The first index of the largest distance (a NaN never wins).
        let mut far = (f64::NEG_INFINITY, 0usize);
        for (i, &d) in dist.iter().enumerate() {
            if d > far.0 {
                far = (d, i);
            }
        }
        if far.0 <= 0.0 {
            break;
        }
        if let Budget::Spacing(s) = budget {
            if chosen.len() >= min_count && far.0.sqrt() < s {
                break;
            }
        }
        next = far.1;
    }
    chosen
}

/// dist[i] = min(dist[i], |p_i - c|^2). Elementwise, so the 256-bit AVX build (dispatched at run
/// time; no FMA) gives the same bits as the baseline 128-bit one, with half the instructions.
fn update_nearest(dist: &mut [f64], xs: &[f64], ys: &[f64], zs: &[f64], c: Vec3) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU has AVX.
        return unsafe { update_nearest_avx(dist, xs, ys, zs, c) };
    }
    update_nearest_lanes(dist, xs, ys, zs, c)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn update_nearest_avx(dist: &mut [f64], xs: &[f64], ys: &[f64], zs: &[f64], c: Vec3) {
    update_nearest_lanes(dist, xs, ys, zs, c)
}

#[inline(always)]
fn update_nearest_lanes(dist: &mut [f64], xs: &[f64], ys: &[f64], zs: &[f64], c: Vec3) {
    for (((d, x), y), z) in dist.iter_mut().zip(xs).zip(ys).zip(zs) {
        let (dx, dy, dz) = (x - c.x, y - c.y, z - c.z);
        let e = dx * dx + dy * dy + dz * dz;
        if e < *d {
            *d = e;
        }
    }
}

/// Per-attractor data weights that soften conflicts between contours.
///
/// Where two contours disagree (a short- and a long-axis curve a few mm apart where their planes
/// cross: segmentation and breath-hold error), the attractors of both pull nearby parts of the
/// surface to different places. The displacement the data ask for, d_i = Q_i - P_i, then changes
/// faster than the surface can follow: a map x -> x + d(x) stays one-to-one only while the
/// gradient of d stays below 1, and a nearly interpolating spline driven past that creases the
/// surface. For each attractor, g_i is the largest |d_i - d_j| / |P_i - P_j| over attractors j of
/// another group (`owner`: the pipeline passes short- vs long-axis) whose data point lies within
/// `radius`. Pairs within a group are never compared: curves of one slice meet at sharp corners
/// (the RV free wall and septum at the insertions) that are data, not conflict.
/// The weight is 1 up to `limit` (the surface can follow: nothing changes) and (limit / g_i)^2
/// beyond, falling as the asked-for gradient passes what the surface can follow. Returns true
/// when any weight is below 1 (else the caller's fit is the unweighted one).
pub fn conflict_weights(
    attractors: &[Vec3],
    closest: &[Vec3],
    owner: &[u32],
    radius: f64,
    limit: f64,
    weights: &mut Vec<f64>,
) -> bool {
    let n = attractors.len().min(closest.len()).min(owner.len());
    // The buffer holds each attractor's largest gradient first, then its weight.
    let grad = weights;
    grad.clear();
    grad.resize(n, 0.0);
    let r2 = radius * radius;
    let mut any = false;
    for i in 0..n {
        let di = attractors[i] - closest[i];
        for j in (i + 1)..n {
            if owner[i] == owner[j] || (attractors[i] - attractors[j]).norm_squared() > r2 {
                continue;
            }
            let dj = attractors[j] - closest[j];
            let span = (closest[i] - closest[j]).norm();
            let change = (di - dj).norm();
            // Coincident closest points with different displacements: an unbounded gradient.
            let g = if span > 0.0 {
                change / span
            } else if change > 0.0 {
                f64::INFINITY
            } else {
                0.0
            };
            grad[i] = grad[i].max(g);
            grad[j] = grad[j].max(g);
        }
    }
    for w in grad.iter_mut() {
        let x = *w / limit;
        // Floor: the solver needs a positive weight; 1e-6 already leaves the point no pull.
        *w = if x <= 1.0 {
            1.0
        } else {
            (1.0 / (x * x)).max(MIN_WEIGHT)
        };
        any |= *w < 1.0;
    }
    any
}

/// Smallest conflict weight (the thin-plate-spline system needs a positive diagonal).
const MIN_WEIGHT: f64 = 1e-6;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    #[test]
    fn picks_extremes_first_and_respects_spacing() {
        let pts: Vec<Vec3> = (0..=100).map(|i| v3(i as f64, 0.0, 0.0)).collect();
        let mut scratch = Vec::new();
        let idx = farthest_point_sampling(&pts, 50, Budget::Count(3), 0, &mut scratch);
        assert_eq!(idx, vec![50, 0, 100]);
        let idx = farthest_point_sampling(&pts, 0, Budget::Spacing(10.0), 0, &mut scratch);
        // Spacing 10 on a 100-long line: 0, 100, 50, 25, 75, then 12/13... stop once gaps < 10:
        let mut xs: Vec<f64> = idx.iter().map(|&i| pts[i].x).collect();
        xs.sort_by(f64::total_cmp);
        let max_gap = xs.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
        assert!(max_gap <= 20.0, "{max_gap}");
        assert!(idx.len() >= 9 && idx.len() <= 17, "{}", idx.len());
    }

    /// Two contours 3 mm apart where they meet pull one closest point both ways: both lose weight.
    /// The same displacements on one contour (a sharp corner in the data), or agreeing
    /// displacements on two, keep full weight.
    #[test]
    fn conflicting_contours_lose_weight_corners_do_not() {
        let attractors = [
            v3(0.0, 0.0, 1.5),
            v3(1.0, 0.0, -1.5),
            v3(30.0, 0.0, 0.0),
            v3(0.0, 40.0, 0.0),
            v3(0.0, 41.0, 3.0),
        ];
        let closest = [
            v3(0.0, 0.0, 0.0),
            v3(1.0, 0.0, 0.0),
            v3(30.0, 0.0, 0.0),
            v3(0.0, 40.0, 0.0),
            v3(0.0, 41.0, 0.0),
        ];
        let mut w = Vec::new();
        // Attractors 0/1: displacements +1.5 and -1.5 over 1 mm, a gradient of 3.
        assert!(conflict_weights(
            &attractors,
            &closest,
            &[0, 1, 1, 2, 2],
            10.0,
            1.0,
            &mut w
        ));
        assert!(
            (w[0] - 1.0 / 9.0).abs() < 1e-12 && (w[1] - 1.0 / 9.0).abs() < 1e-12,
            "{w:?}"
        );
        // 2 is too far from anyone; 3/4 are one contour (a corner): untouched.
        assert_eq!(&w[2..], &[1.0, 1.0, 1.0]);
        // Agreeing displacements on two contours: no conflict.
        let shifted: Vec<Vec3> = closest.iter().map(|p| p + v3(0.0, 0.0, 2.0)).collect();
        assert!(!conflict_weights(
            &shifted,
            &closest,
            &[0, 1, 2, 3, 4],
            10.0,
            1.0,
            &mut w
        ));
        assert!(w.iter().all(|&x| x == 1.0), "{w:?}");
        // Coincident closest points asked to move apart: the floor, never zero.
        let same = [v3(0.0, 0.0, 0.0); 2];
        conflict_weights(
            &[v3(0.0, 0.0, 1.0), v3(0.0, 0.0, -1.0)],
            &same,
            &[0, 1],
            10.0,
            1.0,
            &mut w,
        );
        assert!(w.iter().all(|&x| x > 0.0 && x < 1e-5), "{w:?}");
    }

    #[test]
    fn duplicates_do_not_loop() {
        let pts = vec![v3(1.0, 1.0, 1.0); 10];
        let mut scratch = Vec::new();
        let idx = farthest_point_sampling(&pts, 0, Budget::Count(5), 0, &mut scratch);
        assert_eq!(idx, vec![0]);
    }
}
