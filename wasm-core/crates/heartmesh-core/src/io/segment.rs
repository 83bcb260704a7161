//! Segment studies (Medviso Segment and Segment CMR; Heiberg et al., BMC Medical Imaging 2010):
//! the `.mat` file Segment saves, its `setstruct` variable a struct array with one element per
//! image stack (the short-axis cine, each long-axis view, ...).
//!
//! A stack keeps its contours in pixels: `EndoX`/`EndoY` (LV endocardium), `EpiX`/`EpiY` (LV
//! epicardium), `RVEndoX`/`RVEndoY` and `RVEpiX`/`RVEpiY`, each `N x TSize x ZSize` (N points per
//! curve, NaN where nothing is drawn). `x` counts rows and `y` columns, both from 1, so a point
//! lies at `ImagePosition + (x-1) ResolutionX ImageOrientation(4:6) + (y-1) ResolutionY
//! ImageOrientation(1:3)`, and slice `z` (from 1) `(z-1) (SliceThickness + SliceGap)` along
//! `-(ImageOrientation(1:3) x ImageOrientation(4:6))`: Segment's own conversion to patient
//! coordinates, DICOM's LPS in millimetres, so a study's stacks land where the scanner put them.
//!
//! Each stack's slices and frames become images for [`super::pixel_contours`], which places the
//! curves and reads one frame per slice as for cvi42 and Sunnybrook; frames are labelled from 1
//! as Segment shows them, and without a frame asked for each slice reads the study's
//! end-diastole (`EDT`) where it is drawn there. Frames are the most drawn stack's: another
//! cine stack's frames are matched to them by cardiac phase ([`phases`]), so a long-axis view
//! of another length or with its end-diastole on another frame is read in the same phase.

use super::dicom_image::ImageGeometry;
use super::frame_choice::FrameChoice;
use super::mat::Value;
use super::mat::Variable;
use super::pixel_contours::{count, place_preferring, Images, PixelContour, Source};
use crate::contours::ContourSet;
use crate::error::Result;
use crate::geometry::{v3, Vec3};
use phases::{match_frames, Cycle};

/// How the reader's account of what it read begins (a note: [`super::is_reading_note`]).
pub const NOTE: &str = "Segment study read with ";

/// How the reader's line naming the study's phases begins (a note too).
pub const PHASES: &str = "Segment study's end-diastole";

/// How the reader's line on a stack whose frames were matched by phase begins (a note too).
pub const MATCHED: &str = "Segment study's frames matched by cardiac phase: ";

/// The curve fields of a stack: (x field, y field, contour type).
const CURVES: [(&str, &str, &str); 4] = [
    ("EndoX", "EndoY", "Endo"),
    ("EpiX", "EpiY", "Epi"),
    ("RVEndoX", "RVEndoY", "RVEndo"),
    ("RVEpiX", "RVEpiY", "RVEpi"),
];

/// Slices x frames of one stack above this are no Segment stack (a corrupt size).
const MAX_IMAGES: usize = 100_000;

const SOURCE: Source = Source {
    what: "Segment study",
    note: NOTE,
    surface_of,
    landmark_of,
    image: "image",
    first_frame: 1,
};

/// The surface a Segment contour type delineates.
pub fn surface_of(kind: &str) -> std::result::Result<&'static str, &'static str> {
    match kind {
        "Endo" => Ok("LV_ENDO"),
        "Epi" => Ok("LV_EPI"),
        "RVEndo" => Ok("RV_ENDO"),
        "RVEpi" => Ok("RV_EPI"),
        _ => Err("not a Segment contour type"),
    }
}

/// The landmark an annotation point's label names: Segment takes `RV insertion`, `P1` and `P2`
/// for the RV insertions when it places the AHA sectors, and offers the two named by side.
fn landmark_of(label: &str) -> Option<&'static str> {
    match label.trim().to_ascii_lowercase().as_str() {
        "rv insertion anterior" => Some("RV_INSERT_ANTERIOR"),
        "rv insertion inferior" => Some("RV_INSERT_INFERIOR"),
        "rv insertion" | "p1" | "p2" => Some("RV_INSERT"),
        _ => None,
    }
}

/// Whether the variables are a Segment study: Segment names its stacks `setstruct` (the format
/// detection looks for that name alone, so an empty or damaged study is refused as a study).
pub fn is_segment(variables: &[Variable]) -> bool {
    variables.iter().any(|v| v.name == "setstruct")
}

