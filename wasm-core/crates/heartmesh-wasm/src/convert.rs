//! Conversions between the core's types and the flat, JSON-described data the worker protocol
//! carries (web/src/core-client/protocol.ts). Pure Rust, so it is unit-tested natively.
//!
//! Bulk data leave as flat f32/u32 vectors (converted once, here, from the core's f64); small
//! descriptions leave as JSON with the protocol's field names.

use heartmesh_core::contours::{Contour, ContourKind};
use heartmesh_core::error::{CoreError, Result};
use heartmesh_core::geometry::Vec3;
use heartmesh_core::mesh::quality::quality;
use heartmesh_core::mesh::topology;
use heartmesh_core::params::{EndCapMode, LidMode, SmoothingMethod};
use heartmesh_core::pipeline::Reconstruction;
use heartmesh_core::Params;
use serde_json::{json, Map, Value};

/// The non-numeric options the params JSON object may also carry (beside the schema's numbers):
/// `smoothing_method` (a string, `SmoothingMethod::ALL`), `soften_conflicts`, `align_slices`,
/// `keep_specks`, `apex_floor` and `drop_second_loops` (bools), `end_caps` (a string,
/// `EndCapMode::ALL`); absent: the
/// core's default. They travel inside the same object so that the run, the sweep and
/// leave-one-out take them one way.
pub const SMOOTHING_METHOD: &str = "smoothing_method";
pub const SOFTEN_CONFLICTS: &str = "soften_conflicts";
pub const ALIGN_SLICES: &str = "align_slices";
pub const END_CAPS: &str = "end_caps";
/// Keep the strays and specks a reconstruction otherwise leaves out (`Params::keep_specks`).
pub const KEEP_SPECKS: &str = "keep_specks";
/// The one-sided floor at the tip the apical rings' taper predicts, for an apex no long-axis
/// curve reaches (`Params::apex_floor`; on by default since session 14).
pub const APEX_FLOOR: &str = "apex_floor";
/// Leave out the closed loops lying apart from their short-axis slice's main loop, which the
/// load-time warning names (`Params::drop_second_loops`; off by default: the user's call).
pub const DROP_SECOND_LOOPS: &str = "drop_second_loops";
/// The ids of the contours the user leaves out (`Params::leave_out`; an array of strings, the
/// app's Contours table): the run's, a session's, the walls' and the phases' alike.
pub const LEAVE_OUT: &str = "leave_out";

/// Builds parameters from a JSON object of schema names to numbers (plus the options above),
/// applied in schema order (so `attractor_spacing` > 0 wins over `attractors`, whatever the key
/// order), plus the lids mode and the surface.
pub fn params_from_json(params_json: &str, lids: &str, surface: Option<String>) -> Result<Params> {
    let value: Value = serde_json::from_str(params_json).map_err(|e| CoreError::ParamInvalid {
        name: "params".into(),
        message: format!("not a JSON object: {e}"),
    })?;
    let object = value.as_object().ok_or_else(|| CoreError::ParamInvalid {
        name: "params".into(),
        message: "not a JSON object".into(),
    })?;
    let schema = Params::schema();
    let is_option = |k: &str| {
        [
            SMOOTHING_METHOD,
            SOFTEN_CONFLICTS,
            ALIGN_SLICES,
            END_CAPS,
            KEEP_SPECKS,
            APEX_FLOOR,
            DROP_SECOND_LOOPS,
            LEAVE_OUT,
        ]
        .contains(&k)
    };
    if let Some(unknown) = object
        .keys()
        .find(|k| !is_option(k) && !schema.iter().any(|s| s.name == *k))
    {
        return Err(CoreError::ParamInvalid {
            name: unknown.clone(),
            message: "unknown parameter".into(),
        });
    }
    let mut params = Params::default();
    for spec in schema {
        if let Some(v) = object.get(spec.name) {
            let number = v.as_f64().ok_or_else(|| CoreError::ParamInvalid {
                name: spec.name.to_string(),
                message: format!("{v} is not a number"),
            })?;
            params.set(spec.name, number)?;
        }
    }
    apply_options(&mut params, object)?;
    params.set_lids(lids)?;
    params.surface = surface;
    params.validate()?;
    Ok(params)
}

