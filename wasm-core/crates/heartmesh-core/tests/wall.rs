//! The LV myocardium wall (`mesh::wall`, `heartmesh myocardium`) against known walls: the endo-
//! and epicardium of a reference shape sliced on the same planes (one acquisition, as both are
//! drawn on the same images), each surface reconstructed at the defaults, the wall built between
//! them, and compared with the wall built the same way between the truth surfaces at the same
//! base plane.
//!
//! Run with `--nocapture` to see the `WALL` lines (the figures of docs/VALIDATION.md).

mod common;

use common::*;
use heartmesh_core::contours::ContourSet;
use heartmesh_core::mesh::topology::validity;
use heartmesh_core::mesh::wall::{build_biventricular, build_wall, Wall, BASE, BIV_REGION_NAMES};
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::metrics::compare::{common_basal_plane, common_basal_plane_all, compare};
use heartmesh_core::sim::planes::simulate_surfaces;
use heartmesh_core::sim::slice::Plane;
use heartmesh_core::sim::{AcquisitionSpec, Misalignment};
use heartmesh_core::{Params, Reconstruction};

/// Mean surface distance (both ways) a wall may have to its truth: the LV surfaces' own target
/// (issue 2: mean <= 0.2 mm), since the wall is made of them.
const MEAN_MM: f64 = 0.2;
/// Mean distance a wall from a misaligned acquisition may have to its truth: issue 2 holds
/// misaligned reconstructions to a contour-to-mesh mean of 1 mm.
const MISALIGNED_MEAN_MM: f64 = 1.0;
/// Wall volume error allowed, relative: a thin shell (8-10 mm) turns each surface's 0.1-0.2 mm
/// mean error into a few per cent of its volume.
const VOLUME_REL: f64 = 0.05;

/// Slices `endo` and `epi` on one acquisition planned on the epicardium ([`simulate_surfaces`]:
/// both drawn on the same images, its most basal slice a margin below the lower of the rims).
fn acquire(endo: &TriMesh, epi: &TriMesh, spec: &AcquisitionSpec) -> ContourSet {
    simulate_surfaces(&[("LV_EPI", epi), ("LV_ENDO", endo)], spec)
        .unwrap()
        .contours
}

/// Every plane shifted up to 2 mm and tilted up to 2 degrees (issue 2's misaligned case),
/// one breath-hold per image for all the surfaces on it.
fn misaligned(seed: u64) -> AcquisitionSpec {
    misaligned_by(seed, 2.0)
}

/// Every plane shifted up to `mm` and tilted up to as many degrees.
fn misaligned_by(seed: u64, mm: f64) -> AcquisitionSpec {
    AcquisitionSpec {
        misalignment: Some(Misalignment {
            shift_mm: mm,
            tilt_deg: mm,
        }),
        seed,
        ..AcquisitionSpec::default()
    }
}

fn reconstruct_surface(set: &ContourSet, surface: &str) -> Reconstruction {
    reconstruct_with(set, surface, false)
}

/// One surface at the defaults, with or without breath-hold alignment.
fn reconstruct_with(set: &ContourSet, surface: &str, align_slices: bool) -> Reconstruction {
    let params = Params {
        surface: Some(surface.to_string()),
        align_slices,
        ..Params::default()
    };
    let mut rec = Reconstruction::new(set, params).unwrap();
    rec.run().unwrap();
    rec
}

fn wall_case(name: &str, endo_file: &str, epi_file: &str) -> Wall {
    let (endo, epi) = (load_truth(endo_file), load_truth(epi_file));
    let set = acquire(&endo, &epi, &AcquisitionSpec::default());
    let endo_rec = reconstruct_surface(&set, "LV_ENDO");
    let epi_rec = reconstruct_surface(&set, "LV_EPI");
    let base = common_basal_plane(&endo_rec, &epi_rec).unwrap();
    let wall = build_wall(endo_rec.mesh(), epi_rec.mesh(), &base, Some(1.0)).unwrap();
    let truth = build_wall(&endo, &epi, &base, None).unwrap();
    against_truth(name, &wall, &truth, MEAN_MM);
    wall
}

