//! The mesh must not depend on the scanner frame: the same contours, rotated and moved, give the
//! same mesh rotated and moved. Contours come in patient/scanner coordinates, and nothing about
//! how the patient lay in the scanner should change the reconstructed shape (session 6 found the
//! first ring's start tied to the scanner x axis: SurFCo's contour-to-mesh mean then varied from
//! 0.055 to 0.094 mm with the rotation about its long axis). Nor on the order a file lists its
//! contours in: the same contours in another order give the same mesh, to the bit.

mod common;

use common::*;
use heartmesh_core::contours::ContourSet;
use heartmesh_core::geometry::Vec3;
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::Params;
use nalgebra::{Rotation3, Unit};

fn moved(set: &ContourSet, r: &Rotation3<f64>, t: &Vec3) -> ContourSet {
    let mut out = set.clone();
    for c in &mut out.contours {
        for piece in &mut c.pieces {
            for p in &mut piece.points {
                *p = r * *p + t;
            }
        }
    }
    out
}

/// Largest distance between the vertices of `a` and those of `b` mapped back by the inverse motion.
fn deviation_mm(a: &[Vec3], b: &[Vec3], r: &Rotation3<f64>, t: &Vec3) -> f64 {
    let inv = r.inverse();
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - inv * (q - t)).norm())
        .fold(0.0, f64::max)
}

/// The two motions every case is checked under.
fn motions() -> [(Rotation3<f64>, Vec3); 2] {
    [
        // About the long axis of the stack (scanner z): the case that used to move the seam.
        (
            Rotation3::from_axis_angle(&Vec3::z_axis(), 0.7),
            Vec3::zeros(),
        ),
        // An oblique axis, and far from the origin.
        (
            Rotation3::from_axis_angle(&Unit::new_normalize(Vec3::new(0.3, -0.8, 0.5)), 2.1),
            Vec3::new(-1200.0, 350.0, 80.0),
        ),
    ]
}

fn run(set: &ContourSet, surface: Option<&str>) -> TriMesh {
    let params = Params {
        surface: surface.map(str::to_string),
        ..Params::default()
    };
    reconstruct(set, params).0
}

#[test]
fn surfco_mesh_follows_a_rigid_motion_of_its_contours() {
    let sub = "surfco-example.csv";
    let set = load_contours(sub);
    let mesh = run(&set, None);
    for (r, t) in motions() {
        let other = run(&moved(&set, &r, &t), None);
        assert_eq!(
            other.positions.len(),
            mesh.positions.len(),
            "{sub}: vertex count"
        );
        assert_eq!(other.triangles, mesh.triangles, "{sub}: connectivity");
        let d = deviation_mm(&mesh.positions, &other.positions, &r, &t);
        eprintln!(
            "INVARIANCE {sub}: rotation {:.2} rad: vertices within {d:.2e} mm",
            r.angle()
        );
        assert!(
            d < 1e-3,
            "{sub}: moved input gives a different mesh ({d} mm)"
        );
    }
}

/// The biv-me RV endocardium (rings joined from free-wall and septum pieces) is chaotic at the
/// level of rounding: a last-bit difference can flip one of two near-equal decimation costs, and
/// the meshes part (session 6: identical to 2.4e-5 mm about z, apart after the first remesh
/// about the oblique axis). The shape must still agree: volume, mean distance to the data,
/// counts. The single-point maximum is printed, not held: it sits where the septum's SAX and LAX
/// curves disagree and moved 4.47 -> 5.30 mm.
#[test]
fn bivme_rv_shape_follows_a_rigid_motion_of_its_contours() {
    let sub = "bivme-example-patient1/patient1-ED.csv";
    let set = load_contours(sub);
    let stats = |set: &ContourSet, mesh: &TriMesh| {
        let rv: Vec<_> = set
            .contours
            .iter()
            .filter(|c| c.surface.as_deref() == Some("RV_ENDO"))
            .cloned()
            .collect();
        let d = contour_to_mesh_of(&rv, mesh);
        (mesh.volume_ml(), mean(&d), max(&d), mesh.positions.len())
    };
    let mesh = run(&set, Some("RV_ENDO"));
    let (v0, m0, x0, n0) = stats(&set, &mesh);
    for (r, t) in motions() {
        let set_b = moved(&set, &r, &t);
        let (v, m, x, n) = stats(&set_b, &run(&set_b, Some("RV_ENDO")));
        eprintln!(
            "INVARIANCE {sub} RV_ENDO: volume {v0:.2} -> {v:.2} ml, contour->mesh mean {m0:.3} -> \
             {m:.3} max {x0:.2} -> {x:.2} mm, {n0} -> {n} vertices"
        );
        assert_eq!(n, n0, "vertex count");
        assert!((v - v0).abs() < 0.01 * v0, "volume {v0} -> {v} ml");
        assert!((m - m0).abs() < 0.05, "contour->mesh mean {m0} -> {m} mm");
    }
}

