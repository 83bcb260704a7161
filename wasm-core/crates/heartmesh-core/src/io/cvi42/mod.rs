//! Circle cvi42 workspaces (`.cvi42wsx`): the contours of the most used clinical CMR software,
//! and the manual contours of UK Biobank's cardiac studies.
//!
//! A workspace is XML. Under an element keyed (`Hash:key`) `ImageStates`, each image is keyed by
//! its DICOM SOP Instance UID and holds `Contours`: each keyed by its type
//! (`saendocardialContour`, `sarvendocardialContour`, `laepicardialContour`, ...), with
//! `SubpixelResolution` and `Points`, each point's `Point:x` (column) and `Point:y` (row) in
//! pixels times the subpixel resolution. The workspace does not say where its images lie, so it is
//! read with the DICOM images it was drawn on ([`super::dicom_image`]): pixel (x, y) is
//! ImagePositionPatient + x column spacings along the rows + y row spacings along the columns,
//! 0 at the first pixel's centre (DICOM PS3.3 C.7.6.2), in DICOM patient coordinates (LPS, mm).
//!
//! Each image is one time frame of one slice: images sharing a series and a plane are a cine
//! slice, ordered by Trigger Time (then Instance Number), and an image's frame is its place in
//! that order from 0 (frame 0 is usually end-diastole). Without `--frame`, each slice keeps its
//! first contoured frame, as GPFiles do ([`super::frames`]).

use std::collections::{BTreeMap, HashMap};

use roxmltree::{Document, Node};

use super::builder::ContourBuilder;
use super::dicom_image::{image_geometry, ImageGeometry, NoGeometry};
use super::frame_choice::FrameChoice;
use super::frames::FrameFilter;
use crate::contours::ContourSet;
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;

/// The namespace every cvi42 workspace declares, which tells it from other XML.
const NAMESPACE: &str = "circlecvi.com/cvi42/Workspace";

/// True when the bytes start like a cvi42 workspace (its namespace in the first 4 KiB).
pub fn is_cvi42(bytes: &[u8]) -> bool {
    let head = &bytes[..bytes.len().min(4096)];
    let head = String::from_utf8_lossy(head);
    head.trim_start_matches('\u{feff}')
        .trim_start()
        .starts_with('<')
        && head.contains(NAMESPACE)
}

/// How the reader's account of what it read begins (a note, not a warning: [`super::is_reading_note`]).
pub const NOTE: &str = "workspace read with ";

/// The refusal of a workspace opened without its images.
pub const NEEDS_IMAGES: &str = "a cvi42 workspace holds its contours in the pixels of its \
    images: open it together with the DICOM images it was drawn on (the study's folder)";

/// One contour of one image, as the workspace stores it: pixel coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct PixelContour {
    pub image_uid: String,
    /// The contour's type (`saendocardialContour`, ...).
    pub kind: String,
    /// (column, row) in pixels.
    pub points: Vec<[f64; 2]>,
}

fn err(message: impl Into<String>) -> CoreError {
    CoreError::parse(0, format!("cvi42 workspace: {}", message.into()))
}

/// The `Hash:key` of an element (any prefix bound to the hash namespace, or none).
fn key<'a>(node: &Node<'a, '_>) -> Option<&'a str> {
    node.attributes()
        .find(|a| a.name() == "key")
        .map(|a| a.value())
}

fn child<'a, 'i>(node: &Node<'a, 'i>, name: &str) -> Option<Node<'a, 'i>> {
    node.children()
        .find(|c| c.is_element() && key(c) == Some(name))
}

/// The number in an element's text.
fn number(node: &Node) -> Option<f64> {
    node.text()?
        .trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
}

/// A point item's (x, y): its child elements named `x` and `y` (namespace `Point`).
fn point(item: &Node) -> Option<[f64; 2]> {
    let coord = |n: &str| {
        item.descendants()
            .find(|c| c.is_element() && c.tag_name().name() == n)
            .and_then(|c| number(&c))
    };
    Some([coord("x")?, coord("y")?])
}