/// Applies `smoothing_method`, `end_caps`, `soften_conflicts`, `align_slices`, `keep_specks`,
/// `apex_floor` and `drop_second_loops` when present, with the core's setters; a wrong type or
/// name is an error naming the option and what it accepts.
fn apply_options(params: &mut Params, object: &Map<String, Value>) -> Result<()> {
    match object.get(SMOOTHING_METHOD) {
        None => {}
        Some(Value::String(name)) => params.set_smoothing_method(name)?,
        Some(other) => {
            return Err(CoreError::ParamInvalid {
                name: SMOOTHING_METHOD.into(),
                message: format!("{other} is not a method name (allowed: {})", method_names()),
            })
        }
    }
    match object.get(END_CAPS) {
        None => {}
        Some(Value::String(mode)) => params.set_end_caps(mode)?,
        Some(other) => {
            return Err(CoreError::ParamInvalid {
                name: END_CAPS.into(),
                message: format!("{other} is not a mode (allowed: {})", end_cap_names()),
            })
        }
    }
    match object.get(LEAVE_OUT) {
        None => {}
        Some(v) => params.leave_out = heartmesh_core::io::session::contour_ids(v)?,
    }
    for (name, field) in [
        (SOFTEN_CONFLICTS, &mut params.soften_conflicts),
        (ALIGN_SLICES, &mut params.align_slices),
        (KEEP_SPECKS, &mut params.keep_specks),
        (APEX_FLOOR, &mut params.apex_floor),
        (DROP_SECOND_LOOPS, &mut params.drop_second_loops),
    ] {
        match object.get(name) {
            None => {}
            Some(Value::Bool(on)) => *field = *on,
            Some(other) => {
                return Err(CoreError::ParamInvalid {
                    name: name.into(),
                    message: format!("{other} is not true or false"),
                })
            }
        }
    }
    Ok(())
}

fn end_cap_names() -> String {
    let names: Vec<&str> = EndCapMode::ALL.iter().map(|(_, n)| *n).collect();
    names.join(", ")
}

fn method_names() -> String {
    let names: Vec<&str> = SmoothingMethod::ALL.iter().map(|(_, n)| *n).collect();
    names.join(", ")
}

/// The options of `params` as `{smoothing_method, soften_conflicts, align_slices, end_caps,
/// keep_specks, apex_floor, drop_second_loops}` (run results, exports, the settings of a loaded
/// session).
pub fn options_to_json(params: &Params) -> Value {
    json!({
        SMOOTHING_METHOD: params.smoothing.name(),
        SOFTEN_CONFLICTS: params.soften_conflicts,
        ALIGN_SLICES: params.align_slices,
        END_CAPS: params.end_caps.name(),
        KEEP_SPECKS: params.keep_specks,
        APEX_FLOOR: params.apex_floor,
        DROP_SECOND_LOOPS: params.drop_second_loops,
    })
}

