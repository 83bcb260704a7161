//! Cardiac Atlas Project / biv-me guide-point files (`GPFile_*.txt`, see ../shared/data/README.md):
//! `x y z contour-type slice-id weight frame`, tab separated, header optional, plus the optional
//! `SliceInfoFile.txt` that gives each slice's image plane.
//!
//! Contour types map to surfaces (RV endocardium arrives as free wall + septum curves, joined
//! later by the pipeline); landmarks (valves, apex, RV inserts) are kept as named points. One
//! contour per (slice, type), named `s<slice>_<type>` like the canonical CSV files.

use super::builder::ContourBuilder;
use super::frame_choice::FrameChoice;
use super::frames::FrameFilter;
use super::text::{lines, parse_coord, quote};
use crate::contours::ContourSet;
use crate::error::{CoreError, Result};
use crate::geometry::{v3, Vec3};

/// Landmark types: single named points, not curves.
const LANDMARKS: &[&str] = &[
    "MITRAL_VALVE",
    "TRICUSPID_VALVE",
    "AORTA_VALVE",
    "PULMONARY_VALVE",
    "APEX_POINT",
    "RV_INSERT",
];

/// Single points rather than curves: the classic landmarks, and what newer biv-me versions add
/// (synthetic valve rings `*_PHANTOM`, `APEX_ENDO_POINT`/`APEX_EPI_POINT`, long-axis extents
/// `LAX_*_EXTENT`). Kept as named points so they are shown, never fitted.
fn is_landmark(kind: &str) -> bool {
    LANDMARKS.contains(&kind)
        || kind.ends_with("_PHANTOM")
        || kind.ends_with("_EXTENT")
        || (kind.starts_with("APEX_") && kind.ends_with("_POINT"))
}

/// Curve types biv-me writes that are none of the four ventricular surfaces, and what they are:
/// skipped with a warning that says so, rather than "unknown". Points marked removed in biv-me's
/// editor (`REMOVED`, `EXCLUDED`) were dropped on purpose and are skipped without one.
fn not_a_surface(kind: &str) -> Option<&'static str> {
    let base = kind
        .strip_prefix("SAX_")
        .or_else(|| kind.strip_prefix("LAX_"))
        .unwrap_or(kind);
    Some(match base {
        "LA" => "left atrium",
        "RA" => "right atrium",
        "RV_OUTLET" => "RV outflow tract",
        "REMOVED" | "EXCLUDED" => "",
        _ if base.starts_with("OUTLET_") => "RV outflow tract",
        _ => return None,
    })
}

/// Surface of a contour type (without its SAX_/LAX_ prefix).
pub fn surface_of(kind: &str) -> Option<&'static str> {
    Some(match kind {
        "LV_ENDOCARDIAL" => "LV_ENDO",
        "LV_EPICARDIAL" => "LV_EPI",
        "RV_FREEWALL" | "RV_SEPTUM" | "RV_ENDOCARDIAL" => "RV_ENDO",
        "RV_EPICARDIAL" => "RV_EPI",
        _ => return None,
    })
}

/// Column positions; without a header the biv-me order is assumed.
#[derive(Debug, Clone, Copy)]
struct Columns {
    x: usize,
    y: usize,
    z: usize,
    kind: usize,
    slice: Option<usize>,
    frame: Option<usize>,
}

const DEFAULT_COLUMNS: Columns = Columns {
    x: 0,
    y: 1,
    z: 2,
    kind: 3,
    slice: Some(4),
    frame: Some(6),
};

/// True when `text` looks like a guide-point file (used by format detection).
pub fn looks_like_gpfile(text: &str) -> bool {
    let Some((_, first)) = lines(text).find(|(_, l)| !l.trim().is_empty()) else {
        return false;
    };
    let f = split(first);
    let lower = first.to_ascii_lowercase();
    if lower.contains("contour type") || lower.contains("contour_type") {
        return true;
    }
    f.len() >= 4
        && f[..3].iter().all(|v| v.parse::<f64>().is_ok())
        && (f[3].starts_with("SAX_")
            || f[3].starts_with("LAX_")
            || is_landmark(f[3])
            || not_a_surface(f[3]).is_some())
}

/// Tab-separated (header names contain spaces), else comma-separated (a GPFile saved from a
/// spreadsheet or pandas), else whitespace-separated.
fn split(line: &str) -> Vec<&str> {
    if line.contains('\t') {
        line.split('\t').map(str::trim).collect()
    } else if line.contains(',') {
        line.split(',').map(str::trim).collect()
    } else {
        line.split_whitespace().collect()
    }
}

