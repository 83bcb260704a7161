//! 3D Slicer markups (`.mrk.json`, Slicer's Markups module): contours drawn in Slicer as closed
//! curves on the short-axis slices and curves on the long-axis views.
//!
//! Slicer saves each markup node in a file of its own (`LV_ENDO_3.mrk.json`), so a study is
//! usually a folder of them: read together ([`read_markups`] with the others as companions,
//! [`super::read_study`]), they make one contour set, in name order whatever the order given.
//!
//! What is read of each markup (schema markups-schema-v1.0.x):
//! - `ClosedCurve` is a closed contour, `Curve` an open one. Slicer draws a smooth spline through
//!   the control points (its default curve type), not the polygon of the points: with a dozen
//!   points round a 25 mm ring the polygon's chords fall up to 0.9 mm inside the drawn curve, as
//!   much as the reconstruction's whole error. So the points are joined by a centripetal
//!   Catmull-Rom spline (points about 1 mm apart), which follows the points' curve as Slicer's does;
//!   points already under a millimetre apart are left as they are by it.
//! - `Fiducial` (a point list): each defined point is a landmark named by its label
//!   (`RV_INSERT_ANTERIOR`, `APEX_POINT`, ...), as a CSV's `# landmark` lines are; unless the
//!   list is a contour clicked point by point, as Slicer users drew them before curves existed
//!   ([`point_list_is_contour`]: neither the list nor a point named as a landmark, and the list
//!   named after a wall or holding four or more points in one plane), read as a curve that
//!   closes where its ends meet as a CSV's does.
//! - Slicer's legacy point list files (`.fcsv`, [`fcsv`]) and its control points tables (a CSV of
//!   `label,l,p,s,defined,...`, [`points_table`]) are read as the point list Slicer makes of one,
//!   so a folder of them (one contour per file) is a study as a folder of `.mrk.json` is.
//! - `Line`, `Angle`, `Plane` and `ROI` hold no contour: skipped, with one warning naming them.
//! - A curve of one placed point is that point, kept as a CSV keeps a one-point piece (biv-me's
//!   curves carry some); a closed curve of fewer than three points is open.
//! - Control points whose `positionStatus` is not `defined` (`undefined`, `preview`) are skipped:
//!   Slicer keeps them for points not yet placed.
//! - `coordinateSystem` (`LPS`, Slicer's default, or `RAS`) is the set's patient frame; a markup in
//!   the other frame than the first's is taken into the first's. `coordinateUnits` (`mm`, `um`,
//!   as a string or a UCUM code) scales to millimetres.
//!
//! Contour ids are the markups' `name`s (else the file's name without `.mrk.json`); markups of one
//! name are pieces of one contour, as a CSV's rows of one id are (a curve drawn in two stretches
//! across a gap, as real files store some). The surface comes from the name, so one folder may hold every surface: a
//! name saying a ventricle and a wall is that surface (`LV endo 3`, `s02_SAX_LV_ENDOCARDIAL`,
//! `LVEpi_4ch` are `LV_ENDO`, `LV_ENDO`, `LV_EPI`; an RV's free wall and septum are both
//! `RV_ENDO`, joined per slice as biv-me's are); any other name is its surface without its slice
//! tags (`myo_3` is `MYO`; Slicer's default names `CC`, `CC_1`, ... are all one surface, `CC`).

pub mod fcsv;
pub mod points_table;

use serde_json::Value;

use super::builder::{polyline_from_run, ContourBuilder, MAX_POINTS};
use crate::contours::checks::NON_PLANAR_MM;
use crate::contours::clean::clean_and_split;
use crate::contours::plane::fit_plane;
use crate::contours::{ContourSet, CoordinateSystem};
use crate::error::{CoreError, Result};
use crate::geometry::{v3, Vec3};

/// How the note on point lists read as contours starts (a reading note: how the files were
/// understood, not a fault in them).
pub const POINT_CONTOURS: &str = "Slicer point lists read as contours";

/// What the reader calls a file in its messages.
const WHAT: &str = "Slicer markups file";

/// Spline step along each segment's chord, mm: finer than any contour's resampling in the pipeline.
const STEP_MM: f64 = 1.0;

/// Most points one spline segment is cut into (a hostile file's 10 km segment stays cheap).
const MAX_SEGMENT_STEPS: usize = 64;