/// The small part of the protocol's `RunResult` (`Session::result_json`): surface, contours,
/// perContour, overall, volumeMl, areaMm2, watertight, quality, params, lids, options, alignment (the
/// core's `Alignment`, null unless `align_slices`; `contours` are then the shifted contours),
/// crossing_residual_mm, suggest_alignment, set_aside (the contours left out: the CLI report's
/// `set_aside` entries, `[]` when none), leave_out (the ids asked), version.
pub fn result_value(rec: &Reconstruction, lids: &str) -> Value {
    let mesh = rec.mesh();
    let q = quality(mesh);
    let distances = rec.contour_distances();
    let per_contour: Vec<_> = distances
        .per_contour
        .iter()
        .map(|c| {
            let mut row = json!({ "id": c.id, "kind": c.kind, "stats": c.stats });
            // Points left out of it as damaged values: the Contours panel says so in its row.
            if let Some(fields) = row.as_object_mut() {
                fields.extend(rec.damage_of(&c.id));
            }
            row
        })
        .collect();
    json!({
        "surface": rec.params().surface,
        "contours": contour_infos(rec.contours(), Some(rec.kinds())),
        "perContour": per_contour,
        "overall": distances.overall,
        "volumeMl": mesh.volume_ml(),
        "pastData": rec.past_data(),
        // Which ends no curve closes got synthetic lid points (per resampling; not data), and
        // the core's sentence for a base too narrow for any that runs on past the data (null
        // otherwise).
        "end_caps": rec.end_caps(),
        "endCapNote": rec.end_cap_note(),
        // Long-axis curves closed across the valve that the mesh was fitted to opened there,
        // and the core's sentence about them (null when none).
        "valve_chords": rec.valve_chords(),
        "valveChordNote": rec.valve_chord_note(),
        // Remeshes skipped because each would have wrecked the surface, and the core's sentence
        // about them (empty / null on sound data).
        "skipped_remeshes": rec.skipped_remeshes(),
        "skippedRemeshNote": rec.skipped_remesh_note(),
        "areaMm2": mesh.area(),
        "watertight": topology::validity(mesh).is_closed_manifold(),
        // What a volume mesher or a 3D-printing slicer would trip over: creased neighbours
        // (more than 90 degrees) and triangles passing through each other.
        "quality": { "folded_edges": q.folded_edges, "self_intersections": q.self_intersections },
        "params": params_to_json(rec.params()),
        "lids": lids,
        "options": options_to_json(rec.params()),
        "alignment": rec.alignment(),
        // How far apart the file's images are where their planes cross (null: no crossings), and
        // whether that is enough to suggest the alignment (off and above the core's threshold).
        "crossing_residual_mm": rec.crossing_residual_mm(),
        "suggest_alignment": rec.alignment_suggested(),
        // With alignment on, `overall` is to the shifted contours the mesh follows; this is to the
        // file's contours as drawn (the app shows both).
        "contour_to_mesh_as_given": rec.contour_distances_as_given().map(|d| d.overall),
        // The contours the run left out (the user's, then strays and specks): `id`, `line`,
        // `reason` and its figures, and `mean`, `median`, `max`: how far the mesh passes from it
        // (mm), as the CLI report's `set_aside` (the core's `SetAsideDistance`).
        "set_aside": rec.set_aside_distances(),
        // The ids the run was asked to leave out (those of this surface are in `set_aside` as
        // `by_user`).
        LEAVE_OUT: rec.params().leave_out,
        "version": heartmesh_core::VERSION,
    })
}

/// Every schema parameter's effective value, for the run result and exports.
pub fn params_to_json(params: &Params) -> Value {
    let mut out = Map::new();
    for spec in Params::schema() {
        if let Some(v) = params.get(spec.name) {
            out.insert(spec.name.to_string(), json!(v));
        }
    }
    Value::Object(out)
}

/// The settings of a saved session in the protocol's terms (`SessionSettings`): `{params,
/// lids, options, surface, leave_out}`.
pub fn session_settings(params: &Params) -> Value {
    let lids = match params.lids {
        LidMode::None => "none",
        _ => "auto",
    };
    json!({
        "params": params_to_json(params),
        "lids": lids,
        "options": options_to_json(params),
        "surface": params.surface,
        LEAVE_OUT: params.leave_out,
    })
}

/// `ContourInfo[]` of the protocol; `start`/`count` index points in [`flat_points`] order.
pub fn contour_infos(contours: &[Contour], kinds: Option<&[ContourKind]>) -> Value {
    let mut start = 0usize;
    let infos: Vec<Value> = contours
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let pieces: Vec<Value> = c
                .pieces
                .iter()
                .map(|p| {
                    let piece =
                        json!({ "closed": p.closed, "start": start, "count": p.points.len() });
                    start += p.points.len();
                    piece
                })
                .collect();
            let kind = kinds
                .and_then(|k| k.get(i))
                .map(|k| json!(k))
                .unwrap_or(Value::Null);
            json!({ "id": c.id, "surface": c.surface, "kind": kind, "pieces": pieces })
        })
        .collect();
    Value::Array(infos)
}

/// xyz of all points of all pieces of all contours, in order, as f32.
pub fn flat_points(contours: &[Contour]) -> Vec<f32> {
    contours
        .iter()
        .flat_map(|c| c.points())
        .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
        .collect()
}

