//! The validation lab's binding (issue 5): a ground-truth surface (the parametric LV or a dropped
//! mesh), a simulated CMR acquisition of it, the comparison of a reconstruction with the truth
//! clipped at the most basal SAX plane, and stepped batches (leave-one-out, parameter sweep). It
//! follows the validation protocol of Villard, Grau & Zacur (J. Imaging 2018, section 3); every
//! algorithm is heartmesh-core's `sim` and `metrics` modules, this file only holds state between
//! calls and converts at the boundary (same rules as [`crate::Session`]).

mod batch;
mod spec;

use heartmesh_core::contours::ContourSet;
use heartmesh_core::error::CoreError;
use heartmesh_core::io;
use heartmesh_core::mesh::topology;
use heartmesh_core::metrics::compare::{compare, vertex_distances, ClipPlane};
use heartmesh_core::sim::repair::{orient_consistently, weld};
use heartmesh_core::sim::simulate;
use heartmesh_core::TriMesh;
use serde_json::json;
use wasm_bindgen::prelude::*;

use crate::{convert, errors, Session};
use batch::Batch;

/// Triangulation of the parametric LV: points per ring and rings from apex to base (~0.5 mm
/// edges near the apex, ~1.7 mm at the equator: finer than any reconstruction we compare).
const LV_AROUND: usize = 96;
const LV_ALONG: usize = 64;

/// Distance under which dropped-mesh vertices are merged (STL stores every triangle's corners).
const WELD_MM: f64 = 1e-6;

struct Truth {
    mesh: TriMesh,
}

/// The Lab's state: at most one truth, its last acquisition, and one batch.
#[wasm_bindgen]
pub struct Lab {
    truth: Option<Truth>,
    /// The most basal SAX plane of the last simulated acquisition of this truth.
    clip: Option<ClipPlane>,
    simulated: Option<ContourSet>,
    last_distances: Vec<f64>,
    batch: Option<Batch>,
    batch_points: Vec<f32>,
}

impl Default for Lab {
    fn default() -> Self {
        Self::new()
    }
}

#[wasm_bindgen]
impl Lab {
    #[wasm_bindgen(constructor)]
    pub fn new() -> Lab {
        Lab {
            truth: None,
            clip: None,
            simulated: None,
            last_distances: Vec::new(),
            batch: None,
            batch_points: Vec::new(),
        }
    }

    /// Makes the built-in parametric LV the truth (see `lab/spec.rs` for the JSON); returns the
    /// truth's description `{name, vertices, triangles, volumeMl, closed}`.
    pub fn make_parametric(&mut self, lv_json: &str) -> Result<String, JsValue> {
        let lv = spec::parametric_lv(lv_json).map_err(|e| errors::to_js(&e))?;
        let mesh = lv
            .mesh(LV_AROUND, LV_ALONG)
            .map_err(|e| errors::to_js(&e))?;
        Ok(self.set_truth("parametric LV".into(), mesh))
    }

    /// Reads a dropped mesh (OBJ, STL, PLY, VTK, VTP) as the truth: welded (STL stores corners per
    /// triangle) and consistently oriented (mixed orientations spoil volumes), as the CLI does.
    pub fn load_truth(&mut self, file_name: &str, bytes: &[u8]) -> Result<String, JsValue> {
        let data = io::read_mesh(file_name, bytes).map_err(|e| errors::to_js(&e))?;
        let (welded, _) = weld(&data.mesh, WELD_MM);
        let (mesh, _) = orient_consistently(&welded);
        let area = mesh.area();
        if mesh.triangles.len() < 4 || !(area.is_finite() && area > 0.0) {
            return Err(errors::to_js(&CoreError::Degenerate(format!(
                "{file_name} is not a usable surface: {} triangles, area {area:.3} mm²",
                mesh.triangles.len()
            ))));
        }
        let mut mesh = mesh;
        if mesh.signed_volume() < 0.0 {
            // Inward-facing closed surfaces would measure negative volumes.
            mesh.flip_orientation();
        }
        Ok(self.set_truth(file_name.to_string(), mesh))
    }

    /// Truth vertices, xyz, mm.
    pub fn truth_positions(&self) -> Result<Vec<f32>, JsValue> {
        Ok(self.truth()?.mesh.positions_f32())
    }

    /// Truth triangles, outward.
    pub fn truth_indices(&self) -> Result<Vec<u32>, JsValue> {
        Ok(self.truth()?.mesh.indices_u32())
    }

