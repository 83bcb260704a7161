//! The validation lab's binding (issue 5): a ground-truth surface (the parametric LV or a dropped
//! mesh) or several labelled surfaces of one heart (`lab/truths.rs`), a simulated CMR acquisition
//! of them, the comparison of a reconstruction with the truth of its surface clipped at the most
//! basal SAX plane, and stepped batches (leave-one-out, parameter sweep). It
//! follows the validation protocol of Villard, Grau & Zacur (J. Imaging 2018, section 3); every
//! algorithm is heartmesh-core's `sim` and `metrics` modules, this file only holds state between
//! calls and converts at the boundary (same rules as [`crate::Session`]).

mod batch;
mod phases;
mod spec;
mod truths;

use heartmesh_core::contours::{ContourSet, CoordinateSystem};
use heartmesh_core::error::CoreError;
use heartmesh_core::io;
use heartmesh_core::mesh::topology;
use heartmesh_core::metrics::anatomical::Layout;
use heartmesh_core::metrics::compare::{compare, vertex_distances, ClipPlane};
use heartmesh_core::sim::planes::simulate_surfaces;
use heartmesh_core::sim::repair::{orient_consistently, weld};
use heartmesh_core::sim::simulate;
use heartmesh_core::TriMesh;
use serde_json::json;
use wasm_bindgen::prelude::*;

use crate::{convert, errors, wall, Session};
use batch::Batch;
use truths::{usage, Truths};
pub use truths::{LabError, Truth};

/// Triangulation of the parametric LV: points per ring and rings from apex to base (~0.5 mm
/// edges near the apex, ~1.7 mm at the equator: finer than any reconstruction we compare).
const LV_AROUND: usize = 96;
const LV_ALONG: usize = 64;

/// Distance under which dropped-mesh vertices are merged (STL stores every triangle's corners).
const WELD_MM: f64 = 1e-6;

/// The Lab's state: its truths (one, or several surfaces of one heart), their last acquisition,
/// the last comparison, and one batch.
#[wasm_bindgen]
pub struct Lab {
    truths: Truths,
    /// Per truth (in order), the most basal SAX plane of the last acquisition that carries a
    /// contour of it: where that truth is clipped (a surface drawn only below the others' base,
    /// `sim::planes::simulate_surfaces`, is unobserved above its own top slice). Empty: none.
    clips: Vec<ClipPlane>,
    simulated: Option<ContourSet>,
    last_distances: Vec<f64>,
    batch: Option<Batch>,
    batch_points: Vec<f32>,
    /// The last phases batch once finished (its meshes, contours and base planes), for the
    /// study's anatomical layouts; dropped when another phases batch starts.
    finished_phases: Option<phases::Phases>,
    /// The files of the last [`Lab::phases_anatomical`], each taken once by
    /// [`Lab::phases_anatomical_file`].
    anatomical_files: Vec<Option<Vec<u8>>>,
}

/// How the study's anatomical layouts' failures begin in the app.
pub const ANATOMICAL_STUDY: &str = "the anatomical meshes";

impl Default for Lab {
    fn default() -> Self {
        Self::new()
    }
}

/// A Lab error as the worker expects it (core errors keep their code and line).
fn js(e: LabError) -> JsValue {
    match e {
        LabError::Core(e) => errors::to_js(&e),
        LabError::Usage { code, message } => errors::usage(code, message),
    }
}

#[wasm_bindgen]
impl Lab {
    #[wasm_bindgen(constructor)]
    pub fn new() -> Lab {
        Lab {
            truths: Truths::default(),
            clips: Vec::new(),
            simulated: None,
            last_distances: Vec::new(),
            batch: None,
            batch_points: Vec::new(),
            finished_phases: None,
            anatomical_files: Vec::new(),
        }
    }

    /// Makes the built-in parametric LV the only truth (see `lab/spec.rs` for the JSON); returns
    /// the truth's description `{name, label, index, vertices, triangles, volumeMl, closed}`.
    pub fn make_parametric(&mut self, lv_json: &str) -> Result<String, JsValue> {
        self.make_parametric_with(lv_json).map_err(js)
    }

    /// Reads a dropped mesh (OBJ, STL, PLY, VTK, VTP) as the only truth: welded (STL stores
    /// corners per triangle) and consistently oriented (mixed orientations spoil volumes), as the
    /// CLI does.
    pub fn load_truth(&mut self, file_name: &str, bytes: &[u8]) -> Result<String, JsValue> {
        self.load_truth_with(file_name, None, bytes).map_err(js)
    }

    /// Reads a mesh as one more truth, labelled `label` (LV_ENDO, ...; None: to be given before
    /// simulating several); a clashing or invalid label is refused and the truths stay as they
    /// were. Returns its description (with its `index`).
    pub fn add_truth(
        &mut self,
        file_name: &str,
        label: Option<String>,
        bytes: &[u8],
    ) -> Result<String, JsValue> {
        self.add_truth_with(file_name, label, bytes).map_err(js)
    }

    /// Labels truth `index` (None: no label); returns `[{name, label}]` of all truths.
    pub fn set_truth_label(
        &mut self,
        index: usize,
        label: Option<String>,
    ) -> Result<String, JsValue> {
        self.set_truth_label_with(index, label).map_err(js)
    }

    /// Removes truth `index`; returns `[{name, label}]` of the truths left.
    pub fn remove_truth(&mut self, index: usize) -> Result<String, JsValue> {
        self.remove_truth_with(index).map_err(js)
    }

    /// Vertices of truth `index`, xyz, mm.
    pub fn truth_positions(&self, index: usize) -> Result<Vec<f32>, JsValue> {
        Ok(self.truths.get(index).map_err(js)?.mesh.positions_f32())
    }

    /// Triangles of truth `index`, outward.
    pub fn truth_indices(&self, index: usize) -> Result<Vec<u32>, JsValue> {
        Ok(self.truths.get(index).map_err(js)?.mesh.indices_u32())
    }

    /// Slices the truths like a CMR acquisition (see `lab/spec.rs` for the JSON): one truth as
    /// `sim::simulate` does, several on one acquisition with `sim::planes::simulate_surfaces`.
    /// Keeps the contours and the most basal SAX plane. Returns `{sax, lax, points, surfaces:
    /// [{label, sax, lax, points}], clip: {origin, normal}}`; the contours themselves come from
    /// [`Lab::simulated_csv`].
    pub fn simulate(&mut self, acquisition_json: &str) -> Result<String, JsValue> {
        self.simulate_with(acquisition_json).map_err(js)
    }

    /// The last simulated contours as canonical CSV (loaded like any dropped contour file).
    pub fn simulated_csv(&self) -> Result<Vec<u8>, JsValue> {
        self.simulated_csv_with().map_err(js)
    }