/// Every contour of the workspace, in pixel coordinates, in document order, and how many were
/// repeats: a workspace may hold an image's state under several study maps (UK Biobank's keep
/// them under `StudyMapStates`), and a curve read twice would weigh twice.
pub fn read_pixel_contours(bytes: &[u8]) -> Result<(Vec<PixelContour>, usize)> {
    let text = super::text::decode(bytes)?;
    let doc = Document::parse(&text).map_err(|e| {
        let p = e.pos();
        CoreError::parse(
            p.row as usize,
            format!("cvi42 workspace: not valid XML: {e}"),
        )
    })?;
    let mut out = Vec::new();
    let mut seen = std::collections::HashSet::new();
    let mut repeats = 0usize;
    let mut bad_resolution = 0usize;
    for states in doc
        .descendants()
        .filter(|n| n.is_element() && key(n) == Some("ImageStates"))
    {
        for image in states.children().filter(Node::is_element) {
            let Some(uid) = key(&image) else { continue };
            let Some(contours) = child(&image, "Contours") else {
                continue;
            };
            for contour in contours.children().filter(Node::is_element) {
                let Some(kind) = key(&contour) else { continue };
                let Some(points) = child(&contour, "Points") else {
                    continue;
                };
                let sub = match child(&contour, "SubpixelResolution").map(|n| number(&n)) {
                    None => 1.0,
                    Some(Some(s)) if s > 0.0 => s,
                    Some(_) => {
                        bad_resolution += 1;
                        continue;
                    }
                };
                let pts: Vec<[f64; 2]> = points
                    .children()
                    .filter(Node::is_element)
                    .filter_map(|p| point(&p))
                    .map(|[x, y]| [x / sub, y / sub])
                    .filter(|p| p.iter().all(|v| v.is_finite()))
                    .collect();
                if pts.is_empty() {
                    continue;
                }
                if !seen.insert((uid.trim(), kind)) {
                    repeats += 1;
                } else {
                    out.push(PixelContour {
                        image_uid: uid.trim().to_string(),
                        kind: kind.to_string(),
                        points: pts,
                    });
                }
            }
        }
    }
    if out.is_empty() {
        let why = if bad_resolution > 0 {
            format!("{bad_resolution} contours have no usable SubpixelResolution")
        } else {
            "no contour points under ImageStates".to_string()
        };
        return Err(err(why));
    }
    Ok((out, repeats))
}

/// The surface a cvi42 contour type delineates, or what it is when it is none of the four.
pub fn surface_of(kind: &str) -> std::result::Result<&'static str, &'static str> {
    let k = kind.to_ascii_lowercase();
    let has = |s: &str| k.contains(s);
    if has("musc") || has("papil") || has("trabec") {
        return Err("papillary muscles or trabeculae");
    }
    if has("ref") || has("extent") || has("valve") || has("diameter") || has("point") {
        return Err("reference points and landmarks");
    }
    if has("flow") || has("roi") {
        return Err("flow or signal regions");
    }
    match (has("endocardial"), has("epicardial"), has("rv")) {
        (true, false, false) => Ok("LV_ENDO"),
        (false, true, false) => Ok("LV_EPI"),
        (true, false, true) => Ok("RV_ENDO"),
        (false, true, true) => Ok("RV_EPI"),
        _ if has("lala") || has("lara") || has("atri") => Err("atria"),
        _ => Err("not a ventricular surface"),
    }
}

/// The landmark name a cvi42 point type is read as, for the types heartmesh uses: the two SAX
/// reference points are the RV insertions (cvi42's "superior" one is the anterior insertion the
/// AHA segments start from, [`crate::metrics::septum`]); the long-axis LV/RV extent points
/// (valve hinges and apex) are kept as biv-me's GPFiles keep theirs, shown and never fitted.
pub fn landmark_of(kind: &str) -> Option<&'static str> {
    match kind.to_ascii_lowercase().as_str() {
        "sacardialrefpoint" => Some("RV_INSERT_ANTERIOR"),
        "sacardialinferiorrefpoint" => Some("RV_INSERT_INFERIOR"),
        "laxlvextentpoints" => Some("LAX_LV_EXTENT"),
        "laxrvextentpoints" => Some("LAX_RV_EXTENT"),
        _ => None,
    }
}

/// Images of one cine slice: same series, same plane (position and orientation to 0.01 mm).
fn slice_key(g: &ImageGeometry) -> (Option<i64>, [i64; 9]) {
    let q = |v: f64| (v * 100.0).round() as i64;
    let (p, r, c) = (g.position, g.row_dir, g.col_dir);
    (
        g.series,
        [
            q(p.x),
            q(p.y),
            q(p.z),
            q(r.x),
            q(r.y),
            q(r.z),
            q(c.x),
            q(c.y),
            q(c.z),
        ],
    )
}

