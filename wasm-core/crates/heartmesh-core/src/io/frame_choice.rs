//! A time frame asked for by its label as the file writes it (`--frame 9`, `--frame ES`, the
//! app's Frame picker), and how frame labels compare.
//!
//! Frames are chosen by label rather than by number because exports write phases as text as
//! often as numbers (a `phase` column of `ED` and `ES`); a number-only choice left every frame
//! but the first out of reach in such a file.
//!
//! Labels compare as numbers where they are numbers, so `1`, `1.0` and ` 1 ` are one frame
//! (biv-me writes some frames as `1.0`). Text compares trimmed and without regard to case:
//! exporters write the same phase `ED`, `ed` or `Ed`, a command line is typed in any case, and two
//! phases of one heart are never told apart by case alone. Rows labelled `ES` and `es` in one file
//! are therefore one frame (listed as first written), so that choosing it reads all of them rather
//! than a choice in one case reading a frame the listing shows twice.

use std::fmt;

/// A time frame to read, by its label (see the module documentation for how labels compare). Two
/// choices are equal when they choose the same frame (`9` and `9.0`, `ES` and `es`).
#[derive(Debug, Clone)]
pub struct FrameChoice {
    /// As asked for, trimmed (named in messages).
    label: String,
    /// What rows' frames are compared with ([`frame_key`]).
    key: String,
}

impl FrameChoice {
    /// The frame labelled `label` (`"9"`, `"1.0"`, `"ES"`); None when it is blank, which names no
    /// frame.
    pub fn new(label: &str) -> Option<FrameChoice> {
        let label = label.trim();
        (!label.is_empty()).then(|| FrameChoice {
            label: label.to_string(),
            key: frame_key(label),
        })
    }

    /// The label as asked for, trimmed.
    pub fn label(&self) -> &str {
        &self.label
    }

    /// Whether a row whose frame column holds `value` is in this frame.
    pub fn matches(&self, value: &str) -> bool {
        frame_key(value) == self.key
    }

    pub(crate) fn key(&self) -> &str {
        &self.key
    }
}

impl PartialEq for FrameChoice {
    fn eq(&self, other: &Self) -> bool {
        self.key == other.key
    }
}

impl Eq for FrameChoice {}

/// Frame numbers as before labels (`--frame 9`, a saved link's `frame=9`).
impl From<u32> for FrameChoice {
    fn from(n: u32) -> Self {
        let label = n.to_string();
        FrameChoice {
            key: frame_key(&label),
            label,
        }
    }
}

impl fmt::Display for FrameChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.label)
    }
}

/// A frame value as numbers print (`1.0` -> `1`), else trimmed text: how a frame is listed.
pub(crate) fn frame_label(value: &str) -> String {
    let v = value.trim();
    match v.parse::<f64>() {
        // + 0.0: -0 is frame 0.
        Ok(f) if f.is_finite() => format!("{}", f + 0.0),
        _ => v.to_string(),
    }
}

/// What frame values are compared by: [`frame_label`] with text in lower case.
pub(crate) fn frame_key(value: &str) -> String {
    let v = value.trim();
    match v.parse::<f64>() {
        Ok(f) if f.is_finite() => format!("{}", f + 0.0),
        _ => v.to_lowercase(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_compare_as_numbers() {
        let one = FrameChoice::new("1").unwrap();
        for same in ["1", "1.0", " 1 ", "01", "1e0", "+1"] {
            assert!(one.matches(same), "{same:?}");
        }
        assert!(
            FrameChoice::from(0).matches("-0") && FrameChoice::new("-0.0").unwrap().matches("0")
        );
        assert_eq!(frame_label("-0"), "0");
        for other in ["10", "1.5", "-1", "", "one"] {
            assert!(!one.matches(other), "{other:?}");
        }
        assert_eq!(FrameChoice::from(9), FrameChoice::new("9.0").unwrap());
        assert_ne!(FrameChoice::from(9), FrameChoice::new("90").unwrap());
        assert_eq!(
            FrameChoice::new(" 9.0 ").unwrap().label(),
            "9.0",
            "as asked"
        );
        assert_eq!(frame_label(" 9.0 "), "9");
    }

    #[test]
    fn text_compares_trimmed_and_in_any_case() {
        let es = FrameChoice::new(" es ").unwrap();
        assert_eq!(es.label(), "es");
        assert_eq!(es, FrameChoice::new("ES").unwrap(), "the same frame");
        for same in ["ES", "es", " Es\t", "eS"] {
            assert!(es.matches(same), "{same:?}");
        }
        for other in ["ED", "E S", "ES2", "0"] {
            assert!(!es.matches(other), "{other:?}");
        }
        assert!(FrameChoice::new("Diastole").unwrap().matches("DIASTOLE"));
        assert!(
            FrameChoice::new("Ünd").unwrap().matches("ünd"),
            "not ASCII only"
        );
        assert_eq!(frame_label(" ES "), "ES", "listed as written");
        // Not finite numbers are text, compared as such.
        assert!(FrameChoice::new("inf").unwrap().matches("INF"));
        assert!(!FrameChoice::new("1e999").unwrap().matches("inf"));
    }

    #[test]
    fn a_blank_label_is_no_frame() {
        for blank in ["", " ", "\t"] {
            assert_eq!(FrameChoice::new(blank), None, "{blank:?}");
        }
    }
}