    /// Compares a reconstruction of `surface` (xyz mm, triangles) with the truth of that surface
    /// (the only one when there is one), both clipped at the most basal SAX plane carrying a
    /// contour of that surface in the last acquisition; returns the JSON of the core's `CompareReport` plus `truth_index`,
    /// `truth_label` and `truth_name`. Keeps the distance of every vertex of that truth to the
    /// mesh for [`Lab::truth_distances`].
    pub fn compare(
        &mut self,
        surface: Option<String>,
        positions: &[f32],
        indices: &[u32],
    ) -> Result<String, JsValue> {
        self.compare_with(surface.as_deref(), positions, indices)
            .map_err(js)
    }

    /// Per vertex of the truth of the last [`Lab::compare`], distance (mm) to the mesh.
    pub fn truth_distances(&self) -> Vec<f32> {
        convert::to_f32(&self.last_distances)
    }

    /// Starts leave-one-out on a file loaded in `session`; returns `{total, contours}` (the
    /// protocol's ContourInfo[] of the cleaned contours, the order of the items); their points
    /// come from [`Lab::batch_points`].
    pub fn start_leave_one_out(
        &mut self,
        session: &Session,
        file_name: &str,
        surface: Option<String>,
        params_json: &str,
        lids: &str,
    ) -> Result<String, JsValue> {
        let params = self
            .new_batch_params(params_json, lids, surface)
            .map_err(|e| errors::to_js(&e))?;
        let set = session.file(file_name)?;
        let (batch, cleaned, kinds) =
            Batch::leave_one_out(set, &params).map_err(|e| errors::to_js(&e))?;
        self.batch_points = convert::flat_points(&cleaned);
        let info = json!({
            "total": batch.total(),
            "contours": convert::contour_infos(&cleaned, Some(&kinds)),
        });
        self.batch = Some(batch);
        Ok(info.to_string())
    }

    /// Starts a sweep on a loaded file. `sweep_json` = `{grid: {lambda: [..],
    /// smoothing_iterations: [..], target_reduction: [..], attractor_spacing: [..]}, with_truth}`
    /// (a missing or empty list keeps the base value; with `with_truth`, every result is also
    /// compared with the truth). Returns `{total}`.
    pub fn start_sweep(
        &mut self,
        session: &Session,
        file_name: &str,
        surface: Option<String>,
        params_json: &str,
        lids: &str,
        sweep_json: &str,
    ) -> Result<String, JsValue> {
        let params = self
            .new_batch_params(params_json, lids, surface)
            .map_err(|e| errors::to_js(&e))?;
        let (grid, with_truth) = sweep_request(sweep_json).map_err(|e| errors::to_js(&e))?;
        let set = session.file(file_name)?;
        let truth = if with_truth {
            self.sweep_truth(surface_of(&params))?
        } else {
            None
        };
        let batch = Batch::sweep(set, &params, &grid, truth).map_err(|e| errors::to_js(&e))?;
        let info = json!({ "total": batch.total() });
        self.batch = Some(batch);
        self.batch_points.clear();
        Ok(info.to_string())
    }

    /// Starts the phases batch of one heart's function: every surface of every phase at these
    /// parameters. `phases_json` = `[{name, file, frame?}]`: a phase is a loaded file as the
    /// session holds it, or (with `frame`) that time frame of the file whose bytes (and long-axis
    /// views, names and `Uint8Array`s) are given here, read without replacing the session's file,
    /// whose frame the page shows. Returns `{total, phases, surfaces}`; the items are the cells,
    /// phase by phase, and the last `batch_step` carries the `summary`.
    #[allow(clippy::too_many_arguments)]
    pub fn start_phases(
        &mut self,
        session: &Session,
        phases_json: &str,
        params_json: &str,
        lids: &str,
        sequence: &[u8],
        view_names: Vec<String>,
        views: js_sys::Array,
    ) -> Result<String, JsValue> {
        let views = convert::views_from_js(view_names, &views)?;
        let pairs = convert::view_pairs(&views);
        self.start_phases_with(session, phases_json, params_json, lids, sequence, &pairs)
            .map_err(|e| errors::to_js(&e))
    }

    /// Advances the batch by one pipeline step: `{completed, total, done, item?}` (and, for the
    /// phases batch once done, `summary`).
    pub fn batch_step(&mut self) -> Result<String, JsValue> {
        let batch = self
            .batch
            .as_mut()
            .ok_or_else(|| errors::usage("no_batch", "no batch has been started"))?;
        let p = batch.step();
        let done = batch.is_done();
        let mut out = json!({ "completed": p.completed, "total": p.total, "done": done });
        if let Some(item) = p.item {
            out["item"] = item;
        }
        if let Some(summary) = batch.summary() {
            out["summary"] = summary;
        }
        if done {
            // A finished phases batch stays for its anatomical layouts.
            self.finished_phases = self.batch.take().and_then(Batch::into_phases);
        }
        Ok(out.to_string())
    }

    /// The anatomical layouts of the last finished phases batch, as `heartmesh volumes
    /// --anatomical-meshes` writes them: every phase's LV surfaces (LV_ENDO, LV_EPI) resampled on
    /// `layout` (`RINGSxPOINTS`, e.g. "24x48": the same vertices and triangles in every file),
    /// all turned by the septum of the LV's end-diastole, each with point data `displacement_mm`
    /// from the same vertex at that phase, written as `format` (vtk, vtp, ply, obj, stl). Returns
    /// the command line report's `anatomical_meshes` (`{format, layout, septum,
    /// displacement_from_phase, layouts: [{phase, surface, file, summary, septum_turn_deg,
    /// displacement_mean_mm, displacement_max_mm} | {phase, surface, file: null, note}]}`) plus
    /// `files: [{name, index}]`, each file's bytes then taken with
    /// [`Lab::phases_anatomical_file`]. Without a finished phases batch, an LV surface among those
    /// measured or a phase saying where the septum is, an error whose message says why, starting
    /// "the anatomical meshes: ".
    pub fn phases_anatomical(&mut self, layout: &str, format: &str) -> Result<String, JsValue> {
        self.phases_anatomical_with(layout, format)
            .map_err(|e| JsValue::from_str(&e.to_string()))
    }

    /// The bytes of file `index` of the last [`Lab::phases_anatomical`], handed over once (the
    /// Lab keeps no copy afterwards).
    pub fn phases_anatomical_file(&mut self, index: usize) -> Result<Vec<u8>, JsValue> {
        self.phases_anatomical_file_with(index).ok_or_else(|| {
            errors::usage(
                "no_file",
                format!("{ANATOMICAL_STUDY}: no file {index} to hand over"),
            )
        })
    }

    /// Drops the batch in progress (cancel).
    pub fn stop_batch(&mut self) {
        self.batch = None;
    }

    /// xyz (mm) of the contours of the last leave-one-out (indexed by its ContourInfo pieces).
    pub fn batch_points(&self) -> Vec<f32> {
        self.batch_points.clone()
    }
}

