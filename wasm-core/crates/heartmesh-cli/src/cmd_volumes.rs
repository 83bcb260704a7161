//! `heartmesh volumes PHASES...`: cardiac function from one heart's contours over its phases.
//! Each surface is reconstructed in each phase at the same parameters, and the closed meshes'
//! volumes give each cavity's end-diastolic and end-systolic volume, stroke volume and ejection
//! fraction, and the LV myocardial mass (core `metrics::function`). Phases are one file each (ED
//! and ES GPFiles, ACDC's frame label maps) or the time frames of one file holding a sequence.

use std::cell::RefCell;
use std::time::Instant;

use heartmesh_core::io::{self, FrameChoice, MeshFormat};
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::metrics::anatomical_study::PhaseSurface;
use heartmesh_core::metrics::compare::{basal_plane, common_basal_plane_of, ClipPlane};
use heartmesh_core::metrics::function::{self, file_stem, Function, Measured, Outcome, UNLABELLED};
use heartmesh_core::metrics::segments::SegmentThickening;
use heartmesh_core::metrics::thickening::{self as wall_thickening, PhaseLv, Thickening};
use heartmesh_core::metrics::{bullseye, septum};
use heartmesh_core::pipeline::Reconstruction;
use heartmesh_core::{Contour, ContourSet, CoreError, Params};
use serde_json::{json, Value};

use crate::anatomical_study_out;
use crate::cmd_convert::file_name;
use crate::cmd_reconstruct::{apex_lid, classify, params_from, parse_with_inputs};
use crate::contours;
use crate::each_surface;
use crate::error::CliError;
use crate::files;
use crate::hex_study_out;

pub const USAGE: &str = "heartmesh volumes PHASES... [--surface all|LV_ENDO,LV_EPI,...]
    [--frames all|F,F,...] [--csv VOLUMES.csv] [--json VOLUMES.json] [--plot CURVE.svg]
    [--meshes DIR] [--thickening-plot BULLSEYE.svg]
    [--anatomical-meshes DIR [--anatomical-layout 24x48] [--anatomical-format vtk]]
    [--hex-meshes DIR [--hex-layout 24x48] [--layers 3] [--helix-angles 60,-60]]
    [reconstruct's parameter options: --iterations ... --end-caps ... --align-slices ...] [--quiet]
  Cardiac function: every surface reconstructed in every phase at the same parameters; prints
  the volumes (ml, of the closed meshes: the lids at the base included), each cavity's
  end-diastolic and end-systolic volume (its largest and smallest), stroke volume and ejection
  fraction, and the LV myocardial mass, 1.05 g/ml x (LV_EPI - LV_ENDO), at LV end-diastole and
  end-systole (none where LV_EPI encloses the RV cavity: a biventricular epicardium).
  PHASES: one contour file per phase (GPFile_000.txt GPFile_009.txt, patient1-ED.csv
  patient1-ES.csv, ACDC's frame01 and frame12 label maps), named by file; or one file holding a
  sequence (a cine GPFile, a CSV with a frame or phase column, a 4D label map, a cvi42
  workspace with its DICOM images or their folder, a Sunnybrook case's contours with its
  series), each time frame a phase named as the file
  writes it; --frames F,F,... takes only those frames.
  --surface: the surfaces to reconstruct (default all of the files'); epicardia and unknown
  labels (LABEL_n) get volumes but no ejection fraction.
  --csv: one row per phase and surface (volume_ml empty where the mesh is open or the run
  failed); --json: the volumes, each cavity's function and the mass per phase; --plot: each
  cavity's volume over the phases as an SVG chart (a gap where a phase has no volume);
  --meshes DIR: each mesh as DIR/PHASE-SURFACE.obj.
  --anatomical-meshes DIR: each phase's LV surfaces (LV_ENDO, LV_EPI) on the anatomical layout
  (see reconstruct --anatomical-mesh: the same vertices and triangles in every file), as
  DIR/PHASE-SURFACE.vtk (--anatomical-format vtk|vtp|ply|obj|stl); every phase turned by ONE
  septum direction, the LV end-diastole's (else the first phase whose file places it: RV_INSERT
  landmarks or RV contours), taken across each phase's own long axis, so that no phase's
  drawing of the RV turns its grid; point data displacement_mm: each vertex's distance from the
  same vertex at that phase; the JSON's anatomical_meshes lists the files and their figures.
  --hex-meshes DIR: each phase's LV wall as myocardium --hex-mesh writes it (hexahedra and
  apex wedges between the two layouts, fibres, AHA segments), DIR/PHASE-LV_WALL.vtk, every
  phase with the same points and cells, turned by that one septum; point vectors displacement:
  each point's displacement from the same point at that phase (a motion sequence for
  simulation); needs LV_ENDO and LV_EPI; the JSON's hex_meshes gives each file's counts,
  volume, cell quality and displacement.
  With LV_ENDO and LV_EPI: the LV wall's systolic thickening in each of the 17 AHA segments,
  100 x (ES - ED) / ED of the segment's mean thickness, the walls built as myocardium builds
  them at the LV's end-diastole and end-systole, their segments placed in each phase from the
  file's RV_INSERT landmarks or RV contours (the JSON's wall_thickening; a line says the mean
  and the range); --thickening-plot: those segments drawn as the AHA bullseye (SVG).
  A run that fails is named (phase and surface) and the others go on (exit status of the last
  failure).";

