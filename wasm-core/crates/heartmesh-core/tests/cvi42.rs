//! A cvi42 workspace read with its DICOM images lands every contour where the millimetre file it
//! was made from has it. The fixture (tests/data/cvi42-patient1, written by
//! scripts/cvi42_fixture.py) is biv-me's patient 1 in pixels of its own image planes
//! (SliceInfoFile.txt) at subpixel resolution 8, with one header-only DICOM image per slice and
//! frame: reading it back must give the GPFile's points, each moved onto its image plane and
//! rounded to an eighth of a pixel, and a mesh as close to the GPFile's as that.

mod common;

use common::*;
use heartmesh_core::contours::ContourSet;
use heartmesh_core::geometry::Vec3;
use heartmesh_core::io::{self, ContourOptions, FrameChoice};
use heartmesh_core::metrics::compare::compare;
use heartmesh_core::Params;
use std::path::PathBuf;

fn fixture() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/cvi42-patient1")
}

fn read_cvi42(frame: Option<&str>) -> ContourSet {
    let dir = fixture().join("dicom");
    let mut names: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    names.sort();
    let images: Vec<(String, Vec<u8>)> = names
        .iter()
        .map(|p| (p.display().to_string(), std::fs::read(p).unwrap()))
        .collect();
    assert_eq!(images.len(), 110);
    let wsx = std::fs::read(fixture().join("Contours.cvi42wsx")).unwrap();
    let mut files: Vec<(&str, &[u8])> = vec![("Contours.cvi42wsx", &wsx)];
    files.extend(images.iter().map(|(n, b)| (n.as_str(), b.as_slice())));
    let options = ContourOptions {
        frame: frame.and_then(FrameChoice::new),
        ..ContourOptions::default()
    };
    let (stack, set) = io::read_study(&files, &options).unwrap();
    assert_eq!(stack, 0);
    set
}

fn read_gpfile(name: &str) -> ContourSet {
    load_contours(&format!("bivme-example-patient1/{name}"))
}

/// An eighth of a pixel (1.40625 mm) in both directions: the rounding's largest offset.
const ROUNDING_MM: f64 = 0.5 / 8.0 * 1.40625 * std::f64::consts::SQRT_2;

#[test]
fn the_workspace_gives_the_gpfiles_points_on_their_image_planes() {
    for (frame, gp) in [(None, "GPFile_000.txt"), (Some("9"), "GPFile_009.txt")] {
        let cvi = read_cvi42(frame);
        let gp = read_gpfile(gp);
        // The curves the fixture copied one for one (the RV endocardium was joined from pieces).
        for surface in ["LV_ENDO", "LV_EPI", "RV_EPI"] {
            assert_on_gpfile_points(
                &format!("CVI42 frame {frame:?}"),
                &cvi,
                &gp,
                surface,
                ROUNDING_MM,
            );
        }
    }
}

#[test]
fn the_workspaces_meshes_match_the_gpfiles_where_the_contours_do() {
    let cvi = read_cvi42(None);
    let gp = read_gpfile("GPFile_000.txt");
    let tf = cvi.time_frames.as_ref().unwrap();
    assert_eq!(tf.frames, ["0", "9"]);
    assert_eq!(tf.read, ["0"]);
    for surface in ["LV_ENDO", "RV_ENDO"] {
        let params = Params {
            surface: Some(surface.into()),
            ..Params::default()
        };
        let (a, _) = reconstruct(&cvi, params.clone());
        let (b, _) = reconstruct(&gp, params);
        check_closed_manifold_outward(&a).unwrap();
        let c2m = surface_to_mesh(&cvi, surface, &a);
        let r = compare(&b, &a, None).unwrap();
        eprintln!(
            "CVI42 {surface}: contour-to-mesh mean {:.3} max {:.3} mm; vs the GPFile's mesh \
             mean {:.3} / {:.3} mm, volumes {:.1} / {:.1} ml",
            mean(&c2m),
            max(&c2m),
            r.mesh_to_truth.mean,
            r.truth_to_mesh.mean,
            a.volume_ml(),
            b.volume_ml()
        );
        assert!(mean(&c2m) <= 1.0, "{surface}");
        if surface == "LV_ENDO" {
            // The same curves, moved by under 2 mm onto their planes: the same cavity.
            assert!(r.mesh_to_truth.mean <= 0.3 && r.truth_to_mesh.mean <= 0.3);
            assert!((a.volume_ml() / b.volume_ml() - 1.0).abs() < 0.02);
        }
    }
}

#[test]
fn the_reference_points_are_the_gpfiles_insertions_and_extents() {
    for (frame, gp) in [(None, "GPFile_000.txt"), (Some("9"), "GPFile_009.txt")] {
        let cvi = read_cvi42(frame);
        let gp = read_gpfile(gp);
        let named = |set: &ContourSet, names: &[&str]| -> Vec<Vec3> {
            set.landmarks
                .iter()
                .filter(|(n, _)| names.contains(&n.as_str()))
                .map(|(_, p)| *p)
                .collect()
        };
        let inserts = named(&gp, &["RV_INSERT"]);
        let extents = named(&gp, &["MITRAL_VALVE", "APEX_POINT"]);
        let anterior = named(&cvi, &["RV_INSERT_ANTERIOR"]);
        let inferior = named(&cvi, &["RV_INSERT_INFERIOR"]);
        let lax = named(&cvi, &["LAX_LV_EXTENT"]);
        eprintln!(
            "CVI42 frame {frame:?} landmarks: {} anterior + {} inferior insertions ({} in the \
             GPFile), {} LV extent points ({})",
            anterior.len(),
            inferior.len(),
            inserts.len(),
            lax.len(),
            extents.len()
        );
        assert_eq!(anterior.len() + inferior.len(), inserts.len());
        assert_eq!(anterior.len(), inferior.len());
        assert_eq!(lax.len(), extents.len());
        // Each within the pixel rounding of its GPFile point (the fixture put them on their
        // planes: the GPFile's lie up to 0.1 mm off).
        for (mine, theirs) in [
            (&anterior, &inserts),
            (&inferior, &inserts),
            (&lax, &extents),
        ] {
            for p in mine.iter() {
                let gap = theirs
                    .iter()
                    .map(|q| (q - p).norm())
                    .fold(f64::INFINITY, f64::min);
                assert!(gap <= ROUNDING_MM + 0.15, "{p:?}: {gap}");
            }
        }
        // The superior reference point is the more anterior of its slice's two (LPS: lower y;
        // frame 9's apical pair ties in y to 1e-5 mm).
        for (a, i) in anterior.iter().zip(&inferior) {
            assert!(a.y < i.y + 0.01, "{a:?} {i:?}");
        }
    }
}
