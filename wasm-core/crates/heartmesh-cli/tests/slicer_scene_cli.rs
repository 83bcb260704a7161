//! 3D Slicer scenes end to end: the folder Slicer saves a scene into, and the same folder as one
//! `.mrb` bundle (Slicer's "Medical Reality Bundle", a ZIP), read for their contours: a scene with
//! markups curves gives the mesh of its markups, one with a segmentation the mesh of its
//! segmentation; the scene file, images and point lists are set aside and named; a scene file
//! alone, or a scene without contours, is refused in one line.

mod common;
use common::{bin, core_data, data, files_under, run, scratch, stored_zip};
use std::path::Path;

const SCENE: &str = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<MRML  version=\"Slicer4.4.0\" \
userTags=\"\">\n</MRML>\n";

/// An intensity image of 64 x 64 x 4 voxels as Slicer saves a scan (values 0-999).
fn image() -> Vec<u8> {
    let mut bytes = b"NRRD0004\ntype: short\ndimension: 3\nspace: left-posterior-superior\n\
sizes: 64 64 4\nspace directions: (1.4,0,0) (0,1.4,0) (0,0,10)\nkinds: domain domain domain\n\
endian: little\nencoding: raw\nspace origin: (0,0,0)\n\n"
        .to_vec();
    for v in 0..64 * 64 * 4 {
        bytes.extend_from_slice(&((v * 37 % 1000) as i16).to_le_bytes());
    }
    bytes
}

/// A point list (RV insertions) as Slicer's Markups module saves one.
const POINTS: &str = r#"{"@schema":"https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/markups-schema-v1.0.3.json#","markups":[{"type":"Fiducial","name":"F","coordinateSystem":"LPS","controlPoints":[{"label":"RV_INSERT_1","position":[220.0,60.0,260.0],"positionStatus":"defined"}]}]}"#;

/// `reconstruct INPUT -o DIR/NAME --surface SURFACE`: status, stderr and the mesh file's lines.
fn mesh_of(input: &Path, surface: &str, dir: &Path, name: &str) -> (i32, String, Vec<String>) {
    let out = dir.join(name);
    let (code, _, err) = run(bin()
        .arg("reconstruct")
        .arg(input)
        .args(["--surface", surface, "-o"])
        .arg(&out));
    let lines = std::fs::read_to_string(&out)
        .map(|t| {
            t.lines()
                .filter(|l| !l.starts_with('#'))
                .map(str::to_string)
                .collect()
        })
        .unwrap_or_default();
    (code, err, lines)
}

/// `root` zipped as Slicer bundles a scene: every file under one top folder named after it.
fn bundle(root: &Path, to: &Path) {
    let top = root.file_name().unwrap().to_string_lossy().to_string();
    let files: Vec<(String, Vec<u8>)> = files_under(root)
        .into_iter()
        .map(|(name, bytes)| (format!("{top}/{name}"), bytes))
        .collect();
    std::fs::write(to, stored_zip(&files)).unwrap();
}

#[test]
fn a_scene_of_markups_curves_gives_the_mesh_of_its_markups() {
    let dir = scratch("scene_markups");
    let markups = Path::new(&core_data("slicer-markups-patient1")).to_path_buf();
    let (code, err, plain) = mesh_of(&markups, "LV_ENDO", &dir, "plain.obj");
    assert_eq!(code, 0, "{err}");
    assert!(plain.len() > 1000);
    // The scene's folder: its scene file, a scan and a screenshot beside the curves' folder.
    let scene = dir.join("Patient1");
    let data_dir = scene.join("Data");
    std::fs::create_dir_all(&data_dir).unwrap();
    for (name, bytes) in files_under(&markups) {
        std::fs::write(data_dir.join(name), bytes).unwrap();
    }
    std::fs::write(scene.join("Patient1.mrml"), SCENE).unwrap();
    std::fs::write(data_dir.join("cine.nrrd"), image()).unwrap();
    std::fs::write(scene.join("Patient1.png"), b"\x89PNG\r\n\x1a\n").unwrap();
    let mrb = dir.join("Patient1.mrb");
    bundle(&scene, &mrb);
    for input in [&scene, &mrb] {
        let (code, err, mesh) = mesh_of(input, "LV_ENDO", &dir, "scene.obj");
        assert_eq!(code, 0, "{err}");
        assert!(
            mesh == plain,
            "{} differs from the markups' mesh",
            input.display()
        );
        assert!(
            err.contains(
                "3 other file(s) of the Slicer scene set aside (the contours come from \
                          the Slicer markups): "
            ) && err.contains("Patient1.mrml (the scene file)")
                && err.contains("cine.nrrd")
                && err.contains("Patient1.png"),
            "{err}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_scene_of_a_segmentation_gives_the_mesh_of_its_segmentation() {
    let dir = scratch("scene_segmentation");
    let seg = dir.join("Segmentation.seg.nrrd");
    let mesh = |name: &str| data(&format!("meshes/{name}")).display().to_string();
    let (code, _, err) = run(bin().args([
        "segment",
        "--lv-endo",
        &mesh("cardiomesh-spasm-LV_endo.obj"),
        "--lv-epi",
        &mesh("cardiomesh-spasm-LV_epi.obj"),
        "-o",
        seg.to_str().unwrap(),
    ]));
    assert_eq!(code, 0, "{err}");
    let (code, err, plain) = mesh_of(&seg, "LV_EPI", &dir, "plain.obj");
    assert_eq!(code, 0, "{err}");
    assert!(plain.len() > 1000);
    let scene = dir.join("Scene");
    std::fs::create_dir_all(scene.join("Data")).unwrap();
    std::fs::copy(&seg, scene.join("Data/Segmentation.seg.nrrd")).unwrap();
    std::fs::write(scene.join("Data/cine.nrrd"), image()).unwrap();
    std::fs::write(scene.join("Data/F.mrk.json"), POINTS).unwrap();
    std::fs::write(scene.join("Scene.mrml"), SCENE).unwrap();
    let mrb = dir.join("Scene.mrb");
    bundle(&scene, &mrb);
    for input in [&scene, &mrb] {
        let (code, err, mesh) = mesh_of(input, "LV_EPI", &dir, "scene.obj");
        assert_eq!(code, 0, "{err}");
        assert!(
            mesh == plain,
            "{} differs from the segmentation's mesh",
            input.display()
        );
        assert!(
            err.contains(
                "3 other file(s) of the Slicer scene set aside (the contours come from \
                          the segmentation): "
            ) && err.contains("F.mrk.json, ")
                && err.contains("cine.nrrd, ")
                && err.contains("Scene.mrml (the scene file)"),
            "{err}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_scene_file_alone_or_a_scene_without_contours_is_refused_in_one_line() {
    let dir = scratch("scene_refused");
    let mrml = dir.join("Scene.mrml");
    std::fs::write(&mrml, SCENE).unwrap();
    let (code, err, _) = mesh_of(&mrml, "LV_ENDO", &dir, "x.obj");
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("Scene.mrml")
            && err.contains("3D Slicer scene file (.mrml)")
            && err.contains("open the scene's folder, or the scene saved as one .mrb bundle"),
        "{err}"
    );
    // The scene's folder with a scan and nothing drawn on it.
    std::fs::write(dir.join("cine.nrrd"), image()).unwrap();
    let (code, err, _) = mesh_of(&dir, "LV_ENDO", &dir, "x.obj");
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("the 3D Slicer scene holds no contours")
            && err.contains("among its 2 file(s)"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
