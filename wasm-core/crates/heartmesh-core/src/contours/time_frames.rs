//! The time frames of a file that holds a cine sequence, and which of them a reading took.
//!
//! A reader keeps one frame (`io::ContourOptions::frame`, chosen by its label, or each contour's
//! first); this record lets a caller that offers the choice (the app's Frame picker) list the
//! others and name the one on screen, in exports, in a saved session and in the CLI's report.

/// Frames listed at most (a "frame" column that is really a point index would list every row).
pub const LISTED: usize = 1000;

/// The frames of a file with a time-frame column and what was read of them.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct TimeFrames {
    /// The file's frames in order of first appearance, as numbers compare (`1.0` reads as `1`),
    /// text trimmed and as first written (`ES` and `es` are one frame, `io::FrameChoice`), at
    /// most [`LISTED`]. Each is a label a reader can be asked for.
    pub frames: Vec<String>,
    /// Distinct frames in the file (more than `frames.len()` past the limit).
    pub count: usize,
    /// The frames read: the one asked for (as the file writes it); else `firsts`.
    pub read: Vec<String>,
    /// Each contour's (slice's) first frame, distinct, in file order: what is read when no frame
    /// is asked for (one entry when every contour starts in the same frame).
    pub firsts: Vec<String>,
    /// Whether `read` is a frame asked for rather than the file's first.
    pub chosen: bool,
    /// Points of other frames left out.
    pub left_out: usize,
    /// Some contour (slice) has points in more than one frame: the file holds several phases of
    /// one heart, and another frame gives another surface. A file whose slices each carry their
    /// own frame number (biv-me's example labels one slice 1.0 in a frame-0 file) is no sequence.
    pub sequence: bool,
    /// The frames the file itself names as end-diastole and end-systole (a Segment study's `EDT`
    /// and `EST`), when it does and they are among `frames`: the picker says which is which.
    pub end_diastole: Option<String>,
    pub end_systole: Option<String>,
}

impl TimeFrames {
    /// The one frame read, when the reading took one (not each contour's first of several).
    pub fn single(&self) -> Option<&str> {
        match self.read.as_slice() {
            [one] => Some(one),
            _ => None,
        }
    }

    /// The frame worth naming beside the file (exports, sessions): the single frame read of a
    /// sequence, or one asked for; None for a file that holds one frame.
    pub fn named(&self) -> Option<&str> {
        if self.sequence || self.chosen {
            self.single()
        } else {
            None
        }
    }

    /// What a saved session of frame `frame` knows of its source: that one frame, as chosen.
    pub fn saved(frame: &str) -> TimeFrames {
        TimeFrames {
            frames: vec![frame.to_string()],
            count: 1,
            read: vec![frame.to_string()],
            firsts: vec![frame.to_string()],
            chosen: true,
            left_out: 0,
            sequence: false,
            end_diastole: None,
            end_systole: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn named_only_for_a_sequence_or_a_choice() {
        let mut t = TimeFrames {
            frames: vec!["0".into(), "1".into()],
            count: 2,
            read: vec!["0".into(), "1".into()],
            ..TimeFrames::default()
        };
        assert_eq!((t.single(), t.named()), (None, None));
        t.read = vec!["0".into()];
        assert_eq!(
            (t.single(), t.named()),
            (Some("0"), None),
            "one frame per slice"
        );
        t.sequence = true;
        assert_eq!(t.named(), Some("0"));
        assert_eq!(TimeFrames::saved("9").named(), Some("9"));
    }
}
