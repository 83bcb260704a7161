//! Distances and measures: summary statistics, contour-to-mesh distances (the colour map on the
//! contours), the distance field on the mesh, and (compare.rs) mesh-to-mesh comparison.

pub mod anatomical;
pub mod anatomical_study;
pub mod bullseye;
pub mod compare;
pub mod extent;
pub mod function;
pub mod segments;
pub mod septum;
pub mod thickening;

use crate::contours::{Contour, ContourKind};
use crate::geometry::Vec3;
use crate::mesh::TriMesh;
use crate::spatial::{Bvh, SegmentTree};
use serde::Serialize;

/// Summary of a set of distances (mm).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Stats {
    pub mean: f64,
    pub median: f64,
    pub p95: f64,
    pub max: f64,
    pub min: f64,
    pub count: usize,
}

/// Mean, median, 95th percentile (nearest rank), max and min; all zero for an empty input.
pub fn stats(values: &[f64]) -> Stats {
    if values.is_empty() {
        return Stats::default();
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let median = if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    };
    let rank = ((0.95 * n as f64).ceil() as usize).clamp(1, n) - 1;
    Stats {
        mean: v.iter().sum::<f64>() / n as f64,
        median,
        p95: v[rank],
        max: v[n - 1],
        min: v[0],
        count: n,
    }
}

/// Per-contour summary of contour-to-mesh distances.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContourStats {
    pub id: String,
    pub kind: ContourKind,
    pub stats: Stats,
}

/// Contour-to-mesh distances for every contour point.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct ContourDistances {
    /// One distance per contour point: contour order, then piece order, then point order.
    pub per_point: Vec<f64>,
    pub per_contour: Vec<ContourStats>,
    pub overall: Stats,
}

/// Distance from each point to the mesh surface (point-to-triangle, through a BVH). An empty mesh
/// gives infinite distances.
pub fn points_to_mesh(points: &[Vec3], mesh: &TriMesh) -> Vec<f64> {
    let bvh = Bvh::build(mesh);
    points
        .iter()
        .map(|p| {
            bvh.closest_point(mesh, *p)
                .map_or(f64::INFINITY, |h| h.distance_sq.sqrt())
        })
        .collect()
}

/// The distance of every point of `contours` to the mesh: contour order, then piece order, then
/// point order (one BVH for all).
pub fn contour_points_to_mesh(contours: &[Contour], mesh: &TriMesh) -> Vec<f64> {
    let points: Vec<Vec3> = contours.iter().flat_map(|c| c.points().copied()).collect();
    points_to_mesh(&points, mesh)
}

/// Per contour, the summary of its points' distances to the mesh (in `contours`' order).
pub fn per_contour_stats(contours: &[Contour], mesh: &TriMesh) -> Vec<Stats> {
    split_stats(contours, &contour_points_to_mesh(contours, mesh))
}

/// `per_point` (one distance per point of `contours`, in order) summarised per contour.
fn split_stats(contours: &[Contour], per_point: &[f64]) -> Vec<Stats> {
    let mut offset = 0;
    contours
        .iter()
        .map(|c| {
            let n = c.point_count();
            let s = stats(&per_point[offset..offset + n]);
            offset += n;
            s
        })
        .collect()
}

/// Distances of every contour point to the mesh, summarised per contour and overall.
pub fn contour_to_mesh(
    contours: &[Contour],
    kinds: &[ContourKind],
    mesh: &TriMesh,
) -> ContourDistances {
    let per_point = contour_points_to_mesh(contours, mesh);
    let per_contour = contours
        .iter()
        .zip(split_stats(contours, &per_point))
        .enumerate()
        .map(|(i, (c, stats))| ContourStats {
            id: c.id.clone(),
            kind: kinds.get(i).copied().unwrap_or(ContourKind::Lax),
            stats,
        })
        .collect();
    let overall = stats(&per_point);
    ContourDistances {
        per_point,
        per_contour,
        overall,
    }
}

/// For every mesh vertex, the distance (mm) to the nearest point of any contour polyline (segments
/// included, so sparse contour sampling does not inflate it): the distance field shown on the mesh,
/// large where the surface is far from any data.
pub fn vertex_to_contours(mesh: &TriMesh, contours: &[Contour]) -> Vec<f64> {
    let mut segments: Vec<(Vec3, Vec3)> = Vec::new();
    for c in contours {
        for piece in &c.pieces {
            let p = &piece.points;
            match p.len() {
                0 => {}
                1 => segments.push((p[0], p[0])),
                n => {
                    segments.extend(p.windows(2).map(|w| (w[0], w[1])));
                    if piece.closed && n > 2 {
                        segments.push((p[n - 1], p[0]));
                    }
                }
            }
        }
    }
    let tree = SegmentTree::new(segments);
    mesh.positions.iter().map(|v| tree.distance(v)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_of_known_values() {
        let s = stats(&[4.0, 1.0, 3.0, 2.0]);
        assert_eq!(s.mean, 2.5);
        assert_eq!(s.median, 2.5);
        assert_eq!(s.max, 4.0);
        assert_eq!(s.min, 1.0);
        assert_eq!(s.p95, 4.0);
        let v: Vec<f64> = (1..=100).map(|i| i as f64).collect();
        assert_eq!(stats(&v).p95, 95.0);
        assert_eq!(stats(&[]).count, 0);
    }
}
