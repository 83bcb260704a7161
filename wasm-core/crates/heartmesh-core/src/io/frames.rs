//! One time frame out of a file that holds several (a cine sequence exported whole: a `frame`
//! column in a CSV, the `time frame` column of a GPFile).
//!
//! Without a choice, each contour (or slice) keeps the first frame it has in the file: files
//! normally hold one frame, but one slice may carry another frame number (the biv-me example
//! does), and mixing every frame's curves into one surface is never what the user meant. When
//! that leaves rows out, the warning says how many, from which frames, and how to choose.

use std::collections::{HashMap, HashSet};

use crate::contours::time_frames::{TimeFrames, LISTED};
use crate::error::CoreError;

/// How the warning tells a command-line user to read another frame; the app's binding puts its
/// own wording (the Frame picker) in its place.
pub const COMMAND_LINE_FRAME_ADVICE: &str =
    "save one frame per file, or choose one with the command line's --frame N";

/// Rows kept and left out by frame, keyed by contour or slice.
#[derive(Debug, Default)]
pub struct FrameFilter {
    wanted: Option<String>,
    /// The first frame seen for each key (hashed: a file may hold 10^5 contours).
    first: HashMap<String, String>,
    /// The distinct first frames of the keys, in file order (one: every key starts in the same
    /// frame), at most [`LISTED`].
    firsts: Vec<String>,
    /// Every frame seen, and the first [`LISTED`] in file order.
    seen: HashSet<String>,
    order: Vec<String>,
    skipped: usize,
    kept: usize,
    /// Some key has rows in more than one frame.
    sequence: bool,
}

/// Frames named in a message.
const SHOWN: usize = 8;

/// Frame values compared as numbers where they are numbers (`1`, `1.0`), else as text (`ED`).
fn normalised(value: &str) -> String {
    let v = value.trim();
    match v.parse::<f64>() {
        Ok(f) if f.is_finite() => format!("{f}"),
        _ => v.to_string(),
    }
}

impl FrameFilter {
    pub fn new(wanted: Option<u32>) -> Self {
        FrameFilter {
            wanted: wanted.map(|w| w.to_string()),
            ..Self::default()
        }
    }

    /// True when a row of `key` in frame `value` is read.
    pub fn keep(&mut self, key: &str, value: &str) -> bool {
        let frame = normalised(value);
        if !self.seen.contains(&frame) {
            if self.order.len() < LISTED {
                self.order.push(frame.clone());
            }
            self.seen.insert(frame.clone());
        }
        let first = match self.first.get(key) {
            Some(first) => {
                self.sequence |= *first != frame;
                first
            }
            None => {
                if self.firsts.len() < LISTED && !self.firsts.contains(&frame) {
                    self.firsts.push(frame.clone());
                }
                self.first.insert(key.to_string(), frame.clone());
                &frame
            }
        };
        let keep = match &self.wanted {
            Some(want) => *want == frame,
            None => *first == frame,
        };
        if keep {
            self.kept += 1;
        } else {
            self.skipped += 1;
        }
        keep
    }

    fn frame_list(&self) -> String {
        let more = if self.seen.len() > SHOWN { ", ..." } else { "" };
        let shown = &self.order[..self.order.len().min(SHOWN)];
        format!("{}{more}", shown.join(", "))
    }

    /// The file's frames and what was read of them; None when no row carried a frame.
    pub fn time_frames(&self) -> Option<TimeFrames> {
        if self.seen.is_empty() {
            return None;
        }
        let read = match &self.wanted {
            Some(want) => vec![want.clone()],
            None => self.firsts.clone(),
        };
        Some(TimeFrames {
            frames: self.order.clone(),
            count: self.seen.len(),
            read,
            firsts: self.firsts.clone(),
            chosen: self.wanted.is_some(),
            left_out: self.skipped,
            sequence: self.sequence,
        })
    }

    /// The error when a chosen frame matched no row (None otherwise).
    pub fn nothing_in_wanted(&self) -> Option<CoreError> {
        let want = self.wanted.as_ref()?;
        (self.kept == 0 && !self.seen.is_empty()).then(|| {
            CoreError::parse(
                0,
                format!(
                    "no contour points in frame {want} (frames in the file: {})",
                    self.frame_list()
                ),
            )
        })
    }

