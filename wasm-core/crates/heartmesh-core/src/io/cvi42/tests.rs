use super::*;
use crate::geometry::v3;
use crate::io::dicom_image::{image_geometry, ImageGeometry, NoGeometry};
use crate::io::test_images::*;
use crate::io::{read_contours_with, read_study, ContourOptions};

/// An image's contours: (type, points in subpixels).
type Drawn<'a> = [(&'a str, &'a [[i64; 2]])];

fn workspace(images: &[(&str, &Drawn)], sub: &str) -> String {
    let mut x = String::from(
        "<?xml version=\"1.0\"?>\n<Hash:root xmlns:Hash=\"http://www.circlecvi.com/cvi42/Workspace/Hash/\" \
         xmlns:Point=\"http://www.circlecvi.com/cvi42/Workspace/Point/\" \
         xmlns:List=\"http://www.circlecvi.com/cvi42/Workspace/List/\">\
         <Hash:item Hash:key=\"ImageStates\">",
    );
    for (uid, contours) in images {
        x += &format!("<Hash:item Hash:key=\"{uid}\"><Hash:item Hash:key=\"Contours\">");
        for (kind, points) in *contours {
            x += &format!(
                "<Hash:item Hash:key=\"{kind}\"><Hash:item Hash:key=\"SubpixelResolution\">{sub}\
                 </Hash:item><List:item Hash:key=\"Points\">"
            );
            for [px, py] in *points {
                x += &format!(
                    "<List:item><Point:x>{px}</Point:x><Point:y>{py}</Point:y></List:item>"
                );
            }
            x += "</List:item></Hash:item>";
        }
        x += "</Hash:item></Hash:item>";
    }
    x + "</Hash:item></Hash:root>"
}

/// A square of 16 points, 8 pixels a side, at subpixel resolution 4.
fn square() -> Vec<[i64; 2]> {
    let mut out = Vec::new();
    for k in 0..4 {
        out.push([4 * (10 + 2 * k), 40]);
    }
    for k in 0..4 {
        out.push([4 * 18, 4 * (10 + 2 * k)]);
    }
    for k in 0..4 {
        out.push([4 * (18 - 2 * k), 4 * 18]);
    }
    for k in 0..4 {
        out.push([40, 4 * (18 - 2 * k)]);
    }
    out
}

fn read(wsx: &str, images: &[(&str, Vec<u8>)], frame: Option<&str>) -> Result<ContourSet> {
    let views: Vec<(&str, &[u8])> = images.iter().map(|(n, b)| (*n, b.as_slice())).collect();
    let frame = frame.and_then(FrameChoice::new);
    read_contours_with(
        "Contours.cvi42wsx",
        wsx.as_bytes(),
        &ContourOptions {
            views: &views,
            frame,
            ..ContourOptions::default()
        },
    )
}

#[test]
fn cvi42_types_map_to_the_four_surfaces_and_the_rest_is_named() {
    for (kind, surface) in [
        ("saendocardialContour", "LV_ENDO"),
        ("saepicardialContour", "LV_EPI"),
        ("sarvendocardialContour", "RV_ENDO"),
        ("sarvepicardialContour", "RV_EPI"),
        ("laendocardialContour", "LV_ENDO"),
        ("larvepicardialContour", "RV_EPI"),
        ("saendocardialOpenContour", "LV_ENDO"),
    ] {
        assert_eq!(surface_of(kind), Ok(surface), "{kind}");
    }
    assert_eq!(
        surface_of("saPapMuscContour"),
        Err("papillary muscles or trabeculae")
    );
    assert_eq!(
        surface_of("saReferencePoint"),
        Err("reference points and landmarks")
    );
    assert_eq!(landmark_of("sacardialRefPoint"), Some("RV_INSERT_ANTERIOR"));
    assert_eq!(landmark_of("saendocardialContour"), None);
    assert_eq!(surface_of("lalaContour"), Err("atria"));
}

