//! The method on shapes it was not developed on (docs/VALIDATION.md "Session 7: population"): a
//! fixed-seed population drawn from the eight reference shapes (`sim::population`: scaled 0.6-1.4,
//! bent, warped by Gaussian bumps, posed anywhere in scanner space), sliced as the accuracy tests
//! slice them (LV: 3 LAX on its own axis; RV: one LAX, SAX on the LV axis of the same subject),
//! reconstructed at the defaults.
//!
//! Every reconstruction must be closed, manifold and outward, have at most the real cases' fold
//! bound, and meet the acceptance means (LV 0.2 mm, RV 0.5 mm); misaligned (2 mm / 2 degrees)
//! acquisitions must keep the contour-to-mesh mean within 1 mm. Maxima are printed for every
//! shape; the accuracy tests' Hausdorff target is asserted only for the surface types that meet
//! it (MAX_CHECKED). RVs may fold along their crescent's real creases (RV_MAX_FOLDED_EDGES).

mod common;

use common::*;
use heartmesh_core::sim::experiment::{Design, Experiment, Row};
use heartmesh_core::sim::population::{generate, Base, Plan, Source};
use heartmesh_core::Params;

const LV_MEAN_MM: f64 = 0.2;
const RV_MEAN_MM: f64 = 0.5;
const MISALIGNED_C2M_MEAN_MM: f64 = 1.0;
/// The real cases' fold bound (tests/real_cases.rs MAX_FOLDED_EDGES), held by every LV.
const MAX_FOLDED_EDGES: f64 = 3.0;
/// RVs end with folded edges along the crescent's tips, where the truth is creased (biv-me:
/// dihedral 161-177 degrees) or the short-axis contours turn by 110-180 degrees (the spasm cavity's
/// free wall meeting its septum): the mesh follows a real crease (docs/VALIDATION.md, "Session 8:
/// RV folds": all 55 folds of the 20 aligned RVs of `scripts/population.sh` are of that kind).
/// How many edges line a crease varies with the mesh (0-8 aligned, 0-10 misaligned there), so the
/// bound is this sample's measured 5 plus 2; it was 10 while the decimation also left folds where
/// the truth is smooth.
const RV_MAX_FOLDED_EDGES: f64 = 7.0;
/// Surface types whose maxima meet the accuracy tests' Hausdorff target (LV 1.5 mm) on the
/// reference shapes and across the population; the others are printed only (their maxima are
/// the unobserved features analysed in docs/VALIDATION.md, sessions 6 and 7).
const MAX_CHECKED: [&str; 3] = ["lv-endo-param", "lv-endo-cap", "lv-epi-cap"];
const LV_MAX_MM: f64 = 1.5;
/// Members per base shape (8 bases): 16 shapes, 32 runs, a few seconds each in release.
const PER_BASE: usize = 2;
const SEED: u64 = 7;

fn bases() -> Vec<Base> {
    let lv = |name: &str, file: &str| Base {
        name: name.into(),
        source: Source::Mesh(load_truth(file)),
        plan: Plan::Lv,
    };
    vec![
        Base {
            name: "lv-endo-param".into(),
            source: Source::Parametric,
            plan: Plan::Lv,
        },
        lv("lv-endo-cap", "cap-atlas-mean-ED-LV_ENDO-open.obj"),
        lv("lv-endo-spasm", "cardiomesh-spasm-LV_endo.obj"),
        lv("lv-endo-bivme", "bivme-patient1-ED-LV_ENDO-closed.obj"),
        lv("lv-epi-cap", "cap-atlas-mean-ED-LV_EPI-open.obj"),
        lv("lv-epi-spasm", "cardiomesh-spasm-LV_epi.obj"),
        Base {
            name: "rv-bivme".into(),
            source: Source::Mesh(load_truth("bivme-patient1-ED-RV_ENDO-closed.obj")),
            plan: Plan::Rv {
                lv: load_truth("bivme-patient1-ED-LV_ENDO-closed.obj"),
            },
        },
        Base {
            name: "rv-spasm".into(),
            source: Source::Mesh(spasm_rv_cavity()),
            plan: Plan::Rv {
                lv: load_truth("cardiomesh-spasm-LV_endo.obj"),
            },
        },
    ]
}

fn m(r: &Row, col: &str) -> f64 {
    r.metric(col)
        .unwrap_or_else(|| panic!("{}: no {col} ({:?})", r.shape, r.error))
}

#[test]
fn population_meets_the_acceptance_means() {
    let bases = bases();
    let members = generate(&bases, PER_BASE * bases.len(), SEED).unwrap();
    let subjects = members.iter().map(|m| m.subject.clone()).collect();
    let rows: Vec<Row> = Experiment::new(&Design::population(SEED), subjects, &Params::default())
        .unwrap()
        .collect();
    assert_eq!(rows.len(), 2 * members.len());
    let mut failures = Vec::new();
    for r in &rows {
        if let Some(e) = &r.error {
            failures.push(format!("{}: {e}", r.shape));
            continue;
        }
        let rv = r.shape.contains("-rv-");
        let aligned = r.setting("shift_mm") == Some(0.0);
        let mean = 0.5 * (m(r, "mesh_to_truth_mean") + m(r, "truth_to_mesh_mean"));
        eprintln!(
            "POPULATION {} {}: mean {:.3} (m->t {:.3} t->m {:.3}) max m->t {:.2} t->m {:.2} at \
             height {:.2}; contour->mesh mean {:.3} max {:.2}; volume {:.1} / {:.1} ml; folds {}; \
             {} SAX {} LAX; {:.2} s",
            r.shape,
            if aligned { "aligned" } else { "2 mm/2 deg" },
            mean,
            m(r, "mesh_to_truth_mean"),
            m(r, "truth_to_mesh_mean"),
            m(r, "mesh_to_truth_max"),
            m(r, "truth_to_mesh_max"),
            m(r, "worst_height"),
            m(r, "contour_to_mesh_mean"),
            m(r, "contour_to_mesh_max"),
            m(r, "volume_truth_ml"),
            m(r, "volume_mesh_ml"),
            m(r, "folded_edges"),
            r.sax,
            r.lax,
            r.seconds
        );
        if m(r, "closed_manifold_outward") != 1.0 {
            failures.push(format!("{}: not closed, manifold and outward", r.shape));
        }
        let fold_limit = if rv {
            RV_MAX_FOLDED_EDGES
        } else {
            MAX_FOLDED_EDGES
        };
        if m(r, "folded_edges") > fold_limit {
            failures.push(format!(
                "{}: {} folded edges > {fold_limit}",
                r.shape,
                m(r, "folded_edges")
            ));
        }
        if aligned {
            let target = if rv { RV_MEAN_MM } else { LV_MEAN_MM };
            for dir in ["mesh_to_truth_mean", "truth_to_mesh_mean"] {
                if m(r, dir) > target {
                    failures.push(format!("{}: {dir} {:.3} > {target}", r.shape, m(r, dir)));
                }
            }
            let base = r.shape.split_once('-').map_or("", |(_, b)| b);
            if MAX_CHECKED.contains(&base) && m(r, "hausdorff") > LV_MAX_MM {
                failures.push(format!(
                    "{}: Hausdorff {:.2} > {LV_MAX_MM}",
                    r.shape,
                    m(r, "hausdorff")
                ));
            }
        } else if m(r, "contour_to_mesh_mean") > MISALIGNED_C2M_MEAN_MM {
            failures.push(format!(
                "{} misaligned: contour-to-mesh mean {:.3} > {MISALIGNED_C2M_MEAN_MM}",
                r.shape,
                m(r, "contour_to_mesh_mean")
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
