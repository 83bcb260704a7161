use super::*;
use crate::geometry::{v3, Vec3};
use crate::io::test_images::{dicom, Image};
use crate::io::{read_contours_with, read_study, ContourOptions};

#[test]
fn names_give_the_image_number_and_the_type() {
    let ok = [
        ("IM-0001-0048-icontour-manual.txt", (48, "icontour")),
        (
            "SC-HF-I-01/contours-manual/IRCCI-expert/IM-0001-0220-ocontour-manual.txt",
            (220, "ocontour"),
        ),
        ("a\\im-0001-0007-p1contour-auto.TXT", (7, "p1contour")),
        ("IM-0001-0060-icontour.txt", (60, "icontour")),
    ];
    for (name, want) in ok {
        assert_eq!(contour_name(name), Some(want), "{name}");
    }
    for name in [
        "IM-0001-0048.dcm",
        "IM-0001-0048-icontour-manual.csv",
        "contours.txt",
        "IM-0001-0048-i-manual.txt",
        "IM-0001--icontour-manual.txt",
        "IM-0001-0048-contour-manual.txt",
        "IM-0001-0048-i contour-manual.txt",
        "IM-1234567890-0048-icontour.txt",
        "IM-",
        "",
    ] {
        assert_eq!(contour_name(name), None, "{name}");
    }
    assert!(is_contour_file(
        "IM-0001-0048-icontour-manual.txt",
        b"120.50 85.00\n121.00 85.50\n"
    ));
    assert!(!is_contour_file(
        "IM-0001-0048-icontour-manual.txt",
        b"x,y,z\n1,2,3\n"
    ));
    assert!(!is_contour_file("notes.txt", b"120.50 85.00\n"));
}

/// Plane k of a short-axis stack 8 mm apart along z (rows along x, columns along y, 1.25 mm
/// pixels), frame `f` of 4, numbered `IM-0003-NNNN` as the data's series are.
fn stack_image(k: usize, f: usize) -> (String, Vec<u8>) {
    let n = k * 4 + f + 1;
    let uid: &'static str = format!("1.2.840.9.{k}.{f}").leak();
    let bytes = dicom(&Image {
        uid,
        position: [-50.0, -60.0, 8.0 * k as f64],
        orientation: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
        spacing: [1.25, 1.25],
        series: 300,
        trigger: 45.0 * f as f64,
        instance: Some(n as i64),
    });
    (format!("CINESAX_300/IM-0003-{n:04}.dcm"), bytes)
}

/// A long-axis series numbered 1-4 as the stack's first slice is.
fn lax_image(f: usize) -> (String, Vec<u8>) {
    let uid: &'static str = format!("1.2.840.9.lax.{f}").leak();
    let bytes = dicom(&Image {
        uid,
        position: [0.0, -60.0, -10.0],
        orientation: [0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
        spacing: [1.25, 1.25],
        series: 400,
        trigger: 45.0 * f as f64,
        instance: Some(f as i64 + 1),
    });
    (format!("CINE2CH_400/IM-0004-{:04}.dcm", f + 1), bytes)
}

/// A circle of 24 points of `r` pixels around pixel (40, 48), as the data write them.
fn circle(r: f64) -> Vec<u8> {
    let mut out = String::new();
    for i in 0..24 {
        let a = i as f64 * std::f64::consts::TAU / 24.0;
        out += &format!("{:.2} {:.2}\n", 40.0 + r * a.cos(), 48.0 + r * a.sin());
    }
    out.into_bytes()
}

/// Endo- and epicardium on every slice's frame 0, the endocardium on frame 2 too, a papillary
/// muscle on one slice.
fn contour_files() -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    for k in 0..3 {
        let n = k * 4 + 1;
        out.push((format!("IM-0001-{n:04}-icontour-manual.txt"), circle(16.0)));
        out.push((format!("IM-0001-{n:04}-ocontour-manual.txt"), circle(22.0)));
        out.push((
            format!("IM-0001-{:04}-icontour-manual.txt", n + 2),
            circle(11.0),
        ));
    }
    out.push(("IM-0001-0005-p1contour-manual.txt".into(), circle(3.0)));
    out
}

