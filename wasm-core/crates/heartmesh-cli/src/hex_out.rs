//! `myocardium --hex-mesh HEX.vtk [--hex-layout 24x48] [--layers 3] [--helix-angles 60,-60]`:
//! the LV wall as layers of
//! hexahedra between the anatomical layouts of its two surfaces (core `mesh::hex_wall`), written
//! beside the wall solid, its figures in the report.
//!
//! Checked before any run: the option's values, that the wall is the LV's (a biventricular wall
//! has no single layout), and that the file says where the septum is.

use heartmesh_core::mesh::hex_wall::{self, HexWall, DEFAULT_HELIX_DEG, DEFAULT_LAYERS, LAYERS};
use heartmesh_core::metrics::anatomical::{self, Layout};
use heartmesh_core::metrics::segments::Orientation;
use heartmesh_core::metrics::septum;
use heartmesh_core::pipeline::Reconstruction;
use heartmesh_core::sim::slice::Plane;
use heartmesh_core::TriMesh;
use heartmesh_core::{ContourSet, CoreError};
use serde_json::{json, Value};

use crate::args::Parsed;
use crate::cmd_convert::file_name;
use crate::error::CliError;

/// What `--hex-mesh` asked for.
pub struct Request {
    pub path: String,
    pub shape: Shape,
}

/// The cells asked for: the layout of each surface, the cells through the wall, the fibres.
#[derive(Debug, Clone, Copy)]
pub struct Shape {
    pub layout: Layout,
    pub layers: usize,
    /// The fibres' helix angles, endocardium and epicardium (degrees).
    pub helix: (f64, f64),
}

impl Shape {
    /// `--hex-layout`, `--layers` and `--helix-angles` (their defaults where absent).
    pub fn from(p: &Parsed) -> Result<Shape, CliError> {
        let layout = p
            .value("hex-layout")
            .map_or(Ok(Layout::DEFAULT), Layout::parse)
            .map_err(|e| CliError::usage(format!("--hex-layout: {e}")))?;
        let layers = match p.value("layers") {
            None => DEFAULT_LAYERS,
            Some(v) => v
                .parse::<usize>()
                .ok()
                .filter(|n| (LAYERS.0..=LAYERS.1).contains(n))
                .ok_or_else(|| {
                    CliError::usage(format!(
                        "--layers {v}: give {}-{} cells through the wall",
                        LAYERS.0, LAYERS.1
                    ))
                })?,
        };
        let helix = match p.value("helix-angles") {
            None => DEFAULT_HELIX_DEG,
            Some(v) => helix_angles(v).ok_or_else(|| {
                CliError::usage(format!(
                    "--helix-angles {v}: give ENDO,EPI in degrees, each from -90 to 90 (e.g. \
                     60,-60)"
                ))
            })?,
        };
        Ok(Shape {
            layout,
            layers,
            helix,
        })
    }

    /// Whether any of the shape's options was given (alone they would do nothing).
    pub fn asked(p: &Parsed) -> bool {
        ["hex-layout", "layers", "helix-angles"]
            .iter()
            .any(|o| p.value(o).is_some())
    }
}

/// The request, or None without `--hex-mesh`; `--hex-layout` or `--layers` alone are usage
/// errors (they would silently do nothing).
pub fn request_from(p: &Parsed, biventricular: bool) -> Result<Option<Request>, CliError> {
    let Some(path) = p.value("hex-mesh") else {
        if Shape::asked(p) {
            return Err(CliError::usage(
                "--hex-layout, --layers and --helix-angles shape the cells of --hex-mesh; add \
                 --hex-mesh FILE.vtk",
            ));
        }
        return Ok(None);
    };
    if biventricular {
        return Err(CliError::usage(
            "--hex-mesh lays out the LV wall's cells; leave out --biventricular",
        ));
    }
    if !path.to_ascii_lowercase().ends_with(".vtk") {
        return Err(CliError::usage(format!(
            "--hex-mesh {path}: the hexahedral mesh is written as a VTK unstructured grid (.vtk)"
        )));
    }
    Ok(Some(Request {
        path: path.to_string(),
        shape: Shape::from(p)?,
    }))
}

