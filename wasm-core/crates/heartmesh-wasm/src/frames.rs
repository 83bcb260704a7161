//! A loaded file's time frames as the app's Frame picker reads them (`LoadedFile.timeFrames`),
//! and the reader's frame warning in the app's words: the app user chooses a frame with the
//! picker, not with the command line's `--frame` the core's warning names.

use heartmesh_core::contours::TimeFrames;
use heartmesh_core::io::COMMAND_LINE_FRAME_ADVICE;
use serde_json::{json, Value};

/// What the app says instead of the command line's advice.
pub const APP_FRAME_ADVICE: &str = "choose another with the Frame picker";

/// `{frames, count, read, firsts, chosen, leftOut, sequence}` (with `endDiastole` and `endSystole`
/// when the file names them), or null for a file without a frame column.
pub fn time_frames_json(frames: Option<&TimeFrames>) -> Value {
    match frames {
        None => Value::Null,
        Some(t) => {
            let mut v = json!({
                "frames": t.frames,
                "count": t.count,
                "read": t.read,
                "firsts": t.firsts,
                "chosen": t.chosen,
                "leftOut": t.left_out,
                "sequence": t.sequence,
            });
            // Only files that name their phases (a Segment study) carry them.
            for (key, frame) in [
                ("endDiastole", &t.end_diastole),
                ("endSystole", &t.end_systole),
            ] {
                if let Some(f) = frame {
                    v[key] = json!(f);
                }
            }
            v
        }
    }
}

/// A reader's warning with the frame advice in the app's words (other warnings unchanged): the
/// advice and its example (`--frame ES`) end the warning, and give way to the picker's.
pub fn in_app_words(warning: &str) -> String {
    match warning.rfind(COMMAND_LINE_FRAME_ADVICE) {
        Some(at) => format!("{}{APP_FRAME_ADVICE}", &warning[..at]),
        None => warning.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_command_line_advice_becomes_the_pickers() {
        let core = format!(
            "the file holds 2 time frames (ED, ES): frame ED read, 12 points of other frames left out; {COMMAND_LINE_FRAME_ADVICE} (e.g. --frame ES)"
        );
        let app = in_app_words(&core);
        assert!(
            !app.contains("--frame") && !app.contains("command line"),
            "{app}"
        );
        assert!(
            app.ends_with("left out; choose another with the Frame picker"),
            "{app}"
        );
        assert_eq!(
            in_app_words("3 points of unknown contour type X skipped"),
            "3 points of unknown contour type X skipped"
        );
    }

    #[test]
    fn no_frame_column_is_null() {
        assert_eq!(time_frames_json(None), Value::Null);
        let j = time_frames_json(Some(&TimeFrames::saved("9")));
        assert_eq!(j["read"], json!(["9"]));
        assert_eq!(j["chosen"], true);
        assert_eq!(j["leftOut"], 0);
    }
}
