//! WebAssembly binding of heartmesh-core: one stateful export, [`Session`], used only by the
//! browser worker (web/src/core-client/reconstruct.worker.ts) and the Node tests.
//!
//! Rules of the boundary (ARCHITECTURE.md): bulk data leave wasm memory exactly once, as fresh
//! `Float32Array`/`Uint32Array` copies (wasm-bindgen copies a returned `Vec<f32>` into a new typed
//! array; no view into wasm memory survives a call), small descriptions leave as JSON strings,
//! errors are thrown as JSON strings `{code, message, line?, available?}`. The reconstruction
//! itself (Villard, Grau & Zacur, J. Imaging 2018) lives entirely in heartmesh-core.

// No unwrap/expect outside tests: a panic on user data would kill the CLI run or the app's
// worker, so every fallible step returns a typed error (`clippy -D warnings` in CI enforces this;
// tests may unwrap).
#![cfg_attr(not(test), deny(clippy::unwrap_used, clippy::expect_used))]

mod anatomical;
mod clock;
mod convert;
#[cfg(test)]
mod cvi42;
mod errors;
mod frames;
mod hex;
mod lab;
mod panic;
#[cfg(test)]
mod test_data;
mod wall;

use std::collections::BTreeMap;

use heartmesh_core::contours::axis::classify_kinds;
use heartmesh_core::geometry::Vec3;
use heartmesh_core::pipeline::Reconstruction;
use heartmesh_core::{io, ContourSet, Params};
use serde_json::json;
use wasm_bindgen::prelude::*;

pub use lab::Lab;
pub use panic::take_panic_message;

/// Runs when the module is instantiated.
#[wasm_bindgen(start)]
pub fn on_start() {
    panic::install();
}

/// JSON array of the numeric parameters (`Params::schema()`): name, default, min, max, log,
/// integer, unit, help.
#[wasm_bindgen]
pub fn schema_json() -> String {
    Params::schema_json()
}

/// Version of the core, recorded in exports.
#[wasm_bindgen]
pub fn version() -> String {
    heartmesh_core::VERSION.to_string()
}

/// `{"dims": [i, j, k], "frames": t}` of a label map (NIfTI-1 plain or gzip, NRRD, DICOM SEG) from its header
/// alone, or undefined when the bytes are not one: the app tells a short-axis stack from the
/// single-slice long-axis views opened with it (a dimension of 1) before loading them together.
#[wasm_bindgen]
pub fn label_map_grid(bytes: &[u8]) -> Option<String> {
    io::nifti::label_map_grid(bytes)
        .map(|(dims, frames)| json!({ "dims": dims, "frames": frames }).to_string())
}

/// A reconstruction in progress, with what it needs to report.
struct ActiveRun {
    rec: Reconstruction,
    lids: String,
    /// Attractors at the last step, to tell when they were re-sampled.
    last_attractors: Vec<Vec3>,
    attractors_changed: bool,
}

/// Loaded contour files and at most one reconstruction.
#[wasm_bindgen]
pub struct Session {
    files: BTreeMap<String, ContourSet>,
    run: Option<ActiveRun>,
}

impl Default for Session {
    fn default() -> Self {
        Self::new()
    }
}

#[wasm_bindgen]
impl Session {
    #[wasm_bindgen(constructor)]
    pub fn new() -> Session {
        Session {
            files: BTreeMap::new(),
            run: None,
        }
    }

    /// Parses a contour file and keeps it under `file_name` (replacing an earlier one). Returns
    /// the JSON of the protocol's `LoadedFile` without `points` (see [`Session::file_points`]);
    /// for a saved session, `session` holds its settings (`convert::session_settings`).
    /// `frame` reads that time frame of a file holding several (GPFile, CSV with a frame column),
    /// by its label as `timeFrames.frames` lists it or as the file writes it (`9`, `ES`; absent
    /// or blank: each contour's first); `timeFrames` lists the file's frames and those read.
    pub fn load(
        &mut self,
        file_name: &str,
        bytes: &[u8],
        frame: Option<String>,
    ) -> Result<String, JsValue> {
        self.load_with_views(file_name, bytes, &[], frame)
    }

    /// [`Session::load`] of a short-axis label map (NIfTI, NRRD, DICOM SEG) with its long-axis views: single-slice
    /// label maps named `view_names`, their bytes the `Uint8Array`s of `views` in the same order
    /// (the core matches their labels to the stack's by position and adds one curve per surface
    /// each shows; `warnings` says what each view was read as). Loading the stack again, for
    /// another frame, needs its views again. Of a cvi42 workspace, `views` are the DICOM images
    /// it was drawn on (their headers are enough; the core's note, first in `notes`, says how
    /// many placed its contours).
    pub fn load_study(
        &mut self,
        file_name: &str,
        bytes: &[u8],
        view_names: Vec<String>,
        views: js_sys::Array,
        frame: Option<String>,
    ) -> Result<String, JsValue> {
        let views = convert::views_from_js(view_names, &views)?;
        let pairs = convert::view_pairs(&views);
        self.load_with_views(file_name, bytes, &pairs, frame)
    }
}