#[test]
fn pixels_become_patient_millimetres_on_the_image_plane() {
    let wsx = workspace(&[("1.2.3.1", &[("saendocardialContour", &square())])], "4");
    let set = read(&wsx, &[("a.dcm", dicom(&oblique("1.2.3.1", 0.0)))], None).unwrap();
    let c = &set.contours[0];
    assert_eq!(c.surface.as_deref(), Some("LV_ENDO"));
    assert_eq!(c.id, "s01_saendocardialContour");
    let ring = &c.pieces[0];
    assert!(ring.closed, "a closed cvi42 contour is a ring");
    assert_eq!(ring.points.len(), 16);
    // Pixel (column 10, row 10): 10 columns of 1.25 mm along the rows, 10 rows of 0.8 mm along
    // the columns, from the first pixel's centre.
    let want = v3(10.0, -20.0, 30.0) + v3(S2, S2, 0.0) * 12.5 + v3(0.0, 0.0, 1.0) * 8.0;
    assert!(
        (ring.points[0] - want).norm() < 1e-9,
        "{:?}",
        ring.points[0]
    );
    // Pixel (18, 18) is 8 columns and 8 rows further.
    let far = want + v3(S2, S2, 0.0) * 10.0 + v3(0.0, 0.0, 1.0) * 6.4;
    assert!((ring.points[8] - far).norm() < 1e-9);
}

#[test]
fn reference_points_are_the_insertions_of_the_frame_read() {
    let sq = square();
    let (ant, inf, other) = ([[40, 40]], [[72, 72]], [[8, 8]]);
    // Frame 0 (trigger 0) with its curve and both reference points; frame 1 with a curve and a
    // reference point of its own; an image of another slice with a reference point and no curve.
    let wsx = workspace(
        &[
            (
                "1.2.3.1",
                &[
                    ("saendocardialContour", &sq[..]),
                    ("sacardialRefPoint", &ant[..]),
                    ("sacardialInferiorRefPoint", &inf[..]),
                    ("laxLvExtentPoints", &other[..]),
                ],
            ),
            (
                "1.2.3.2",
                &[
                    ("saendocardialContour", &sq[..]),
                    ("sacardialRefPoint", &other[..]),
                ],
            ),
            ("1.2.3.9", &[("sacardialRefPoint", &ant[..])]),
        ],
        "4",
    );
    let mut elsewhere = oblique("1.2.3.9", 0.0);
    elsewhere.position = [10.0, -20.0, 60.0];
    elsewhere.series = 6;
    let images = [
        ("f0.dcm", dicom(&oblique("1.2.3.1", 0.0))),
        ("f1.dcm", dicom(&oblique("1.2.3.2", 40.0))),
        ("s2.dcm", dicom(&elsewhere)),
    ];
    let set = read(&wsx, &images, None).unwrap();
    let names: Vec<&str> = set.landmarks.iter().map(|l| l.0.as_str()).collect();
    assert_eq!(
        names,
        ["RV_INSERT_ANTERIOR", "RV_INSERT_INFERIOR", "LAX_LV_EXTENT"]
    );
    // Pixel (10, 10) of the oblique plane, as the curve's first point.
    let want = v3(10.0, -20.0, 30.0) + v3(S2, S2, 0.0) * 12.5 + v3(0.0, 0.0, 1.0) * 8.0;
    assert!((set.landmarks[0].1 - want).norm() < 1e-9);
    assert!(
        !set.warnings.iter().any(|w| w.contains("RefPoint")),
        "{:?}",
        set.warnings
    );
    // Curves only count in the note: two frames of one slice (not the third image's point).
    assert!(
        set.warnings
            .iter()
            .any(|w| w.contains("contours on 2 of them, in 1 cine slice")),
        "{:?}",
        set.warnings
    );
    // Frame 1: its own reference point only.
    let one = read(&wsx, &images, Some("1")).unwrap();
    assert_eq!(one.landmarks.len(), 1);
    let p = v3(10.0, -20.0, 30.0) + v3(S2, S2, 0.0) * 2.5 + v3(0.0, 0.0, 1.0) * 1.6;
    assert!((one.landmarks[0].1 - p).norm() < 1e-9);
    // Reference points alone make no surface.
    let bare = workspace(&[("1.2.3.1", &[("sacardialRefPoint", &ant[..])])], "4");
    let e = read(&bare, &images, None).unwrap_err().to_string();
    assert!(e.contains("no contour of a ventricular surface"), "{e}");
}

