//! Mesh-to-truth of the study's cases, aligned each way.
use super::cases::Case;
use heartmesh_core::contours::align::{align_slices_with, Options};
use heartmesh_core::contours::ContourSet;
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::{Params, Reconstruction};
use std::collections::HashMap;

/// Both ways of aligning: in-plane only (the product) and with through-plane offsets.
pub const BOTH: [(&str, Options); 2] = [
    (
        "in-plane",
        Options {
            through_plane: false,
        },
    ),
    (
        "through-plane",
        Options {
            through_plane: true,
        },
    ),
];

/// Reconstructs each surface of each case from the contours aligned each way (the defaults
/// otherwise, as `--align-slices` does) and prints mesh-to-truth mean / Hausdorff.
pub fn meshes_vs_truth(title: &str, cases: &[Case]) {
    println!("\n## {title}: mesh-to-truth mean / Hausdorff (mm), in-plane -> through-plane; folds");
    let mut sums = HashMap::<String, (f64, f64, f64, f64, usize)>::new();
    for case in cases {
        for (surface, truth) in &case.truths {
            let mut out = Vec::new();
            for (_, o) in BOTH {
                let (shifted, _) = align_slices_with(&case.set, o);
                let params = Params {
                    surface: surface.clone(),
                    ..Params::default()
                };
                let Ok(mut rec) = Reconstruction::new(&shifted, params) else {
                    continue;
                };
                let mut done = false;
                for _ in 0..100_000 {
                    match rec.step() {
                        Ok(r) if r.done => {
                            done = true;
                            break;
                        }
                        Ok(_) => {}
                        Err(_) => break,
                    }
                }
                if !done {
                    continue;
                }
                let mesh = rec.mesh().clone();
                let Ok(c) =
                    heartmesh_core::metrics::compare::compare(truth, &mesh, Some(&case.clip))
                else {
                    continue;
                };
                let folds = heartmesh_core::mesh::quality::quality(&mesh).folded_edges;
                out.push((c.mesh_to_truth.mean, c.hausdorff, folds));
            }
            if let [a, b] = out[..] {
                let key = surface.clone().unwrap_or("LV".into());
                println!(
                    "{:28} {key:8} {:.3} / {:.2} -> {:.3} / {:.2}  folds {} -> {}",
                    case.name, a.0, a.1, b.0, b.1, a.2, b.2
                );
                let e = sums.entry(key).or_default();
                e.0 += a.0;
                e.1 += b.0;
                e.2 += a.1;
                e.3 += b.1;
                e.4 += 1;
            }
        }
    }
    let mut keys: Vec<_> = sums.keys().cloned().collect();
    keys.sort();
    for k in keys {
        let (a, b, ha, hb, n) = sums[&k];
        let n = n as f64;
        println!(
            "ALL {title} {k}: mean {:.3} -> {:.3}, Hausdorff {:.2} -> {:.2} (averages over {n})",
            a / n,
            b / n,
            ha / n,
            hb / n
        );
    }
}

/// A reconstruction at the defaults (one surface), to the end; None if it fails.
pub fn run(set: &ContourSet, surface: Option<String>) -> Option<TriMesh> {
    let params = Params {
        surface,
        ..Params::default()
    };
    let mut rec = Reconstruction::new(set, params).ok()?;
    for _ in 0..100_000 {
        if rec.step().ok()?.done {
            return Some(rec.mesh().clone());
        }
    }
    None
}
