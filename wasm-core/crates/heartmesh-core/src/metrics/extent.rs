//! How far a mesh reaches past its data along the long axis.

use crate::contours::Contour;
use crate::geometry::Vec3;
use serde::Serialize;

/// Millimetres the mesh reaches beyond the highest (base) and the lowest (apex) contour point along
/// the long axis; negative where it stops short of them. Where no curve closes an end of the
/// cavity, the surface there is extrapolated: the remesh smoothing and the spline carry it on by
/// up to a ring radius (docs/VALIDATION.md, "Session 9: overrun past the data"), and the volume
/// includes that part. Reported so a user can tell a measured volume from an extrapolated one.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PastData {
    pub base_mm: f64,
    pub apex_mm: f64,
}

/// `axis` points from apex to base (unit). None without mesh vertices or contour points.
pub fn past_data(mesh_points: &[Vec3], contours: &[Contour], axis: &Vec3) -> Option<PastData> {
    let range = |it: &mut dyn Iterator<Item = f64>| {
        it.fold(None, |r: Option<(f64, f64)>, h| {
            Some(r.map_or((h, h), |(lo, hi)| (lo.min(h), hi.max(h))))
        })
    };
    let (mesh_lo, mesh_hi) = range(&mut mesh_points.iter().map(|p| p.dot(axis)))?;
    let (data_lo, data_hi) = range(
        &mut contours
            .iter()
            .flat_map(|c| c.points())
            .map(|p| p.dot(axis)),
    )?;
    Some(PastData {
        base_mm: mesh_hi - data_hi,
        apex_mm: data_lo - mesh_lo,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contours::Polyline;
    use crate::geometry::v3;

    #[test]
    fn overrun_at_each_end_along_the_axis() {
        let ring = |z: f64| Contour {
            id: format!("z{z}"),
            surface: None,
            pieces: vec![Polyline {
                points: vec![v3(1.0, 0.0, z), v3(0.0, 1.0, z), v3(-1.0, 0.0, z)],
                closed: true,
            }],
            first_line: 0,
        };
        let contours = [ring(0.0), ring(10.0)];
        let mesh = [v3(0.0, 0.0, -2.5), v3(3.0, 0.0, 5.0), v3(0.0, 0.0, 14.0)];
        let p = past_data(&mesh, &contours, &v3(0.0, 0.0, 1.0)).unwrap();
        assert!(
            (p.base_mm - 4.0).abs() < 1e-12 && (p.apex_mm - 2.5).abs() < 1e-12,
            "{p:?}"
        );
        // Reversed axis: the ends swap.
        let q = past_data(&mesh, &contours, &v3(0.0, 0.0, -1.0)).unwrap();
        assert!(
            (q.base_mm - 2.5).abs() < 1e-12 && (q.apex_mm - 4.0).abs() < 1e-12,
            "{q:?}"
        );
        assert!(past_data(&[], &contours, &v3(0.0, 0.0, 1.0)).is_none());
        assert!(past_data(&mesh, &[], &v3(0.0, 0.0, 1.0)).is_none());
    }
}