#[test]
fn an_image_kept_under_two_study_maps_is_read_once() {
    let one = workspace(&[("1.2.3.1", &[("saendocardialContour", &square())])], "4");
    let inner = &one[one.find("<Hash:item Hash:key=\"ImageStates\">").unwrap()
        ..one.rfind("</Hash:root>").unwrap()];
    let two = one.replace(inner, &format!("<Hash:item Hash:key=\"StudyMapStates\"><List:item>{inner}</List:item><List:item>{inner}</List:item></Hash:item>"));
    let set = read(&two, &[("a.dcm", dicom(&oblique("1.2.3.1", 0.0)))], None).unwrap();
    assert_eq!(set.contours.len(), 1);
    assert_eq!(set.contours[0].pieces.len(), 1);
    assert!(
        set.warnings
            .iter()
            .any(|w| w.starts_with("1 contour stored again")),
        "{:?}",
        set.warnings
    );
}

#[test]
fn open_types_stay_open_and_other_types_are_skipped_with_a_warning() {
    let sq = square();
    let wsx = workspace(
        &[(
            "1.2.3.1",
            &[
                ("saendocardialOpenContour", &sq[..]),
                ("saPapMuscContour", &sq[..4]),
            ],
        )],
        "4",
    );
    let set = read(&wsx, &[("a.dcm", dicom(&oblique("1.2.3.1", 0.0)))], None).unwrap();
    assert_eq!(set.contours.len(), 1);
    assert!(!set.contours[0].pieces[0].closed);
    assert!(
        set.warnings
            .iter()
            .any(|w| w.contains("saPapMuscContour skipped: papillary")),
        "{:?}",
        set.warnings
    );
}

#[test]
fn frames_are_places_in_the_cine_slice_by_trigger_time() {
    let sq = square();
    let small: Vec<[i64; 2]> = sq.iter().map(|[x, y]| [x / 2, y / 2]).collect();
    // Frame 1 of the slice (trigger 40 ms) listed first in the workspace; frame 0's image has no
    // contour but still counts (an image of the cine without one).
    let wsx = workspace(
        &[
            ("1.2.3.2", &[("saendocardialContour", &small[..])]),
            ("1.2.3.3", &[("saendocardialContour", &sq[..])]),
        ],
        "4",
    );
    let images = [
        ("f0.dcm", dicom(&oblique("1.2.3.1", 0.0))),
        ("f2.dcm", dicom(&oblique("1.2.3.3", 80.0))),
        ("f1.dcm", dicom(&oblique("1.2.3.2", 40.0))),
    ];
    let set = read(&wsx, &images, None).unwrap();
    let tf = set.time_frames.as_ref().unwrap();
    assert_eq!(tf.frames, ["1", "2"]);
    assert_eq!(tf.read, ["1"]);
    assert_eq!(set.contours[0].pieces[0].points.len(), 16);
    // The frame read is the smaller square (pixel 5..9): 4 columns of 1.25 mm across.
    let p = &set.contours[0].pieces[0].points;
    assert!(((p[4] - p[0]).norm() - 5.0).abs() < 1e-9);
    assert!(set.warnings.iter().any(|w| w.contains("frame 1 read")));
    let two = read(&wsx, &images, Some("2")).unwrap();
    let p = &two.contours[0].pieces[0].points;
    assert!(((p[4] - p[0]).norm() - 10.0).abs() < 1e-9);
    let none = read(&wsx, &images, Some("7")).unwrap_err().to_string();
    assert!(none.contains("no contour points in frame 7"), "{none}");
}

