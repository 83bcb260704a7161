//! The initial mesh M0: a ruled tube through the short-axis rings, closed by lids
//! (Villard et al. 2018, section 2.2; METHOD.md sections 2 and 3).

use crate::contours::axis::Layout;
use crate::contours::{Contour, ContourKind};
use crate::geometry::{centroid, order_free_centroid, Vec3};
use crate::mesh::TriMesh;
use crate::params::LidMode;

/// Where the lids go: apex (below the first ring) and base (above the last), if any.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lids {
    pub apex: Option<Vec3>,
    pub base: Option<Vec3>,
}

/// Lid points: each end ring's centroid, moved along the axis to the farthest long-axis point beyond
/// that ring (no LAX, or LAX not reaching past the ring: the lid stays flat at the ring).
pub fn lids(mode: &LidMode, rings: &[Vec<Vec3>], contours: &[Contour], layout: &Layout) -> Lids {
    let (Some(first), Some(last)) = (rings.first(), rings.last()) else {
        return Lids {
            apex: None,
            base: None,
        };
    };
    let z = layout.axis;
    let lax_heights = contours
        .iter()
        .zip(&layout.kinds)
        .filter(|(_, k)| **k == ContourKind::Lax)
        .flat_map(|(c, _)| c.points().map(|p| p.dot(&z)));
    let (lo, hi) = lax_heights.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), h| {
        (lo.min(h), hi.max(h))
    });
    // The apex of a ventricle need not lie above the centre of its most apical ring (the RV's does
    // not): where long-axis curves reach below that ring, the lid goes under the mean of their
    // lowest points, else under the ring's centroid. "Below" means by more than a rounding-size
    // tolerance: a curve ending in the ring's own plane (a flat-bottomed phantom, or slices
    // shifted by --align-slices by 1e-15 mm) would otherwise put the lid on the ring's rim, and
    // a lid on a ring vertex makes zero-area fan triangles that the first remesh refuses.
    let ring_centre = centroid(first);
    let ring_height = ring_centre.dot(&z);
    let tolerance = MIN_LID_GAP_PER_RADIUS * mean_radius(first, &ring_centre);
    let lowest: Vec<Vec3> = contours
        .iter()
        .zip(&layout.kinds)
        .filter(|(_, k)| **k == ContourKind::Lax)
        .filter_map(|(c, _)| lowest_points_centroid(c, &z, TIE_PER_RADIUS * tolerance))
        .filter(|p| p.dot(&z) < ring_height - tolerance)
        .collect();
    let auto_apex = {
        let c = if lowest.is_empty() {
            ring_centre
        } else {
            // One point per curve, in the file's order of curves: summed in an order of their own.
            order_free_centroid(&lowest)
        };
        c + z * (lo.min(ring_height) - c.dot(&z))
    };
    let auto_base = {
        let c = centroid(last);
        let h = c.dot(&z);
        c + z * (hi.max(h) - h)
    };
    match mode {
        LidMode::None => Lids {
            apex: None,
            base: None,
        },
        LidMode::Auto => Lids {
            apex: Some(auto_apex),
            base: Some(auto_base),
        },
        LidMode::Explicit { apex, base } => Lids {
            apex: Some(apex.unwrap_or(auto_apex)),
            base: Some(base.unwrap_or(auto_base)),
        },
    }
}

fn mean_radius(ring: &[Vec3], centre: &Vec3) -> f64 {
    ring.iter().map(|p| (p - centre).norm()).sum::<f64>() / ring.len().max(1) as f64
}

/// Heights closer than this share of [`MIN_LID_GAP_PER_RADIUS`]'s tolerance are ties (rounding of
/// an exactly flat part; neighbouring points of a measured curve's rounded bottom differ by ~1e-3 of
/// the radius, far more, so they stay distinct).
const TIE_PER_RADIUS: f64 = 1e-6;

/// The centroid of a curve's points within `tolerance` of its lowest height along `z`: its lowest
/// point, or the middle of an exactly flat bottom (a curve across a flat-bottomed phantom has many
/// lowest points, and taking the first listed would put the lid at one end of the flat part).
fn lowest_points_centroid(c: &Contour, z: &Vec3, tolerance: f64) -> Option<Vec3> {
    let low = c.points().map(|p| p.dot(z)).min_by(|a, b| a.total_cmp(b))?;
    let ties: Vec<Vec3> = c
        .points()
        .filter(|p| p.dot(z) <= low + tolerance)
        .copied()
        .collect();
    Some(centroid(&ties))
}

