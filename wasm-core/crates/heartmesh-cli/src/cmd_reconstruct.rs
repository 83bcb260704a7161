//! `heartmesh reconstruct CONTOURS -o MESH`: the whole method of Villard, Grau & Zacur
//! (J. Imaging 2018) from a contour file to a mesh file and an optional JSON report.

use std::cell::RefCell;
use std::time::Instant;

use heartmesh_core::contours::{cite, set_aside, slice_loops};
use heartmesh_core::io::{self, MeshFormat};
use heartmesh_core::pipeline::{Reconstruction, SetAsideDistance};
use heartmesh_core::{ContourSet, CoreError, LidMode, Params};

use heartmesh_core::metrics::anatomical::{Anatomical, Layout};

use crate::anatomical_out;
use crate::args::{parse, Parsed, Spec};
use crate::cmd_convert::file_name;
use crate::contours;
use crate::each_surface;
use crate::error::CliError;
use crate::files;
use crate::report;

pub const USAGE: &str =
    "heartmesh reconstruct CONTOURS -o MESH.obj [--report REPORT.json] [--surface LV_ENDO|all]
    [--iterations 250] [--lambda 1e5] [--beta 0.1] [--attractors N | --attractor-spacing MM]
    [--remesh-every 20] [--smoothing-iterations 200] [--smoothing-factor 0.1]
    [--smoothing-method laplacian-affine|taubin|laplacian-hc|laplacian-twicing] [--target-reduction 0.72] [--lids auto|none|apex] [--resample-attractors-every 25]
    [--ring-points 50] [--no-soften-conflicts] [--align-slices [--align-in-plane-only]] [--end-caps auto|off] [--no-apex-floor] [--drop-second-loops] [--keep-specks] [--frame N|LABEL]
    [--leave-out ID[,ID...]] [--contour-distances POINTS.csv]
    [--anatomical-mesh GRID.vtk [--anatomical-layout 24x48]] [--ascii] [--quiet]
  CONTOURS may be a NIfTI short-axis label map followed by its long-axis views (single-slice
  label maps, any order of the files: reconstruct SEG.nii.gz LA_2CH.nii.gz LA_4CH.nii.gz -o ...),
  their labels matched to the stack's by position; or a cvi42 workspace followed by the DICOM
  images it was drawn on, files, folders or ZIP archives (reconstruct Contours.cvi42wsx DICOM/
  -o ..., reconstruct 1234_cvi42.zip 1234_images.zip -o ...; a ZIP archive alone is read for
  the contour file in it); or a Sunnybrook Cardiac Data case, its contour files
  (IM-0001-0048-icontour-manual.txt, ...) with the cine short-axis series they were drawn on
  (reconstruct SC-HF-I-01/contours-manual/IRCCI-expert/ SCD0000101/CINESAX_300/ -o ...; image
  0048 of the series, by file name or Instance Number; icontour LV_ENDO, ocontour LV_EPI): each
  contour placed by its image's position, orientation and pixel spacing, the frame of a cine
  slice by trigger time from 0 (--frame 9), other files set aside with a warning; or 3D Slicer
  markups (.mrk.json, one file per curve as Slicer saves them: the files or their folder,
  reconstruct patient1-markups/ -o ...; Slicer 4's point list files .fcsv and Slicer's control
  points tables .csv, label,l,p,s,..., the same way), read as
  one set, closed curves and curves through their control points (point lists clicked along a
  contour too), each curve's surface from its name (LV endo 3: LV_ENDO); or a 3D Slicer
  scene, its .mrb bundle or its folder (reconstruct Patient1.mrb -o ...): its markups curves,
  else its segmentation, the scene file, scans and the rest set aside with a warning;
  MESH format from its extension: .obj .stl .ply .vtk .vtp (--ascii: ASCII STL); PLY, VTK and
  VTP carry each vertex's distance to the nearest contour point (mm) as point data `distance`;
  --smoothing-method taubin: lambda/mu smoothing (lambda = smoothing factor, at most 0.6)
  instead of Laplacian + affine shrink correction; laplacian-hc: Laplacian sweeps with a local
  shrink correction after each (HC, Vollmer et al. 1999); laplacian-twicing: each vertex pushed
  back by the smoothed part of its own displacement (factor at most 0.5);
  --no-soften-conflicts: keep full weight on short- and long-axis attractors that disagree in
  the final steps (the default down-weights them there instead of letting the surface fold);
  --align-slices: first shift every short-axis slice and long-axis view of the file (all
  surfaces together) in its own plane until the curves meet where the planes cross (breath-hold
  misalignment); the report gains the shifts (alignment) and the distances to the contours as
  given (contour_to_mesh_as_given);
  each short-axis slice also moves along its own normal where the long-axis curves' slopes
  show it (the report's through_plane_mm); --align-in-plane-only (a study switch) keeps the
  shifts in the image planes (the alignment before through-plane offsets);
  --end-caps auto (the default): at each end of the cavity no long-axis curve closes (usually
  the base), synthetic lid points in the lid's plane pull the mesh with a weight below 1, so it
  stops at the data instead of running on past it: where long-axis curves reach the end, at their
  tips; where none does (short-axis only), at the apex the apex floor below (none with
  --no-apex-floor: extrapolated) and at the base a ceiling one slice spacing beyond the basal
  slice; they are not data (never in the distances); the report's
  end_caps says which ends got them and how many (end_caps.base_too_narrow: the base wanted a
  lid but its outline has no room for points two attractor spacings in from its rim, as an RV
  crescent may at a hundred attractors or fewer; if such a base runs on over 5 mm past the data,
  at an attractor resampling from iteration 51 on its lid is laid nearer the rim,
  end_caps.base_rim_lid_at the iteration; a note when none fits even there);
  --end-caps off leaves such ends to
  extrapolation (the paper's method);
  with end caps on, an apex no long-axis curve reaches (short-axis-only files) gets by default
  one lid point at the tip the most apical slices' taper predicts (the apex floor: slice area
  against height, the shallower of a paraboloid through the two most apical slices and a quadric
  dome fitted to up to four), pulling only while the mesh stops short of it; none where the
  slices do not taper (or the two slices' taper would put the tip over two slice gaps below the
  apical slice); the report's end_caps.apex_floor says where it was placed, parameters.apex_floor
  whether it was on; --no-apex-floor leaves such an apex to the paper's extrapolation (which
  stops short of it); --apex-floor, the default, is still accepted (it turns the floor back on
  over a session saved without it);
  --drop-second-loops: leave out closed loops that lie apart (median over 3 mm) from the main
  loop of their short-axis slice (another structure the slice cut; the load-time warning names
  them), so the surface follows each slice's main loop only;
  by default a contour or a small group of them far from the rest of its surface (a stray:
  further than half the rest's span and three times its slice spacing), a short-axis slice
  whose ring is under a tenth of the ring one slice away anywhere but at the apex (a speck), and
  a long-axis curve under a tenth of the data's extent along the axis (a click in a long-axis
  view) are left out of the reconstruction, each named in a warning and in the report's
  set_aside; --keep-specks keeps them (the paper's method);
  --leave-out ID[,ID...] (repeatable): leave out the contours of those ids (a slice drawn badly,
  a view from another phase; ids as `heartmesh info` or the report's per_contour name them),
  before the rules above; the report's set_aside lists them (reason by_user) with how far the
  mesh passes from each (mean, median, max in mm: leave-one-out's figures for it) and a note
  names them with those; an id no contour of the file has is an error; one of another surface
  is ignored there (volumes: an id only some phases have is left out of those);
  --lids apex puts the apex lid at the file's apex landmark (biv-me GPFiles: APEX_POINT, or
  APEX_ENDO_POINT / APEX_EPI_POINT for the endo- / epicardial surfaces);
  --contour-distances writes the cleaned contours with each point's distance to the mesh (mm).
  --anatomical-mesh writes the finished LV surface (LV_ENDO, LV_EPI) resampled onto a fixed
  grid, the same vertices in the same order and the same triangles for every heart and phase
  (point correspondence for shape analysis): vertex 0 the apex (the lowest point along the long
  axis), then RINGS rings of POINTS vertices from the apex to the base plane (the most basal
  short-axis slice; ring heights 1 - cos(pi/2 s) of the length, denser at the apex), vertex j
  of each ring where the ray from the section's centre at 360*j/POINTS degrees from the
  septum's middle (towards anterior) leaves the surface, last the base lid's centre (triangles
  labelled wall and base); every vertex lies on the surface; the septum comes from the file's
  RV_INSERT landmarks or RV contours (a file with neither is refused before the run, as is an
  RV surface); --anatomical-layout RINGSxPOINTS (2-200 x 8-720, default 24x48); the report's
  anatomical_mesh gives its figures (volume, distance to the surface); with --surface all each
  LV surface gets its own (GRID-LV_ENDO.vtk, ...).
  --surface all: each surface of the file in turn (its order), each to the output names with
  -SURFACE before the extension (-o m.obj --report r.json: m-LV_ENDO.obj, r-LV_ENDO.json, ...);
  a surface that fails is named and the others still run (exit status of the last failure).
  --surface BIV_EPI: the biventricular epicardium of a file with LV_EPI and RV_EPI curves (both
  read together, plane by plane; LV points inside the RV's region left out); not part of all.
  CONTOURS: csv (UTF-8, UTF-16 or Windows-1252; units in the header applied; without a header
  the rows read name,x,y,z[,surface] or x,y,z), biv-me GPFile (SliceInfoFile.txt beside it is
  used), xyz text, vtk/vtp lines, SurFCo .mat, a Segment study .mat (frames from 1), heartmesh
  session .json (its parameters are the starting point; flags override them); --frame reads one
  time frame of a GPFile or of a CSV with a frame or phase column, named as the file writes it:
  a number (--frame 9; 9.0 is the same frame) or a label (--frame ES; text in any case); default:
  each contour's first; the report's frame says which was read.";

/// Options of this command only that take a value.
const VALUE_FLAGS: &[&str] = &[
    "output",
    "report",
    "frame",
    "contour-distances",
    "anatomical-mesh",
    "anatomical-layout",
];

/// Options without a value of this command only.
const SWITCHES: &[&str] = &["ascii", "quiet"];

/// Options with a value that set reconstruction parameters ([`params_from`]), besides the numeric
/// ones; shared with the commands that reconstruct (`volumes`).
pub(crate) const PARAM_VALUE_FLAGS: &[&str] = &[
    "surface",
    "lids",
    "smoothing-method",
    "end-caps",
    "leave-out",
];

/// Switches that set reconstruction parameters ([`params_from`]).
pub(crate) const PARAM_SWITCHES: &[&str] = &[
    "no-soften-conflicts",
    "align-slices",
    "align-in-plane-only",
    "drop-second-loops",
    "apex-floor",
    "no-apex-floor",
    "keep-specks",
];

/// Parses the command line of a command that reconstructs: its own options with a value
/// (`own_values`) and switches, and the parameters' ([`params_from`] reads them).
/// The `-o` mesh file and its format (from the extension; `--ascii` turns STL into ASCII STL);
/// `missing` is the usage error when there is no `-o`.
pub(crate) fn mesh_output<'a>(
    p: &'a Parsed,
    missing: &str,
) -> Result<(&'a str, MeshFormat), CliError> {
    let output = p.value("output").ok_or_else(|| CliError::usage(missing))?;
    let format = MeshFormat::from_path(output).ok_or_else(|| {
        CliError::usage(format!(
            "cannot tell the mesh format of {output} (use .obj .stl .ply .vtk or .vtp)"
        ))
    })?;
    Ok((
        output,
        if p.switch("ascii") && format == MeshFormat::StlBinary {
            MeshFormat::StlAscii
        } else {
            format
        },
    ))
}

pub(crate) fn parse_with_params(
    args: &[String],
    own_values: &[&str],
    own_switches: &[&str],
    aliases: &[(&str, &str)],
) -> Result<Parsed, CliError> {
    let numeric = numeric_flags();
    let mut with_value: Vec<&str> = own_values.to_vec();
    with_value.extend(PARAM_VALUE_FLAGS);
    with_value.extend(numeric.iter().map(String::as_str));
    let mut switches: Vec<&str> = own_switches.to_vec();
    switches.extend(PARAM_SWITCHES);
    parse(
        args,
        &Spec {
            with_value: &with_value,
            switches: &switches,
            aliases,
        },
    )
}

/// [`parse_with_params`] for a command that reads contour files: a call naming none is a usage
/// error (`missing` says what the command needs) before any flag is looked at, alike in every
/// command that runs reconstructions.
pub(crate) fn parse_with_inputs(
    args: &[String],
    own_values: &[&str],
    own_switches: &[&str],
    aliases: &[(&str, &str)],
    missing: &str,
) -> Result<Parsed, CliError> {
    let p = parse_with_params(args, own_values, own_switches, aliases)?;
    if p.positional.is_empty() {
        return Err(CliError::usage(missing));
    }
    Ok(p)
}

/// Flag names (dashes) of the numeric parameters, from the core's schema.
fn numeric_flags() -> Vec<String> {
    Params::schema()
        .iter()
        .map(|s| s.name.replace('_', "-"))
        .collect()
}

pub fn run(args: &[String]) -> Result<(), CliError> {
    let p = parse_with_inputs(
        args,
        VALUE_FLAGS,
        SWITCHES,
        &[("-o", "output"), ("-q", "quiet")],
        "reconstruct needs a contour file (or a segmented study: a short-axis label map and its \
         long-axis views)",
    )?;
    let (output, format) = mesh_output(&p, "reconstruct needs -o MESH (e.g. -o mesh.obj)")?;
    let quiet = p.switch("quiet");
    let frame = contours::frame_flag(p.value("frame"))?;
    // Check the flags before reading (a usage error should not wait for a big file), and that
    // the outputs can be written (a mistyped directory should not cost a whole run).
    params_from(&p, Params::default())?;
    let layout = anatomical_out::layout_from(&p)?;
    for option in ["output", "report", "contour-distances", "anatomical-mesh"] {
        if let Some(path) = p.value(option) {
            files::check_output(path)?;
        }
    }
    let (input, loaded) = contours::load_all(&p.positional, frame)?;
    let params = params_from(&p, loaded.session_params.unwrap_or_default())?;
    let input_format = loaded.format.name();
    let set = loaded.set;
    let outputs = Outputs {
        mesh: output.to_string(),
        format,
        report: p.value("report").map(str::to_string),
        distances: p.value("contour-distances").map(str::to_string),
        anatomical: p.value("anatomical-mesh").map(str::to_string),
    };
    let requested = each_surface::requested(params.surface.as_deref(), &set);
    // The surfaces that get an anatomical layout, checked before any run.
    let anatomical = match layout {
        Some(layout) => {
            let surfaces = requested
                .clone()
                .unwrap_or_else(|| vec![params.surface.clone()]);
            Some((layout, anatomical_out::check(input, &set, &surfaces)?))
        }
        None => None,
    };
    let run = Run {
        input,
        input_format,
        set: &set,
        quiet,
        apex_lids: p.value("lids") == Some("apex"),
        said: RefCell::new(Vec::new()),
        anatomical,
    };
    let inputs: Vec<&str> = p.positional.iter().map(String::as_str).collect();
    let every: Vec<Outputs> = match &requested {
        Some(surfaces) => surfaces
            .iter()
            .map(|s| match s {
                Some(s) => outputs.for_surface(s),
                None => outputs.clone(),
            })
            .collect(),
        None => vec![outputs.clone()],
    };
    let named: Vec<(&str, &str)> = every.iter().flat_map(Outputs::named).collect();
    files::check_distinct(&inputs, &named)?;
    match requested {
        None => run.surface(params, &outputs),
        Some(surfaces) => each_surface::run(&surfaces, |surface| {
            let mut params = params.clone();
            params.surface = surface.map(str::to_string);
            let outputs = match surface {
                Some(s) => outputs.for_surface(s),
                None => outputs.clone(),
            };
            run.surface(params, &outputs)
        }),
    }
}

/// Where one reconstruction's files go.
#[derive(Clone)]
struct Outputs {
    mesh: String,
    format: MeshFormat,
    report: Option<String>,
    distances: Option<String>,
    /// `--anatomical-mesh`.
    anatomical: Option<String>,
}

impl Outputs {
    /// The files written, each with the option that names it (for messages).
    fn named(&self) -> Vec<(&'static str, &str)> {
        let mut v = vec![("-o", self.mesh.as_str())];
        v.extend(self.report.as_deref().map(|r| ("--report", r)));
        v.extend(
            self.distances
                .as_deref()
                .map(|d| ("--contour-distances", d)),
        );
        v.extend(self.anatomical.as_deref().map(|a| ("--anatomical-mesh", a)));
        v
    }

    /// The same files with the surface's name before each extension (`mesh-LV_ENDO.obj`).
    fn for_surface(&self, surface: &str) -> Outputs {
        let name = |path: &str| each_surface::path_for(path, surface);
        Outputs {
            mesh: name(&self.mesh),
            format: self.format,
            report: self.report.as_deref().map(name),
            distances: self.distances.as_deref().map(name),
            anatomical: self.anatomical.as_deref().map(name),
        }
    }
}

/// What every surface's run of one file shares.
struct Run<'a> {
    input: &'a str,
    input_format: &'a str,
    set: &'a ContourSet,
    quiet: bool,
    /// `--lids apex`: each surface's apex lid at the file's apex landmark for that surface.
    apex_lids: bool,
    /// The stderr lines already printed: a note or warning about the whole file (the images'
    /// crossing gap, a unit conversion) is said once, not once per surface of `--surface all`.
    said: RefCell<Vec<String>>,
    /// `--anatomical-mesh`: the layout and the surfaces that can have it (checked before).
    anatomical: Option<(Layout, Vec<Option<String>>)>,
}

impl Run<'_> {
    /// Prints a note or warning line on stderr unless this run printed it already.
    fn say(&self, line: String) {
        let mut said = self.said.borrow_mut();
        if !said.contains(&line) {
            eprintln!("{line}");
            said.push(line);
        }
    }

    /// Reconstructs `params.surface` of the file and writes `out`'s files.
    fn surface(&self, mut params: Params, out: &Outputs) -> Result<(), CliError> {
        let (input, set, quiet) = (self.input, self.set, self.quiet);
        if self.apex_lids {
            let surface = params
                .surface
                .clone()
                .or_else(|| set.surfaces().first().cloned());
            params.lids = apex_lid(set, surface.as_deref()).ok_or_else(|| {
                CliError::input(
                    input,
                    CoreError::parse(0, "--lids apex needs an APEX_POINT landmark in the file"),
                )
            })?;
        }
        let output = out.mesh.as_str();
        // Warnings are printed after success; on failure the first one joins the single error line
        // (the contract: one line on stderr), since it may well be the cause.
        // Only the warnings about this surface's contours (and the file's): a biventricular file's
        // LV warnings have nothing to say about its RV.
        let file_warnings = set.warnings_for(params.surface.as_deref());
        let fail = |e: CoreError| classify(input, e).with_hint(&file_warnings);
        let started = Instant::now();
        let mut rec = Reconstruction::new(set, params.clone()).map_err(fail)?;
        // Step 0 builds the initial tube; the growth note, from its size, comes before the wait it
        // explains.
        rec.step().map_err(fail)?;
        if let (false, Some(note)) = (quiet, rec.growth_note()) {
            self.say(format!("heartmesh: note: {input}: {note}"));
        }
        rec.run().map_err(fail)?;
        let seconds = started.elapsed().as_secs_f64();

        // The load-time warnings name what the run leaves out; any it left out unnamed joins them.
        let mut warnings = file_warnings.clone();
        warnings.extend(set_aside::unannounced(rec.set_aside(), &file_warnings));
        let facts = report::Facts {
            input: file_name(input),
            input_format: self.input_format,
            output: file_name(output),
            params: &params,
            seconds,
            warnings: &warnings,
            time_frames: set.time_frames.as_ref(),
            coordinate_system: set.coordinate_system,
        };
        let mut rep = report::build(&rec, &facts);
        let anatomical = self.anatomical_of(&rec, &params, out, &mut rep);
        let comment = report::header_comment(&facts);
        let distances = report::vertex_distances(&rec);
        let point_data = Some(("distance", distances.as_slice()));
        let mesh_bytes = io::write_mesh(rec.mesh(), out.format, point_data, &comment)
            .map_err(|e| CliError::Failed(format!("{output}: {e}")))?;
        files::write(output, &mesh_bytes)?;
        if let Some(path) = out.distances.as_deref() {
            let cleaned = ContourSet {
                contours: rec.contours().to_vec(),
                ..ContourSet::default()
            };
            let d = rec.contour_distances();
            let csv = io::csv::write_csv(&cleaned, Some(&d.per_point))
                .map_err(|e| CliError::Failed(format!("{path}: {e}")))?;
            files::write(path, &csv)?;
        }
        if let Some(path) = out.report.as_deref() {
            let text = serde_json::to_string_pretty(&rep)
                .map_err(|e| CliError::Failed(format!("{path}: {e}")))?;
            files::write(path, format!("{text}\n").as_bytes())?;
        }
        // Written last: a layout that could not be built fails after the mesh and the report.
        if let (Some(path), Some(built)) = (out.anatomical.as_deref(), &anatomical) {
            let surface = rep["surface"].as_str().unwrap_or("the surface");
            match built {
                Ok(a) => anatomical_out::write(path, a, input, surface, set.coordinate_system)?,
                Err(why) => {
                    return Err(CliError::Failed(format!(
                        "{path}: no anatomical layout: {why}"
                    )))
                }
            }
        }
        if !quiet {
            for w in &warnings {
                self.say(contours::warning_line(input, w));
            }
            if params.keep_specks && !set_aside::found_in(set).is_empty() {
                self.say(format!(
                    "heartmesh: note: {input}: --keep-specks: the contours named above as left out \
                     are kept in the reconstruction"
                ));
            }
            if let Some(note) = asked_note(&rec.set_aside_distances()) {
                self.say(format!("heartmesh: note: {input}: {note}"));
            }
            if warnings
                .iter()
                .any(|w| slice_loops::is_second_loop_warning(w))
            {
                self.say(format!(
                    "heartmesh: note: {input}: {}",
                    if params.drop_second_loops {
                        "--drop-second-loops: the loops named above are left out of the \
                         reconstruction"
                    } else {
                        "--drop-second-loops leaves such loops out, so the surface follows each \
                         slice's main loop"
                    }
                ));
            }
            if let Some(note) = report::alignment_note(&rep) {
                self.say(format!("heartmesh: note: {input}: {note}"));
            }
            if let Some(note) = rec.valve_chord_note() {
                self.say(format!("heartmesh: note: {input}: {note}"));
            }
            if let Some(note) = rec.end_cap_note() {
                self.say(format!("heartmesh: note: {input}: {note}"));
            }
            if let Some(w) = rec.skipped_remesh_note() {
                self.say(format!("heartmesh: warning: {input}: {w}"));
            }
            if let Some(w) = report::self_intersection_warning(&rep) {
                self.say(format!("heartmesh: warning: {output}: {w}"));
            }
            outln!("{}", report::summary(output, &rep));
            if let (Some(path), Some(Ok(a))) = (out.anatomical.as_deref(), &anatomical) {
                outln!("{}", anatomical_out::summary_line(path, a));
            }
        }
        Ok(())
    }
}