impl Lab {
    /// [`Lab::start_phases`] with the views as slices (native, so tests reach it).
    pub fn start_phases_with(
        &mut self,
        session: &Session,
        phases_json: &str,
        params_json: &str,
        lids: &str,
        sequence: &[u8],
        views: &[(&str, &[u8])],
    ) -> heartmesh_core::error::Result<String> {
        self.batch_points.clear();
        // The layouts of a former study would be taken for this one's.
        self.finished_phases = None;
        self.anatomical_files.clear();
        let params = self.new_batch_params(params_json, lids, None)?;
        let requests = phase_requests(phases_json)?;
        // The frames are read one by one as the batch reaches them (`phases::Source::Frame`).
        let sequence = requests
            .iter()
            .find(|r| r.frame.is_some())
            .map(|r| phases::Sequence {
                file: r.file.clone(),
                bytes: sequence.to_vec(),
                views: views
                    .iter()
                    .map(|(n, b)| (n.to_string(), b.to_vec()))
                    .collect(),
                surfaces: session
                    .loaded(&r.file)
                    .map(ContourSet::surfaces)
                    .unwrap_or_default(),
            });
        let inputs = requests
            .into_iter()
            .map(|r| phases::PhaseInput {
                name: r.name,
                file: r.file.clone(),
                leave_out: r.leave_out,
                source: match r.frame {
                    Some(frame) => phases::Source::Frame(frame),
                    None => phases::Source::Read(
                        session
                            .loaded(&r.file)
                            .map(|set| Box::new(set.clone()))
                            .ok_or_else(|| format!("{} has not been loaded", r.file)),
                    ),
                },
            })
            .collect();
        let batch = Batch::phases(inputs, &params, sequence, batch_clock())?;
        let mut info = batch.layout().unwrap_or_else(|| json!({}));
        info["total"] = json!(batch.total());
        self.batch = Some(batch);
        Ok(info.to_string())
    }

    /// [`Lab::phases_anatomical_file`], natively (None: no such file, or handed over already).
    pub fn phases_anatomical_file_with(&mut self, index: usize) -> Option<Vec<u8>> {
        self.anatomical_files.get_mut(index).and_then(Option::take)
    }

    /// [`Lab::phases_anatomical`], natively: the JSON, or the error's JSON (`{code, message}`).
    pub fn phases_anatomical_with(
        &mut self,
        layout: &str,
        format: &str,
    ) -> Result<String, serde_json::Value> {
        self.anatomical_files.clear();
        let Some(phases) = self.finished_phases.as_ref() else {
            return Err(json!({
                "code": "no_phases",
                "message": format!(
                    "{ANATOMICAL_STUDY}: no finished phases batch: measure all phases first"
                ),
            }));
        };
        let refusal = |e: CoreError| errors::refusal_json(&e, ANATOMICAL_STUDY);
        let invalid = |name: &str, message: String| CoreError::ParamInvalid {
            name: name.into(),
            message,
        };
        let layout = Layout::parse(layout).map_err(|m| refusal(invalid("layout", m)))?;
        let format = wall::mesh_format(format).map_err(refusal)?;
        let made = phases.anatomical(layout, format).map_err(refusal)?;
        let mut out = made.report;
        out["files"] = json!(made
            .files
            .iter()
            .enumerate()
            .map(|(index, (name, _))| json!({ "name": name, "index": index }))
            .collect::<Vec<_>>());
        self.anatomical_files = made.files.into_iter().map(|(_, b)| Some(b)).collect();
        Ok(out.to_string())
    }

    /// The parameters of a new batch, the one in progress dropped first: a start that fails
    /// leaves no batch, never the previous one to go on stepping.
    fn new_batch_params(
        &mut self,
        params_json: &str,
        lids: &str,
        surface: Option<String>,
    ) -> heartmesh_core::error::Result<heartmesh_core::Params> {
        self.batch = None;
        convert::params_from_json(params_json, lids, surface)
    }

    /// [`Lab::make_parametric`], natively.
    pub fn make_parametric_with(&mut self, lv_json: &str) -> Result<String, LabError> {
        let lv = spec::parametric_lv(lv_json)?;
        let mesh = lv.mesh(LV_AROUND, LV_ALONG)?;
        self.truths
            .replace(Truth::new("parametric LV".into(), None, mesh))?;
        Ok(self.changed(0))
    }

    /// [`Lab::load_truth`], natively, with an optional label.
    pub fn load_truth_with(
        &mut self,
        file_name: &str,
        label: Option<String>,
        bytes: &[u8],
    ) -> Result<String, LabError> {
        self.truths
            .replace(dropped_truth(file_name, label, bytes)?)?;
        Ok(self.changed(0))
    }

    /// [`Lab::add_truth`], natively.
    pub fn add_truth_with(
        &mut self,
        file_name: &str,
        label: Option<String>,
        bytes: &[u8],
    ) -> Result<String, LabError> {
        let index = self.truths.add(dropped_truth(file_name, label, bytes)?)?;
        Ok(self.changed(index))
    }

    /// [`Lab::set_truth_label`], natively.
    pub fn set_truth_label_with(
        &mut self,
        index: usize,
        label: Option<String>,
    ) -> Result<String, LabError> {
        self.truths.relabel(index, label)?;
        self.forget_acquisition();
        Ok(self.truths.summary().to_string())
    }

    /// [`Lab::remove_truth`], natively.
    pub fn remove_truth_with(&mut self, index: usize) -> Result<String, LabError> {
        self.truths.remove(index)?;
        self.forget_acquisition();
        Ok(self.truths.summary().to_string())
    }

    /// [`Lab::simulate`], natively.
    pub fn simulate_with(&mut self, acquisition_json: &str) -> Result<String, LabError> {
        let spec = spec::acquisition(acquisition_json)?;
        let acq = if self.truths.len() == 1 {
            // One truth: the acquisition as it always was (no surface column), label or not.
            simulate(&self.truths.get(0)?.mesh, &spec)?
        } else {
            let surfaces = self.truths.labelled()?;
            if surfaces.is_empty() {
                return Err(usage(
                    "no_truth",
                    "no truth surface: make or load one first",
                ));
            }
            simulate_surfaces(&surfaces, &spec)?
        };
        let sax = acq.sax_planes.len();
        let info = json!({
            "sax": sax,
            // One truth: contours past the SAX ones, as always; several: the LAX images.
            "lax": if self.truths.len() == 1 {
                acq.contours.contours.len().saturating_sub(sax)
            } else {
                acq.lax_planes.len()
            },
            "points": acq.contours.point_count(),
            "surfaces": per_surface(&acq.contours, &self.truths.labels(), &acq.surface_clips),
            "clip": {
                "origin": [acq.clip.origin.x, acq.clip.origin.y, acq.clip.origin.z],
                "normal": [acq.clip.normal.x, acq.clip.normal.y, acq.clip.normal.z],
            },
        });
        self.clips = acq.surface_clips;
        self.simulated = Some(acq.contours);
        Ok(info.to_string())
    }