/// Options of this command only that take a value.
const VALUE_FLAGS: &[&str] = &[
    "frames",
    "csv",
    "json",
    "plot",
    "meshes",
    "thickening-plot",
    "anatomical-meshes",
    "anatomical-layout",
    "anatomical-format",
    "hex-meshes",
    "hex-layout",
    "layers",
    "helix-angles",
];

/// Switches of this command only.
const SWITCHES: &[&str] = &["quiet"];

/// One phase of the heart: a file, or one time frame of a file holding a sequence.
struct Phase {
    name: String,
    input: String,
    set: ContourSet,
    session_params: Option<Params>,
}

/// One surface reconstructed (or not) in one phase, and how long it took.
struct Cell {
    out: Outcome,
    seconds: f64,
    /// The run's most basal short-axis plane (the anatomical layouts stop there).
    base: Option<ClipPlane>,
    /// The core's sentence about remeshes it skipped (`Reconstruction::skipped_remesh_note`):
    /// a volume measured on such a mesh needs the user's eye.
    skipped_remeshes: Option<String>,
}

impl Cell {
    fn none(missing: &'static str) -> Cell {
        Cell {
            out: Outcome::none(missing),
            seconds: 0.0,
            base: None,
            skipped_remeshes: None,
        }
    }
}

pub fn run(args: &[String]) -> Result<(), CliError> {
    let p = parse_with_inputs(
        args,
        VALUE_FLAGS,
        SWITCHES,
        &[("-q", "quiet")],
        "volumes needs contour files, one per phase (e.g. the ED and ES files), or one file \
         holding a sequence of time frames",
    )?;
    // A usage error should not wait for the files.
    params_from(&p, Params::default())?;
    let layouts = anatomical_study_out::request(&p)?;
    let hexes = hex_study_out::request(&p)?;
    // The outputs before any work: a mistyped directory should not cost every phase's runs.
    for option in ["csv", "json", "plot", "thickening-plot"] {
        if let Some(path) = p.value(option) {
            files::check_output(path)?;
        }
    }
    let inputs: Vec<&str> = p.positional.iter().map(String::as_str).collect();
    let outputs: Vec<(&str, &str)> = [
        ("--csv", "csv"),
        ("--json", "json"),
        ("--plot", "plot"),
        ("--thickening-plot", "thickening-plot"),
    ]
    .into_iter()
    .filter_map(|(flag, name)| p.value(name).map(|v| (flag, v)))
    .collect();
    files::check_distinct(&inputs, &outputs)?;
    let frames = frames_flag(p.value("frames"))?;
    let phases = load_phases(&p.positional, frames.as_deref())?;
    let base = phases
        .first()
        .and_then(|ph| ph.session_params.clone())
        .unwrap_or_default();
    let params = params_from(&p, base)?;
    let surfaces = surfaces_wanted(p.value("surface"), &phases)?;
    check_leave_out(&params.leave_out, &phases, &surfaces)?;
    if p.value("thickening-plot").is_some() {
        check_thickening(&phases, &surfaces)?;
    }
    if layouts.is_some() {
        anatomical_study_out::check(phases.iter().map(|ph| &ph.set), &surfaces)?;
    }
    if hexes.is_some() {
        hex_study_out::check(phases.iter().map(|ph| &ph.set), &surfaces)?;
    }
    let meshes = p.value("meshes");
    let dirs = meshes
        .into_iter()
        .chain(layouts.as_ref().map(|r| r.dir.as_str()))
        .chain(hexes.as_ref().map(|r| r.dir.as_str()));
    for dir in dirs {
        files::create_dir(dir)?;
    }
    let quiet = p.switch("quiet");
    let apex_lids = p.value("lids") == Some("apex");
    let said = RefCell::new(Vec::<String>::new());
    let say = |line: String| {
        let mut said = said.borrow_mut();
        if !said.contains(&line) {
            eprintln!("{line}");
            said.push(line);
        }
    };

    let table = Table::new(&phases, &surfaces);
    if !quiet {
        outln!(
            "heartmesh: volumes of {} phase(s) x {} surface(s), ml",
            phases.len(),
            surfaces.len()
        );
        outln!("{}", table.header());
    }
    let mut failed: Option<CliError> = None;
    let mut cells: Vec<Vec<Cell>> = Vec::with_capacity(phases.len());
    for phase in &phases {
        let mut row = Vec::with_capacity(surfaces.len());
        for surface in &surfaces {
            let s = surface.as_deref();
            let cell = match reconstruct(phase, s, &params, apex_lids) {
                Ok(cell) => cell,
                Err(e) => {
                    let e = CliError::Surface(
                        Box::new(e),
                        format!("{}, phase {}", s.unwrap_or(UNLABELLED), phase.name),
                    );
                    if let Some(earlier) = failed.replace(e) {
                        eprintln!("heartmesh: {}", earlier.message());
                    }
                    Cell::none("failed")
                }
            };
            if let (Some(dir), Some(mesh)) = (meshes, &cell.out.mesh) {
                write_mesh(dir, phase, s, mesh)?;
            }
            row.push(cell);
        }
        if !quiet {
            for surface in &surfaces {
                for w in phase.set.warnings_for(surface.as_deref()) {
                    say(contours::warning_line(&phase.input, &w));
                }
            }
            for (surface, cell) in surfaces.iter().zip(&row) {
                if let Some(note) = &cell.skipped_remeshes {
                    let s = surface.as_deref().unwrap_or(UNLABELLED);
                    say(format!("heartmesh: warning: {}: {s}: {note}", phase.input));
                }
            }
            outln!("{}", table.row(phase, &row));
        }
        cells.push(row);
    }

    let summary = summarise(&phases, &surfaces, &cells);
    let thickening = thickening(&phases, &surfaces, &cells, &summary, &params);
    let mut written = Vec::new();
    if let Some(req) = &layouts {
        let w = anatomical_layouts(req, &phases, &surfaces, &cells, &summary)?;
        written.push(("anatomical_meshes", w.json, w.lines, w.notes));
    }
    if let Some(req) = &hexes {
        let w = hex_walls(req, &phases, &surfaces, &cells, &summary, &params)?;
        written.push(("hex_meshes", w.json, w.lines, w.notes));
    }
    if !quiet {
        for line in summary_lines(&summary) {
            outln!("{line}");
        }
        match &thickening {
            Some(Ok(t)) => outln!("{}", thickening_line(t)),
            Some(Err(why)) => eprintln!("heartmesh: note: no LV wall thickening: {why}"),
            None => {}
        }
        for line in written.iter().flat_map(|w| &w.2) {
            outln!("{line}");
        }
    }
    for note in written.iter().flat_map(|w| &w.3) {
        eprintln!("{note}");
    }
    if let Some(path) = p.value("csv") {
        files::write(path, csv(&phases, &surfaces, &cells).as_bytes())?;
    }
    if let Some(path) = p.value("plot") {
        files::write(path, plot(&phases, &surfaces, &cells, &summary).as_bytes())?;
    }
    if let Some(path) = p.value("json") {
        let mut doc = json_report(&phases, &surfaces, &cells, &summary, &params);
        if let (Some(t), Value::Object(map)) = (&thickening, &mut doc) {
            let (value, note) = match t {
                Ok(t) => (json!(t), Value::Null),
                Err(why) => (Value::Null, json!(why)),
            };
            map.insert("wall_thickening".into(), value);
            if !note.is_null() {
                map.insert("wall_thickening_note".into(), note);
            }
        }
        if let Value::Object(map) = &mut doc {
            for (key, json, _, _) in &written {
                map.insert((*key).into(), json.clone());
            }
        }
        let text = serde_json::to_string_pretty(&doc)
            .map_err(|e| CliError::Failed(format!("{path}: {e}")))?;
        files::write(path, format!("{text}\n").as_bytes())?;
    }
    // Last, so that a study without a thickening still gets its table, CSV and JSON.
    if let Some(path) = p.value("thickening-plot") {
        match &thickening {
            Some(Ok(t)) => files::write(path, bullseye::thickening_svg(t).as_bytes())?,
            Some(Err(why)) => {
                return Err(CliError::Failed(format!(
                    "{path}: no LV wall thickening: {why}"
                )))
            }
            None => {}
        }
    }
    failed.map_or(Ok(()), Err)
}