fn study(with_lax: bool) -> Vec<(String, Vec<u8>)> {
    let mut files = contour_files();
    for k in 0..3 {
        files.extend((0..4).map(|f| stack_image(k, f)));
    }
    if with_lax {
        files.extend((0..4).map(lax_image));
    }
    files
}

fn read(files: &[(String, Vec<u8>)], frame: Option<&str>) -> Result<ContourSet> {
    let named: Vec<(&str, &[u8])> = files
        .iter()
        .map(|(n, b)| (n.as_str(), b.as_slice()))
        .collect();
    let options = ContourOptions {
        frame: frame.and_then(FrameChoice::new),
        ..ContourOptions::default()
    };
    read_study(&named, &options).map(|(_, set)| set)
}

fn surface<'a>(set: &'a ContourSet, name: &str) -> Vec<&'a crate::contours::Contour> {
    set.contours
        .iter()
        .filter(|c| c.surface.as_deref() == Some(name))
        .collect()
}

#[test]
fn pixels_become_millimetres_on_the_series_that_holds_the_numbers() {
    let set = read(&study(true), None).unwrap();
    let endo = surface(&set, "LV_ENDO");
    let epi = surface(&set, "LV_EPI");
    assert_eq!((endo.len(), epi.len()), (3, 3));
    // Pixel (x, y) = position + x * 1.25 along the rows + y * 1.25 along the columns.
    for (k, c) in endo.iter().enumerate() {
        assert_eq!(c.id, format!("s{:02}_icontour", k + 1));
        let first = c.points().next().unwrap();
        let want = v3(-50.0 + 56.0 * 1.25, -60.0 + 48.0 * 1.25, 8.0 * k as f64);
        assert!((first - want).norm() < 1e-9, "{k}: {first:?} vs {want:?}");
        let centre = v3(-50.0 + 40.0 * 1.25, -60.0 + 48.0 * 1.25, 0.0);
        for p in c.points() {
            let d = (p.xy() - centre.xy()).norm();
            assert!((d - 20.0).abs() < 0.01, "{k}: radius {d} mm, not 16 px");
        }
        assert_eq!(c.points().count(), 24);
    }
    // The long-axis series numbered 1-4 holds one contour number, the stack all: the stack's
    // images are the ones (or the first slice's ring would lie in the long-axis plane).
    assert!(endo[0].points().all(|p| p.z.abs() < 1e-9));
    assert!(set.warnings[0].starts_with(NOTE), "{:?}", set.warnings);
    assert!(
        set.warnings[0].contains("16 DICOM images: contours on 6 of them, in 3 cine slices"),
        "{}",
        set.warnings[0]
    );
    assert!(
        set.warnings
            .iter()
            .any(|w| w == "contours of type p1contour skipped: papillary muscles"),
        "{:?}",
        set.warnings
    );
    let frames = set.time_frames.as_ref().unwrap();
    assert_eq!(
        (frames.frames.clone(), frames.read.clone()),
        (
            vec!["0".to_string(), "2".to_string()],
            vec!["0".to_string()]
        )
    );
}

#[test]
fn a_frame_is_chosen_by_its_place_in_the_cine_slice() {
    let set = read(&study(false), Some("2")).unwrap();
    let endo = surface(&set, "LV_ENDO");
    assert_eq!(endo.len(), 3);
    assert!(
        surface(&set, "LV_EPI").is_empty(),
        "the epicardium is drawn at frame 0 only"
    );
    let centre = v3(-50.0 + 40.0 * 1.25, -60.0 + 48.0 * 1.25, 0.0);
    for c in endo {
        for p in c.points() {
            let d = (p.xy() - centre.xy()).norm();
            assert!((d - 11.0 * 1.25).abs() < 0.01, "radius {d} mm, not 11 px");
        }
    }
    let e = read(&study(false), Some("3")).unwrap_err().to_string();
    assert!(e.contains("frame"), "{e}");
}

