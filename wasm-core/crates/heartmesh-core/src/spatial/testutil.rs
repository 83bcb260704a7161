//! Deterministic test helpers: a splitmix64 generator (Steele, Lea & Flood, "Fast splittable
//! pseudorandom number generators", OOPSLA 2014) and a few random meshes, so tests are seeded and
//! reproducible without a `rand` dependency.

use crate::geometry::{v3, Vec3};
use crate::mesh::TriMesh;

/// splitmix64: tiny, fast, and good enough for test inputs.
pub struct SplitMix64(u64);

impl SplitMix64 {
    pub fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    pub fn vec3(&mut self, lo: f64, hi: f64) -> Vec3 {
        v3(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }
}

/// A UV sphere of radius `r` with `rings` x `segments` quads, outward-oriented and closed.
pub fn uv_sphere(r: f64, rings: usize, segments: usize) -> TriMesh {
    let mut positions = vec![v3(0., 0., -r)];
    for i in 1..rings {
        let th = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..segments {
            let ph = 2.0 * std::f64::consts::PI * j as f64 / segments as f64;
            positions.push(v3(
                r * th.sin() * ph.cos(),
                r * th.sin() * ph.sin(),
                -r * th.cos(),
            ));
        }
    }
    positions.push(v3(0., 0., r));
    let top = (positions.len() - 1) as u32;
    let ring = |i: usize, j: usize| (1 + (i - 1) * segments + j % segments) as u32;
    let mut triangles = Vec::new();
    for j in 0..segments {
        triangles.push([0, ring(1, j + 1), ring(1, j)]);
    }
    for i in 1..rings - 1 {
        for j in 0..segments {
            let (a, b) = (ring(i, j), ring(i, j + 1));
            let (c, d) = (ring(i + 1, j), ring(i + 1, j + 1));
            triangles.push([a, b, d]);
            triangles.push([a, d, c]);
        }
    }
    for j in 0..segments {
        triangles.push([top, ring(rings - 1, j), ring(rings - 1, j + 1)]);
    }
    TriMesh::new(positions, triangles)
}

/// A soup of random triangles, some of them degenerate (repeated or collinear corners).
pub fn random_soup(rng: &mut SplitMix64, n_vertices: usize, n_triangles: usize) -> TriMesh {
    let mut positions: Vec<Vec3> = (0..n_vertices).map(|_| rng.vec3(-10.0, 10.0)).collect();
    // A few exactly collinear vertex triples.
    for k in 0..n_vertices / 20 {
        let i = 3 * k;
        if i + 2 < n_vertices {
            positions[i + 2] = positions[i] + (positions[i + 1] - positions[i]) * 2.5;
        }
    }
    let mut triangles = Vec::with_capacity(n_triangles);
    for t in 0..n_triangles {
        let tri = match t % 17 {
            0 => {
                let a = rng.below(n_vertices) as u32;
                [a, a, rng.below(n_vertices) as u32]
            }
            1 if n_vertices >= 20 => {
                let k = (3 * rng.below(n_vertices / 20)) as u32;
                [k, k + 1, k + 2]
            }
            _ => [
                rng.below(n_vertices) as u32,
                rng.below(n_vertices) as u32,
                rng.below(n_vertices) as u32,
            ],
        };
        triangles.push(tri);
    }
    TriMesh::new(positions, triangles)
}

/// A random m x m factor B and the symmetric positive definite A = B B^T + m I (row-major, full),
/// for the dense and preconditioned solver tests.
pub fn random_spd(rng: &mut SplitMix64, m: usize) -> (Vec<f64>, Vec<f64>) {
    let b: Vec<f64> = (0..m * m).map(|_| rng.range(-1.0, 1.0)).collect();
    let mut a = vec![0.0; m * m];
    for i in 0..m {
        for j in 0..m {
            let s: f64 = (0..m).map(|k| b[i * m + k] * b[j * m + k]).sum();
            a[i * m + j] = s + if i == j { m as f64 } else { 0.0 };
        }
    }
    (b, a)
}