/// `--frames all|F,F,...`: None for every frame, else the frames asked for.
fn frames_flag(value: Option<&str>) -> Result<Option<Vec<FrameChoice>>, CliError> {
    let Some(v) = value.filter(|v| !v.trim().eq_ignore_ascii_case("all")) else {
        return Ok(None);
    };
    v.split(',')
        .map(|f| {
            FrameChoice::new(f).ok_or_else(|| {
                CliError::usage(format!(
                    "--frames: {v:?} holds an empty frame (give frame numbers or labels as the \
                     file writes them, comma-separated: --frames 0,9 or --frames ED,ES)"
                ))
            })
        })
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
}

/// The phases: each file one, or each (asked-for) time frame of a single file holding a sequence.
fn load_phases(paths: &[String], frames: Option<&[FrameChoice]>) -> Result<Vec<Phase>, CliError> {
    // A phase may be a folder (of Slicer markups, one file per curve).
    let phase = |path: &str, name: String, frame: Option<FrameChoice>| {
        contours::load_all(&[path.to_string()], frame).map(|(_, l)| Phase {
            name,
            input: path.to_string(),
            set: l.set,
            session_params: l.session_params,
        })
    };
    // One input holding a sequence: a file, or contours with the images they were drawn on.
    if paths.len() == 1 || contours::is_workspace_study(paths) {
        let read = |name: Option<String>, frame: Option<FrameChoice>| {
            contours::load_all(paths, frame).map(|(input, l)| Phase {
                name: name.unwrap_or_else(|| stem(file_name(input)).to_string()),
                input: input.to_string(),
                set: l.set,
                session_params: l.session_params,
            })
        };
        let first = read(None, None)?;
        let only = first.input.clone();
        let only = only.as_str();
        let listed = first
            .set
            .time_frames
            .as_ref()
            .filter(|t| t.sequence && t.frames.len() > 1)
            .map(|t| t.frames.clone());
        let Some(listed) = listed else {
            if frames.is_some() {
                return Err(CliError::usage(format!(
                    "--frames: {only} holds one phase (no contour has points in several time \
                     frames); give one file per phase instead"
                )));
            }
            return Ok(vec![first]);
        };
        let chosen: Vec<String> = match frames {
            None => listed.clone(),
            Some(wanted) => wanted
                .iter()
                .map(|w| {
                    listed
                        .iter()
                        .find(|f| w.matches(f))
                        .cloned()
                        .ok_or_else(|| no_such_frame(only, w, &listed))
                })
                .collect::<Result<_, _>>()?,
        };
        return chosen
            .into_iter()
            .map(|f| read(Some(f.clone()), FrameChoice::new(&f)))
            .collect();
    }
    if frames.is_some() {
        return Err(CliError::usage(
            "--frames picks time frames of one file holding a sequence; with one file per phase, \
             give the files of the phases wanted",
        ));
    }
    // A phase is named by its file without the extension; files of the same name in different
    // folders are told apart by their paths.
    let names: Vec<&str> = paths.iter().map(|p| stem(file_name(p))).collect();
    paths
        .iter()
        .zip(&names)
        .map(|(path, name)| {
            let unique = names.iter().filter(|n| *n == name).count() == 1;
            let name = if unique { name } else { path.as_str() };
            phase(path, name.to_string(), None)
        })
        .collect()
}

