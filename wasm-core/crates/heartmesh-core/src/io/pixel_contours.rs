//! Contours drawn in the pixels of DICOM images (a cvi42 workspace, the Sunnybrook data's text
//! files), placed in patient millimetres by their images' planes: pixel (x, y) is
//! ImagePositionPatient + x column spacings along the rows + y row spacings along the columns, 0 at
//! the first pixel's centre (DICOM PS3.3 C.7.6.2), in DICOM patient coordinates (LPS, mm).
//!
//! The contour files do not say which slice or cine frame an image is; the images do. Images
//! sharing a series and a plane are a cine slice, ordered by Trigger Time (then Instance Number),
//! and an image's frame is its place in that order from 0 (frame 0 is usually end-diastole).
//! Without `--frame`, each slice keeps one contoured frame, as GPFiles do ([`super::frames`]):
//! the frame in which the most surfaces are drawn where the slice has it, else its earliest. Each format only reads its own files into [`PixelContour`]s and names
//! its contour types ([`Source`]); the rest is here, once.

use std::collections::{BTreeMap, HashMap};

use super::builder::ContourBuilder;
use super::dicom_image::{image_geometry, ImageGeometry, NoGeometry};
use super::frame_choice::FrameChoice;
use super::frames::FrameFilter;
use crate::contours::ContourSet;
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;

/// One contour of one image, as its file stores it: pixel coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct PixelContour {
    pub image_uid: String,
    /// The contour's type as its format names it (`saendocardialContour`, `icontour`, ...).
    pub kind: String,
    /// (column, row) in pixels.
    pub points: Vec<[f64; 2]>,
}

/// What a format's contours are, for the messages and for the surfaces they become.
pub struct Source {
    /// How messages name the contours ("cvi42 workspace").
    pub what: &'static str,
    /// How the reader's account of what it read begins (a note: [`super::is_reading_note`]).
    pub note: &'static str,
    /// The surface a contour type delineates, or what it is when it is none of the four.
    pub surface_of: fn(&str) -> std::result::Result<&'static str, &'static str>,
    /// The landmark a point type is read as (None: a curve, or a type not used).
    pub landmark_of: fn(&str) -> Option<&'static str>,
    /// What the note calls an image ("DICOM image").
    pub image: &'static str,
    /// The label of a slice's first frame: 0 where frames are counted in the images' time
    /// order, 1 where the format numbers them from 1 as its software shows them (Segment).
    pub first_frame: usize,
}

impl Source {
    pub fn error(&self, message: impl Into<String>) -> CoreError {
        CoreError::parse(0, format!("{}: {}", self.what, message.into()))
    }
}

/// The images among the files given with the contours, and the files that placed none.
#[derive(Default)]
pub struct Images<'a> {
    /// (file name, plane) of every DICOM image with an image plane, in the order given.
    pub placed: Vec<(&'a str, ImageGeometry)>,
    not_dicom: Vec<String>,
    no_plane: Vec<String>,
    /// How many files were given (images or not).
    given: usize,
}

