//! `volumes --hex-meshes DIR [--hex-layout 24x48] [--layers 3] [--helix-angles 60,-60]`: the LV
//! wall of every phase as the hexahedra `myocardium --hex-mesh` writes, all with the same
//! points and cells, all turned by the study's one septum (core
//! `metrics::anatomical_study::study_septum`), each carrying every point's displacement from
//! end-diastole as a vector. A sequence of simulation meshes with one connectivity is what a
//! modeller prescribes motion with (the displacement at each point, frame by frame); walls
//! turned by each frame's own RV drawing would twist by a few degrees between frames.
//!
//! Checked before the runs: the shape options, LV_ENDO and LV_EPI among the surfaces measured,
//! and a phase saying where the septum is.

use heartmesh_core::geometry::Vec3;
use heartmesh_core::mesh::hex_wall::{self, HexWall};
use heartmesh_core::metrics::anatomical_study::{self, PhaseSurface, StudySeptum};
use heartmesh_core::sim::slice::Plane;
use heartmesh_core::{ContourSet, TriMesh};
use serde_json::{json, Value};

use crate::anatomical_study_out::{require_septum, Written};
use crate::args::Parsed;
use crate::error::CliError;
use crate::files;
use crate::hex_out::Shape;

/// The walls' minimum thickness along each ray (mm): `myocardium`'s default, as the thickening
/// walls use it.
const MIN_THICKNESS_MM: f64 = 1.0;

/// What `--hex-meshes` asked for.
pub struct Request {
    pub dir: String,
    pub shape: Shape,
}

/// The request, None without `--hex-meshes`; the shape options alone are usage errors.
pub fn request(p: &Parsed) -> Result<Option<Request>, CliError> {
    match p.value("hex-meshes") {
        None if Shape::asked(p) => Err(CliError::usage(
            "--hex-layout, --layers and --helix-angles shape the cells of --hex-meshes; add \
             --hex-meshes DIR",
        )),
        None => Ok(None),
        Some(dir) => Ok(Some(Request {
            dir: dir.to_string(),
            shape: Shape::from(p)?,
        })),
    }
}

/// Before any run: the LV's two surfaces measured and a septum in some phase (status 2).
pub fn check<'a>(
    sets: impl IntoIterator<Item = &'a ContourSet>,
    surfaces: &[Option<String>],
) -> Result<(), CliError> {
    let measured = |s: &str| surfaces.iter().any(|k| k.as_deref() == Some(s));
    if !(measured("LV_ENDO") && measured("LV_EPI")) {
        return Err(CliError::usage(
            "--hex-meshes fills the LV wall between LV_ENDO and LV_EPI: measure both",
        ));
    }
    require_septum("--hex-meshes starts its cells", sets)
}

/// One phase's wall as the study holds it: its surfaces (closed), the LV_ENDO run's base plane
/// (where the study's septum is found) and the wall's base plane (the lower of the two
/// surfaces' most basal slices, as `myocardium` cuts it); None where a surface is missing.
pub struct PhaseWall<'a> {
    pub phase: &'a str,
    pub input: String,
    pub set: &'a ContourSet,
    pub surfaces: Option<(&'a TriMesh, &'a TriMesh)>,
    pub endo_base: Option<&'a Plane>,
    pub wall_base: Result<Plane, String>,
}