/// A file name without its extension (and a `.gz` before it): `GPFile_000.txt` -> `GPFile_000`,
/// `patient001_frame01_gt.nii.gz` -> `patient001_frame01_gt`.
fn stem(name: &str) -> &str {
    let base = name
        .strip_suffix(".gz")
        .or_else(|| name.strip_suffix(".GZ"))
        .unwrap_or(name);
    let base = base.strip_suffix(".seg.nrrd").unwrap_or(base);
    match base.rfind('.') {
        Some(dot) if dot > 0 => &base[..dot],
        _ => base,
    }
}

fn no_such_frame(input: &str, wanted: &FrameChoice, listed: &[String]) -> CliError {
    const SHOWN: usize = 12;
    let mut some: Vec<&str> = listed.iter().take(SHOWN).map(String::as_str).collect();
    if listed.len() > SHOWN {
        some.push("...");
    }
    CliError::usage(format!(
        "--frames: {input} has no time frame {:?} (its frames: {})",
        wanted.label(),
        some.join(", ")
    ))
}

/// The surfaces to reconstruct, in the files' order: every one (default, `all`), or those named
/// with `--surface A,B`, each of which some phase must hold (BIV_EPI is built from LV_EPI and
/// RV_EPI). `[None]` for files without surface labels.
fn surfaces_wanted(value: Option<&str>, phases: &[Phase]) -> Result<Vec<Option<String>>, CliError> {
    let all = function::surfaces_of(phases.iter().map(|ph| &ph.set));
    let known: Vec<String> = all.iter().flatten().cloned().collect();
    let wanted = value.filter(|v| !v.trim().eq_ignore_ascii_case(each_surface::ALL));
    let Some(wanted) = wanted else {
        return Ok(all);
    };
    wanted
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| {
            if known.iter().any(|k| k == s) || s == heartmesh_core::contours::biv_epi::BIV_EPI {
                Ok(Some(s.to_string()))
            } else {
                Err(CliError::usage(format!(
                    "--surface: no phase holds surface {s:?} (available: {})",
                    if known.is_empty() {
                        "none: the files carry no surface labels".to_string()
                    } else {
                        known.join(", ")
                    }
                )))
            }
        })
        .collect::<Result<Vec<_>, _>>()
        .and_then(|v| {
            if v.is_empty() {
                Err(CliError::usage("--surface: no surface named"))
            } else {
                Ok(v)
            }
        })
}