#[test]
fn images_missing_or_unusable_are_said_and_a_workspace_alone_is_refused() {
    let sq = square();
    let wsx = workspace(
        &[
            ("1.2.3.1", &[("saendocardialContour", &sq[..])]),
            ("9.9.9", &[("saepicardialContour", &sq[..])]),
        ],
        "4",
    );
    let mut no_plane = dicom(&oblique("1.2.3.7", 0.0));
    // Orientation twice the same direction: no plane.
    no_plane = String::from_utf8_lossy(&no_plane)
        .replace("0\\0\\1", "1\\1\\0")
        .into_bytes();
    let images = [
        ("a.dcm", dicom(&oblique("1.2.3.1", 0.0))),
        ("notes.txt", b"scan notes".to_vec()),
        ("b.dcm", no_plane),
    ];
    let set = read(&wsx, &images, None).unwrap();
    assert_eq!(set.contours.len(), 1);
    let all = set.warnings.join("\n");
    assert!(all.contains("contours on 1 image skipped"), "{all}");
    assert!(all.contains("first UID 9.9.9"), "{all}");
    assert!(
        all.contains(
            "workspace read with 1 DICOM image: contours on 1 of them, in 1 cine slice; 2 other \
             files given with it set aside"
        ),
        "{all}"
    );
    assert!(crate::io::is_reading_note(&set.warnings[0]), "{all}");
    assert!(
        all.contains("1 file set aside: not DICOM (notes.txt)"),
        "{all}"
    );
    assert!(
        all.contains("1 DICOM file set aside: no image plane (b.dcm"),
        "{all}"
    );

    let alone = read(&wsx, &[], None).unwrap_err().to_string();
    assert!(alone.contains("together with the DICOM images"), "{alone}");
    let elsewhere = read(&wsx, &[("c.dcm", dicom(&oblique("4.4", 0.0)))], None)
        .unwrap_err()
        .to_string();
    assert!(
        elsewhere.contains("none of the 2 images its ventricular contours were drawn on"),
        "{elsewhere}"
    );
    let strays = read(&wsx, &[("x.txt", b"hello".to_vec())], None)
        .unwrap_err()
        .to_string();
    assert!(
        strays.contains(
            "none of the 1 files given with it is a DICOM image with an image plane (x.txt)"
        ),
        "{strays}"
    );
    let broken = read(
        "<Hash:root xmlns:Hash=\"http://www.circlecvi.com/cvi42/Workspace/Hash/\">",
        &images,
        None,
    )
    .unwrap_err()
    .to_string();
    assert!(broken.contains("not valid XML"), "{broken}");
}

#[test]
fn a_header_slice_is_enough_and_a_study_is_the_workspace_with_its_images() {
    let wsx = workspace(&[("1.2.3.1", &[("saendocardialContour", &square())])], "4");
    let whole = dicom(&oblique("1.2.3.1", 0.0));
    let full = image_geometry(&whole).unwrap();
    // Cut inside the pixel data, then right after the spacing: the same plane.
    for cut in [whole.len() - 1000, whole.len() - 4096 - 12] {
        assert_eq!(image_geometry(&whole[..cut]).unwrap(), full);
    }
    assert!(matches!(
        image_geometry(&whole[..200]),
        Err(NoGeometry::Missing { .. })
    ));
    let files: [(&str, &[u8]); 2] = [("IM_1.dcm", &whole[..600]), ("ws.cvi42wsx", wsx.as_bytes())];
    let (stack, set) = read_study(&files, &ContourOptions::default()).unwrap();
    assert_eq!(stack, 1);
    assert_eq!(set.contours.len(), 1);
    let two: [(&str, &[u8]); 3] = [
        ("a.cvi42wsx", wsx.as_bytes()),
        ("b.cvi42wsx", wsx.as_bytes()),
        ("IM_1.dcm", &whole),
    ];
    let e = read_study(&two, &ContourOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("a.cvi42wsx and b.cvi42wsx are both cvi42 workspaces"),
        "{e}"
    );
}