/// One stack's plane: where its first pixel of slice 1 is and how rows, columns and slices run.
struct Plane {
    /// The fields the file lacked, placed at Segment's defaults.
    defaulted: Vec<&'static str>,
    position: Vec3,
    row_dir: Vec3,
    col_dir: Vec3,
    /// Along the rows' direction (Segment's x), then along a row (y).
    spacing: [f64; 2],
    /// From one slice to the next (SliceThickness + SliceGap), along -normal.
    slice_step: f64,
}

impl Plane {
    /// Unit normal of the image planes.
    fn normal(&self) -> Vec3 {
        self.row_dir.cross(&self.col_dir).normalize()
    }

    /// Where slice `z` (from 0) has its first pixel: Segment steps along minus the (unnormalised)
    /// cross product of the orientation's two directions.
    fn slice_origin(&self, z: usize) -> Vec3 {
        self.position - self.row_dir.cross(&self.col_dir) * (z as f64 * self.slice_step)
    }
}

/// A stack's name in messages: its number from 1 and its view (`stack 2 (4CH)`).
fn stack_name(set: &Value, e: usize) -> String {
    let view = ["ImageViewPlane", "SeriesDescription"]
        .iter()
        .filter_map(|f| set.field(e, f)?.text())
        .map(str::trim)
        .find(|t| !t.is_empty());
    match view {
        Some(v) => format!("stack {} ({v})", e + 1),
        None => format!("stack {}", e + 1),
    }
}

fn numbers<'v>(set: &'v Value, e: usize, field: &str) -> Option<&'v [f64]> {
    set.field(e, field)?.numbers().map(|(_, d)| d)
}

/// Where a stack without a plane lies: Segment's defaults when it loads such a file (its first
/// pixel at the origin, rows along x, columns along y).
const DEFAULT_POSITION: [f64; 3] = [0.0, 0.0, 0.0];
const DEFAULT_ORIENTATION: [f64; 6] = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0];

fn plane(set: &Value, e: usize) -> std::result::Result<Plane, String> {
    let mut defaulted = Vec::new();
    let mut vector = |field: &'static str,
                      fallback: &[f64]|
     -> std::result::Result<Vec<f64>, String> {
        let n = fallback.len();
        match numbers(set, e, field) {
            Some(d) if d.len() >= n && d[..n].iter().all(|v| v.is_finite()) => Ok(d[..n].to_vec()),
            Some(d) if !d.is_empty() => Err(format!("{field} is not {n} finite numbers")),
            _ => {
                defaulted.push(field);
                Ok(fallback.to_vec())
            }
        }
    };
    let position = vector("ImagePosition", &DEFAULT_POSITION)?;
    let o = vector("ImageOrientation", &DEFAULT_ORIENTATION)?;
    let (row, col) = (v3(o[0], o[1], o[2]), v3(o[3], o[4], o[5]));
    let unit = |v: Vec3| (v.norm() - 1.0).abs() < 0.01;
    if !unit(row) || !unit(col) || row.dot(&col).abs() > 0.01 {
        return Err("ImageOrientation is not two perpendicular unit directions".into());
    }
    let positive = |field: &str| -> std::result::Result<f64, String> {
        match numbers(set, e, field).and_then(|d| d.first().copied()) {
            Some(v) if v.is_finite() && v > 0.0 => Ok(v),
            Some(v) => Err(format!("{field} is {v} (a pixel size in mm, above 0)")),
            None => Err(format!("has no {field}")),
        }
    };
    let spacing = [positive("ResolutionX")?, positive("ResolutionY")?];
    let thickness = numbers(set, e, "SliceThickness").and_then(|d| d.first().copied());
    let gap = numbers(set, e, "SliceGap").and_then(|d| d.first().copied());
    let slice_step = thickness.unwrap_or(0.0) + gap.unwrap_or(0.0);
    Ok(Plane {
        defaulted,
        position: v3(position[0], position[1], position[2]),
        // As given, not normalised: Segment's conversion uses them so.
        row_dir: row,
        col_dir: col,
        spacing,
        slice_step,
    })
}

/// A curve array's points per frame and slice: (N, frames, slices) from its dimensions.
fn shape(dims: &[usize]) -> (usize, usize, usize) {
    let d = |k: usize| dims.get(k).copied().unwrap_or(1);
    (d(0), d(1), dims.iter().skip(2).product())
}

