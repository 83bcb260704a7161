//! Sunnybrook contour files read with their DICOM images land every contour where the millimetre
//! file they were made from has it. The fixture (tests/data/sunnybrook-patient1, written by
//! scripts/sunnybrook_fixture.py) is biv-me's patient 1's short-axis LV contours laid out as a
//! Sunnybrook case: `IM-0001-NNNN-{i,o}contour-manual.txt` in pixels with two decimals, the cine
//! short-axis series as `CINESAX_300/IM-0003-NNNN.dcm` (20 frames a slice), and a long-axis series
//! numbered like the first slice beside it. Reading it back must give the GPFile's points on
//! their image planes to the rounding, and a mesh as close to the GPFile's as that.

mod common;

use common::*;
use heartmesh_core::contours::ContourSet;
use heartmesh_core::io::{self, ContourOptions, FrameChoice};
use heartmesh_core::metrics::compare::compare;
use heartmesh_core::Params;
use std::path::{Path, PathBuf};

fn fixture() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/sunnybrook-patient1")
}

fn files_in(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut names: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    names.sort();
    names
        .iter()
        .map(|p| (p.display().to_string(), std::fs::read(p).unwrap()))
        .collect()
}

fn read_sunnybrook(frame: Option<&str>) -> ContourSet {
    let mut all = files_in(&fixture().join("CINE2CH_400"));
    all.extend(files_in(&fixture().join("contours-manual/IRCCI-expert")));
    all.extend(files_in(&fixture().join("CINESAX_300")));
    assert_eq!(all.len(), 20 + 15 + 100);
    let files: Vec<(&str, &[u8])> = all
        .iter()
        .map(|(n, b)| (n.as_str(), b.as_slice()))
        .collect();
    let options = ContourOptions {
        frame: frame.and_then(FrameChoice::new),
        ..ContourOptions::default()
    };
    let (main, set) = io::read_study(&files, &options).unwrap();
    assert!(
        files[main].0.ends_with("IM-0001-0001-icontour-manual.txt"),
        "{}",
        files[main].0
    );
    set
}

/// SAX-only contours of a GPFile (Sunnybrook's experts drew the short axis only).
fn gpfile_sax(name: &str) -> ContourSet {
    let mut set = load_contours(&format!("bivme-example-patient1/{name}"));
    set.contours.retain(|c| c.id.contains("SAX_"));
    set
}

/// Half a hundredth of a pixel (1.40625 mm) in both directions: the two decimals' largest offset.
const ROUNDING_MM: f64 = 0.005 * 1.40625 * std::f64::consts::SQRT_2;

#[test]
fn the_files_give_the_gpfiles_points_on_their_image_planes() {
    for (frame, gp, surfaces) in [
        (None, "GPFile_000.txt", &["LV_ENDO", "LV_EPI"][..]),
        (Some("9"), "GPFile_009.txt", &["LV_ENDO"][..]),
    ] {
        let sb = read_sunnybrook(frame);
        let gp = gpfile_sax(gp);
        for surface in surfaces {
            assert_on_gpfile_points(
                &format!("SUNNYBROOK frame {frame:?}"),
                &sb,
                &gp,
                surface,
                ROUNDING_MM,
            );
        }
        // The experts drew the epicardium at end-diastole only; the papillary muscle is no surface.
        let epi = sb
            .contours
            .iter()
            .filter(|c| c.surface.as_deref() == Some("LV_EPI"))
            .count();
        assert_eq!(epi, if frame.is_none() { 5 } else { 0 });
        assert!(
            sb.warnings.iter().any(|w| w.contains("p1contour skipped")),
            "{:?}",
            sb.warnings
        );
        assert!(
            sb.warnings[0].contains("120 DICOM images: contours on 9 of them, in 5 cine slices"),
            "{}",
            sb.warnings[0]
        );
    }
}

#[test]
fn the_meshes_match_the_gpfiles_short_axis_meshes() {
    let sb = read_sunnybrook(None);
    let tf = sb.time_frames.as_ref().unwrap();
    assert_eq!(tf.frames, ["0", "9"]);
    assert_eq!(tf.read, ["0"]);
    let params = Params {
        surface: Some("LV_ENDO".into()),
        ..Params::default()
    };
    for (set, gp) in [
        (sb, "GPFile_000.txt"),
        (read_sunnybrook(Some("9")), "GPFile_009.txt"),
    ] {
        let (a, _) = reconstruct(&set, params.clone());
        let (b, _) = reconstruct(&gpfile_sax(gp), params.clone());
        check_closed_manifold_outward(&a).unwrap();
        let c2m = surface_to_mesh(&set, "LV_ENDO", &a);
        let r = compare(&b, &a, None).unwrap();
        eprintln!(
            "SUNNYBROOK {gp} LV_ENDO: contour-to-mesh mean {:.3} max {:.3} mm; vs the GPFile's \
             mesh mean {:.3} / {:.3} mm, volumes {:.2} / {:.2} ml",
            mean(&c2m),
            max(&c2m),
            r.mesh_to_truth.mean,
            r.truth_to_mesh.mean,
            a.volume_ml(),
            b.volume_ml()
        );
        assert!(mean(&c2m) <= 0.5);
        // The same rings, moved onto their planes by at most 0.2 mm: the same cavity.
        assert!(r.mesh_to_truth.mean <= 0.3 && r.truth_to_mesh.mean <= 0.3);
        assert!((a.volume_ml() / b.volume_ml() - 1.0).abs() < 0.01);
    }
}
