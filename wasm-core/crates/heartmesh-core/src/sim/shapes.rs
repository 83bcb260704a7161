//! Reference shapes with known geometry: a UV sphere (analytic tests of the metrics) and the built-in
//! parametric left ventricle of the validation lab, a truncated prolate spheroid with an optional
//! regional bulge — the classic idealised LV of cardiac mechanics (e.g. Streeter & Hanna 1973,
//! used as ground truth by Villard et al. 2018 alongside real shapes).

use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::TriMesh;
use std::f64::consts::PI;

/// A closed UV sphere with outward triangles: vertex 0 is the bottom pole, then `n_lat - 1` rings of
/// `n_lon` vertices from bottom to top, then the top pole.
pub fn uv_sphere(center: Vec3, radius: f64, n_lon: usize, n_lat: usize) -> TriMesh {
    let n_lon = n_lon.max(3);
    let n_lat = n_lat.max(2);
    let mut rings = Vec::with_capacity(n_lat - 1);
    for k in 1..n_lat {
        let theta = PI * k as f64 / n_lat as f64;
        let (z, r) = (-radius * theta.cos(), radius * theta.sin());
        rings.push(
            (0..n_lon)
                .map(|i| {
                    let phi = 2.0 * PI * i as f64 / n_lon as f64;
                    center + Vec3::new(r * phi.cos(), r * phi.sin(), z)
                })
                .collect::<Vec<_>>(),
        );
    }
    let bottom = center - Vec3::new(0.0, 0.0, radius);
    let top = center + Vec3::new(0.0, 0.0, radius);
    surface_of_revolution(Some(bottom), &rings, Some(top))
}

/// A regional bulge (e.g. an aneurysm or a hypertrophic segment): a Gaussian radial displacement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bulge {
    /// Outward displacement at the centre, mm (negative: a dent).
    pub amplitude_mm: f64,
    /// Height of the centre as a fraction of the length, 0 = apex, 1 = base.
    pub height_fraction: f64,
    /// Direction of the centre about the long axis, degrees from +x.
    pub angle_deg: f64,
    /// Gaussian width (standard deviation) in mm.
    pub width_mm: f64,
}

/// The parametric LV: long axis +z, apex at the origin, base plane at z = `length_mm`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParametricLv {
    /// Apex to base plane, mm.
    pub length_mm: f64,
    /// Largest radius (the spheroid's short semi-axis), mm.
    pub radius_mm: f64,
    /// Radius of the opening at the base, mm (<= radius; equal: cut at the equator).
    pub base_radius_mm: f64,
    pub bulge: Option<Bulge>,
    /// Close the base with a flat lid (a watertight shape) instead of leaving it open.
    pub closed_base: bool,
}

impl Default for ParametricLv {
    /// A typical adult LV endocardium at end-diastole.
    fn default() -> Self {
        ParametricLv {
            length_mm: 80.0,
            radius_mm: 25.0,
            base_radius_mm: 20.0,
            bulge: None,
            closed_base: false,
        }
    }
}

impl ParametricLv {
    /// The validation truth of the accuracy tests and the CLI experiments: the default LV with a
    /// 4 mm regional bulge at mid-ventricle (a feature only some planes see), finely triangulated.
    pub fn bulged_truth() -> Result<TriMesh> {
        ParametricLv {
            bulge: Some(Bulge {
                amplitude_mm: 4.0,
                height_fraction: 0.5,
                angle_deg: 30.0,
                width_mm: 10.0,
            }),
            ..ParametricLv::default()
        }
        .mesh(96, 64)
    }

    /// Triangulates the shape with `n_around` points per ring and `n_along` rings from apex to base.
    pub fn mesh(&self, n_around: usize, n_along: usize) -> Result<TriMesh> {
        let (l, b, ro) = (self.length_mm, self.radius_mm, self.base_radius_mm);
        if !(l.is_finite() && b.is_finite() && ro.is_finite()) || l <= 0.0 || b <= 0.0 {
            return Err(CoreError::Degenerate(
                "parametric LV needs a positive length and radius".into(),
            ));
        }
        if !(ro > 0.0 && ro <= b) {
            return Err(CoreError::Degenerate(format!(
                "parametric LV base radius {ro} mm must be in (0, {b}] mm"
            )));
        }
        if n_around < 3 || n_along < 2 {
            return Err(CoreError::Degenerate(
                "parametric LV needs at least 3 points per ring and 2 rings".into(),
            ));
        }
        // Prolate spheroid with its apex at z = 0: z = a (1 - cos t), r = b sin t, cut where r = ro
        // on the far side of the equator.
        let s = (1.0 - (ro / b).powi(2)).max(0.0).sqrt();
        let a = l / (1.0 + s);
        let t_max = (-s).acos();
        let bulge_centre = self.bulge.map(|g| {
            let t = ((1.0 - g.height_fraction.clamp(0.0, 1.0) * l / a).clamp(-1.0, 1.0)).acos();
            let phi = g.angle_deg.to_radians();
            (
                g,
                Vec3::new(
                    b * t.sin() * phi.cos(),
                    b * t.sin() * phi.sin(),
                    a * (1.0 - t.cos()),
                ),
            )
        });
        let mut rings = Vec::with_capacity(n_along);
        for k in 1..=n_along {
            let t = t_max * k as f64 / n_along as f64;
            let (z, r) = (a * (1.0 - t.cos()), b * t.sin());
            let z = if k == n_along { l } else { z };
            rings.push(
                (0..n_around)
                    .map(|i| {
                        let phi = 2.0 * PI * i as f64 / n_around as f64;
                        let p = Vec3::new(r * phi.cos(), r * phi.sin(), z);
                        match bulge_centre {
                            Some((g, c)) if g.width_mm > 0.0 => {
                                let w =
                                    (-(p - c).norm_squared() / (2.0 * g.width_mm.powi(2))).exp();
                                p + Vec3::new(phi.cos(), phi.sin(), 0.0) * (g.amplitude_mm * w)
                            }
                            _ => p,
                        }
                    })
                    .collect::<Vec<_>>(),
            );
        }
        let base = self.closed_base.then(|| Vec3::new(0.0, 0.0, l));
        Ok(surface_of_revolution(Some(Vec3::zeros()), &rings, base))
    }
}