    /// [`Lab::simulated_csv`], natively.
    pub fn simulated_csv_with(&self) -> Result<Vec<u8>, LabError> {
        let set = self
            .simulated
            .as_ref()
            .ok_or_else(|| usage("no_acquisition", "no acquisition has been simulated"))?;
        Ok(io::csv::write_csv(set, None)?)
    }

    /// [`Lab::compare`], natively.
    pub fn compare_with(
        &mut self,
        surface: Option<&str>,
        positions: &[f32],
        indices: &[u32],
    ) -> Result<String, LabError> {
        let mesh = mesh_from_buffers(positions, indices)?;
        let index = self.truths.for_surface(surface)?;
        let truth = self.truths.get(index)?;
        let clip = self.clips.get(index);
        let report = compare(&truth.mesh, &mesh, clip)?;
        let mut distances = vertex_distances(&truth.mesh, &mesh);
        if let Some(clip) = clip {
            // Above the most basal SAX plane nothing was measured: NaN (drawn neutral).
            for (d, p) in distances.iter_mut().zip(&truth.mesh.positions) {
                if clip.signed_distance(p) > 0.0 {
                    *d = f64::NAN;
                }
            }
        }
        let mut out =
            serde_json::to_value(&report).map_err(|e| usage("internal", e.to_string()))?;
        out["truth_index"] = json!(index);
        out["truth_label"] = json!(truth.label);
        out["truth_name"] = json!(truth.name);
        self.last_distances = distances;
        Ok(out.to_string())
    }

    /// The truth a sweep of `surface` is measured against (none held: no truth to measure).
    fn sweep_truth(
        &self,
        surface: Option<&str>,
    ) -> Result<Option<(TriMesh, Option<ClipPlane>)>, JsValue> {
        if self.truths.len() == 0 {
            return Ok(None);
        }
        let index = self.truths.for_surface(surface).map_err(js)?;
        let truth = self.truths.get(index).map_err(js)?;
        Ok(Some((truth.mesh.clone(), self.clips.get(index).copied())))
    }

    /// Describes truth `index` after a change of the truths, forgetting the acquisition (it was
    /// of other truths).
    fn changed(&mut self, index: usize) -> String {
        self.forget_acquisition();
        match self.truths.get(index) {
            Ok(t) => json!({
                "name": t.name,
                "label": t.label,
                "index": index,
                "vertices": t.mesh.positions.len(),
                "triangles": t.mesh.triangles.len(),
                "volumeMl": t.mesh.volume_ml(),
                "closed": topology::validity(&t.mesh).is_closed_manifold(),
                "frame": t.frame.map(|f| f.name()),
                "convertedFrom": t.converted_from.map(|f| f.name()),
            })
            .to_string(),
            Err(_) => "{}".into(),
        }
    }

    fn forget_acquisition(&mut self) {
        self.clips.clear();
        self.simulated = None;
        self.last_distances.clear();
    }
}

/// The surface a batch's parameters select.
fn surface_of(params: &heartmesh_core::Params) -> Option<&str> {
    params.surface.as_deref()
}

/// A dropped mesh file as a truth named by the file: loading the only truth and adding one more
/// read a file alike.
fn dropped_truth(
    file_name: &str,
    label: Option<String>,
    bytes: &[u8],
) -> heartmesh_core::error::Result<Truth> {
    let (mesh, frame) = read_truth(file_name, bytes)?;
    Ok(Truth {
        frame,
        ..Truth::new(file_name.to_string(), label, mesh)
    })
}

/// A dropped mesh as a truth: welded and consistently oriented, outward; refuses what is no
/// usable surface. With the patient frame its file states, if any.
fn read_truth(
    file_name: &str,
    bytes: &[u8],
) -> heartmesh_core::error::Result<(TriMesh, Option<CoordinateSystem>)> {
    let data = io::read_mesh(file_name, bytes)?;
    let (welded, _) = weld(&data.mesh, WELD_MM);
    let (mut mesh, _) = orient_consistently(&welded);
    let area = mesh.area();
    if mesh.triangles.len() < 4 || !(area.is_finite() && area > 0.0) {
        return Err(CoreError::Degenerate(format!(
            "{file_name} is not a usable surface: {} triangles, area {area:.3} mm²",
            mesh.triangles.len()
        )));
    }
    if mesh.signed_volume() < 0.0 {
        // Inward-facing closed surfaces would measure negative volumes.
        mesh.flip_orientation();
    }
    Ok((mesh, data.coordinate_system))
}

/// SAX and LAX contours and points of each surface of an acquisition (the simulator's ids
/// start with `sax` or `lax`), in the truths' order (`labels`; a lone truth's contours have no
/// surface).
fn per_surface(
    set: &ContourSet,
    labels: &[Option<String>],
    clips: &[ClipPlane],
) -> serde_json::Value {
    let mut rows: Vec<(Option<String>, usize, usize, usize)> = if labels.len() > 1 {
        labels.iter().map(|l| (l.clone(), 0, 0, 0)).collect()
    } else {
        Vec::new()
    };
    for c in &set.contours {
        let k = match rows.iter().position(|r| r.0 == c.surface) {
            Some(k) => k,
            None => {
                rows.push((c.surface.clone(), 0, 0, 0));
                rows.len() - 1
            }
        };
        if c.id.starts_with("lax") {
            rows[k].2 += 1;
        } else {
            rows[k].1 += 1;
        }
        rows[k].3 += c.point_count();
    }
    serde_json::Value::Array(
        rows.into_iter()
            .enumerate()
            .map(|(k, (label, sax, lax, points))| {
                // The plane this surface's truth is clipped at (its own most basal slice).
                let clip = clips.get(k).map(|c| {
                    json!({
                        "origin": [c.origin.x, c.origin.y, c.origin.z],
                        "normal": [c.normal.x, c.normal.y, c.normal.z],
                    })
                });
                json!({ "label": label, "sax": sax, "lax": lax, "points": points, "clip": clip })
            })
            .collect(),
    )
}

/// A mesh from flat buffers, refusing what would mislead the measures (the core's checks, which
/// the `mesh_from_buffers` fuzz target covers).
fn mesh_from_buffers(positions: &[f32], indices: &[u32]) -> heartmesh_core::error::Result<TriMesh> {
    heartmesh_core::io::mesh_from_buffers(positions, indices)
}

/// The phases batch's cells are timed like a run: by `performance.now()` in the browser
/// (`Instant` traps there), natively by `Instant`.
fn batch_clock() -> Box<dyn heartmesh_core::clock::Clock> {
    #[cfg(target_arch = "wasm32")]
    {
        Box::new(crate::clock::PerformanceClock::new())
    }
    #[cfg(not(target_arch = "wasm32"))]
    {
        Box::new(heartmesh_core::clock::DefaultClock::default())
    }
}

