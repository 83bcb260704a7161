use super::*;
use crate::io::{read_contours, read_study, ContourOptions};

const SCENE: &[u8] = b"<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<MRML  version=\"Slicer4.4.0\" \
userTags=\"\">\n <Selection id=\"vtkMRMLSelectionNodeSingleton\"></Selection>\n</MRML>\n";

/// A NRRD of `n` x `n` x `slices` voxels, 1.5 mm pixels, slices 10 mm apart, of 16-bit values.
fn nrrd(
    n: usize,
    slices: usize,
    extra: &str,
    value: impl Fn(usize, usize, usize) -> i16,
) -> Vec<u8> {
    let mut bytes = format!(
        "NRRD0004\ntype: short\ndimension: 3\nspace: left-posterior-superior\nsizes: {n} {n} \
         {slices}\nspace directions: (1.5,0,0) (0,1.5,0) (0,0,10)\nkinds: domain domain domain\n\
         endian: little\nencoding: raw\nspace origin: (-20,-20,0)\n{extra}\n"
    )
    .into_bytes();
    for k in 0..slices {
        for j in 0..n {
            for i in 0..n {
                bytes.extend_from_slice(&value(i, j, k).to_le_bytes());
            }
        }
    }
    bytes
}

/// A segmentation as Slicer saves it: one disc per slice, label 1, named `LV`.
fn segmentation() -> Vec<u8> {
    nrrd(
        28,
        4,
        "Segment0_Name:=LV\nSegment0_LabelValue:=1\nSegment0_Layer:=0\n",
        |i, j, _| {
            let (x, y) = (i as f64 - 13.5, j as f64 - 13.5);
            i16::from(x * x + y * y < 64.0)
        },
    )
}

/// The scan it was drawn on: intensities 0-499.
fn image() -> Vec<u8> {
    nrrd(28, 4, "", |i, j, k| {
        ((i * 7 + j * 13 + k * 31) % 500) as i16
    })
}

/// A markups file holding one closed curve named `name`, or a point list of landmarks (`curve`
/// false: points on several images, not one contour clicked point by point).
fn markups(name: &str, curve: bool, z: f64) -> Vec<u8> {
    let kind = if curve { "ClosedCurve" } else { "Fiducial" };
    let points: Vec<String> = (0..8)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 8.0;
            let z = if curve { z } else { z + 10.0 * k as f64 };
            format!(
                r#"{{"label":"P-{k}","position":[{},{},{z}],"positionStatus":"defined"}}"#,
                12.0 * a.cos(),
                12.0 * a.sin()
            )
        })
        .collect();
    format!(
        r#"{{"@schema":"https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/markups-schema-v1.0.3.json#","markups":[{{"type":"{kind}","name":"{name}","coordinateSystem":"LPS","controlPoints":[{}]}}]}}"#,
        points.join(",")
    )
    .into_bytes()
}

#[test]
fn a_scene_file_is_told_by_its_root_element() {
    assert!(is_mrml(SCENE));
    assert!(is_mrml(b"<MRML version=\"Slicer5.6\"></MRML>"));
    assert!(is_mrml(
        b"\xEF\xBB\xBF  <!-- saved by Slicer -->\n<mrml>\n</mrml>"
    ));
    assert!(!is_mrml(b"<MRMLX>"));
    assert!(!is_mrml(
        b"<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\">"
    ));
    assert!(!is_mrml(b"<!-- never closed <MRML>"));
    assert!(!is_mrml(b"x,y,z\n1,2,3\n"));
    // Opened alone it says what to open instead, whatever its extension.
    for name in ["Scene.mrml", "scene.xml", "scene.txt"] {
        let e = read_contours(name, SCENE).unwrap_err().to_string();
        assert!(
            e.contains("3D Slicer scene file (.mrml)") && e.contains(".mrb bundle"),
            "{e}"
        );
    }
}

#[test]
fn a_scene_with_curves_reads_its_markups_and_sets_the_rest_aside() {
    let (a, b, img) = (
        markups("LV endo 1", true, 0.0),
        markups("LV endo 2", true, 10.0),
        image(),
    );
    let seg = segmentation();
    let files: Vec<(&str, &[u8])> = vec![
        ("Scene/Scene.mrml", SCENE),
        ("Scene/Data/cine.nrrd", &img),
        ("Scene/Data/LV endo 2.mrk.json", &b),
        ("Scene/Data/LV endo 1.mrk.json", &a),
        ("Scene/Scene.png", b"\x89PNG\r\n\x1a\n"),
        ("Scene/Data/Segment.nrrd", &seg),
    ];
    let scene = select(&files).unwrap().unwrap();
    assert_eq!(scene.read, vec![2, 3]);
    assert_eq!(scene.aside, vec![0, 1, 4, 5]);
    let (main, set) = read_study(&files, &ContourOptions::default()).unwrap();
    assert!([2, 3].contains(&main));
    let ids: Vec<&str> = set.contours.iter().map(|c| c.id.as_str()).collect();
    assert_eq!(ids, ["LV endo 1", "LV endo 2"]);
    assert!(set
        .contours
        .iter()
        .all(|c| c.surface.as_deref() == Some("LV_ENDO")));
    let w = set.warnings.last().unwrap();
    assert_eq!(
        w,
        "4 other file(s) of the Slicer scene set aside (the contours come from the Slicer \
         markups): Scene/Scene.mrml (the scene file), Scene/Data/cine.nrrd, Scene/Scene.png, \
         Scene/Data/Segment.nrrd (a segmentation: open it alone to read it instead)"
    );
}

