//! Benchmarks of the remeshing step (Villard et al. 2018, METHOD.md section 5) at the sizes the
//! pipeline sees: a ~5-6k-triangle surface is subdivided to ~20-23k, smoothed 200 times and
//! decimated by 0.72 (PERFORMANCE.md: meshoptimizer needs ~5.6 ms for 23k -> 6.5k).

use criterion::{black_box, criterion_group, Criterion};
use heartmesh_core::geometry::Vec3;
use heartmesh_core::mesh::shapes::icosphere;
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::refine::smooth::laplacian_direct;
use heartmesh_core::refine::{decimate, laplacian, remesh, smooth, subdivide};

/// An icosphere of radius 10 mm (5120 triangles) with 0.1 mm of deterministic noise, so the
/// decimation does not meet the perfectly regular special case.
fn sphere() -> TriMesh {
    let mut m = icosphere(10.0, 4);
    let mut state = 0x9e3779b97f4a7c15u64;
    for p in &mut m.positions {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let r = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        *p += *p / p.norm() * (0.2 * r);
    }
    m
}

fn benches(c: &mut Criterion) {
    let base = sphere();
    let fine = subdivide(&base).expect("subdivide a clean sphere");
    let smoothed = smooth(&fine, 200, 0.1).expect("smooth a clean sphere");
    let mut g = c.benchmark_group("refine");
    g.sample_size(20);
    g.bench_function("subdivide 5120 tris", |b| {
        b.iter(|| subdivide(black_box(&base)))
    });
    g.bench_function("smooth 200 x 5120 tris", |b| {
        b.iter(|| smooth(black_box(&base), 200, 0.1))
    });
    g.bench_function("decimate 0.72 of 5120 tris", |b| {
        b.iter(|| decimate(black_box(&base), 0.72))
    });
    g.bench_function("smooth 200 x 20480 tris", |b| {
        b.iter(|| smooth(black_box(&fine), 200, 0.1))
    });
    g.bench_function("decimate 0.72 of 20480 tris", |b| {
        b.iter(|| decimate(black_box(&smoothed), 0.72))
    });
    g.bench_function("remesh 5120 tris", |b| {
        b.iter(|| remesh(black_box(&base), 200, 0.1, 0.72))
    });
    g.finish();
    let _: Vec3 = base.positions[0];
}

/// `REFINE_BENCH_MIN=N cargo bench --bench refine` prints the fastest of N runs of each step and
/// skips criterion: on a shared, loaded machine the minimum is the most stable figure.
fn min_times(runs: usize) {
    let base = sphere();
    let fine = subdivide(&base).expect("subdivide a clean sphere");
    let smoothed = smooth(&fine, 200, 0.1).expect("smooth a clean sphere");
    let time = |name: &str, f: &dyn Fn()| {
        let (mut best, mut best_cpu) = (f64::INFINITY, f64::INFINITY);
        for _ in 0..runs {
            let (t, c) = (std::time::Instant::now(), thread_cpu_ms());
            f();
            best = best.min(t.elapsed().as_secs_f64() * 1e3);
            best_cpu = best_cpu.min(thread_cpu_ms() - c);
        }
        println!("{name}: min {best:.3} ms wall, {best_cpu:.3} ms on-CPU, {runs} runs");
    };
    time("subdivide 5120 tris", &|| {
        black_box(subdivide(&base).ok());
    });
    time("smooth 200 x 5120 tris", &|| {
        black_box(smooth(&base, 200, 0.1).ok());
    });
    time("decimate 0.72 of 5120 tris", &|| {
        black_box(decimate(&base, 0.72).ok());
    });
    time("smooth 200 x 20480 tris", &|| {
        black_box(smooth(&fine, 200, 0.1).ok());
    });
    time("laplacian 200 x 20480 tris, sweep by sweep", &|| {
        black_box(laplacian_direct(&fine, 200, 0.1).ok());
    });
    time("laplacian 200 x 20480 tris, Chebyshev series", &|| {
        black_box(laplacian(&fine, 200, 0.1).ok());
    });
    time("decimate 0.72 of 20480 tris", &|| {
        black_box(decimate(&smoothed, 0.72).ok());
    });
    time("remesh 5120 tris", &|| {
        black_box(remesh(&base, 200, 0.1, 0.72).ok());
    });
}

/// Time this thread spent on a CPU (Linux schedstat; NaN elsewhere): on a machine shared with
/// other jobs it excludes the time spent waiting for a core.
fn thread_cpu_ms() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .map_or(f64::NAN, |ns| ns / 1e6)
}

criterion_group!(refine_benches, benches);

fn main() {
    match std::env::var("REFINE_BENCH_MIN")
        .ok()
        .and_then(|v| v.parse().ok())
    {
        Some(runs) => min_times(runs),
        None => {
            refine_benches();
            Criterion::default().configure_from_args().final_summary();
        }
    }
}
