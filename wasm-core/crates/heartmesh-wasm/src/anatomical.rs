//! The anatomical layout in the app: the command line's `reconstruct --anatomical-mesh`
//! (heartmesh-cli `anatomical_out.rs`) made of a finished LV mesh the app holds, for the Export
//! panel. Given the same mesh, the same vertices, summary and file as the command line's (an app
//! header, when given, follows the command line's comment). Everything is checked before the core
//! sees it, so a bad call is an error thrown as JSON, never a panic: the worker goes on.

use heartmesh_core::io::{tagged_comment, write_mesh_with, Regions};
use heartmesh_core::metrics::anatomical::{self, Layout, REGION_NAMES};
use heartmesh_core::metrics::compare::clip_plane_from_contours;
use heartmesh_core::{ContourSet, CoreError, Params};
use serde_json::json;
use wasm_bindgen::prelude::*;

use crate::wall::{append_lines, export_object, mesh_format, mesh_of, SurfaceMesh, WallExport};
use crate::{convert, errors, Session};

/// How the layout's failures begin in the app.
pub const WHAT: &str = "the anatomical mesh";

#[wasm_bindgen]
impl Session {
    /// The anatomical layout of a finished LV surface (`surface`, e.g. "LV_ENDO", its mesh as
    /// `positions` and `indices`) of a loaded file run with `params_json` and `lids` (as
    /// [`Session::start`] takes them): `rings` rings of `points` vertices (2-200, 8-720), vertex
    /// 0 the apex, each ring from the septum, last the base lid's centre. `format` is a mesh
    /// extension; `header`: lines the app adds after the command line's comment. Returns
    /// `{summary, bytes}`: the summary JSON (the command line report's `anatomical_mesh`: rings,
    /// points, vertices, septum_from, septum/anterior/axis directions, apex, length_mm,
    /// volume_ml, surface_volume_ml, to_surface_mean_mm, to_surface_max_mm) and the file. A
    /// surface or file that can have none (an RV surface, no RV landmarks or contours) is an
    /// error whose message says why, starting "the anatomical mesh: ".
    #[allow(clippy::too_many_arguments)]
    #[wasm_bindgen(unchecked_return_type = "{ summary: string; bytes: Uint8Array }")]
    pub fn anatomical_mesh(
        &self,
        file_name: &str,
        params_json: &str,
        lids: &str,
        surface: &str,
        positions: &[f64],
        indices: &[u32],
        rings: usize,
        points: usize,
        format: &str,
        header: &str,
    ) -> Result<js_sys::Object, JsValue> {
        let set = self.file(file_name)?;
        let params = convert::params_from_json(params_json, lids, Some(surface.to_string()))
            .map_err(|e| errors::to_js(&e))?;
        let mesh = SurfaceMesh::new(surface, positions, indices);
        let built = build(set, file_name, &params, mesh, rings, points, format, header)
            .map_err(|e| JsValue::from_str(&errors::refusal_json(&e, WHAT).to_string()))?;
        export_object(&built)
    }
}

/// The work of [`Session::anatomical_mesh`] (native, so tests reach it).
#[allow(clippy::too_many_arguments)]
pub fn build(
    set: &ContourSet,
    file_name: &str,
    params: &Params,
    surface: SurfaceMesh,
    rings: usize,
    points: usize,
    format: &str,
    header: &str,
) -> heartmesh_core::error::Result<WallExport> {
    let invalid = |name: &str, message: String| CoreError::ParamInvalid {
        name: name.into(),
        message,
    };
    let layout = Layout::new(rings, points).map_err(|m| invalid("layout", m))?;
    let format = mesh_format(format)?;
    if let Some(why) = anatomical::refusal(set, Some(surface.name)) {
        return Err(CoreError::Degenerate(why));
    }
    let mesh = mesh_of(surface)?;
    let base = clip_plane_from_contours(set, params.clone())?;
    let built = anatomical::of_file(set, Some(surface.name), &mesh, &base, layout)
        .map_err(CoreError::Degenerate)?;
    let mut comment = anatomical::header_comment(&built.summary, surface.name, file_name);
    append_lines(&mut comment, header);
    let regions = Regions {
        array: "region",
        ids: &built.regions,
        names: &REGION_NAMES,
    };
    let comment = tagged_comment(set.coordinate_system, &comment);
    let bytes = write_mesh_with(&built.mesh, format, None, Some(&regions), &comment)?;
    Ok(WallExport {
        summary: json!(built.summary),
        bytes,
    })
}
