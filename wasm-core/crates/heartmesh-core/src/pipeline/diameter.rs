//! The scale of a contour set: its largest inter-point distance.

use crate::geometry::Vec3;

/// Above this many candidate points the diameter is estimated by repeated farthest-point sweeps
/// instead of all pairs (a scale factor only needs to be consistent, not exact).
const EXACT_DIAMETER_LIMIT: usize = 6000;

/// Largest inter-point distance (exact up to [`EXACT_DIAMETER_LIMIT`] points, else the best of a few
/// farthest-point sweeps).
pub(super) fn diameter(points: &[Vec3]) -> f64 {
    if points.len() <= EXACT_DIAMETER_LIMIT {
        // Four running maxima instead of one: a single `best = best.max(..)` chain waits on the
        // previous comparison at every pair (millions of pairs). The maximum of a set of finite
        // numbers does not depend on the order they are compared in, so the result is the same bits.
        let mut lanes = [0.0f64; 4];
        for (i, a) in points.iter().enumerate() {
            let rest = &points[i + 1..];
            let mut quads = rest.chunks_exact(4);
            for q in &mut quads {
                for (lane, b) in lanes.iter_mut().zip(q) {
                    *lane = lane.max((a - b).norm_squared());
                }
            }
            for b in quads.remainder() {
                lanes[0] = lanes[0].max((a - b).norm_squared());
            }
        }
        return lanes.iter().fold(0.0f64, |m, &l| m.max(l)).sqrt();
    }
    let mut from = 0usize;
    let mut best = 0.0f64;
    for _ in 0..4 {
        let (d, i) = points
            .iter()
            .enumerate()
            .map(|(i, p)| ((p - points[from]).norm_squared(), i))
            .fold((0.0, from), |a, b| if b.0 > a.0 { b } else { a });
        best = best.max(d);
        from = i;
    }
    best.sqrt()
}

#[cfg(test)]
mod tests {
    use super::diameter;
    use crate::geometry::Vec3;
    use crate::sim::prng::SplitMix64;

    /// The four-lane exact diameter equals the plain pair loop bit for bit, for every remainder of
    /// the lanes (point counts 1..=13) and for a few hundred points.
    #[test]
    fn four_lane_diameter_is_the_pair_maximum() {
        let mut rng = SplitMix64::new(11);
        for n in (1..=13).chain([257, 1001]) {
            let pts: Vec<Vec3> = (0..n)
                .map(|_| {
                    Vec3::new(
                        rng.uniform(-80.0, 80.0),
                        rng.uniform(-60.0, 60.0),
                        rng.uniform(-300.0, 300.0),
                    )
                })
                .collect();
            let mut best = 0.0f64;
            for (i, a) in pts.iter().enumerate() {
                for b in &pts[i + 1..] {
                    best = best.max((a - b).norm_squared());
                }
            }
            assert_eq!(diameter(&pts).to_bits(), best.sqrt().to_bits(), "n = {n}");
        }
    }
}
