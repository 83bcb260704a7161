use super::*;
use crate::io::mat::read_mat_frame;
use crate::io::mat::test_files::{
    cell, doubles, empty, file, scalar, singles, small_integers, structs, text, Array,
};

const FIELDS: [&str; 17] = [
    "IM",
    "ImagePosition",
    "ImageOrientation",
    "ResolutionX",
    "ResolutionY",
    "SliceThickness",
    "SliceGap",
    "EDT",
    "EST",
    "ImageViewPlane",
    "Rotated",
    "EndoX",
    "EndoY",
    "EpiX",
    "EpiY",
    "Point",
    "EndoPinX",
];

/// One curve: (frame, slice, (x, y) points), both from 0.
type Curve = (usize, usize, Vec<[f64; 2]>);

struct Stack {
    position: [f64; 3],
    orientation: [f64; 6],
    resolution: [f64; 2],
    thickness: f64,
    gap: f64,
    frames: usize,
    slices: usize,
    edt: f64,
    est: f64,
    view: &'static str,
    rotated: bool,
    endo: Vec<Curve>,
    epi: Vec<Curve>,
    /// (x, y, z, t, label), Segment's values (from 1; t NaN: all frames).
    points: Vec<(f64, f64, f64, f64, &'static str)>,
}

impl Default for Stack {
    fn default() -> Self {
        Stack {
            position: [10.0, 20.0, 30.0],
            orientation: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
            resolution: [1.5, 2.0],
            thickness: 8.0,
            gap: 2.0,
            frames: 4,
            slices: 3,
            edt: 1.0,
            est: 3.0,
            view: "Short-axis",
            rotated: false,
            endo: Vec::new(),
            epi: Vec::new(),
            points: Vec::new(),
        }
    }
}

/// 79 points round (`cx`, `cy`) and the first again, as Segment stores a closed curve.
fn circle(cx: f64, cy: f64, r: f64) -> Vec<[f64; 2]> {
    let mut c: Vec<[f64; 2]> = (0..79)
        .map(|k| {
            let a = k as f64 / 79.0 * std::f64::consts::TAU;
            [cx + r * a.cos(), cy + r * a.sin()]
        })
        .collect();
    c.push(c[0]);
    c
}

/// A curve field pair, 80 x frames x slices, NaN where `curves` draws nothing.
fn curve_arrays(s: &Stack, curves: &[Curve]) -> (Array, Array) {
    if curves.is_empty() {
        return (empty(), empty());
    }
    let n = 80;
    let mut x = vec![f64::NAN; n * s.frames * s.slices];
    let mut y = x.clone();
    for (t, z, pts) in curves {
        for (k, p) in pts.iter().enumerate() {
            x[n * (t + s.frames * z) + k] = p[0];
            y[n * (t + s.frames * z) + k] = p[1];
        }
    }
    let dims = [n, s.frames, s.slices];
    (doubles(&dims, &x), doubles(&dims, &y))
}

fn element(s: &Stack) -> Vec<Array> {
    let (endo_x, endo_y) = curve_arrays(s, &s.endo);
    let (epi_x, epi_y) = curve_arrays(s, &s.epi);
    let row = |f: fn(&(f64, f64, f64, f64, &str)) -> f64| {
        let v: Vec<f64> = s.points.iter().map(f).collect();
        doubles(&[1, v.len()], &v)
    };
    let labels: Vec<Array> = s.points.iter().map(|p| text(p.4)).collect();
    let point = structs(
        &["X", "Y", "Z", "T", "Label"],
        &[vec![
            row(|p| p.0),
            row(|p| p.1),
            row(|p| p.2),
            row(|p| p.3),
            cell(&labels),
        ]],
    );
    vec![
        singles(&[16, 16, s.frames, s.slices], 0.5),
        doubles(&[1, 3], &s.position),
        doubles(&[1, 6], &s.orientation),
        scalar(s.resolution[0]),
        scalar(s.resolution[1]),
        scalar(s.thickness),
        scalar(s.gap),
        small_integers(&[1, 1], &[s.edt as u8]),
        scalar(s.est),
        text(s.view),
        small_integers(&[1, 1], &[u8::from(s.rotated)]),
        endo_x,
        endo_y,
        epi_x,
        epi_y,
        point,
        cell(&[]),
    ]
}

fn study(stacks: &[Stack]) -> Vec<u8> {
    let elements: Vec<Vec<Array>> = stacks.iter().map(element).collect();
    file(
        &[
            ("preview", small_integers(&[2, 2], &[1, 2, 3, 4])),
            ("info", structs(&["Name"], &[vec![text("Test")]])),
            ("im", empty()),
            ("setstruct", structs(&FIELDS, &elements)),
        ],
        true,
    )
}

fn read(bytes: &[u8], frame: Option<&str>) -> Result<ContourSet> {
    let frame = frame.map(|f| FrameChoice::new(f).unwrap());
    read_mat_frame(bytes, frame.as_ref())
}

/// A short-axis stack with an endocardium on every slice at frames 1-4 (radius growing with the
/// frame) and an epicardium at frame 1, and a one-slice 4CH view with an endocardium at frame 1.
fn two_stacks() -> Vec<Stack> {
    let mut sax = Stack::default();
    for z in 0..3 {
        for t in 0..4 {
            sax.endo.push((t, z, circle(40.0, 40.0, 8.0 + t as f64)));
        }
        sax.epi.push((0, z, circle(40.0, 40.0, 14.0)));
    }
    let lax = Stack {
        position: [0.0, 20.0, 60.0],
        orientation: [1.0, 0.0, 0.0, 0.0, 0.0, -1.0],
        slices: 1,
        view: "4CH",
        endo: vec![(0, 0, circle(30.0, 40.0, 12.0))],
        ..Stack::default()
    };
    vec![sax, lax]
}

#[test]
fn a_point_lands_where_segments_conversion_puts_it() {
    // x = 3 (row), y = 5 (column) on slice 2: ImagePosition + 2 ResolutionX along
    // ImageOrientation(4:6) + 4 ResolutionY along ImageOrientation(1:3) - 1 (8 + 2) along the normal.
    let mut pts = circle(40.0, 40.0, 6.0);
    pts[0] = [3.0, 5.0];
    pts[79] = [3.0, 5.0];
    let s = Stack {
        orientation: [0.6, 0.8, 0.0, 0.0, 0.0, -1.0],
        endo: vec![(0, 1, pts)],
        ..Stack::default()
    };
    let set = read(&study(&[s]), None).unwrap();
    let p = set.contours[0].pieces[0].points[0];
    // row (0.6, 0.8, 0), column (0, 0, -1), normal row x column = (-0.8, 0.6, 0).
    let want = v3(10.0, 20.0, 30.0) + v3(0.0, 0.0, -1.0) * 3.0 + v3(0.6, 0.8, 0.0) * 8.0
        - v3(-0.8, 0.6, 0.0) * 10.0;
    assert!((p - want).norm() < 1e-9, "{p:?} vs {want:?}");
    assert!(set.contours[0].pieces[0].closed);
    assert_eq!(set.contours[0].pieces[0].points.len(), 79);
}

#[test]
fn each_slice_reads_the_end_diastole_and_frames_are_counted_from_1() {
    let mut stacks = two_stacks();
    // Both stacks' end-diastole at frame 2, so their frames are the same phases.
    (stacks[0].edt, stacks[1].edt) = (2.0, 2.0);
    let bytes = study(&stacks);
    let set = read(&bytes, None).unwrap();
    let tf = set.time_frames.as_ref().unwrap();
    assert_eq!(tf.frames, ["1", "2", "3", "4"]);
    // EDT 2: the SAX endocardium there, no epicardium; the 4CH view, drawn at frame 1 only,
    // keeps that frame (each slice reads one frame, as for cvi42).
    assert_eq!(
        (
            surface_count(&set, "LV_ENDO"),
            surface_count(&set, "LV_EPI")
        ),
        (4, 0)
    );
    let phases = set.warnings.iter().find(|w| w.starts_with(PHASES)).unwrap();
    assert!(
        phases.contains("frame 2, its end-systole frame 3"),
        "{phases}"
    );
    assert!(crate::io::is_reading_note(phases));

    // Frame 1 asked for: both stacks, endo- and epicardium; frame 4: the SAX endocardium only.
    let first = read(&bytes, Some("1")).unwrap();
    let surfaces = surface_count;
    assert_eq!(
        (surfaces(&first, "LV_ENDO"), surfaces(&first, "LV_EPI")),
        (4, 3)
    );
    let last = read(&bytes, Some("4")).unwrap();
    assert_eq!(
        (surfaces(&last, "LV_ENDO"), surfaces(&last, "LV_EPI")),
        (3, 0)
    );
    let note = last.warnings.iter().find(|w| w.starts_with(NOTE)).unwrap();
    assert!(
        note.contains("with 16 images: contours on 13 of them, in 4 cine slices"),
        "{note}"
    );
    assert!(read(&bytes, Some("5")).is_err());
}

#[test]
fn a_view_of_another_length_is_read_in_the_same_phase() {
    // The short-axis stack: 4 frames, ED 1, ES 3. The 4CH view: 8 frames, ED 2, ES 6, its
    // endocardium drawn at those two (12 and 9 pixels round) and an insertion point at ES.
    let mut stacks = two_stacks();
    let lax = &mut stacks[1];
    (lax.frames, lax.edt, lax.est) = (8, 2.0, 6.0);
    lax.endo = vec![
        (1, 0, circle(30.0, 40.0, 12.0)),
        (5, 0, circle(30.0, 40.0, 9.0)),
    ];
    lax.points = vec![(30.0, 40.0, 1.0, 6.0, "RV insertion")];
    let bytes = study(&stacks);
    // The view's curve: the one across the short-axis planes; its height 2 r x 1.5 mm rows.
    let view_height = |set: &ContourSet| {
        let heights: Vec<f64> = set
            .contours
            .iter()
            .map(|c| {
                let z = c.pieces[0].points.iter().map(|p| p.z);
                z.clone().fold(f64::MIN, f64::max) - z.fold(f64::MAX, f64::min)
            })
            .filter(|&h| h > 1.0)
            .collect();
        assert!(heights.len() <= 1, "{heights:?}");
        heights.first().copied()
    };
    let ed = read(&bytes, None).unwrap();
    let h = view_height(&ed).unwrap();
    assert!((h - 36.0).abs() < 0.1, "{h}");
    assert!(ed.landmarks.is_empty());
    let note = warning(&ed, MATCHED);
    assert_eq!(
        note,
        "Segment study's frames matched by cardiac phase: stack 2 (4CH)'s 8 frames to stack 1 \
         (Short-axis)'s 4 (end-diastole: its frame 2 = frame 1; end-systole: its frame 6 = frame 3)"
    );
    assert!(crate::io::is_reading_note(note));
    // Frame 3, the short axis's end-systole: the view's frame 6 and its point.
    let es = read(&bytes, Some("3")).unwrap();
    let h = view_height(&es).unwrap();
    assert!((h - 27.0).abs() < 0.1, "{h}");
    assert_eq!(es.landmarks.len(), 1);
    // Frame 2 is the view's frame 4, not drawn: the short axis alone.
    let two = read(&bytes, Some("2")).unwrap();
    assert_eq!(view_height(&two), None);
    assert_eq!(surface_count(&two, "LV_ENDO"), 3);
    assert_eq!(
        ed.time_frames.as_ref().unwrap().frames,
        ["1", "2", "3", "4"]
    );
}

#[test]
fn without_an_end_diastole_each_slice_reads_its_most_drawn_frame() {
    let mut stacks = two_stacks();
    stacks[0].edt = 0.0; // not a frame
    let set = read(&study(&stacks), None).unwrap();
    assert_eq!(surface_count(&set, "LV_EPI"), 3);
    assert!(!set.warnings.iter().any(|w| w.starts_with(PHASES)));
}

#[test]
fn rv_insertions_become_landmarks_of_the_frame_read() {
    let mut stacks = two_stacks();
    stacks[0].points = vec![
        (30.0, 40.0, 2.0, 1.0, "RV insertion"),
        (50.0, 40.0, 2.0, f64::NAN, "P2"),
        (45.0, 45.0, 3.0, 1.0, "RV insertion Anterior"),
        (35.0, 35.0, 3.0, 2.0, "RV insertion Inferior"),
        (40.0, 40.0, 1.0, 1.0, "P7"),
        (40.0, 40.0, 9.0, 1.0, "RV insertion"),
    ];
    let set = read(&study(&stacks), None).unwrap();
    let names: Vec<&str> = set.landmarks.iter().map(|l| l.0.as_str()).collect();
    // Frame 1 read: the two on slice 2 and the anterior one of slice 3 (the inferior one is at
    // frame 2, P7 is no insertion, slice 9 does not exist).
    assert_eq!(names, ["RV_INSERT", "RV_INSERT", "RV_INSERT_ANTERIOR"]);
    let two = read(&study(&stacks), Some("2")).unwrap();
    let names: Vec<&str> = two.landmarks.iter().map(|l| l.0.as_str()).collect();
    assert_eq!(names, ["RV_INSERT", "RV_INSERT_INFERIOR"]);
}

#[test]
fn rotated_stacks_and_stacks_without_curves_are_left_out() {
    let mut stacks = two_stacks();
    stacks[1].rotated = true;
    stacks.push(Stack {
        view: "Scout",
        ..Stack::default()
    });
    let set = read(&study(&stacks), Some("1")).unwrap();
    assert_eq!(set.contours.len(), 6);
    let w = warning(&set, "rotated");
    assert!(
        w.starts_with("stack 2 (4CH): a rotated (radial) stack"),
        "{w}"
    );
}

#[test]
fn refusals_name_the_stack_and_the_problem() {
    let refusal = |stacks: &[Stack]| read(&study(stacks), None).unwrap_err().to_string();
    let e = refusal(&[Stack::default(), Stack::default()]);
    assert!(
        e.contains("none of its 2 image stacks has an LV or RV contour"),
        "{e}"
    );
    let mut s = two_stacks();
    s[0].orientation = [1.0, 0.0, 0.0, 1.0, 0.0, 0.0];
    let e = refusal(&s);
    assert!(
        e.contains(
            "stack 1 (Short-axis): ImageOrientation is not two perpendicular unit directions"
        ),
        "{e}"
    );
    let mut s = two_stacks();
    s[0].resolution[1] = 0.0;
    assert!(refusal(&s).contains("ResolutionY is 0 (a pixel size in mm, above 0)"));
    let mut s = two_stacks();
    (s[0].thickness, s[0].gap) = (0.0, 0.0);
    assert!(refusal(&s).contains("3 slices but SliceThickness + SliceGap is 0 mm"));
    // X and Y of different sizes.
    let mut stacks = two_stacks();
    stacks[0].epi.clear();
    let mut e = element(&stacks[0]);
    e[13] = doubles(&[80, 4, 3], &vec![1.0; 960]);
    e[14] = doubles(&[80, 4, 2], &vec![1.0; 640]);
    let bytes = file(&[("setstruct", structs(&FIELDS, &[e]))], false);
    let e = read(&bytes, None).unwrap_err().to_string();
    assert!(
        e.contains("EpiX is [80, 4, 3] but EpiY is [80, 4, 2]"),
        "{e}"
    );
}

#[test]
fn the_image_is_skipped_and_any_damage_is_an_error_not_a_panic() {
    let bytes = study(&two_stacks());
    let vars = crate::io::mat::read_variables(
        &bytes,
        crate::io::mat::Limits {
            kept_values: 1000,
            ..Default::default()
        },
    )
    .unwrap();
    let set = &vars.iter().find(|v| v.name == "setstruct").unwrap().value;
    assert!(
        matches!(set.field(0, "IM"), Some(Value::Skipped { dims, .. }) if dims == &[16, 16, 4, 3])
    );
    assert!(read_segment(&vars, None).is_ok());
    // Truncated anywhere, or a byte changed, in the uncompressed form (compressed damage is
    // the inflater's to find).
    let elements: Vec<Vec<Array>> = two_stacks().iter().map(element).collect();
    let plain = file(&[("setstruct", structs(&FIELDS, &elements))], false);
    assert!(read(&plain, None).is_ok());
    for cut in (0..plain.len()).step_by(7) {
        let _ = read(&plain[..cut], None);
    }
    let mut seed = 12345u64;
    for _ in 0..400 {
        let mut m = plain.clone();
        for _ in 0..4 {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let at = (seed >> 33) as usize % m.len();
            m[at] = (seed >> 20) as u8;
        }
        let _ = read(&m, None);
        let _ = read(&m, Some("2"));
    }
    for cut in (0..bytes.len()).step_by(11) {
        let _ = read(&bytes[..cut], None);
    }
}

#[test]
fn a_second_stack_on_the_same_planes_is_left_out_and_one_adding_planes_is_read() {
    // Late enhancement: one frame, the cine stack's planes shifted 1 mm, its own curves.
    let mut stacks = two_stacks();
    let mut lge = Stack {
        position: [10.0, 20.0, 29.0],
        frames: 1,
        view: "Short-axis",
        ..Stack::default()
    };
    for z in 0..3 {
        lge.endo.push((0, z, circle(40.0, 40.0, 7.0)));
    }
    stacks.push(lge);
    let set = read(&study(&stacks), Some("1")).unwrap();
    assert_eq!(
        surface_count(&set, "LV_ENDO"),
        4,
        "the cine stack's 3 rings and the 4CH view's curve"
    );
    let w = warning(&set, "not read");
    assert!(
        w.starts_with("stack 3 (Short-axis): its 3 curves not read: its slices repeat those of stack 1 (Short-axis)"),
        "{w}"
    );
    // Basal slices acquired as a stack of their own (30 mm further along the stack): read.
    stacks[2].position = [10.0, 20.0, 30.0 - 30.0];
    let set = read(&study(&stacks), Some("1")).unwrap();
    assert_eq!(surface_count(&set, "LV_ENDO"), 7);
    assert!(!set.warnings.iter().any(|w| w.contains("not read")));
}

/// The reader's warning that holds `part`.
fn warning<'s>(set: &'s ContourSet, part: &str) -> &'s str {
    set.warnings
        .iter()
        .find(|w| w.contains(part))
        .unwrap_or_else(|| panic!("no warning with {part:?}: {:?}", set.warnings))
}