/// Whether the start of a file is a Slicer markups file: a JSON object naming the markups
/// schema, or holding `markups` with `controlPoints` (files written by scripts without a schema).
pub fn is_markups(head: &[u8]) -> bool {
    let head = head.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(head);
    if !head.trim_ascii_start().starts_with(b"{") {
        return fcsv::is_fcsv(head) || points_table::is_points_table(head);
    }
    let has = |needle: &[u8]| {
        head.windows(needle.len())
            .any(|w| w.eq_ignore_ascii_case(needle))
    };
    has(b"markups-schema") || (has(b"\"markups\"") && has(b"\"controlPoints\""))
}

/// Whether a markups file holds a curve or a closed curve (not only point lists, lines, planes):
/// a Slicer scene's contours come from its curves when it has any.
pub fn holds_curves(bytes: &[u8]) -> bool {
    if let Some(markup) = point_list_file("", bytes) {
        // A damaged point list file is still markups, as a damaged JSON one is.
        return markup.map_or(true, |m| Reader::default().reads_as_contour(&m));
    }
    let Ok(text) = super::text::decode(bytes) else {
        return false;
    };
    let Ok(root) = serde_json::from_str::<Value>(&text) else {
        // A damaged markups file is still markups: read with them, it is named in the refusal.
        return true;
    };
    root.get("markups")
        .and_then(Value::as_array)
        .is_some_and(|list| {
            list.iter().any(|m| {
                matches!(
                    m.get("type").and_then(Value::as_str),
                    Some("ClosedCurve" | "Curve")
                ) || Reader::default().reads_as_contour(m)
            })
        })
}

/// The point list a file that is no JSON makes, row by row ([`fcsv`], [`points_table`]).
struct PointListRows {
    name: String,
    points: Vec<Value>,
}

impl PointListRows {
    fn new(name: &str) -> Self {
        Self {
            name: name.to_string(),
            points: Vec::new(),
        }
    }

    /// Adds the point of file line `line`: its label (numbered after the list when the cell is
    /// empty or missing, as Slicer numbers it) and position.
    fn push(&mut self, label: Option<&str>, position: [f64; 3], line: usize) -> Result<()> {
        let label = label.map(str::trim).filter(|l| !l.is_empty()).map_or_else(
            || format!("{}-{}", self.name, self.points.len() + 1),
            str::to_string,
        );
        self.points
            .push(serde_json::json!({ "label": label, "position": position }));
        if self.points.len() > MAX_POINTS {
            return Err(CoreError::parse(
                line,
                format!("too many points: the limit is {MAX_POINTS} points per file"),
            ));
        }
        Ok(())
    }

    /// The markups JSON point list, in `frame` (`LPS` or `RAS`).
    fn finish(self, frame: &str) -> Value {
        serde_json::json!({
            "type": "Fiducial",
            "name": self.name,
            "coordinateSystem": frame,
            "controlPoints": self.points,
        })
    }
}

/// A point list file that is no JSON (Slicer's legacy `.fcsv`, or its control points table CSV)
/// as the markup Slicer makes of it, named `stem`; None for any other file.
fn point_list_file(stem: &str, bytes: &[u8]) -> Option<Result<Value>> {
    if fcsv::is_fcsv(bytes) {
        Some(fcsv::to_markup(stem, bytes))
    } else if points_table::is_points_table(bytes) {
        Some(points_table::to_markup(stem, bytes))
    } else {
        None
    }
}

/// Reads `name` and its `companions` (other markups files of the same study) into one set.
pub fn read_markups(name: &str, bytes: &[u8], companions: &[(&str, &[u8])]) -> Result<ContourSet> {
    let mut files: Vec<(&str, &[u8])> = vec![(name, bytes)];
    files.extend_from_slice(companions);
    // Name order: the same files give the same contours in the same order however picked.
    files.sort_by(|a, b| a.0.cmp(b.0));
    refuse_studies_in_folders(&files)?;
    read_sorted(&files)
}

fn read_sorted(files: &[(&str, &[u8])]) -> Result<ContourSet> {
    let mut reader = Reader::default();
    for (file, bytes) in files {
        reader.file(file, bytes, files.len() > 1)?;
    }
    reader.finish()
}

/// The folder part of a file's path ("" for none).
fn folder_of(file: &str) -> &str {
    file.rfind(['/', '\\']).map_or("", |at| &file[..at])
}

