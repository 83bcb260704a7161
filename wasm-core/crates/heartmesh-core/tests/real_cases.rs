//! Real contours (issue 2 acceptance): the SurFCo example and the biv-me patients, every surface,
//! end-diastole and end-systole, reconstruct at the defaults to closed, manifold, outward meshes
//! whose contour-to-mesh mean distance is at most 1 mm. Each case prints its numbers.

mod common;

use common::*;
use heartmesh_core::contours::{biv_epi, ContourKind};
use heartmesh_core::mesh::quality::quality;
use heartmesh_core::metrics::compare::{clip_plane_from_contours, compare};
use heartmesh_core::pipeline::Reconstruction;
use heartmesh_core::Params;

const MEAN_MM: f64 = 1.0;
/// Creased edges (dihedral > 90 degrees, `mesh::quality`) a surface may end with. The goal is none;
/// where short- and long-axis curves disagree by a few mm some remain after the conflict
/// softening of the final steps (session 4: at most 2 per surface, 8 on 5 of 15 surfaces; 8 and
/// 26 on 9 before). One above the measured worst: fold counts move by one or two with any change
/// of the arithmetic (the solver's precision), a regression moves them by more.
const MAX_FOLDED_EDGES: usize = 3;
/// Surfaces held to another fold count, with the reason. Patient 1 ES RV epicardium: 4 since end
/// caps became the default (session 12; 3 with `--end-caps off`, 2 with session 10's lid, which
/// had a worse basal corner: docs/VALIDATION.md, "Session 11: the cap-to-wall corner"); 6 since
/// its base lid holds 13 points instead of 3 (session 54). The folds are not at the lid: all lie
/// at the apical ring (s06, 18 points), 45 mm below it, where the long-axis curves disagree
/// with it, and their count there moves with any change elsewhere (2-4 over attractor counts
/// 150-400 before the change, 2-6 after).
const FOLD_EXCEPTIONS: &[(&str, usize)] = &[("patient1-ES.csv RV_EPI", 6)];

/// Reconstructs every surface of one file; returns failures as messages (all cases run).
fn file_case(sub: &str) -> Vec<String> {
    let set = load_contours(sub);
    let mut surfaces: Vec<Option<String>> = set.surfaces().into_iter().map(Some).collect();
    // The biventricular epicardium, where the file has both epicardia, is held to the same bar.
    if biv_epi::available(&set) {
        surfaces.push(Some(biv_epi::BIV_EPI.to_string()));
    }
    if surfaces.is_empty() {
        surfaces.push(None);
    }
    let mut failures = Vec::new();
    for surface in surfaces {
        let label = format!("{sub} {}", surface.as_deref().unwrap_or("(single surface)"));
        let params = Params {
            surface: surface.clone(),
            ..Params::default()
        };
        let started = std::time::Instant::now();
        let mut rec = match Reconstruction::new(&set, params) {
            Ok(r) => r,
            Err(e) => {
                failures.push(format!("{label}: new: {e}"));
                continue;
            }
        };
        if let Err(e) = rec.run() {
            failures.push(format!("{label}: run: {e}"));
            continue;
        }
        let seconds = started.elapsed().as_secs_f64();
        let q = quality(rec.mesh());
        let d = rec.contour_distances();
        // Independent check of the pipeline's own measure.
        let ours = contour_to_mesh_of(rec.contours(), rec.mesh());
        let worst = d
            .per_contour
            .iter()
            .max_by(|a, b| a.stats.mean.total_cmp(&b.stats.mean));
        let n_lax = rec
            .kinds()
            .iter()
            .filter(|k| **k == ContourKind::Lax)
            .count();
        eprintln!(
            "REAL {label}: {} contours ({} LAX); contour->mesh mean {:.3} median {:.3} p95 {:.3} \
             max {:.3} mm (independent mean {:.3}); worst contour {} mean {:.3} max {:.3}; \
             {} vertices, volume {:.2} ml; folds {} max dihedral {:.0}; {:.2} s",
            rec.contours().len(),
            n_lax,
            d.overall.mean,
            d.overall.median,
            d.overall.p95,
            d.overall.max,
            mean(&ours),
            worst.map_or("-", |w| w.id.as_str()),
            worst.map_or(0.0, |w| w.stats.mean),
            worst.map_or(0.0, |w| w.stats.max),
            rec.mesh().positions.len(),
            rec.mesh().volume_ml(),
            q.folded_edges,
            q.max_dihedral_deg,
            seconds
        );
        // Neither stray nor speck on a real file (session 14): every contour is used.
        if !rec.set_aside().is_empty() {
            failures.push(format!("{label}: left out {:?}", rec.set_aside()));
        }
        if let Err(e) = check_closed_manifold_outward(rec.mesh()) {
            failures.push(format!("{label}: mesh is not closed/manifold/outward: {e}"));
        }
        // A volume mesher or a slicer takes the surface only if it does not pass through itself.
        if q.self_intersections > 0 {
            failures.push(format!(
                "{label}: {} pairs of triangles pass through each other",
                q.self_intersections
            ));
        }
        let max_folds = FOLD_EXCEPTIONS
            .iter()
            .find(|(l, _)| label.ends_with(l))
            .map_or(MAX_FOLDED_EDGES, |(_, n)| *n);
        if q.folded_edges > max_folds {
            failures.push(format!(
                "{label}: {} folded edges (max dihedral {:.0} deg) > {max_folds}",
                q.folded_edges, q.max_dihedral_deg
            ));
        }
        if (d.overall.mean - mean(&ours)).abs() > 1e-6 {
            failures.push(format!(
                "{label}: pipeline's contour distance {:.6} disagrees with the independent {:.6}",
                d.overall.mean,
                mean(&ours)
            ));
        }
        if d.overall.mean.is_nan() || d.overall.mean > MEAN_MM {
            failures.push(format!(
                "{label}: contour-to-mesh mean {:.3} mm > {MEAN_MM} (max {:.3}, worst contour {})",
                d.overall.mean,
                d.overall.max,
                worst.map_or("-", |w| w.id.as_str())
            ));
        }
    }
    failures
}

