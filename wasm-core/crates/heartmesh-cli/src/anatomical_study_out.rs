//! `volumes --anatomical-meshes DIR [--anatomical-layout 24x48] [--anatomical-format vtk]`: every
//! phase's LV surfaces on the anatomical layout, all turned by one septum (core
//! `metrics::anatomical_study`), each file carrying its vertices' displacement from the LV's
//! end-diastole. What a motion or shape study loads: the same vertices in every file.
//!
//! What can be known before the runs is checked before them (no LV surface measured, no phase
//! saying where the septum is): a refusal after every phase's reconstruction would waste them.

use heartmesh_core::io::MeshFormat;
use heartmesh_core::metrics::anatomical::{self, Layout};
use heartmesh_core::metrics::anatomical_study::{self, PhaseLayout, PhaseSurface, Study};
use heartmesh_core::metrics::septum;
use heartmesh_core::ContourSet;
use serde_json::{json, Value};

use crate::args::Parsed;
use crate::cmd_convert::file_name;
use crate::error::CliError;
use crate::files;

/// What `--anatomical-meshes` asked for.
#[derive(Debug, Clone)]
pub struct Request {
    pub dir: String,
    pub layout: Layout,
    pub format: MeshFormat,
}

/// The request, None without `--anatomical-meshes`; its companions alone are usage errors (they
/// would silently do nothing).
pub fn request(p: &Parsed) -> Result<Option<Request>, CliError> {
    let layout = p.value("anatomical-layout");
    let format = p.value("anatomical-format");
    let Some(dir) = p.value("anatomical-meshes") else {
        return match (layout, format) {
            (None, None) => Ok(None),
            _ => Err(CliError::usage(
                "--anatomical-layout and --anatomical-format set the files of \
                 --anatomical-meshes; add --anatomical-meshes DIR",
            )),
        };
    };
    let layout = layout
        .map_or(Ok(Layout::DEFAULT), Layout::parse)
        .map_err(|e| CliError::usage(format!("--anatomical-layout: {e}")))?;
    let format = match format.map(|f| f.trim_start_matches('.').to_ascii_lowercase()) {
        None => MeshFormat::Vtk,
        Some(ext) => MeshFormat::from_path(&format!("x.{ext}")).ok_or_else(|| {
            CliError::usage(format!(
                "--anatomical-format {ext}: one of vtk, vtp, ply, obj, stl"
            ))
        })?,
    };
    Ok(Some(Request {
        dir: dir.to_string(),
        layout,
        format,
    }))
}

/// Whether a surface label is one of the LV's (the layout's surfaces).
pub fn is_lv(surface: &str) -> bool {
    surface.to_ascii_uppercase().starts_with("LV") && anatomical::surface_refusal(surface).is_none()
}

/// Before any run: the LV surfaces among those measured, or why there can be no layout
/// (status 2).
pub fn check<'a>(
    sets: impl IntoIterator<Item = &'a ContourSet>,
    surfaces: &[Option<String>],
) -> Result<(), CliError> {
    // An unlabelled file's one surface may be an LV's (the septum check below decides).
    if !surfaces.iter().any(|s| s.as_deref().is_none_or(is_lv)) {
        return Err(CliError::usage(
            "--anatomical-meshes lays out the LV's surfaces (LV_ENDO, LV_EPI), and none is \
             among the surfaces measured",
        ));
    }
    require_septum("--anatomical-meshes starts every layout", sets)
}

/// Before any run of a study's layouts (`--anatomical-meshes`, `--hex-meshes`): some phase's
/// file must say where the septum is (status 2), `what` naming the option.
pub fn require_septum<'a>(
    what: &str,
    sets: impl IntoIterator<Item = &'a ContourSet>,
) -> Result<(), CliError> {
    if sets.into_iter().any(septum::said) {
        return Ok(());
    }
    Err(CliError::usage(format!(
        "{what} at the septum, and no phase's file has RV_INSERT landmarks or RV contours to \
         place it by"
    )))
}

/// What a study's files came to (`--anatomical-meshes`, `--hex-meshes`): the JSON's entry, the
/// lines for stdout and the notes for stderr.
pub struct Written {
    pub json: Value,
    pub lines: Vec<String>,
    pub notes: Vec<String>,
}

/// Lays out `items`, writes each layout into the request's directory (named as `--meshes` names
/// its files, `name(phase, surface)`), and says what was written.
pub fn write_all(
    req: &Request,
    items: &[PhaseSurface],
    preferred: Option<&str>,
    inputs: &dyn Fn(&str) -> String,
    name: &dyn Fn(&str, &str) -> String,
) -> Result<Written, CliError> {
    let study = anatomical_study::of_study(items, preferred, req.layout)
        .map_err(|why| CliError::Failed(format!("--anatomical-meshes: {why}")))?;
    let ext = req.format.extension();
    let mut files = Vec::with_capacity(study.layouts.len());
    let mut notes = Vec::new();
    for l in &study.layouts {
        let input = file_name(&inputs(&l.phase)).to_string();
        match l.file(&study, req.format, &input) {
            Some(bytes) => {
                let file = format!("{}.{ext}", name(&l.phase, &l.surface));
                let path = format!("{}/{file}", req.dir.trim_end_matches(['/', '\\']));
                let bytes = bytes.map_err(|e| CliError::Failed(format!("{path}: {e}")))?;
                files::write(&path, &bytes)?;
                files.push(Some(file));
            }
            None => {
                if let Err(why) = &l.built {
                    notes.push(format!(
                        "heartmesh: note: no anatomical mesh of {} in phase {}: {why}",
                        l.surface, l.phase
                    ));
                }
                files.push(None);
            }
        }
    }
    let mut json = study.report(req.format, &files);
    if let Value::Object(map) = &mut json {
        map.insert("directory".into(), json!(req.dir));
    }
    Ok(Written {
        json,
        lines: lines(req, &study),
        notes,
    })
}

/// The stdout lines: what was written and on which septum, then each surface's largest mean
/// displacement from the reference phase.
fn lines(req: &Request, study: &Study) -> Vec<String> {
    let built: Vec<&PhaseLayout> = study.layouts.iter().filter(|l| l.built.is_ok()).collect();
    let turns: Vec<f64> = built.iter().filter_map(|l| l.septum_turn_deg).collect();
    let own = match turns.iter().copied().reduce(f64::max) {
        Some(t) => format!("; each phase's own within {t:.1} degrees of it"),
        None => String::new(),
    };
    let mut out = vec![format!(
        "anatomical meshes {}x{} in {}: {} of {} layouts, the same vertices in each; one septum \
         for every phase: {}{own}",
        study.layout.rings,
        study.layout.points,
        req.dir,
        built.len(),
        study.layouts.len(),
        study.septum.source,
    )];
    let mut surfaces: Vec<&str> = Vec::new();
    for l in &built {
        if !surfaces.contains(&l.surface.as_str()) {
            surfaces.push(&l.surface);
        }
    }
    for s in surfaces {
        let most = built
            .iter()
            .filter(|l| l.surface == s)
            .filter_map(|l| l.displacement_stats().map(|d| (l, d)))
            .max_by(|a, b| a.1 .0.total_cmp(&b.1 .0));
        if let Some((l, (mean, max))) = most.filter(|(_, (mean, _))| *mean > 0.0) {
            out.push(format!(
                "  {s}: mean displacement from phase {} up to {mean:.2} mm (phase {}), largest \
                 {max:.2} mm",
                study.septum.phase, l.phase
            ));
        }
    }
    out
}