#[test]
fn a_scene_without_curves_reads_its_segmentation_not_its_image_or_points() {
    let (seg, img, points) = (segmentation(), image(), markups("F", false, 0.0));
    let files: Vec<(&str, &[u8])> = vec![
        ("Scene/Data/F.mrk.json", &points),
        ("Scene/Data/cine.nrrd", &img),
        ("Scene/Data/Segmentation.seg.nrrd", &seg),
        ("Scene/Scene.mrml", SCENE),
    ];
    assert!(nifti::is_image(&img) && !nifti::is_image(&seg));
    let scene = select(&files).unwrap().unwrap();
    assert_eq!(
        (scene.read.clone(), scene.aside.clone()),
        (vec![2], vec![0, 1, 3])
    );
    let (main, set) = read_study(&files, &ContourOptions::default()).unwrap();
    assert_eq!(main, 2);
    // The same contours as the segmentation opened alone.
    let alone = read_contours("Segmentation.seg.nrrd", &seg).unwrap();
    assert_eq!(set.contours.len(), 4);
    assert_eq!(set.contours.len(), alone.contours.len());
    for (a, b) in set.contours.iter().zip(&alone.contours) {
        assert_eq!((&a.id, &a.surface), (&b.id, &b.surface));
        assert_eq!(a.point_count(), b.point_count());
    }
    assert!(set.warnings.last().unwrap().starts_with(
        "3 other file(s) of the Slicer scene set aside (the contours come from the segmentation): \
         Scene/Data/F.mrk.json, Scene/Data/cine.nrrd, Scene/Scene.mrml (the scene file)"
    ));
}

#[test]
fn markups_among_other_files_are_a_scene_without_its_scene_file() {
    let (a, img) = (markups("LV endo 1", true, 0.0), image());
    let files: Vec<(&str, &[u8])> = vec![("a.mrk.json", &a), ("cine.nrrd", &img)];
    let scene = select(&files).unwrap().unwrap();
    assert_eq!(
        (scene.read.clone(), scene.aside.clone()),
        (vec![0], vec![1])
    );
    assert_eq!(
        scene.warning(&files).unwrap(),
        "1 other file(s) set aside (the contours come from the Slicer markups): cine.nrrd"
    );
    // Neither a scene file nor markups: another kind of study.
    let seg = segmentation();
    assert_eq!(select(&[("a.nrrd", &seg), ("b.nrrd", &img)]).unwrap(), None);
    assert_eq!(
        select(&[("a.mrk.json", &a), ("b.mrk.json", &a)]).unwrap(),
        None
    );
}

#[test]
fn a_scene_without_contours_is_refused_naming_its_files() {
    let img = image();
    let files: Vec<(&str, &[u8])> = vec![("Scene.mrml", SCENE), ("cine.nrrd", &img)];
    let e = read_study(&files, &ContourOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("the 3D Slicer scene holds no contours")
            && e.contains("among its 2 file(s): Scene.mrml, cine.nrrd"),
        "{e}"
    );
    // Point lists alone: the markups reader's own refusal.
    let points = markups("F", false, 0.0);
    let files: Vec<(&str, &[u8])> = vec![("Scene.mrml", SCENE), ("F.mrk.json", &points)];
    let e = read_study(&files, &ContourOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("no curve or closed curve"), "{e}");
}

#[test]
fn a_scene_of_slicer_4_reads_its_point_list_files_as_contours() {
    // Slicer 4.10 saved a scene's point lists as .fcsv (RAS, the frame by number); contours were
    // point lists clicked along each curve, one per slice.
    let fcsv = |z: f64| {
        let mut text = String::from(
            "# Markups fiducial file version = 4.10\n# CoordinateSystem = 0\n\
             # columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n",
        );
        for k in 0..10 {
            let a = std::f64::consts::TAU * k as f64 / 10.0;
            text.push_str(&format!(
                "vtkMRMLMarkupsFiducialNode_{k},{},{},{z},0,0,0,1,1,1,0,F-{},,vtkMRMLScalarVolumeNode1\n",
                15.0 * a.cos(),
                15.0 * a.sin(),
                k + 1
            ));
        }
        text.into_bytes()
    };
    let (a, b, seg) = (fcsv(0.0), fcsv(10.0), segmentation());
    let files: Vec<(&str, &[u8])> = vec![
        ("Scene/Scene.mrml", SCENE),
        ("Scene/Data/LV_ENDO_2.fcsv", &b),
        ("Scene/Data/LV_ENDO_1.fcsv", &a),
        ("Scene/Data/Segment.nrrd", &seg),
    ];
    let scene = select(&files).unwrap().unwrap();
    assert_eq!(
        (scene.read.clone(), scene.aside.clone()),
        (vec![1, 2], vec![0, 3])
    );
    let (_, set) = read_study(&files, &ContourOptions::default()).unwrap();
    let ids: Vec<&str> = set.contours.iter().map(|c| c.id.as_str()).collect();
    assert_eq!(ids, ["LV_ENDO_1", "LV_ENDO_2"]);
    assert_eq!(
        set.coordinate_system,
        Some(crate::contours::CoordinateSystem::Ras)
    );
    assert!(set.contours.iter().all(|c| c.pieces[0].closed));
}