impl Run<'_> {
    /// The anatomical layout of a finished run when one was asked for and its surface can have
    /// one (added to `rep` either way); None when none is to be written for this surface.
    fn anatomical_of(
        &self,
        rec: &Reconstruction,
        params: &Params,
        out: &Outputs,
        rep: &mut serde_json::Value,
    ) -> Option<Result<Anatomical, String>> {
        let (layout, fit) = self.anatomical.as_ref()?;
        let path = out.anatomical.as_deref()?;
        if !fit.contains(&params.surface) {
            if !self.quiet {
                let surface = params.surface.as_deref().unwrap_or("this surface");
                self.say(anatomical_out::skipped_note(self.input, surface));
            }
            return None;
        }
        let built = anatomical_out::build(rec, self.set, params.surface.as_deref(), *layout);
        anatomical_out::add_to_report(rep, path, &built);
        Some(built)
    }
}

/// Parameters from the flags on top of `base` (the defaults, or a session's parameters); every
/// numeric flag maps onto `Params::set` (dashes to underscores), which checks the range.
pub(crate) fn params_from(p: &Parsed, base: Params) -> Result<Params, CliError> {
    if p.value("attractors").is_some() && p.value("attractor-spacing").is_some() {
        return Err(CliError::usage(
            "give either --attractors or --attractor-spacing, not both",
        ));
    }
    let mut params = base;
    for (name, value) in &p.values {
        let key = name.replace('-', "_");
        if Params::schema().iter().any(|s| s.name == key) {
            let v: f64 = value
                .trim()
                .parse()
                .map_err(|_| CliError::usage(format!("--{name}: {value:?} is not a number")))?;
            params.set(&key, v).map_err(CliError::param)?;
        }
    }
    // `apex` is resolved once the file is read (it needs the APEX_POINT landmark).
    if let Some(l) = p.value("lids").filter(|l| *l != "apex") {
        params.set_lids(l).map_err(CliError::param)?;
    }
    if let Some(m) = p.value("smoothing-method") {
        params.set_smoothing_method(m).map_err(CliError::param)?;
    }
    if let Some(s) = p.value("surface") {
        params.surface = Some(s.to_string());
    }
    if p.switch("no-soften-conflicts") {
        params.soften_conflicts = false;
    }
    if p.switch("align-slices") {
        params.align_slices = true;
    }
    params.align_through_plane = through_plane_switch(p, params.align_slices)?;
    if p.switch("drop-second-loops") {
        params.drop_second_loops = true;
    }
    if let Some(on) = apex_floor_switch(p)? {
        params.apex_floor = on;
    }
    if p.switch("keep-specks") {
        params.keep_specks = true;
    }
    if let Some(m) = p.value("end-caps") {
        params.set_end_caps(m).map_err(CliError::param)?;
    }
    add_leave_out(p, &mut params);
    params.validate().map_err(CliError::param)?;
    Ok(params)
}

