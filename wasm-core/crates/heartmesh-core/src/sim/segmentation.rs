//! A segmentation of reference shapes as a network or an annotator delivers it: a label map on a
//! short-axis stack (pixels of ~1.25 mm, slices ~10 mm apart, oriented along the long axis), so
//! that the label-map reader ([`crate::io::nifti`]) can be checked against a known truth, end to
//! end, the way the contour acquisitions of [`super::planes`] check the method.

use super::axis::LongAxis;
use super::slice::{join_chains, slice_mesh, Plane};
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::io::nifti::LabelVolume;
use crate::mesh::TriMesh;

/// The stack's geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentationSpec {
    /// In-plane pixel size (mm).
    pub pixel_mm: f64,
    /// Distance between slices (mm).
    pub slice_mm: f64,
    /// Background kept around the shapes in plane (mm).
    pub margin_mm: f64,
}

/// One structure to paint.
#[derive(Debug, Clone, Copy)]
pub struct Structure<'a> {
    pub label: u16,
    pub mesh: &'a TriMesh,
    /// Section chains whose ends come this close are joined into one outline (0: none): a
    /// composite truth (an RV cavity made of its free wall and the LV epicardium's septum) gives
    /// two arcs per plane with small gaps between them ([`join_chains`]). Only closed sections
    /// are painted, so a plane through an open truth's rim paints nothing of it.
    pub join_gap_mm: f64,
}

impl<'a> Structure<'a> {
    /// A closed (or open-based) surface, painted where its sections close.
    pub fn new(label: u16, mesh: &'a TriMesh) -> Self {
        Structure {
            label,
            mesh,
            join_gap_mm: 0.0,
        }
    }
}

impl Default for SegmentationSpec {
    /// A typical cine short-axis stack: 1.25 mm pixels, 10 mm slices.
    fn default() -> Self {
        SegmentationSpec {
            pixel_mm: 1.25,
            slice_mm: 10.0,
            margin_mm: 10.0,
        }
    }
}

impl SegmentationSpec {
    /// Refuses spacings no grid can have, before a stack or a view is sized by them.
    fn check(&self) -> Result<()> {
        if !(self.pixel_mm > 0.0 && self.slice_mm > 0.0 && self.margin_mm >= 0.0) {
            return Err(invalid("pixel, slice spacing and margin must be positive"));
        }
        Ok(())
    }
}

/// A segmentation refused: its settings, or geometry no label map can be made of. One
/// constructor for stacks and views, so every refusal carries the same parameter name.
fn invalid(message: &str) -> CoreError {
    CoreError::ParamInvalid {
        name: "segmentation".into(),
        message: message.into(),
    }
}

/// Largest label map made (voxels), far above any cardiac stack.
const MAX_VOXELS: usize = 64 << 20;

