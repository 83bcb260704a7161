//! The Sunnybrook Cardiac Data (Radau et al. 2009: the MICCAI 2009 LV segmentation challenge, 45
//! cine MRI studies with expert contours, public domain, in the Cardiac Atlas Project): one text
//! file per image and contour type, `IM-0001-0048-icontour-manual.txt`, a line `x y` per point in
//! pixels (column, row; 0 at the first pixel's centre, as the data's own evaluation fills them),
//! `icontour` the LV endocardium, `ocontour` the epicardium, `p1contour` / `p2contour` the
//! papillary muscles.
//!
//! The files do not say where their images lie: they are read with the DICOM images of the cine
//! short-axis series they were drawn on ([`super::pixel_contours`] places them and tells slices
//! and frames apart). The number after the contours' `IM-0001` (0048) is the image's number in
//! that series: the image file `IM-SSSS-0048.dcm` of the series (the series part differs from the
//! contours' 0001), or for images named otherwise the one whose Instance Number is 48. A patient's
//! folder holds several series numbered alike; the one holding the most of the contours' images
//! (at least half) is theirs.

use std::collections::BTreeMap;

use super::frame_choice::FrameChoice;
use super::pixel_contours::{count, listed, place, Images, PixelContour, Source};
use super::text;
use crate::contours::ContourSet;
use crate::error::{CoreError, Result};

/// How the reader's account of what it read begins (a note: [`super::is_reading_note`]).
pub const NOTE: &str = "Sunnybrook contours read with ";

/// The refusal of contour files opened without their images.
pub const NEEDS_IMAGES: &str = "Sunnybrook contours are in the pixels of their images: open the \
    contour files together with the DICOM images they were drawn on (the case's contours folder \
    and its short-axis cine series, both at once)";

const SOURCE: Source = Source {
    what: "Sunnybrook contours",
    note: NOTE,
    surface_of,
    landmark_of,
    image: "DICOM image",
    first_frame: 0,
};

/// The surface a Sunnybrook contour type delineates, or what it is when it is none.
pub fn surface_of(kind: &str) -> std::result::Result<&'static str, &'static str> {
    match kind.to_ascii_lowercase().as_str() {
        "icontour" => Ok("LV_ENDO"),
        "ocontour" => Ok("LV_EPI"),
        "p1contour" | "p2contour" => Err("papillary muscles"),
        _ => Err("not a Sunnybrook contour type (icontour, ocontour)"),
    }
}

fn landmark_of(_: &str) -> Option<&'static str> {
    None
}

/// A file name's last part (after `/` or `\`: paths, ZIP members).
fn base_name(path: &str) -> &str {
    path.rsplit(['/', '\\']).next().unwrap_or(path)
}

/// `IM-<series>-<number>` at the start of a name: (series, number). Both runs of digits, at most 9.
fn im_numbers(name: &str) -> Option<(&str, u32, &str)> {
    let rest = name
        .get(..3)
        .filter(|p| p.eq_ignore_ascii_case("im-"))
        .map(|_| &name[3..])?;
    let digits = |s: &str| s.bytes().take_while(u8::is_ascii_digit).count();
    let n = digits(rest);
    if n == 0 || n > 9 || rest.as_bytes().get(n) != Some(&b'-') {
        return None;
    }
    let series = &rest[..n];
    let rest = &rest[n + 1..];
    let m = digits(rest);
    if m == 0 || m > 9 {
        return None;
    }
    Some((series, rest[..m].parse().ok()?, &rest[m..]))
}