/// `ENDO,EPI` degrees, each within +-90.
fn helix_angles(text: &str) -> Option<(f64, f64)> {
    let (a, b) = text.split_once(',')?;
    let angle = |s: &str| {
        s.trim()
            .parse::<f64>()
            .ok()
            .filter(|d| d.is_finite() && d.abs() <= 90.0)
    };
    Some((angle(a)?, angle(b)?))
}

/// Before any run: a file that does not say where the septum is has no layout (status 2).
pub fn check(input: &str, set: &ContourSet) -> Result<(), CliError> {
    if septum::said(set) {
        return Ok(());
    }
    Err(CliError::input(
        input,
        CoreError::parse(
            0,
            "--hex-mesh lays its cells out from the septum: the file has no RV_INSERT landmarks \
             and no RV contours",
        ),
    ))
}

/// The mesh between the finished endo- and epicardium, both laid out on the wall's `base` from
/// one septum (seen from the endocardium's centre) and on the endocardium's rays
/// ([`anatomical::build_pair`]), or why there is none.
pub fn build(
    set: &ContourSet,
    endo: &Reconstruction,
    epi: &Reconstruction,
    base: &Plane,
    r: &Request,
    min_thickness_mm: Option<f64>,
) -> Result<HexWall, String> {
    let orientation = anatomical::orientation_of(set, endo.mesh(), base)?;
    build_on(
        endo.mesh(),
        epi.mesh(),
        base,
        &orientation,
        r.shape,
        min_thickness_mm,
    )
}

/// The mesh between `endo` and `epi` on `base`, turned by `orientation`.
pub fn build_on(
    endo: &TriMesh,
    epi: &TriMesh,
    base: &Plane,
    orientation: &Orientation,
    shape: Shape,
    min_thickness_mm: Option<f64>,
) -> Result<HexWall, String> {
    let (inner, outer) = anatomical::build_pair(endo, epi, base, orientation, shape.layout)
        .map_err(|e| anatomical::reason(&e))?;
    hex_wall::build_with_helix(
        &inner,
        &outer,
        shape.layout,
        base,
        shape.layers,
        shape.helix,
        min_thickness_mm,
    )
    .map_err(|e| anatomical::reason(&e))
}

/// The report's `hex_mesh` (the file and the figures) or null and `hex_mesh_note`.
pub fn add_to_report(rep: &mut Value, path: &str, built: &Result<HexWall, String>) {
    let summary = built.as_ref().map(|x| json!(x.summary));
    crate::report::add_built(rep, "hex_mesh", path, summary);
}

/// The stdout line after the wall's.
pub fn summary_line(path: &str, h: &HexWall) -> String {
    let s = &h.summary;
    format!(
        "{}: {} hexahedra + {} wedges in {} layers, {} points, {:.1} ml, smallest scaled Jacobian \
         {:.2}{}",
        file_name(path),
        s.hexahedra,
        s.wedges,
        s.layers,
        s.points,
        s.volume_ml,
        s.min_scaled_jacobian,
        if s.inverted_cells > 0 {
            format!(", {} inverted cells", s.inverted_cells)
        } else {
            String::new()
        }
    )
}

/// A warning when cells are inverted (the two surfaces cross, or touch, somewhere): a solver
/// would refuse the mesh.
pub fn inverted_warning(path: &str, h: &HexWall) -> Option<String> {
    let n = h.summary.inverted_cells;
    (n > 0).then(|| {
        format!(
            "heartmesh: warning: {}: {n} of {} cells are inverted or flat: the endo- and \
             epicardium cross or touch there (a thin apex, images from different breath-holds; \
             try --align-slices)",
            file_name(path),
            h.cells.len()
        )
    })
}