/// Each image's slice number (from 1: by series, then along the plane's normal) and frame (from 0:
/// by trigger time, then instance number, within its slice).
fn slices_and_frames(images: &[ImageGeometry]) -> HashMap<&str, (usize, usize)> {
    let mut slices: BTreeMap<(Option<i64>, [i64; 9]), Vec<&ImageGeometry>> = BTreeMap::new();
    for g in images {
        slices.entry(slice_key(g)).or_default().push(g);
    }
    let mut order: Vec<(Option<i64>, f64, Vec<&ImageGeometry>)> = slices
        .into_values()
        .map(|mut frames| {
            frames.sort_by(|a, b| {
                let t = |g: &ImageGeometry| g.trigger_ms.unwrap_or(f64::NAN);
                t(a).total_cmp(&t(b))
                    .then(a.instance.cmp(&b.instance))
                    .then(a.uid.cmp(&b.uid))
            });
            let g = frames[0];
            (g.series, g.position.dot(&g.normal()), frames)
        })
        .collect();
    order.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut out = HashMap::new();
    for (n, (_, _, frames)) in order.iter().enumerate() {
        for (f, g) in frames.iter().enumerate() {
            out.entry(g.uid.as_str()).or_insert((n + 1, f));
        }
    }
    out
}

/// Files given with a workspace that placed no image, by reason, for one warning line.
#[derive(Default)]
struct SetAside {
    not_dicom: Vec<String>,
    no_plane: Vec<String>,
}

/// "1 image", "2 images".
fn count(n: usize, what: &str) -> String {
    format!("{n} {what}{}", if n == 1 { "" } else { "s" })
}

fn listed(names: &[String]) -> String {
    let shown: Vec<&str> = names.iter().take(3).map(String::as_str).collect();
    let more = if names.len() > 3 { ", ..." } else { "" };
    format!("{}{more}", shown.join(", "))
}