/// `--leave-out ID[,ID...]` (repeatable) added to `params.leave_out` (a session's list): the
/// flags say what else to leave out. Empty ids stay, for `Params::validate` to refuse by name.
pub(crate) fn add_leave_out(p: &Parsed, params: &mut Params) {
    for id in p.values_of("leave-out").flat_map(|v| v.split(',')) {
        let id = id.trim().to_string();
        if !params.leave_out.contains(&id) {
            params.leave_out.push(id);
        }
    }
}

/// The note naming the contours `--leave-out` left out of this surface, each with how far the
/// finished mesh passes from it (None: none of them is this surface's), so that a run says what
/// it did not use as the warnings do for the rules', and whether that contour disagreed with the
/// rest (its distance is then a held-out slice's).
pub(crate) fn asked_note(list: &[SetAsideDistance]) -> Option<String> {
    let named: Vec<String> = list
        .iter()
        .filter(|d| d.contour.why == set_aside::Why::ByUser)
        .map(|d| {
            cite(
                &d.contour.id,
                d.contour.line,
                &format!(
                    "the mesh {:.2} mm from it on average, {:.2} mm at most",
                    d.mean, d.max
                ),
            )
        })
        .collect();
    let verb = if named.len() == 1 { "is" } else { "are" };
    (!named.is_empty()).then(|| {
        format!(
            "--leave-out: {} {verb} left out of the reconstruction",
            named.join(", ")
        )
    })
}

