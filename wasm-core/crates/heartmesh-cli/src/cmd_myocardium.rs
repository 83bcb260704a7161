//! `heartmesh myocardium CONTOURS -o WALL`: the LV myocardium as one closed solid, for volume
//! meshing, simulation and 3D printing. The two surfaces are reconstructed as `reconstruct` would
//! (same parameters, same warnings), then cut at the base and joined (core `mesh::wall`).

use std::time::Instant;

use heartmesh_core::contours::biv_epi::{self, BIV_EPI};
use heartmesh_core::contours::CoordinateSystem;
use heartmesh_core::io;
use heartmesh_core::mesh::hex_wall;
use heartmesh_core::mesh::wall::{self, Wall};
use heartmesh_core::metrics::compare::common_basal_plane_all;
use heartmesh_core::metrics::segments::{self as aha, Segments};
use heartmesh_core::metrics::{bullseye, septum};
use heartmesh_core::pipeline::Reconstruction;
use heartmesh_core::{ContourSet, CoreError, Params};
use serde_json::{json, Value};

use crate::cmd_convert::file_name;
use crate::cmd_reconstruct::{
    apex_lid, asked_note, classify, mesh_output, params_from, parse_with_inputs,
};
use crate::contours;
use crate::error::CliError;
use crate::files;
use crate::hex_out;
use crate::report;