/// Labels the pixel centres of a stack of planes across `axis` inside each structure's closed
/// sections; `structures` are painted in order, the first listed keeping a pixel (list the LV
/// cavity before the epicardium, whose inside then becomes the myocardium). The first slice lies
/// half a spacing above the lowest point of any structure, as a planned stack starts.
pub fn segment(
    structures: &[Structure],
    axis: &LongAxis,
    spec: &SegmentationSpec,
) -> Result<LabelVolume> {
    spec.check()?;
    let d = axis.direction;
    let helper = [Vec3::x(), Vec3::y(), Vec3::z()]
        .into_iter()
        .min_by(|a, b| a.dot(&d).abs().total_cmp(&b.dot(&d).abs()))
        .unwrap_or(Vec3::x());
    let e1 = (helper - d * helper.dot(&d)).normalize();
    let e2 = d.cross(&e1);
    let frame = |p: &Vec3| {
        let q = p - axis.centre;
        [q.dot(&e1), q.dot(&e2), q.dot(&d)]
    };
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in structures.iter().flat_map(|s| s.mesh.positions.iter()) {
        for (c, v) in frame(p).into_iter().enumerate() {
            lo[c] = lo[c].min(v);
            hi[c] = hi[c].max(v);
        }
    }
    if !lo.iter().chain(hi.iter()).all(|v| v.is_finite()) {
        return Err(invalid("no finite vertex to segment"));
    }
    let start = [
        lo[0] - spec.margin_mm,
        lo[1] - spec.margin_mm,
        lo[2] + spec.slice_mm / 2.0,
    ];
    let count = |span: f64, step: f64| (span / step).floor() as usize + 1;
    let dims = [
        count(hi[0] - lo[0] + 2.0 * spec.margin_mm, spec.pixel_mm),
        count(hi[1] - lo[1] + 2.0 * spec.margin_mm, spec.pixel_mm),
        count((hi[2] - start[2]).max(0.0), spec.slice_mm),
    ];
    if dims.iter().product::<usize>() > MAX_VOXELS {
        return Err(invalid(
            "more than 64 M voxels: use larger pixels or slices",
        ));
    }
    let origin = axis.centre + e1 * start[0] + e2 * start[1] + d * start[2];
    let axes = [e1 * spec.pixel_mm, e2 * spec.pixel_mm, d * spec.slice_mm];
    let mut labels = vec![0u16; dims[0] * dims[1] * dims[2]];
    for k in 0..dims[2] {
        let centre = origin + axes[2] * k as f64;
        let Some(plane) = Plane::new(centre, d) else {
            continue;
        };
        let layer = &mut labels[k * dims[0] * dims[1]..(k + 1) * dims[0] * dims[1]];
        paint(
            layer,
            [dims[0], dims[1]],
            &plane,
            origin,
            [axes[0], axes[1]],
            structures,
            false,
        );
    }
    Ok(LabelVolume::new(dims, origin, axes, labels))
}

/// A long-axis view of the structures as a single-slice label map: the plane through `centre`
/// across `normal`, its rows along `up` (projected into the plane; the long axis, as a scanner
/// lays out a 2- or 4-chamber image), covering the structures' sections plus the margin, one
/// slice `spec.slice_mm` thick. Sections open at a valve are closed across it.
pub fn segment_view(
    structures: &[Structure],
    centre: Vec3,
    normal: Vec3,
    up: Vec3,
    spec: &SegmentationSpec,
) -> Result<LabelVolume> {
    spec.check()?;
    let plane = Plane::new(centre, normal).ok_or_else(|| invalid("the view's normal is zero"))?;
    let n = plane.normal;
    let v = up - n * up.dot(&n);
    if v.norm().is_nan() || v.norm() <= 1e-9 {
        return Err(invalid("the view's rows cannot run along its normal"));
    }
    let e2 = v.normalize();
    let e1 = e2.cross(&n);
    let sections: Vec<Vec3> = structures
        .iter()
        .flat_map(|s| join_chains(slice_mesh(s.mesh, &plane), s.join_gap_mm, &plane))
        .flat_map(|l| l.points)
        .collect();
    if sections.is_empty() {
        return Err(invalid("the view's plane misses every structure"));
    }
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in &sections {
        let q = p - centre;
        for (c, x) in [q.dot(&e1), q.dot(&e2)].into_iter().enumerate() {
            lo[c] = lo[c].min(x);
            hi[c] = hi[c].max(x);
        }
    }
    let count =
        |c: usize| ((hi[c] - lo[c] + 2.0 * spec.margin_mm) / spec.pixel_mm).floor() as usize + 1;
    let dims = [count(0), count(1), 1];
    if dims[0] * dims[1] > MAX_VOXELS {
        return Err(invalid("more than 64 M pixels: use larger pixels"));
    }
    let origin = centre + e1 * (lo[0] - spec.margin_mm) + e2 * (lo[1] - spec.margin_mm);
    let axes = [e1 * spec.pixel_mm, e2 * spec.pixel_mm, n * spec.slice_mm];
    let mut labels = vec![0u16; dims[0] * dims[1]];
    paint(
        &mut labels,
        [dims[0], dims[1]],
        &plane,
        origin,
        [axes[0], axes[1]],
        structures,
        true,
    );
    Ok(LabelVolume::new(dims, origin, axes, labels))
}