/// A curve or landmark as its stack keeps it, in pixels.
#[derive(Clone)]
struct Drawing {
    /// Slice and frame from 0; no frame: a landmark placed in every frame.
    slice: usize,
    frame: Option<usize>,
    kind: String,
    points: Vec<[f64; 2]>,
}

/// One stack's curves, with the images (slice, frame) they lie on.
struct StackCurves {
    contours: Vec<Drawing>,
    /// Frames and slices of the stack's curve arrays (the largest of them).
    frames: usize,
    slices: usize,
}

fn curves(set: &Value, e: usize) -> std::result::Result<StackCurves, String> {
    let mut out = StackCurves {
        contours: Vec::new(),
        frames: 0,
        slices: 0,
    };
    for (fx, fy, kind) in CURVES {
        let (Some(xs), Some(ys)) = (set.field(e, fx), set.field(e, fy)) else {
            continue;
        };
        let (Some((dx, x)), Some((dy, y))) = (xs.numbers(), ys.numbers()) else {
            if xs.is_empty() || ys.is_empty() {
                continue;
            }
            return Err(format!("{fx}/{fy} are not numeric arrays"));
        };
        if x.is_empty() && y.is_empty() {
            continue;
        }
        if dx != dy {
            return Err(format!("{fx} is {dx:?} but {fy} is {dy:?}"));
        }
        let (n, frames, slices) = shape(dx);
        let whole = n.checked_mul(frames).and_then(|v| v.checked_mul(slices));
        if whole != Some(x.len()) || x.len() != y.len() {
            return Err(format!("{fx} holds {} values for {dx:?}", x.len()));
        }
        if frames.saturating_mul(slices) > MAX_IMAGES {
            return Err(format!("{fx} has {frames} frames x {slices} slices"));
        }
        out.frames = out.frames.max(frames);
        out.slices = out.slices.max(slices);
        for z in 0..slices {
            for t in 0..frames {
                let at = n * (t + frames * z);
                // NaN marks what is not drawn; a curve is its finite points, in order.
                let points: Vec<[f64; 2]> = (at..at + n)
                    .filter(|&k| x[k].is_finite() && y[k].is_finite())
                    .map(|k| [y[k] - 1.0, x[k] - 1.0])
                    .collect();
                if points.len() >= 3 {
                    out.contours.push(Drawing {
                        slice: z,
                        frame: Some(t),
                        kind: kind.to_string(),
                        points,
                    });
                }
            }
        }
    }
    Ok(out)
}

/// A stack's annotation points that are landmarks, one drawing each; a point placed in all
/// frames (T NaN) is on each of the stack's frames, so it is read with whichever frame its slice
/// is.
fn points(set: &Value, e: usize) -> Vec<Drawing> {
    let Some(point) = set.field(e, "Point") else {
        return Vec::new();
    };
    let coordinate = |f: &str| point.field(0, f).and_then(Value::numbers).map(|(_, d)| d);
    let (Some(x), Some(y), Some(z), Some(t), Some(Value::Cell { items: labels, .. })) = (
        coordinate("X"),
        coordinate("Y"),
        coordinate("Z"),
        coordinate("T"),
        point.field(0, "Label"),
    ) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for (k, label) in labels.iter().enumerate() {
        let (Some(label), Some(&x), Some(&y), Some(&z), Some(&t)) =
            (label.text(), x.get(k), y.get(k), z.get(k), t.get(k))
        else {
            continue;
        };
        let index = |v: f64| (v.is_finite() && v >= 1.0).then(|| v.round() as usize - 1);
        let (true, Some(z), true) = (
            landmark_of(label).is_some(),
            index(z),
            x.is_finite() && y.is_finite(),
        ) else {
            continue;
        };
        let frame = match index(t) {
            Some(t) => Some(t),
            None if t.is_nan() => None,
            None => continue,
        };
        out.push(Drawing {
            slice: z,
            frame,
            kind: label.trim().to_string(),
            points: vec![[y - 1.0, x - 1.0]],
        });
    }
    out
}

/// The frames (the main stack's, from 0) a drawing is read in: its own where the stack's frames
/// are the main stack's, else those matched to its frame; every one for a landmark of all frames.
fn frames_of(drawing: &Drawing, matched: Option<&[usize]>, frames: usize) -> Vec<usize> {
    match (drawing.frame, matched) {
        (None, _) => (0..frames).collect(),
        (Some(t), None) => vec![t],
        (Some(t), Some(m)) => (0..m.len()).filter(|&k| m[k] == t).collect(),
    }
}

