//! Outlines of a structure in each slice of a label map, as closed curves in millimetres.
//!
//! Each slice's mask is traced with marching squares (the `contour` crate, linear interpolation
//! on the 0/1 mask, so the outline runs along the pixel edges through their midpoints, as the
//! contour a reader would draw around the pixels does) and placed in the world with the volume's
//! affine. Holes inside a structure (papillary muscles segmented apart) are filled: the method
//! reconstructs the cavity's outer boundary.

use super::volume::LabelVolume;
use crate::geometry::Vec3;

/// Loops enclosing fewer pixels than this are single stray voxels or pairs, which outline as
/// diamonds of 4-6 points rather than curves; they are counted and left out.
pub const MIN_LOOP_PIXELS: f64 = 2.0;

/// The slices to trace: across which voxel axis, and which indices along it.
#[derive(Debug, Clone, PartialEq)]
pub struct SlicePlan {
    /// Voxel axis (0 i, 1 j, 2 k) the slices are taken across: the one with the widest spacing.
    pub axis: usize,
    /// Every `step`-th slice is traced (1 for a stack of thick slices).
    pub step: usize,
    /// Spacing of the traced slices (mm).
    pub spacing_mm: f64,
}

/// Slices a label map is traced in. A short-axis stack has one axis of thick slices (5-10 mm):
/// each is traced. A volume of near-cubic voxels (a 3D acquisition) is traced every ~5 mm along its
/// k axis: a curve per millimetre would add thousands of points and nothing the method uses.
pub fn plan(volume: &LabelVolume) -> SlicePlan {
    let spacing = volume.spacing();
    let mut axis = 2;
    for a in [1, 0] {
        if spacing[a] > spacing[axis] * 1.01 {
            axis = a;
        }
    }
    let step = if spacing[axis] < 5.0 {
        ((5.0 / spacing[axis]).round() as usize).max(1)
    } else {
        1
    };
    SlicePlan {
        axis,
        step,
        spacing_mm: spacing[axis] * step as f64,
    }
}

/// One traced loop.
#[derive(Debug, Clone)]
pub struct Loop {
    /// Slice index along the plan's axis.
    pub slice: usize,
    /// Enclosed area in pixels.
    pub pixels: f64,
    pub points: Vec<Vec3>,
}

/// The outlines of the voxels whose label is in `labels`, slice by slice (largest
/// loop of a slice first), and the number of loops under [`MIN_LOOP_PIXELS`] left out.
pub fn trace(volume: &LabelVolume, labels: &[u16], plan: &SlicePlan) -> (Vec<Loop>, usize) {
    let d = volume.dims;
    let (u, v) = match plan.axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    let stride = [1, d[0], d[0] * d[1]];
    let values = &volume.labels;
    let mut loops = Vec::new();
    let mut specks = 0;
    let mut mask = vec![0.0; d[u] * d[v]];
    let builder = contour::ContourBuilder::new(d[u], d[v], true);
    for s in (0..d[plan.axis]).step_by(plan.step) {
        let mut any = false;
        for y in 0..d[v] {
            for x in 0..d[u] {
                let n = s * stride[plan.axis] + x * stride[u] + y * stride[v];
                let inside = labels.contains(&values[n]);
                any |= inside;
                mask[x + d[u] * y] = if inside { 1.0 } else { 0.0 };
            }
        }
        if !any {
            continue;
        }
        let Ok(found) = builder.contours(&mask, &[0.5]) else {
            continue;
        };
        let mut here: Vec<Loop> = Vec::new();
        for polygon in found.iter().flat_map(|c| c.geometry().0.iter()) {
            let ring = &polygon.exterior().0;
            let pixels = shoelace(ring.iter().map(|c| (c.x, c.y)));
            if pixels < MIN_LOOP_PIXELS {
                specks += 1;
                continue;
            }
            let mut points: Vec<Vec3> = ring
                .iter()
                .map(|c| {
                    let mut ijk = [0.0; 3];
                    ijk[plan.axis] = s as f64;
                    // The tracer puts pixel (x, y) on [x, x+1] x [y, y+1]; voxel centres are at
                    // whole indices.
                    ijk[u] = c.x - 0.5;
                    ijk[v] = c.y - 0.5;
                    volume.world(ijk)
                })
                .collect();
            if points.len() > 1 && points.first() == points.last() {
                points.pop();
            }
            here.push(Loop {
                slice: s,
                pixels,
                points,
            });
        }
        here.sort_by(|a, b| b.pixels.total_cmp(&a.pixels));
        loops.extend(here);
    }
    (loops, specks)
}