/// `set` with its contours in the order `order` gives (indices into `set.contours`).
fn reordered(set: &ContourSet, order: &[usize]) -> ContourSet {
    let mut out = set.clone();
    out.contours = order.iter().map(|&i| set.contours[i].clone()).collect();
    out
}

/// The same contours listed in another order (reversed; each RV slice's septum before its free
/// wall; long-axis views first) give the same mesh to the bit: every sum over contours (the
/// normalisation's centre, the long axis, slice heights, lids, the valve plane's fit) is taken in
/// an order of its own. Session 41 found the biv-me RV's volume moving 180.6 -> 181.5 ml with the
/// order of its contours, the mesh a chaotic function of last-bit differences in those sums.
#[test]
fn the_order_of_the_contours_in_the_file_does_not_change_the_mesh() {
    for sub in [
        "bivme-example-patient1/patient1-ED.csv",
        "bivme-test-patient2/patient2-ED.csv",
    ] {
        let set = load_contours(sub);
        let n = set.contours.len();
        let reversed: Vec<usize> = (0..n).rev().collect();
        let mut pairs_swapped: Vec<usize> = (0..n).collect();
        for pair in pairs_swapped.chunks_mut(2) {
            pair.reverse();
        }
        let lax_first: Vec<usize> = {
            let is_lax = |i: &usize| set.contours[*i].id.contains("LAX");
            let (mut lax, sax): (Vec<usize>, Vec<usize>) = (0..n).partition(is_lax);
            lax.extend(sax);
            lax
        };
        for surface in ["RV_ENDO", "LV_EPI"] {
            let mesh = run(&set, Some(surface));
            for (what, order) in [
                ("reversed", &reversed),
                ("pairs swapped", &pairs_swapped),
                ("long-axis first", &lax_first),
            ] {
                let other = run(&reordered(&set, order), Some(surface));
                assert_eq!(other.triangles, mesh.triangles, "{sub} {surface} {what}");
                assert!(
                    other.positions == mesh.positions,
                    "{sub} {surface} {what}: volume {} -> {} ml",
                    mesh.volume_ml(),
                    other.volume_ml()
                );
            }
        }
    }
}

/// `set` with each image plane's RV free wall and septum under one name (`s02_SAX_RV`), their
/// pieces kept as they are: the same curves, named as a tool that stores one curve per slice
/// would name them.
fn one_name_per_plane(set: &ContourSet) -> ContourSet {
    let mut out = set.clone();
    out.contours.clear();
    for c in &set.contours {
        let id =
            c.id.replace("_RV_FREEWALL", "_RV")
                .replace("_RV_SEPTUM", "_RV");
        match out
            .contours
            .iter_mut()
            .find(|o| o.id == id && o.surface == c.surface)
        {
            Some(o) => o.pieces.extend(c.pieces.iter().cloned()),
            None => {
                let mut c = c.clone();
                c.id = id;
                out.contours.push(c);
            }
        }
    }
    out
}

/// The attractor counts of a run's steps (the automatic count, and the count after each
/// resampling).
fn attractor_counts(set: &ContourSet, surface: &str) -> (Vec<usize>, TriMesh) {
    let params = Params {
        surface: Some(surface.to_string()),
        ..Params::default()
    };
    let mut rec = heartmesh_core::Reconstruction::new(set, params).expect("new");
    let mut counts = Vec::new();
    loop {
        let report = rec.step().expect("step");
        counts.push(report.attractors);
        if report.done {
            break;
        }
    }
    (counts, rec.mesh().clone())
}