/// Share of the way from the most basal ring to the base lid at which [`extend_to_base`] adds a ring.
/// Below 1 so the lid stays a shallow cone rather than a flat fan folded at the rim (measured in
/// docs/VALIDATION.md: 0.5, 0.9 and 1.0 all lower the LV means; 0.9 kept the maxima lowest).
const BASE_RING_FRACTION: f64 = 0.9;

/// Smallest lid height beyond an end ring, as a share of that ring's mean radius, that counts: for
/// [`extend_to_base`] to add a ring, and for long-axis curves to count as reaching below the apical
/// ring in [`lids`] (a scale-free tolerance, so millimetre and centimetre files agree).
const MIN_LID_GAP_PER_RADIUS: f64 = 1e-3;

/// Where the long-axis curves run on above the most basal short-axis ring (open LV curves reach the
/// valve plane, often 10-20 mm higher), the wall there is nearly parallel to the axis, not a cone
/// closing on the lid: the tube gets one more ring, the basal ring moved up most of the way to the
/// lid, so the initial mesh already has that wall and the deformation only has to refine it.
pub fn extend_to_base(rings: &mut Vec<Vec<Vec3>>, lids: &Lids, z: &Vec3) {
    let (Some(base), Some(last)) = (lids.base, rings.last()) else {
        return;
    };
    let centre = centroid(last);
    let gap = (base - centre).dot(z);
    // Long-axis curves that end in the basal slice's own plane leave a gap of rounding size: a ring
    // there would sit on the basal ring and make a band of zero-area triangles, which the first
    // remesh refuses. Below a thousandth of the ring's radius the extension adds nothing anyway.
    if !(gap.is_finite() && gap > MIN_LID_GAP_PER_RADIUS * mean_radius(last, &centre)) {
        return;
    }
    let shift = z * (gap * BASE_RING_FRACTION);
    let ring: Vec<Vec3> = last.iter().map(|p| p + shift).collect();
    rings.push(ring);
}

/// Triangulates consecutive rings (all of the same length, counter-clockwise about the axis, apex to
/// base) two triangles per quad, with fan lids; faces point outwards.
pub fn ruled_tube(rings: &[Vec<Vec3>], lids: &Lids) -> TriMesh {
    let k = rings.first().map_or(0, |r| r.len());
    let mut positions: Vec<Vec3> = rings.iter().flatten().copied().collect();
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(2 * k * rings.len());
    let idx = |ring: usize, i: usize| (ring * k + i % k) as u32;
    for j in 0..rings.len().saturating_sub(1) {
        for i in 0..k {
            triangles.push([idx(j, i), idx(j, i + 1), idx(j + 1, i)]);
            triangles.push([idx(j + 1, i), idx(j, i + 1), idx(j + 1, i + 1)]);
        }
    }
    if let Some(apex) = lids.apex {
        let a = positions.len() as u32;
        positions.push(apex);
        for i in 0..k {
            triangles.push([a, idx(0, i + 1), idx(0, i)]);
        }
    }
    if let Some(base) = lids.base {
        let b = positions.len() as u32;
        positions.push(base);
        let last = rings.len() - 1;
        for i in 0..k {
            triangles.push([b, idx(last, i), idx(last, i + 1)]);
        }
    }
    TriMesh::new(positions, triangles)
}