impl<'a> Images<'a> {
    /// Images whose planes the contour file itself gives (a Segment study's stacks).
    pub fn from_planes(placed: Vec<(&'a str, ImageGeometry)>) -> Self {
        Images {
            given: placed.len(),
            placed,
            ..Images::default()
        }
    }

    /// Reads the plane of every file (headers are enough); files that are not DICOM images (a
    /// DICOMDIR, notes) are kept aside by reason, for the warnings.
    pub fn read(files: &[(&'a str, &[u8])]) -> Self {
        let mut out = Images {
            given: files.len(),
            ..Images::default()
        };
        for &(name, data) in files {
            match image_geometry(data) {
                Ok(g) => out.placed.push((name, g)),
                Err(NoGeometry::NotDicom) => out.not_dicom.push(name.to_string()),
                Err(NoGeometry::Missing { .. }) => out.no_plane.push(name.to_string()),
                Err(NoGeometry::Invalid { why, .. }) => {
                    out.no_plane.push(format!("{name} ({why})"));
                }
            }
        }
        out
    }

    fn set_aside(&self) -> usize {
        self.not_dicom.len() + self.no_plane.len()
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
fn slices_and_frames<'g>(
    images: impl Iterator<Item = &'g ImageGeometry>,
) -> HashMap<&'g str, (usize, usize)> {
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

/// "1 image", "2 images".
pub fn count(n: usize, what: &str) -> String {
    format!("{n} {what}{}", if n == 1 { "" } else { "s" })
}

/// The first three names, then "...".
pub fn listed(names: &[String]) -> String {
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

/// The contours placed on `images` as one contour set. `warnings` (the format's own: repeats,
/// files it could not match) follow the frames' warnings; contours on images not given are
/// skipped with one.
pub fn place(
    source: &Source,
    contours: &[PixelContour],
    images: &Images,
    warnings: &[String],
    frame: Option<&FrameChoice>,
) -> Result<ContourSet> {
    place_preferring(source, contours, images, warnings, frame, None)
}

/// [`place`], each slice read at frame `preferred` (from 0, in time order) where it has
/// contours there and no frame is asked for: the end-diastole a format records (Segment's EDT).
pub fn place_preferring(
    source: &Source,
    contours: &[PixelContour],
    images: &Images,
    warnings: &[String],
    frame: Option<&FrameChoice>,
    preferred: Option<usize>,
) -> Result<ContourSet> {
    let geometries = || images.placed.iter().map(|(_, g)| g);
    let places = slices_and_frames(geometries());
    let by_uid: HashMap<&str, &ImageGeometry> = geometries().map(|g| (g.uid.as_str(), g)).collect();

    let mut placed: Vec<(usize, usize, &PixelContour)> = Vec::new();
    let mut marks: Vec<(usize, usize, &PixelContour, &'static str)> = Vec::new();
    let mut missing: Vec<&str> = Vec::new();
    let mut skipped: BTreeMap<&'static str, Vec<&str>> = BTreeMap::new();
    for c in contours {
        let place = places.get(c.image_uid.as_str());
        if let Some(name) = (source.landmark_of)(&c.kind) {
            // A landmark on an image not given is no reason to ask for it: only curves are.
            if let Some(&(slice, f)) = place {
                marks.push((slice, f, c, name));
            }
            continue;
        }
        match (place, (source.surface_of)(&c.kind)) {
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
        let aside_names: Vec<String> = images
            .not_dicom
            .iter()
            .chain(&images.no_plane)
            .cloned()
            .collect();
        let why = if missing.is_empty() {
            "no contour of a ventricular surface (LV or RV endo- or epicardium)".to_string()
        } else if images.placed.is_empty() {
            format!(
                "none of the {} files given with it is a DICOM image with an image plane ({}); \
                 give the images its contours were drawn on",
                images.given,
                listed(&aside_names)
            )
        } else {
            format!(
                "none of the {} images its ventricular contours were drawn on is among the {} \
                 DICOM images given (first: {}); give the study's images",
                missing.len(),
                images.placed.len(),
                missing[0]
            )
        };
        return Err(source.error(why));
    }
    // Without a frame asked for, each slice reads its first frame in this order: the frame in
    // which the most surfaces are drawn first (end-diastole, where readers draw the epicardium
    // too: Sunnybrook's experts drew it at end-diastole only, on some cases' last frame), then by
    // time; the earliest of those that tie (frame 0 is usually end-diastole).
    let drawn_at = |f: usize| placed.iter().any(|&(_, at, _)| at == f);
    let preferred = preferred.filter(|&f| drawn_at(f)).unwrap_or_else(|| {
        let mut per_frame: BTreeMap<usize, Vec<&str>> = BTreeMap::new();
        for &(_, f, c) in &placed {
            let surfaces = per_frame.entry(f).or_default();
            if let Ok(s) = (source.surface_of)(&c.kind) {
                if !surfaces.contains(&s) {
                    surfaces.push(s);
                }
            }
        }
        per_frame
            .iter()
            .max_by(|a, b| a.1.len().cmp(&b.1.len()).then(b.0.cmp(a.0)))
            .map_or(0, |(&f, _)| f)
    });
    placed.sort_by_key(|&(slice, f, _)| (slice, f != preferred, f));
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
    let others = if images.set_aside() > 0 {
        format!(
            "; {} given with it set aside",
            count(images.set_aside(), "other file")
        )
    } else {
        String::new()
    };
    b.warn(format!(
        "{}{}: contours on {drawn_on} of them, in {}{others}",
        source.note,
        count(images.placed.len(), source.image),
        count(drawn_slices, "cine slice")
    ));
    let mut frames = FrameFilter::new(frame);
    // The frame each slice's curves were read from: its landmarks are read from that frame only.
    let mut read_frame: HashMap<usize, usize> = HashMap::new();
    for (slice, f, c) in placed {
        let surface = (source.surface_of)(&c.kind).ok();
        let (slice_id, label) = (format!("s{slice:02}"), (f + source.first_frame).to_string());
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
    for w in warnings {
        b.warn(w.clone());
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
    if !images.not_dicom.is_empty() {
        b.warn(format!(
            "{} set aside: not DICOM ({})",
            count(images.not_dicom.len(), "file"),
            listed(&images.not_dicom)
        ));
    }
    if !images.no_plane.is_empty() {
        b.warn(format!(
            "{} set aside: no image plane ({})",
            count(images.no_plane.len(), "DICOM file"),
            listed(&images.no_plane)
        ));
    }
    let mut set = b.finish()?;
    set.time_frames = frames.time_frames().map(|mut tf| {
        // In time order for the frame picker, whichever was read first.
        tf.frames
            .sort_by_key(|f| f.parse::<usize>().unwrap_or(usize::MAX));
        tf
    });
    Ok(set)
}
