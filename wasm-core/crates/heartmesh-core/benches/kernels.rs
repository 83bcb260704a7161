//! Benchmarks of the per-iteration kernels of the deformation loop (see PERFORMANCE.md):
//! thin-plate-spline fit and evaluation, BVH build / refit / closest-point queries.
//!
//! Run with `cargo bench -p heartmesh-core --bench kernels`. Sizes match the default pipeline:
//! N = 200-300 attractors, ~3k vertices, a ~6k-triangle mesh.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use heartmesh_core::deform::tps::TpsSolver;
use heartmesh_core::geometry::{v3, Vec3};
use heartmesh_core::spatial::Bvh;
use heartmesh_core::TriMesh;
use std::time::Duration;

/// splitmix64, so inputs are the same on every run.
struct Rng(u64);
impl Rng {
    fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn vec3(&mut self, h: f64) -> Vec3 {
        v3(
            (2.0 * self.unit() - 1.0) * h,
            (2.0 * self.unit() - 1.0) * h,
            (2.0 * self.unit() - 1.0) * h,
        )
    }
}

/// UV sphere of radius r: 2 * segments * (rings - 1) triangles.
fn sphere(r: f64, rings: usize, segments: usize) -> TriMesh {
    use std::f64::consts::PI;
    let mut pos = vec![v3(0., 0., -r)];
    for i in 1..rings {
        let th = PI * i as f64 / rings as f64;
        for j in 0..segments {
            let ph = 2.0 * PI * j as f64 / segments as f64;
            pos.push(v3(
                r * th.sin() * ph.cos(),
                r * th.sin() * ph.sin(),
                -r * th.cos(),
            ));
        }
    }
    pos.push(v3(0., 0., r));
    let top = (pos.len() - 1) as u32;
    let ring = |i: usize, j: usize| (1 + (i - 1) * segments + j % segments) as u32;
    let mut tris = Vec::new();
    for j in 0..segments {
        tris.push([0, ring(1, j + 1), ring(1, j)]);
        tris.push([top, ring(rings - 1, j), ring(rings - 1, j + 1)]);
    }
    for i in 1..rings - 1 {
        for j in 0..segments {
            let (a, b, c, d) = (
                ring(i, j),
                ring(i, j + 1),
                ring(i + 1, j),
                ring(i + 1, j + 1),
            );
            tris.push([a, b, d]);
            tris.push([a, d, c]);
        }
    }
    TriMesh::new(pos, tris)
}

/// Attractor-like centres on a unit-diameter ellipsoid (normalised units) and targets a small
/// step away, as in one deformation iteration.
fn tps_problem(n: usize) -> (Vec<Vec3>, Vec<Vec3>) {
    let mut rng = Rng(7);
    let centres: Vec<Vec3> = (0..n)
        .map(|_| {
            let d = rng.vec3(1.0).normalize();
            v3(0.3 * d.x + 1.2, 0.25 * d.y - 0.4, 0.5 * d.z)
        })
        .collect();
    let targets = centres.iter().map(|c| c + rng.vec3(0.002)).collect();
    (centres, targets)
}

fn bench_tps(c: &mut Criterion) {
    for n in [200usize, 300] {
        let (centres, targets) = tps_problem(n);
        // Projection and factorisation every fit (a repeated fit would otherwise reuse it).
        let mut solver = TpsSolver::new();
        solver.set_always_refactor(true);
        c.bench_function(&format!("tps_fit_n{n}"), |b| {
            b.iter(|| {
                solver
                    .fit(black_box(&centres), black_box(&targets), 1e5 / n as f64)
                    .expect("benchmark fit")
            })
        });
    }
    // A fit reusing the last factor: the centres alternate between two sets 1e-4 apart (about
    // the move of one late deformation step), so every fit is a nearby system.
    let (centres, targets) = tps_problem(200);
    let mut rng = Rng(9);
    let moved: Vec<Vec3> = centres.iter().map(|c| c + rng.vec3(1e-4)).collect();
    let mut solver = TpsSolver::new();
    let mut flip = false;
    c.bench_function("tps_refit_n200_reused", |b| {
        b.iter(|| {
            flip = !flip;
            let cs = if flip { &moved } else { &centres };
            solver
                .fit(black_box(cs), black_box(&targets), 1e5 / 200.0)
                .expect("benchmark fit")
        })
    });
    let (centres, targets) = tps_problem(300);
    let mut solver = TpsSolver::new();
    solver
        .fit(&centres, &targets, 1e5 / 300.0)
        .expect("benchmark fit");
    let mesh = sphere(0.4, 40, 76);
    let mut pts: Vec<Vec3> = mesh
        .positions
        .iter()
        .take(3000)
        .map(|p| p + v3(1.2, -0.4, 0.0))
        .collect();
    pts.truncate(3000);
    let original = pts.clone();
    c.bench_function(&format!("tps_apply_{}v_x300", pts.len()), |b| {
        b.iter(|| {
            pts.copy_from_slice(&original);
            solver.apply(black_box(&mut pts));
        })
    });
}

fn bench_bvh(c: &mut Criterion) {
    let mesh = sphere(30.0, 40, 76);
    let n_tri = mesh.triangles.len();
    c.bench_function(&format!("bvh_build_{n_tri}t"), |b| {
        b.iter(|| Bvh::build(black_box(&mesh)))
    });
    let mut bvh = Bvh::build(&mesh);
    let mut moved = mesh.clone();
    for p in &mut moved.positions {
        *p = v3(1.1 * p.x, 0.9 * p.y, p.z + 0.05 * p.x);
    }
    c.bench_function(&format!("bvh_refit_{n_tri}t"), |b| {
        b.iter(|| bvh.refit(black_box(&moved)).expect("same topology"))
    });
    let mut rng = Rng(11);
    // Attractor-like queries: near the surface (within a few mm), as in the deformation loop.
    let queries: Vec<Vec3> = (0..300)
        .map(|_| {
            let d = rng.vec3(1.0).normalize();
            d * (30.0 + 6.0 * (rng.unit() - 0.5))
        })
        .collect();
    let bvh = Bvh::build(&mesh);
    let mut out = Vec::with_capacity(300);
    c.bench_function(&format!("bvh_300_queries_{n_tri}t"), |b| {
        b.iter(|| bvh.closest_points(black_box(&mesh), black_box(&queries), &mut out))
    });
}

criterion_group! {
    name = kernels;
    config = Criterion::default()
        .sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    targets = bench_tps, bench_bvh
}
criterion_main!(kernels);
