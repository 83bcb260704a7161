//! One-sided lid points: a ceiling, not a floor (docs/VALIDATION.md, "Session 10, round 2: the
//! cap-to-wall corner").
//!
//! The end caps' lid points (`ends`) mark where the data stop. Pulling the mesh onto them both ways
//! does two things: it stops the end running on past the data (wanted), and it drags the rounded
//! rim, where the wall curves in below the lid's plane, up and out into the plane's flat corner
//! (not wanted: there the wall data are the only evidence, and the corner is where the accuracy
//! maxima and the folds of the two-sided caps sat). So a lid point starts to pull only once its
//! closest mesh point lies past its plane, outwards beyond the data, by more than a small share of
//! the lid points' spacing, and stops once the mesh is back inside the plane by as much; a point
//! not pulling is left out of that step's fit.
//!
//! Why the hysteresis: a pulling point brings the mesh towards the plane from outside and would
//! drop out at the tolerance, then pull again a few steps later. Every switch changes the size of
//! the spline's system, which then factorises instead of reusing the last factor (measured on
//! SurFCo: with a single threshold 149 of 236 fits factorised, +26% instructions; with the
//! hysteresis +9%). Deciding only at the attractor re-samplings (free for the solver) was tried
//! and measured worse on the real files (docs).

use crate::geometry::Vec3;

/// Where a lid point's plane faces: `normal` is the unit normal of the lid's plane at the point,
/// pointing outwards (past the data); `tolerance` (same units as the points) is how far past the
/// plane the mesh may lie before the point pulls.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LidSide {
    pub normal: Vec3,
    pub tolerance: f64,
    /// The point's data weight while it pulls.
    pub weight: f64,
}

/// A lid point pulls once the mesh lies this share of the lid points' spacing past its plane: the
/// spacing is the resolution the attractors describe the surface at, and a tenth of it is below
/// what the fit resolves (and keeps the rule from switching on rounding).
pub const ONE_SIDED_TOLERANCE_PER_SPACING: f64 = 0.1;

/// Marks a lid point left out of a step's fit ([`apply`] removes it). Left out rather than kept
/// with a vanishing weight: a weight switching between 0.3 and 1e-6 spoils the factor the solver
/// reuses as a preconditioner (measured on SurFCo: every reuse failed).
pub const RELEASED_WEIGHT: f64 = 0.0;

/// Whether the mesh point `closest` (of lid point `lid`) lies past the lid's plane by more than
/// the tolerance.
pub fn past_lid(lid: &Vec3, closest: &Vec3, side: &LidSide) -> bool {
    (closest - lid).dot(&side.normal) > side.tolerance
}

/// The weights of this step's lid points at `first..` of `lids` (`closest` aligned with `lids`,
/// `sides[k - first]` for index k) into `out`, which holds the last step's: a point that was not
/// pulling pulls once [`past_lid`], one that was pulling goes on while [`holds_lid`]; pulling
/// points get their side's weight, the others [`RELEASED_WEIGHT`]. Returns how many pull.
pub fn decide(
    first: usize,
    lids: &[Vec3],
    closest: &[Vec3],
    sides: &[LidSide],
    out: &mut Vec<f64>,
) -> usize {
    let before = std::mem::take(out);
    for (k, side) in sides.iter().enumerate() {
        let (Some(q), Some(c)) = (lids.get(first + k), closest.get(first + k)) else {
            break;
        };
        let was = before.get(k).is_some_and(|&w| w > RELEASED_WEIGHT);
        let pulls = if was {
            holds_lid(q, c, side)
        } else {
            past_lid(q, c, side)
        };
        out.push(if pulls { side.weight } else { RELEASED_WEIGHT });
    }
    out.iter().filter(|&&w| w > RELEASED_WEIGHT).count()
}

/// Whether a lid point that pulls goes on pulling: while its mesh point is not back inside the
/// plane by more than the tolerance (the hysteresis of the module's doc).
pub fn holds_lid(lid: &Vec3, closest: &Vec3, side: &LidSide) -> bool {
    (closest - lid).dot(&side.normal) > -side.tolerance
}

/// Applies decided lid weights (`lid_weights[k]` for index `first + k`) to a step's `closest`,
/// `targets` and `weights`: a pulling point gets its weight, a released one is removed from all
/// three (left out of the fit; order kept). Lid points past `lid_weights` are kept as they are.
pub fn apply(
    first: usize,
    lid_weights: &[f64],
    closest: &mut Vec<Vec3>,
    targets: &mut Vec<Vec3>,
    weights: &mut Vec<f64>,
) {
    let len = closest.len().min(targets.len()).min(weights.len());
    let mut j = first.min(len);
    for i in first.min(len)..len {
        let lw = lid_weights.get(i - first).copied();
        if lw.is_some_and(|w| w <= RELEASED_WEIGHT) {
            continue;
        }
        closest[j] = closest[i];
        targets[j] = targets[i];
        weights[j] = lw.unwrap_or(weights[i]);
        j += 1;
    }
    closest.truncate(j);
    targets.truncate(j);
    weights.truncate(j);
}