fn shoelace(ring: impl Iterator<Item = (f64, f64)> + Clone) -> f64 {
    let next = ring.clone().skip(1).chain(ring.clone().take(1));
    (ring
        .zip(next)
        .map(|(a, b)| a.0 * b.1 - b.0 * a.1)
        .sum::<f64>()
        / 2.0)
        .abs()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::nifti::roles::tests::heart_slice;

    fn volume(labels: Vec<u16>, dims: [usize; 3], steps: [f64; 3]) -> LabelVolume {
        LabelVolume::new(
            dims,
            Vec3::new(10.0, 20.0, 30.0),
            [
                Vec3::new(steps[0], 0.0, 0.0),
                Vec3::new(0.0, steps[1], 0.0),
                Vec3::new(0.0, 0.0, steps[2]),
            ],
            labels,
        )
    }

    #[test]
    fn a_square_of_pixels_outlines_along_its_edges() {
        let n = 8;
        let mut labels = vec![0; n * n * 2];
        for y in 2..5 {
            for x in 3..7 {
                labels[x + n * y + n * n] = 4;
            }
        }
        let v = volume(labels, [n, n, 2], [1.5, 1.5, 8.0]);
        let plan = plan(&v);
        assert_eq!((plan.axis, plan.step), (2, 1));
        let (loops, specks) = trace(&v, &[4], &plan);
        assert_eq!((loops.len(), specks), (1, 0));
        let l = &loops[0];
        assert_eq!((l.slice, l.pixels), (1, 12.0 - 0.5));
        // Voxel centres 3..6 by 2..4: the outline lies half a voxel outside them (corners cut).
        let xs: Vec<f64> = l.points.iter().map(|p| p.x).collect();
        let lo = xs.iter().cloned().fold(f64::MAX, f64::min);
        let hi = xs.iter().cloned().fold(f64::MIN, f64::max);
        assert!((lo - (10.0 + 2.5 * 1.5)).abs() < 1e-9 && (hi - (10.0 + 6.5 * 1.5)).abs() < 1e-9);
        assert!(l.points.iter().all(|p| (p.z - 38.0).abs() < 1e-9));
    }

    #[test]
    fn specks_and_holes() {
        let n = 40;
        let mut slice = heart_slice(n, 3, 2, 1);
        slice[5 + n * 5] = 3; // a lone voxel of the cavity's label
        let v = volume(slice, [n, n, 1], [1.25, 1.25, 10.0]);
        let plan = plan(&v);
        let (cavity, specks) = trace(&v, &[3], &plan);
        assert_eq!((cavity.len(), specks), (1, 1));
        // The myocardium alone is a ring with a hole; its outline is the outer one only.
        let (ring, _) = trace(&v, &[2], &plan);
        let (epi, _) = trace(&v, &[2, 3], &plan);
        assert_eq!(ring.len(), 1);
        assert!((ring[0].pixels - epi[0].pixels).abs() < 1e-9);
        assert!(epi[0].pixels > 2.0 * cavity[0].pixels);
    }

    #[test]
    fn thin_voxels_are_traced_about_five_mm_apart() {
        let v = volume(vec![0; 8], [2, 2, 2], [1.0, 1.2, 1.0]);
        assert_eq!(
            plan(&v),
            SlicePlan {
                axis: 1,
                step: 4,
                spacing_mm: 4.8
            }
        );
    }
}
