//! One time frame out of a file that holds several (a cine sequence exported whole: a `frame`
//! or `phase` column in a CSV, the `time frame` column of a GPFile).
//!
//! Without a choice, each contour (or slice) keeps the first frame it has in the file: files
//! normally hold one frame, but one slice may carry another frame number (the biv-me example
//! does), and mixing every frame's curves into one surface is never what the user meant. When
//! that leaves rows out, the warning says how many, from which frames, and how to choose. A frame
//! is chosen by its label ([`FrameChoice`]: `9`, `ES`), compared as [`frame_key`] says.

use std::collections::HashMap;

use super::frame_choice::{frame_key, frame_label, FrameChoice};
use crate::contours::time_frames::{TimeFrames, LISTED};
use crate::error::CoreError;

/// How the warning tells a command-line user to read another frame (followed by an example, a
/// frame of the file: `--frame ES`); the app's binding puts its own wording (the Frame picker) in
/// its place.
pub const COMMAND_LINE_FRAME_ADVICE: &str =
    "save one frame per file, or choose one with the command line's --frame";

/// Rows kept and left out by frame, keyed by contour or slice.
#[derive(Debug, Default)]
pub struct FrameFilter {
    wanted: Option<FrameChoice>,
    /// The label of the frame asked for as the file writes it, once a row matched it.
    matched: Option<String>,
    /// The key of the first frame seen for each contour or slice (hashed: a file may hold 10^5
    /// contours).
    first: HashMap<String, String>,
    /// The distinct first frames of the keys (labels), in file order (one: every key starts in
    /// the same frame), at most [`LISTED`].
    firsts: Vec<String>,
    /// Every frame seen: its label by its key; and the first [`LISTED`] labels in file order.
    seen: HashMap<String, String>,
    order: Vec<String>,
    skipped: usize,
    kept: usize,
    /// Rows whose frame cell is blank: in no frame, so read whichever frame is (a structure drawn
    /// once for the whole sequence); never listed as a frame of their own.
    unframed: usize,
    /// Some key has rows in more than one frame.
    sequence: bool,
}

/// Frames named in a message.
const SHOWN: usize = 8;

impl FrameFilter {
    pub fn new(wanted: Option<&FrameChoice>) -> Self {
        FrameFilter {
            wanted: wanted.cloned(),
            ..Self::default()
        }
    }

