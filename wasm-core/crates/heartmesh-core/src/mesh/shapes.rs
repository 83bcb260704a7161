//! Simple reference shapes with known geometry (sphere, tube), used by tests and benchmarks to check
//! remeshing against exact radii and volumes, and handy as fixtures elsewhere.

use crate::geometry::{v3, Vec3};
use crate::mesh::TriMesh;
use std::collections::HashMap;

/// The right tetrahedron on the unit axes (volume 1/6), faces outward: the smallest closed mesh.
pub fn unit_tetrahedron() -> TriMesh {
    TriMesh::new(
        vec![
            v3(0., 0., 0.),
            v3(1., 0., 0.),
            v3(0., 1., 0.),
            v3(0., 0., 1.),
        ],
        vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    )
}

/// A regular octahedron with vertices `radius` mm from `centre` on the axes, faces outward.
pub fn octahedron(radius: f64, centre: Vec3) -> TriMesh {
    let p = |x: f64, y: f64, z: f64| centre + v3(x, y, z) * radius;
    TriMesh::new(
        vec![
            p(1., 0., 0.),
            p(-1., 0., 0.),
            p(0., 1., 0.),
            p(0., -1., 0.),
            p(0., 0., 1.),
            p(0., 0., -1.),
        ],
        vec![
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ],
    )
}

/// An icosphere of `radius` mm centred at the origin: an icosahedron whose faces are split into 4,
/// `level` times, with every vertex projected onto the sphere. 20 * 4^level triangles, outward.
pub fn icosphere(radius: f64, level: u32) -> TriMesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut positions: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| v3(x, y, z).normalize() * radius)
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut next = Vec::with_capacity(triangles.len() * 4);
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<Vec3>| -> u32 {
            let key = (a.min(b), a.max(b));
            *midpoints.entry(key).or_insert_with(|| {
                let p = (positions[a as usize] + positions[b as usize]).normalize() * radius;
                positions.push(p);
                (positions.len() - 1) as u32
            })
        };
        for &[a, b, c] in &triangles {
            let ab = midpoint(a, b, &mut positions);
            let bc = midpoint(b, c, &mut positions);
            let ca = midpoint(c, a, &mut positions);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    TriMesh::new(positions, triangles)
}

/// A cylinder of `radius` mm around the z axis from z = 0 to z = `height`, made like the initial
/// mesh of the method: `rings` rings of `segments` points, two triangles per quad, and with `lids`
/// a fan to one apex point at the centre of each end ring (apex valence = `segments`).
/// Outward-oriented; open (two boundary loops) without lids.
pub fn cylinder_tube(
    radius: f64,
    height: f64,
    segments: usize,
    rings: usize,
    lids: bool,
) -> TriMesh {
    let segments = segments.max(3);
    let rings = rings.max(2);
    let mut positions = Vec::with_capacity(segments * rings + 2);
    for j in 0..rings {
        let z = height * j as f64 / (rings - 1) as f64;
        for i in 0..segments {
            let a = std::f64::consts::TAU * i as f64 / segments as f64;
            positions.push(v3(radius * a.cos(), radius * a.sin(), z));
        }
    }
    let at = |j: usize, i: usize| (j * segments + i % segments) as u32;
    let mut triangles = Vec::with_capacity(2 * segments * rings);
    for j in 0..rings - 1 {
        for i in 0..segments {
            triangles.push([at(j, i), at(j, i + 1), at(j + 1, i)]);
            triangles.push([at(j + 1, i), at(j, i + 1), at(j + 1, i + 1)]);
        }
    }
    if lids {
        let bottom = positions.len() as u32;
        positions.push(v3(0.0, 0.0, 0.0));
        let top = positions.len() as u32;
        positions.push(v3(0.0, 0.0, height));
        for i in 0..segments {
            triangles.push([bottom, at(0, i + 1), at(0, i)]);
            triangles.push([top, at(rings - 1, i), at(rings - 1, i + 1)]);
        }
    }
    TriMesh::new(positions, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn icosphere_counts_and_volume() {
        let s = icosphere(10.0, 3);
        assert_eq!(s.triangles.len(), 1280);
        assert_eq!(s.positions.len(), 642);
        let exact = 4.0 / 3.0 * std::f64::consts::PI * 1000.0;
        let v = s.signed_volume();
        assert!(v > 0.97 * exact && v < exact, "volume {v}");
    }

    #[test]
    fn tube_volume() {
        let t = cylinder_tube(10.0, 30.0, 50, 7, true);
        let exact = std::f64::consts::PI * 100.0 * 30.0;
        let v = t.signed_volume();
        assert!(v > 0.99 * exact && v < exact, "volume {v}");
    }
}
