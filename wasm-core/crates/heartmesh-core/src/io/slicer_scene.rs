//! 3D Slicer scenes: the folder Slicer saves a scene into, or the same folder zipped as one
//! Medical Reality Bundle (`.mrb`), which is how Slicer users keep and share their work.
//!
//! The scene file (`.mrml`) only names the data files beside it, so the contours come from
//! those: the markups curves (`.mrk.json`, one file per curve; Slicer 4's point list files
//! `.fcsv` drawn along contours, [`markups::point_list_is_contour`]) when there are any, else the
//! segmentations (`.seg.nrrd`, a NIfTI label map: the label-map study reader's files). The scene
//! file, the images (intensity volumes, which a scene always holds beside its segmentations),
//! models, screenshots and the rest are set aside, named in a warning, so nothing is dropped
//! without a word. Markups mixed with other files (a scene folder whose `.mrml` was not kept) are
//! read the same way.

use super::{markups, nifti};
use crate::error::{CoreError, Result};

/// Which files of a scene to read, and which to set aside.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Indices of the files holding the contours (markups, or segmentations).
    pub read: Vec<usize>,
    /// Indices of the files set aside.
    pub aside: Vec<usize>,
    /// What the contours come from, for the warning ("the Slicer markups", "the segmentation").
    source: &'static str,
}

impl Scene {
    /// The warning naming the files set aside (None: nothing was).
    pub fn warning(&self, files: &[(&str, &[u8])]) -> Option<String> {
        if self.aside.is_empty() {
            return None;
        }
        let names: Vec<String> = self
            .aside
            .iter()
            .map(|&n| {
                let (name, bytes) = files[n];
                if is_mrml(bytes) {
                    format!("{name} (the scene file)")
                } else if is_segmentation(name, bytes) {
                    // Set aside because the scene's curves won: the user may want it instead.
                    format!("{name} (a segmentation: open it alone to read it instead)")
                } else {
                    name.to_string()
                }
            })
            .collect();
        let whose = if files.iter().any(|(_, b)| is_mrml(b)) {
            " of the Slicer scene"
        } else {
            ""
        };
        Some(format!(
            "{} other file(s){whose} set aside (the contours come from {}): {}",
            names.len(),
            self.source,
            names.join(", ")
        ))
    }
}

/// Whether a file is a 3D Slicer scene file (MRML: XML whose root element is `MRML`).
pub fn is_mrml(bytes: &[u8]) -> bool {
    let head = &bytes[..bytes.len().min(4096)];
    let mut rest = head.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(head);
    // The XML declaration and comments may come before the root.
    loop {
        rest = rest.trim_ascii_start();
        let close: &[u8] = if rest.starts_with(b"<?") {
            b"?>"
        } else if rest.starts_with(b"<!--") {
            b"-->"
        } else {
            break;
        };
        match rest.windows(close.len()).position(|w| w == close) {
            Some(at) => rest = &rest[at + close.len()..],
            None => return false,
        }
    }
    rest.len() > 5
        && rest[..5].eq_ignore_ascii_case(b"<MRML")
        && (rest[5].is_ascii_whitespace() || rest[5] == b'>' || rest[5] == b'/')
}

/// Whether a file is a Slicer segmentation (`.seg.nrrd`: a NRRD naming its segments), told
/// without reading its voxels.
fn is_segmentation(name: &str, bytes: &[u8]) -> bool {
    let head = &bytes[..bytes.len().min(1 << 16)];
    nifti::is_nrrd(bytes)
        && (name.to_ascii_lowercase().ends_with(".seg.nrrd")
            || head.windows(9).any(|w| w == b"Segment0_"))
}

/// The refusal of a scene file opened alone.
pub fn scene_file_alone() -> CoreError {
    CoreError::parse(
        0,
        "this is a 3D Slicer scene file (.mrml): it names the scene's data files and holds no \
         contours itself; open the scene's folder, or the scene saved as one .mrb bundle",
    )
}

/// What to read of `files` when they are a Slicer scene (one of them is its `.mrml`) or hold
/// markups among other files; None when they are neither (read as any other study). Markups
/// holding a curve win; else segmentations (label maps that are not images); else the markups
/// (point lists alone, which the markups reader then refuses with its reason).
pub fn select(files: &[(&str, &[u8])]) -> Result<Option<Scene>> {
    let is_markups = |n: &usize| markups::is_markups(&files[*n].1[..files[*n].1.len().min(4096)]);
    let all: Vec<usize> = (0..files.len()).collect();
    let (marks, others): (Vec<usize>, Vec<usize>) = all.iter().partition(|n| is_markups(n));
    let scene = files.iter().any(|(_, b)| is_mrml(b));
    if !scene && (marks.is_empty() || others.is_empty()) {
        return Ok(None);
    }
    let apart = |read: &[usize]| -> Vec<usize> {
        all.iter().copied().filter(|n| !read.contains(n)).collect()
    };
    if marks.iter().any(|&n| markups::holds_curves(files[n].1)) {
        return Ok(Some(Scene {
            aside: apart(&marks),
            read: marks,
            source: "the Slicer markups",
        }));
    }
    let segmentations: Vec<usize> = others
        .iter()
        .copied()
        .filter(|&n| nifti::label_map_grid(files[n].1).is_some() && !nifti::is_image(files[n].1))
        .collect();
    if !segmentations.is_empty() {
        let source = if segmentations.len() == 1 {
            "the segmentation"
        } else {
            "the segmentations"
        };
        return Ok(Some(Scene {
            aside: apart(&segmentations),
            read: segmentations,
            source,
        }));
    }
    if !marks.is_empty() {
        return Ok(Some(Scene {
            aside: apart(&marks),
            read: marks,
            source: "the Slicer markups",
        }));
    }
    let names: Vec<&str> = files.iter().map(|(name, _)| *name).collect();
    Err(CoreError::parse(
        0,
        format!(
            "the 3D Slicer scene holds no contours: no markups curve (.mrk.json, .fcsv) and no \
             segmentation (.seg.nrrd or a label map) among its {} file(s): {}",
            files.len(),
            shortened(&names)
        ),
    ))
}

/// Up to eight names, then how many more.
fn shortened(names: &[&str]) -> String {
    let shown = names.iter().take(8).copied().collect::<Vec<_>>().join(", ");
    match names.len() {
        n if n > 8 => format!("{shown} and {} more", n - 8),
        _ => shown,
    }
}

#[cfg(test)]
mod tests;