impl Session {
    /// The work of [`Session::load`] and [`Session::load_study`] (native, so tests reach it).
    pub fn load_with_views(
        &mut self,
        file_name: &str,
        bytes: &[u8],
        views: &[(&str, &[u8])],
        frame: Option<String>,
    ) -> Result<String, JsValue> {
        let set = read_contours(file_name, bytes, views, frame.as_deref())
            .map_err(|e| errors::to_js(&e))?;
        let landmarks: Vec<_> = set
            .landmarks
            .iter()
            .map(|(name, p)| json!({ "name": name, "x": p.x, "y": p.y, "z": p.z }))
            .collect();
        // SAX/LAX drawn before any run: the core's rule, per surface (null where undecidable).
        let mut contours = convert::contour_infos(&set.contours, None);
        if let serde_json::Value::Array(items) = &mut contours {
            for (item, kind) in items.iter_mut().zip(classify_kinds(&set)) {
                item["kind"] = json!(kind);
            }
        }
        // The label-map reader's account of what it read is information, shown apart.
        let (notes, warnings): (Vec<String>, Vec<String>) = set
            .warnings
            .iter()
            .map(|w| frames::in_app_words(w))
            .partition(|w| io::is_reading_note(w));
        let mut warnings = warnings;
        // Those about one surface's contours only, so the app shows each surface its own.
        let surface_warnings: Vec<_> = set
            .surface_warnings
            .iter()
            .map(|(surface, w)| json!({ "surface": surface, "text": frames::in_app_words(w) }))
            .collect();
        // A saved session also carries the settings it was made with: the app applies them.
        let settings = if io::session::looks_like_session(bytes) {
            match io::session::read_session(bytes).and_then(|s| s.params()) {
                Ok(p) => convert::session_settings(&p),
                Err(e) => {
                    warnings.push(format!("the session's parameters were not applied: {e}"));
                    serde_json::Value::Null
                }
            }
        } else {
            serde_json::Value::Null
        };
        let info = json!({
            "fileName": file_name,
            "surfaces": surfaces_offered(&set),
            "contours": contours,
            "landmarks": landmarks,
            "warnings": warnings,
            "notes": notes,
            "surfaceWarnings": surface_warnings,
            "session": settings,
            "timeFrames": frames::time_frames_json(set.time_frames.as_ref()),
            // The patient frame the format fixes (LPS, RAS; null: unknown): the app's mesh
            // exports say it where 3D Slicer reads it.
            "coordinateSystem": set.coordinate_system.map(|c| c.name()),
        });
        self.files.insert(file_name.to_string(), set);
        Ok(info.to_string())
    }
}

/// A contour file's contours as [`Session::load`] reads them (with its long-axis views, as time
/// frame `frame`), without keeping them: the phases batch reads the frames of a sequence the
/// session does not hold, and must not replace the frame the page shows.
pub(crate) fn read_contours(
    file_name: &str,
    bytes: &[u8],
    views: &[(&str, &[u8])],
    frame: Option<&str>,
) -> heartmesh_core::error::Result<ContourSet> {
    let options = io::ContourOptions {
        frame: frame.and_then(io::FrameChoice::new),
        views,
        ..io::ContourOptions::default()
    };
    io::read_contours_with(file_name, bytes, &options)
}

#[wasm_bindgen]
impl Session {
    /// xyz (mm) of all points of a loaded file, in the order `load`'s pieces index.
    pub fn file_points(&self, file_name: &str) -> Result<Vec<f32>, JsValue> {
        let set = self.file(file_name)?;
        Ok(convert::flat_points(&set.contours))
    }

    /// A heartmesh session file (the core's `io::session` JSON) of a loaded file with these
    /// settings (same arguments as [`Session::start`]), so that opening it again brings back the
    /// contours, the parameters, the options, the lids and the surface.
    pub fn session_json(
        &self,
        file_name: &str,
        surface: Option<String>,
        params_json: &str,
        lids: &str,
        app_version: &str,
    ) -> Result<Vec<u8>, JsValue> {
        let params =
            convert::params_from_json(params_json, lids, surface).map_err(|e| errors::to_js(&e))?;
        let set = self.file(file_name)?;
        io::session::write_session(set, &params, app_version).map_err(|e| errors::to_js(&e))
    }

    /// Forgets a loaded file.
    pub fn unload(&mut self, file_name: &str) {
        self.files.remove(file_name);
    }