/// Markups of several folders whose curves share names are several studies (a patient's `ED/`
/// and `ES/` folders, two patients), not pieces of one: joined, each curve would be one phase's
/// ring plus the other's, a surface between the two that looks plausible. Refused naming the
/// folders; folders whose names do not meet (`LV/` beside `RV/`) are one set.
fn refuse_studies_in_folders(files: &[(&str, &[u8])]) -> Result<()> {
    let mut folders: Vec<&str> = files.iter().map(|(f, _)| folder_of(f)).collect();
    folders.sort_unstable();
    folders.dedup();
    if folders.len() < 2 {
        return Ok(());
    }
    let mut owner: std::collections::BTreeMap<String, &str> = Default::default();
    let mut shared: Vec<String> = Vec::new();
    for folder in &folders {
        let group: Vec<(&str, &[u8])> = files
            .iter()
            .copied()
            .filter(|(f, _)| folder_of(f) == *folder)
            .collect();
        // A folder that cannot be read alone (only landmarks, a damaged file) shares no curve
        // name; the whole set's reading says what is wrong with it.
        let Ok(set) = read_sorted(&group) else {
            continue;
        };
        for c in set.contours {
            match owner.get(&c.id) {
                Some(first) if first != folder => shared.push(c.id),
                Some(_) => {}
                None => {
                    owner.insert(c.id, folder);
                }
            }
        }
    }
    if shared.is_empty() {
        return Ok(());
    }
    shared.dedup();
    let shown: Vec<&str> = shared.iter().take(4).map(String::as_str).collect();
    Err(CoreError::parse(
        0,
        format!(
            "Slicer markups from {} folders ({}) hold curves of the same names ({}{}): each \
             folder is a study of its own (a phase, a patient); open one folder at a time (two \
             phases: heartmesh volumes ED_FOLDER ES_FOLDER)",
            folders.len(),
            folders.join(", "),
            shown.join(", "),
            if shared.len() > shown.len() {
                ", ..."
            } else {
                ""
            }
        ),
    ))
}

#[derive(Default)]
struct Reader {
    builder: ContourBuilder,
    frame: Option<CoordinateSystem>,
    skipped: Vec<String>,
    converted: Vec<String>,
    /// Point lists read as contours ([`point_list_is_contour`]), said in a warning.
    point_contours: Vec<String>,
    /// Point lists read as landmarks, with why: said when the set then holds no contour.
    landmark_lists: Vec<String>,
}

impl Reader {
    fn file(&mut self, file: &str, bytes: &[u8], several: bool) -> Result<()> {
        // Several files: each error names its file (one alone is named by the caller).
        let named = |e: CoreError| match e {
            CoreError::Parse { line, message } if several => {
                CoreError::parse(line, format!("{file}: {message}"))
            }
            other => other,
        };
        let stem = stem_of(file);
        if let Some(markup) = point_list_file(stem, bytes) {
            return self.markup(&markup.map_err(named)?, stem).map_err(named);
        }
        let text = super::text::decode(bytes).map_err(named)?;
        let root: Value = serde_json::from_str(&text).map_err(|e| {
            let msg = e.to_string();
            let msg = msg.rfind(" at line ").map_or(msg.as_str(), |i| &msg[..i]);
            named(CoreError::parse(e.line(), format!("not valid JSON: {msg}")))
        })?;
        let markups = root
            .get("markups")
            .and_then(Value::as_array)
            .ok_or_else(|| {
                named(CoreError::parse(
                    0,
                    format!("not a {WHAT}: no \"markups\" list (3D Slicer's .mrk.json)"),
                ))
            })?;
        for (k, markup) in markups.iter().enumerate() {
            let fallback = if markups.len() > 1 {
                format!("{stem}-{}", k + 1)
            } else {
                stem.to_string()
            };
            self.markup(markup, &fallback).map_err(named)?;
        }
        Ok(())
    }

    fn markup(&mut self, markup: &Value, fallback: &str) -> Result<()> {
        let name = markup
            .get("name")
            .and_then(Value::as_str)
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .unwrap_or(fallback)
            .to_string();
        let kind = markup.get("type").and_then(Value::as_str).unwrap_or("");
        let closed = match kind {
            "ClosedCurve" => true,
            "Curve" => false,
            "Fiducial" => return self.point_list(markup, &name),
            _ => {
                self.skipped.push(format!(
                    "{name} ({})",
                    if kind.is_empty() { "no type" } else { kind }
                ));
                return Ok(());
            }
        };
        let points = self.control_points(markup, &name)?;
        if points.is_empty() {
            self.builder
                .warn(format!("{name}: no placed control point: skipped"));
            return Ok(());
        }
        let surface = surface_of(&name);
        let curve = catmull_rom(&points, closed)?;
        self.builder
            .push_piece(&name, surface.as_deref(), curve, Some(closed), 0)
    }