    /// True when a row of `key` in frame `value` is read.
    pub fn keep(&mut self, key: &str, value: &str) -> bool {
        if value.trim().is_empty() {
            self.unframed += 1;
            return true;
        }
        let frame = frame_key(value);
        if !self.seen.contains_key(&frame) {
            let label = frame_label(value);
            if self.order.len() < LISTED {
                self.order.push(label.clone());
            }
            self.seen.insert(frame.clone(), label);
        }
        let first = match self.first.get(key) {
            Some(first) => {
                self.sequence |= *first != frame;
                first
            }
            None => {
                let label = &self.seen[&frame];
                if self.firsts.len() < LISTED && !self.firsts.contains(label) {
                    self.firsts.push(label.clone());
                }
                self.first.insert(key.to_string(), frame.clone());
                &frame
            }
        };
        let keep = match &self.wanted {
            Some(want) => want.key() == frame,
            None => *first == frame,
        };
        if keep {
            self.kept += 1;
            if self.wanted.is_some() && self.matched.is_none() {
                self.matched = Some(self.seen[&frame].clone());
            }
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
        let read = match (&self.wanted, &self.matched) {
            (Some(_), Some(label)) => vec![label.clone()],
            (Some(want), None) => vec![want.label().to_string()],
            (None, _) => self.firsts.clone(),
        };
        Some(TimeFrames {
            frames: self.order.clone(),
            count: self.seen.len(),
            read,
            firsts: self.firsts.clone(),
            chosen: self.wanted.is_some(),
            left_out: self.skipped,
            sequence: self.sequence,
            end_diastole: None,
            end_systole: None,
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

    /// Every warning of the reading: rows of other frames left out ([`Self::warning`]) and rows
    /// of no frame ([`Self::unframed_warning`]); `each` as for the first.
    pub fn warnings(&self, each: &str) -> impl Iterator<Item = String> {
        self.warning(each)
            .into_iter()
            .chain(self.unframed_warning())
    }

    /// The note when some rows carry a frame and others none (None otherwise): those are read with
    /// every frame, which the user should know when the blanks were a mistake.
    pub fn unframed_warning(&self) -> Option<String> {
        (self.unframed > 0 && !self.seen.is_empty()).then(|| {
            let (n, have) = match self.unframed {
                1 => ("1 point".to_string(), "has"),
                n => (format!("{n} points"), "have"),
            };
            format!("{n} {have} no time frame (a blank frame cell): read with every frame")
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
        // The example names a frame that was left out (rows were, so one is listed unless past
        // the listing's limit), so that a file of `ED` and `ES` shows `--frame ES` is possible.
        let example = self
            .order
            .iter()
            .find(|f| !self.firsts.contains(f))
            .or(self.order.first())
            .map(String::as_str)
            .unwrap_or("N");
        Some(format!(
            "the file holds {} time frames ({}): {read}, {} points of other frames left out; \
             {COMMAND_LINE_FRAME_ADVICE} (e.g. --frame {example})",
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
                 command line's --frame (e.g. --frame 5)"
            )
        );
        assert!(f.nothing_in_wanted().is_none());
    }

    /// A blank frame cell is no frame: always read, never listed, counted in a note; a file whose
    /// cells are all blank has no frames at all.
    #[test]
    fn blank_frame_cells_are_read_with_every_frame() {
        for wanted in [None, Some(FrameChoice::from(5))] {
            let mut f = FrameFilter::new(wanted.as_ref());
            let kept: Vec<bool> = [("a", "0"), ("a", ""), ("b", " "), ("a", "5")]
                .iter()
                .map(|(k, v)| f.keep(k, v))
                .collect();
            assert_eq!(kept, [wanted.is_none(), true, true, wanted.is_some()]);
            let t = f.time_frames().unwrap();
            assert_eq!(t.frames, ["0", "5"], "no frame \"\"");
            assert_eq!(
                f.unframed_warning().as_deref(),
                Some("2 points have no time frame (a blank frame cell): read with every frame")
            );
        }
        let mut blank = FrameFilter::new(None);
        assert!(blank.keep("a", "") && blank.keep("b", ""));
        assert!(blank.time_frames().is_none() && blank.unframed_warning().is_none());
        // Only blanks besides the frame asked for: that frame has no points.
        let mut g = FrameFilter::new(Some(&7.into()));
        g.keep("a", "0");
        g.keep("a", "");
        assert!(g.nothing_in_wanted().is_some());
    }

    #[test]
    fn a_chosen_frame_reads_only_it_and_says_when_it_is_absent() {
        let mut f = FrameFilter::new(Some(&1.into()));
        assert!(!f.keep("a", "0"));
        assert!(f.keep("a", "1.0"));
        assert_eq!(f.warning("contour"), None, "the user chose");
        let mut g = FrameFilter::new(Some(&7.into()));
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
        let mut g = FrameFilter::new(Some(&9.into()));
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

    /// Phases written as text (a `phase` column of `ED` and `ES`): either is chosen by its label,
    /// in any case and with spaces around it; the frame read is named as the file writes it.
    #[test]
    fn text_frames_are_chosen_by_label_in_any_case() {
        let rows = [
            ("a", "ED"),
            ("b", " ED"),
            ("a", "ES "),
            ("b", "es"),
            ("a", "ED"),
        ];
        let run = |want: Option<&str>| {
            let choice = want.and_then(FrameChoice::new);
            let mut f = FrameFilter::new(choice.as_ref());
            let kept: Vec<bool> = rows.iter().map(|(k, v)| f.keep(k, v)).collect();
            (kept, f)
        };
        let (kept, f) = run(None);
        assert_eq!(kept, [true, true, false, false, true]);
        let t = f.time_frames().unwrap();
        assert_eq!(
            t.frames,
            ["ED", "ES"],
            "`ES ` and `es` are one frame, as first written"
        );
        assert_eq!(
            (t.read.as_slice(), t.left_out),
            (&["ED".to_string()][..], 2)
        );
        assert_eq!(
            f.warning("contour").as_deref(),
            Some(
                "the file holds 2 time frames (ED, ES): frame ED read, 2 points of other frames \
                 left out; save one frame per file, or choose one with the command line's \
                 --frame (e.g. --frame ES)"
            )
        );
        for asked in ["ES", "es", " Es\t"] {
            let (kept, f) = run(Some(asked));
            assert_eq!(kept, [false, false, true, true, false], "{asked:?}");
            let t = f.time_frames().unwrap();
            assert_eq!(t.read, ["ES"], "{asked:?}: named as the file writes it");
            assert_eq!((t.chosen, t.left_out), (true, 3));
            assert_eq!(f.warning("contour"), None);
            assert!(f.nothing_in_wanted().is_none());
        }
        let (kept, f) = run(Some("ed"));
        assert_eq!(kept, [true, true, false, false, true]);
        assert_eq!(f.time_frames().unwrap().read, ["ED"]);
        let (_, f) = run(Some("systole"));
        assert_eq!(
            f.nothing_in_wanted().map(|e| e.to_string()).as_deref(),
            Some("no contour points in frame systole (frames in the file: ED, ES)")
        );
        assert_eq!(f.time_frames().unwrap().read, ["systole"]);
    }

    /// Numbers as numbers whatever their form, in a file that mixes numbers and text.
    #[test]
    fn number_forms_choose_the_same_frame() {
        let rows = [("a", "0"), ("a", "1.0"), ("a", "ED"), ("a", "1")];
        for asked in ["1", "1.0", " 1 ", "1e0", "01"] {
            let want = FrameChoice::new(asked);
            let mut f = FrameFilter::new(want.as_ref());
            let kept: Vec<bool> = rows.iter().map(|(k, v)| f.keep(k, v)).collect();
            assert_eq!(kept, [false, true, false, true], "{asked:?}");
            assert_eq!(f.time_frames().unwrap().read, ["1"], "{asked:?}");
        }
        let mut f = FrameFilter::new(FrameChoice::new("1.5").as_ref());
        rows.iter().for_each(|(k, v)| {
            f.keep(k, v);
        });
        assert_eq!(
            f.nothing_in_wanted().map(|e| e.to_string()).as_deref(),
            Some("no contour points in frame 1.5 (frames in the file: 0, 1, ED)")
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