    /// Starts a reconstruction of a loaded file, replacing any run in progress. `params_json` is
    /// an object of schema names to numbers (missing ones take their defaults), which may also
    /// carry `smoothing_method`, `soften_conflicts`, `align_slices`, `end_caps`, `keep_specks` and
    /// `apex_floor` (see `convert`); `lids` is "auto"
    /// or "none"; `surface` picks one surface of a multi-surface file.
    pub fn start(
        &mut self,
        file_name: &str,
        surface: Option<String>,
        params_json: &str,
        lids: &str,
    ) -> Result<(), JsValue> {
        self.run = None;
        let params =
            convert::params_from_json(params_json, lids, surface).map_err(|e| errors::to_js(&e))?;
        let set = self.file(file_name)?;
        let mut rec = Reconstruction::new(set, params).map_err(|e| errors::to_js(&e))?;
        rec.set_clock(Box::new(clock::PerformanceClock::new()));
        self.run = Some(ActiveRun {
            rec,
            lids: lids.to_string(),
            last_attractors: Vec::new(),
            attractors_changed: false,
        });
        Ok(())
    }

    /// Advances one iteration; returns the JSON of the core's `StepReport`.
    pub fn step(&mut self) -> Result<String, JsValue> {
        let run = self.run_mut()?;
        let report = run.rec.step().map_err(|e| errors::to_js(&e))?;
        let attractors = run.rec.attractors();
        run.attractors_changed = attractors != run.last_attractors;
        run.last_attractors = attractors;
        serde_json::to_string(&report).map_err(|e| errors::usage("internal", e.to_string()))
    }

    /// The core's note before a long run (`Reconstruction::growth_note`: a mesh that will reach the
    /// remesh cap, or attractors that make the spline's solve long),
    /// known after the first step; None otherwise or before.
    pub fn growth_note(&self) -> Option<String> {
        self.run.as_ref().and_then(|r| r.rec.growth_note())
    }

    pub fn is_done(&self) -> bool {
        self.run.as_ref().is_some_and(|r| r.rec.is_done())
    }

    /// True when the last step re-sampled the attractors.
    pub fn attractors_changed(&self) -> bool {
        self.run.as_ref().is_some_and(|r| r.attractors_changed)
    }

    /// Current mesh vertices, xyz, mm.
    pub fn positions(&self) -> Result<Vec<f32>, JsValue> {
        Ok(self.run_ref()?.rec.mesh().positions_f32())
    }

    /// Current mesh vertices in full precision (for differential tests against the native CLI).
    pub fn positions_f64(&self) -> Result<Vec<f64>, JsValue> {
        let mesh = self.run_ref()?.rec.mesh();
        Ok(mesh
            .positions
            .iter()
            .flat_map(|p| [p.x, p.y, p.z])
            .collect())
    }

    /// Current triangles, three vertex indices each, counter-clockwise seen from outside.
    pub fn indices(&self) -> Result<Vec<u32>, JsValue> {
        Ok(self.run_ref()?.rec.mesh().indices_u32())
    }

    /// Current attractor points, xyz, mm.
    pub fn attractors(&self) -> Result<Vec<f32>, JsValue> {
        Ok(convert::flat_vec3(&self.run_ref()?.last_attractors))
    }

    /// The selected surface's cleaned contour points, xyz, mm (the order of `result_json`'s
    /// contour pieces and of `point_distances`).
    pub fn contour_points(&self) -> Result<Vec<f32>, JsValue> {
        Ok(convert::flat_points(self.run_ref()?.rec.contours()))
    }

    /// Distance (mm) from each contour point to the mesh, in f64 (tests) ...
    pub fn point_distances_f64(&self) -> Result<Vec<f64>, JsValue> {
        Ok(self.run_ref()?.rec.contour_distances().per_point)
    }

    /// ... and in f32 (display).
    pub fn point_distances(&self) -> Result<Vec<f32>, JsValue> {
        Ok(convert::to_f32(&self.point_distances_f64()?))
    }

    /// Distance (mm) from each mesh vertex to the nearest contour point, in f64 (the mesh
    /// files' point data, written as the command line writes them) ...
    pub fn vertex_distances_f64(&self) -> Result<Vec<f64>, JsValue> {
        Ok(self.run_ref()?.rec.vertex_distances())
    }

    /// ... and in f32 (display).
    pub fn vertex_distances(&self) -> Result<Vec<f32>, JsValue> {
        Ok(convert::to_f32(&self.vertex_distances_f64()?))
    }

    /// xyz (mm) of the contours the run leaves out (the user's, strays and specks: the core's
    /// `set_aside_contours`, as the file gives them, moved with their image when aligned), in the
    /// order `result_json`'s `set_aside_contours` pieces index.
    pub fn set_aside_points(&self) -> Result<Vec<f32>, JsValue> {
        Ok(convert::flat_points(
            self.run_ref()?.rec.set_aside_contours(),
        ))
    }

    /// Distance (mm) of each of those points to the mesh (the core's, taken where they are
    /// drawn), in `set_aside_points` order: the hover's read-out on a contour left out.
    pub fn set_aside_point_distances(&self) -> Result<Vec<f32>, JsValue> {
        Ok(convert::to_f32(
            &self.run_ref()?.rec.set_aside_point_distances(),
        ))
    }