fn surface_count(set: &ContourSet, surface: &str) -> usize {
    set.contours
        .iter()
        .filter(|c| c.surface.as_deref() == Some(surface))
        .count()
}

#[test]
fn a_stack_without_a_plane_is_placed_as_segment_places_it_with_a_warning() {
    let stacks = two_stacks();
    let mut sax = element(&stacks[0]);
    (sax[1], sax[2]) = (empty(), empty());
    let bytes = file(&[("setstruct", structs(&FIELDS, &[sax]))], true);
    let set = read(&bytes, Some("1")).unwrap();
    let w = warning(&set, "no ImagePosition");
    assert!(
        w.starts_with("stack 1 (Short-axis): no ImagePosition or ImageOrientation: placed as Segment places such a stack"),
        "{w}"
    );
    // Row x = 40 + 14 (each epicardium's first point) lies 53 rows of 1.5 mm along y, column 40
    // 39 columns of 2 mm along x; slices 1-3 at z = 0, -10, -20 (8 + 2 mm apart, along -z).
    let mut firsts: Vec<Vec3> = set
        .contours
        .iter()
        .filter(|c| c.surface.as_deref() == Some("LV_EPI"))
        .map(|c| c.pieces[0].points[0])
        .collect();
    firsts.sort_by(|a, b| b.z.total_cmp(&a.z));
    let want = [0.0, -10.0, -20.0].map(|z| v3(78.0, 79.5, z));
    assert_eq!(firsts.len(), 3);
    for (p, q) in firsts.iter().zip(&want) {
        assert!((p - q).norm() < 1e-9, "{p:?} vs {q:?}");
    }
}