/// How a file names the curves of one image plane does not change the mesh: biv-me writes each
/// slice's RV endocardium as a free wall and a septum, other tools one curve per slice. The
/// automatic attractor count is the paper's 25 per contour, a contour being one plane's
/// delineation; counted per name, patient 1's ED RV had 400 attractors as biv-me names it and
/// 200 with a name per slice, and the volumes differed by 5 ml (181.3 and 186.4 ml).
#[test]
fn the_names_of_one_planes_curves_do_not_change_the_mesh() {
    for (sub, planes) in [
        ("bivme-example-patient1/patient1-ED.csv", 8),
        ("bivme-test-patient2/patient2-ED.csv", 6),
    ] {
        let set = load_contours(sub);
        let merged = one_name_per_plane(&set);
        let names = |s: &ContourSet| {
            s.contours
                .iter()
                .filter(|c| c.surface.as_deref() == Some("RV_ENDO"))
                .count()
        };
        assert_eq!(
            names(&set),
            2 * planes,
            "{sub}: free wall + septum per plane"
        );
        assert_eq!(names(&merged), planes, "{sub}: one name per plane");
        let (counts, mesh) = attractor_counts(&set, "RV_ENDO");
        let (merged_counts, merged_mesh) = attractor_counts(&merged, "RV_ENDO");
        // max(150, 25 x planes): the paper's count for one curve per plane.
        assert_eq!(counts[0], (25 * planes).max(150), "{sub}");
        assert_eq!(merged_counts, counts, "{sub}: attractor counts");
        let rv = surface_contours(&set, "RV_ENDO");
        let (v0, v1) = (mesh.volume_ml(), merged_mesh.volume_ml());
        let (m0, m1) = (
            mean(&contour_to_mesh_of(&rv, &mesh)),
            mean(&contour_to_mesh_of(&rv, &merged_mesh)),
        );
        eprintln!(
            "NAMES {sub} RV_ENDO: {v0:.2} -> {v1:.2} ml, contour->mesh mean {m0:.3} -> {m1:.3} mm"
        );
        // Not to the bit: the long axis is the mean of the short-axis curves' plane normals, and a
        // slice's free wall and septum fitted apart give two normals where the slice gives one.
        assert!(
            (v1 - v0).abs() < 0.005 * v0,
            "{sub}: volume {v0} -> {v1} ml"
        );
        assert!(
            (m1 - m0).abs() < 0.02,
            "{sub}: contour->mesh mean {m0} -> {m1} mm"
        );
    }
}

/// `set` with every coordinate moved by up to `amp` mm (a fixed pseudo-random sequence per
/// `seed`: the rounding of another exporter, a file written with fewer digits).
fn jittered(set: &ContourSet, amp: f64, seed: u64) -> ContourSet {
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut next = move || {
        // xorshift64*: uniform in [-1, 1).
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        let bits = state.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        bits as f64 / (1u64 << 52) as f64 - 1.0
    };
    let mut out = set.clone();
    for c in &mut out.contours {
        for piece in &mut c.pieces {
            for p in &mut piece.points {
                *p += Vec3::new(next(), next(), next()) * amp;
            }
        }
    }
    out
}

/// A tenth of a micrometre of noise on SurFCo's points must not change how well the mesh fits
/// them. The method's stop rule holds at some iteration that such noise moves; stopping right
/// there, a few steps after a remesh, left part of that remesh's smoothing offset in the mesh
/// (session 42: mean contour distance 0.058-0.089 mm over eight such copies, in two groups as
/// the rule first held at iteration 240 or 224). Now a run whose rule holds settles for as long
/// as a run's last steps do before it stops, and every copy fits alike.
#[test]
fn surfco_fits_alike_under_a_tenth_of_a_micrometre_of_noise() {
    let set = load_contours("surfco-example.csv");
    let means: Vec<f64> = (0..6)
        .map(|seed| {
            let copy = if seed == 0 {
                set.clone()
            } else {
                jittered(&set, 1e-4, seed)
            };
            let mesh = run(&copy, None);
            mean(&contour_to_mesh(&copy, &mesh))
        })
        .collect();
    let lo = means.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = means.iter().copied().fold(0.0, f64::max);
    eprintln!("NOISE surfco: contour->mesh means {means:.4?} mm");
    assert!(hi < 0.07, "worst mean {hi} mm ({means:?})");
    assert!(hi - lo < 0.01, "means {lo}..{hi} mm ({means:?})");
}
