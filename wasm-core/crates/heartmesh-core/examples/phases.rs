//! Developer tool: time full default reconstructions of one contour file and print the median
//! per-phase split plus the result figures (to check that a speed-up did not change the result).
//! `cargo run --release --example phases -- FILE [SURFACE] [REPEATS]`; one thread
//! unless HEARTMESH_THREADS=N asks for N.
use heartmesh_core::pipeline::PhaseTimings;
use heartmesh_core::{io, Params, Reconstruction};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    heartmesh_core::parallel::configure_from_env();
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: phases FILE [SURFACE|-] [REPEATS]");
        std::process::exit(2);
    };
    let surface = args.get(2).filter(|s| *s != "-").cloned();
    let repeats: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(5);
    let run = || -> Result<(), heartmesh_core::CoreError> {
        let bytes =
            std::fs::read(path).map_err(|e| heartmesh_core::CoreError::Io(e.to_string()))?;
        let set = io::read_contours(path, &bytes)?;
        let mut runs: Vec<PhaseTimings> = Vec::new();
        for rep in 0..repeats {
            let params = Params {
                surface: surface.clone(),
                ..Params::default()
            };
            let mut r = Reconstruction::new(&set, params)?;
            r.run()?;
            runs.push(r.total_timings());
            if rep == 0 {
                let d = r.contour_distances();
                let m = r.mesh();
                println!(
                    "result: V {} T {} volume {:.6} ml  contour mean {:.6} median {:.6} max {:.6} mm",
                    m.positions.len(),
                    m.triangles.len(),
                    m.signed_volume() / 1000.0,
                    d.overall.mean,
                    d.overall.median,
                    d.overall.max
                );
                if let Some(f) = std::env::var_os("HM_DUMP") {
                    let text: String = m
                        .positions
                        .iter()
                        .map(|p| format!("{:.17e} {:.17e} {:.17e}\n", p.x, p.y, p.z))
                        .collect();
                    std::fs::write(f, text).ok();
                }
            }
        }
        let m = |f: fn(&PhaseTimings) -> f64| median(runs.iter().map(f).collect());
        println!(
            "median of {repeats} ({} thread(s), ms): total {:.1} | attractors {:.1} closest {:.1} solve {:.1} apply {:.1} remesh {:.1}",
            heartmesh_core::parallel::threads(),
            m(|t| t.total_ms),
            m(|t| t.attractors_ms),
            m(|t| t.closest_ms),
            m(|t| t.solve_ms),
            m(|t| t.apply_ms),
            m(|t| t.remesh_ms)
        );
        Ok(())
    };
    if let Err(e) = run() {
        eprintln!("{path}: {e}");
        std::process::exit(2);
    }
}
