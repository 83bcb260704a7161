//! How far the mixed-precision spline evaluation (f32 kernel sum, `deform::tps`) moves the vertices
//! from the all-f64 evaluation, measured on whole default runs of real contours: before every
//! deformation step the same fit is applied both ways to the same vertices.

use super::Reconstruction;
use crate::contours::ContourSet;
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

pub(super) fn load(sub: &str) -> ContourSet {
    let path = data_path(&format!("contours/{sub}"));
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    io::read_contours(sub, &bytes).unwrap_or_else(|e| panic!("{sub}: {e}"))
}

/// Runs a default reconstruction; returns the largest f32-vs-f64 vertex difference of any step
/// and the largest vertex move of any step, both in mm.
fn worst_difference_mm(set: &ContourSet, surface: Option<&str>) -> (f64, f64) {
    let params = Params {
        surface: surface.map(str::to_owned),
        ..Params::default()
    };
    let mut rec = Reconstruction::new(set, params).unwrap_or_else(|e| panic!("new: {e}"));
    let (mut worst, mut largest_move) = (0.0f64, 0.0f64);
    let mut before: Vec<Vec3> = Vec::new();
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
        }
        if rec.done {
            break;
        }
    }
    (worst, largest_move)
}

#[test]
fn f32_kernel_sum_moves_vertices_by_micrometres() {
    let cases = [
        ("surfco-example.csv", None),
        ("bivme-example-patient1/patient1-ED.csv", Some("RV_ENDO")),
    ];
    for (file, surface) in cases {
        let (worst, largest_move) = worst_difference_mm(&load(file), surface);
        println!(
            "{file} {surface:?}: max |F32(x) - F64(x)| = {worst:.3e} mm (largest step {largest_move:.3} mm)"
        );
        assert!(worst < 1e-3, "{file}: {worst:e} mm");
        assert!(largest_move > 0.1, "{file}: nothing moved");
    }
}