/// `--apex-floor` / `--no-apex-floor`: Some(on) when either is given (None: the base's value, the
/// default or a session's). The floor is on by default (session 14), so `--apex-floor` only
/// matters over a session saved without it; both at once is a usage error rather than one
/// silently winning.
pub(crate) fn apex_floor_switch(p: &Parsed) -> Result<Option<bool>, CliError> {
    match (p.switch("apex-floor"), p.switch("no-apex-floor")) {
        (true, true) => Err(CliError::usage(
            "give either --apex-floor or --no-apex-floor, not both",
        )),
        (true, false) => Ok(Some(true)),
        (false, true) => Ok(Some(false)),
        (false, false) => Ok(None),
    }
}

/// Whether the alignment moves slices along their normals: unless `--align-in-plane-only`,
/// which only means something with the breath-hold alignment on (`aligning`): alone it is a
/// usage error rather than silently nothing.
pub(crate) fn through_plane_switch(p: &Parsed, aligning: bool) -> Result<bool, CliError> {
    let in_plane = p.switch("align-in-plane-only");
    if in_plane && !aligning {
        return Err(CliError::usage(
            "--align-in-plane-only needs --align-slices (it restricts the breath-hold alignment)",
        ));
    }
    Ok(!in_plane)
}

/// The apex lid at the file's apex landmark (biv-me guide points carry one); the base lid stays
/// automatic. Newer biv-me files mark the endocardial and epicardial apex apart
/// (`APEX_ENDO_POINT`, `APEX_EPI_POINT`, several millimetres apart across the wall): each
/// surface takes its own, then the plain `APEX_POINT`, then either.
pub(crate) fn apex_lid(set: &ContourSet, surface: Option<&str>) -> Option<LidMode> {
    let own = match surface {
        Some(s) if s.ends_with("_EPI") || s == "EPI" => "APEX_EPI_POINT",
        _ => "APEX_ENDO_POINT",
    };
    let apex = [own, "APEX_POINT", "APEX_ENDO_POINT", "APEX_EPI_POINT"]
        .iter()
        .find_map(|want| set.landmarks.iter().find(|(name, _)| name == want))
        .map(|(_, p)| *p)?;
    Some(LidMode::Explicit {
        apex: Some(apex),
        base: None,
    })
}

