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

use roxmltree::{Document, Node};

use super::frame_choice::FrameChoice;
pub use super::pixel_contours::PixelContour;
use super::pixel_contours::{count, place, Images, Source};
use crate::contours::ContourSet;
use crate::error::{CoreError, Result};

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

fn err(message: impl Into<String>) -> CoreError {
    SOURCE.error(message)
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

/// The cvi42 workspace's contour types, for the placement on the images.
const SOURCE: Source = Source {
    what: "cvi42 workspace",
    note: NOTE,
    surface_of,
    landmark_of,
    image: "DICOM image",
    first_frame: 0,
};

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
    let images = Images::read(files);
    let repeated = (repeats > 0).then(|| {
        format!(
            "{} stored again under another study map of the workspace read once",
            count(repeats, "contour")
        )
    });
    place(&SOURCE, &contours, &images, repeated.as_slice(), frame)
}

#[cfg(test)]
mod tests;