    /// JSON of the small part of the protocol's `RunResult` ([`convert::result_value`]; with
    /// `align_slices`, `alignment` holds the shifts and `contours` and `contour_points` are the
    /// shifted contours), plus `set_aside_contours`: the `ContourInfo`s of the contours left out
    /// (one per `set_aside` entry, in its order), indexing [`Session::set_aside_points`].
    pub fn result_json(&self) -> Result<String, JsValue> {
        let run = self.run_ref()?;
        let mut value = convert::result_value(&run.rec, &run.lids);
        value["set_aside_contours"] = convert::contour_infos(run.rec.set_aside_contours(), None);
        Ok(value.to_string())
    }
}

impl Session {
    /// A loaded file's contours (None: not loaded), for callers that must not build a JS error.
    fn loaded(&self, file_name: &str) -> Option<&ContourSet> {
        self.files.get(file_name)
    }

    fn file(&self, file_name: &str) -> Result<&ContourSet, JsValue> {
        self.files
            .get(file_name)
            .ok_or_else(|| errors::usage("not_loaded", format!("{file_name} has not been loaded")))
    }

    fn run_ref(&self) -> Result<&ActiveRun, JsValue> {
        self.run
            .as_ref()
            .ok_or_else(|| errors::usage("no_run", "no reconstruction has been started"))
    }

    fn run_mut(&mut self) -> Result<&mut ActiveRun, JsValue> {
        self.run
            .as_mut()
            .ok_or_else(|| errors::usage("no_run", "no reconstruction has been started"))
    }
}