/// Checks a reconstructed wall against the truth's wall at the same base: closed, no crossings,
/// mean distance both ways within `mean_mm`, wall and cavity volumes within [`VOLUME_REL`].
fn against_truth(name: &str, wall: &Wall, truth: &Wall, mean_mm: f64) {
    let v = validity(&wall.mesh);
    assert!(v.is_closed_manifold(), "{name}: {}", v.describe());
    assert_eq!(wall.self_intersections, 0, "{name}: {:?}", wall.crossings);
    let r = compare(&truth.mesh, &wall.mesh, None).unwrap();
    let vol_err = (wall.volume_ml - truth.volume_ml) / truth.volume_ml;
    let mean_t = |w: &Wall| w.thickness.iter().sum::<f64>() / w.thickness.len() as f64;
    eprintln!(
        "WALL {name}: mean mesh->truth {:.3} truth->mesh {:.3} mm, hausdorff {:.2} mm; wall {:.2} \
         ml (truth {:.2}, {:+.1}%), cavities {:.2?} ml (truth {:.2?}); thickness mean {:.2} mm \
         (truth {:.2}); {} triangles ({} base)",
        r.mesh_to_truth.mean,
        r.truth_to_mesh.mean,
        r.hausdorff,
        wall.volume_ml,
        truth.volume_ml,
        100.0 * vol_err,
        wall.cavities_ml,
        truth.cavities_ml,
        mean_t(wall),
        mean_t(truth),
        wall.mesh.triangles.len(),
        wall.triangles_per_region.last().unwrap()
    );
    assert!(
        r.mesh_to_truth.mean <= mean_mm && r.truth_to_mesh.mean <= mean_mm,
        "{name}: mean {:.3} / {:.3} mm > {mean_mm}",
        r.mesh_to_truth.mean,
        r.truth_to_mesh.mean
    );
    assert!(
        vol_err.abs() <= VOLUME_REL,
        "{name}: wall volume {:.2} ml vs truth {:.2} ml",
        wall.volume_ml,
        truth.volume_ml
    );
    for (got, want) in wall.cavities_ml.iter().zip(&truth.cavities_ml) {
        assert!(
            (got - want).abs() / want < VOLUME_REL,
            "{name}: cavity {got} vs {want}"
        );
    }
}

#[test]
fn cap_atlas_wall_matches_the_truth_wall() {
    wall_case(
        "CAP atlas",
        "cap-atlas-mean-ED-LV_ENDO-open.obj",
        "cap-atlas-mean-ED-LV_EPI-open.obj",
    );
}

#[test]
fn spasm_wall_matches_the_truth_wall() {
    wall_case(
        "spasm",
        "cardiomesh-spasm-LV_endo.obj",
        "cardiomesh-spasm-LV_epi.obj",
    );
}

/// The real cases: every biv-me phase gives a closed wall without crossings, with a plausible
/// mass and thickness, its base ring flat in the base plane.
#[test]
fn real_cases_give_closed_walls() {
    for file in [
        "bivme-example-patient1/patient1-ED.csv",
        "bivme-example-patient1/patient1-ES.csv",
        "bivme-test-patient2/patient2-ED.csv",
        "bivme-test-patient2/patient2-ES.csv",
    ] {
        let set = load_contours(file);
        let endo = reconstruct_surface(&set, "LV_ENDO");
        let epi = reconstruct_surface(&set, "LV_EPI");
        let base = common_basal_plane(&endo, &epi).unwrap();
        let wall = build_wall(endo.mesh(), epi.mesh(), &base, Some(1.0)).unwrap();
        let v = validity(&wall.mesh);
        assert!(v.is_closed_manifold(), "{file}: {}", v.describe());
        assert_eq!(wall.self_intersections, 0, "{file}");
        let mass = 1.05 * wall.volume_ml;
        let mean_t = wall.thickness.iter().sum::<f64>() / wall.thickness.len() as f64;
        eprintln!(
            "WALL {file}: mass below the base {mass:.1} g, cavity {:.1} ml, thickness mean \
             {mean_t:.2} mm",
            wall.cavity_ml
        );
        // Adult LV mass is 60-250 g, wall thickness 4-15 mm; the cut removes the base.
        assert!((40.0..250.0).contains(&mass), "{file}: mass {mass}");
        assert!((3.0..16.0).contains(&mean_t), "{file}: thickness {mean_t}");
        // The cavity below the base is less than the closed cavity, which runs on to its lid.
        assert!(wall.cavity_ml > 0.0 && wall.cavity_ml < endo.mesh().volume_ml());
        for (t, &r) in wall.regions.iter().enumerate() {
            if r == BASE {
                for p in wall.mesh.corners(t) {
                    assert!(base.signed_distance(&p).abs() < 1e-6, "{file}");
                }
            }
        }
    }
}