/// Reconstructs `surface` of `phase`; a phase without that surface is a cell marked absent.
fn reconstruct(
    phase: &Phase,
    surface: Option<&str>,
    params: &Params,
    apex_lids: bool,
) -> Result<Cell, CliError> {
    let holds = match surface {
        None => true,
        Some(s) if s == heartmesh_core::contours::biv_epi::BIV_EPI => true,
        Some(s) => phase.set.surfaces().iter().any(|k| k == s),
    };
    if !holds {
        return Ok(Cell::none("absent"));
    }
    let mut params = params.clone();
    params.surface = surface.map(str::to_string);
    params.leave_out = leave_out_of(&params.leave_out, &phase.set);
    if apex_lids {
        params.lids = apex_lid(&phase.set, surface).ok_or_else(|| {
            CliError::input(
                &phase.input,
                CoreError::parse(0, "--lids apex needs an APEX_POINT landmark in the file"),
            )
        })?;
    }
    let warnings = phase.set.warnings_for(surface);
    let fail = |e: CoreError| classify(&phase.input, e).with_hint(&warnings);
    let started = Instant::now();
    let mut rec = Reconstruction::new(&phase.set, params).map_err(fail)?;
    rec.run().map_err(fail)?;
    Ok(Cell {
        out: Outcome::of(&rec),
        seconds: started.elapsed().as_secs_f64(),
        base: basal_plane(&rec).ok(),
        skipped_remeshes: rec.skipped_remesh_note(),
    })
}

/// `--thickening-plot` needs LV_ENDO and LV_EPI in two phases or more and the septum's direction
/// in each (RV insertion landmarks or RV contours): said before any run (status 2).
fn check_thickening(phases: &[Phase], surfaces: &[Option<String>]) -> Result<(), CliError> {
    let measured = |s: &str| surfaces.iter().any(|k| k.as_deref() == Some(s));
    let why = if phases.len() < 2 {
        Some("two phases or more (ED and ES)".to_string())
    } else if !(measured("LV_ENDO") && measured("LV_EPI")) {
        Some("LV_ENDO and LV_EPI among the surfaces measured".to_string())
    } else {
        phases.iter().find(|ph| !septum::said(&ph.set)).map(|ph| {
            format!(
                "the septum's direction in every phase: {} has no RV_INSERT landmarks and \
                     no RV contours",
                ph.name
            )
        })
    };
    why.map_or(Ok(()), |why| {
        Err(CliError::usage(format!("--thickening-plot needs {why}")))
    })
}

/// The LV wall's thickening between its end-diastole and end-systole ([`wall_thickening`]).
fn thickening(
    phases: &[Phase],
    surfaces: &[Option<String>],
    cells: &[Vec<Cell>],
    f: &Function,
    params: &Params,
) -> Option<Result<Thickening, String>> {
    let column = |name: &str| surfaces.iter().position(|s| s.as_deref() == Some(name));
    let (endo, epi) = (column("LV_ENDO")?, column("LV_EPI")?);
    let lvs: Vec<PhaseLv> = phases
        .iter()
        .zip(cells)
        .map(|(ph, row)| PhaseLv {
            name: &ph.name,
            set: &ph.set,
            params: Params {
                leave_out: leave_out_of(&params.leave_out, &ph.set),
                ..params.clone()
            },
            endo: row[endo].out.mesh.as_ref(),
            epi: row[epi].out.mesh.as_ref(),
        })
        .collect();
    wall_thickening::of_study(&lvs, f)
}

/// The line printed under the function: the mean and the range over the segments.
fn thickening_line(t: &Thickening) -> String {
    let known: Vec<&SegmentThickening> = t
        .segments
        .iter()
        .filter(|s| s.thickening_percent.is_some())
        .collect();
    let pct = |s: &&SegmentThickening| s.thickening_percent.unwrap_or(f64::NAN);
    let least = known.iter().min_by(|a, b| pct(a).total_cmp(&pct(b)));
    let most = known.iter().max_by(|a, b| pct(a).total_cmp(&pct(b)));
    let range = match (least, most) {
        (Some(a), Some(b)) => format!(
            ", from {:.0} % ({} {}) to {:.0} % ({} {})",
            pct(a),
            a.id,
            a.name,
            pct(b),
            b.id,
            b.name
        ),
        _ => String::new(),
    };
    format!(
        "LV wall thickening by AHA segment, {} to {}: mean {:.0} %{range}",
        t.ed_phase, t.es_phase, t.mean_percent
    )
}

