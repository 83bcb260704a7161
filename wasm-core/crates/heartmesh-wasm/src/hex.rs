//! The LV wall as hexahedra in the app: the command line's `myocardium --hex-mesh` (heartmesh-cli
//! `hex_out.rs`) made of the two finished meshes the app holds, for the LV wall row. Given the
//! same meshes, the same cells, arrays and summary as the command line's (an app header, when
//! given, follows the command line's comment). A bad call is an error thrown as JSON, never a
//! panic: the worker goes on.

use heartmesh_core::mesh::hex_wall;
use heartmesh_core::metrics::anatomical::{self, Layout};
use heartmesh_core::metrics::compare::common_basal_plane_of;
use heartmesh_core::{ContourSet, CoreError, Params};
use serde_json::json;
use wasm_bindgen::prelude::*;

use crate::wall::{append_lines, export_object, mesh_of, SurfaceMesh, WallExport};
use crate::{convert, errors, Session};

/// How the hexahedral mesh's failures begin in the app.
pub const WHAT: &str = "the hexahedral wall";

#[wasm_bindgen]
impl Session {
    /// The LV wall of a loaded file as layers of hexahedra (VTK unstructured grid), as
    /// `heartmesh myocardium --hex-mesh` builds it, from the finished meshes of its endocardium
    /// (`endo_surface`, e.g. "LV_ENDO") and epicardium (`epi_surface`), both run with
    /// `params_json` and `lids`: `rings` x `points` (2-200 x 8-720) per layout, `layers` (1-20)
    /// cells through the wall. `header`: lines the app adds after the command line's comment.
    /// Returns `{summary, bytes}`: the summary JSON (the report's `hex_mesh` without `file`:
    /// rings, points_per_ring, layers, points, hexahedra, wedges, volume_ml,
    /// layouts_volume_ml, min_scaled_jacobian, inverted_cells) and the `.vtk` file. Errors start
    /// "the hexahedral wall: " (a file that does not say where the septum is, bad values).
    #[allow(clippy::too_many_arguments)]
    #[wasm_bindgen(unchecked_return_type = "{ summary: string; bytes: Uint8Array }")]
    pub fn hex_wall(
        &self,
        file_name: &str,
        params_json: &str,
        lids: &str,
        endo_surface: &str,
        endo_positions: &[f64],
        endo_indices: &[u32],
        epi_surface: &str,
        epi_positions: &[f64],
        epi_indices: &[u32],
        rings: usize,
        points: usize,
        layers: usize,
        header: &str,
    ) -> Result<js_sys::Object, JsValue> {
        let set = self.file(file_name)?;
        let params =
            convert::params_from_json(params_json, lids, None).map_err(|e| errors::to_js(&e))?;
        let endo = SurfaceMesh::new(endo_surface, endo_positions, endo_indices);
        let epi = SurfaceMesh::new(epi_surface, epi_positions, epi_indices);
        let built = build(
            set, file_name, &params, endo, epi, rings, points, layers, header,
        )
        .map_err(|e| JsValue::from_str(&errors::refusal_json(&e, WHAT).to_string()))?;
        export_object(&built)
    }
}

/// The work of [`Session::hex_wall`] (native, so tests reach it).
#[allow(clippy::too_many_arguments)]
pub fn build(
    set: &ContourSet,
    file_name: &str,
    params: &Params,
    endo: SurfaceMesh,
    epi: SurfaceMesh,
    rings: usize,
    points: usize,
    layers: usize,
    header: &str,
) -> heartmesh_core::error::Result<WallExport> {
    let layout = Layout::new(rings, points).map_err(|message| CoreError::ParamInvalid {
        name: "layout".into(),
        message,
    })?;
    if !heartmesh_core::metrics::septum::said(set) {
        return Err(CoreError::Degenerate(
            "its cells are laid out from the septum: the file has no RV_INSERT landmarks and no \
             RV contours"
                .into(),
        ));
    }
    let (endo_mesh, epi_mesh) = (mesh_of(endo)?, mesh_of(epi)?);
    let base = common_basal_plane_of(set, params, endo.name, epi.name)?;
    let orientation =
        anatomical::orientation_of(set, &endo_mesh, &base).map_err(CoreError::Degenerate)?;
    let (inner, outer) =
        anatomical::build_pair(&endo_mesh, &epi_mesh, &base, &orientation, layout)?;
    // The LV wall row's solid keeps its wall 1 mm thick (the command line's default
    // --min-thickness); its cells do the same.
    let hex = hex_wall::build_with_helix(
        &inner,
        &outer,
        layout,
        &base,
        layers,
        hex_wall::DEFAULT_HELIX_DEG,
        Some(crate::wall::DEFAULT_MIN_THICKNESS_MM),
    )?;
    let mut comment = hex_wall::comment(&hex, file_name, endo.name, epi.name);
    append_lines(&mut comment, header);
    Ok(WallExport {
        summary: json!(hex.summary),
        bytes: hex.to_vtk(&heartmesh_core::io::tagged_comment(
            set.coordinate_system,
            &comment,
        )),
    })
}