/// Patient 1 at ED with its contours listed in another order (one a shuffle gave): the surfaces
/// differ from the file order's in their last bits, and the reconstructions part (session 41);
/// with this order the RV endocardium's triangles came out through an inward crease of the
/// epicardium near the RV apex, 52-58 mm below the base, every corner at the 1 mm depth under
/// its own nearest face, and the wall kept 4 crossing pairs until the crossings themselves were
/// cleared (`inset::clear_crossings`).
#[test]
fn a_biventricular_wall_clears_crossings_its_vertex_pushes_leave() {
    let file = "bivme-example-patient1/patient1-ED.csv";
    let set = load_contours(file);
    let order = [
        "s09_LAX_LV_EPICARDIAL",
        "s02_SAX_LV_ENDOCARDIAL",
        "s11_LAX_RV_EPICARDIAL",
        "s08_LAX_RV_FREEWALL",
        "s07_LAX_RV_SEPTUM",
        "s05_SAX_RV_FREEWALL",
        "s08_LAX_RV_SEPTUM",
        "s03_SAX_LV_ENDOCARDIAL",
        "s07_LAX_LV_EPICARDIAL",
        "s08_LAX_LV_ENDOCARDIAL",
        "s08_LAX_LV_EPICARDIAL",
        "s09_LAX_LV_ENDOCARDIAL",
        "s03_SAX_RV_EPICARDIAL",
        "s08_LAX_RV_EPICARDIAL",
        "s03_SAX_RV_SEPTUM",
        "s06_SAX_RV_SEPTUM",
        "s02_SAX_RV_FREEWALL",
        "s02_SAX_RV_EPICARDIAL",
        "s03_SAX_LV_EPICARDIAL",
        "s06_SAX_LV_ENDOCARDIAL",
        "s04_SAX_LV_ENDOCARDIAL",
        "s05_SAX_RV_SEPTUM",
        "s04_SAX_RV_EPICARDIAL",
        "s07_LAX_RV_EPICARDIAL",
        "s07_LAX_LV_ENDOCARDIAL",
        "s04_SAX_RV_SEPTUM",
        "s06_SAX_RV_FREEWALL",
        "s07_LAX_RV_FREEWALL",
        "s11_LAX_RV_FREEWALL",
        "s06_SAX_RV_EPICARDIAL",
        "s05_SAX_LV_EPICARDIAL",
        "s02_SAX_RV_SEPTUM",
        "s04_SAX_LV_EPICARDIAL",
        "s05_SAX_RV_EPICARDIAL",
        "s05_SAX_LV_ENDOCARDIAL",
        "s04_SAX_RV_FREEWALL",
        "s06_SAX_LV_EPICARDIAL",
        "s11_LAX_RV_SEPTUM",
        "s03_SAX_RV_FREEWALL",
        "s02_SAX_LV_EPICARDIAL",
    ];
    let mut shuffled = set.clone();
    shuffled.contours = order
        .iter()
        .map(|id| set.contours.iter().find(|c| c.id == *id).unwrap().clone())
        .collect();
    assert_eq!(shuffled.contours.len(), set.contours.len());
    let [lv, rv, biv] =
        ["LV_ENDO", "RV_ENDO", "BIV_EPI"].map(|s| reconstruct_surface(&shuffled, s));
    let base = common_basal_plane_all(&[&lv, &biv, &rv]).unwrap();
    let wall = build_biventricular(lv.mesh(), rv.mesh(), biv.mesh(), &base, Some(1.0)).unwrap();
    assert!(validity(&wall.mesh).is_closed_manifold());
    assert_eq!(wall.self_intersections, 0, "{:?}", wall.crossings);
    // The clearing moves little: no endocardial vertex further than the file order's run does
    // plus a step or two. (Not a fixed figure: on this real patient the push of the file order
    // itself ranges 1.2-5.9 mm over attractor counts of 150-300, chaos of misregistered slices.)
    let [lv0, rv0, biv0] = ["LV_ENDO", "RV_ENDO", "BIV_EPI"].map(|s| reconstruct_surface(&set, s));
    let base0 = common_basal_plane_all(&[&lv0, &biv0, &rv0]).unwrap();
    let in_order =
        build_biventricular(lv0.mesh(), rv0.mesh(), biv0.mesh(), &base0, Some(1.0)).unwrap();
    eprintln!(
        "BIV {file} shuffled: endocardium moved {:?} (file order {:?})",
        wall.pushed, in_order.pushed
    );
    assert!(
        wall.pushed.max_mm < in_order.pushed.max_mm + 1.5,
        "{:?} against the file order's {:?}",
        wall.pushed,
        in_order.pushed
    );
}