    /// A point list: landmarks, or a contour clicked point by point ([`point_list_is_contour`]).
    fn point_list(&mut self, markup: &Value, name: &str) -> Result<()> {
        let labels = labels(markup, name);
        let points = self.control_points(markup, name)?;
        if let Some(why) = landmarks_because(name, &labels, &points) {
            self.landmark_lists.push(format!("{name} ({why})"));
            for (label, p) in labels.iter().zip(points) {
                self.builder.landmark(label, p, 0)?;
            }
            return Ok(());
        }
        self.point_contours.push(name.to_string());
        // Closed where its ends meet, and in pieces where it jumps, as a CSV's curve is: a spline
        // drawn across a jump would bridge the gap the file left.
        let surface = surface_of(name);
        for piece in clean_and_split(&polyline_from_run(points)) {
            let curve = catmull_rom(&piece.points, piece.closed)?;
            self.builder
                .push_piece(name, surface.as_deref(), curve, Some(piece.closed), 0)?;
        }
        Ok(())
    }

    /// Whether a markup is a point list read as a contour (for telling a scene's curves).
    fn reads_as_contour(&mut self, markup: &Value) -> bool {
        let name = markup.get("name").and_then(Value::as_str).unwrap_or("");
        markup.get("type").and_then(Value::as_str) == Some("Fiducial")
            && self
                .control_points(markup, name)
                .is_ok_and(|points| point_list_is_contour(name, &labels(markup, name), &points))
    }
}

/// The labels of a point list's defined points (the list's name for a point without one).
fn labels(markup: &Value, name: &str) -> Vec<String> {
    defined(markup)
        .map(|p| {
            p.get("label")
                .and_then(Value::as_str)
                .map(str::trim)
                .filter(|s| !s.is_empty())
                .unwrap_or(name)
                .to_string()
        })
        .collect()
}

/// Fewest points of a point list read as a contour: three points are a triangle, not a curve.
const MIN_CONTOUR_POINTS: usize = 4;

/// Words that make a name a landmark's (biv-me's `APEX_POINT`, `RV_INSERT`, `MITRAL_VALVE`,
/// `*_PHANTOM`, `LAX_*_EXTENT`; Segment's "RV insertion anterior"), compared word by word.
const LANDMARK_WORDS: &[&str] = &[
    "apex",
    "valve",
    "insert",
    "insertion",
    "insertions",
    "mitral",
    "tricuspid",
    "aorta",
    "aortic",
    "pulmonary",
    "pulmonic",
    "landmark",
    "landmarks",
    "phantom",
    "extent",
];

fn names_landmark(name: &str) -> bool {
    name.split(|c: char| !c.is_ascii_alphanumeric())
        .any(|w| LANDMARK_WORDS.iter().any(|l| w.eq_ignore_ascii_case(l)))
}

/// Whether a point list is a contour clicked point by point rather than landmarks. Neither the
/// list nor any point may be named as a landmark; then a list named after a ventricle's wall
/// (`s06_SAX_RV_SEPTUM`, `LV endo 3`: `named_wall`) is a contour however few its points (a
/// short septum arc takes three clicks; one point is kept as a curve's one placed point is), and
/// any other one needs `MIN_CONTOUR_POINTS` points lying in one plane, as a curve drawn on one
/// image does (within the contours' own `NON_PLANAR_MM` (2.5 mm)).
/// Landmarks are few, named, and spread over several images; a list of the apex, valve points
/// and insertions fails every test.
pub fn point_list_is_contour(name: &str, labels: &[String], points: &[Vec3]) -> bool {
    landmarks_because(name, labels, points).is_none()
}