/// The image number and contour type a Sunnybrook contour file's name gives
/// (`IM-0001-0048-icontour-manual.txt` -> (48, "icontour")); None for other names.
pub fn contour_name(path: &str) -> Option<(u32, &str)> {
    let name = base_name(path);
    let (_, number, rest) = im_numbers(name)?;
    let stem = rest.strip_prefix('-')?;
    let stem = stem
        .get(stem.len().checked_sub(4)?..)
        .filter(|e| e.eq_ignore_ascii_case(".txt"))
        .map(|_| &stem[..stem.len() - 4])?;
    let kind = stem.split('-').next()?;
    let ok = kind.len() > "contour".len()
        && kind.to_ascii_lowercase().ends_with("contour")
        && kind.bytes().all(|b| b.is_ascii_alphanumeric());
    ok.then_some((number, kind))
}

/// Whether a file is a Sunnybrook contour file: its name, and a first line of two numbers.
pub fn is_contour_file(path: &str, bytes: &[u8]) -> bool {
    contour_name(path).is_some()
        && text::data_lines(&text::head(bytes, 256))
            .next()
            .is_some_and(|(_, l)| {
                let f = fields(l);
                f.len() == 2 && f.iter().all(|v| v.parse::<f64>().is_ok())
            })
}

fn fields(line: &str) -> Vec<&str> {
    line.split(|c: char| c.is_whitespace() || c == ',')
        .filter(|f| !f.is_empty())
        .collect()
}

/// The points of one contour file, `x y` a line.
fn read_points(name: &str, bytes: &[u8]) -> Result<Vec<[f64; 2]>> {
    let at = |line: usize, m: String| CoreError::parse(0, format!("{name}, line {line}: {m}"));
    let text = text::decode(bytes).map_err(|e| CoreError::parse(0, format!("{name}: {e}")))?;
    let mut points = Vec::new();
    for (line, l) in text::data_lines(&text) {
        let f = fields(l);
        if f.len() != 2 {
            return Err(at(
                line,
                format!(
                    "expected two numbers (x y, in pixels), found {} fields",
                    f.len()
                ),
            ));
        }
        let x = text::parse_coord(f[0], line, "x").map_err(|e| at(line, strip_line(e)))?;
        let y = text::parse_coord(f[1], line, "y").map_err(|e| at(line, strip_line(e)))?;
        points.push([x, y]);
    }
    if points.is_empty() {
        return Err(CoreError::parse(0, format!("{name}: no points")));
    }
    Ok(points)
}

/// A parse error's message without its line (the caller puts the file and line in front).
fn strip_line(e: CoreError) -> String {
    match e {
        CoreError::Parse { message, .. } => message,
        other => other.to_string(),
    }
}

/// Which image a contour file's number names: images named `IM-SSSS-NNNN` by their name (series
/// SSSS), others by their Series and Instance Numbers.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
enum Series {
    Named(String),
    Number(Option<i64>),
}

fn numbered(name: &str, series: Option<i64>, instance: Option<i64>) -> Option<(Series, u32)> {
    if let Some((s, n, _)) = im_numbers(base_name(name)) {
        return Some((Series::Named(s.to_string()), n));
    }
    let n = u32::try_from(instance?).ok()?;
    Some((Series::Number(series), n))
}

fn series_text(s: &Series) -> String {
    match s {
        Series::Named(s) => format!("IM-{s}-*"),
        Series::Number(Some(n)) => format!("series {n}"),
        Series::Number(None) => "images without a series number".into(),
    }
}