/// One entry of [`Lab::start_phases`]'s list.
struct PhaseRequest {
    name: String,
    file: String,
    frame: Option<String>,
    leave_out: Vec<String>,
}

/// `[{name, file, frame?, leave_out?}]` of [`Lab::start_phases`]: `leave_out` lists the contours
/// the user left out of that phase (the Contours panel's lists of its file and frame).
fn phase_requests(text: &str) -> heartmesh_core::error::Result<Vec<PhaseRequest>> {
    let bad = |message: String| CoreError::ParamInvalid {
        name: "phases".into(),
        message,
    };
    let value: serde_json::Value =
        serde_json::from_str(text).map_err(|e| bad(format!("not JSON: {e}")))?;
    let list = value
        .as_array()
        .ok_or_else(|| bad("not a list of phases".into()))?;
    list.iter()
        .map(|p| {
            let text = |key: &str| p.get(key).and_then(serde_json::Value::as_str);
            match (text("name"), text("file")) {
                (Some(name), Some(file)) => Ok(PhaseRequest {
                    name: name.to_string(),
                    file: file.to_string(),
                    frame: text("frame").map(str::to_string),
                    leave_out: match p.get(crate::convert::LEAVE_OUT) {
                        None => Vec::new(),
                        Some(v) => heartmesh_core::io::session::contour_ids(v)?,
                    },
                }),
                _ => Err(bad(format!("{p} lacks a name or a file"))),
            }
        })
        .collect()
}

/// `{grid, with_truth}` of [`Lab::start_sweep`].
fn sweep_request(text: &str) -> heartmesh_core::error::Result<([Vec<f64>; 4], bool)> {
    let map = spec::object(text, "sweep")?;
    let grid = match map.get("grid") {
        Some(serde_json::Value::Object(g)) => sweep_grid(g)?,
        None => Default::default(),
        Some(_) => {
            return Err(CoreError::ParamInvalid {
                name: "grid".into(),
                message: "not an object of value lists".into(),
            })
        }
    };
    let with_truth = map
        .get("with_truth")
        .and_then(serde_json::Value::as_bool)
        .unwrap_or(false);
    Ok((grid, with_truth))
}