/// Every id `--leave-out` names must be a contour of some phase (a typo would otherwise leave the
/// contour in without a word); one that only some phases have is left out of those (a slice
/// drawn badly at end-systole only, a view acquired at one phase). Status 2, with the ids the
/// phases have (those of the `surfaces` measured, when they have any), before any run.
fn check_leave_out(
    ids: &[String],
    phases: &[Phase],
    surfaces: &[Option<String>],
) -> Result<(), CliError> {
    let Some(unknown) = ids
        .iter()
        .find(|id| !phases.iter().any(|ph| has_contour(&ph.set, id)))
    else {
        return Ok(());
    };
    let all = phases.iter().flat_map(|ph| &ph.set.contours);
    let measured = |c: &&Contour| surfaces.iter().any(|s| s.is_none() || *s == c.surface);
    let mut listed: Vec<&Contour> = all.clone().filter(measured).collect();
    if listed.is_empty() {
        listed = all.collect();
    }
    let mut available: Vec<String> = Vec::new();
    for c in listed {
        if !available.contains(&c.id) {
            available.push(c.id.clone());
        }
    }
    let error = CoreError::UnknownContour {
        id: unknown.clone(),
        available,
    };
    // One file names its file; the ids of several phases are no one file's.
    Err(match phases {
        [one] => CliError::input(&one.input, error),
        _ => CliError::param(error),
    })
}

fn has_contour(set: &ContourSet, id: &str) -> bool {
    set.contours.iter().any(|c| c.id == id)
}

/// The ids of `ids` this phase's file has: each phase leaves out its own (the others are
/// another phase's contours, checked by [`check_leave_out`]).
fn leave_out_of(ids: &[String], set: &ContourSet) -> Vec<String> {
    ids.iter()
        .filter(|id| has_contour(set, id))
        .cloned()
        .collect()
}

fn write_mesh(
    dir: &str,
    phase: &Phase,
    surface: Option<&str>,
    mesh: &TriMesh,
) -> Result<(), CliError> {
    let path = format!(
        "{}/{}.obj",
        dir.trim_end_matches(['/', '\\']),
        file_stem(&phase.name, surface.unwrap_or(UNLABELLED))
    );
    let comment = format!(
        "heartmesh {} volumes: {} of phase {} ({})",
        heartmesh_core::VERSION,
        surface.unwrap_or(UNLABELLED),
        phase.name,
        file_name(&phase.input)
    );
    let comment = io::tagged_comment(phase.set.coordinate_system, &comment);
    let bytes = io::write_mesh(mesh, MeshFormat::Obj, None, &comment)
        .map_err(|e| CliError::Failed(format!("{path}: {e}")))?;
    files::write(&path, &bytes)
}

/// A cell's mesh when it is closed (a layout or a wall needs a closed surface).
fn closed(c: &Cell) -> Option<&TriMesh> {
    c.out.mesh.as_ref().filter(|_| c.out.watertight)
}

/// The LV endocardium's end-diastolic phase: the reference of a study's layouts and walls (their
/// septum, and the displacements from it).
fn lv_end_diastole(summary: &Function) -> Option<&str> {
    summary
        .ventricles
        .iter()
        .find(|v| v.surface == "LV_ENDO")
        .map(|v| v.ed_phase.as_str())
}

/// `--anatomical-meshes`: the LV surfaces of every phase laid out on one septum, the LV's
/// end-diastole the reference (its septum, and the displacements from it).
fn anatomical_layouts(
    req: &anatomical_study_out::Request,
    phases: &[Phase],
    surfaces: &[Option<String>],
    cells: &[Vec<Cell>],
    summary: &Function,
) -> Result<anatomical_study_out::Written, CliError> {
    let mut items = Vec::new();
    for (phase, row) in phases.iter().zip(cells) {
        for (surface, cell) in surfaces.iter().zip(row) {
            let s = match surface.as_deref() {
                None => UNLABELLED,
                Some(s) if anatomical_study_out::is_lv(s) => s,
                Some(_) => continue,
            };
            if surface.is_some() && !phase.set.surfaces().iter().any(|k| k == s) {
                continue;
            }
            items.push(PhaseSurface {
                phase: &phase.name,
                surface: s,
                set: &phase.set,
                mesh: closed(cell).zip(cell.base.as_ref()),
            });
        }
    }
    let preferred = lv_end_diastole(summary);
    let input = |name: &str| {
        phases
            .iter()
            .find(|p| p.name == name)
            .map(|p| p.input.clone())
            .unwrap_or_default()
    };
    anatomical_study_out::write_all(req, &items, preferred, &input, &file_stem)
}

