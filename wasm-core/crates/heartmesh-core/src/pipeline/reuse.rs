//! How far solving the spline by conjugate gradients with a reused factor (`deform::tps`) moves
//! the vertices from factorising every step, on whole default runs of real contours: after every
//! deformation step the step's fit and a fresh, factorised fit of the same centres, targets and
//! weights are applied to the same vertices.

use super::precision::load;
use super::Reconstruction;
use crate::contours::ContourSet;
use crate::deform::tps::{SolveStats, TpsSolver};
use crate::geometry::Vec3;
use crate::Params;

struct Outcome {
    /// Largest vertex difference of any step between the step's fit and the factorised one (mm).
    worst_step_mm: f64,
    final_positions: Vec<Vec3>,
    stats: SolveStats,
}

fn run(set: &ContourSet, surface: Option<&str>, always_refactor: bool) -> Outcome {
    let params = Params {
        surface: surface.map(str::to_owned),
        ..Params::default()
    };
    let lambda = params.lambda;
    let mut rec = Reconstruction::new(set, params).unwrap_or_else(|e| panic!("new: {e}"));
    rec.tps.set_always_refactor(always_refactor);
    let mut exact = TpsSolver::new();
    exact.set_always_refactor(true);
    let mut worst = 0.0f64;
    let mut before: Vec<Vec3> = Vec::new();
    let (mut a, mut b) = (Vec::new(), Vec::new());
    loop {
        before.clone_from(&rec.mesh_unit.positions);
        rec.step().unwrap_or_else(|e| panic!("step: {e}"));
        if rec.iteration > 0 && !rec.tps.is_empty() && !always_refactor {
            // `rec.closest`, `rec.targets` and `rec.weights` are this step's fit inputs.
            // As the step: the data weight per contour attractor (end caps' lid points excluded).
            let lambda_eff = lambda / rec.real_attractors.min(rec.attractors.len()).max(1) as f64;
            let weights = rec.weighted.then_some(&rec.weights[..]);
            exact
                .fit_weighted(&rec.closest, &rec.targets, lambda_eff, weights)
                .unwrap_or_else(|e| panic!("exact fit: {e}"));
            a.clone_from(&before);
            b.clone_from(&before);
            rec.tps.apply_f64(&mut a);
            exact.apply_f64(&mut b);
            for (p, q) in a.iter().zip(&b) {
                worst = worst.max((p - q).norm() * rec.norm.scale);
            }
        }
        if rec.done {
            break;
        }
    }
    Outcome {
        worst_step_mm: worst,
        final_positions: rec.mesh().positions.clone(),
        stats: rec.tps.stats(),
    }
}

#[test]
fn reused_factor_moves_vertices_by_nanometres() {
    let cases = [
        ("surfco-example.csv", None),
        ("bivme-example-patient1/patient1-ED.csv", Some("RV_ENDO")),
        ("bivme-example-patient1/patient1-ES.csv", Some("LV_EPI")),
    ];
    for (file, surface) in cases {
        let set = load(file);
        let fast = run(&set, surface, false);
        let reference = run(&set, surface, true);
        let s = fast.stats;
        let fits = s.factorisations + s.reused;
        let final_mm = if fast.final_positions.len() == reference.final_positions.len() {
            fast.final_positions
                .iter()
                .zip(&reference.final_positions)
                .map(|(p, q)| (p - q).norm())
                .fold(0.0f64, f64::max)
        } else {
            f64::INFINITY
        };
        println!(
            "{file} {surface:?}: max step difference {:.3e} mm, final vertices {final_mm:.3e} mm; \
             {fits} fits: {} factorised, {} reused ({:.2} iterations each), {} failed",
            fast.worst_step_mm,
            s.factorisations,
            s.reused,
            s.iterations as f64 / s.reused.max(1) as f64,
            s.failed
        );
        assert_eq!(reference.stats.reused, 0, "{file}: the reference reused");
        assert!(s.reused > fits / 2, "{file}: the factor was rarely reused");
        // Per step the solve tolerance bounds the move (CG_RTOL in deform::tps).
        assert!(
            fast.worst_step_mm < 1e-6,
            "{file}: step {:e} mm",
            fast.worst_step_mm
        );
        // Over a whole run the differences pass through remeshing (discrete choices), so the
        // final vertices differ by more, but still far below the 0.05-0.6 mm contour distances.
        assert!(final_mm < 1e-3, "{file}: final {final_mm:e} mm");
    }
}