#[test]
fn images_named_otherwise_are_matched_by_instance_number() {
    let files: Vec<(String, Vec<u8>)> = study(false)
        .into_iter()
        .enumerate()
        .map(|(i, (n, b))| match n.ends_with(".dcm") {
            true => (format!("series/{}", 9000 + i), b),
            false => (n, b),
        })
        .collect();
    let by_number = read(&files, None).unwrap();
    let by_name = read(&study(false), None).unwrap();
    let points = |s: &ContourSet| -> Vec<Vec3> {
        s.contours
            .iter()
            .flat_map(|c| c.points().copied().collect::<Vec<_>>())
            .collect()
    };
    assert_eq!(points(&by_number), points(&by_name));
}

fn refusal(files: &[(String, Vec<u8>)]) -> String {
    read(files, None).unwrap_err().to_string()
}

#[test]
fn what_cannot_be_read_is_said() {
    // Contours alone.
    let alone = contour_files();
    let e = refusal(&alone);
    assert!(e.contains(NEEDS_IMAGES), "{e}");
    let one = &alone[0];
    let e = read_contours_with(&one.0, &one.1, &ContourOptions::default()).unwrap_err();
    assert!(e.to_string().contains(NEEDS_IMAGES), "{e}");
    // Images of other numbers.
    let mut files = contour_files();
    files.extend((0..4).map(|f| stack_image(7, f)));
    let e = refusal(&files);
    assert!(e.contains("none of the 4 DICOM images given is numbered as the contour files' images (0001, 0003, 0005, 0007, ...)"), "{e}");
    // Only a long-axis series numbered 1-4: it holds 2 of the 6 images.
    let mut files = contour_files();
    files.extend((0..4).map(lax_image));
    let e = refusal(&files);
    assert!(e.contains("the DICOM images given hold only 2 of the 6 images the contour files were drawn on (0001, 0003, 0005, 0007, ..., in IM-0004-*)"), "{e}");
    // Two series alike.
    let mut files = study(false);
    for k in 0..3 {
        for f in 0..4 {
            let (n, b) = stack_image(k, f);
            let b = String::from_utf8_lossy(&b).replace("1.2.840.9.", "1.2.840.8.");
            files.push((n.replace("IM-0003", "IM-0005"), b.into_bytes()));
        }
    }
    let e = refusal(&files);
    assert!(
        e.contains("two series alike (IM-0003-* and IM-0005-*)"),
        "{e}"
    );
    // One case's file twice.
    let mut files = study(false);
    files.push(("other/IM-0001-0001-icontour-manual.txt".into(), circle(5.0)));
    let e = refusal(&files);
    assert!(
        e.contains("IM-0001-0001-icontour-manual.txt is given twice"),
        "{e}"
    );
    // A line that is not two numbers, an empty file: the file and the line.
    for (text, want) in [
        (&b"40 48\n41 48 3\n"[..], "IM-0001-0005-icontour-manual.txt, line 2: expected two numbers (x y, in pixels), found 3 fields"),
        (&b"40 48\nnan 48\n"[..], "IM-0001-0005-icontour-manual.txt, line 2: x: \"nan\" is not a finite number"),
        (&b"\n\n"[..], "IM-0001-0005-icontour-manual.txt: empty file"),
    ] {
        let mut files = study(false);
        let at = files.iter().position(|(n, _)| n == "IM-0001-0005-icontour-manual.txt").unwrap();
        files[at].1 = text.to_vec();
        let e = refusal(&files);
        assert!(e.contains(want), "{e}");
    }
}

#[test]
fn contours_without_their_image_and_other_files_are_set_aside_with_a_warning() {
    let mut files = study(false);
    files.push(("IM-0001-0077-icontour-manual.txt".into(), circle(9.0)));
    files.push(("README.txt".into(), b"Sunnybrook Cardiac Data".to_vec()));
    let set = read(&files, None).unwrap();
    assert_eq!(surface(&set, "LV_ENDO").len(), 3);
    let said = set.warnings.join("\n");
    assert!(said.contains("1 contour file skipped: no image of their number in IM-0003-* (IM-0001-0077-icontour-manual.txt)"), "{said}");
    assert!(
        said.contains("1 file set aside: not DICOM (README.txt)"),
        "{said}"
    );
}

