//! Breath-hold slice alignment (`Params::align_slices`) on simulated misaligned acquisitions, with
//! the truth known, and on the real biv-me contours (docs/VALIDATION.md, session 9).
//! `cargo test --release -p heartmesh-core --test alignment -- --nocapture` prints the tables.

mod common;
use common::*;
use heartmesh_core::contours::align::align_slices;
use heartmesh_core::contours::{Contour, ContourKind, ContourSet};
use heartmesh_core::geometry::Vec3;
use heartmesh_core::mesh::quality::quality;
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::metrics::compare::compare;
use heartmesh_core::sim::planes::draw_motion;
use heartmesh_core::sim::planes::simulate_surfaces;
use heartmesh_core::sim::prng::SplitMix64;
use heartmesh_core::sim::{simulate, AcquisitionSpec, Misalignment, Plane};
use heartmesh_core::{Params, Reconstruction};
use nalgebra::Matrix3;

fn aligned() -> Params {
    Params {
        align_slices: true,
        ..Params::default()
    }
}

/// The defaults for one surface, alignment on or off.
fn surface(name: &str, align: bool) -> Params {
    Params {
        surface: Some(name.into()),
        align_slices: align,
        ..Params::default()
    }
}

/// Mesh-to-truth mean and Hausdorff (mm), clipped at `clip`.
/// Every plane shifted up to 2 mm and tilted up to 2 degrees.
const MISALIGNMENT: Misalignment = Misalignment {
    shift_mm: 2.0,
    tilt_deg: 2.0,
};

/// The CMR-like acquisition with every plane shifted up to 2 mm and tilted up to 2 degrees.
fn misaligned_spec(seed: u64, lax_count: usize) -> AcquisitionSpec {
    AcquisitionSpec {
        misalignment: Some(MISALIGNMENT),
        seed,
        lax_count,
        ..AcquisitionSpec::default()
    }
}

fn versus_truth(truth: &TriMesh, mesh: &TriMesh, clip: &Plane) -> (f64, f64) {
    let r = compare(truth, mesh, Some(clip)).unwrap_or_else(|e| panic!("compare: {e}"));
    (r.mesh_to_truth.mean, r.hausdorff)
}

/// Simulated misaligned LVs (one surface each): 2 mm / 2 degrees per plane, as the paper's
/// Figure 7 level 2. Alignment must lower mesh-to-truth in every case.
#[test]
fn misaligned_single_surfaces() {
    let cases = [
        ("cap-atlas-mean-ED-LV_ENDO-open.obj", 3),
        ("cardiomesh-spasm-LV_endo.obj", 2),
        ("cardiomesh-spasm-LV_epi.obj", 3),
        ("bivme-patient1-ED-LV_ENDO-closed.obj", 3),
    ];
    let mut worst_after: f64 = 0.0;
    let (mut sum_before, mut sum_after, mut n) = (0.0, 0.0, 0.0);
    for (file, lax) in cases {
        let truth = load_truth(file);
        for seed in 1..=4u64 {
            let spec = misaligned_spec(seed, lax);
            let acq = simulate(&truth, &spec).unwrap_or_else(|e| panic!("{file}: {e}"));
            let (m0, _) = reconstruct(&acq.contours, Params::default());
            let (m1, _) = reconstruct(&acq.contours, aligned());
            let (a0, h0) = versus_truth(&truth, &m0, &acq.clip);
            let (a1, h1) = versus_truth(&truth, &m1, &acq.clip);
            let (_, al) = align_slices(&acq.contours);
            eprintln!(
                "MISALIGNED {file} seed {seed}: m2t {a0:.3} / H {h0:.2} -> {a1:.3} / H {h1:.2}; folds {} -> {}; residual {:.3} -> {:.3} mm, {} rounds, largest shift {:.2} mm",
                quality(&m0).folded_edges,
                quality(&m1).folded_edges,
                al.residual_before_mm,
                al.residual_after_mm,
                al.rounds,
                al.max_shift_mm()
            );
            check_closed_manifold_outward(&m1).unwrap_or_else(|e| panic!("{file} {seed}: {e}"));
            assert!(a1 < a0, "{file} seed {seed}: {a0} -> {a1}");
            worst_after = worst_after.max(a1);
            sum_before += a0;
            sum_after += a1;
            n += 1.0;
        }
    }
    eprintln!(
        "MISALIGNED mean of means {:.3} -> {:.3} mm, worst after {worst_after:.3} mm",
        sum_before / n,
        sum_after / n
    );
    // Measured (session 9, in-plane shifts): 0.537 -> 0.291 mm on average, worst case 0.52 mm
    // after; session 12 (slices also along their normals): 0.275, worst 0.50. The tilts are not
    // recoverable by shifts, so the aligned acquisitions' 0.05-0.16 mm is out of reach.
    assert!(sum_after / n < 0.35, "{}", sum_after / n);
    assert!(worst_after < 0.6, "{worst_after}");
}