/// The outward unit normal of a lid plane whose height along `axis` changes by `gradient` per mm
/// across it (`outward` +1 at the base, -1 at the apex): the plane is {x : x.axis - x.gradient =
/// const}, so its normal is along axis - gradient.
pub fn lid_normal(axis: &Vec3, gradient: &Vec3, outward: f64) -> Vec3 {
    let n = axis - gradient;
    n.try_normalize(1e-300).unwrap_or(*axis) * outward.signum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    const Z: Vec3 = Vec3::new(0.0, 0.0, 1.0);

    #[test]
    fn pulls_only_past_the_plane() {
        let side = LidSide {
            normal: Z,
            tolerance: 0.2,
            weight: 0.3,
        };
        let q = v3(1.0, 2.0, 10.0);
        // 0.3 past the plane (> 0.2): pulls; 0.2 exactly, 0.1 past, on it, below it: released.
        assert!(past_lid(&q, &v3(1.0, 2.0, 10.3), &side));
        assert!(!past_lid(&q, &v3(1.0, 2.0, 10.2), &side));
        assert!(!past_lid(&q, &v3(1.0, 2.0, 10.1), &side));
        assert!(!past_lid(&q, &q, &side));
        assert!(!past_lid(&q, &v3(1.0, 2.0, 7.0), &side));
        // Sideways moves do not count, only the height over the plane.
        assert!(past_lid(&q, &v3(9.0, -5.0, 10.25), &side));
        // At the apex the outside is below.
        let apex = LidSide {
            normal: -Z,
            tolerance: 0.2,
            weight: 0.3,
        };
        assert!(past_lid(&q, &v3(1.0, 2.0, 9.5), &apex));
        assert!(!past_lid(&q, &v3(1.0, 2.0, 10.5), &apex));
    }

    #[test]
    fn released_points_neither_pull_nor_move() {
        // Two contour points (untouched), then three lid points at z = 0 facing +z.
        let lids = [
            v3(0.0, 0.0, 5.0),
            v3(1.0, 0.0, 5.0),
            v3(0.0, 0.0, 0.0),
            v3(1.0, 0.0, 0.0),
            v3(2.0, 0.0, 0.0),
        ];
        let closest = [
            v3(0.0, 0.0, 4.0),
            v3(1.0, 0.0, 4.0),
            v3(0.0, 0.0, 2.0),  // 2 past: pulls
            v3(1.0, 0.0, -1.0), // below: released
            v3(2.5, 0.0, 0.05), // 0.05 past, inside the 0.1 tolerance: released
        ];
        let side = LidSide {
            normal: Z,
            tolerance: 0.1,
            weight: 0.3,
        };
        let mut lid_weights = Vec::new();
        let n = decide(2, &lids, &closest, &[side; 3], &mut lid_weights);
        assert_eq!(n, 1);
        assert_eq!(lid_weights, vec![0.3, RELEASED_WEIGHT, RELEASED_WEIGHT]);
        let mut weights = vec![1.0; 5];
        let mut targets: Vec<Vec3> = closest
            .iter()
            .zip(&lids)
            .map(|(c, q)| c + (q - c) * 0.5)
            .collect();
        let mut kept = closest.to_vec();
        let before = targets.clone();
        apply(2, &lid_weights, &mut kept, &mut targets, &mut weights);
        // The two released points are left out: contour points and the pulling one remain.
        assert_eq!(weights, vec![1.0, 1.0, 0.3]);
        assert_eq!(targets, before[..3].to_vec());
        assert_eq!(targets[2], v3(0.0, 0.0, 1.0));
        assert_eq!(kept, closest[..3].to_vec());
        // The next step: the pulling point has brought its mesh to 0.05 inside the plane (within
        // the tolerance: goes on pulling); the released one at 0.05 past stays released; the
        // first released one is now 0.15 past (> 0.1: starts).
        let next = [
            closest[0],
            closest[1],
            v3(0.0, 0.0, -0.05),
            v3(1.0, 0.0, 0.15),
            v3(2.0, 0.0, 0.05),
        ];
        assert_eq!(decide(2, &lids, &next, &[side; 3], &mut lid_weights), 2);
        assert_eq!(lid_weights, vec![0.3, 0.3, RELEASED_WEIGHT]);
        // Then back inside by 0.15 (beyond the tolerance): released.
        let inside = [next[0], next[1], v3(0.0, 0.0, -0.15), next[3], next[4]];
        assert_eq!(decide(2, &lids, &inside, &[side; 3], &mut lid_weights), 1);
        assert_eq!(lid_weights, vec![RELEASED_WEIGHT, 0.3, RELEASED_WEIGHT]);
        // Fewer slots than sides: stops without panicking.
        lid_weights.clear();
        assert_eq!(decide(4, &lids, &closest, &[side; 3], &mut lid_weights), 0);
        assert_eq!(lid_weights, vec![RELEASED_WEIGHT]);
        let mut w = vec![1.0; 5];
        let (mut c, mut t) = (closest.to_vec(), closest.to_vec());
        apply(4, &[0.3, 0.3, 0.3], &mut c, &mut t, &mut w);
        assert_eq!((c.len(), t.len(), w), (5, 5, vec![1.0, 1.0, 1.0, 1.0, 0.3]));
    }

    #[test]
    fn tilted_plane_normal() {
        // Height rising 1 mm per mm along x: the plane z - x = c, normal (-1, 0, 1) / sqrt 2.
        let n = lid_normal(&Z, &v3(1.0, 0.0, 0.0), 1.0);
        let s = 0.5f64.sqrt();
        assert!((n - v3(-s, 0.0, s)).norm() < 1e-15, "{n:?}");
        assert_eq!(lid_normal(&Z, &Vec3::zeros(), -1.0), -Z);
    }
}
