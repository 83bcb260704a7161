//! What the mixed precision of `deform::tps` changes, measured on whole default runs of real
//! contours: how far the f32 kernel sum of the evaluation moves the vertices from the all-f64
//! evaluation (every step's fit applied both ways to the same vertices), and how far the solve
//! (f32 factor, f64 refinement) is from the all-f64 solve of the same system.

use super::Reconstruction;
use crate::contours::ContourSet;
use crate::deform::tps::{tests::solution_difference, TpsSolver};
use crate::geometry::Vec3;
use crate::{io, Params};
use std::path::PathBuf;

/// `shared/data/<sub>` beside the checkout or any ancestor (as `tests/common`).
fn data_path(sub: &str) -> PathBuf {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    manifest
        .ancestors()
        .map(|a| a.join("shared/data"))
        .find(|d| d.is_dir())
        .unwrap_or_else(|| manifest.join("../../../../shared/data"))
        .join(sub)
}

fn load(sub: &str) -> ContourSet {
    let path = data_path(&format!("contours/{sub}"));
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    io::read_contours(sub, &bytes).unwrap_or_else(|e| panic!("{sub}: {e}"))
}

struct Worst {
    /// Largest f32-vs-f64 evaluation difference of any vertex at any step, mm.
    eval_mm: f64,
    /// Largest vertex move of any step, mm.
    largest_move_mm: f64,
    /// Largest relative difference of a mixed solve from the all-f64 one.
    solve: f64,
    max_refinements: usize,
    fallbacks: usize,
    fits: usize,
}

/// Runs a default reconstruction and compares every step's fit and evaluation with all-f64 ones.
fn worst_differences(set: &ContourSet, surface: Option<&str>) -> Worst {
    let params = Params {
        surface: surface.map(str::to_owned),
        ..Params::default()
    };
    let mut rec = Reconstruction::new(set, params).unwrap_or_else(|e| panic!("new: {e}"));
    let (mut worst, mut largest_move) = (0.0f64, 0.0f64);
    let mut before: Vec<Vec3> = Vec::new();
    let mut reference = TpsSolver::new();
    reference.f64_only = true;
    let (mut solve, mut max_refinements, mut fallbacks, mut fits) = (0.0f64, 0, 0, 0);
    loop {
        before.clone_from(&rec.mesh_unit.positions);
        rec.step().unwrap_or_else(|e| panic!("step: {e}"));
        if rec.iteration > 0 && !rec.tps.is_empty() {
            // `rec.tps` holds the fit this step applied to `before`.
            let (mut mixed, mut exact) = (before.clone(), before.clone());
            rec.tps.apply(&mut mixed);
            rec.tps.apply_f64(&mut exact);
            for ((a, b), p) in mixed.iter().zip(&exact).zip(&before) {
                worst = worst.max((a - b).norm() * rec.norm.scale);
                largest_move = largest_move.max((b - p).norm() * rec.norm.scale);
            }
            let st = rec.tps.last_solve;
            fits += 1;
            fallbacks += usize::from(st.fell_back);
            max_refinements = max_refinements.max(st.refinements);
            let lambda_eff = rec.params.lambda / rec.attractors.len() as f64;
            // The same system: with the conflict weights of the step when it had any.
            reference
                .fit_weighted(
                    &rec.closest,
                    &rec.targets,
                    lambda_eff,
                    rec.weighted.then_some(&rec.weights[..]),
                )
                .unwrap_or_else(|e| panic!("f64 fit: {e}"));
            solve = solve.max(solution_difference(&rec.tps, &reference));
        }
        if rec.done {
            break;
        }
    }
    Worst {
        eval_mm: worst,
        largest_move_mm: largest_move,
        solve,
        max_refinements,
        fallbacks,
        fits,
    }
}

#[test]
fn mixed_precision_changes_micrometres() {
    let cases = [
        ("surfco-example.csv", None),
        ("bivme-example-patient1/patient1-ED.csv", Some("RV_ENDO")),
    ];
    for (file, surface) in cases {
        let w = worst_differences(&load(file), surface);
        println!(
            "{file} {surface:?}: evaluation max |F32(x) - F64(x)| = {:.3e} mm (largest step \
             {:.3} mm); solve max relative difference {:.3e}, {} fits, at most {} refinement \
             steps, {} fallbacks",
            w.eval_mm, w.largest_move_mm, w.solve, w.fits, w.max_refinements, w.fallbacks
        );
        assert!(w.eval_mm < 1e-3, "{file}: {:e} mm", w.eval_mm);
        assert!(w.largest_move_mm > 0.1, "{file}: nothing moved");
        assert!(w.solve < 1e-9, "{file}: solve {:e}", w.solve);
        assert!(
            w.fits > 100 && w.max_refinements <= 4,
            "{file}: {} fits",
            w.fits
        );
    }
}