/// Header names as the columns they name: the two-word names (`contour type`, `time frame`,
/// `slice id`) become one again where spaces separate the fields.
fn header_names(fields: &[&str]) -> Vec<String> {
    const TWO_WORDS: &[(&str, &str)] = &[
        ("contour", "type"),
        ("time", "frame"),
        ("slice", "id"),
        ("frame", "id"),
    ];
    let lower: Vec<String> = fields.iter().map(|f| f.to_ascii_lowercase()).collect();
    let mut out = Vec::with_capacity(lower.len());
    let mut i = 0;
    while i < lower.len() {
        match lower.get(i + 1) {
            Some(next) if TWO_WORDS.contains(&(lower[i].as_str(), next.as_str())) => {
                out.push(format!("{} {next}", lower[i]));
                i += 2;
            }
            _ => {
                out.push(lower[i].clone());
                i += 1;
            }
        }
    }
    out
}

fn header_columns(fields: &[&str], line: usize) -> Result<Columns> {
    let names = header_names(fields);
    let find = |w: &[&str]| super::text::find_column(&names, w);
    let need = |w: &[&str]| super::text::need_column(&names, w, line);
    Ok(Columns {
        x: need(&["x"])?,
        y: need(&["y"])?,
        z: need(&["z"])?,
        kind: need(&["contour type", "contour_type", "type"])?,
        slice: find(&[
            "frameid", "frame id", "sliceid", "slice", "slice id", "slice_id",
        ]),
        frame: find(&["time frame", "time_frame", "timeframe", "frame"]),
    })
}

/// Reads a guide-point file. `frame`: keep only rows of that time frame (a GPFile's frames are
/// numbers: `9`, `9.0`); None keeps, for each
/// slice, the first frame that slice has in the file (files normally hold one frame, but a slice
/// may carry another frame number, as in the biv-me example).
pub fn read_gpfile(text: &str, frame: Option<&FrameChoice>) -> Result<ContourSet> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut rows = lines(text)
        .filter(|(_, l)| {
            let t = l.trim_start();
            !t.is_empty() && !t.starts_with('#')
        })
        .peekable();
    let (first_line, first) = *rows
        .peek()
        .ok_or_else(|| CoreError::parse(0, "empty file"))?;
    let ff = split(first);
    let cols = if ff.first().is_some_and(|v| v.parse::<f64>().is_err()) {
        rows.next();
        header_columns(&ff, first_line)?
    } else {
        DEFAULT_COLUMNS
    };
    let needed = cols.x.max(cols.y).max(cols.z).max(cols.kind) + 1;
    let mut b = ContourBuilder::new();
    let mut frames = FrameFilter::new(frame);
    let mut unknown: Vec<(String, usize)> = Vec::new();
    let mut kept = 0usize;
    for (line, row) in rows {
        let f = split(row);
        if f.len() < needed {
            return Err(CoreError::parse(
                line,
                format!(
                    "row has {} fields; at least {needed} needed (x y z type ...)",
                    f.len()
                ),
            ));
        }
        let x = parse_coord(f[cols.x], line, "column \"x\"")?;
        let y = parse_coord(f[cols.y], line, "column \"y\"")?;
        let z = parse_coord(f[cols.z], line, "column \"z\"")?;
        let kind = f[cols.kind];
        let slice = cols.slice.and_then(|i| f.get(i)).copied().unwrap_or("0");
        let slice_id = match slice.parse::<f64>() {
            Ok(v) if v.fract() == 0.0 && (0.0..1e6).contains(&v) => format!("{:02}", v as u32),
            _ => {
                return Err(CoreError::parse(
                    line,
                    format!("slice id {} is not a whole number", quote(slice)),
                ))
            }
        };
        if let Some(fr) = cols.frame.and_then(|i| f.get(i)) {
            parse_coord(fr, line, "column \"time frame\"")?;
            if !frames.keep(&slice_id, fr) {
                continue;
            }
        }
        let p = v3(x, y, z);
        if is_landmark(kind) {
            b.landmark(kind, p, line)?;
            continue;
        }
        let base = kind
            .strip_prefix("SAX_")
            .or_else(|| kind.strip_prefix("LAX_"))
            .unwrap_or(kind);
        match surface_of(base) {
            Some(surface) => {
                b.push(&format!("s{slice_id}_{kind}"), Some(surface), p, line)?;
                kept += 1;
            }
            None => match unknown.iter_mut().find(|(k, _)| k == kind) {
                Some((_, n)) => *n += 1,
                None => unknown.push((kind.to_string(), 1)),
            },
        }
    }
    if kept == 0 {
        if let Some(e) = frames.nothing_in_wanted() {
            return Err(e);
        }
    }
    for w in frames.warnings("slice") {
        b.warn(w);
    }
    for (k, n) in unknown {
        let n = format!("{n} point{}", if n == 1 { "" } else { "s" });
        match not_a_surface(&k) {
            Some("") => {}
            Some(what) => b.warn(format!(
                "{n} of contour type {k} ({what}) skipped: not a ventricular surface"
            )),
            None => b.warn(format!("{n} of unknown contour type {k} skipped")),
        }
    }
    let mut set = b.finish()?;
    set.time_frames = frames.time_frames();
    Ok(set)
}