/// A stack's frames and phases, for matching its frames to the main stack's.
fn cycle(set: &Value, d: &Drawn) -> Cycle {
    Cycle {
        frames: d.found.frames,
        end_diastole: frame_index(set, d.stack, "EDT"),
        end_systole: frame_index(set, d.stack, "EST"),
    }
}

fn image_uid(stack: usize, slice: usize, frame: usize) -> String {
    format!(
        "stack {} slice {} frame {}",
        stack + 1,
        slice + 1,
        frame + 1
    )
}

/// The 1-based frame a scalar field names (EDT, EST), as an index from 0.
fn frame_index(set: &Value, e: usize, field: &str) -> Option<usize> {
    let v = set.field(e, field)?.scalar()?;
    (v.is_finite() && v >= 1.0 && v.fract() == 0.0 && v <= MAX_IMAGES as f64)
        .then(|| v as usize - 1)
}

/// Reads a Segment study's LV and RV curves from its variables ([`is_segment`]), at time frame
/// `frame` (labelled from 1) or each slice's end-diastole.
pub fn read_segment(variables: &[Variable], frame: Option<&FrameChoice>) -> Result<ContourSet> {
    let set = variables
        .iter()
        .find(|v| v.name == "setstruct")
        .map(|v| &v.value)
        .ok_or_else(|| SOURCE.error("no setstruct variable"))?;
    let stacks = set.len();
    let mut warnings = Vec::new();
    let mut drawn: Vec<Drawn> = Vec::new();
    for e in 0..stacks {
        let name = stack_name(set, e);
        let found = curves(set, e).map_err(|why| SOURCE.error(format!("{name}: {why}")))?;
        if found.contours.is_empty() {
            continue;
        }
        if set
            .field(e, "Rotated")
            .and_then(Value::scalar)
            .unwrap_or(0.0)
            != 0.0
        {
            warnings.push(format!(
                "{name}: a rotated (radial) stack, whose slices Segment does not place in the \
                 patient; its {} skipped",
                count(found.contours.len(), "curve")
            ));
            continue;
        }
        let plane = plane(set, e).map_err(|why| SOURCE.error(format!("{name}: {why}")))?;
        if found.slices > 1 && plane.slice_step <= 0.0 {
            return Err(SOURCE.error(format!(
                "{name}: {} slices but SliceThickness + SliceGap is {} mm",
                found.slices, plane.slice_step
            )));
        }
        if !plane.defaulted.is_empty() {
            warnings.push(format!(
                "{name}: no {}: placed as Segment places such a stack (its first pixel at the \
                 origin, rows along x, columns along y), so other stacks' curves may not line up \
                 with its own",
                plane.defaulted.join(" or ")
            ));
        }
        drawn.push(Drawn {
            stack: e,
            name,
            plane,
            found,
        });
    }
    let read = one_per_plane(&mut drawn, &mut warnings);
    let Some(main) = read.first().map(|d| d.stack) else {
        return Err(SOURCE.error(format!(
            "none of its {} has an LV or RV contour (EndoX, EpiX, RVEndoX, RVEpiX)",
            count(stacks, "image stack")
        )));
    };
    let main_cycle = cycle(set, read[0]);
    let mut contours = Vec::new();
    let mut planes: Vec<(String, ImageGeometry)> = Vec::new();
    let mut in_order: Vec<&Drawn> = read.clone();
    in_order.sort_by_key(|d| d.stack);
    for d in in_order {
        let (p, e) = (&d.plane, d.stack);
        let own = cycle(set, d);
        let matched = (e != main).then(|| match_frames(main_cycle, own)).flatten();
        if let Some(m) = &matched {
            warnings.push(matched_note(&d.name, &read[0].name, main_cycle, own, m));
        }
        let frames = matched.as_ref().map_or(d.found.frames, Vec::len);
        if frames.saturating_mul(d.found.slices) > MAX_IMAGES {
            return Err(SOURCE.error(format!(
                "{}: {} slices in each of {} frames",
                d.name, d.found.slices, frames
            )));
        }
        for z in 0..d.found.slices {
            for t in 0..frames {
                planes.push((
                    image_uid(e, z, t),
                    ImageGeometry {
                        uid: image_uid(e, z, t),
                        position: p.slice_origin(z),
                        row_dir: p.row_dir,
                        col_dir: p.col_dir,
                        pixel_spacing: p.spacing,
                        series: Some(e as i64),
                        series_description: Some(d.name.clone()),
                        instance: Some(t as i64),
                        trigger_ms: Some(t as f64),
                    },
                ));
            }
        }
        let drawings = d.found.contours.iter().cloned().chain(points(set, e));
        for drawing in drawings {
            for t in frames_of(&drawing, matched.as_deref(), frames) {
                contours.push(PixelContour {
                    image_uid: image_uid(e, drawing.slice, t),
                    kind: drawing.kind.clone(),
                    points: drawing.points.clone(),
                });
            }
        }
    }
    let ed = frame_index(set, main, "EDT");
    let es = frame_index(set, main, "EST");
    let images = Images::from_planes(
        planes
            .iter()
            .map(|(n, g)| (n.as_str(), g.clone()))
            .collect(),
    );
    let mut set_out = place_preferring(&SOURCE, &contours, &images, &warnings, frame, ed)?;
    if let Some(tf) = set_out.time_frames.as_mut() {
        let listed = |f: Option<usize>| {
            let label = (f? + SOURCE.first_frame).to_string();
            tf.frames.contains(&label).then_some(label)
        };
        (tf.end_diastole, tf.end_systole) = (listed(ed), listed(es));
    }
    if let (Some(ed), Some(es)) = (ed, es) {
        set_out.warnings.insert(
            1.min(set_out.warnings.len()),
            format!(
                "{PHASES} is frame {}, its end-systole frame {} ({})",
                ed + 1,
                es + 1,
                stack_name(set, main)
            ),
        );
    }
    Ok(set_out)
}