/// The surfaces the app's picker offers: the file's own, then the biventricular epicardium the
/// core makes of its LV and RV epicardia when it has both.
fn surfaces_offered(set: &heartmesh_core::ContourSet) -> Vec<String> {
    let mut out = set.surfaces();
    if heartmesh_core::contours::biv_epi::available(set) {
        out.push(heartmesh_core::contours::biv_epi::BIV_EPI.to_string());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const RINGS: &str = "contour,x,y,z\n\
        a,20,0,0\na,0,20,0\na,-20,0,0\na,0,-20,0\n\
        b,20,0,10\nb,0,20,10\nb,-20,0,10\nb,0,-20,10\n";

    /// Warnings about one surface's contours only come with that surface, so the app can leave
    /// them out of another surface's run; the file's own warnings stay in `warnings` alone.
    #[test]
    fn load_names_the_surface_of_a_surface_warning() {
        let mut csv = String::from("contour,x,y,z,surface\n");
        for (surface, r) in [("LV_ENDO", 20.0), ("RV_ENDO", 30.0)] {
            for (k, z) in [0.0, 10.0, 20.0].iter().enumerate() {
                for i in 0..24 {
                    let t = std::f64::consts::TAU * i as f64 / 24.0;
                    let (x, y) = (r * t.cos() + 100.0 * f64::from(r > 25.0), r * t.sin());
                    csv.push_str(&format!("{surface}{k},{x},{y},{z},{surface}\n"));
                }
            }
        }
        csv.push_str("dot,1,2,5,LV_ENDO\n");
        let mut s = Session::new();
        let info: serde_json::Value =
            serde_json::from_str(&s.load("biv.csv", csv.as_bytes(), None).unwrap()).unwrap();
        let scoped = info["surfaceWarnings"].as_array().unwrap();
        assert_eq!(scoped.len(), 1, "{info}");
        assert_eq!(scoped[0]["surface"], "LV_ENDO");
        let text = scoped[0]["text"].as_str().unwrap();
        assert!(text.contains("\"dot\""), "{text}");
        assert_eq!(info["warnings"], serde_json::json!([text]));
    }

    #[test]
    fn a_written_session_loads_back_with_its_settings() {
        let mut s = Session::new();
        s.load("rings.csv", RINGS.as_bytes(), None).unwrap();
        let bytes = s
            .session_json(
                "rings.csv",
                None,
                r#"{"beta": 0.3, "smoothing_method": "taubin", "soften_conflicts": false}"#,
                "none",
                "9.9.9",
            )
            .unwrap();
        let info: serde_json::Value =
            serde_json::from_str(&s.load("rings.json", &bytes, None).unwrap()).unwrap();
        let settings = &info["session"];
        assert_eq!(settings["options"]["smoothing_method"], "taubin");
        assert_eq!(settings["options"]["soften_conflicts"], false);
        assert_eq!(settings["lids"], "none");
        assert_eq!(settings["params"]["beta"], 0.3);
        assert_eq!(info["contours"].as_array().map(Vec::len), Some(2));
        // The params object did not name the apex floor: stored on (the default), read back on.
        assert_eq!(settings["options"]["apex_floor"], true);
        let off = s
            .session_json(
                "rings.csv",
                None,
                r#"{"apex_floor": false}"#,
                "auto",
                "9.9.9",
            )
            .unwrap();
        let info: serde_json::Value =
            serde_json::from_str(&s.load("off.json", &off, None).unwrap()).unwrap();
        assert_eq!(info["session"]["options"]["apex_floor"], false);
        // A plain contour file carries no settings.
        let plain: serde_json::Value =
            serde_json::from_str(&s.load("rings.csv", RINGS.as_bytes(), None).unwrap()).unwrap();
        assert!(plain["session"].is_null());
    }

    /// A file of two time frames: the load result lists them and which was read, in the app's
    /// words (the picker, not `--frame`); a frame asked for is read alone, without the warning;
    /// a session of it records the frame and loads back knowing it (no picker: one frame).
    #[test]
    fn a_two_frame_file_loads_either_frame_and_says_which() {
        let mut two = String::from("contour,x,y,z,frame\n");
        for (frame, r) in [(0, 20.0), (9, 15.0)] {
            for (id, z) in [("a", 0.0), ("b", 10.0)] {
                for (x, y) in [(r, 0.0), (0.0, r), (-r, 0.0), (0.0, -r)] {
                    two.push_str(&format!("{id},{x},{y},{z},{frame}\n"));
                }
            }
        }
        let mut s = Session::new();
        let load = |s: &mut Session, frame: Option<u32>| -> serde_json::Value {
            let frame = frame.map(|f| f.to_string());
            serde_json::from_str(&s.load("two.csv", two.as_bytes(), frame).unwrap()).unwrap()
        };
        let first = load(&mut s, None);
        let t = &first["timeFrames"];
        assert_eq!(t["frames"], serde_json::json!(["0", "9"]));
        assert_eq!(t["read"], serde_json::json!(["0"]));
        assert_eq!(
            (t["chosen"].as_bool(), t["sequence"].as_bool()),
            (Some(false), Some(true))
        );
        assert_eq!(t["leftOut"], 8);
        let w = first["warnings"][0].as_str().unwrap();
        assert!(w.ends_with("frame 0 read, 8 points of other frames left out; choose another with the Frame picker"), "{w}");
        assert_eq!(s.file_points("two.csv").unwrap()[0], 20.0);
        let nine = load(&mut s, Some(9));
        assert_eq!(nine["timeFrames"]["read"], serde_json::json!(["9"]));
        assert_eq!(nine["timeFrames"]["chosen"], true);
        assert_eq!(nine["timeFrames"]["firsts"], serde_json::json!(["0"]));
        assert_eq!(nine["warnings"], serde_json::json!([]));
        assert_eq!(
            s.file_points("two.csv").unwrap()[0],
            15.0,
            "the file is now frame 9"
        );
        let bytes = s
            .session_json("two.csv", None, "{}", "auto", "9.9.9")
            .unwrap();
        assert!(String::from_utf8_lossy(&bytes).contains(r#""frame":"9""#));
        let saved: serde_json::Value =
            serde_json::from_str(&s.load("two.json", &bytes, None).unwrap()).unwrap();
        let t = &saved["timeFrames"];
        assert_eq!(
            (t["read"].clone(), t["sequence"].as_bool()),
            (serde_json::json!(["9"]), Some(false))
        );
        // No frame column: null, as a file of one frame shows no picker.
        let plain: serde_json::Value =
            serde_json::from_str(&s.load("rings.csv", RINGS.as_bytes(), None).unwrap()).unwrap();
        assert!(plain["timeFrames"].is_null());
    }

    /// Phases written as text (`ED`, `ES` in a `phase` column): the load lists them, and either
    /// is read by its label (as listed, or in another case), named as the file writes it; a
    /// session of `ES` saves it so and loads back knowing it.
    #[test]
    fn a_text_phase_is_read_by_its_label() {
        let mut two = String::from("contour,x,y,z,phase\n");
        for (phase, r) in [("ED", 20.0), ("ES", 15.0)] {
            for (id, z) in [("a", 0.0), ("b", 10.0)] {
                for (x, y) in [(r, 0.0), (0.0, r), (-r, 0.0), (0.0, -r)] {
                    two.push_str(&format!("{id},{x},{y},{z},{phase}\n"));
                }
            }
        }
        let mut s = Session::new();
        let load = |s: &mut Session, frame: Option<&str>| -> serde_json::Value {
            let frame = frame.map(str::to_string);
            serde_json::from_str(&s.load("ph.csv", two.as_bytes(), frame).unwrap()).unwrap()
        };
        let first = load(&mut s, None);
        assert_eq!(
            first["timeFrames"]["frames"],
            serde_json::json!(["ED", "ES"])
        );
        assert_eq!(first["timeFrames"]["read"], serde_json::json!(["ED"]));
        let w = first["warnings"][0].as_str().unwrap();
        assert!(
            w.ends_with("frame ED read, 8 points of other frames left out; choose another with the Frame picker"),
            "{w}"
        );
        for asked in ["ES", "es"] {
            let es = load(&mut s, Some(asked));
            assert_eq!(
                es["timeFrames"]["read"],
                serde_json::json!(["ES"]),
                "{asked}"
            );
            assert_eq!(es["timeFrames"]["chosen"], true);
            assert_eq!(es["warnings"], serde_json::json!([]));
            assert_eq!(
                s.file_points("ph.csv").unwrap()[0],
                15.0,
                "{asked}: ES read"
            );
        }
        let bytes = s
            .session_json("ph.csv", None, "{}", "auto", "9.9.9")
            .unwrap();
        assert!(String::from_utf8_lossy(&bytes).contains(r#""frame":"ES""#));
        let saved: serde_json::Value =
            serde_json::from_str(&s.load("es.json", &bytes, None).unwrap()).unwrap();
        assert_eq!(saved["timeFrames"]["read"], serde_json::json!(["ES"]));
        // A blank frame is none: the file's own reading.
        assert_eq!(
            load(&mut s, Some(" "))["timeFrames"]["read"],
            serde_json::json!(["ED"])
        );
    }

    /// An ellipsoidal cavity: SAX rings every 8 mm (the third shifted 3 mm along x) and two
    /// long-axis views, as CSV.
    fn misaligned_csv() -> String {
        let shift = |k: usize| if k == 2 { 3.0 } else { 0.0 };
        format!(
            "contour,x,y,z,surface\n{}",
            crate::test_data::cavity_rows("LV_ENDO", "", 25.0, 60.0, shift)
        )
    }

    /// `result_json` of a finished run (natively: `Session::start` needs the browser's clock).
    fn result_with(options: &str) -> serde_json::Value {
        result_of(&misaligned_csv(), options).0
    }

    /// The result of a run of `csv` and the file's contours it left out (what `Session::start`
    /// keeps for `set_aside_points`).
    fn result_of(
        csv: &str,
        options: &str,
    ) -> (serde_json::Value, Vec<heartmesh_core::contours::Contour>) {
        let set = io::read_contours("lv.csv", csv.as_bytes()).unwrap();
        let params = convert::params_from_json(options, "auto", None).unwrap();
        let mut rec = Reconstruction::new(&set, params).unwrap();
        rec.run().unwrap();
        let aside = rec.set_aside_contours().to_vec();
        (convert::result_value(&rec, "auto"), aside)
    }

    /// The ellipsoid with a speck: a 3-point loop 2.9 mm around, in a short-axis plane 8 mm past
    /// the basal ring (as `public/samples` plus a stray click), and the line of its first point.
    fn speck_csv() -> (String, usize) {
        let mut csv = misaligned_csv();
        let line = csv.lines().count() + 1;
        for (x, y) in [(5.0, 0.0), (4.4, 0.6), (4.4, -0.6)] {
            csv.push_str(&format!("speck,{x},{y},8,LV_ENDO\n"));
        }
        (csv, line)
    }

    /// The run's result names the speck it left out as the CLI report does (`id`, `line`,
    /// `reason`, its figures), the binding hands out its points, and `keep_specks` keeps it.
    #[test]
    fn result_json_carries_the_contours_set_aside() {
        let (csv, line) = speck_csv();
        let (left_out, aside) = result_of(&csv, r#"{"iterations": 3}"#);
        let list = left_out["set_aside"].as_array().unwrap();
        assert_eq!(list.len(), 1, "{list:?}");
        let s = &list[0];
        assert_eq!(s["id"], "speck");
        assert_eq!(s["line"].as_u64(), Some(line as u64));
        assert_eq!(s["reason"], "speck");
        let around = s["perimeter_mm"].as_f64().unwrap();
        assert!((2.8..3.0).contains(&around), "{around}");
        assert_eq!(s["next_id"], "s6");
        assert!(s["next_perimeter_mm"].as_f64().unwrap() > 100.0);
        assert_eq!(left_out["options"]["keep_specks"], false);
        // Not among the contours the run follows; its own three points, as the file gives them.
        let ids = |r: &serde_json::Value| -> Vec<String> {
            r["contours"]
                .as_array()
                .unwrap()
                .iter()
                .map(|c| c["id"].as_str().unwrap().to_string())
                .collect()
        };
        assert!(!ids(&left_out).contains(&"speck".to_string()));
        assert_eq!(aside.len(), 1);
        assert_eq!(aside[0].id, "speck");
        let info = convert::contour_infos(&aside, None);
        assert_eq!(info[0]["pieces"][0]["start"], 0);
        assert_eq!(info[0]["pieces"][0]["count"], 3);
        let points = convert::flat_points(&aside);
        assert_eq!(points.len(), 9);
        assert_eq!(&points[..3], &[5.0, 0.0, 8.0]);
        // Kept: one contour more, nothing left out.
        let (kept, none) = result_of(&csv, r#"{"iterations": 3, "keep_specks": true}"#);
        assert_eq!(kept["set_aside"], serde_json::json!([]));
        assert!(none.is_empty());
        assert_eq!(kept["options"]["keep_specks"], true);
        assert!(ids(&kept).contains(&"speck".to_string()));
        assert_eq!(ids(&kept).len(), ids(&left_out).len() + 1);
        // The file without it: nothing to leave out.
        assert_eq!(
            result_with(r#"{"iterations": 3}"#)["set_aside"],
            serde_json::json!([])
        );
    }

    /// A contour named in `leave_out` is left out like the rules' (`set_aside` with reason
    /// `by_user`, its points handed out), the result echoes the list, and an id the file lacks
    /// is an error naming the option's id.
    #[test]
    fn result_json_carries_the_contours_left_out_by_the_user() {
        let csv = misaligned_csv();
        let (all, none) = result_of(&csv, r#"{"iterations": 3}"#);
        assert!(none.is_empty());
        assert_eq!(all["leave_out"], serde_json::json!([]));
        let (asked, aside) = result_of(&csv, r#"{"iterations": 3, "leave_out": ["s2"]}"#);
        let line = 2 + csv
            .lines()
            .skip(1)
            .position(|l| l.starts_with("s2,"))
            .unwrap();
        let entry = &asked["set_aside"][0];
        assert_eq!(asked["set_aside"].as_array().unwrap().len(), 1);
        assert_eq!(
            (&entry["id"], entry["line"].as_u64(), &entry["reason"]),
            (
                &serde_json::json!("s2"),
                Some(line as u64),
                &serde_json::json!("by_user")
            )
        );
        // How far the mesh built without it passes from it, as the CLI report gives it.
        let mm = |k: &str| entry[k].as_f64().unwrap();
        assert!(mm("mean") > 0.0 && mm("mean") <= mm("max") && mm("median") <= mm("max"));
        assert!(mm("max").is_finite(), "{entry}");
        assert_eq!(asked["leave_out"], serde_json::json!(["s2"]));
        assert_eq!(aside.len(), 1);
        assert_eq!(aside[0].id, "s2");
        let count = |r: &serde_json::Value| r["perContour"].as_array().unwrap().len();
        assert_eq!(count(&asked) + 1, count(&all));
        let set = io::read_contours("lv.csv", csv.as_bytes()).unwrap();
        let params = convert::params_from_json(r#"{"leave_out": ["s22"]}"#, "auto", None).unwrap();
        let e = Reconstruction::new(&set, params).err().unwrap();
        assert_eq!(e.code(), "unknown_contour");
        assert!(e.to_string().contains("\"s22\""), "{e}");
    }

    /// The misaligned ellipsoid's short-axis slices alone (no long-axis curve reaches the apex):
    /// at the defaults the result says the apex got a floor (`end_caps.apex_floor`) and that the
    /// floor was on (`options.apex_floor`); with `"apex_floor": false` neither, and the mesh
    /// differs.
    #[test]
    fn result_json_says_whether_the_apex_got_a_floor() {
        let sax_only: String = misaligned_csv()
            .lines()
            .filter(|l| !l.starts_with('l'))
            .map(|l| format!("{l}\n"))
            .collect();
        let (on, _) = result_of(&sax_only, r#"{"iterations": 20}"#);
        assert_eq!(on["options"]["apex_floor"], true);
        assert_eq!(on["end_caps"]["apex_floor"], true, "{}", on["end_caps"]);
        assert_eq!(on["end_caps"]["apex"], true);
        let (off, _) = result_of(&sax_only, r#"{"iterations": 20, "apex_floor": false}"#);
        assert_eq!(off["options"]["apex_floor"], false);
        assert!(
            off["end_caps"].get("apex_floor").is_none(),
            "{}",
            off["end_caps"]
        );
        assert_ne!(on["volumeMl"], off["volumeMl"]);
        // Long-axis curves reach the apex: no floor, whatever the switch.
        let full = result_with(r#"{"iterations": 3}"#);
        assert_eq!(full["options"]["apex_floor"], true);
        assert!(full["end_caps"].get("apex_floor").is_none());
    }

    #[test]
    fn result_json_carries_the_alignment() {
        let off = result_with(r#"{"iterations": 3}"#);
        assert!(off["alignment"].is_null());
        assert!(off["contour_to_mesh_as_given"].is_null());
        // Three iterations in, the mesh still stops short of the apex the curves reach.
        assert!(off["pastData"]["apex_mm"].as_f64().unwrap() < 0.0);
        assert_eq!(off["options"]["align_slices"], false);
        let on = result_with(r#"{"align_slices": true}"#);
        assert_eq!(on["options"]["align_slices"], true);
        // A full run: the long-axis curves close the apex, so the mesh ends at the data there.
        let apex = on["pastData"]["apex_mm"].as_f64().unwrap();
        assert!(
            apex.abs() < 2.0 && on["pastData"]["base_mm"].is_f64(),
            "{apex}"
        );
        let a = &on["alignment"];
        // The residual every run reports is the alignment's starting point; one slice 3 mm off
        // in seven is not enough to suggest aligning (measured 0.29 mm), and with it on, no need.
        let r = off["crossing_residual_mm"].as_f64().unwrap();
        assert_eq!(a["residual_before_mm"].as_f64(), Some(r));
        assert_eq!(on["crossing_residual_mm"].as_f64(), Some(r));
        assert!((0.2..1.0).contains(&r), "{r}");
        assert_eq!(off["suggest_alignment"], false);
        assert_eq!(on["suggest_alignment"], false);
        let groups = a["groups"].as_array().unwrap();
        // Seven slices and two views, each with its kind, label, ids and a shift in mm.
        assert_eq!(groups.len(), 9);
        assert_eq!(groups[0]["kind"], "SAX");
        assert_eq!(groups[0]["label"], "SAX 1");
        // The views in an order of their own (longest curve first), each named by its curve.
        let mut views: Vec<&str> = groups[7..]
            .iter()
            .map(|g| {
                assert_eq!(g["kind"], "LAX");
                assert_eq!(g["contour_ids"], serde_json::json!([g["label"]]));
                g["label"].as_str().unwrap()
            })
            .collect();
        views.sort_unstable();
        assert_eq!(views, ["l0", "l1"]);
        let shift = |g: &serde_json::Value| -> Vec<f64> {
            g["shift_mm"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap())
                .collect()
        };
        // The shifted slice moves back by about its 3 mm relative to the others.
        let x: Vec<f64> = groups[..7].iter().map(|g| shift(g)[0]).collect();
        let others = (x.iter().sum::<f64>() - x[2]) / 6.0;
        assert!((x[2] - others + 3.0).abs() < 0.3, "{x:?}");
        assert!(a["rounds"].as_u64().unwrap() >= 1);
        let before = a["residual_before_mm"].as_f64().unwrap();
        let after = a["residual_after_mm"].as_f64().unwrap();
        // One slice in seven is off: the mean over all crossings starts at a fraction of 3 mm.
        assert!(before > 0.2 && after < 0.1 * before, "{before} -> {after}");
        // The mesh follows the shifted contours: the file's own slice stays ~3 mm off it.
        let to_shifted = on["overall"]["mean"].as_f64().unwrap();
        let given = &on["contour_to_mesh_as_given"];
        let (given_mean, given_max) = (
            given["mean"].as_f64().unwrap(),
            given["max"].as_f64().unwrap(),
        );
        assert!(
            given_mean > to_shifted + 0.1,
            "{given_mean} vs {to_shifted}"
        );
        assert!((2.0..4.0).contains(&given_max), "{given_max}");
    }

    /// `end_caps` rides in the params JSON and comes back in the result: the ellipsoid's curves
    /// close its apex, not its base (they stop 4 mm above the top ring, at the wall).
    #[test]
    fn result_json_carries_the_end_caps() {
        let off = result_with(r#"{"iterations": 3, "end_caps": "off"}"#);
        assert_eq!(
            off["end_caps"],
            serde_json::json!({"mode": "off", "base": false, "apex": false, "points": 0})
        );
        assert_eq!(off["options"]["end_caps"], "off");
        let on = result_with(r#"{"iterations": 3, "end_caps": "auto"}"#);
        assert_eq!(on["end_caps"]["mode"], "auto");
        assert_eq!(on["end_caps"]["base"], true);
        assert_eq!(on["end_caps"]["apex"], false);
        let points = on["end_caps"]["points"].as_u64().unwrap();
        assert!((5..=100).contains(&points), "{points}");
        assert_eq!(on["options"]["end_caps"], "auto");
        // Lid points are not data: the same contour points are measured either way.
        assert_eq!(on["overall"]["count"], off["overall"]["count"]);
        let e = convert::params_from_json(r#"{"end_caps": "on"}"#, "auto", None).unwrap_err();
        assert_eq!(e.code(), "param_invalid");
        assert!(e.to_string().contains("end_caps"), "{e}");
        assert!(e.to_string().contains("auto, off"), "{e}");
        let e = convert::params_from_json(r#"{"end_caps": true}"#, "auto", None).unwrap_err();
        assert!(e.to_string().contains("auto, off"), "{e}");
    }

    /// The mesh checks a volume mesher needs ride in the result: the full run on the ellipsoid
    /// gives a surface with no crossing triangles and no creases.
    #[test]
    fn result_json_carries_the_mesh_quality() {
        let r = result_with(r#"{"iterations": 30}"#);
        assert_eq!(r["quality"]["self_intersections"], 0);
        assert_eq!(r["quality"]["folded_edges"], 0);
    }
}