/// The sweep's value lists in `batch::SWEEP_NAMES` order.
fn sweep_grid(
    map: &serde_json::Map<String, serde_json::Value>,
) -> heartmesh_core::error::Result<[Vec<f64>; 4]> {
    if let Some(k) = map
        .keys()
        .find(|k| !batch::SWEEP_NAMES.contains(&k.as_str()))
    {
        return Err(CoreError::ParamInvalid {
            name: k.clone(),
            message: "not a swept parameter".into(),
        });
    }
    let mut out: [Vec<f64>; 4] = Default::default();
    for (slot, name) in out.iter_mut().zip(batch::SWEEP_NAMES) {
        if let Some(v) = map.get(name) {
            let list = v.as_array().ok_or_else(|| CoreError::ParamInvalid {
                name: name.into(),
                message: "not a list of numbers".into(),
            })?;
            for x in list {
                slot.push(x.as_f64().filter(|x| x.is_finite()).ok_or_else(|| {
                    CoreError::ParamInvalid {
                        name: name.into(),
                        message: format!("{x} is not a finite number"),
                    }
                })?);
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod multi_tests;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parametric_truth_simulate_compare() {
        let mut lab = Lab::new();
        let info: serde_json::Value =
            serde_json::from_str(&lab.make_parametric("{}").unwrap()).unwrap();
        assert_eq!(info["closed"], true);
        let sim: serde_json::Value =
            serde_json::from_str(&lab.simulate(r#"{"sax_count": 6, "lax_count": 2}"#).unwrap())
                .unwrap();
        assert_eq!(sim["sax"], 6);
        assert_eq!(sim["lax"], 2);
        assert!(!lab.simulated_csv().unwrap().is_empty());
        // The truth against itself: zero distance, equal clipped volumes.
        let t = lab.truths.get(0).unwrap().mesh.clone();
        let report: serde_json::Value = serde_json::from_str(
            &lab.compare(None, &t.positions_f32(), &t.indices_u32())
                .unwrap(),
        )
        .unwrap();
        assert!(report["hausdorff"].as_f64().unwrap() < 1e-4);
        assert_eq!(report["clipped"], true);
        let (vt, vm) = (
            report["volume_truth_ml"].as_f64().unwrap(),
            report["volume_mesh_ml"].as_f64().unwrap(),
        );
        assert!(vt > 10.0 && (vt - vm).abs() < 1e-3, "{vt} {vm}");
        // Distances per truth vertex; NaN exactly above the clip plane.
        let d = lab.truth_distances();
        assert_eq!(d.len(), t.positions.len());
        let above = t.positions.iter().filter(|p| p.z > 79.0).count();
        assert!(above > 0 && d.iter().filter(|x| x.is_nan()).count() >= above);
        assert!(d.iter().filter(|x| x.is_finite()).all(|x| *x < 1e-4));
    }

    use crate::test_data::data;

    fn patient1(phase: &str) -> Vec<u8> {
        std::fs::read(data(&format!(
            "contours/bivme-example-patient1/patient1-{phase}.csv"
        )))
        .unwrap()
    }

    /// Runs the batch to its end: the items and the final summary.
    fn drain(lab: &mut Lab) -> (Vec<serde_json::Value>, serde_json::Value) {
        let mut items = Vec::new();
        for _ in 0..1_000_000 {
            let p: serde_json::Value = serde_json::from_str(&lab.batch_step().unwrap()).unwrap();
            if let Some(item) = p.get("item") {
                items.push(item.clone());
            }
            if p["done"] == true {
                return (items, p["summary"].clone());
            }
        }
        panic!("the batch does not finish");
    }

    /// The same volume to the last bit: the items come back through `serde_json::from_str`, which
    /// (with the workspace's `float_roundtrip` feature) reads back the very double the core wrote.
    /// A mesh that differed would differ far more: a 250-step run amplifies any change.
    fn assert_same_ml(got: f64, want: f64, item: &serde_json::Value) {
        assert_eq!(got.to_bits(), want.to_bits(), "{got} vs {want}: {item}");
    }

    /// The volume of `surface` reconstructed directly by the core, as `heartmesh volumes` does.
    fn direct_volume(set: &ContourSet, surface: &str) -> f64 {
        let params = heartmesh_core::Params {
            surface: Some(surface.to_string()),
            ..heartmesh_core::Params::default()
        };
        let mut rec = heartmesh_core::pipeline::Reconstruction::new(set, params).unwrap();
        rec.run().unwrap();
        assert!(topology::validity(rec.mesh()).is_closed_manifold());
        rec.mesh().volume_ml()
    }

    /// A phase's `leave_out` reaches its cells only: ED's LV_ENDO is the run without the contour
    /// (the Contours panel's run on screen), ED's other surfaces and every ES cell as before; an id
    /// the phase's file lacks fails that phase's cells, the others measured.
    #[test]
    fn phases_batch_leaves_out_each_phases_contours() {
        let (ed, es) = (patient1("ED"), patient1("ES"));
        let mut session = Session::new();
        session.load("patient1-ED.csv", &ed, None).unwrap();
        session.load("patient1-ES.csv", &es, None).unwrap();
        let mut lab = Lab::new();
        let lax = "s07_LAX_LV_ENDOCARDIAL";
        let phases = format!(
            r#"[{{"name": "ED", "file": "patient1-ED.csv", "leave_out": ["{lax}"]}},
                {{"name": "ES", "file": "patient1-ES.csv"}}]"#
        );
        lab.start_phases_with(&session, &phases, "{}", "auto", &[], &[])
            .unwrap();
        let (items, _) = drain(&mut lab);
        let volume = |i: usize| items[i]["volume_ml"].as_f64().unwrap();
        let surfaces = ["RV_ENDO", "RV_EPI", "LV_EPI", "LV_ENDO"];
        let set = |b: &[u8]| heartmesh_core::io::read_contours("p.csv", b).unwrap();
        let (ed_set, es_set) = (set(&ed), set(&es));
        let mut rec = heartmesh_core::pipeline::Reconstruction::new(
            &ed_set,
            heartmesh_core::Params {
                surface: Some("LV_ENDO".into()),
                leave_out: vec![lax.into()],
                ..heartmesh_core::Params::default()
            },
        )
        .unwrap();
        rec.run().unwrap();
        assert_same_ml(volume(3), rec.mesh().volume_ml(), &items[3]);
        assert!((volume(3) - direct_volume(&ed_set, "LV_ENDO")).abs() > 1.0);
        for i in [0, 1, 2] {
            assert_same_ml(volume(i), direct_volume(&ed_set, surfaces[i]), &items[i]);
        }
        assert_same_ml(volume(7), direct_volume(&es_set, "LV_ENDO"), &items[7]);
        let bad = r#"[{"name": "ED", "file": "patient1-ED.csv", "leave_out": ["nope"]},
                      {"name": "ES", "file": "patient1-ES.csv"}]"#;
        lab.start_phases_with(&session, bad, "{}", "auto", &[], &[])
            .unwrap();
        let (items, _) = drain(&mut lab);
        assert!(items[..4].iter().all(|it| it["error"]
            .as_str()
            .is_some_and(|e| e.contains("no contour \"nope\""))));
        assert!(items[4..].iter().all(|it| it["volume_ml"].is_number()));
        let e = lab
            .start_phases_with(
                &session,
                r#"[{"name": "a", "file": "patient1-ED.csv", "leave_out": "x"}, {"name": "b", "file": "patient1-ES.csv"}]"#,
                "{}",
                "auto",
                &[],
                &[],
            )
            .unwrap_err();
        assert!(e.to_string().contains("leave_out"), "{e}");
    }

    /// Patient 1's ED and ES files: every surface of both phases, each volume the core's own, the
    /// summary ED/ES by volume; the same phases as the frames of one file holding both give the
    /// same volumes, read without touching the session's file; a phase that cannot be read is
    /// failed cells, the others measured.
    #[test]
    fn phases_batch_measures_every_surface_of_every_phase() {
        let (ed, es) = (patient1("ED"), patient1("ES"));
        let mut session = Session::new();
        session.load("patient1-ED.csv", &ed, None).unwrap();
        session.load("patient1-ES.csv", &es, None).unwrap();
        let mut lab = Lab::new();
        let phases = r#"[{"name": "patient1-ED", "file": "patient1-ED.csv"},
                         {"name": "patient1-ES", "file": "patient1-ES.csv"}]"#;
        let info: serde_json::Value = serde_json::from_str(
            &lab.start_phases_with(&session, phases, "{}", "auto", &[], &[])
                .unwrap(),
        )
        .unwrap();
        // In the files' order, as the CLI's table.
        let surfaces = ["RV_ENDO", "RV_EPI", "LV_EPI", "LV_ENDO"];
        assert_eq!(info["surfaces"], json!(surfaces), "{info}");
        assert_eq!(info["phases"], json!(["patient1-ED", "patient1-ES"]));
        assert_eq!(info["total"], 8);
        let (items, summary) = drain(&mut lab);
        assert_eq!(items.len(), 8);
        let mut volumes = Vec::new();
        for (i, it) in items.iter().enumerate() {
            let (bytes, phase) = if i < 4 { (&ed, "ED") } else { (&es, "ES") };
            let set = heartmesh_core::io::read_contours("p.csv", bytes).unwrap();
            let want = direct_volume(&set, surfaces[i % 4]);
            let got = it["volume_ml"].as_f64().unwrap();
            println!("{phase} {}: {got:.3} ml", surfaces[i % 4]);
            assert_same_ml(got, want, it);
            assert_eq!(it["surface"], surfaces[i % 4]);
            assert_eq!(it["watertight"], true);
            assert!(it["missing"].is_null() && it["error"].is_null(), "{it}");
            let mean = it["contour_to_mesh_mean"].as_f64().unwrap();
            assert!(mean > 0.0 && mean < 2.0, "{it}");
            volumes.push(got);
        }
        let lv = &summary["ventricles"][1];
        assert_eq!(lv["surface"], "LV_ENDO");
        assert_eq!(
            (lv["ed_phase"].as_str(), lv["es_phase"].as_str()),
            (Some("patient1-ED"), Some("patient1-ES"))
        );
        let ef = 100.0 * (volumes[3] - volumes[7]) / volumes[3];
        assert!((lv["ef_percent"].as_f64().unwrap() - ef).abs() < 1e-12);
        // The CLI's figures for these files (README: 62.1 %, 134.0 g at ED).
        assert!((ef - 62.1).abs() < 0.05, "{ef}");
        let mass = &summary["lv_mass"];
        let ed_g = mass["ed_g"].as_f64().unwrap();
        assert!((ed_g - 1.05 * (volumes[2] - volumes[3])).abs() < 1e-9);
        assert!((ed_g - 134.0).abs() < 0.05, "{ed_g}");

        // One file holding both phases (a `phase` column), its frames read from the bytes given,
        // plus a phase whose frame the file lacks.
        let mut cine = String::from("contour,x,y,z,surface,phase\n");
        for (bytes, phase) in [(&ed, "ED"), (&es, "ES")] {
            let text = String::from_utf8_lossy(bytes).to_string();
            for line in text
                .lines()
                .skip(1)
                .filter(|l| !l.is_empty() && !l.starts_with('#'))
            {
                cine.push_str(&format!("{line},{phase}\n"));
            }
        }
        session.load("cine.csv", cine.as_bytes(), None).unwrap();
        let frames = r#"[{"name": "ED", "file": "cine.csv", "frame": "ED"},
                         {"name": "ES", "file": "cine.csv", "frame": "es"},
                         {"name": "XX", "file": "cine.csv", "frame": "XX"},
                         {"name": "gone", "file": "gone.csv"}]"#;
        lab.start_phases_with(&session, frames, "{}", "auto", cine.as_bytes(), &[])
            .unwrap();
        let (items, summary) = drain(&mut lab);
        assert_eq!(items.len(), 16);
        for (i, it) in items[..8].iter().enumerate() {
            assert_eq!(it["volume_ml"].as_f64(), Some(volumes[i]), "{it}");
        }
        for it in &items[8..] {
            assert_eq!(it["missing"], "failed", "{it}");
            assert!(it["volume_ml"].is_null());
        }
        let xx = items[8]["error"].as_str().unwrap();
        assert!(xx.contains("XX"), "{xx}");
        assert!(items[12]["error"]
            .as_str()
            .unwrap()
            .contains("gone.csv has not been loaded"));
        assert_eq!(summary["ventricles"][0]["ed_phase"], "ED");
        assert_eq!(summary["ventricles"][0]["es_phase"], "ES");
        // The session's file is as it was loaded: frame ED, each contour's first.
        let first = heartmesh_core::io::read_contours("cine.csv", cine.as_bytes()).unwrap();
        assert_eq!(session.loaded("cine.csv"), Some(&first));

        // Fewer than two phases, or a list that is no list: refused before any work.
        let one = r#"[{"name": "ED", "file": "patient1-ED.csv"}]"#;
        assert!(lab
            .start_phases_with(&session, one, "{}", "auto", &[], &[])
            .is_err());
        assert!(lab
            .start_phases_with(&session, "{}", "{}", "auto", &[], &[])
            .is_err());
        assert!(lab
            .start_phases_with(&session, r#"[{"name": 1}, {}]"#, "{}", "auto", &[], &[])
            .is_err());
    }

    /// A legacy VTK file's POINTS (xyz).
    fn vtk_points(bytes: &[u8]) -> Vec<f64> {
        let text = String::from_utf8_lossy(bytes);
        let mut lines = text.lines().skip_while(|l| !l.starts_with("POINTS "));
        let n: usize = lines
            .next()
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|v| v.parse().ok())
            .unwrap();
        let mut out = Vec::with_capacity(3 * n);
        for line in lines {
            if out.len() >= 3 * n {
                break;
            }
            out.extend(line.split_whitespace().map(|v| v.parse::<f64>().unwrap()));
        }
        assert_eq!(out.len(), 3 * n);
        out
    }

    /// After a finished phases batch of patient 1's ED and ES files, the study's anatomical
    /// layouts are the core's for the same runs (`anatomical_study::of_study` on the core's own
    /// reconstructions, each with its `basal_plane`, the LV's end-diastole preferred, as `heartmesh
    /// volumes --anatomical-meshes` does): four layouts (LV_EPI and LV_ENDO of both phases), the
    /// ED LV_ENDO file's vertices and every displacement mean to 1e-9, the ES layouts' septum
    /// turns numbers; each file handed over once.
    #[test]
    fn phases_anatomical_are_the_cores_study_layouts() {
        use heartmesh_core::io::MeshFormat;
        use heartmesh_core::metrics::anatomical_study::{of_study, PhaseSurface};
        use heartmesh_core::metrics::compare::basal_plane;
        let (ed, es) = (patient1("ED"), patient1("ES"));
        let mut session = Session::new();
        session.load("patient1-ED.csv", &ed, None).unwrap();
        session.load("patient1-ES.csv", &es, None).unwrap();
        let mut lab = Lab::new();
        // Nothing measured yet: refused, saying why.
        let e = lab.phases_anatomical_with("24x48", "vtk").unwrap_err();
        assert_eq!(e["code"], "no_phases");
        assert!(e["message"]
            .as_str()
            .unwrap()
            .starts_with("the anatomical meshes: no finished phases batch"));
        let phases = r#"[{"name": "patient1-ED", "file": "patient1-ED.csv"},
                         {"name": "patient1-ES", "file": "patient1-ES.csv"}]"#;
        lab.start_phases_with(&session, phases, "{}", "auto", &[], &[])
            .unwrap();
        drain(&mut lab);
        let out: serde_json::Value =
            serde_json::from_str(&lab.phases_anatomical_with("24x48", "vtk").unwrap()).unwrap();

        // The core's study of the same runs.
        let sets: Vec<ContourSet> = [&ed, &es]
            .iter()
            .map(|b| heartmesh_core::io::read_contours("p.csv", b).unwrap())
            .collect();
        let names = ["patient1-ED", "patient1-ES"];
        let surfaces = ["LV_EPI", "LV_ENDO"];
        let mut runs = Vec::new();
        for set in &sets {
            for s in surfaces {
                let params = heartmesh_core::Params {
                    surface: Some(s.to_string()),
                    ..heartmesh_core::Params::default()
                };
                let mut rec = heartmesh_core::pipeline::Reconstruction::new(set, params).unwrap();
                rec.run().unwrap();
                runs.push((rec.mesh().clone(), basal_plane(&rec).unwrap()));
            }
        }
        let items: Vec<PhaseSurface> = runs
            .iter()
            .enumerate()
            .map(|(i, (mesh, base))| PhaseSurface {
                phase: names[i / 2],
                surface: surfaces[i % 2],
                set: &sets[i / 2],
                mesh: Some((mesh, base)),
            })
            .collect();
        let layout = Layout::parse("24x48").unwrap();
        let study = of_study(&items, Some("patient1-ED"), layout).unwrap();
        assert_eq!(study.septum.phase, "patient1-ED");

        assert_eq!(out["format"], "vtk");
        assert_eq!(out["layout"], json!({"rings": 24, "points": 48}));
        assert_eq!(out["septum"]["phase"], "patient1-ED");
        assert_eq!(out["septum"]["surface"], "LV_ENDO");
        assert_eq!(out["septum"]["source"], json!(study.septum.source));
        assert_eq!(out["displacement_from_phase"], "patient1-ED");
        let layouts = out["layouts"].as_array().unwrap();
        assert_eq!(layouts.len(), 4, "{out}");
        let files = out["files"].as_array().unwrap();
        assert_eq!(files.len(), 4);
        for (i, (entry, core)) in layouts.iter().zip(&study.layouts).enumerate() {
            assert_eq!(entry["phase"], json!(core.phase));
            assert_eq!(entry["surface"], json!(core.surface));
            let name = format!("{}-{}.vtk", core.phase, core.surface);
            assert_eq!(entry["file"], json!(name));
            assert_eq!(files[i], json!({"name": name, "index": i}));
            assert_eq!(entry["summary"]["vertices"], 1154);
            let (mean, max) = core.displacement_stats().unwrap();
            let got = entry["displacement_mean_mm"].as_f64().unwrap();
            println!(
                "{} {}: displacement mean {got:.4} mm, max {:.4} mm, septum turn {}",
                core.phase, core.surface, entry["displacement_max_mm"], entry["septum_turn_deg"]
            );
            assert!((got - mean).abs() <= 1e-9, "{got} vs {mean}");
            assert!((entry["displacement_max_mm"].as_f64().unwrap() - max).abs() <= 1e-9);
            if core.phase == "patient1-ED" {
                assert_eq!(got, 0.0);
            } else {
                // The LV contracts: millimetres of motion, and the septum its own file gives
                // within a few degrees of ED's.
                assert!(got > 1.0 && got < 15.0, "{got}");
                let turn = entry["septum_turn_deg"].as_f64().unwrap();
                assert!(turn.is_finite() && (0.0..10.0).contains(&turn), "{turn}");
            }
        }
        // The ED LV_ENDO file: the core's vertices (1e-9) and the core's very bytes.
        let k = study
            .layouts
            .iter()
            .position(|l| l.phase == "patient1-ED" && l.surface == "LV_ENDO")
            .unwrap();
        let bytes = lab.phases_anatomical_file_with(k).unwrap();
        let want = study.layouts[k]
            .file(&study, MeshFormat::Vtk, "patient1-ED.csv")
            .unwrap()
            .unwrap();
        let (mine, theirs) = (vtk_points(&bytes), vtk_points(&want));
        assert_eq!(mine.len(), 3 * 1154);
        let built = study.layouts[k].built.as_ref().unwrap();
        for (i, p) in built.mesh.positions.iter().enumerate() {
            for (c, v) in [p.x, p.y, p.z].into_iter().enumerate() {
                assert!((mine[3 * i + c] - v).abs() <= 1e-9 * v.abs().max(1.0));
            }
        }
        assert_eq!(mine, theirs);
        assert_eq!(bytes, want);
        let text = String::from_utf8_lossy(&bytes);
        assert!(text.contains("displacement_mm"), "no point data");
        // Handed over once; an index past the files is an error too.
        assert!(lab.phases_anatomical_file_with(k).is_none());
        assert!(lab.phases_anatomical_file_with(4).is_none());
        // A layout out of range or an unknown format: the core's reason.
        let e = lab.phases_anatomical_with("1x48", "vtk").unwrap_err();
        let m = e["message"].as_str().unwrap();
        assert!(
            m.starts_with("the anatomical meshes: ") && m.contains("2-200 rings"),
            "{m}"
        );
        let e = lab.phases_anatomical_with("24x48", "gif").unwrap_err();
        assert!(
            e["message"].as_str().unwrap().contains("no mesh format"),
            "{e}"
        );
        // Another format, the same layouts.
        let ply: serde_json::Value =
            serde_json::from_str(&lab.phases_anatomical_with("12x24", "ply").unwrap()).unwrap();
        assert_eq!(ply["files"][0]["name"], "patient1-ED-LV_EPI.ply");
        assert_eq!(ply["layouts"][0]["summary"]["vertices"], 12 * 24 + 2);
        assert!(!lab.phases_anatomical_file_with(3).unwrap().is_empty());
        // A new phases batch drops the finished one.
        lab.start_phases_with(&session, phases, "{}", "auto", &[], &[])
            .unwrap();
        assert_eq!(
            lab.phases_anatomical_with("24x48", "vtk").unwrap_err()["code"],
            "no_phases"
        );
    }

    /// Two phases of a file without RV contours or landmarks (the SurFCo example, twice): no
    /// layouts, and the reason names the septum; the Lab goes on.
    #[test]
    fn phases_anatomical_refuses_a_study_without_a_septum() {
        let bytes = std::fs::read(data("contours/surfco-example.csv")).unwrap();
        let mut session = Session::new();
        session.load("a.csv", &bytes, None).unwrap();
        session.load("b.csv", &bytes, None).unwrap();
        let mut lab = Lab::new();
        let phases = r#"[{"name": "a", "file": "a.csv"}, {"name": "b", "file": "b.csv"}]"#;
        lab.start_phases_with(&session, phases, "{}", "auto", &[], &[])
            .unwrap();
        drain(&mut lab);
        let e = lab.phases_anatomical_with("24x48", "vtk").unwrap_err();
        assert_eq!(e["code"], "degenerate");
        let m = e["message"].as_str().unwrap();
        assert_eq!(
            m,
            "the anatomical meshes: every layout starts at the septum, and no phase's file has \
             RV_INSERT landmarks or RV contours to place it by"
        );
        assert!(lab.phases_anatomical_file_with(0).is_none());
        // Only RV surfaces measured: refused for the surfaces.
        let rv_only = heartmesh_core::io::read_contours("p.csv", &patient1("ED")).unwrap();
        let mut csv_rv = heartmesh_core::ContourSet {
            contours: rv_only
                .contours
                .iter()
                .filter(|c| c.surface.as_deref() == Some("RV_ENDO"))
                .cloned()
                .collect(),
            ..rv_only.clone()
        };
        csv_rv.landmarks.clear();
        let text = heartmesh_core::io::csv::write_csv(&csv_rv, None).unwrap();
        session.load("rv.csv", &text, None).unwrap();
        let rv = r#"[{"name": "a", "file": "rv.csv"}, {"name": "b", "file": "rv.csv"}]"#;
        lab.start_phases_with(&session, rv, r#"{"iterations": 20}"#, "auto", &[], &[])
            .unwrap();
        drain(&mut lab);
        let e = lab.phases_anatomical_with("24x48", "vtk").unwrap_err();
        let m = e["message"].as_str().unwrap();
        assert!(
            m.contains("LV's surfaces") && m.contains("none is among"),
            "{m}"
        );
    }

    #[test]
    fn bad_inputs_are_errors() {
        assert!(mesh_from_buffers(&[0.0; 9], &[0, 1, 3]).is_err());
        assert!(mesh_from_buffers(&[0.0; 8], &[0, 1, 2]).is_err());
        assert!(mesh_from_buffers(&[f32::NAN; 9], &[0, 1, 2]).is_err());
        assert!(sweep_request(r#"{"grid": {"beta": [1]}}"#).is_err());
        assert!(sweep_request(r#"{"grid": {"lambda": ["x"]}}"#).is_err());
        assert!(sweep_request(r#"{"grid": [1]}"#).is_err());
        let (g, with_truth) =
            sweep_request(r#"{"grid": {"lambda": [1, 10]}, "with_truth": true}"#).unwrap();
        assert_eq!(g[0], vec![1.0, 10.0]);
        assert!(g[1].is_empty() && with_truth);
    }
}