/// Input problems exit with 2 and name the file; numerical failures are the tool's (exit 1).
pub(crate) fn classify(input: &str, e: CoreError) -> CliError {
    match e {
        CoreError::Numerical(_) | CoreError::InvalidMesh(_) | CoreError::Io(_) => {
            CliError::Failed(format!("{input}: reconstruction failed: {e}"))
        }
        CoreError::ParamOutOfRange { .. } | CoreError::ParamInvalid { .. } => CliError::param(e),
        _ => CliError::input(input, e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parsed(a: &[&str]) -> Parsed {
        let v: Vec<String> = a.iter().map(|s| s.to_string()).collect();
        parse_with_params(&v, VALUE_FLAGS, SWITCHES, &[]).unwrap()
    }

    fn params_from_default(p: &Parsed) -> Result<Params, CliError> {
        params_from(p, Params::default())
    }

    /// Each surface's own apex landmark first, then the plain one, then either.
    #[test]
    fn apex_lid_takes_the_surfaces_own_apex_landmark() {
        use heartmesh_core::geometry::v3;
        let at = |set: &ContourSet, s: Option<&str>| match apex_lid(set, s) {
            Some(LidMode::Explicit { apex: Some(p), .. }) => Some(p.x),
            _ => None,
        };
        let mut set = ContourSet::default();
        assert_eq!(at(&set, Some("LV_ENDO")), None);
        set.landmarks
            .push(("APEX_EPI_POINT".into(), v3(3.0, 0.0, 0.0)));
        assert_eq!(at(&set, Some("LV_ENDO")), Some(3.0));
        set.landmarks.push(("APEX_POINT".into(), v3(1.0, 0.0, 0.0)));
        assert_eq!(at(&set, Some("LV_ENDO")), Some(1.0));
        assert_eq!(at(&set, Some("LV_EPI")), Some(3.0));
        set.landmarks
            .push(("APEX_ENDO_POINT".into(), v3(2.0, 0.0, 0.0)));
        assert_eq!(at(&set, Some("RV_ENDO")), Some(2.0));
        assert_eq!(at(&set, None), Some(2.0));
        assert_eq!(at(&set, Some("RV_EPI")), Some(3.0));
    }

    #[test]
    fn flags_map_onto_params() {
        let p = params_from_default(&parsed(&[
            "--iterations",
            "40",
            "--lambda=1e3",
            "--attractor-spacing",
            "2.5",
            "--target-reduction",
            "0.5",
            "--lids",
            "none",
            "--surface",
            "LV_EPI",
            "--smoothing-method",
            "taubin",
        ]))
        .unwrap();
        assert_eq!(p.iterations, 40);
        assert_eq!(p.smoothing, heartmesh_core::params::SmoothingMethod::Taubin);
        assert_eq!(p.lambda, 1e3);
        assert_eq!(p.attractors, heartmesh_core::AttractorMode::SpacingMm(2.5));
        assert_eq!(p.target_reduction, 0.5);
        assert_eq!(p.lids, heartmesh_core::LidMode::None);
        assert_eq!(p.surface.as_deref(), Some("LV_EPI"));
        assert!(p.soften_conflicts);
        let p = params_from_default(&parsed(&["--no-soften-conflicts"])).unwrap();
        assert!(!p.soften_conflicts);
        assert!(!p.align_slices);
        let p = params_from_default(&parsed(&["--align-slices"])).unwrap();
        assert!(p.align_slices);
        assert!(p.align_through_plane);
        let p = params_from_default(&parsed(&["--align-slices", "--align-in-plane-only"])).unwrap();
        assert!(p.align_slices && !p.align_through_plane);
        let e = params_from_default(&parsed(&["--align-in-plane-only"])).unwrap_err();
        assert!(
            matches!(&e, crate::error::CliError::Usage(m) if m.contains("needs --align-slices")),
            "{e:?}"
        );
        // The apex floor is on by default; --no-apex-floor turns it off, --apex-floor is still
        // accepted (a no-op at the defaults, on over a session without it), both are refused.
        assert!(params_from_default(&parsed(&[])).unwrap().apex_floor);
        assert!(
            params_from_default(&parsed(&["--apex-floor"]))
                .unwrap()
                .apex_floor
        );
        assert!(
            !params_from_default(&parsed(&["--no-apex-floor"]))
                .unwrap()
                .apex_floor
        );
        let off = Params {
            apex_floor: false,
            ..Params::default()
        };
        assert!(
            params_from(&parsed(&["--apex-floor"]), off.clone())
                .unwrap()
                .apex_floor
        );
        assert!(!params_from(&parsed(&[]), off).unwrap().apex_floor);
        let e = params_from_default(&parsed(&["--apex-floor", "--no-apex-floor"])).unwrap_err();
        assert!(
            matches!(&e, crate::error::CliError::Usage(m) if m.contains("not both")),
            "{e:?}"
        );
        for (flag, mode) in [
            ("auto", heartmesh_core::EndCapMode::Auto),
            ("off", heartmesh_core::EndCapMode::Off),
        ] {
            let p = params_from_default(&parsed(&["--end-caps", flag])).unwrap();
            assert_eq!(p.end_caps, mode);
        }
    }

    #[test]
    fn bad_values() {
        let e = params_from_default(&parsed(&["--beta", "2"])).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(e.message().contains("allowed 0.01 to 1"), "{}", e.message());
        let e = params_from_default(&parsed(&["--beta", "x"])).unwrap_err();
        assert!(e.message().contains("not a number"), "{}", e.message());
        let e = params_from_default(&parsed(&[
            "--attractors",
            "200",
            "--attractor-spacing",
            "2",
        ]));
        assert!(e.is_err());
        let e = params_from_default(&parsed(&["--lids", "maybe"])).unwrap_err();
        assert!(e.message().contains("auto, none"), "{}", e.message());
        let e = params_from_default(&parsed(&["--smoothing-method", "gauss"])).unwrap_err();
        assert!(e.message().contains("taubin"), "{}", e.message());
        let e = params_from_default(&parsed(&["--end-caps", "on"])).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(e.message().contains("auto, off"), "{}", e.message());
        // Taubin with lambda 0.8 would amplify the highest frequencies: refused.
        let e = params_from_default(&parsed(&[
            "--smoothing-method",
            "taubin",
            "--smoothing-factor",
            "0.8",
        ]));
        assert!(e.is_err());
        // Twicing above factor 0.5 could amplify the highest frequency (gain -3): refused.
        for (factor, ok) in [("0.5", true), ("0.6", false)] {
            let p = params_from_default(&parsed(&[
                "--smoothing-method",
                "laplacian-twicing",
                "--smoothing-factor",
                factor,
            ]));
            assert_eq!(p.is_ok(), ok, "factor {factor}");
        }
    }
}
