//! `reconstruct --anatomical-mesh FILE [--anatomical-layout 24x48]`: the finished LV surface
//! resampled onto the anatomical layout (core `metrics::anatomical`), the same vertices and
//! triangles for every heart, written beside the mesh, its figures in the report.
//!
//! What can be known before a run is checked before it (an RV surface, a file that does not say
//! where the septum is): a refusal after a minute's reconstruction would waste it. Under
//! `--surface all` the LV surfaces get their layouts and the others are named in a note.

use heartmesh_core::contours::CoordinateSystem;
use heartmesh_core::io::{self, MeshFormat, Regions};
use heartmesh_core::metrics::anatomical::{self, Anatomical, Layout, REGION_NAMES};
use heartmesh_core::metrics::compare::basal_plane;
use heartmesh_core::pipeline::Reconstruction;
use heartmesh_core::{ContourSet, CoreError};
use serde_json::{json, Value};

use crate::args::Parsed;
use crate::cmd_convert::file_name;
use crate::error::CliError;

/// The layout asked for: None without `--anatomical-mesh`; `--anatomical-layout` alone is a
/// usage error (it would silently do nothing).
pub fn layout_from(p: &Parsed) -> Result<Option<Layout>, CliError> {
    match (p.value("anatomical-mesh"), p.value("anatomical-layout")) {
        (None, None) => Ok(None),
        (None, Some(_)) => Err(CliError::usage(
            "--anatomical-layout sets the grid of --anatomical-mesh; add --anatomical-mesh FILE",
        )),
        (Some(path), layout) => {
            if MeshFormat::from_path(path).is_none() {
                return Err(CliError::usage(format!(
                    "--anatomical-mesh {path}: the extension must be .obj, .stl, .ply, .vtk or .vtp"
                )));
            }
            layout
                .map_or(Ok(Layout::DEFAULT), Layout::parse)
                .map(Some)
                .map_err(|e| CliError::usage(format!("--anatomical-layout: {e}")))
        }
    }
}

/// Before any run: the surfaces of `surfaces` (None: the file's only one) that can have a
/// layout; an error (status 2) when none can, naming why.
pub fn check(
    input: &str,
    set: &ContourSet,
    surfaces: &[Option<String>],
) -> Result<Vec<Option<String>>, CliError> {
    let mut why = None;
    let fit: Vec<Option<String>> = surfaces
        .iter()
        .filter(|s| match anatomical::refusal(set, s.as_deref()) {
            Some(w) => {
                why.get_or_insert(w);
                false
            }
            None => true,
        })
        .cloned()
        .collect();
    match (fit.is_empty(), why) {
        (true, Some(w)) => Err(CliError::input(
            input,
            CoreError::parse(0, format!("--anatomical-mesh: {w}")),
        )),
        _ => Ok(fit),
    }
}

/// The layout of a finished reconstruction of `surface`, or why there is none.
pub fn build(
    rec: &Reconstruction,
    set: &ContourSet,
    surface: Option<&str>,
    layout: Layout,
) -> Result<Anatomical, String> {
    let base = basal_plane(rec).map_err(|e| e.to_string())?;
    anatomical::of_file(set, surface, rec.mesh(), &base, layout)
}

/// The report's `anatomical_mesh` (the file and the layout's figures) or, when it could not be
/// built, null and `anatomical_mesh_note`.
pub fn add_to_report(rep: &mut Value, path: &str, built: &Result<Anatomical, String>) {
    let summary = built.as_ref().map(|x| json!(x.summary));
    crate::report::add_built(rep, "anatomical_mesh", path, summary);
}

/// The layout's file: regions `wall` and `base`, the layout spelled out in the header.
pub fn write(
    path: &str,
    a: &Anatomical,
    input: &str,
    surface: &str,
    system: Option<CoordinateSystem>,
) -> Result<(), CliError> {
    let format = MeshFormat::from_path(path)
        .ok_or_else(|| CliError::Failed(format!("{path}: unknown mesh extension")))?;
    let comment = io::tagged_comment(
        system,
        &anatomical::header_comment(&a.summary, surface, input),
    );
    let regions = Regions {
        array: "region",
        ids: &a.regions,
        names: &REGION_NAMES,
    };
    let bytes = io::write_mesh_with(&a.mesh, format, None, Some(&regions), &comment)
        .map_err(|e| CliError::Failed(format!("{path}: {e}")))?;
    crate::files::write(path, &bytes)
}

/// The stdout line after the mesh's: the layout's file and figures.
pub fn summary_line(path: &str, a: &Anatomical) -> String {
    let s = &a.summary;
    format!(
        "{}: anatomical layout {}x{}, {} vertices, {:.1} ml ({:.1} ml below the base on the \
         surface), {:.2} mm from the surface on average, {:.2} mm at most; septum from {}",
        file_name(path),
        s.rings,
        s.points,
        s.vertices,
        s.volume_ml,
        s.surface_volume_ml,
        s.to_surface_mean_mm,
        s.to_surface_max_mm,
        s.septum_from
    )
}

/// The one-line note for a surface of `--surface all` that gets no layout.
pub fn skipped_note(input: &str, surface: &str) -> String {
    format!("heartmesh: note: {input}: no anatomical layout for {surface} (the LV's surfaces only)")
}