/// Points as flat f32 triples.
pub fn flat_vec3(points: &[Vec3]) -> Vec<f32> {
    points
        .iter()
        .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
        .collect()
}

/// f64 values as f32, for per-point and per-vertex distances.
pub fn to_f32(values: &[f64]) -> Vec<f32> {
    values.iter().map(|&v| v as f32).collect()
}

/// The long-axis views a page sends with a label map: names and `Uint8Array`s in the same order.
/// Owned, since the JS arrays cannot be borrowed; [`view_pairs`] lends them to the core.
pub fn views_from_js(
    names: Vec<String>,
    views: &js_sys::Array,
) -> std::result::Result<Vec<(String, Vec<u8>)>, wasm_bindgen::JsValue> {
    if names.len() != views.length() as usize {
        return Err(crate::errors::to_js(&CoreError::ParamInvalid {
            name: "views".into(),
            message: "one name per view".into(),
        }));
    }
    Ok(names
        .into_iter()
        .zip(views.iter().map(|v| js_sys::Uint8Array::new(&v).to_vec()))
        .collect())
}

/// `(name, bytes)` views as the core's readers take them.
pub fn view_pairs(views: &[(String, Vec<u8>)]) -> Vec<(&str, &[u8])> {
    views
        .iter()
        .map(|(n, b)| (n.as_str(), b.as_slice()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use heartmesh_core::contours::Polyline;
    use heartmesh_core::geometry::v3;
    use heartmesh_core::params::AttractorMode;

    fn contour(id: &str, pieces: &[usize]) -> Contour {
        Contour {
            id: id.into(),
            surface: Some("LV_ENDO".into()),
            pieces: pieces
                .iter()
                .map(|&n| Polyline {
                    points: (0..n).map(|i| v3(i as f64, 0.5, -1.0)).collect(),
                    closed: n > 2,
                })
                .collect(),
            first_line: 2,
        }
    }

    #[test]
    fn params_apply_in_schema_order() {
        let p = params_from_json(
            r#"{"attractors": 200, "attractor_spacing": 3.5, "beta": 0.2}"#,
            "none",
            Some("LV_EPI".into()),
        )
        .unwrap();
        assert_eq!(p.attractors, AttractorMode::SpacingMm(3.5));
        assert_eq!(p.beta, 0.2);
        assert_eq!(p.lids, LidMode::None);
        assert_eq!(p.surface.as_deref(), Some("LV_EPI"));
        let q = params_from_json(
            r#"{"attractors": 200, "attractor_spacing": 0}"#,
            "auto",
            None,
        )
        .unwrap();
        assert_eq!(q.attractors, AttractorMode::Count(200));
    }

    #[test]
    fn params_errors_are_typed() {
        let e = params_from_json(r#"{"beta": 5}"#, "auto", None).unwrap_err();
        assert_eq!(e.code(), "param_out_of_range");
        let e = params_from_json(r#"{"gamma": 1}"#, "auto", None).unwrap_err();
        assert_eq!(e.code(), "param_invalid");
        let e = params_from_json(r#"{"beta": "x"}"#, "auto", None).unwrap_err();
        assert_eq!(e.code(), "param_invalid");
        let e = params_from_json("[1]", "auto", None).unwrap_err();
        assert_eq!(e.code(), "param_invalid");
        let e = params_from_json("{}", "sideways", None).unwrap_err();
        assert_eq!(e.code(), "param_invalid");
    }

    #[test]
    fn options_ride_in_the_params_object() {
        let p = params_from_json(
            r#"{"smoothing_method": "taubin", "soften_conflicts": false, "smoothing_factor": 0.5}"#,
            "auto",
            None,
        )
        .unwrap();
        assert_eq!(p.smoothing, SmoothingMethod::Taubin);
        assert!(!p.soften_conflicts);
        assert_eq!(p.smoothing_factor, 0.5);
        let o = options_to_json(&p);
        assert_eq!(
            o,
            json!({"smoothing_method": "taubin", "soften_conflicts": false, "align_slices": false, "end_caps": "auto", "keep_specks": false, "apex_floor": true, "drop_second_loops": false})
        );
        // Absent: the core's defaults.
        let d = params_from_json("{}", "auto", None).unwrap();
        assert_eq!(d.smoothing, SmoothingMethod::LaplacianAffine);
        assert!(d.soften_conflicts);
        let q = params_from_json(
            r#"{"smoothing_method": "laplacian-affine", "soften_conflicts": true}"#,
            "auto",
            None,
        )
        .unwrap();
        assert_eq!(q, d);
        assert_eq!(
            options_to_json(&d),
            json!({"smoothing_method": "laplacian-affine", "soften_conflicts": true, "align_slices": false, "end_caps": "auto", "keep_specks": false, "apex_floor": true, "drop_second_loops": false})
        );
        assert!(!d.align_slices);
        let a = params_from_json(r#"{"align_slices": true}"#, "auto", None).unwrap();
        assert!(a.align_slices);
        assert_eq!(options_to_json(&a)["align_slices"], true);
        assert!(!d.keep_specks);
        let k = params_from_json(r#"{"keep_specks": true}"#, "auto", None).unwrap();
        assert!(k.keep_specks);
        assert_eq!(options_to_json(&k)["keep_specks"], true);
        assert!(d.apex_floor);
        let f = params_from_json(r#"{"apex_floor": false}"#, "auto", None).unwrap();
        assert!(!f.apex_floor);
        assert_eq!(options_to_json(&f)["apex_floor"], false);
        assert!(!d.drop_second_loops);
        let l = params_from_json(r#"{"drop_second_loops": true}"#, "auto", None).unwrap();
        assert!(l.drop_second_loops);
        assert_eq!(options_to_json(&l)["drop_second_loops"], true);
    }

    #[test]
    fn bad_options_name_the_option_and_the_allowed_values() {
        let e = params_from_json(r#"{"smoothing_method": "gaussian"}"#, "auto", None).unwrap_err();
        assert_eq!(e.code(), "param_invalid");
        let text = e.to_string();
        assert!(text.contains("smoothing_method"), "{text}");
        assert!(text.contains("gaussian"), "{text}");
        assert!(text.contains("laplacian-affine, taubin"), "{text}");
        let e = params_from_json(r#"{"smoothing_method": 2}"#, "auto", None).unwrap_err();
        assert_eq!(e.code(), "param_invalid");
        assert!(e.to_string().contains("laplacian-affine, taubin"), "{e}");
        let e = params_from_json(r#"{"soften_conflicts": "no"}"#, "auto", None).unwrap_err();
        assert_eq!(e.code(), "param_invalid");
        assert!(e.to_string().contains("soften_conflicts"), "{e}");
        assert!(e.to_string().contains("true or false"), "{e}");
        for bad in [r#""yes""#, "1", "null", "[true]"] {
            for name in ["align_slices", "keep_specks", "apex_floor"] {
                let e =
                    params_from_json(&format!(r#"{{"{name}": {bad}}}"#), "auto", None).unwrap_err();
                assert_eq!(e.code(), "param_invalid");
                assert!(e.to_string().contains(name), "{e}");
            }
        }
        // Taubin is unstable above a factor of 0.6: the core's range error, naming the limit.
        let e = params_from_json(
            r#"{"smoothing_method": "taubin", "smoothing_factor": 0.8}"#,
            "auto",
            None,
        )
        .unwrap_err();
        assert_eq!(e.code(), "param_out_of_range");
        assert!(e.to_string().contains("smoothing_factor"), "{e}");
        assert!(e.to_string().contains("0.6"), "{e}");
        // The same factor is fine with the default method.
        assert!(params_from_json(r#"{"smoothing_factor": 0.8}"#, "auto", None).is_ok());
    }

    /// A params object without `apex_floor` (an app older than its switch) gets the core's
    /// default, on; a caller may turn it off; a non-bool is a typed error naming it.
    #[test]
    fn apex_floor_is_the_core_default_unless_given() {
        assert!(params_from_json("{}", "auto", None).unwrap().apex_floor);
        assert!(
            params_from_json(r#"{"apex_floor": true}"#, "auto", None)
                .unwrap()
                .apex_floor
        );
        assert!(
            !params_from_json(r#"{"apex_floor": false}"#, "auto", None)
                .unwrap()
                .apex_floor
        );
        let e = params_from_json(r#"{"apex_floor": 1}"#, "auto", None).unwrap_err();
        assert_eq!(e.code(), "param_invalid");
        assert!(e.to_string().contains("apex_floor"), "{e}");
    }

    #[test]
    fn session_settings_carry_the_options() {
        let p = params_from_json(
            r#"{"smoothing_method": "taubin", "soften_conflicts": false, "beta": 0.3}"#,
            "none",
            Some("LV_EPI".into()),
        )
        .unwrap();
        let v = session_settings(&p);
        assert_eq!(v["lids"], "none");
        assert_eq!(v["surface"], "LV_EPI");
        assert_eq!(v["params"]["beta"], 0.3);
        assert_eq!(v["options"]["smoothing_method"], "taubin");
        assert_eq!(v["options"]["soften_conflicts"], false);
        // What the app sends back reproduces the parameters.
        let mut object = v["params"].as_object().unwrap().clone();
        object.extend(v["options"].as_object().unwrap().clone());
        let again = params_from_json(
            &Value::Object(object).to_string(),
            v["lids"].as_str().unwrap(),
            Some("LV_EPI".into()),
        )
        .unwrap();
        assert_eq!(again, p);
    }

    /// A session's `apex_floor` reaches the app's options, also when it is off (a session saved
    /// before sessions stored it reads back off, `io::session`), and goes back to the same
    /// parameters.
    #[test]
    fn session_settings_carry_the_apex_floor() {
        for on in [true, false] {
            let p = Params {
                apex_floor: on,
                ..Params::default()
            };
            let v = session_settings(&p);
            assert_eq!(v["options"]["apex_floor"], on);
            let mut object = v["params"].as_object().unwrap().clone();
            object.extend(v["options"].as_object().unwrap().clone());
            let again = params_from_json(&Value::Object(object).to_string(), "auto", None).unwrap();
            assert_eq!(again.apex_floor, on);
        }
    }

    /// `leave_out` rides in the params object, comes back in a session's settings and refuses
    /// anything but a list of ids.
    #[test]
    fn leave_out_rides_in_the_params_object() {
        let p = params_from_json(r#"{"leave_out": ["s1", "lax0"]}"#, "auto", None).unwrap();
        assert_eq!(p.leave_out, ["s1", "lax0"]);
        assert_eq!(session_settings(&p)[LEAVE_OUT], json!(["s1", "lax0"]));
        assert_eq!(session_settings(&Params::default())[LEAVE_OUT], json!([]));
        for bad in [
            r#"{"leave_out": "s1"}"#,
            r#"{"leave_out": [1]}"#,
            r#"{"leave_out": [""]}"#,
        ] {
            let e = params_from_json(bad, "auto", None).unwrap_err();
            assert_eq!(e.code(), "param_invalid", "{bad}");
            assert!(e.to_string().contains("leave_out"), "{e}");
        }
    }

    #[test]
    fn params_round_trip_through_json() {
        let p = params_from_json(r#"{"iterations": 40, "lambda": 1000}"#, "auto", None).unwrap();
        let v = params_to_json(&p);
        assert_eq!(v["iterations"], 40.0);
        assert_eq!(v["lambda"], 1000.0);
        assert_eq!(v.as_object().unwrap().len(), Params::schema().len());
    }

    #[test]
    fn contour_pieces_index_the_flat_points() {
        let cs = vec![contour("a", &[3, 2]), contour("b", &[4])];
        let info = contour_infos(&cs, Some(&[ContourKind::Sax, ContourKind::Lax]));
        assert_eq!(info[0]["pieces"][1]["start"], 3);
        assert_eq!(info[0]["pieces"][1]["count"], 2);
        assert_eq!(info[1]["pieces"][0]["start"], 5);
        assert_eq!(info[1]["kind"], "LAX");
        assert_eq!(info[0]["pieces"][1]["closed"], false);
        let flat = flat_points(&cs);
        assert_eq!(flat.len(), 9 * 3);
        assert_eq!(&flat[15..18], &[0.0, 0.5, -1.0]);
        assert_eq!(contour_infos(&cs, None)[0]["kind"], Value::Null);
    }
}