/// The note on a stack whose frames were matched to the main stack's, frames named from 1.
fn matched_note(name: &str, main_name: &str, main: Cycle, own: Cycle, m: &[usize]) -> String {
    let phase = |what: &str, at: Option<usize>| {
        at.filter(|&f| f < m.len())
            .map(|f| format!("{what}: its frame {} = frame {}", m[f] + 1, f + 1))
    };
    let phases: Vec<String> = [
        phase("end-diastole", main.end_diastole),
        phase("end-systole", main.end_systole),
    ]
    .into_iter()
    .flatten()
    .collect();
    format!(
        "{MATCHED}{name}'s {} to {main_name}'s {} ({})",
        count(own.frames, "frame"),
        main.frames,
        if phases.is_empty() {
            "in proportion".to_string()
        } else {
            phases.join("; ")
        }
    )
}

/// A stack with curves, placed.
struct Drawn {
    stack: usize,
    name: String,
    plane: Plane,
    found: StackCurves,
}

/// Stacks whose planes repeat a more drawn stack's (normals within this angle)...
const PARALLEL_DEG: f64 = 10.0;
/// ...with a slice this close to one of its slices, or half its slice step if that is more.
const SAME_SLICE_MM: f64 = 2.0;

/// The stacks to read, the most drawn first: a stack whose slices repeat those of a more drawn
/// one (a study keeps the late-enhancement short axis, drawn for its scar, beside the cine one,
/// on the same planes) would interleave another acquisition's, another phase's, curves with
/// the main stack's, so it is left out with a warning; stacks that add planes (long-axis views,
/// short-axis slices acquired as a stack of their own) are read.
fn one_per_plane<'d>(drawn: &'d mut [Drawn], warnings: &mut Vec<String>) -> Vec<&'d Drawn> {
    drawn.sort_by_key(|d| std::cmp::Reverse(d.found.contours.len()));
    let cos = PARALLEL_DEG.to_radians().cos();
    let mut read: Vec<&Drawn> = Vec::new();
    for d in drawn.iter() {
        let n = d.plane.normal();
        let repeats = read.iter().find(|r| {
            let m = r.plane.normal();
            let near = SAME_SLICE_MM.max(r.plane.slice_step / 2.0);
            n.dot(&m).abs() >= cos
                && (0..d.found.slices).any(|z| {
                    let h = d.plane.slice_origin(z).dot(&m);
                    (0..r.found.slices).any(|w| (r.plane.slice_origin(w).dot(&m) - h).abs() < near)
                })
        });
        match repeats {
            Some(r) => warnings.push(format!(
                "{}: its {} not read: its slices repeat those of {}, which has more (another \
                 acquisition of the same planes, such as late enhancement); remove either stack \
                 in Segment to read the other",
                d.name,
                count(d.found.contours.len(), "curve"),
                r.name
            )),
            None => read.push(d),
        }
    }
    read
}

mod phases;

#[cfg(test)]
mod tests;