/// One slice of `SliceInfoFile.txt`: its image plane in patient coordinates (mm).
#[derive(Debug, Clone, PartialEq)]
pub struct SliceInfo {
    pub slice_id: u32,
    pub position: Vec3,
    /// Direction of the image rows and columns (ImageOrientationPatient).
    pub row_dir: Vec3,
    pub col_dir: Vec3,
    pub pixel_spacing: [f64; 2],
}

impl SliceInfo {
    /// Unit normal of the image plane.
    pub fn normal(&self) -> Vec3 {
        self.row_dir.cross(&self.col_dir).normalize()
    }
}

/// Reads `SliceInfoFile.txt` (`<file> sliceID: <id> ImagePositionPatient x y z
/// ImageOrientationPatient r1 r2 r3 c1 c2 c3 PixelSpacing a b`; `frameID:` also accepted).
pub fn read_slice_info(text: &str) -> Result<Vec<SliceInfo>> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut out = Vec::new();
    for (line, row) in lines(text) {
        let f: Vec<&str> = row.split_whitespace().collect();
        if f.is_empty() {
            continue;
        }
        let after = |key: &str, n: usize| -> Result<Vec<f64>> {
            let i = f
                .iter()
                .position(|t| t.eq_ignore_ascii_case(key))
                .ok_or_else(|| CoreError::parse(line, format!("missing {key}")))?;
            (1..=n)
                .map(|k| {
                    let t = f.get(i + k).ok_or_else(|| {
                        CoreError::parse(line, format!("{key} needs {n} numbers"))
                    })?;
                    parse_coord(t, line, key)
                })
                .collect()
        };
        let id_key = f
            .iter()
            .find(|t| t.to_ascii_lowercase().ends_with("id:"))
            .copied()
            .unwrap_or("sliceID:");
        let id = after(id_key, 1)?[0];
        let pos = after("ImagePositionPatient", 3)?;
        let o = after("ImageOrientationPatient", 6)?;
        let ps = after("PixelSpacing", 2).unwrap_or_else(|_| vec![1.0, 1.0]);
        let row_dir = v3(o[0], o[1], o[2]);
        let col_dir = v3(o[3], o[4], o[5]);
        if row_dir.cross(&col_dir).norm() < 1e-6 {
            return Err(CoreError::parse(
                line,
                "ImageOrientationPatient is degenerate",
            ));
        }
        out.push(SliceInfo {
            slice_id: id as u32,
            position: v3(pos[0], pos[1], pos[2]),
            row_dir,
            col_dir,
            pixel_spacing: [ps[0], ps[1]],
        });
    }
    if out.is_empty() {
        return Err(CoreError::parse(0, "no slices in the slice info file"));
    }
    Ok(out)
}

/// Points farther than this from their slice's plane are reported.
const OFF_PLANE_WARN_MM: f64 = 2.0;

