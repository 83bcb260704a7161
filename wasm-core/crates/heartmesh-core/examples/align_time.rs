//! Developer tool: the cost of breath-hold slice alignment (`contours::align`) on one contour
//! file. `cargo run --release --example align_time -- FILE [REPEATS]` prints the median time of
//! `align_slices` over the repeats, the rounds and the residuals.
use heartmesh_core::contours::align::align_slices;
use heartmesh_core::io;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: align_time FILE [REPEATS]");
        std::process::exit(2);
    };
    let repeats: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(9);
    let set = match std::fs::read(path)
        .map_err(|e| e.to_string())
        .and_then(|b| io::read_contours(path, &b).map_err(|e| e.to_string()))
    {
        Ok(s) => s,
        Err(e) => {
            eprintln!("{path}: {e}");
            std::process::exit(2);
        }
    };
    let mut ms = Vec::new();
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let t = Instant::now();
        let (_, a) = align_slices(&set);
        ms.push(t.elapsed().as_secs_f64() * 1e3);
        last = Some(a);
    }
    ms.sort_by(f64::total_cmp);
    if let Some(a) = last {
        println!(
            "{path}: median {:.2} ms (min {:.2}, max {:.2}) over {} runs; {} groups, {} rounds, residual {:.3} -> {:.3} mm, largest shift {:.2} mm",
            ms[ms.len() / 2],
            ms[0],
            ms[ms.len() - 1],
            ms.len(),
            a.groups.len(),
            a.rounds,
            a.residual_before_mm,
            a.residual_after_mm,
            a.max_shift_mm()
        );
    }
}