/// `--hex-meshes`: every phase's LV wall as hexahedra on the study's septum, the LV's
/// end-diastole the reference.
fn hex_walls(
    req: &hex_study_out::Request,
    phases: &[Phase],
    surfaces: &[Option<String>],
    cells: &[Vec<Cell>],
    summary: &Function,
    params: &Params,
) -> Result<anatomical_study_out::Written, CliError> {
    let column = |name: &str| surfaces.iter().position(|s| s.as_deref() == Some(name));
    let (Some(endo), Some(epi)) = (column("LV_ENDO"), column("LV_EPI")) else {
        return Err(CliError::usage(
            "--hex-meshes fills the LV wall between LV_ENDO and LV_EPI: measure both",
        ));
    };
    let walls: Vec<hex_study_out::PhaseWall> = phases
        .iter()
        .zip(cells)
        .map(|(ph, row)| {
            let wall_params = Params {
                leave_out: leave_out_of(&params.leave_out, &ph.set),
                ..params.clone()
            };
            hex_study_out::PhaseWall {
                phase: &ph.name,
                input: file_name(&ph.input).to_string(),
                set: &ph.set,
                surfaces: closed(&row[endo]).zip(closed(&row[epi])),
                endo_base: row[endo].base.as_ref(),
                wall_base: common_basal_plane_of(&ph.set, &wall_params, "LV_ENDO", "LV_EPI")
                    .map_err(|e| format!("no base plane: {e}")),
            }
        })
        .collect();
    let preferred = lv_end_diastole(summary);
    hex_study_out::write_all(req, &walls, preferred, &|phase: &str| {
        file_stem(phase, "LV_WALL")
    })
}

/// The stdout table: a row per phase, a column per surface.
struct Table {
    phase_width: usize,
    widths: Vec<usize>,
    names: Vec<String>,
}

impl Table {
    fn new(phases: &[Phase], surfaces: &[Option<String>]) -> Table {
        let names: Vec<String> = surfaces
            .iter()
            .map(|s| s.clone().unwrap_or_else(|| UNLABELLED.to_string()))
            .collect();
        Table {
            phase_width: phases
                .iter()
                .map(|p| p.name.chars().count())
                .max()
                .unwrap_or(0)
                .max(5),
            widths: names.iter().map(|n| n.chars().count().max(8)).collect(),
            names,
        }
    }

    fn header(&self) -> String {
        let mut line = format!("{:<w$}", "phase", w = self.phase_width);
        for (n, w) in self.names.iter().zip(&self.widths) {
            line.push_str(&format!("  {n:>w$}"));
        }
        line
    }

    fn row(&self, phase: &Phase, cells: &[Cell]) -> String {
        let mut line = format!("{:<w$}", phase.name, w = self.phase_width);
        for (c, w) in cells.iter().zip(&self.widths) {
            let text = match c.out.volume_ml {
                Some(v) => format!("{v:.1}"),
                None => c.out.missing.unwrap_or("-").to_string(),
            };
            line.push_str(&format!("  {text:>w$}"));
        }
        line
    }
}

/// Function and mass of the cells (core `metrics::function::summarise`).
fn summarise(phases: &[Phase], surfaces: &[Option<String>], cells: &[Vec<Cell>]) -> Function {
    let names: Vec<String> = phases.iter().map(|p| p.name.clone()).collect();
    let labels: Vec<String> = surfaces.iter().map(|s| label(s).to_string()).collect();
    let measured: Vec<Vec<Measured>> = cells
        .iter()
        .map(|row| row.iter().map(|c| c.out.measured()).collect())
        .collect();
    function::summarise(&names, &labels, &measured)
}

/// The volume curve (`--plot`, [`crate::volume_plot`]).
fn plot(
    phases: &[Phase],
    surfaces: &[Option<String>],
    cells: &[Vec<Cell>],
    f: &Function,
) -> String {
    let names: Vec<String> = phases.iter().map(|p| p.name.clone()).collect();
    let labels: Vec<String> = surfaces.iter().map(|s| label(s).to_string()).collect();
    let volumes: Vec<Vec<Option<f64>>> = cells
        .iter()
        .map(|row| row.iter().map(|c| c.out.volume_ml).collect())
        .collect();
    crate::volume_plot::curve(&names, &labels, &volumes, f)
}

fn label(surface: &Option<String>) -> &str {
    surface.as_deref().unwrap_or(UNLABELLED)
}