/// Why a point list is landmarks, in words for a message; None when it is a contour
/// ([`point_list_is_contour`]).
fn landmarks_because(name: &str, labels: &[String], points: &[Vec3]) -> Option<String> {
    if names_landmark(name) || labels.iter().any(|l| names_landmark(l)) {
        return Some("named as landmarks".into());
    }
    if named_wall(&tokens_of(name)).is_some() {
        return points.is_empty().then(|| "no placed point".into());
    }
    if points.len() < MIN_CONTOUR_POINTS {
        return Some(format!(
            "{} point(s), and its name says no wall",
            points.len()
        ));
    }
    match fit_plane(points.iter()) {
        None => Some("its points lie on a line".into()),
        Some(f) if f.max_residual > NON_PLANAR_MM => Some(format!(
            "points up to {:.1} mm off one plane",
            f.max_residual
        )),
        Some(_) => None,
    }
}

impl Reader {
    /// The defined control points in millimetres, in the set's frame.
    fn control_points(&mut self, markup: &Value, name: &str) -> Result<Vec<Vec3>> {
        let scale = units_scale(markup.get("coordinateUnits")).map_err(|u| {
            CoreError::parse(
                0,
                format!("{name}: coordinate units {u} (expected mm or um)"),
            )
        })?;
        let frame = match markup.get("coordinateSystem").and_then(Value::as_str) {
            None => CoordinateSystem::Lps,
            Some(s) if s.eq_ignore_ascii_case("LPS") => CoordinateSystem::Lps,
            Some(s) if s.eq_ignore_ascii_case("RAS") => CoordinateSystem::Ras,
            Some(other) => {
                return Err(CoreError::parse(
                    0,
                    format!("{name}: coordinate system {other:?} (expected LPS or RAS)"),
                ))
            }
        };
        let first = *self.frame.get_or_insert(frame);
        let flip = if first != frame {
            self.converted.push(name.to_string());
            -1.0
        } else {
            1.0
        };
        defined(markup)
            .enumerate()
            .map(|(k, p)| {
                let xyz = p
                    .get("position")
                    .and_then(Value::as_array)
                    .filter(|a| a.len() == 3)
                    .and_then(|a| {
                        let f: Vec<f64> = a.iter().filter_map(Value::as_f64).collect();
                        (f.len() == 3 && f.iter().all(|v| v.is_finite())).then_some(f)
                    })
                    .ok_or_else(|| {
                        CoreError::parse(
                            0,
                            format!("{name}: control point {} has no position [x, y, z] of finite numbers", k + 1),
                        )
                    })?;
                Ok(v3(flip * xyz[0] * scale, flip * xyz[1] * scale, xyz[2] * scale))
            })
            .collect()
    }

    fn finish(mut self) -> Result<ContourSet> {
        if !self.skipped.is_empty() {
            self.builder.warn(format!(
                "markups without a contour skipped: {}",
                self.skipped.join(", ")
            ));
        }
        if let Some(frame) = self.frame.filter(|_| !self.converted.is_empty()) {
            self.builder.warn(format!(
                "{} taken from the other patient frame into {} (the first markup's)",
                some_of(&self.converted),
                frame.name()
            ));
        }
        if !self.point_contours.is_empty() {
            self.builder.warn(format!(
                "{POINT_CONTOURS} (drawn point by point: no point is named as a landmark): {}",
                some_of(&self.point_contours)
            ));
        }
        let frame = self.frame;
        let lists = if self.landmark_lists.is_empty() {
            String::new()
        } else {
            format!(
                "; point lists read as landmarks: {} (a contour clicked point by point has four \
                 points or more in one plane, or a name saying its wall: LV_ENDO_3)",
                some_of(&self.landmark_lists)
            )
        };
        let mut set = self.builder.finish().map_err(|e| match e {
            CoreError::Parse { line, message } if message == "no contour points found" => {
                CoreError::parse(
                    line,
                    format!(
                        "no curve or closed curve with control points found (Slicer markups){lists}"
                    ),
                )
            }
            other => other,
        })?;
        set.coordinate_system = frame;
        // One curve cannot be reconstructed, and one file of a Slicer folder holds one: the
        // reason travels first with the set, so the refusal that follows says what to do.
        if let [only] = set.contours.as_slice() {
            set.warnings.insert(
                0,
                format!(
                    "one curve ({}): 3D Slicer saves each curve in a file of its own; open the \
                     folder, or all its .mrk.json (.fcsv) files together, to read the study",
                    only.id
                ),
            );
        }
        Ok(set)
    }
}

/// Names for a message: the first [`NAMES_SHOWN`], then how many in all (a folder of forty curves
/// would otherwise fill the page).
fn some_of(names: &[String]) -> String {
    let shown: Vec<&str> = names.iter().take(NAMES_SHOWN).map(String::as_str).collect();
    if names.len() > shown.len() {
        format!("{}, ... ({} in all)", shown.join(", "), names.len())
    } else {
        shown.join(", ")
    }
}