/// Stitches rings (each counter-clockwise about +z, listed bottom to top) into a tube with optional
/// pole fans, triangles facing outwards.
fn surface_of_revolution(bottom: Option<Vec3>, rings: &[Vec<Vec3>], top: Option<Vec3>) -> TriMesh {
    let n = rings.first().map_or(0, |r| r.len());
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    let bottom_index = bottom.map(|p| {
        positions.push(p);
        0u32
    });
    let first = positions.len() as u32;
    for ring in rings {
        positions.extend_from_slice(ring);
    }
    let ring_start = |k: usize| first + (k * n) as u32;
    if let Some(b) = bottom_index {
        for i in 0..n {
            let (p, q) = (
                ring_start(0) + i as u32,
                ring_start(0) + ((i + 1) % n) as u32,
            );
            triangles.push([b, q, p]);
        }
    }
    for k in 0..rings.len().saturating_sub(1) {
        for i in 0..n {
            let j = (i + 1) % n;
            let (a, b) = (ring_start(k) + i as u32, ring_start(k) + j as u32);
            let (c, d) = (ring_start(k + 1) + i as u32, ring_start(k + 1) + j as u32);
            triangles.push([a, b, d]);
            triangles.push([a, d, c]);
        }
    }
    if let Some(t) = top {
        positions.push(t);
        let ti = positions.len() as u32 - 1;
        let last = ring_start(rings.len() - 1);
        for i in 0..n {
            triangles.push([ti, last + i as u32, last + ((i + 1) % n) as u32]);
        }
    }
    TriMesh::new(positions, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    #[test]
    fn sphere_is_outward_and_close_to_analytic() {
        let m = uv_sphere(v3(3.0, -2.0, 1.0), 10.0, 96, 48);
        let v = m.signed_volume();
        let exact = 4.0 / 3.0 * PI * 1000.0;
        assert!(v > 0.0);
        assert!((v - exact).abs() / exact < 0.01, "volume {v} vs {exact}");
        assert!((m.area() - 4.0 * PI * 100.0).abs() / (4.0 * PI * 100.0) < 0.01);
    }

    #[test]
    fn parametric_lv_dimensions() {
        let lv = ParametricLv {
            closed_base: true,
            ..ParametricLv::default()
        };
        let m = lv.mesh(64, 40).unwrap();
        let (lo, hi) = m.bounds().unwrap();
        assert!(lo.z.abs() < 1e-12 && (hi.z - 80.0).abs() < 1e-12);
        assert!((hi.x - 25.0).abs() < 0.1, "max radius {}", hi.x);
        // Closed, outward: positive volume, a bit below the cylinder bound pi r^2 L.
        let v = m.volume_ml();
        assert!(
            v > 0.0 && v < PI * 25.0 * 25.0 * 80.0 / 1000.0,
            "volume {v}"
        );
        // Base ring radius.
        let top_ring: Vec<&Vec3> = m
            .positions
            .iter()
            .filter(|p| (p.z - 80.0).abs() < 1e-9)
            .collect();
        for p in top_ring.iter().filter(|p| p.x.hypot(p.y) > 1.0) {
            assert!((p.x.hypot(p.y) - 20.0).abs() < 1e-9);
        }
        assert!(ParametricLv {
            base_radius_mm: 30.0,
            ..lv
        }
        .mesh(8, 8)
        .is_err());
    }

    #[test]
    fn bulge_displaces_its_region_only() {
        let plain = ParametricLv::default().mesh(72, 40).unwrap();
        let bulged = ParametricLv {
            bulge: Some(Bulge {
                amplitude_mm: 5.0,
                height_fraction: 0.5,
                angle_deg: 0.0,
                width_mm: 8.0,
            }),
            ..ParametricLv::default()
        }
        .mesh(72, 40)
        .unwrap();
        let moved: Vec<f64> = plain
            .positions
            .iter()
            .zip(&bulged.positions)
            .map(|(p, q)| (p - q).norm())
            .collect();
        let max = moved.iter().cloned().fold(0.0, f64::max);
        assert!(max > 4.5 && max <= 5.0 + 1e-9, "max displacement {max}");
        // The opposite side (angle 180) is untouched.
        for (p, d) in plain.positions.iter().zip(&moved) {
            if p.x < -5.0 {
                assert!(*d < 1e-3);
            }
        }
    }
}