    /// The warning when rows of other frames were left out without a choice; `each` names what
    /// kept its first frame ("contour", "slice").
    pub fn warning(&self, each: &str) -> Option<String> {
        if self.wanted.is_some() || self.skipped == 0 {
            return None;
        }
        let read = if let [only] = self.firsts.as_slice() {
            format!("frame {only} read")
        } else {
            format!("each {each}'s first frame read")
        };
        Some(format!(
            "the file holds {} time frames ({}): {read}, {} points of other frames left out; \
             {COMMAND_LINE_FRAME_ADVICE}",
            self.seen.len(),
            self.frame_list(),
            self.skipped
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_frame_per_key_and_a_warning_with_counts() {
        let mut f = FrameFilter::new(None);
        let rows = [
            ("a", "0"),
            ("a", "0.0"),
            ("b", "1"),
            ("a", "5"),
            ("b", "0"),
            ("b", "1"),
        ];
        let kept: Vec<bool> = rows.iter().map(|(k, v)| f.keep(k, v)).collect();
        assert_eq!(kept, [true, true, true, false, false, true]);
        assert_eq!(
            f.warning("slice").as_deref(),
            Some(
                "the file holds 3 time frames (0, 1, 5): each slice's first frame read, 2 points \
                 of other frames left out; save one frame per file, or choose one with the \
                 command line's --frame N"
            )
        );
        assert!(f.nothing_in_wanted().is_none());
    }

    #[test]
    fn a_chosen_frame_reads_only_it_and_says_when_it_is_absent() {
        let mut f = FrameFilter::new(Some(1));
        assert!(!f.keep("a", "0"));
        assert!(f.keep("a", "1.0"));
        assert_eq!(f.warning("contour"), None, "the user chose");
        let mut g = FrameFilter::new(Some(7));
        g.keep("a", "0");
        g.keep("a", "ED");
        let e = g.nothing_in_wanted().map(|e| e.to_string());
        assert_eq!(
            e.as_deref(),
            Some("no contour points in frame 7 (frames in the file: 0, ED)")
        );
    }

    /// What a caller offering the choice learns: every frame in file order, the frames read,
    /// how many points were left out and whether some key spans frames (a sequence).
    #[test]
    fn time_frames_list_the_file_and_what_was_read() {
        let rows = [("a", "0"), ("b", "1.0"), ("a", "9"), ("b", "9"), ("a", "0")];
        let mut f = FrameFilter::new(None);
        for (k, v) in rows {
            f.keep(k, v);
        }
        let t = f.time_frames().unwrap();
        assert_eq!(t.frames, ["0", "1", "9"]);
        assert_eq!(t.count, 3);
        assert_eq!(t.read, ["0", "1"], "each key's first, in file order");
        assert_eq!((t.chosen, t.left_out, t.sequence), (false, 2, true));
        let mut g = FrameFilter::new(Some(9));
        for (k, v) in rows {
            g.keep(k, v);
        }
        let t = g.time_frames().unwrap();
        assert_eq!(
            (t.read.as_slice(), t.chosen, t.left_out),
            (&["9".to_string()][..], true, 3)
        );
        assert!(t.sequence);
        assert_eq!(
            t.firsts,
            ["0", "1"],
            "what the file's own reading takes, whatever was asked"
        );
        // Each key in a frame of its own: several frames, no sequence, nothing left out.
        let mut h = FrameFilter::new(None);
        h.keep("a", "0");
        h.keep("b", "1");
        let t = h.time_frames().unwrap();
        assert_eq!((t.count, t.sequence, t.left_out), (2, false, 0));
        assert_eq!(
            FrameFilter::new(None).time_frames(),
            None,
            "no row carried a frame"
        );
    }

    #[test]
    fn a_frame_column_of_point_indices_lists_a_bounded_number() {
        let mut f = FrameFilter::new(None);
        for i in 0..(LISTED + 5) {
            f.keep("a", &i.to_string());
        }
        let t = f.time_frames().unwrap();
        assert_eq!((t.frames.len(), t.count), (LISTED, LISTED + 5));
    }

    #[test]
    fn one_frame_is_silent() {
        let mut f = FrameFilter::new(None);
        assert!(f.keep("a", "3") && f.keep("b", "3"));
        assert_eq!(f.warning("contour"), None);
    }
}