/// The biventricular myocardium of the real biv-me patient (the only one with RV epicardial
/// curves): closed, no crossings, the LV cavity the LV wall's at the same base, and more
/// myocardium than the LV wall by the RV free wall.
#[test]
fn real_biventricular_walls_are_closed_and_hold_the_lv_wall() {
    for file in [
        "bivme-example-patient1/patient1-ED.csv",
        "bivme-example-patient1/patient1-ES.csv",
    ] {
        let set = load_contours(file);
        let lv = reconstruct_surface(&set, "LV_ENDO");
        let rv = reconstruct_surface(&set, "RV_ENDO");
        let biv = reconstruct_surface(&set, "BIV_EPI");
        let lv_epi = reconstruct_surface(&set, "LV_EPI");
        let base = common_basal_plane_all(&[&lv, &biv, &rv]).unwrap();
        let wall = build_biventricular(lv.mesh(), rv.mesh(), biv.mesh(), &base, Some(1.0)).unwrap();
        let v = validity(&wall.mesh);
        assert!(v.is_closed_manifold(), "{file}: {}", v.describe());
        assert_eq!(wall.self_intersections, 0, "{file}: {:?}", wall.crossings);
        assert_eq!(wall.region_names, &BIV_REGION_NAMES);
        assert!(wall.triangles_per_region.iter().all(|&n| n > 50), "{file}");
        let lv_wall = build_wall(lv.mesh(), lv_epi.mesh(), &base, Some(1.0)).unwrap();
        let mean_t = wall.thickness.iter().sum::<f64>() / wall.thickness.len() as f64;
        eprintln!(
            "BIV {file}: {:.1} ml (LV wall {:.1}), cavities {:.1} / {:.1} ml, thickness {mean_t:.2}",
            wall.volume_ml, lv_wall.volume_ml, wall.cavities_ml[0], wall.cavities_ml[1]
        );
        let (lv_cavity, rv_cavity) = (wall.cavities_ml[0], wall.cavities_ml[1]);
        assert!(
            (lv_cavity - lv_wall.cavity_ml).abs() / lv_wall.cavity_ml < 0.02,
            "{file}: {lv_cavity} vs {}",
            lv_wall.cavity_ml
        );
        assert!(
            rv_cavity > 0.0 && rv_cavity < rv.mesh().volume_ml(),
            "{file}"
        );
        // The RV free wall adds myocardium: more than a tenth of the LV wall, less than it all.
        let extra = wall.volume_ml / lv_wall.volume_ml;
        assert!((1.1..2.0).contains(&extra), "{file}: {extra}");
        assert!((3.0..12.0).contains(&mean_t), "{file}: thickness {mean_t}");
    }
}

/// How far below the top slice biv-me's model is compared: at the top slice its cavities reach
/// out to its epicardium along the valve rims (its surfaces are joined there).
const BIV_SHIFT_MM: f64 = 10.0;

/// biv-me's model of patient 1 (LV and RV cavities, biventricular epicardium) sliced on one set
/// of planes planned on the LV, reconstructed, and the biventricular wall compared with the wall
/// the model's own surfaces make at the same base. The RV's surfaces carry the RV's larger error
/// (issue 2: RV mean <= 0.5 mm), so the wall is held to that.
#[test]
fn biventricular_wall_matches_the_truth_wall() {
    let lv = load_truth("bivme-patient1-ED-LV_ENDO-closed.obj");
    let rv = load_truth("bivme-patient1-ED-RV_ENDO-closed.obj");
    let epi = load_truth("bivme-patient1-ED-EPI-closed.obj");
    let set = biv_acquisition(&lv, &rv, &epi, &AcquisitionSpec::default());
    let [lv_rec, rv_rec, epi_rec] =
        ["LV_ENDO", "RV_ENDO", "BIV_EPI"].map(|s| reconstruct_surface(&set, s));
    let top = common_basal_plane_all(&[&lv_rec, &epi_rec, &rv_rec]).unwrap();
    // biv-me's model joins its surfaces along the valve rims, where its cavities reach out to
    // the epicardium: the comparison is made a slice spacing below the top slice.
    let base = below(&top, BIV_SHIFT_MM);
    let wall = build_biventricular(
        lv_rec.mesh(),
        rv_rec.mesh(),
        epi_rec.mesh(),
        &base,
        Some(1.0),
    )
    .unwrap();
    // The model's own RV free wall comes out through its epicardium in places (its surfaces are
    // fitted apart too): the truth is held to the same rule, and how far it moved is printed.
    let truth = build_biventricular(&lv, &rv, &epi, &base, Some(1.0)).unwrap();
    eprintln!("BIV truth moved: {:?} {:?}", truth.pushed, truth.epi_pushed);
    against_truth("biv-me patient 1 biventricular", &wall, &truth, 0.5);
}