/// Builds every phase's wall on the study's septum (the `preferred` phase's, the LV's
/// end-diastole), writes them as DIR/`name(phase)`.vtk with each point's displacement from the
/// septum's phase, and says what was written.
pub fn write_all(
    req: &Request,
    walls: &[PhaseWall],
    preferred: Option<&str>,
    name: &dyn Fn(&str) -> String,
) -> Result<Written, CliError> {
    let items: Vec<PhaseSurface> = walls
        .iter()
        .map(|w| PhaseSurface {
            phase: w.phase,
            surface: "LV_ENDO",
            set: w.set,
            mesh: w.surfaces.map(|(endo, _)| endo).zip(w.endo_base),
        })
        .collect();
    let septum = anatomical_study::study_septum(&items, preferred)
        .map_err(|why| CliError::Failed(format!("--hex-meshes: {why}")))?;
    let built: Vec<Result<HexWall, String>> =
        walls.iter().map(|w| wall_of(w, req, &septum)).collect();
    let reference = walls
        .iter()
        .zip(&built)
        .find(|(w, _)| w.phase == septum.phase)
        .and_then(|(_, b)| b.as_ref().ok());
    let mut entries = Vec::new();
    let mut notes = Vec::new();
    let mut moved: Vec<(String, f64, f64)> = Vec::new();
    for (w, b) in walls.iter().zip(&built) {
        match b {
            Ok(h) => {
                let shift: Option<Vec<Vec3>> = reference
                    .filter(|r| r.points.len() == h.points.len())
                    .map(|r| h.points.iter().zip(&r.points).map(|(p, q)| p - q).collect());
                let lengths: Vec<f64> = shift.iter().flatten().map(|d| d.norm()).collect();
                let mean = (!lengths.is_empty())
                    .then(|| lengths.iter().sum::<f64>() / lengths.len() as f64);
                let max = mean.map(|_| lengths.iter().copied().fold(0.0, f64::max));
                if let (Some(mean), Some(max)) = (mean, max) {
                    moved.push((w.phase.to_string(), mean, max));
                }
                let file = format!("{}.vtk", name(w.phase));
                let path = format!("{}/{file}", req.dir.trim_end_matches(['/', '\\']));
                let mut comment = hex_wall::comment(h, &w.input, "LV_ENDO", "LV_EPI");
                comment.push_str(&format!(
                    "; phase {}; every phase turned by one septum ({})",
                    w.phase, septum.source
                ));
                if shift.is_some() {
                    comment.push_str(&format!(
                        "; point vectors displacement: from the same point in phase {}",
                        septum.phase
                    ));
                }
                let extra = shift.as_deref().map(|d| ("displacement", d));
                files::write(&path, &h.to_vtk_with(&comment, extra))?;
                entries.push(json!({
                    "phase": w.phase,
                    "file": file,
                    "summary": h.summary,
                    "displacement_mean_mm": mean,
                    "displacement_max_mm": max,
                }));
            }
            Err(why) => {
                notes.push(format!(
                    "heartmesh: note: no hexahedral wall in phase {}: {why}",
                    w.phase
                ));
                entries.push(json!({ "phase": w.phase, "file": Value::Null, "note": why }));
            }
        }
    }
    let s = req.shape;
    let written = built.iter().filter(|b| b.is_ok()).count();
    let inverted: usize = built
        .iter()
        .flatten()
        .map(|h| h.summary.inverted_cells)
        .sum();
    let mut lines = vec![format!(
        "hexahedral walls {}x{}x{} in {}: {written} of {} phases, the same points and cells in \
         each; one septum for every phase: {}{}",
        s.layout.rings,
        s.layout.points,
        s.layers,
        req.dir,
        walls.len(),
        septum.source,
        if inverted > 0 {
            format!("; {inverted} inverted cells")
        } else {
            String::new()
        }
    )];
    if let Some((phase, mean, max)) = moved
        .iter()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .filter(|m| m.1 > 0.0)
    {
        lines.push(format!(
            "  wall points: mean displacement from phase {} up to {mean:.2} mm (phase {phase}), \
             largest {max:.2} mm",
            septum.phase
        ));
    }
    Ok(Written {
        json: json!({
            "directory": req.dir,
            "layout": { "rings": s.layout.rings, "points": s.layout.points },
            "layers": s.layers,
            "helix_deg": [s.helix.0, s.helix.1],
            "septum": septum,
            "displacement_from_phase": septum.phase,
            "meshes": entries,
        }),
        lines,
        notes,
    })
}

/// One phase's wall on the study's septum, taken across the wall's own axis.
fn wall_of(w: &PhaseWall, req: &Request, septum: &StudySeptum) -> Result<HexWall, String> {
    let (endo, epi) = w
        .surfaces
        .ok_or_else(|| "no closed LV_ENDO and LV_EPI meshes in this phase".to_string())?;
    let base = w.wall_base.as_ref().map_err(|e| e.clone())?;
    let orientation =
        anatomical_study::orientation_across(&Vec3::from(septum.direction), &base.normal)
            .ok_or_else(|| "the study's septum lies along this phase's long axis".to_string())?;
    crate::hex_out::build_on(
        endo,
        epi,
        base,
        &orientation,
        req.shape,
        Some(MIN_THICKNESS_MM),
    )
}