/// Where the ruled tube of [`ruled_tube`] (`k` points per ring, `rings` rings, then the lids)
/// has a triangle of zero area: the two rings it joins (a lid counts as ring `rings`), or None
/// when every triangle has an area. Such a triangle (two rings that share a point, a ring folded
/// on itself) leaves no tube to deform: remeshing refuses it. Real slices never touch; contours
/// that do are points of several slices under one name.
pub fn zero_area_between(mesh: &TriMesh, rings: usize, k: usize) -> Option<(usize, usize)> {
    let ring_of = |v: u32| (v as usize / k.max(1)).min(rings);
    (0..mesh.triangles.len()).find_map(|t| {
        let [a, b, c] = mesh.corners(t);
        let n = (b - a).cross(&(c - a)).norm();
        let scale = (b - a)
            .norm_squared()
            .max((c - a).norm_squared())
            .max((c - b).norm_squared());
        // The remesh's own test of a degenerate triangle (`mesh::topology`).
        (n.is_nan() || n <= 1e-12 * scale).then(|| {
            let r = mesh.triangles[t].map(ring_of);
            (
                r.iter().copied().min().unwrap_or(0),
                r.iter().copied().max().unwrap_or(0),
            )
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    #[test]
    fn base_ring_added_below_a_high_lid_only() {
        let ring: Vec<Vec3> = (0..8)
            .map(|i| {
                let a = i as f64 / 8.0 * std::f64::consts::TAU;
                v3(10.0 * a.cos(), 10.0 * a.sin(), 0.0)
            })
            .collect();
        let z = v3(0.0, 0.0, 1.0);
        let mut rings = vec![ring.clone()];
        let high = Lids {
            apex: None,
            base: Some(v3(0.0, 0.0, 20.0)),
        };
        extend_to_base(&mut rings, &high, &z);
        assert_eq!(rings.len(), 2);
        assert!((rings[1][3] - (ring[3] + z * 18.0)).norm() < 1e-12);
        // A lid at the ring's height (no LAX above it) or none: unchanged.
        let mut rings = vec![ring.clone()];
        let flat = Lids {
            apex: None,
            base: Some(v3(0.0, 0.0, 0.0)),
        };
        extend_to_base(&mut rings, &flat, &z);
        // Long-axis curves ending in the basal plane, up to rounding: no ring on top of the last.
        let rounding = Lids {
            apex: None,
            base: Some(v3(0.0, 0.0, 3.7e-15)),
        };
        extend_to_base(&mut rings, &rounding, &z);
        extend_to_base(
            &mut rings,
            &Lids {
                apex: None,
                base: None,
            },
            &z,
        );
        assert_eq!(rings.len(), 1);
    }

    /// Two rings that share a point (points of two slices under one name) leave triangles of no
    /// area between them, found with the rings they join; apart, none.
    #[test]
    fn rings_that_touch_are_found() {
        let circle = |z: f64| -> Vec<Vec3> {
            (0..8)
                .map(|i| {
                    let a = i as f64 / 8.0 * std::f64::consts::TAU;
                    v3(10.0 * a.cos(), 10.0 * a.sin(), z)
                })
                .collect()
        };
        let lids = Lids {
            apex: Some(v3(0.0, 0.0, -5.0)),
            base: Some(v3(0.0, 0.0, 25.0)),
        };
        let apart = vec![circle(0.0), circle(10.0), circle(20.0)];
        assert_eq!(zero_area_between(&ruled_tube(&apart, &lids), 3, 8), None);
        let mut touching = apart.clone();
        touching[2][3] = touching[1][3];
        assert_eq!(
            zero_area_between(&ruled_tube(&touching, &lids), 3, 8),
            Some((1, 2))
        );
    }

    #[test]
    fn closed_tube_has_outward_faces_and_right_counts() {
        let rings: Vec<Vec<Vec3>> = [0.0, 10.0, 20.0]
            .iter()
            .map(|&z| {
                (0..50)
                    .map(|i| {
                        let a = i as f64 / 50.0 * std::f64::consts::TAU;
                        v3(10.0 * a.cos(), 10.0 * a.sin(), z)
                    })
                    .collect()
            })
            .collect();
        let m = ruled_tube(
            &rings,
            &Lids {
                apex: Some(v3(0., 0., -5.)),
                base: Some(v3(0., 0., 25.)),
            },
        );
        assert_eq!(m.positions.len(), 152);
        assert_eq!(m.triangles.len(), 2 * 50 * 2 + 100);
        // Cylinder 20 mm tall of a 50-gon plus two cones of height 5.
        let polygon_area = 0.5 * 50.0 * 100.0 * (std::f64::consts::TAU / 50.0).sin();
        let expected = polygon_area * (20.0 + 2.0 * 5.0 / 3.0);
        assert!(
            (m.signed_volume() - expected).abs() < 1e-6 * expected,
            "{}",
            m.signed_volume()
        );
    }
}