/// biv-me's model's three surfaces on one acquisition planned on the LV.
fn biv_acquisition(
    lv: &TriMesh,
    rv: &TriMesh,
    epi: &TriMesh,
    spec: &AcquisitionSpec,
) -> ContourSet {
    simulate_surfaces(&[("LV_ENDO", lv), ("RV_ENDO", rv), ("BIV_EPI", epi)], spec)
        .unwrap()
        .contours
}

/// Misaligned acquisitions (every image its own breath-hold, the same for every surface on it):
/// the biventricular wall is still one solid, with or without slice alignment. Near the base
/// the model's RV free wall runs within a millimetre of its epicardium and both run nearly along
/// the base plane, so the offsets put the RV's outline outside the epicardium's there unless the
/// outlines are separated in the plane (`mesh::outline`).
#[test]
fn misaligned_biventricular_walls_are_solids() {
    let lv = load_truth("bivme-patient1-ED-LV_ENDO-closed.obj");
    let rv = load_truth("bivme-patient1-ED-RV_ENDO-closed.obj");
    let epi = load_truth("bivme-patient1-ED-EPI-closed.obj");
    // Seeds 1-3 at the 2 mm / 2 degrees; seed 10 at 3 mm / 3 degrees left 43 crossing
    // pairs just under the top slice (the LV cavity far out through the epicardium there) until
    // the base could move down a millimetre.
    for (seed, mm) in [(1u64, 2.0), (2, 2.0), (3, 2.0), (10, 3.0)] {
        let set = biv_acquisition(&lv, &rv, &epi, &misaligned_by(seed, mm));
        for align in [false, true] {
            let [lv_rec, rv_rec, epi_rec] =
                ["LV_ENDO", "RV_ENDO", "BIV_EPI"].map(|s| reconstruct_with(&set, s, align));
            let top = common_basal_plane_all(&[&lv_rec, &epi_rec, &rv_rec]).unwrap();
            let name = format!("biv-me seed {seed} at {mm} mm, align {align}");
            let build = |base: &Plane| {
                build_biventricular(
                    lv_rec.mesh(),
                    rv_rec.mesh(),
                    epi_rec.mesh(),
                    base,
                    Some(1.0),
                )
                .unwrap_or_else(|e| panic!("{name}: {e}"))
            };
            // At the base a user gets: one solid.
            let wall = build(&top);
            eprintln!("{name}: notes {:?}", wall.notes);
            let v = validity(&wall.mesh);
            assert!(v.is_closed_manifold(), "{name}: {}", v.describe());
            assert_eq!(wall.self_intersections, 0, "{name}: {:?}", wall.crossings);
            // Against the model where its own surfaces are apart (as the aligned case).
            let base = below(&top, BIV_SHIFT_MM);
            let truth = build_biventricular(&lv, &rv, &epi, &base, Some(1.0)).unwrap();
            against_truth(&name, &build(&base), &truth, MISALIGNED_MEAN_MM);
        }
    }
}

/// `plane` moved `mm` towards the apex.
fn below(plane: &Plane, mm: f64) -> Plane {
    Plane {
        origin: plane.origin - plane.normal * mm,
        normal: plane.normal,
    }
}

/// The LV walls of the CAP atlas and the spasm model from misaligned acquisitions.
#[test]
fn misaligned_lv_walls_are_solids() {
    for (name, endo_file, epi_file) in [
        (
            "CAP atlas",
            "cap-atlas-mean-ED-LV_ENDO-open.obj",
            "cap-atlas-mean-ED-LV_EPI-open.obj",
        ),
        (
            "spasm",
            "cardiomesh-spasm-LV_endo.obj",
            "cardiomesh-spasm-LV_epi.obj",
        ),
    ] {
        let (endo, epi) = (load_truth(endo_file), load_truth(epi_file));
        for seed in 1..=3u64 {
            let set = acquire(&endo, &epi, &misaligned(seed));
            for align in [false, true] {
                let endo_rec = reconstruct_with(&set, "LV_ENDO", align);
                let epi_rec = reconstruct_with(&set, "LV_EPI", align);
                let base = common_basal_plane(&endo_rec, &epi_rec).unwrap();
                let name = format!("{name} seed {seed} align {align}");
                let wall = build_wall(endo_rec.mesh(), epi_rec.mesh(), &base, Some(1.0))
                    .unwrap_or_else(|e| panic!("{name}: {e}"));
                let truth = build_wall(&endo, &epi, &base, None).unwrap();
                against_truth(&name, &wall, &truth, MISALIGNED_MEAN_MM);
            }
        }
    }
}