/// Patient 1's biventricular epicardium against biv-me's own model fitted to the same contours
/// (`bivme-patient1-ED-EPI-closed.obj`: a fit, not an independent truth, so the bounds are loose:
/// the two methods smooth differently between the slices), both clipped at the basal slice.
#[test]
fn bivme_patient1_biventricular_epicardium_agrees_with_bivme_fit() {
    let set = load_contours("bivme-example-patient1/patient1-ED.csv");
    let params = Params {
        surface: Some(biv_epi::BIV_EPI.into()),
        ..Params::default()
    };
    let (mesh, _) = reconstruct(&set, params.clone());
    let clip = clip_plane_from_contours(&set, params).unwrap();
    let fit = load_truth("bivme-patient1-ED-EPI-closed.obj");
    let r = compare(&fit, &mesh, Some(&clip)).unwrap();
    let mean = (r.mesh_to_truth.mean + r.truth_to_mesh.mean) / 2.0;
    let volume = r.volume_mesh_ml / r.volume_truth_ml - 1.0;
    eprintln!(
        "BIV_EPI p1 ED vs biv-me fit: mean {mean:.3} mm, Hausdorff {:.2} mm, volume {:.1} vs {:.1} ml",
        r.hausdorff, r.volume_mesh_ml, r.volume_truth_ml
    );
    // Measured (session 20): mean 0.93, Hausdorff 6.6, volume -0.5 %.
    assert!(mean < 1.2, "mean {mean}");
    assert!(r.hausdorff < 8.0, "Hausdorff {}", r.hausdorff);
    assert!(volume.abs() < 0.03, "volume {volume}");
    // It holds both ventricles: more than the LV and RV epicardia's parts alone.
    for part in ["LV_EPI", "RV_EPI"] {
        let (m, _) = reconstruct(
            &set,
            Params {
                surface: Some(part.into()),
                ..Params::default()
            },
        );
        assert!(mesh.volume_ml() > m.volume_ml() * 1.2, "{part}");
    }
}