pub const USAGE: &str =
    "heartmesh myocardium CONTOURS [VIEWS...] -o WALL.vtk [--report REPORT.json]
    [--endo LV_ENDO] [--epi LV_EPI] [--biventricular [--rv-endo RV_ENDO]]
    [--min-thickness 1|off] [--frame N|LABEL] [--bullseye SEGMENTS.svg]
    [--hex-mesh HEX.vtk [--hex-layout 24x48] [--layers 3] [--helix-angles 60,-60]]
    [reconstruct's parameter options: --iterations ... --end-caps ... --align-slices ...]
    [--ascii] [--quiet]
  The LV myocardium as one closed solid (volume meshing with gmsh or TetGen, simulation, 3D
  printing): the endocardium and the epicardium reconstructed at the same parameters, both cut
  at the base, the plane across the long axis at the most basal short-axis slice both were
  drawn on, and joined there by a flat ring. The solid faces outwards (the endocardium into
  the cavity). Its triangles are labelled by region, 1 epicardium, 2 endocardium, 3 base:
  cell data `region` in PLY, VTK and VTP, groups of those names in OBJ, none in STL; every
  vertex carries the wall thickness (mm, to the other surface) as point data `thickness`.
  Prints the wall volume, the myocardial mass below the base (1.05 g/ml) and the cavity volume
  below the base; REPORT.json adds the base plane, the thickness, the regions and each
  surface's reconstruct report (under surfaces). Where the endocardium passes through the
  epicardium, or comes closer to it than --min-thickness MM (default 1; a wall thinner than the
  reconstructions' error: a thinned apex, images drawn on different breath-holds), those
  endocardial vertices are first moved that far under it, then any epicardial vertex still
  that close out over it, so the solid stays valid; a note says how many moved and how far
  (the report's endocardium_moved, epicardium_moved); --min-thickness off leaves the surfaces
  as reconstructed (a warning then counts any crossings). The report's
  quality.folded_edges leaves out the rim, where the base meets the walls at a right angle.
  --endo/--epi: other surface names of the file (default LV_ENDO and LV_EPI).
  --biventricular: both ventricles' myocardium as one solid, the biventricular epicardium
  (--epi, default BIV_EPI: the file's LV_EPI and RV_EPI curves joined, see reconstruct) minus
  the LV cavity (--endo) and the RV cavity (--rv-endo, default RV_ENDO), cut at the most basal
  short-axis slice all three were drawn on; regions 1 epicardium, 2 lv_endocardium,
  3 rv_endocardium, 4 base; the cavities are also kept --min-thickness apart (the septum).
  AHA segments (LV wall): REPORT.json's segments give the wall thickness (area-weighted mean,
  min, max, mm) in each of the 17 segments of the AHA model, placed round the long axis from the
  septum's direction (the file's RV_INSERT landmarks, else its RV contours' centre; the file's
  coordinates must be a right-handed patient frame, DICOM LPS or RAS); the levels are thirds of
  the cavity below the base, segment 17 the wall beyond the cavity's lowest point.
  --hex-mesh: the LV wall also as a volume mesh for finite-element simulation, layers of
  hexahedra (wedges round the apex) between the anatomical layouts of the two surfaces (see
  reconstruct --anatomical-mesh), both laid out on the wall's base plane from one septum: a VTK
  unstructured grid with point data transmural (0 endocardium - 1 epicardium), longitudinal
  (0 apex - 1 base), circumferential_deg (from the septum towards anterior) and cell data
  aha_segment (1-17), and the unit vectors fibre (rule-based: the helix angle turns from
  +60 degrees at the endocardium to -60 at the epicardium, linear through the wall, positive a
  right-handed helix; --helix-angles ENDO,EPI sets them) and sheet (transmural);
  --hex-layout RINGSxPOINTS (default 24x48), --layers 1-20 (default 3);
  both surfaces are laid out on the endocardium's rays, so each column of cells runs straight
  through the wall; where the epicardium lies less than --min-thickness outside the endocardium
  along a ray, the endocardial vertex moves in to keep that thickness (as the solid's does; the
  report's hex_mesh.endocardium_moved), and a warning counts any cell still inverted; the report's hex_mesh gives the counts, volume and the
  smallest scaled Jacobian. Refused before any run with --biventricular or for a file without
  RV landmarks or contours.
  --bullseye: those segments drawn as the AHA bullseye (SVG), anterior up, septum left.";

/// Options of this command only that take a value.
const VALUE_FLAGS: &[&str] = &[
    "output",
    "report",
    "endo",
    "epi",
    "rv-endo",
    "frame",
    "min-thickness",
    "bullseye",
    "hex-mesh",
    "hex-layout",
    "layers",
    "helix-angles",
];

/// The default of --min-thickness (mm): a wall this thin is under any reconstruction's error,
/// and far under the thinnest real myocardium (2-3 mm at a thinned apex).
const MIN_THICKNESS_MM: f64 = 1.0;

/// --min-thickness: a depth in mm (0 to 10), or off.
fn min_thickness(value: Option<&str>) -> Result<Option<f64>, CliError> {
    match value {
        None => Ok(Some(MIN_THICKNESS_MM)),
        Some(v) if v.eq_ignore_ascii_case("off") => Ok(None),
        Some(v) => match v.parse::<f64>() {
            Ok(mm) if mm.is_finite() && (0.0..=10.0).contains(&mm) => Ok(Some(mm)),
            _ => Err(CliError::usage(format!(
                "--min-thickness {v}: give a thickness in mm from 0 to 10, or off"
            ))),
        },
    }
}

/// Switches of this command only.
const SWITCHES: &[&str] = &["quiet", "ascii", "biventricular"];

/// One surface's finished run.
struct Surface {
    name: String,
    rec: Reconstruction,
    seconds: f64,
    warnings: Vec<String>,
}

pub fn run(args: &[String]) -> Result<(), CliError> {
    let p = parse_with_inputs(
        args,
        VALUE_FLAGS,
        SWITCHES,
        &[("-o", "output"), ("-q", "quiet")],
        "myocardium needs a contour file with LV endo- and epicardial contours",
    )?;
    if p.value("surface").is_some() {
        return Err(CliError::usage(
            "myocardium takes --endo and --epi (the two surfaces of the wall), not --surface",
        ));
    }
    let (output, format) = mesh_output(&p, "myocardium needs -o WALL (e.g. -o wall.vtk)")?;
    let quiet = p.switch("quiet");
    let min_thickness = min_thickness(p.value("min-thickness"))?;
    let frame = contours::frame_flag(p.value("frame"))?;
    params_from(&p, Params::default())?;
    let report_path = p.value("report");
    let bullseye_path = p.value("bullseye");
    let hex = hex_out::request_from(&p, p.switch("biventricular"))?;
    let hex_path = hex.as_ref().map(|h| h.path.as_str());
    let mut named = vec![("-o", output)];
    for path in [Some(output), report_path, bullseye_path, hex_path]
        .into_iter()
        .flatten()
    {
        files::check_output(path)?;
    }
    named.extend(report_path.map(|r| ("--report", r)));
    named.extend(bullseye_path.map(|r| ("--bullseye", r)));
    named.extend(hex_path.map(|r| ("--hex-mesh", r)));
    let inputs: Vec<&str> = p.positional.iter().map(String::as_str).collect();
    files::check_distinct(&inputs, &named)?;

    let (input, loaded) = contours::load_all(&p.positional, frame)?;
    let params = params_from(&p, loaded.session_params.unwrap_or_default())?;
    let set = loaded.set;
    let biventricular = p.switch("biventricular");
    if biventricular && bullseye_path.is_some() {
        return Err(CliError::usage(
            "--bullseye draws the LV wall's 17 segments; leave out --biventricular",
        ));
    }
    if bullseye_path.is_some() && !septum::said(&set) {
        return Err(CliError::input(
            input,
            CoreError::parse(
                0,
                "--bullseye needs the septum's direction: the file has no RV_INSERT landmarks \
                 and no RV contours",
            ),
        ));
    }
    if hex.is_some() {
        hex_out::check(input, &set)?;
    }
    if !biventricular && p.value("rv-endo").is_some() {
        return Err(CliError::usage(
            "--rv-endo names the RV cavity of a --biventricular wall; add --biventricular",
        ));
    }
    let endo_name = p.value("endo").unwrap_or("LV_ENDO");
    let epi_name = p
        .value("epi")
        .unwrap_or(if biventricular { BIV_EPI } else { "LV_EPI" });
    let mut names = vec![("--endo", endo_name), ("--epi", epi_name)];
    if biventricular {
        names.push(("--rv-endo", p.value("rv-endo").unwrap_or("RV_ENDO")));
    }
    for (i, (flag, name)) in names.iter().enumerate() {
        if let Some((other, _)) = names[..i]
            .iter()
            .find(|(_, n)| n.eq_ignore_ascii_case(name))
        {
            return Err(CliError::usage(format!(
                "{other} and {flag} name the same surface ({name})"
            )));
        }
    }
    let mut available = set.surfaces();
    if biv_epi::available(&set) {
        available.push(BIV_EPI.to_string());
    }
    let what = if biventricular {
        "a biventricular myocardium needs"
    } else {
        "a myocardium needs"
    };
    let needed: Vec<&str> = names.iter().map(|(_, n)| *n).collect();
    for &wanted in &needed {
        if !available.iter().any(|s| s.eq_ignore_ascii_case(wanted)) {
            let listed = if available.is_empty() {
                "its contours name no surface".to_string()
            } else {
                format!("its surfaces: {}", available.join(", "))
            };
            return Err(CliError::input(
                input,
                CoreError::parse(
                    0,
                    format!(
                        "{what} {} contours; the file has no {} ({listed})",
                        and_list(&needed),
                        biv_epi::requested_name(wanted)
                    ),
                ),
            ));
        }
    }

    let started = Instant::now();
    let surfaces = needed
        .iter()
        .map(|name| reconstruct(input, &set, &params, name, p.value("lids")))
        .collect::<Result<Vec<_>, _>>()?;
    let recs: Vec<&Reconstruction> = surfaces.iter().map(|s| &s.rec).collect();
    let base = common_basal_plane_all(&recs)
        .map_err(|e| CliError::Failed(format!("{input}: no base plane: {e}")))?;
    let mesh = |k: usize| surfaces[k].rec.mesh();
    let wall = if biventricular {
        wall::build_biventricular(mesh(0), mesh(2), mesh(1), &base, min_thickness)
    } else {
        wall::build_wall(mesh(0), mesh(1), &base, min_thickness)
    }
    .map_err(|e| CliError::Failed(format!("{input}: the myocardium wall: {e}")))?;
    let regional = (!biventricular).then(|| aha::of_file(&set, &wall));
    let hexes = hex.as_ref().map(|r| {
        hex_out::build(
            &set,
            &surfaces[0].rec,
            &surfaces[1].rec,
            &base,
            r,
            min_thickness,
        )
    });
    let seconds = started.elapsed().as_secs_f64();

    let labels: Vec<String> = wall
        .region_names
        .iter()
        .enumerate()
        .map(|(k, n)| format!("{} {n}", k + 1))
        .collect();
    let comment = io::tagged_comment(
        set.coordinate_system,
        &format!(
            "{} of {} ({}); units mm, the contour file's coordinates; region {}",
            kind(&wall),
            file_name(input),
            needed.join(" + "),
            labels.join(", ")
        ),
    );
    let bytes = wall
        .write(format, &comment)
        .map_err(|e| CliError::Failed(format!("{output}: {e}")))?;
    files::write(output, &bytes)?;
    let mut rep = build_report(
        &Context {
            input,
            input_format: loaded.format.name(),
            output,
            params: &params,
            min_thickness,
            seconds,
            coordinate_system: set.coordinate_system,
        },
        &wall,
        &surfaces,
        regional.as_ref(),
    );
    if let (Some(r), Some(built)) = (&hex, &hexes) {
        hex_out::add_to_report(&mut rep, &r.path, built);
    }
    if let Some(path) = bullseye_path {
        match &regional {
            Some(Ok(segments)) => {
                let title = format!("{} ({})", file_name(input), needed.join(" + "));
                files::write(path, bullseye::svg(segments, &title).as_bytes())?;
            }
            Some(Err(why)) => {
                return Err(CliError::Failed(format!("{path}: no segments: {why}")));
            }
            None => {}
        }
    }
    if let Some(path) = report_path {
        let text = serde_json::to_string_pretty(&rep)
            .map_err(|e| CliError::Failed(format!("{path}: {e}")))?;
        files::write(path, format!("{text}\n").as_bytes())?;
    }
    // Written after the wall and the report: cells that cannot be laid out fail last.
    if let (Some(r), Some(built)) = (&hex, &hexes) {
        match built {
            Ok(h) => {
                let comment = io::tagged_comment(
                    set.coordinate_system,
                    &hex_wall::comment(h, input, endo_name, epi_name),
                );
                files::write(&r.path, &h.to_vtk(&comment))?;
            }
            Err(why) => {
                return Err(CliError::Failed(format!(
                    "{}: no hexahedral mesh: {why}",
                    r.path
                )))
            }
        }
    }
    if !quiet {
        let mut said: Vec<String> = Vec::new();
        for s in &surfaces {
            for w in &s.warnings {
                let line = contours::warning_line(input, w);
                if !said.contains(&line) {
                    eprintln!("{line}");
                    said.push(line);
                }
            }
            // Each surface's contours left out by hand, with how far its mesh passes from them.
            if let Some(note) = asked_note(&s.rec.set_aside_distances()) {
                eprintln!("heartmesh: note: {input}: {}: {note}", s.name);
            }
            if let Some(note) = s.rec.skipped_remesh_note() {
                eprintln!("heartmesh: warning: {input}: {}: {note}", s.name);
            }
        }
        for (moved, what, how) in [
            (
                wall.pushed,
                "endocardial",
                if biventricular {
                    "under the epicardium and apart from the other cavity"
                } else {
                    "under the epicardium"
                },
            ),
            (wall.epi_pushed, "epicardial", "out over the endocardium"),
        ] {
            if moved.vertices == 0 {
                continue;
            }
            let n = moved.vertices;
            let (noun, verb) = if n == 1 {
                ("vertex", "was")
            } else {
                ("vertices", "were")
            };
            eprintln!(
                "heartmesh: note: {output}: {n} {what} {noun} {verb} moved up to {:.2} mm {how} \
                 to keep the wall at least {} mm thick (--min-thickness off leaves the surfaces \
                 as reconstructed)",
                moved.max_mm,
                min_thickness.unwrap_or(0.0)
            );
        }
        for note in &wall.notes {
            eprintln!("heartmesh: note: {output}: {note}");
        }
        if matches!(&regional, Some(Err(why)) if why == aha::ENCLOSES_RV) {
            eprintln!(
                "heartmesh: warning: {output}: {epi_name} encloses the RV cavity (a \
                 biventricular epicardium): this wall holds the RV cavity as muscle; \
                 --biventricular cuts both cavities out of it"
            );
        }
        for c in &wall.crossings {
            let [a, b] = c.regions.map(|r| r.replace('_', " "));
            let what = if a == b {
                format!("the {a} passes through itself")
            } else {
                format!("the {b} passes through the {a}")
            };
            eprintln!(
                "heartmesh: warning: {output}: {what} ({} crossing triangle pairs): the wall is \
                 thinner there than the reconstructions' error; volume meshers will refuse it",
                c.pairs
            );
        }
        outln!("{}", summary(output, &wall));
        if let (Some(r), Some(Ok(h))) = (&hex, &hexes) {
            if let Some(w) = hex_out::inverted_warning(&r.path, h) {
                eprintln!("{w}");
            }
            outln!("{}", hex_out::summary_line(&r.path, h));
        }
    }
    Ok(())
}

/// Reconstructs one surface of the file, as `reconstruct --surface NAME` would.
fn reconstruct(
    input: &str,
    set: &ContourSet,
    params: &Params,
    name: &str,
    lids: Option<&str>,
) -> Result<Surface, CliError> {
    let mut params = params.clone();
    params.surface = Some(name.to_string());
    if lids == Some("apex") {
        params.lids = apex_lid(set, Some(name)).ok_or_else(|| {
            CliError::input(
                input,
                CoreError::parse(0, "--lids apex needs an APEX_POINT landmark in the file"),
            )
        })?;
    }
    let warnings = set.warnings_for(Some(name));
    let fail = |e: CoreError| classify(input, e).with_hint(&warnings);
    let started = Instant::now();
    let mut rec = Reconstruction::new(set, params).map_err(fail)?;
    rec.run().map_err(fail)?;
    Ok(Surface {
        name: name.to_string(),
        rec,
        seconds: started.elapsed().as_secs_f64(),
        warnings,
    })
}

/// What the report says besides the wall and the surfaces.
struct Context<'a> {
    input: &'a str,
    input_format: &'a str,
    output: &'a str,
    params: &'a Params,
    min_thickness: Option<f64>,
    seconds: f64,
    coordinate_system: Option<CoordinateSystem>,
}

fn build_report(
    c: &Context,
    wall: &Wall,
    surfaces: &[Surface],
    regional: Option<&Result<Segments, String>>,
) -> Value {
    let Context {
        input,
        input_format,
        output,
        params,
        ..
    } = *c;
    let mut rep = report::mesh_facts(&wall.mesh);
    if let Some(q) = rep.get_mut("quality").and_then(Value::as_object_mut) {
        q.insert("folded_edges".into(), json!(wall.folded_edges_off_rim()));
    }
    let mut per_surface = serde_json::Map::new();
    for s in surfaces {
        let facts = report::Facts {
            input: file_name(input),
            input_format,
            output: file_name(output),
            params: &{
                let mut p = params.clone();
                p.surface = Some(s.name.clone());
                p
            },
            seconds: s.seconds,
            warnings: &s.warnings,
            time_frames: None,
            coordinate_system: c.coordinate_system,
        };
        per_surface.insert(s.name.clone(), report::build(&s.rec, &facts));
    }
    for (key, value) in [
        ("version", json!(heartmesh_core::VERSION)),
        ("input", json!(file_name(input))),
        ("input_format", json!(input_format)),
        (
            "coordinate_system",
            json!(c.coordinate_system.map(CoordinateSystem::name)),
        ),
        ("output", json!(file_name(output))),
        ("seconds", json!(c.seconds)),
        ("parameters", report::parameters(params)),
        ("surfaces", Value::Object(per_surface)),
    ] {
        rep.insert(key.to_string(), value);
    }
    if let Ok(Value::Object(summary)) = serde_json::to_value(wall.summary(c.min_thickness)) {
        rep.extend(summary);
    }
    match regional {
        Some(Ok(segments)) => {
            rep.insert("segments".into(), json!(segments));
        }
        Some(Err(why)) => {
            rep.insert("segments".into(), Value::Null);
            rep.insert("segments_note".into(), json!(why));
        }
        None => {}
    }
    Value::Object(rep)
}

/// The line printed after a successful run.
fn summary(output: &str, wall: &Wall) -> String {
    let s = wall.summary(None);
    let cavities = match s.cavities.as_slice() {
        [lv, rv] => format!(
            "cavities LV {:.1} ml, RV {:.1} ml below the base",
            lv.volume_ml, rv.volume_ml
        ),
        _ => format!("cavity {:.1} ml below the base", s.cavity_volume_ml),
    };
    format!(
        "{output}: {}, {} vertices, {} triangles, closed; wall {:.1} ml (mass {:.1} g below the \
         base), {cavities}, thickness mean {:.1} mm",
        kind(wall),
        wall.mesh.positions.len(),
        wall.mesh.triangles.len(),
        s.wall_volume_ml,
        s.myocardial_mass_g,
        s.thickness_mm.mean
    )
}

/// "A and B", "A, B and C".
fn and_list(names: &[&str]) -> String {
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => names.join(""),
    }
}

/// What the solid is, in words.
fn kind(wall: &Wall) -> &'static str {
    if wall.cavities_ml.len() == 2 {
        "biventricular myocardium"
    } else {
        "LV myocardium wall"
    }
}
