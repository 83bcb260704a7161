//! Indexed triangle meshes: the one mesh type of the core, plus measures and validity checks.

pub mod cells;
pub mod clip;
pub mod hex_wall;
pub mod inset;
pub mod intersect;
pub mod outline;
pub mod quality;
pub mod shapes;
pub mod topology;
pub mod wall;

use crate::geometry::Vec3;

/// An indexed triangle mesh in millimetres. Triangles are counter-clockwise seen from outside
/// (outward normals), so a closed mesh has positive [`TriMesh::volume`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriMesh {
    pub positions: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    pub fn new(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Self {
        TriMesh {
            positions,
            triangles,
        }
    }

    /// The three corners of triangle `t`.
    #[inline]
    pub fn corners(&self, t: usize) -> [Vec3; 3] {
        let [a, b, c] = self.triangles[t];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    /// Total surface area in mm^2.
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| self.triangle_area(t))
            .sum()
    }

    /// Area of triangle `t` in mm^2.
    #[inline]
    pub fn triangle_area(&self, t: usize) -> f64 {
        let [a, b, c] = self.corners(t);
        0.5 * (b - a).cross(&(c - a)).norm()
    }

    /// Signed enclosed volume in mm^3 (divergence theorem); meaningful for closed meshes, positive
    /// when the triangles face outwards.
    pub fn signed_volume(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.corners(t);
                a.dot(&b.cross(&c)) / 6.0
            })
            .sum()
    }

    /// Enclosed volume in millilitres (1 ml = 1000 mm^3).
    pub fn volume_ml(&self) -> f64 {
        self.signed_volume() / 1000.0
    }

    /// Flips every triangle (turns inward normals outward).
    pub fn flip_orientation(&mut self) {
        for t in &mut self.triangles {
            t.swap(1, 2);
        }
    }

    /// Axis-aligned bounds (min, max); None for an empty mesh.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let first = *self.positions.first()?;
        Some(
            self.positions
                .iter()
                .fold((first, first), |(lo, hi), p| (lo.inf(p), hi.sup(p))),
        )
    }

    /// Positions as flat f32 triples, for renderers and wasm (converted once, at the boundary).
    pub fn positions_f32(&self) -> Vec<f32> {
        self.positions
            .iter()
            .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
            .collect()
    }

    /// Triangle indices as a flat u32 array.
    pub fn indices_u32(&self) -> Vec<u32> {
        self.triangles.iter().flatten().copied().collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit right tetrahedron with outward faces.
    fn tetra() -> TriMesh {
        crate::mesh::shapes::unit_tetrahedron()
    }

    #[test]
    fn tetra_volume_and_area() {
        let m = tetra();
        assert!((m.signed_volume() - 1.0 / 6.0).abs() < 1e-12);
        let expected = 1.5 + 0.5 * 3f64.sqrt();
        assert!((m.area() - expected).abs() < 1e-12);
    }
}