fn assert_none(failures: Vec<String>) {
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn surfco_example() {
    assert_none(file_case("surfco-example.csv"));
}

#[test]
fn bivme_patient1_ed() {
    assert_none(file_case("bivme-example-patient1/patient1-ED.csv"));
}

#[test]
fn bivme_patient1_es() {
    assert_none(file_case("bivme-example-patient1/patient1-ES.csv"));
}

#[test]
fn bivme_patient2_ed() {
    assert_none(file_case("bivme-test-patient2/patient2-ED.csv"));
}

#[test]
fn bivme_patient2_es() {
    assert_none(file_case("bivme-test-patient2/patient2-ES.csv"));
}

/// A small target reduction grows the mesh at every remesh (subdivision x4, keep 1 - r): the
/// remesh caps it at `MAX_REMESH_TRIANGLES` instead of running out of memory.
#[test]
fn low_target_reduction_is_capped() {
    use heartmesh_core::pipeline::MAX_REMESH_TRIANGLES;
    let set = load_contours("surfco-example.csv");
    let params = Params {
        target_reduction: 0.0,
        iterations: 60,
        remesh_every: 10,
        smoothing_iterations: 10,
        ..Params::default()
    };
    let (mesh, _) = reconstruct(&set, params);
    let t = mesh.triangles.len();
    println!("target reduction 0: {t} triangles after the last remesh");
    // Uncapped, 4^k growth over the remeshes would pass a million triangles.
    assert!(t <= MAX_REMESH_TRIANGLES, "{t} triangles");
    assert!(
        t > MAX_REMESH_TRIANGLES / 2,
        "{t} triangles: the cap should have been reached"
    );
    check_closed_manifold_outward(&mesh).unwrap();
}

/// The other way: a large target reduction shrinks the mesh at every remesh (0.95 keeps 0.2x).
/// Unchecked, patient 1 ED's LV ended as a 4-triangle tetrahedron 7.2 mm from its contours that
/// read "closed"; the remesh holds it at the initial tube's triangles, which follow the contours,
/// and the note says so.
#[test]
fn high_target_reduction_keeps_the_tubes_triangles() {
    let set = load_contours("bivme-example-patient1/patient1-ED.csv");
    let at = |target_reduction: f64| {
        let params = Params {
            surface: Some("LV_ENDO".into()),
            target_reduction,
            ..Params::default()
        };
        let mut rec = Reconstruction::new(&set, params).unwrap();
        rec.step().unwrap();
        let tube = rec.mesh().triangles.len();
        let note = rec.growth_note();
        rec.run().unwrap();
        let mean = rec.contour_distances().overall.mean;
        (
            tube,
            rec.mesh().triangles.len(),
            note,
            mean,
            rec.mesh().clone(),
        )
    };
    for r in [0.8, 0.95] {
        let (tube, end, note, mean, mesh) = at(r);
        println!("target reduction {r}: {tube} -> {end} triangles, mean {mean:.3} mm");
        // Decimation stops within a few collapses of its target.
        assert!(end + 8 >= tube && end <= tube + 8, "{r}: {tube} -> {end}");
        assert!(mean < 1.0, "{r}: contour-to-mesh mean {mean} mm");
        check_closed_manifold_outward(&mesh).unwrap();
        let note = note.unwrap_or_default();
        assert!(note.contains("held at the initial tube's"), "{r}: {note}");
    }
    // The defaults grow the mesh and say nothing.
    let (tube, end, note, _, _) = at(0.72);
    assert!(end > 2 * tube, "{tube} -> {end}");
    assert_eq!(note, None);
}

/// The growth note (session 15): from the initial tube's size, a long run at the paper's remesh
/// settings is predicted to reach the remesh cap, and the defaults are not.
#[test]
fn a_long_run_is_told_it_will_reach_the_cap() {
    let set = load_contours("surfco-example.csv");
    let note_after_step_0 = |params: Params| {
        let mut rec = Reconstruction::new(&set, params).unwrap();
        assert_eq!(rec.growth_note(), None, "before the tube exists");
        rec.step().unwrap();
        let triangles = rec.mesh().triangles.len();
        (rec.growth_note(), triangles)
    };
    let (note, triangles) = note_after_step_0(Params::default());
    assert_eq!(note, None);
    let long = Params {
        iterations: 1500,
        ..Params::default()
    };
    let (note, _) = note_after_step_0(long);
    let note = note.unwrap();
    // 1.12x per remesh from the tube's triangles to 200 000, every 20 iterations.
    let k = (200_000.0 / triangles as f64).ln() / 1.12f64.ln();
    let expected = 20 * k.ceil() as usize;
    println!("{triangles} triangles after step 0: {note}");
    assert!(
        note.contains(&format!("by about iteration {expected} of 1500")),
        "{note}"
    );
    assert!(
        note.starts_with("each remesh keeps 1.12x the triangles"),
        "{note}"
    );
}