/// The long-axis views' shift errors, split along and across the long axis, on the 16 misaligned
/// LVs above with each image's shift known (`Motion::draw` draws as `sim` does: same generator
/// calls in the same order). Errors are up to the gauge (one common translation across the axis,
/// fitted). The views' slide along the axis is seen only through the wall's taper, so it is
/// recovered less well than across (docs/VALIDATION.md, session 10).
#[test]
fn views_along_the_long_axis() {
    let cases = [
        ("cap-atlas-mean-ED-LV_ENDO-open.obj", 3),
        ("cardiomesh-spasm-LV_endo.obj", 2),
        ("cardiomesh-spasm-LV_epi.obj", 3),
        ("bivme-patient1-ED-LV_ENDO-closed.obj", 3),
    ];
    let (mut before, mut after, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
    // Slices' through-plane errors (up to the stack's mean) before and after the alignment.
    let (mut through_before, mut through_after) = (Vec::new(), Vec::new());
    for (file, lax) in cases {
        let truth = load_truth(file);
        for seed in 1..=4u64 {
            let spec = misaligned_spec(seed, lax);
            let acq = simulate(&truth, &spec).unwrap_or_else(|e| panic!("{file}: {e}"));
            let mut rng = SplitMix64::new(seed);
            let mut correction = std::collections::HashMap::new();
            for (id, plane) in acq
                .sax_planes
                .iter()
                .enumerate()
                .map(|(k, p)| (format!("sax{:02}", k + 1), p))
                .chain(
                    acq.lax_planes
                        .iter()
                        .enumerate()
                        .map(|(k, p)| (format!("lax{:02}", k + 1), p)),
                )
            {
                let m = draw_motion(&mut rng, plane, MISALIGNMENT);
                let n = plane.normal;
                correction.insert(id, (m.shift - n * m.shift.dot(&n), n, m.shift.dot(&n)));
            }
            let (_, al) = align_slices(&acq.contours);
            let with = &al;
            let pairs: Vec<(f64, f64)> = with
                .groups
                .iter()
                .filter(|g| g.kind == ContourKind::Sax)
                .filter_map(|g| {
                    Some((
                        g.through_plane_mm,
                        correction.get(g.contour_ids.first()?)?.2,
                    ))
                })
                .collect();
            let n = pairs.len().max(1) as f64;
            let mf = pairs.iter().map(|p| p.0).sum::<f64>() / n;
            let mt = pairs.iter().map(|p| p.1).sum::<f64>() / n;
            for (f, t) in pairs {
                through_before.push(t - mt);
                through_after.push((f - mf) - (t - mt));
            }
            let a = acq.axis.direction;
            let rows: Vec<_> = al
                .groups
                .iter()
                .filter_map(|g| {
                    let (t, n, _) = correction.get(g.contour_ids.first()?)?;
                    Some((g, Vec3::from(g.shift_mm), *t, *n))
                })
                .collect();
            for (g, ..) in rows.iter().filter(|r| r.0.kind == ContourKind::Lax) {
                ratios.push(g.information.along_axis / g.information.across_axis);
            }
            let q = Matrix3::identity() - a * a.transpose();
            for (out, use_found) in [(&mut before, false), (&mut after, true)] {
                let found = |f: &Vec3| if use_found { *f } else { Vec3::zeros() };
                let mut m = a * a.transpose();
                let mut b = Vec3::zeros();
                for (_, f, t, n) in &rows {
                    let p = Matrix3::identity() - n * n.transpose();
                    m += q * p * q;
                    b += q * p * (found(f) - t);
                }
                let c = m.try_inverse().unwrap_or_else(|| panic!("gauge")) * b;
                for (_, f, t, n) in rows.iter().filter(|r| r.0.kind == ContourKind::Lax) {
                    let e = found(f) - t - (Matrix3::identity() - n * n.transpose()) * c;
                    let along = (a - n * a.dot(n)).normalize();
                    out.push((e.dot(&along), e.dot(&n.cross(&along))));
                }
            }
        }
    }
    let rms = |v: &[(f64, f64)], k: usize| {
        let s: f64 = v
            .iter()
            .map(|x| if k == 0 { x.0 } else { x.1 }.powi(2))
            .sum();
        (s / v.len() as f64).sqrt()
    };
    ratios.sort_by(f64::total_cmp);
    let (a0, a1, c0, c1) = (
        rms(&before, 0),
        rms(&after, 0),
        rms(&before, 1),
        rms(&after, 1),
    );
    eprintln!(
        "VIEWS {} views: along the axis {a0:.3} -> {a1:.3} mm, across {c0:.3} -> {c1:.3} mm (RMS); information along / across median {:.3}, range {:.3}-{:.3}",
        after.len(),
        ratios[ratios.len() / 2],
        ratios[0],
        ratios[ratios.len() - 1]
    );
    // Measured (session 10, in-plane shifts): 44 views, along 0.670 -> 0.300, across 0.644 ->
    // 0.077 mm; session 12 (slices also along their normals) 0.291 and 0.070; the information
    // ratio 0.10-0.29 (median 0.18).
    let rms1 = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt();
    let (t0, t1) = (rms1(&through_before), rms1(&through_after));
    eprintln!(
        "THROUGH {} slices: through-plane error (up to the stack mean) {t0:.3} -> {t1:.3} mm RMS",
        through_after.len()
    );
    // Measured (session 11): 132 slices, 0.622 -> 0.455 mm (0.343 without the prior).
    assert_eq!(through_after.len(), 132);
    assert!(t1 < 0.85 * t0, "through-plane {t0} -> {t1}");
    assert_eq!(after.len(), 44);
    assert!(a1 < 0.6 * a0, "along {a0} -> {a1}");
    assert!(c1 < 0.2 * c0, "across {c0} -> {c1}");
    assert!(ratios[ratios.len() - 1] < 0.5, "{ratios:?}");
}

/// Clean acquisitions: alignment finds nothing to correct and the meshes stay as accurate.
#[test]
fn aligned_acquisitions_stay_put() {
    for file in [
        "cap-atlas-mean-ED-LV_ENDO-open.obj",
        "cardiomesh-spasm-LV_epi.obj",
    ] {
        let truth = load_truth(file);
        let acq = simulate(&truth, &AcquisitionSpec::default()).unwrap();
        let (_, al) = align_slices(&acq.contours);
        let (m0, _) = reconstruct(&acq.contours, Params::default());
        let (m1, _) = reconstruct(&acq.contours, aligned());
        let (a0, _) = versus_truth(&truth, &m0, &acq.clip);
        let (a1, _) = versus_truth(&truth, &m1, &acq.clip);
        eprintln!(
            "ALIGNED {file}: largest shift {:.3} mm, residual {:.3} -> {:.3} mm; m2t {a0:.3} -> {a1:.3}",
            al.max_shift_mm(),
            al.residual_before_mm,
            al.residual_after_mm
        );
        assert!(al.max_shift_mm() < 0.2, "{file}: {}", al.max_shift_mm());
        assert!((a1 - a0).abs() < 0.02, "{file}: {a0} -> {a1}");
    }
}

/// LV and RV sliced by the same misaligned images (`simulate_surfaces`: one acquisition planned
/// on the LV, each image's motion shared by both): the shifts are estimated from both together,
/// and each surface's mesh moves closer to its truth, clipped at that surface's own most basal
/// slice. The spasm RV cavity has closed sections only well below the LV's base: it is drawn
/// there, and the LV keeps its basal slices (until session 29 the stack stopped at the RV's top,
/// 2 SAX slices for the LV, too few for alignment: it made seeds 1 and 6 worse).
#[test]
fn misaligned_biventricular() {
    let subjects = [
        (
            "spasm",
            load_truth("cardiomesh-spasm-LV_endo.obj"),
            spasm_rv_cavity(),
        ),
        (
            "bivme",
            load_truth("bivme-patient1-ED-LV_ENDO-closed.obj"),
            load_truth("bivme-patient1-ED-RV_ENDO-closed.obj"),
        ),
    ];
    for (name, lv, rv) in &subjects {
        for seed in 1..=3u64 {
            let acq = simulate_surfaces(
                &[("LV_ENDO", lv), ("RV_ENDO", rv)],
                &misaligned_spec(seed, 3),
            )
            .unwrap_or_else(|e| panic!("{name} {seed}: {e}"));
            let set = &acq.contours;
            let sax_lv = set
                .contours
                .iter()
                .filter(|c| c.id.starts_with("sax") && c.id.ends_with("LV_ENDO"))
                .count();
            assert!(sax_lv >= 6, "{name} seed {seed}: {sax_lv} LV slices");
            let (_, al) = align_slices(set);
            for (k, (surf, truth)) in [("LV_ENDO", lv), ("RV_ENDO", rv)].into_iter().enumerate() {
                let clip = acq.surface_clips[k];
                let (m0, _) = reconstruct(set, surface(surf, false));
                let (m1, _) = reconstruct(set, surface(surf, true));
                let (a0, h0) = versus_truth(truth, &m0, &clip);
                let (a1, h1) = versus_truth(truth, &m1, &clip);
                // The prototype's way: the surface's own contours aligned alone.
                let mut alone = set.clone();
                alone
                    .contours
                    .retain(|c| c.surface.as_deref() == Some(surf));
                let (m2, _) = reconstruct(&alone, surface(surf, true));
                let (a2, _) = versus_truth(truth, &m2, &clip);
                eprintln!(
                    "BIV {name} seed {seed} {surf}: m2t {a0:.3} / H {h0:.2} -> {a1:.3} / H {h1:.2} (surface aligned alone {a2:.3}); folds {} -> {}; residual {:.3} -> {:.3}, {} rounds",
                    quality(&m0).folded_edges,
                    quality(&m1).folded_edges,
                    al.residual_before_mm,
                    al.residual_after_mm,
                    al.rounds
                );
                check_closed_manifold_outward(&m1)
                    .unwrap_or_else(|e| panic!("{name} {seed} {surf}: {e}"));
                assert!(a1 < a0, "{name} seed {seed} {surf}: {a0} -> {a1}");
                // Measured (session 29): LV 0.196-0.458, RV 0.333-0.646 mm after.
                let bound = if surf == "LV_ENDO" { 0.55 } else { 0.7 };
                assert!(a1 < bound, "{name} seed {seed} {surf}: {a1}");
            }
        }
    }
}

/// The real biv-me contours, every surface: aligned jointly over the file.
#[test]
fn real_cases() {
    let (mut lv_folds, mut rv_folds) = ((0, 0), (0, 0));
    for file in [
        "bivme-example-patient1/patient1-ED.csv",
        "bivme-example-patient1/patient1-ES.csv",
        "bivme-test-patient2/patient2-ED.csv",
        "bivme-test-patient2/patient2-ES.csv",
    ] {
        let set = load_contours(file);
        let (shifted, al) = align_slices(&set);
        eprintln!(
            "REAL {file}: residual {:.3} -> {:.3} mm, {} rounds, shifts {:?}",
            al.residual_before_mm,
            al.residual_after_mm,
            al.rounds,
            al.groups
                .iter()
                .map(|g| format!(
                    "{} {:.2}",
                    g.label.split(',').next().unwrap_or(""),
                    norm(&g.shift_mm)
                ))
                .collect::<Vec<_>>()
        );
        for surf in set.surfaces() {
            let (m0, _) = reconstruct(&set, surface(&surf, false));
            let (m1, _) = reconstruct(&set, surface(&surf, true));
            let mine = |s: &ContourSet| -> Vec<Contour> {
                s.contours
                    .iter()
                    .filter(|c| c.surface.as_deref() == Some(&surf))
                    .cloned()
                    .collect()
            };
            let c0 = mean(&contour_to_mesh_of(&mine(&set), &m0));
            let c1 = mean(&contour_to_mesh_of(&mine(&shifted), &m1));
            let c1g = mean(&contour_to_mesh_of(&mine(&set), &m1));
            eprintln!(
                "REAL {file} {surf}: c2m {c0:.3} -> {c1:.3} (to as given {c1g:.3}); folds {} -> {}; volume {:.1} -> {:.1} ml",
                quality(&m0).folded_edges,
                quality(&m1).folded_edges,
                m0.volume_ml(),
                m1.volume_ml()
            );
            check_closed_manifold_outward(&m1).unwrap_or_else(|e| panic!("{file} {surf}: {e}"));
            let (f0, f1) = (quality(&m0).folded_edges, quality(&m1).folded_edges);
            if surf.starts_with("LV") {
                // The shifted contours agree better: the mesh fits them at least as closely.
                assert!(c1 <= c0, "{file} {surf}: {c0} -> {c1}");
                assert!(f1 <= f0 + 4, "{file} {surf}: folds {f0} -> {f1}");
                lv_folds.0 += f0;
                lv_folds.1 += f1;
            } else {
                // Measured: every RV surface's c2m falls too (0.224-0.481 -> 0.095-0.394 mm);
                // a fold count moves by a few with any change of the input (0 -> 2, 2 -> 3).
                assert!(c1 <= c0 + 0.05, "{file} {surf}: {c0} -> {c1}");
                assert!(f1 <= 2 * f0 + 6, "{file} {surf}: folds {f0} -> {f1}");
                rv_folds.0 += f0;
                rv_folds.1 += f1;
            }
        }
    }
    // Measured: LV 4 -> 1, RV 5 -> 9 folded edges over the eight LV and six RV meshes (a fold
    // count moves by a few with any change of the input); bounds: twice the unaligned LV count,
    // twice the measured RV count.
    eprintln!("REAL folds LV {lv_folds:?}, RV {rv_folds:?}");
    assert!(lv_folds.1 <= 8, "{lv_folds:?}");
    assert!(rv_folds.1 <= 18, "{rv_folds:?}");
}

fn norm(v: &[f64; 3]) -> f64 {
    v.iter().map(|c| c * c).sum::<f64>().sqrt()
}

/// A contour left out of an aligned run is measured where its image moved, not where the file
/// drew it: patient 1's short-axis slice s04 (every surface's curve in it) moved 4 mm in its
/// plane as a breath-hold would, LV_EPI aligned with its LV epicardial ring left out. The
/// alignment finds the slice's shift from its other curves (the LV endocardial ring anchors it)
/// and the ring left out moves with them, so its distance to the mesh is about the one of the file
/// as drawn (a held-out figure), where measured at its drawn place it would be off by most of
/// the 4 mm.
#[test]
fn a_contour_left_out_of_an_aligned_run_moves_with_its_image() {
    const VIEW: &str = "s04_";
    const LEFT: &str = "s04_SAX_LV_EPICARDIAL";
    let file = load_contours("bivme-example-patient1/patient1-ED.csv");
    let in_view = |c: &Contour| c.id.starts_with(VIEW);
    let view_points: Vec<Vec3> = file
        .contours
        .iter()
        .filter(|c| in_view(c))
        .flat_map(|c| c.points().copied())
        .collect();
    let plane = heartmesh_core::contours::plane::fit_plane(view_points.iter()).unwrap();
    // 4 mm along a direction in the view's plane.
    let along = plane.normal.cross(&Vec3::new(0.3, 0.5, 0.8)).normalize() * 4.0;
    let mut moved = file.clone();
    for c in moved.contours.iter_mut().filter(|c| in_view(c)) {
        for p in c.pieces.iter_mut().flat_map(|p| p.points.iter_mut()) {
            *p += along;
        }
    }
    let held_out = |set: &ContourSet| {
        let mut rec = Reconstruction::new(
            set,
            Params {
                leave_out: vec![LEFT.into()],
                ..surface("LV_EPI", true)
            },
        )
        .unwrap();
        rec.run().unwrap();
        // The per-point distances (the app's hover) are those the figure summarises.
        let points = rec.set_aside_point_distances();
        assert_eq!(points.len(), rec.set_aside_contours()[0].point_count());
        let mean = points.iter().sum::<f64>() / points.len() as f64;
        assert!((mean - rec.set_aside_stats()[0].mean).abs() < 1e-12);
        let drawn = set.contours.iter().find(|c| c.id == LEFT).unwrap();
        let at_drawn = heartmesh_core::sim::leave_one_out::measure(drawn, rec.mesh()).mean;
        (rec.set_aside_stats()[0].mean, at_drawn)
    };
    let (as_drawn, _) = held_out(&file);
    let (moved_with_view, at_moved_place) = held_out(&moved);
    println!(
        "{LEFT} held out, aligned: file as drawn {as_drawn:.3} mm; view moved 4 mm: {moved_with_view:.3} mm \
         (at its drawn place {at_moved_place:.3} mm)"
    );
    assert!(
        (moved_with_view - as_drawn).abs() < 0.5,
        "{moved_with_view} vs {as_drawn}"
    );
    assert!(
        at_moved_place > moved_with_view + 1.5,
        "{at_moved_place} vs {moved_with_view}"
    );
}