/// Reads Sunnybrook contour files with the DICOM images they were drawn on: `files` holds the other
/// contour files and the images (headers are enough), in any order; files of neither kind are set
/// aside with a warning.
pub fn read_sunnybrook(
    name: &str,
    bytes: &[u8],
    files: &[(&str, &[u8])],
    frame: Option<&FrameChoice>,
) -> Result<ContourSet> {
    let mut contour_files: Vec<(&str, &[u8])> = vec![(name, bytes)];
    let mut others: Vec<(&str, &[u8])> = Vec::new();
    for &(n, b) in files {
        if contour_name(n).is_some() {
            contour_files.push((n, b));
        } else {
            others.push((n, b));
        }
    }
    // One case, one reader: the same file name twice is two cases' or two readers' contours.
    let mut by_name: BTreeMap<&str, &str> = BTreeMap::new();
    for &(n, _) in &contour_files {
        if let Some(first) = by_name.insert(base_name(n), n) {
            return Err(SOURCE.error(format!(
                "{} is given twice ({first} and {n}): open one case's contours, of one reader, \
                 at a time",
                base_name(n)
            )));
        }
    }
    if others.is_empty() {
        return Err(SOURCE.error(NEEDS_IMAGES));
    }
    let images = Images::read(&others);
    // Each series' images by number; the series holding the most of the contours' numbers.
    let mut series: BTreeMap<Series, BTreeMap<u32, &str>> = BTreeMap::new();
    for (n, g) in &images.placed {
        if let Some((s, k)) = numbered(n, g.series, g.instance) {
            series
                .entry(s)
                .or_default()
                .entry(k)
                .or_insert(g.uid.as_str());
        }
    }
    let mut wanted: Vec<u32> = contour_files
        .iter()
        .filter_map(|(n, _)| contour_name(n).map(|(k, _)| k))
        .collect();
    wanted.sort_unstable();
    wanted.dedup();
    let held = |s: &BTreeMap<u32, &str>| wanted.iter().filter(|k| s.contains_key(k)).count();
    let mut ranked: Vec<(&Series, usize)> = series.iter().map(|(s, m)| (s, held(m))).collect();
    ranked.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
    let numbers = || {
        let shown: Vec<String> = wanted.iter().take(4).map(|k| format!("{k:04}")).collect();
        format!(
            "{}{}",
            shown.join(", "),
            if wanted.len() > 4 { ", ..." } else { "" }
        )
    };
    let chosen = match ranked[..] {
        [] | [(_, 0), ..] => {
            let why = if images.placed.is_empty() {
                format!(
                    "none of the {} other files given is a DICOM image with an image plane; \
                     give the images the contours were drawn on",
                    others.len()
                )
            } else {
                format!(
                    "none of the {} DICOM images given is numbered as the contour files' images \
                     ({}): give the short-axis cine series they were drawn on",
                    images.placed.len(),
                    numbers()
                )
            };
            return Err(SOURCE.error(why));
        }
        [(a, n), (b, m), ..] if n == m => {
            return Err(SOURCE.error(format!(
                "the contour files' images ({}) are in two series alike ({} and {}): give only \
                 the short-axis cine series they were drawn on",
                numbers(),
                series_text(a),
                series_text(b)
            )))
        }
        // A series holding few of them is another acquisition numbered alike (a long-axis cine
        // series runs 1-20 as the stack's first slice does), not theirs.
        [(s, n), ..] if 2 * n < wanted.len() => {
            return Err(SOURCE.error(format!(
                "the DICOM images given hold only {} of the {} images the contour files were \
                 drawn on ({}, in {}): give the short-axis cine series they were drawn on",
                n,
                wanted.len(),
                numbers(),
                series_text(s)
            )))
        }
        [(s, _), ..] => s.clone(),
    };
    let uids = &series[&chosen];
    let mut contours = Vec::new();
    let mut unmatched: Vec<String> = Vec::new();
    for (n, b) in &contour_files {
        let Some((k, kind)) = contour_name(n) else {
            continue;
        };
        let points = read_points(base_name(n), b)?;
        match uids.get(&k) {
            Some(uid) => contours.push(PixelContour {
                image_uid: uid.to_string(),
                kind: kind.to_ascii_lowercase(),
                points,
            }),
            None => unmatched.push(base_name(n).to_string()),
        }
    }
    let mut warnings = Vec::new();
    if !unmatched.is_empty() {
        unmatched.sort();
        warnings.push(format!(
            "{} skipped: no image of their number in {} ({})",
            count(unmatched.len(), "contour file"),
            series_text(&chosen),
            listed(&unmatched)
        ));
    }
    place(&SOURCE, &contours, &images, &warnings, frame)
}

#[cfg(test)]
mod tests;
