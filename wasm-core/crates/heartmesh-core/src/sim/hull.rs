//! 3D convex hull of a point cloud: the naive baseline the reconstruction must beat on concave
//! shapes such as the crescent-shaped right ventricle.
//!
//! Incremental algorithm (Kallay 1981; see O'Rourke, "Computational Geometry in C", 2nd ed., ch. 4):
//! start from a tetrahedron of extreme points, then for each further point remove the faces it sees
//! and cone the horizon to it. O(n h) with h hull faces, ample for a few thousand contour points.

use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::TriMesh;
use std::collections::HashSet;

/// The convex hull of `points` as a closed mesh with outward triangles (only hull vertices kept).
pub fn convex_hull(points: &[Vec3]) -> Result<TriMesh> {
    let pts: Vec<Vec3> = points
        .iter()
        .copied()
        .filter(|p| p.iter().all(|c| c.is_finite()))
        .collect();
    if pts.len() < 4 {
        return Err(CoreError::Degenerate(
            "convex hull needs at least 4 points".into(),
        ));
    }
    let scale = pts
        .iter()
        .map(|p| (p - pts[0]).norm())
        .fold(0.0f64, f64::max);
    let eps = 1e-9 * scale.max(1e-300);

    // Initial tetrahedron from extreme points.
    let i0 = (0..pts.len())
        .min_by(|&a, &b| pts[a].x.total_cmp(&pts[b].x))
        .unwrap_or(0);
    let i1 = argmax(&pts, |p| (p - pts[i0]).norm());
    let dir = (pts[i1] - pts[i0]).normalize();
    let i2 = argmax(&pts, |p| {
        let d = p - pts[i0];
        (d - dir * d.dot(&dir)).norm()
    });
    let n = (pts[i1] - pts[i0]).cross(&(pts[i2] - pts[i0]));
    if (pts[i1] - pts[i0]).norm() <= eps || n.norm() <= eps * scale {
        return Err(CoreError::Degenerate(
            "convex hull: points are collinear".into(),
        ));
    }
    let n = n.normalize();
    let i3 = argmax(&pts, |p| n.dot(&(p - pts[i0])).abs());
    if n.dot(&(pts[i3] - pts[i0])).abs() <= eps {
        return Err(CoreError::Degenerate(
            "convex hull: points are coplanar".into(),
        ));
    }
    let interior = (pts[i0] + pts[i1] + pts[i2] + pts[i3]) / 4.0;

    let mut faces: Vec<Face> = Vec::new();
    for f in [[i0, i1, i2], [i0, i1, i3], [i0, i2, i3], [i1, i2, i3]] {
        faces.push(Face::oriented(&pts, f, &interior));
    }
    for (p_index, p) in pts.iter().enumerate() {
        if [i0, i1, i2, i3].contains(&p_index) {
            continue;
        }
        let visible: Vec<bool> = faces.iter().map(|f| f.distance(&pts, p) > eps).collect();
        if !visible.iter().any(|&v| v) {
            continue;
        }
        let mut visible_edges: HashSet<(usize, usize)> = HashSet::new();
        for (f, _) in faces.iter().zip(&visible).filter(|(_, &v)| v) {
            for k in 0..3 {
                visible_edges.insert((f.v[k], f.v[(k + 1) % 3]));
            }
        }
        let mut next: Vec<Face> = Vec::with_capacity(faces.len() + 8);
        let mut horizon: Vec<(usize, usize)> = Vec::new();
        for (f, vis) in faces.iter().zip(&visible) {
            if !vis {
                next.push(*f);
                continue;
            }
            for k in 0..3 {
                let (u, v) = (f.v[k], f.v[(k + 1) % 3]);
                if !visible_edges.contains(&(v, u)) {
                    horizon.push((u, v));
                }
            }
        }
        for (u, v) in horizon {
            next.push(Face::new(&pts, [u, v, p_index]));
        }
        faces = next;
    }

    // Keep only the hull vertices, in first-use order.
    let mut remap = vec![u32::MAX; pts.len()];
    let mut positions = Vec::new();
    let mut triangles = Vec::with_capacity(faces.len());
    for f in &faces {
        let t = f.v.map(|v| {
            if remap[v] == u32::MAX {
                remap[v] = positions.len() as u32;
                positions.push(pts[v]);
            }
            remap[v]
        });
        triangles.push(t);
    }
    Ok(TriMesh::new(positions, triangles))
}

fn argmax(pts: &[Vec3], f: impl Fn(&Vec3) -> f64) -> usize {
    let mut best = 0;
    let mut best_v = f64::NEG_INFINITY;
    for (i, p) in pts.iter().enumerate() {
        let v = f(p);
        if v > best_v {
            best_v = v;
            best = i;
        }
    }
    best
}

#[derive(Debug, Clone, Copy)]
struct Face {
    v: [usize; 3],
    normal: Vec3,
}

impl Face {
    fn new(pts: &[Vec3], v: [usize; 3]) -> Face {
        let n = (pts[v[1]] - pts[v[0]]).cross(&(pts[v[2]] - pts[v[0]]));
        let len = n.norm();
        Face {
            v,
            normal: if len > 0.0 { n / len } else { Vec3::zeros() },
        }
    }

    fn oriented(pts: &[Vec3], v: [usize; 3], interior: &Vec3) -> Face {
        let f = Face::new(pts, v);
        if f.distance(pts, interior) > 0.0 {
            Face::new(pts, [v[0], v[2], v[1]])
        } else {
            f
        }
    }

    /// Signed distance of `p` above the face's plane (positive: outside).
    fn distance(&self, pts: &[Vec3], p: &Vec3) -> f64 {
        self.normal.dot(&(p - pts[self.v[0]]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;
    use crate::sim::prng::SplitMix64;

    #[test]
    fn cube_with_interior_points() {
        let mut pts = Vec::new();
        for x in [0.0, 10.0] {
            for y in [0.0, 10.0] {
                for z in [0.0, 10.0] {
                    pts.push(v3(x, y, z));
                }
            }
        }
        let mut rng = SplitMix64::new(3);
        for _ in 0..200 {
            pts.push(v3(
                rng.uniform(0.5, 9.5),
                rng.uniform(0.5, 9.5),
                rng.uniform(0.5, 9.5),
            ));
        }
        let h = convex_hull(&pts).unwrap();
        assert_eq!(h.positions.len(), 8);
        assert_eq!(h.triangles.len(), 12);
        assert!((h.signed_volume() - 1000.0).abs() < 1e-9);
        assert!((h.area() - 600.0).abs() < 1e-9);
    }

    #[test]
    fn sphere_points_and_degenerate_input() {
        let mut rng = SplitMix64::new(11);
        let pts: Vec<Vec3> = (0..2000).map(|_| rng.unit_vector() * 10.0).collect();
        let h = convex_hull(&pts).unwrap();
        // Euler: closed genus-0 triangulation has F = 2V - 4.
        assert_eq!(h.triangles.len(), 2 * h.positions.len() - 4);
        let v = h.signed_volume();
        let exact = 4.0 / 3.0 * std::f64::consts::PI * 1000.0;
        assert!(v > 0.97 * exact && v < exact, "volume {v}");
        let flat = vec![
            v3(0., 0., 0.),
            v3(1., 0., 0.),
            v3(0., 1., 0.),
            v3(1., 1., 0.),
        ];
        assert_eq!(convex_hull(&flat).unwrap_err().code(), "degenerate");
    }
}