#[test]
fn mutated_workspaces_and_images_never_panic() {
    let wsx = workspace(
        &[
            ("1.2.3.1", &[("saendocardialContour", &square())]),
            ("1.2.3.2", &[("laendocardialOpenContour", &square()[..9])]),
        ],
        "4",
    );
    let image = dicom(&oblique("1.2.3.1", 0.0));
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n as u64) as usize
    };
    let mut read_ok = 0;
    for round in 0..400 {
        let (mut w, mut d) = (wsx.clone().into_bytes(), image.clone());
        let target = if round % 2 == 0 { &mut w } else { &mut d };
        for _ in 0..1 + next(4) {
            let at = next(target.len());
            match next(3) {
                0 => target[at] = next(256) as u8,
                1 => target.truncate(at.max(1)),
                _ => target.insert(at, b"-9e999<>\\"[next(9)]),
            }
        }
        let views: [(&str, &[u8]); 1] = [("a.dcm", &d)];
        let r = read_cvi42(&w, &views, None);
        read_ok += usize::from(r.is_ok());
    }
    // Some mutations leave the files readable (a digit changed), most do not: both happen.
    assert!(read_ok > 0 && read_ok < 400, "{read_ok}");
}

/// One implicit VR little endian element (tag, 32-bit length, value).
fn implicit(tag: (u16, u16), value: &[u8]) -> Vec<u8> {
    let mut v = value.to_vec();
    if v.len() % 2 == 1 {
        v.push(b' ');
    }
    let mut out = Vec::new();
    out.extend_from_slice(&tag.0.to_le_bytes());
    out.extend_from_slice(&tag.1.to_le_bytes());
    out.extend_from_slice(&(v.len() as u32).to_le_bytes());
    out.extend_from_slice(&v);
    out
}

#[test]
fn implicit_vr_images_with_a_private_sequence_are_read() {
    // A bare implicit VR data set (no preamble), as older exporters write, with a private
    // sequence of undefined length (a vendor's header) between the plane's elements and the pixels.
    let mut seq = Vec::new();
    seq.extend_from_slice(&0x0029u16.to_le_bytes());
    seq.extend_from_slice(&0x1010u16.to_le_bytes());
    seq.extend_from_slice(&u32::MAX.to_le_bytes());
    seq.extend_from_slice(&[0xFE, 0xFF, 0x00, 0xE0]);
    seq.extend_from_slice(&u32::MAX.to_le_bytes());
    seq.extend(implicit((0x0029, 0x0010), b"SIEMENS CSA"));
    seq.extend_from_slice(&[0xFE, 0xFF, 0x0D, 0xE0, 0, 0, 0, 0]);
    seq.extend_from_slice(&[0xFE, 0xFF, 0xDD, 0xE0, 0, 0, 0, 0]);
    let mut bytes = b"DICM".to_vec();
    bytes.extend(element((2, 0x10), b"UI", b"1.2.840.10008.1.2"));
    bytes.extend(implicit((8, 0x18), b"1.2.3.1"));
    bytes.extend(implicit((0x20, 0x32), b"10\\-20\\30"));
    bytes.extend(implicit((0x20, 0x37), &ds(&[S2, S2, 0.0, 0.0, 0.0, 1.0])));
    bytes.extend(implicit((0x28, 0x30), b"0.8\\1.25"));
    bytes.extend(seq);
    bytes.extend(implicit((0x7FE0, 0x10), &[0u8; 64]));
    let g = image_geometry(&bytes).unwrap();
    assert_eq!(
        g,
        image_geometry(&dicom(&oblique("1.2.3.1", 0.0)))
            .map(|o| ImageGeometry {
                series: None,
                trigger_ms: None,
                ..o
            })
            .unwrap()
    );
    let wsx = workspace(&[("1.2.3.1", &[("saendocardialContour", &square())])], "4");
    let set = read(&wsx, &[("old.dcm", bytes)], None).unwrap();
    let want = v3(10.0, -20.0, 30.0) + v3(S2, S2, 0.0) * 12.5 + v3(0.0, 0.0, 1.0) * 8.0;
    assert!((set.contours[0].pieces[0].points[0] - want).norm() < 1e-9);
}

#[test]
fn an_image_opened_alone_is_refused_as_an_image() {
    let e = crate::io::read_contours("IM_1.dcm", &dicom(&oblique("1.2.3.1", 0.0)))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("this is a DICOM image (modality missing), not contours"),
        "{e}"
    );
    assert!(
        e.contains("a cvi42 workspace together with its images"),
        "{e}"
    );
}