#[test]
fn mutated_contour_files_and_images_never_panic() {
    let base = study(false);
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n.max(1) as u64) as usize
    };
    let mut read_ok = 0;
    for _ in 0..400 {
        let mut files = base.clone();
        for _ in 0..1 + next(3) {
            let f = next(files.len());
            let target = &mut files[f].1;
            let at = next(target.len());
            match next(4) {
                0 => target[at] = next(256) as u8,
                1 => target.truncate(at),
                2 => target.insert(at, b"-9e999 \n,.\0"[next(11)]),
                _ => {
                    let name = &mut files[f].0;
                    let at = next(name.len());
                    name.insert(at, ['-', '0', 'x', '/'][next(4)]);
                }
            }
        }
        read_ok += usize::from(read(&files, None).is_ok());
    }
    assert!(read_ok > 0 && read_ok < 400, "{read_ok}");
}

#[test]
fn the_frame_read_by_default_is_the_one_in_which_the_most_surfaces_are_drawn() {
    // End-diastole last in the cycle (a case's frame 3 of 4, as some of the data's are): both
    // surfaces there, the endocardium alone at frame 1 (end-systole). Frame 3 is read, not 1.
    let mut files = Vec::new();
    for k in 0..3 {
        let n = k * 4 + 1;
        files.push((
            format!("IM-0001-{:04}-icontour-manual.txt", n + 1),
            circle(11.0),
        ));
        files.push((
            format!("IM-0001-{:04}-icontour-manual.txt", n + 3),
            circle(16.0),
        ));
        files.push((
            format!("IM-0001-{:04}-ocontour-manual.txt", n + 3),
            circle(22.0),
        ));
        files.extend((0..4).map(|f| stack_image(k, f)));
    }
    let set = read(&files, None).unwrap();
    assert_eq!(
        (
            surface(&set, "LV_ENDO").len(),
            surface(&set, "LV_EPI").len()
        ),
        (3, 3)
    );
    let frames = set.time_frames.as_ref().unwrap();
    assert_eq!(frames.read, vec!["3".to_string()]);
    assert_eq!(frames.frames, vec!["1".to_string(), "3".to_string()]);
    let centre = v3(-50.0 + 40.0 * 1.25, -60.0 + 48.0 * 1.25, 0.0);
    for c in surface(&set, "LV_ENDO") {
        let d = (c.points().next().unwrap().xy() - centre.xy()).norm();
        assert!(
            (d - 16.0 * 1.25).abs() < 0.01,
            "radius {d} mm: frame 1's ring read"
        );
    }
    // Asked for, frame 1 is read as before.
    let es = read(&files, Some("1")).unwrap();
    assert_eq!(
        (surface(&es, "LV_ENDO").len(), surface(&es, "LV_EPI").len()),
        (3, 0)
    );
    // Frames of as many surfaces tie, whatever their curve counts: the earliest, frame 1, where
    // a slice has it (two of three here), else the slice's own.
    let endo: Vec<(String, Vec<u8>)> = files
        .into_iter()
        .filter(|(n, _)| !n.contains("ocontour") && n != "IM-0001-0010-icontour-manual.txt")
        .collect();
    let set = read(&endo, None).unwrap();
    let radii: Vec<f64> = surface(&set, "LV_ENDO")
        .iter()
        .map(|c| (c.points().next().unwrap().xy() - centre.xy()).norm() / 1.25)
        .collect();
    assert!(
        (radii[0] - 11.0).abs() < 0.01 && (radii[1] - 11.0).abs() < 0.01,
        "{radii:?}"
    );
    assert!((radii[2] - 16.0).abs() < 0.01, "{radii:?}");
}
