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