/// Labels the pixels of one image (`size` pixels along the in-plane steps `steps`, pixel (0, 0)
/// centred on `origin`) inside each structure's closed sections by `plane`, in order. With
/// `close_open`, open sections count too, closed by their chord: a long-axis plane cuts a
/// cavity open at its valves as a U, which a segmentation closes across the valve plane.
fn paint(
    layer: &mut [u16],
    size: [usize; 2],
    plane: &Plane,
    origin: Vec3,
    steps: [Vec3; 2],
    structures: &[Structure],
    close_open: bool,
) {
    let unit = steps.map(|s| s / s.norm_squared());
    for s in structures {
        // Section loops in pixel units of this image.
        let loops: Vec<Vec<[f64; 2]>> =
            join_chains(slice_mesh(s.mesh, plane), s.join_gap_mm, plane)
                .into_iter()
                .filter(|l| l.closed || close_open)
                .map(|l| {
                    l.points
                        .iter()
                        .map(|p| {
                            let q = p - origin;
                            [q.dot(&unit[0]), q.dot(&unit[1])]
                        })
                        .collect()
                })
                .collect();
        fill(layer, size[0], size[1], &loops, s.label);
    }
}

/// Sets to `label` the still-unlabelled pixels whose centre (x, y) lies inside `loops` (even-odd
/// rule), scan line by scan line.
fn fill(layer: &mut [u16], nx: usize, ny: usize, loops: &[Vec<[f64; 2]>], label: u16) {
    let mut xs: Vec<f64> = Vec::new();
    for y in 0..ny {
        let yc = y as f64;
        xs.clear();
        for ring in loops {
            for (a, b) in ring.iter().zip(ring.iter().cycle().skip(1)) {
                if (a[1] > yc) != (b[1] > yc) {
                    xs.push(a[0] + (yc - a[1]) / (b[1] - a[1]) * (b[0] - a[0]));
                }
            }
        }
        xs.sort_by(f64::total_cmp);
        for span in xs.chunks_exact(2) {
            let from = span[0].ceil().max(0.0) as usize;
            let to = span[1].floor().min(nx as f64 - 1.0);
            if to < 0.0 {
                continue;
            }
            for x in from..=to as usize {
                let px = &mut layer[x + nx * y];
                if *px == 0 {
                    *px = label;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::shapes::ParametricLv;

    #[test]
    fn a_cavity_and_its_wall_become_a_ring() {
        let endo = ParametricLv::default().mesh(64, 48).unwrap();
        let epi = ParametricLv {
            radius_mm: 33.0,
            base_radius_mm: 28.0,
            ..ParametricLv::default()
        }
        .mesh(64, 48)
        .unwrap();
        let (axis, _) = LongAxis::from_mesh(&epi).unwrap();
        let v = segment(
            &[Structure::new(3, &endo), Structure::new(2, &epi)],
            &axis,
            &SegmentationSpec::default(),
        )
        .unwrap();
        let count = |l: u16| v.labels.iter().filter(|&&x| x == l).count();
        assert!(
            count(3) > 100 && count(2) > 100,
            "{} {}",
            count(3),
            count(2)
        );
        assert!((v.spacing()[2] - 10.0).abs() < 1e-9);
        // Every labelled pixel centre lies inside its shape's extent.
        let lo = epi
            .positions
            .iter()
            .map(|p| axis.height(p))
            .fold(f64::MAX, f64::min);
        for (n, _) in v.labels.iter().enumerate().filter(|(_, &l)| l != 0) {
            let ijk = [
                n % v.dims[0],
                (n / v.dims[0]) % v.dims[1],
                n / (v.dims[0] * v.dims[1]),
            ];
            let p = v.world(ijk.map(|c| c as f64));
            assert!(axis.height(&p) > lo);
        }
    }
}
