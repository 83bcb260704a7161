//! The right-ventricular cavity of a biventricular model whose RV surface is the free wall only.
//!
//! Models such as CardioMesh's store the RV endocardium as the free wall, attached along the
//! insertion lines to the LV epicardium, which forms the septal side of the RV cavity. The cavity
//! a CMR analyst delineates (free wall + septum per slice) is the free wall plus the part of the LV
//! epicardium it faces. That part is found by casting a ray outward from every LV epicardial
//! triangle and keeping those that meet the free wall within a short distance (ray-triangle test of
//! Moeller & Trumbore, J. Graphics Tools 1997).

use super::axis::area_centroid;
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::TriMesh;

/// The free wall plus the septal part of `lv_epi` facing it within `max_ray_mm` (both meshes
/// concatenated, not welded).
pub fn rv_cavity(free_wall: &TriMesh, lv_epi: &TriMesh, max_ray_mm: f64) -> Result<TriMesh> {
    let (epi_centre, _) = area_centroid(lv_epi)?;
    let normal = |m: &TriMesh, t: usize| {
        let [a, b, c] = m.corners(t);
        ((b - a).cross(&(c - a)), (a + b + c) / 3.0)
    };
    // Orientation of the epicardium: outward if the normals point away from its centroid overall.
    let outward: f64 = (0..lv_epi.triangles.len())
        .map(|t| {
            let (n, c) = normal(lv_epi, t);
            n.dot(&(c - epi_centre))
        })
        .sum();
    let sign = if outward >= 0.0 { 1.0 } else { -1.0 };
    let wall: Vec<[Vec3; 3]> = (0..free_wall.triangles.len())
        .map(|t| free_wall.corners(t))
        .collect();
    let facing: Vec<usize> = (0..lv_epi.triangles.len())
        .filter(|&t| {
            let (n, c) = normal(lv_epi, t);
            let len = n.norm();
            len > 0.0 && {
                let dir = n * (sign / len);
                wall.iter().any(|tri| ray_hits(&c, &dir, tri, max_ray_mm))
            }
        })
        .collect();
    // The septum is the largest connected patch; stray patches elsewhere are dropped.
    let septum = largest_component(lv_epi, &facing);
    let mut out = free_wall.clone();
    let offset = out.positions.len() as u32;
    out.positions.extend_from_slice(&lv_epi.positions);
    for &t in &septum {
        let [a, b, c] = lv_epi.triangles[t];
        out.triangles.push([a + offset, b + offset, c + offset]);
    }
    if septum.is_empty() {
        return Err(CoreError::Degenerate(
            "no part of the LV epicardium faces the RV free wall".into(),
        ));
    }
    // Drop the unused epicardial vertices.
    let (welded, _) = super::repair::weld(&out, 0.0);
    Ok(welded)
}

/// The largest set of `tris` connected through shared vertices (union-find).
fn largest_component(mesh: &TriMesh, tris: &[usize]) -> Vec<usize> {
    let mut parent: Vec<usize> = (0..mesh.positions.len()).collect();
    fn find(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    for &t in tris {
        let [a, b, c] = mesh.triangles[t].map(|v| v as usize);
        for (u, v) in [(a, b), (b, c)] {
            let (ru, rv) = (find(&mut parent, u), find(&mut parent, v));
            if ru != rv {
                parent[ru] = rv;
            }
        }
    }
    let mut size: std::collections::HashMap<usize, usize> = std::collections::HashMap::new();
    let roots: Vec<usize> = tris
        .iter()
        .map(|&t| find(&mut parent, mesh.triangles[t][0] as usize))
        .collect();
    for &r in &roots {
        *size.entry(r).or_insert(0) += 1;
    }
    let Some(best) = roots
        .iter()
        .copied()
        .max_by_key(|r| (size.get(r).copied().unwrap_or(0), usize::MAX - r))
    else {
        return Vec::new();
    };
    tris.iter()
        .zip(&roots)
        .filter(|(_, &r)| r == best)
        .map(|(&t, _)| t)
        .collect()
}

/// Moeller-Trumbore: does the ray origin + s dir, 0 < s <= max, cross the triangle?
fn ray_hits(origin: &Vec3, dir: &Vec3, tri: &[Vec3; 3], max: f64) -> bool {
    let e1 = tri[1] - tri[0];
    let e2 = tri[2] - tri[0];
    let p = dir.cross(&e2);
    let det = e1.dot(&p);
    if det.abs() < 1e-12 {
        return false;
    }
    let inv = 1.0 / det;
    let s = origin - tri[0];
    let u = s.dot(&p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let q = s.cross(&e1);
    let v = dir.dot(&q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    let dist = e2.dot(&q) * inv;
    dist > 1e-9 && dist <= max
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;
    use crate::sim::shapes::uv_sphere;

    #[test]
    fn only_the_facing_side_is_kept() {
        // "LV": sphere r = 10 at the origin; "free wall": the +x half of a sphere r = 15.
        let lv = uv_sphere(v3(0.0, 0.0, 0.0), 10.0, 48, 24);
        let big = uv_sphere(v3(0.0, 0.0, 0.0), 15.0, 48, 24);
        let mut wall = big.clone();
        wall.triangles = big
            .triangles
            .iter()
            .copied()
            .filter(|t| t.iter().all(|&v| big.positions[v as usize].x > 2.0))
            .collect();
        let cav = rv_cavity(&wall, &lv, 10.0).unwrap();
        let kept_lv: Vec<&Vec3> = cav
            .positions
            .iter()
            .filter(|p| (p.norm() - 10.0).abs() < 0.5)
            .collect();
        assert!(!kept_lv.is_empty());
        assert!(
            kept_lv.iter().all(|p| p.x > 0.0),
            "septal part must face the wall"
        );
        // A wall beyond the ray length: nothing faces it.
        assert!(rv_cavity(&wall, &lv, 2.0).is_err());
    }
}