/// How many names a message lists before it counts the rest.
const NAMES_SHOWN: usize = 6;

/// The control points Slicer counts as placed (no `positionStatus` means placed).
fn defined(markup: &Value) -> impl Iterator<Item = &Value> {
    markup
        .get("controlPoints")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
        .filter(|p| {
            p.get("positionStatus")
                .and_then(Value::as_str)
                .is_none_or(|s| s == "defined")
        })
}

/// Millimetres per unit of `coordinateUnits` (a string, or a `[code, "UCUM", meaning]` entry);
/// the unit's text when it is none of those Slicer writes.
fn units_scale(units: Option<&Value>) -> std::result::Result<f64, String> {
    let code = match units {
        None | Some(Value::Null) => return Ok(1.0),
        Some(Value::String(s)) => s.as_str(),
        Some(Value::Array(a)) => a.first().and_then(Value::as_str).unwrap_or(""),
        Some(other) => return Err(other.to_string()),
    };
    match code.trim() {
        "mm" => Ok(1.0),
        "um" | "µm" => Ok(0.001),
        "cm" => Ok(10.0),
        "m" => Ok(1000.0),
        other => Err(format!("{other:?}")),
    }
}

/// A file's name without its folder and `.mrk.json` / `.json` / `.fcsv` / `.csv`.
fn stem_of(file: &str) -> &str {
    let base = file.rsplit(['/', '\\']).next().unwrap_or(file);
    let lower = base.to_ascii_lowercase();
    for ext in [".mrk.json", ".json", ".fcsv", ".csv"] {
        if lower.ends_with(ext) && base.len() > ext.len() {
            return &base[..base.len() - ext.len()];
        }
    }
    base
}

/// A name's words: its runs of letters and digits.
fn tokens_of(name: &str) -> Vec<&str> {
    name.split(|c: char| !c.is_ascii_alphanumeric())
        .filter(|t| !t.is_empty())
        .collect()
}

/// Whether a name's token says which slice or view a curve is on, not what it delineates.
fn is_slice_tag(token: &str) -> bool {
    let t = token.to_ascii_lowercase();
    if matches!(
        t.as_str(),
        "sax" | "sa" | "lax" | "la" | "lvot" | "rvot" | "slice" | "ch"
    ) {
        return true;
    }
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    if digits(&t) {
        return true;
    }
    if let Some(n) = t.strip_suffix("ch") {
        return digits(n);
    }
    ["sax", "lax", "sa", "la", "slice", "sl", "s"]
        .iter()
        .any(|p| t.strip_prefix(p).is_some_and(digits))
}

/// The surface a markup's name delineates: the ventricle's wall it names ([`named_wall`]), else
/// its tokens but the slice tags at either end, joined by `_` in capitals; None when nothing
/// else is left (a name that is only `3`).
pub fn surface_of(name: &str) -> Option<String> {
    let tokens = tokens_of(name);
    if let Some(wall) = named_wall(&tokens) {
        return Some(wall.to_string());
    }
    let start = tokens.iter().position(|t| !is_slice_tag(t))?;
    let end = tokens.iter().rposition(|t| !is_slice_tag(t))?;
    Some(tokens[start..=end].join("_").to_ascii_uppercase())
}