    /// Slices the truth like a CMR acquisition (see `lab/spec.rs` for the JSON); keeps the
    /// contours and the most basal SAX plane. Returns `{sax, lax, points, clip: {origin, normal}}`;
    /// the contours themselves come from [`Lab::simulated_csv`].
    pub fn simulate(&mut self, acquisition_json: &str) -> Result<String, JsValue> {
        let spec = spec::acquisition(acquisition_json).map_err(|e| errors::to_js(&e))?;
        let acq = simulate(&self.truth()?.mesh, &spec).map_err(|e| errors::to_js(&e))?;
        let sax = acq.sax_planes.len();
        let info = json!({
            "sax": sax,
            "lax": acq.contours.contours.len().saturating_sub(sax),
            "points": acq.contours.point_count(),
            "clip": {
                "origin": [acq.clip.origin.x, acq.clip.origin.y, acq.clip.origin.z],
                "normal": [acq.clip.normal.x, acq.clip.normal.y, acq.clip.normal.z],
            },
        });
        self.clip = Some(acq.clip);
        self.simulated = Some(acq.contours);
        Ok(info.to_string())
    }

    /// The last simulated contours as canonical CSV (loaded like any dropped contour file).
    pub fn simulated_csv(&self) -> Result<Vec<u8>, JsValue> {
        let set = self
            .simulated
            .as_ref()
            .ok_or_else(|| errors::usage("no_acquisition", "no acquisition has been simulated"))?;
        io::csv::write_csv(set, None).map_err(|e| errors::to_js(&e))
    }

    /// Compares a reconstruction (xyz mm, triangles) with the truth, both clipped at the most
    /// basal SAX plane of the last acquisition; returns the JSON of the core's `CompareReport`.
    /// Keeps the distance of every truth vertex to the mesh for [`Lab::truth_distances`].
    pub fn compare(&mut self, positions: &[f32], indices: &[u32]) -> Result<String, JsValue> {
        let mesh = mesh_from_buffers(positions, indices).map_err(|e| errors::to_js(&e))?;
        let truth = self.truth()?;
        let report =
            compare(&truth.mesh, &mesh, self.clip.as_ref()).map_err(|e| errors::to_js(&e))?;
        let mut distances = vertex_distances(&truth.mesh, &mesh);
        if let Some(clip) = &self.clip {
            // Above the most basal SAX plane nothing was measured: NaN (drawn neutral).
            for (d, p) in distances.iter_mut().zip(&truth.mesh.positions) {
                if clip.signed_distance(p) > 0.0 {
                    *d = f64::NAN;
                }
            }
        }
        self.last_distances = distances;
        serde_json::to_string(&report).map_err(|e| errors::usage("internal", e.to_string()))
    }

    /// Per truth vertex, distance (mm) to the mesh of the last [`Lab::compare`].
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
        self.batch = None;
        let params =
            convert::params_from_json(params_json, lids, surface).map_err(|e| errors::to_js(&e))?;
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
        self.batch = None;
        let params =
            convert::params_from_json(params_json, lids, surface).map_err(|e| errors::to_js(&e))?;
        let (grid, with_truth) = sweep_request(sweep_json).map_err(|e| errors::to_js(&e))?;
        let set = session.file(file_name)?;
        let truth = match (&self.truth, with_truth) {
            (Some(t), true) => Some((t.mesh.clone(), self.clip)),
            _ => None,
        };
        let batch = Batch::sweep(set, &params, &grid, truth).map_err(|e| errors::to_js(&e))?;
        let info = json!({ "total": batch.total() });
        self.batch = Some(batch);
        self.batch_points.clear();
        Ok(info.to_string())
    }

    /// Advances the batch by one pipeline step: `{completed, total, done, item?}`.
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
        if done {
            self.batch = None;
        }
        Ok(out.to_string())
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
    fn truth(&self) -> Result<&Truth, JsValue> {
        self.truth
            .as_ref()
            .ok_or_else(|| errors::usage("no_truth", "no truth surface: make or load one first"))
    }

    fn set_truth(&mut self, name: String, mesh: TriMesh) -> String {
        let info = json!({
            "name": name,
            "vertices": mesh.positions.len(),
            "triangles": mesh.triangles.len(),
            "volumeMl": mesh.volume_ml(),
            "closed": topology::validity(&mesh).is_closed_manifold(),
        });
        self.truth = Some(Truth { mesh });
        self.clip = None;
        self.simulated = None;
        self.last_distances.clear();
        info.to_string()
    }
}

/// A mesh from flat buffers, refusing what would mislead the measures (the core's checks, which
/// the `mesh_from_buffers` fuzz target covers).
fn mesh_from_buffers(positions: &[f32], indices: &[u32]) -> heartmesh_core::error::Result<TriMesh> {
    heartmesh_core::io::mesh_from_buffers(positions, indices)
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
        let t = lab.truth.as_ref().unwrap().mesh.clone();
        let report: serde_json::Value =
            serde_json::from_str(&lab.compare(&t.positions_f32(), &t.indices_u32()).unwrap())
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