/// The summary as printed after the table.
fn summary_lines(f: &Function) -> Vec<String> {
    let mut out = Vec::new();
    for v in &f.ventricles {
        out.push(format!(
            "{}: EDV {:.1} ml ({}), ESV {:.1} ml ({}), SV {:.1} ml, EF {:.1} %",
            v.surface, v.edv_ml, v.ed_phase, v.esv_ml, v.es_phase, v.sv_ml, v.ef_percent
        ));
    }
    for s in &f.single {
        out.push(match s.volume_ml {
            Some(v) => format!(
                "{}: {v:.1} ml in the one phase with a closed mesh: no ejection fraction (give \
                 the end-diastolic and end-systolic phases)",
                s.surface
            ),
            None => format!("{}: no phase gave a closed mesh, so no volume", s.surface),
        });
    }
    if let Some(mass) = &f.lv_mass {
        let lv = f.ventricles.iter().find(|v| v.surface == "LV_ENDO");
        let at: Vec<(&str, &str)> = match lv {
            Some(v) => vec![
                ("at ED ", v.ed_phase.as_str()),
                ("at ES ", v.es_phase.as_str()),
            ],
            None => mass
                .per_phase
                .iter()
                .map(|p| ("", p.phase.as_str()))
                .collect(),
        };
        let parts: Vec<String> = at
            .iter()
            .filter_map(|(when, phase)| {
                let m = mass.per_phase.iter().find(|m| m.phase == *phase)?;
                Some(match (m.grams, m.why_none) {
                    (Some(g), _) => format!("{g:.1} g {when}({phase})"),
                    (None, why) => format!("none {when}({phase}: {})", why.unwrap_or("")),
                })
            })
            .collect();
        out.push(format!(
            "LV mass, {} g/ml x (LV_EPI - LV_ENDO): {}",
            mass.density_g_per_ml,
            parts.join(", ")
        ));
    }
    out
}

fn csv(phases: &[Phase], surfaces: &[Option<String>], cells: &[Vec<Cell>]) -> String {
    let mut out =
        String::from("phase,surface,volume_ml,watertight,contour_to_mesh_mean_mm,seconds\n");
    let quote = |s: &str| {
        if s.contains([',', '"', '\n']) {
            format!("\"{}\"", s.replace('"', "\"\""))
        } else {
            s.to_string()
        }
    };
    for (ph, row) in phases.iter().zip(cells) {
        for (s, c) in surfaces.iter().zip(row) {
            let opt = |v: Option<f64>, digits: usize| {
                v.map(|x| format!("{x:.digits$}")).unwrap_or_default()
            };
            out.push_str(&format!(
                "{},{},{},{},{},{:.3}\n",
                quote(&ph.name),
                quote(s.as_deref().unwrap_or(UNLABELLED)),
                opt(c.out.volume_ml, 3),
                c.out.watertight,
                opt(c.out.contour_to_mesh_mean, 4),
                c.seconds
            ));
        }
    }
    out
}

fn json_report(
    phases: &[Phase],
    surfaces: &[Option<String>],
    cells: &[Vec<Cell>],
    summary: &Function,
    params: &Params,
) -> Value {
    let names: Vec<&str> = surfaces.iter().map(label).collect();
    let volumes: Vec<Value> = phases
        .iter()
        .zip(cells)
        .flat_map(|(ph, row)| {
            names.iter().zip(row).map(move |(s, c)| {
                json!({
                    "phase": ph.name,
                    "input": file_name(&ph.input),
                    "surface": s,
                    "volume_ml": c.out.volume_ml,
                    "watertight": c.out.watertight,
                    "contour_to_mesh_mean": c.out.contour_to_mesh_mean,
                    "seconds": c.seconds,
                    "missing": c.out.missing,
                })
            })
        })
        .collect();
    let phase_names: Vec<&str> = phases.iter().map(|p| p.name.as_str()).collect();
    json!({
        "version": heartmesh_core::VERSION,
        "phases": phase_names,
        "surfaces": names,
        "parameters": crate::report::report_parameters(params),
        "volumes": volumes,
        "function": summary.ventricles,
        "lv_mass": summary.lv_mass,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phases_are_named_by_their_files_without_extensions() {
        assert_eq!(stem("GPFile_000.txt"), "GPFile_000");
        assert_eq!(
            stem("patient001_frame01_gt.nii.gz"),
            "patient001_frame01_gt"
        );
        assert_eq!(stem("case.seg.nrrd"), "case");
        assert_eq!(stem("ES"), "ES");
        assert_eq!(stem(".hidden"), ".hidden");
    }

    #[test]
    fn frames_flag_reads_lists_and_all() {
        assert!(frames_flag(None).unwrap().is_none());
        assert!(frames_flag(Some("ALL")).unwrap().is_none());
        let f = frames_flag(Some("0, ES")).unwrap().unwrap();
        assert_eq!(f.len(), 2);
        assert!(f[0].matches("0.0") && f[1].matches("es"));
        let e = frames_flag(Some("0,,9")).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(e.message().contains("empty frame"), "{}", e.message());
    }
}
