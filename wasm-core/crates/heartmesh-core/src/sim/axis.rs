//! The long axis of a reference shape, for placing simulated CMR planes.
//!
//! Principal component analysis of the surface (Jolliffe, "Principal Component Analysis", 2002):
//! the direction of largest area-weighted spread is the apex-base axis of a ventricle. Which end is
//! the apex is decided from the shape: an open base (the valve rim) marks the base; otherwise the
//! apex is the end farther from the surface centroid (ventricles taper towards the apex).

use super::repair::{boundary_loops, loop_diameter};
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::TriMesh;
use nalgebra::{Matrix3, SymmetricEigen};
use std::collections::HashMap;

/// A long axis: a point on it and a unit direction pointing from apex to base.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LongAxis {
    pub centre: Vec3,
    pub direction: Vec3,
}

impl LongAxis {
    /// None if the direction is zero or not finite.
    pub fn new(centre: Vec3, direction: Vec3) -> Option<LongAxis> {
        let n = direction.norm();
        (n.is_finite() && n > 0.0 && centre.iter().all(|c| c.is_finite())).then(|| LongAxis {
            centre,
            direction: direction / n,
        })
    }

    /// Height of a point along the axis (mm from the centre, positive towards the base).
    #[inline]
    pub fn height(&self, p: &Vec3) -> f64 {
        self.direction.dot(&(p - self.centre))
    }

    /// The axis of `mesh` by PCA, oriented apex to base (see the module docs), plus the second
    /// principal direction (a default reference for long-axis plane angles).
    pub fn from_mesh(mesh: &TriMesh) -> Result<(LongAxis, Vec3)> {
        let (centre, area) = area_centroid(mesh)?;
        let mut cov = Matrix3::zeros();
        for t in 0..mesh.triangles.len() {
            let [a, b, c] = mesh.corners(t);
            let w = 0.5 * (b - a).cross(&(c - a)).norm() / area;
            // Second moment of a triangle about the centroid (exact for uniform density).
            let (da, db, dc) = (a - centre, b - centre, c - centre);
            let s = da + db + dc;
            cov += (s * s.transpose()
                + da * da.transpose()
                + db * db.transpose()
                + dc * dc.transpose())
                * (w / 12.0);
        }
        let eig = SymmetricEigen::new(cov);
        let mut order = [0usize, 1, 2];
        order.sort_by(|&i, &j| eig.eigenvalues[j].total_cmp(&eig.eigenvalues[i]));
        let mut dir: Vec3 = eig.eigenvectors.column(order[0]).into_owned();
        let second: Vec3 = eig.eigenvectors.column(order[1]).into_owned();
        if !dir.iter().all(|c| c.is_finite()) || dir.norm() == 0.0 {
            return Err(CoreError::Degenerate("shape has no principal axis".into()));
        }
        dir.normalize_mut();
        // The widest boundary loop is the valve rim (small loops are mesh defects).
        let rim = boundary_loops(mesh)
            .into_iter()
            .max_by(|a, b| loop_diameter(mesh, a).total_cmp(&loop_diameter(mesh, b)));
        let base_towards_positive = if let Some(rim) = rim {
            let mean_h: f64 = rim
                .iter()
                .map(|&v| dir.dot(&(mesh.positions[v as usize] - centre)))
                .sum::<f64>()
                / rim.len() as f64;
            mean_h > 0.0
        } else {
            let (lo, hi) = mesh.positions.iter().fold((0.0f64, 0.0f64), |(lo, hi), p| {
                let h = dir.dot(&(p - centre));
                (lo.min(h), hi.max(h))
            });
            // The apex is the far, tapered end.
            -lo > hi
        };
        if !base_towards_positive {
            dir = -dir;
        }
        let axis = LongAxis {
            centre,
            direction: dir,
        };
        Ok((axis, second.normalize()))
    }

    /// Lowest and highest heights of the mesh's vertices, and the highest height below which every
    /// section is closed (the lowest boundary vertex, or the top for a closed mesh).
    pub fn extent(&self, mesh: &TriMesh) -> Option<(f64, f64, f64)> {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for p in &mesh.positions {
            let h = self.height(p);
            lo = lo.min(h);
            hi = hi.max(h);
        }
        if !(lo.is_finite() && hi.is_finite()) {
            return None;
        }
        let rim = boundary_vertices(mesh)
            .iter()
            .map(|&v| self.height(&mesh.positions[v]))
            .fold(hi, f64::min);
        Some((lo, hi, rim))
    }
}

/// Area-weighted centroid of the surface and its area.
pub fn area_centroid(mesh: &TriMesh) -> Result<(Vec3, f64)> {
    let mut area = 0.0;
    let mut acc = Vec3::zeros();
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.corners(t);
        let w = 0.5 * (b - a).cross(&(c - a)).norm();
        area += w;
        acc += (a + b + c) * (w / 3.0);
    }
    if !(area.is_finite() && area > 0.0) {
        return Err(CoreError::Degenerate("shape has zero area".into()));
    }
    Ok((acc / area, area))
}

/// Vertices on edges used by exactly one triangle (the rims of an open mesh), sorted.
pub fn boundary_vertices(mesh: &TriMesh) -> Vec<usize> {
    let mut count: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            let (u, v) = (t[k], t[(k + 1) % 3]);
            *count.entry((u.min(v), u.max(v))).or_insert(0) += 1;
        }
    }
    let mut out: Vec<usize> = count
        .iter()
        .filter(|(_, &c)| c == 1)
        .flat_map(|(&(u, v), _)| [u as usize, v as usize])
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::shapes::ParametricLv;

    #[test]
    fn parametric_lv_axis_points_to_base() {
        for closed_base in [false, true] {
            let m = ParametricLv {
                closed_base,
                ..ParametricLv::default()
            }
            .mesh(48, 30)
            .unwrap();
            let (axis, _) = LongAxis::from_mesh(&m).unwrap();
            assert!(
                axis.direction.z > 0.999,
                "{closed_base}: {:?}",
                axis.direction
            );
            let (lo, hi, rim) = axis.extent(&m).unwrap();
            assert!((hi - lo - 80.0).abs() < 1e-6);
            assert!((hi - rim).abs() < 1e-9);
            assert_eq!(boundary_vertices(&m).is_empty(), closed_base);
        }
    }
}
