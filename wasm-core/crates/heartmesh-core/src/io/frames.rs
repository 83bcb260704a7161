//! One time frame out of a file that holds several (a cine sequence exported whole: a `frame`
//! column in a CSV, the `time frame` column of a GPFile).
//!
//! Without a choice, each contour (or slice) keeps the first frame it has in the file: files
//! normally hold one frame, but one slice may carry another frame number (the biv-me example
//! does), and mixing every frame's curves into one surface is never what the user meant. When
//! that leaves rows out, the warning says how many, from which frames, and how to choose.

use std::collections::{HashMap, HashSet};

use crate::error::CoreError;

/// Rows kept and left out by frame, keyed by contour or slice.
#[derive(Debug, Default)]
pub struct FrameFilter {
    wanted: Option<String>,
    /// The first frame seen for each key (hashed: a file may hold 10^5 contours).
    first: HashMap<String, String>,
    /// The first two distinct first frames (one means every key starts in the same frame).
    firsts: Vec<String>,
    /// Every frame seen, and the first few in file order for messages.
    seen: HashSet<String>,
    shown: Vec<String>,
    skipped: usize,
    kept: usize,
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
        if self.shown.len() < SHOWN && !self.seen.contains(&frame) {
            self.shown.push(frame.clone());
        }
        self.seen.insert(frame.clone());
        let keep = match &self.wanted {
            Some(want) => *want == frame,
            None => match self.first.get(key) {
                Some(first) => *first == frame,
                None => {
                    if self.firsts.len() < 2 && !self.firsts.contains(&frame) {
                        self.firsts.push(frame.clone());
                    }
                    self.first.insert(key.to_string(), frame);
                    true
                }
            },
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
        format!("{}{more}", self.shown.join(", "))
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
             save one frame per file, or choose one with the command line's --frame N",
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

    #[test]
    fn one_frame_is_silent() {
        let mut f = FrameFilter::new(None);
        assert!(f.keep("a", "3") && f.keep("b", "3"));
        assert_eq!(f.warning("contour"), None);
    }
}
