//! Errors cross the boundary as data: a JSON string `{code, message, line?, available?}` thrown
//! to JavaScript, where `code` is the core's stable [`CoreError::code`]. The worker parses it into
//! the protocol's `CoreErrorData`; anything thrown that is not such a string is a crash.

use heartmesh_core::CoreError;
use serde_json::{json, Value};
use wasm_bindgen::JsValue;

/// The JSON object describing `e`.
pub fn error_json(e: &CoreError) -> Value {
    let mut obj = json!({ "code": e.code(), "message": e.to_string() });
    if let Some(line) = e.line() {
        obj["line"] = json!(line);
    }
    match e {
        CoreError::SurfaceRequired { available } | CoreError::UnknownSurface { available, .. } => {
            obj["available"] = json!(available);
        }
        _ => {}
    }
    obj
}

/// A derived file's failure as the app shows it: the core's code, the message after `what`
/// ("the anatomical mesh: ...") in the core's own words (a layout's refusals carry no
/// "degenerate input: ").
pub fn refusal_json(e: &CoreError, what: &str) -> Value {
    let mut v = error_json(e);
    v["message"] = json!(format!(
        "{what}: {}",
        heartmesh_core::metrics::anatomical::reason(e)
    ));
    v
}

/// `e` as the value thrown to JavaScript.
pub fn to_js(e: &CoreError) -> JsValue {
    JsValue::from_str(&error_json(e).to_string())
}

/// A binding-level error (misuse of the session API) in the same shape.
pub fn usage(code: &str, message: impl Into<String>) -> JsValue {
    JsValue::from_str(&json!({ "code": code, "message": message.into() }).to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_error_carries_line() {
        let v = error_json(&CoreError::parse(12, "bad number"));
        assert_eq!(v["code"], "parse");
        assert_eq!(v["line"], 12);
        assert_eq!(v["message"], "line 12: bad number");
    }

    /// What the app's banner gets for two hostile files (session 8): a row with text in a number,
    /// and rings in metres, refused by `Reconstruction::new` (the worker's `start`) for their units.
    #[test]
    fn malformed_and_metre_files_reach_the_app_as_typed_errors() {
        use heartmesh_core::{io, pipeline::Reconstruction, Params};
        let bad = "contour,x,y,z\na,1,2,3\na,1,x2,3\n";
        let e = io::read_contours("bad.csv", bad.as_bytes()).err();
        let v = error_json(&e.unwrap_or(CoreError::Io("read".into())));
        assert_eq!(v["code"], "parse");
        assert_eq!(v["line"], 3);
        assert_eq!(v["message"], "line 3: column \"y\": \"x2\" is not a number");

        let mut metres = String::from("contour,x,y,z\n");
        for (k, z) in [0.0, 0.01, 0.02].iter().enumerate() {
            for i in 0..24 {
                let a = f64::from(i) / 24.0 * std::f64::consts::TAU;
                metres.push_str(&format!(
                    "s{k},{},{},{z}\n",
                    0.025 * a.cos(),
                    0.025 * a.sin()
                ));
            }
        }
        let set = io::read_contours("m.csv", metres.as_bytes());
        let set = set.unwrap_or_default();
        assert!(
            set.warnings.iter().any(|w| w.contains("metres?")),
            "{:?}",
            set.warnings
        );
        let e = Reconstruction::new(&set, Params::default()).err();
        let v = error_json(&e.unwrap_or(CoreError::Io("accepted".into())));
        assert_eq!(v["code"], "degenerate");
        assert!(v.get("line").is_none());
        let text = v["message"].as_str().unwrap_or("");
        assert!(
            text.contains("coordinates span 0.0500") && text.contains("millimetres"),
            "{text}"
        );
    }

    #[test]
    fn surface_required_lists_surfaces() {
        let v = error_json(&CoreError::SurfaceRequired {
            available: vec!["LV_ENDO".into(), "LV_EPI".into()],
        });
        assert_eq!(v["code"], "surface_required");
        assert_eq!(v["available"], json!(["LV_ENDO", "LV_EPI"]));
        assert!(v.get("line").is_none());
    }
}
