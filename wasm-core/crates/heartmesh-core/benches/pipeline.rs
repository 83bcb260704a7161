//! End-to-end benchmark: a full default reconstruction of real contour files (the SurFCo example and
//! biv-me patient 1 at end-diastole), with the median per-phase split printed after criterion's
//! timing. Data come from ../shared/data beside the repository (not shipped).
//!
//! `cargo bench --bench pipeline` (HEARTMESH_THREADS=1 for one thread)

use criterion::{criterion_group, criterion_main, Criterion};
use heartmesh_core::pipeline::PhaseTimings;
use heartmesh_core::{io, ContourSet, Params, Reconstruction};
use std::path::PathBuf;

fn shared(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../../shared/data/contours")
        .join(rel)
}

fn load(rel: &str) -> ContourSet {
    let path = shared(rel);
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    io::read_contours(rel, &bytes).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

fn reconstruct(set: &ContourSet, surface: Option<&str>) -> PhaseTimings {
    let params = Params {
        surface: surface.map(str::to_string),
        ..Params::default()
    };
    let mut r = Reconstruction::new(set, params).expect("valid input");
    r.run().expect("reconstruction");
    r.total_timings()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn bench(c: &mut Criterion) {
    // HEARTMESH_THREADS=1 times the single-threaded run.
    heartmesh_core::parallel::configure_from_env();
    let cases = [
        ("surfco-example", "surfco-example.csv", None),
        (
            "patient1-ED-LV_ENDO",
            "bivme-example-patient1/patient1-ED.csv",
            Some("LV_ENDO"),
        ),
        (
            "patient1-ED-RV_ENDO",
            "bivme-example-patient1/patient1-ED.csv",
            Some("RV_ENDO"),
        ),
    ];
    let mut g = c.benchmark_group("reconstruct_default");
    g.sample_size(10);
    for (name, file, surface) in cases {
        let set = load(file);
        g.bench_function(name, |b| b.iter(|| reconstruct(&set, surface)));
        let runs: Vec<PhaseTimings> = (0..7).map(|_| reconstruct(&set, surface)).collect();
        let m = |f: fn(&PhaseTimings) -> f64| median(runs.iter().map(f).collect());
        println!(
            "{name}: median of 7 per phase (ms): total {:.1} | attractors {:.1} closest {:.1} solve {:.1} apply {:.1} remesh {:.1}",
            m(|t| t.total_ms),
            m(|t| t.attractors_ms),
            m(|t| t.closest_ms),
            m(|t| t.solve_ms),
            m(|t| t.apply_ms),
            m(|t| t.remesh_ms)
        );
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