/// Checks each contour against its image plane and adds a warning for those lying off it (a
/// sign of a mismatched SliceInfoFile or of through-plane motion correction) and one for slices
/// the file does not list. One line each, however many contours: a SliceInfoFile from another
/// acquisition puts every contour off its plane, and forty warnings bury the one that says why.
pub fn check_slices(set: &mut ContourSet, slices: &[SliceInfo]) {
    let mut missing: Vec<u32> = Vec::new();
    let mut missing_contours = 0usize;
    let mut off: Vec<(&str, u32, f64)> = Vec::new();
    for c in &set.contours {
        let Some(id) =
            c.id.strip_prefix('s')
                .and_then(|r| r.split('_').next())
                .and_then(|s| s.parse::<u32>().ok())
        else {
            continue;
        };
        let Some(s) = slices.iter().find(|s| s.slice_id == id) else {
            missing_contours += 1;
            if !missing.contains(&id) {
                missing.push(id);
            }
            continue;
        };
        let n = s.normal();
        let worst = c
            .points()
            .map(|p| (p - s.position).dot(&n).abs())
            .fold(0.0, f64::max);
        if worst > OFF_PLANE_WARN_MM {
            off.push((&c.id, id, worst));
        }
    }
    let mut warnings = Vec::new();
    match off.as_slice() {
        [] => {}
        [(c, id, worst)] => warnings.push(format!(
            "contour {c}: points lie up to {worst:.1} mm from the image plane of slice {id}"
        )),
        many => {
            let worst = many.iter().map(|o| o.2).fold(0.0, f64::max);
            let named: Vec<&str> = many.iter().take(3).map(|o| o.0).collect();
            let more = if many.len() > 3 { ", ..." } else { "" };
            warnings.push(format!(
                "{} contours lie off the image planes of their slices, up to {worst:.1} mm \
                 ({}{more}); is the slice info file from another acquisition?",
                many.len(),
                named.join(", ")
            ));
        }
    }
    if !missing.is_empty() {
        let ids: Vec<String> = missing.iter().map(u32::to_string).collect();
        let (slice, are) = if ids.len() == 1 {
            ("slice", "is")
        } else {
            ("slices", "are")
        };
        warnings.push(format!(
            "{slice} {} ({missing_contours} contours) {are} not in the slice info file",
            ids.join(", ")
        ));
    }
    set.warnings.extend(warnings);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::csv::read_csv;
    use crate::io::sample;

    fn text(rel: &str) -> String {
        String::from_utf8(sample(rel)).unwrap()
    }

    /// Same contours, pieces and points (to the canonical files' 4 decimals) as the CSV.
    fn assert_same_as_canonical(gp: &ContourSet, csv: &ContourSet) {
        assert_eq!(gp.contours.len(), csv.contours.len());
        for s in ["LV_ENDO", "LV_EPI", "RV_ENDO", "RV_EPI"] {
            let count = |set: &ContourSet| -> usize {
                set.contours
                    .iter()
                    .filter(|c| c.surface.as_deref() == Some(s))
                    .map(|c| c.point_count())
                    .sum()
            };
            assert_eq!(count(gp), count(csv), "{s}");
        }
        for c in &csv.contours {
            let g = gp.contours.iter().find(|g| g.id == c.id).expect(&c.id);
            assert_eq!(g.surface, c.surface, "{}", c.id);
            assert_eq!(g.pieces.len(), c.pieces.len(), "{}", c.id);
            for (a, b) in g.pieces.iter().zip(&c.pieces) {
                assert_eq!(a.closed, b.closed, "{}", c.id);
                assert_eq!(a.points.len(), b.points.len(), "{}", c.id);
                for (p, q) in a.points.iter().zip(&b.points) {
                    assert!((p - q).amax() < 6e-5, "{}: {p:?} vs {q:?}", c.id);
                }
            }
        }
    }

    #[test]
    fn patient1_matches_canonical_csv() {
        for (gp, csv, frame) in [
            ("GPFile_000.txt", "patient1-ED.csv", None),
            ("GPFile_009.txt", "patient1-ES.csv", None),
        ] {
            let dir = "contours/bivme-example-patient1/";
            let g = read_gpfile(&text(&format!("{dir}{gp}")), frame).unwrap();
            let c = read_csv(&sample(&format!("{dir}{csv}"))).unwrap();
            assert_same_as_canonical(&g, &c);
        }
        let g = read_gpfile(
            &text("contours/bivme-example-patient1/GPFile_000.txt"),
            None,
        )
        .unwrap();
        assert_eq!(g.landmarks.len(), 23);
        assert_eq!(
            g.landmarks.iter().filter(|l| l.0 == "APEX_POINT").count(),
            1
        );
        assert_eq!(g.contours.len(), 40);
        assert_eq!(g.point_count(), 1791);
        // GPFile_009 holds frame 9 for most slices and "1.0" for slice 8: an explicit frame keeps
        // only its rows, and the two selections partition the contour points.
        let es = text("contours/bivme-example-patient1/GPFile_009.txt");
        let all = read_gpfile(&es, None).unwrap();
        let f9 = read_gpfile(&es, Some(&9.into())).unwrap();
        let f1 = read_gpfile(&es, Some(&1.into())).unwrap();
        assert_eq!(f9.contours.len(), 30);
        assert_eq!(f9.contours.len() + f1.contours.len(), all.contours.len());
        assert!(f1.contours.iter().all(|c| c.id.starts_with("s08_")));
    }

    #[test]
    fn patient2_with_and_without_header() {
        let dir = "contours/bivme-test-patient2/";
        for (gp, csv) in [
            ("GPFile_000.txt", "patient2-ED.csv"),
            ("GPFile_012.txt", "patient2-ES.csv"),
        ] {
            let g = read_gpfile(&text(&format!("{dir}{gp}")), None).unwrap();
            let c = read_csv(&sample(&format!("{dir}{csv}"))).unwrap();
            assert_same_as_canonical(&g, &c);
            assert_eq!(g.surfaces(), vec!["LV_ENDO", "LV_EPI", "RV_ENDO"]);
        }
        let e = read_gpfile(&text(&format!("{dir}GPFile_012.txt")), Some(&3.into())).unwrap_err();
        assert!(e.to_string().contains("frames in the file: 12"), "{e}");
    }

    #[test]
    fn slice_info_planes_fit_the_contours() {
        for dir in ["bivme-example-patient1", "bivme-test-patient2"] {
            let info =
                read_slice_info(&text(&format!("contours/{dir}/SliceInfoFile.txt"))).unwrap();
            let mut set =
                read_gpfile(&text(&format!("contours/{dir}/GPFile_000.txt")), None).unwrap();
            let before = set.warnings.len();
            check_slices(&mut set, &info);
            let off: Vec<_> = set.warnings[before..].to_vec();
            assert!(off.is_empty(), "{dir}: {off:?}");
        }
    }

    #[test]
    fn another_acquisitions_slice_info_is_one_warning_per_kind() {
        let info =
            read_slice_info(&text("contours/bivme-test-patient2/SliceInfoFile.txt")).unwrap();
        let gp = text("contours/bivme-example-patient1/GPFile_000.txt");
        let mut set = read_gpfile(&gp, None).unwrap();
        let before = set.warnings.len();
        check_slices(&mut set, &info);
        let added = &set.warnings[before..];
        assert_eq!(added.len(), 2, "{added:?}");
        assert!(
            added[0].starts_with("37 contours lie off the image planes of their slices, up to 91.4 mm (s02_SAX_RV_FREEWALL, s02_SAX_RV_EPICARDIAL, s02_SAX_RV_SEPTUM, ...); is the slice info file from another acquisition?"),
            "{added:?}"
        );
        assert_eq!(
            added[1],
            "slice 11 (3 contours) is not in the slice info file"
        );
    }

    /// The app sends a folder's SliceInfoFile with each GPFile as the label maps' views are sent:
    /// read as the command line reads the file beside it, and never a reason to refuse the GPFile.
    #[test]
    fn a_slice_info_file_sent_with_the_gpfile_checks_its_planes() {
        use crate::io::{read_contours_with, ContourOptions};
        let gp = sample("contours/bivme-example-patient1/GPFile_000.txt");
        let own = sample("contours/bivme-example-patient1/SliceInfoFile.txt");
        let other = sample("contours/bivme-test-patient2/SliceInfoFile.txt");
        let read = |views: &[(&str, &[u8])]| {
            let options = ContourOptions {
                views,
                ..ContourOptions::default()
            };
            read_contours_with("GPFile_000.txt", &gp, &options)
        };
        let alone = read(&[]).unwrap();
        let with_own = read(&[("SliceInfoFile.txt", &own)]).unwrap();
        assert!(with_own.contours == alone.contours);
        assert_eq!(with_own.warnings, alone.warnings);
        let with_other = read(&[("SliceInfoFile.txt", &other)]).unwrap();
        let added = &with_other.warnings[alone.warnings.len()..];
        assert_eq!(added.len(), 2, "{added:?}");
        assert!(added[0].starts_with("37 contours lie off the image planes"));
        // A damaged one is said, by name and line; the contours are read as without it.
        let damaged = String::from_utf8(own.clone()).unwrap().replacen(
            "ImagePositionPatient",
            "ImagePositionPatient x",
            1,
        );
        let got = read(&[("SliceInfoFile.txt", damaged.as_bytes())]).unwrap();
        assert!(got.contours == alone.contours);
        assert_eq!(
            got.warnings[alone.warnings.len()..],
            ["SliceInfoFile.txt not read (line 1: ImagePositionPatient: \"x\" is not a number): \
              the contours are not checked against their image planes"
                .to_string()]
        );
        // Anything else, or two of them: refused as views of a contour file are.
        for views in [
            vec![
                ("SliceInfoFile.txt", own.as_slice()),
                ("b.txt", other.as_slice()),
            ],
            vec![("GPFile_009.txt", gp.as_slice())],
        ] {
            let e = read(&views).unwrap_err().to_string();
            assert!(e.contains("one SliceInfoFile"), "{e}");
        }
    }

    #[test]
    fn comma_space_and_cr_separated_files_and_several_frames() {
        let gp = text("contours/bivme-example-patient1/GPFile_000.txt");
        let want = read_gpfile(&gp, None).unwrap();
        let spaced = gp.replace('\t', " ");
        for (name, variant) in [
            ("commas", gp.replace('\t', ",")),
            ("spaces", spaced.clone()),
            ("spaces, CR", spaced.replace('\n', "\r")),
        ] {
            let got = read_gpfile(&variant, None).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(got.contours == want.contours, "{name}");
        }
        // Every row again in frame 5, 3 mm to the side: frame 0 (slice 8: frame 1) is read.
        let mut two = String::from(gp.lines().next().unwrap_or(""));
        for row in gp.lines().skip(1) {
            let f: Vec<&str> = row.split('\t').collect();
            let x: f64 = f[0].parse().unwrap();
            two.push_str(&format!("\n{row}\n{}\t{}\t5", x + 3.0, f[1..6].join("\t")));
        }
        let got = read_gpfile(&two, None).unwrap();
        for (a, b) in got.contours.iter().zip(&want.contours) {
            assert_eq!(a.id, b.id);
            assert_eq!(a.pieces.len(), b.pieces.len(), "{}", a.id);
            for (p, q) in a.pieces.iter().zip(&b.pieces) {
                assert_eq!(p.points.len(), q.points.len(), "{}", a.id);
                assert_eq!(p.closed, q.closed, "{}", a.id);
                assert!(p.points == q.points, "{}", a.id);
            }
        }
        assert_eq!(got.contours.len(), want.contours.len());
        let w = got
            .warnings
            .iter()
            .find(|w| w.contains("time frames"))
            .unwrap();
        assert!(
            w.starts_with("the file holds 3 time frames (0, 5, 1): each slice's first frame read, 1814 points of other frames left out"),
            "{w}"
        );
        let five = read_gpfile(&two, Some(&5.into())).unwrap();
        assert_eq!(five.point_count(), want.point_count());
    }

    /// Patient 1's ED (frame 0) and ES (frame 9) files in one, slice 8's "1.0" rewritten to the
    /// frame of its file (as the app's end-to-end test builds it): the set lists both frames and
    /// which was read, and frame 9 reads exactly GPFile_009.txt.
    #[test]
    fn a_two_frame_file_says_its_frames_and_each_reads_its_own_file() {
        let dir = "contours/bivme-example-patient1/";
        let ed = text(&format!("{dir}GPFile_000.txt"));
        let es = text(&format!("{dir}GPFile_009.txt"));
        let rows = |t: &str, frame: &str| -> String {
            t.lines()
                .skip(1)
                .map(|row| {
                    let mut f: Vec<&str> = row.split('\t').collect();
                    f[6] = frame;
                    format!("{}\n", f.join("\t"))
                })
                .collect()
        };
        let header = ed.lines().next().unwrap_or("");
        let two = format!("{header}\n{}{}", rows(&ed, "0"), rows(&es, "9"));
        let first = read_gpfile(&two, None).unwrap();
        let t = first.time_frames.clone().unwrap();
        assert_eq!(t.frames, ["0", "9"]);
        assert_eq!(
            (t.read.as_slice(), t.chosen, t.sequence),
            (&["0".to_string()][..], false, true)
        );
        assert_eq!(t.left_out, 1225, "every row of the ES file");
        assert!(first
            .warnings
            .iter()
            .any(|w| w.contains("holds 2 time frames (0, 9): frame 0 read")));
        // The same curves point for point (their lines in the file differ).
        let curves = |set: &ContourSet| -> Vec<_> {
            set.contours
                .iter()
                .map(|c| (c.id.clone(), c.surface.clone(), c.pieces.clone()))
                .collect()
        };
        let nine = read_gpfile(&two, Some(&9.into())).unwrap();
        let alone = read_gpfile(&es, None).unwrap();
        assert!(curves(&nine) == curves(&alone) && nine.landmarks == alone.landmarks);
        let t = nine.time_frames.unwrap();
        assert_eq!(
            (t.read.as_slice(), t.chosen),
            (&["9".to_string()][..], true)
        );
        assert_eq!(t.named(), Some("9"));
        assert!(curves(&read_gpfile(&two, Some(&0.into())).unwrap()) == curves(&first));
        assert!(curves(&first) == curves(&read_gpfile(&ed, None).unwrap()));
        // The ED file alone: slice 8 carries its own frame 1, which is no sequence (no picker).
        let t = read_gpfile(&ed, None).unwrap().time_frames.unwrap();
        assert_eq!(
            (t.frames.as_slice(), t.sequence, t.left_out),
            (&["0".to_string(), "1".to_string()][..], false, 0)
        );
        assert_eq!(t.named(), None);
    }

    #[test]
    fn errors_and_unknown_types() {
        let e = read_gpfile("1\t2\tx\tSAX_LV_ENDOCARDIAL\t1\t1.0\t0\n", None).unwrap_err();
        assert_eq!(e.line(), Some(1));
        assert!(e.to_string().contains("column \"z\""), "{e}");
        let s = "1 2 3 SAX_LV_ENDOCARDIAL 1 1.0 0\n4 5 6 SAX_LV_ENDOCARDIAL 1 1.0 0\n\
                 7 8 9 SAX_LA 1 1.0 0\n";
        let set = read_gpfile(s, None).unwrap();
        assert_eq!(set.contours[0].id, "s01_SAX_LV_ENDOCARDIAL");
        assert!(
            set.warnings.iter().any(|w| w.contains("SAX_LA")),
            "{:?}",
            set.warnings
        );
        assert!(looks_like_gpfile(s));
        assert!(!looks_like_gpfile("contour,x,y,z\n"));
    }

    /// Types of newer biv-me versions: points kept as landmarks, atria and the outflow tract
    /// named in the warning, removed points dropped quietly; the curves still read.
    #[test]
    fn newer_bivme_types() {
        let rows = [
            "1 2 3 SAX_LV_ENDOCARDIAL 1 1.0 0",
            "4 5 6 SAX_LV_ENDOCARDIAL 1 1.0 0",
            "7 8 9 MITRAL_PHANTOM 5 1.0 0",
            "7 8 9 MITRAL_PHANTOM 5 1.0 0",
            "1 1 1 APEX_ENDO_POINT 5 1.0 0",
            "2 2 2 LAX_LV_EXTENT 5 1.0 0",
            "3 3 3 LAX_LA 5 1.0 0",
            "3 3 4 LAX_LA 5 1.0 0",
            "5 5 5 SAX_RV_OUTLET 2 1.0 0",
            "6 6 6 REMOVED 2 1.0 0",
            "6 6 7 EXCLUDED 2 1.0 0",
        ];
        let set = read_gpfile(&rows.join("\n"), None).unwrap();
        let names: Vec<&str> = set.landmarks.iter().map(|l| l.0.as_str()).collect();
        assert_eq!(
            names,
            [
                "MITRAL_PHANTOM",
                "MITRAL_PHANTOM",
                "APEX_ENDO_POINT",
                "LAX_LV_EXTENT"
            ]
        );
        assert_eq!(set.contours.len(), 1);
        assert_eq!(set.contours[0].point_count(), 2);
        let w = set.warnings.join(" | ");
        assert!(
            w.contains("2 points of contour type LAX_LA (left atrium) skipped"),
            "{w}"
        );
        assert!(
            w.contains("1 point of contour type SAX_RV_OUTLET (RV outflow tract)"),
            "{w}"
        );
        assert!(
            !w.contains("REMOVED") && !w.contains("EXCLUDED") && !w.contains("unknown"),
            "{w}"
        );
        assert!(looks_like_gpfile("7 8 9 MITRAL_PHANTOM 5 1.0 0\n"));
        assert!(looks_like_gpfile("6 6 6 REMOVED 2 1.0 0\n"));
    }
}
