//! Developer tool: reconstruct one contour file and print every step's distances, mesh quality
//! (folds, triangle shape) and timings.
//! `cargo run --release --example trace -- FILE [SURFACE] [--no-soften]`
//! (`--no-soften`: without the conflict softening of the final steps, `Params::soften_conflicts`)
use heartmesh_core::mesh::quality::quality;
use heartmesh_core::{io, Params, Reconstruction};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: trace FILE [SURFACE]");
        std::process::exit(2);
    };
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) => {
            eprintln!("{path}: {e}");
            std::process::exit(2);
        }
    };
    let run = || -> Result<(), heartmesh_core::CoreError> {
        let set = io::read_contours(path, &bytes)?;
        let params = Params {
            surface: args.get(2).filter(|a| !a.starts_with("--")).cloned(),
            soften_conflicts: !args.iter().any(|a| a == "--no-soften"),
            ..Params::default()
        };
        let mut r = Reconstruction::new(&set, params)?;
        while !r.is_done() {
            let s = r.step()?;
            if s.iteration % 10 == 0 || s.done || s.topology_changed {
                let q = quality(r.mesh());
                println!(
                    "it {:3} {:?} max {:.3} mean {:.3} mm  V {} T {}  folds {} (max dihedral {:.0} deg) min q {:.2} longest edge {:.1} mm  {:.2} ms",
                    s.iteration,
                    s.phase,
                    s.max_distance_mm,
                    s.mean_distance_mm,
                    s.vertices,
                    s.triangles,
                    q.folded_edges,
                    q.max_dihedral_deg,
                    q.min_triangle_quality,
                    q.max_edge_mm,
                    s.timings.total_ms
                );
            }
        }
        let d = r.contour_distances();
        for c in &d.per_contour {
            println!(
                "{:28} {:?} mean {:.3} max {:.3}",
                c.id, c.kind, c.stats.mean, c.stats.max
            );
        }
        println!(
            "overall mean {:.3} median {:.3} max {:.3}  volume {:.1} ml  timings {:?}",
            d.overall.mean,
            d.overall.median,
            d.overall.max,
            r.mesh().volume_ml(),
            r.total_timings()
        );
        Ok(())
    };
    if let Err(e) = run() {
        eprintln!("{path}: {e}");
        std::process::exit(1);
    }
}