/// The surface a name's tokens say: a ventricle (`lv`, `rv`, `left`, `right`, or a token starting
/// with `lv`/`rv` and going on with the wall, `LVEndo`) and a wall (`endo...`, `epi...`; the RV's
/// `free wall` / `freewall` / `fw` and `septum` / `septal` are its endocardium).
fn named_wall(tokens: &[&str]) -> Option<&'static str> {
    #[derive(Clone, Copy, PartialEq)]
    enum Wall {
        Endo,
        Epi,
        RvPart,
    }
    let wall_of = |t: &str| {
        if t.starts_with("endo") {
            Some(Wall::Endo)
        } else if t.starts_with("epi") {
            Some(Wall::Epi)
        } else if t == "free" || t.starts_with("freewall") || t == "fw" || t.starts_with("sept") {
            Some(Wall::RvPart)
        } else {
            None
        }
    };
    let (mut lv, mut wall) = (None, None);
    for t in tokens.iter().map(|t| t.to_ascii_lowercase()) {
        let side = match t.as_str() {
            "lv" | "left" => Some(true),
            "rv" | "right" => Some(false),
            _ => None,
        };
        let (side, rest) = match (side, t.get(..2), t.get(2..)) {
            (Some(s), _, _) => (Some(s), None),
            (None, Some("lv"), Some(rest)) if wall_of(rest).is_some() => (Some(true), Some(rest)),
            (None, Some("rv"), Some(rest)) if wall_of(rest).is_some() => (Some(false), Some(rest)),
            _ => (None, Some(t.as_str())),
        };
        lv = lv.or(side);
        wall = wall.or(rest.and_then(wall_of));
    }
    match (lv?, wall?) {
        (true, Wall::Endo) => Some("LV_ENDO"),
        (true, Wall::Epi) => Some("LV_EPI"),
        (false, Wall::Endo | Wall::RvPart) => Some("RV_ENDO"),
        (false, Wall::Epi) => Some("RV_EPI"),
        (true, Wall::RvPart) => None,
    }
}

/// The curve through `points` as Slicer draws one: a centripetal Catmull-Rom spline (closed
/// through the first point again for a closed curve; an open one's ends continued straight),
/// each segment cut into steps of at most [`STEP_MM`]. Centripetal, so that unevenly spaced
/// points make neither loops nor cusps.
fn catmull_rom(points: &[Vec3], closed: bool) -> Result<Vec<Vec3>> {
    let n = points.len();
    if n < 3 && (closed || n < 2) {
        // A point, or two of a closed curve: nothing to draw between (the builder keeps them as
        // an open piece, as a CSV's).
        return Ok(points.to_vec());
    }
    let at = |i: isize| -> Vec3 {
        if closed {
            points[i.rem_euclid(n as isize) as usize]
        } else if i < 0 {
            points[0] * 2.0 - points[1]
        } else if i as usize >= n {
            points[n - 1] * 2.0 - points[n - 2]
        } else {
            points[i as usize]
        }
    };
    let segments = if closed { n } else { n - 1 };
    let steps = |s: isize| {
        let chord = (at(s + 1) - at(s)).norm();
        ((chord / STEP_MM).ceil() as usize).clamp(1, MAX_SEGMENT_STEPS)
    };
    // Counted before any is made: a hostile file's million points would otherwise be 64 million.
    let total: usize = (0..segments as isize).map(steps).sum();
    if total > MAX_POINTS {
        return Err(CoreError::parse(
            0,
            format!("too many points: the limit is {MAX_POINTS} points per file"),
        ));
    }
    let mut out = Vec::with_capacity(total + 1);
    for s in 0..segments as isize {
        let (p0, p1, p2, p3) = (at(s - 1), at(s), at(s + 1), at(s + 2));
        out.push(p1);
        let steps = steps(s);
        for k in 1..steps {
            out.push(centripetal(p0, p1, p2, p3, k as f64 / steps as f64));
        }
    }
    if !closed {
        out.push(points[n - 1]);
    }
    Ok(out)
}

/// The point at `u` (0 at `p1`, 1 at `p2`) of the centripetal Catmull-Rom segment (Barry and
/// Goldman's pyramid); repeated points fall back to the straight segment.
fn centripetal(p0: Vec3, p1: Vec3, p2: Vec3, p3: Vec3, u: f64) -> Vec3 {
    let knot = |a: Vec3, b: Vec3| (b - a).norm().sqrt();
    let (d0, d1, d2) = (knot(p0, p1), knot(p1, p2), knot(p2, p3));
    if d0 < 1e-9 || d1 < 1e-9 || d2 < 1e-9 {
        return p1 + (p2 - p1) * u;
    }
    let (t0, t1, t2, t3) = (0.0, d0, d0 + d1, d0 + d1 + d2);
    let t = t1 + u * d1;
    let lerp = |a: Vec3, b: Vec3, ta: f64, tb: f64| {
        a * ((tb - t) / (tb - ta)) + b * ((t - ta) / (tb - ta))
    };
    let a1 = lerp(p0, p1, t0, t1);
    let a2 = lerp(p1, p2, t1, t2);
    let a3 = lerp(p2, p3, t2, t3);
    let b1 = lerp(a1, a2, t0, t2);
    let b2 = lerp(a2, a3, t1, t3);
    lerp(b1, b2, t1, t2)
}

#[cfg(test)]
mod tests;