/// The landmarks of the frames the curves were read from: a reference point of another frame
/// (cvi42 keeps one per image) would place the septum of another phase, and one on a slice no
/// curve was read from has no frame to belong to.
fn landmarks(
    b: &mut ContourBuilder,
    marks: &[(usize, usize, &PixelContour, &'static str)],
    read_frame: &HashMap<usize, usize>,
    by_uid: &HashMap<&str, &ImageGeometry>,
) -> Result<()> {
    for &(slice, f, c, name) in marks {
        if read_frame.get(&slice) != Some(&f) {
            continue;
        }
        let g = by_uid[c.image_uid.as_str()];
        for &[x, y] in &c.points {
            b.landmark(name, g.to_patient(x, y), 0)?;
        }
    }
    Ok(())
}

/// Reads a cvi42 workspace with the DICOM images (`(file name, bytes)`, headers are enough) its
/// contours were drawn on. Files that are not DICOM images (a DICOMDIR, notes) are set aside with
/// a warning; contours on images not given are skipped with one.
pub fn read_cvi42(
    bytes: &[u8],
    files: &[(&str, &[u8])],
    frame: Option<&FrameChoice>,
) -> Result<ContourSet> {
    let (contours, repeats) = read_pixel_contours(bytes)?;
    if files.is_empty() {
        return Err(err(NEEDS_IMAGES));
    }
    let mut images = Vec::new();
    let mut aside = SetAside::default();
    for (name, data) in files {
        match image_geometry(data) {
            Ok(g) => images.push(g),
            Err(NoGeometry::NotDicom) => aside.not_dicom.push(name.to_string()),
            Err(NoGeometry::Missing { .. }) => aside.no_plane.push(name.to_string()),
            Err(NoGeometry::Invalid { why, .. }) => {
                aside.no_plane.push(format!("{name} ({why})"));
            }
        }
    }
    let places = slices_and_frames(&images);
    let by_uid: HashMap<&str, &ImageGeometry> =
        images.iter().map(|g| (g.uid.as_str(), g)).collect();

    // Contours in slice, then frame order: each slice's first frame is then its earliest.
    let mut placed: Vec<(usize, usize, &PixelContour)> = Vec::new();
    let mut marks: Vec<(usize, usize, &PixelContour, &'static str)> = Vec::new();
    let mut missing: Vec<&str> = Vec::new();
    let mut skipped: BTreeMap<&'static str, Vec<&str>> = BTreeMap::new();
    for c in &contours {
        let place = places.get(c.image_uid.as_str());
        if let Some(name) = landmark_of(&c.kind) {
            // A landmark on an image not given is no reason to ask for it: only curves are.
            if let Some(&(slice, f)) = place {
                marks.push((slice, f, c, name));
            }
            continue;
        }
        match (place, surface_of(&c.kind)) {
            (_, Err(what)) => {
                let kinds = skipped.entry(what).or_default();
                if !kinds.contains(&c.kind.as_str()) {
                    kinds.push(&c.kind);
                }
            }
            (None, Ok(_)) => {
                if !missing.contains(&c.image_uid.as_str()) {
                    missing.push(&c.image_uid);
                }
            }
            (Some(&(slice, f)), Ok(_)) => placed.push((slice, f, c)),
        }
    }
    if placed.is_empty() {
        let aside_names: Vec<String> = aside
            .not_dicom
            .iter()
            .chain(&aside.no_plane)
            .cloned()
            .collect();
        let why = if missing.is_empty() {
            "no contour of a ventricular surface (LV or RV endo- or epicardium)".to_string()
        } else if images.is_empty() {
            format!(
                "none of the {} files given with it is a DICOM image with an image plane ({}); \
                 give the images its contours were drawn on",
                files.len(),
                listed(&aside_names)
            )
        } else {
            format!(
                "none of the {} images its ventricular contours were drawn on is among the {} \
                 DICOM images given (first: {}); give the study's images",
                missing.len(),
                images.len(),
                missing[0]
            )
        };
        return Err(err(why));
    }
    placed.sort_by_key(|&(slice, f, _)| (slice, f));
    let drawn_on = {
        let mut uids: Vec<&str> = placed
            .iter()
            .map(|(_, _, c)| c.image_uid.as_str())
            .collect();
        uids.sort_unstable();
        uids.dedup();
        uids.len()
    };
    let drawn_slices = {
        let mut slices: Vec<usize> = placed.iter().map(|&(slice, _, _)| slice).collect();
        slices.dedup();
        slices.len()
    };

    let mut b = ContourBuilder::new();
    let set_aside = aside.not_dicom.len() + aside.no_plane.len();
    let others = if set_aside > 0 {
        format!(
            "; {} given with it set aside",
            count(set_aside, "other file")
        )
    } else {
        String::new()
    };
    b.warn(format!(
        "{NOTE}{}: contours on {drawn_on} of them, in {}{others}",
        count(images.len(), "DICOM image"),
        count(drawn_slices, "cine slice")
    ));
    let mut frames = FrameFilter::new(frame);
    // The frame each slice's curves were read from: its landmarks are read from that frame only.
    let mut read_frame: HashMap<usize, usize> = HashMap::new();
    for (slice, f, c) in placed {
        let surface = surface_of(&c.kind).ok();
        let (slice_id, label) = (format!("s{slice:02}"), f.to_string());
        // FrameFilter counts points (its warnings say how many were left out): ask per point.
        let mut keep = false;
        for _ in &c.points {
            keep = frames.keep(&slice_id, &label);
        }
        if !keep {
            continue;
        }
        read_frame.insert(slice, f);
        let g = by_uid[c.image_uid.as_str()];
        let points: Vec<Vec3> = c.points.iter().map(|&[x, y]| g.to_patient(x, y)).collect();
        // Closed types say nothing of their ends: the end-point rule decides, as for CSV.
        let ring = c
            .kind
            .to_ascii_lowercase()
            .contains("open")
            .then_some(false);
        b.push_piece(&format!("{slice_id}_{}", c.kind), surface, points, ring, 0)?;
    }
    if let Some(e) = frames.nothing_in_wanted() {
        return Err(e);
    }
    landmarks(&mut b, &marks, &read_frame, &by_uid)?;
    for w in frames.warnings("slice") {
        b.warn(w);
    }
    if repeats > 0 {
        b.warn(format!(
            "{} stored again under another study map of the workspace read once",
            count(repeats, "contour")
        ));
    }
    if !missing.is_empty() {
        b.warn(format!(
            "contours on {} skipped: their DICOM files were not given (first UID {})",
            count(missing.len(), "image"),
            missing[0]
        ));
    }
    for (what, kinds) in &skipped {
        b.warn(format!(
            "contours of type {} skipped: {what}",
            kinds.join(", ")
        ));
    }
    if !aside.not_dicom.is_empty() {
        b.warn(format!(
            "{} set aside: not DICOM ({})",
            count(aside.not_dicom.len(), "file"),
            listed(&aside.not_dicom)
        ));
    }
    if !aside.no_plane.is_empty() {
        b.warn(format!(
            "{} set aside: no image plane ({})",
            count(aside.no_plane.len(), "DICOM file"),
            listed(&aside.no_plane)
        ));
    }
    let mut set = b.finish()?;
    set.time_frames = frames.time_frames();
    Ok(set)
}

#[cfg(test)]
mod tests;
