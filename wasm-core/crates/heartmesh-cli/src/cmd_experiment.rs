//! `heartmesh experiment KIND TRUTH... -o OUT_DIR`: the validation experiments of Villard, Grau &
//! Zacur (J. Imaging 2018, section 3) with one command each; writes `OUT_DIR/KIND.csv` (one row per
//! run) and `OUT_DIR/KIND.svg` (the plot). The experiments themselves live in
//! `heartmesh_core::sim::experiment` so the browser runs the same code.

use std::path::Path;
use std::time::Instant;

use heartmesh_core::sim::cavity::rv_cavity;
use heartmesh_core::sim::experiment::{to_csv, Design, Experiment, Progress, Row};
use heartmesh_core::sim::experiment_design::Subject;
use heartmesh_core::sim::planes::{anatomical_axis, PAPER_LAX_ANGLES_DEG};
use heartmesh_core::sim::population::{generate, Base, Member, Plan, Source};
use heartmesh_core::sim::shapes::ParametricLv;
use heartmesh_core::sim::AcquisitionSpec;
use heartmesh_core::Params;

use crate::args::{parse, Parsed, Spec};
use crate::cmd_experiment_plot::plot;
use crate::cmd_simulate::read_surface;
use crate::error::CliError;
use crate::files;

pub const USAGE: &str =
    "heartmesh experiment sax-count|lax-count|misalignment|sweep|population TRUTH... -o OUT_DIR
    [--from N] [--to N] [--step N] [--lax K] [--sax N] [--levels S:T,...] [--seeds N]
    [--count N] [--seed N]
    [--lambda LIST] [--smoothing-iterations LIST] [--target-reduction LIST]
    [--attractor-spacing LIST] [--iterations N] [--align-slices [--align-in-plane-only]] [--end-caps auto|off]
    [--no-apex-floor] [--smoothing-method NAME] [--tag NAME] [--quiet]
  Slices each TRUTH like a CMR acquisition, reconstructs and measures against the truth (clipped
  at the most basal SAX plane); writes OUT_DIR/KIND.csv (one row per run: settings, distances in
  mm both ways, Hausdorff, volumes in ml, contour-to-mesh, seconds) and OUT_DIR/KIND.svg.
  TRUTH: a surface file (obj, stl, ply, vtk, vtp), `parametric-lv` (built-in LV with a regional
  bulge), or RV.obj@LV.obj (planned on LV.obj's long axis, one four-chamber-like LAX: for an RV;
  RV.obj+SEPTUM.obj@LV.obj: an RV free wall closed by the part of SEPTUM.obj it faces).
  sax-count: SAX --from 2 --to 15 (--step 1), LAX fixed (--lax, default 3; 1 for RV@LV).
  lax-count: LAX --from 1 --to 8 at 0, 90, 45, 135, 22.5, 157.5, 112.5, 67.5 degrees, --sax 4.
  misalignment: --levels 0:0,1:1,2:2,3:3,4:4 (max shift mm : max tilt degrees), --seeds 5.
  misalignment and population: --lax K gives every shape K long-axis views (default: 3 for an
  LV, 1 for RV@LV; 0: short-axis slices only).
  sweep: the grid --lambda 1e3,1e5,1e7 --smoothing-iterations 20,50,200 --target-reduction
  0.72,0.75 --attractor-spacing 0,3 (0: default attractor count); parallel-coordinates plot.
  Each remesh subdivides x4: target reductions below 0.75 grow the mesh (slow), above shrink it.
  population: --count 40 shapes drawn with --seed 1 from the TRUTH shapes in turn (parametric-lv:
  random dimensions; NAME=TRUTH labels a shape), each scaled, bent, warped and posed at random,
  at --levels 0:0,2:2;
  also writes OUT_DIR/population-shapes.csv (what was drawn for each shape).
  --iterations N: deformation iterations of every run (default 250; fewer for quick checks).
  --align-slices: every run aligns the slices first (breath-hold correction, as reconstruct
  --align-slices; contour_to_mesh is then to the shifted contours); use with --tag to compare.
  --align-in-plane-only: with --align-slices, the session-9 alignment (no slice moves along its
  normal; for comparisons).
  --end-caps auto|off: lid points at the ends no curve closes in every run (as reconstruct).
  --no-apex-floor: no run floors a short-axis-only apex at the slices' taper tip (as
  reconstruct: the floor is on by default; --apex-floor, the default, is still accepted).
  --smoothing-method NAME: the remesh smoothing of every run (as reconstruct).
  --tag NAME: write KIND-NAME.csv/.svg instead (several variants in one directory).";

const COMMON: [&str; 5] = [
    "output",
    "iterations",
    "tag",
    "end-caps",
    "smoothing-method",
];
const SWEEP_PARAMS: [&str; 4] = [
    "lambda",
    "smoothing-iterations",
    "target-reduction",
    "attractor-spacing",
];

pub fn run(args: &[String]) -> Result<(), CliError> {
    let Some((kind, rest)) = args.split_first() else {
        return Err(CliError::usage(
            "experiment needs a kind: sax-count, lax-count, misalignment, sweep or population",
        ));
    };
    let own: &[&str] = match kind.as_str() {
        "sax-count" => &["from", "to", "step", "lax"],
        "lax-count" => &["from", "to", "step", "sax"],
        "misalignment" => &["levels", "seeds", "lax"],
        "sweep" => &SWEEP_PARAMS,
        "population" => &["count", "seed", "levels", "lax"],
        other => {
            return Err(CliError::usage(format!(
                "unknown experiment {other:?} (sax-count, lax-count, misalignment, sweep, \
                 population)"
            )))
        }
    };
    let with_value: Vec<&str> = COMMON.iter().chain(own).copied().collect();
    let p = parse(
        rest,
        &Spec {
            with_value: &with_value,
            switches: &[
                "quiet",
                "align-slices",
                "align-in-plane-only",
                "apex-floor",
                "no-apex-floor",
            ],
            aliases: &[("-o", "output"), ("-q", "quiet")],
        },
    )?;
    if p.positional.is_empty() {
        return Err(CliError::usage(format!(
            "experiment {kind} needs at least one TRUTH surface (or parametric-lv)"
        )));
    }
    let out_dir = p
        .value("output")
        .ok_or_else(|| CliError::usage(format!("experiment {kind} needs -o OUT_DIR")))?;
    if let Some(tag) = p.value("tag") {
        if tag.is_empty()
            || !tag
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
        {
            return Err(CliError::usage(format!(
                "--tag {tag:?}: use letters, digits, - and _ only"
            )));
        }
    }
    let design = design(kind, &p)?;
    let mut params = Params {
        align_slices: p.switch("align-slices"),
        align_through_plane: crate::cmd_reconstruct::through_plane_switch(
            &p,
            p.switch("align-slices"),
        )?,
        ..Params::default()
    };
    if let Some(on) = crate::cmd_reconstruct::apex_floor_switch(&p)? {
        params.apex_floor = on;
    }
    if let Some(m) = p.value("end-caps") {
        params.set_end_caps(m).map_err(CliError::param)?;
    }
    if let Some(m) = p.value("smoothing-method") {
        params.set_smoothing_method(m).map_err(CliError::param)?;
    }
    if let Some(n) = p.whole("iterations")? {
        params
            .set("iterations", n as f64)
            .map_err(CliError::param)?;
    }
    let (mut subjects, members) = match &design {
        Design::Population { seed, .. } => {
            let bases = p
                .positional
                .iter()
                .map(|t| population_base(t))
                .collect::<Result<Vec<_>, _>>()?;
            let count = match p.whole("count")? {
                Some(0) => return Err(CliError::usage("--count must be at least 1")),
                Some(n) => n as usize,
                None => DEFAULT_POPULATION,
            };
            let members = generate(&bases, count, *seed).map_err(CliError::param)?;
            let subjects = members.iter().map(|m| m.subject.clone()).collect();
            (subjects, members)
        }
        _ => (
            p.positional
                .iter()
                .map(|t| subject(t))
                .collect::<Result<Vec<_>, _>>()?,
            Vec::new(),
        ),
    };
    // misalignment and population take every subject's own LAX count (3 for an LV, 1 for an RV
    // planned on its LV) unless --lax gives one for all (sax-count reads --lax itself).
    if matches!(
        design,
        Design::Misalignment { .. } | Design::Population { .. }
    ) {
        if let Some(k) = lax_override(&p)? {
            for s in &mut subjects {
                s.base.lax_count = k;
            }
        }
    }
    let mut exp = Experiment::new(&design, subjects, &params).map_err(CliError::param)?;
    files::create_dir(out_dir)?;

    let total = exp.trials().len();
    let quiet = p.switch("quiet");
    let started = Instant::now();
    let rows = exp.run(|progress| {
        if let (Progress::Finished(row), false) = (progress, quiet) {
            eprintln!(
                "heartmesh: {kind} [{}/{total}] {}",
                row.trial + 1,
                describe(row)
            );
        }
        true
    });
    let failed = rows.iter().filter(|r| r.error.is_some()).count();
    if failed == rows.len() {
        return Err(CliError::Failed(format!(
            "experiment {kind}: every run failed (first: {})",
            rows.first()
                .and_then(|r| r.error.clone())
                .unwrap_or_default()
        )));
    }
    let base = match p.value("tag") {
        Some(tag) => format!("{kind}-{tag}"),
        None => kind.to_string(),
    };
    let csv_path = Path::new(out_dir).join(format!("{base}.csv"));
    let svg_path = Path::new(out_dir).join(format!("{base}.svg"));
    let csv_name = csv_path.to_string_lossy().to_string();
    let svg_name = svg_path.to_string_lossy().to_string();
    files::write(&csv_name, to_csv(&rows).as_bytes())?;
    if !members.is_empty() {
        let shapes = Path::new(out_dir).join(format!("{base}-shapes.csv"));
        files::write(&shapes.to_string_lossy(), members_csv(&members).as_bytes())?;
    }
    let names: Vec<String> = exp.subjects().iter().map(|s| s.name.clone()).collect();
    files::write(&svg_name, plot(&design, &rows, &names, &params).as_bytes())?;
    if !quiet {
        outln!(
            "{csv_name}, {svg_name}: {} runs ({failed} failed) in {:.1} s",
            rows.len(),
            started.elapsed().as_secs_f64()
        );
    }
    Ok(())
}

/// One progress line: the shape, the varied settings and the main measures.
fn describe(row: &Row) -> String {
    let settings: Vec<String> = row
        .settings
        .iter()
        .map(|(n, v)| format!("{n}={v}"))
        .collect();
    let what = format!("{} {}", row.shape, settings.join(" "));
    match (&row.metrics, &row.error) {
        (Some(m), _) => format!(
            "{what}: mean {:.3} / {:.3} mm, hausdorff {:.2} mm, contour->mesh {:.3} mm, {:.2} s",
            m.mesh_to_truth.mean,
            m.truth_to_mesh.mean,
            m.hausdorff,
            m.contour_to_mesh_mean,
            row.seconds
        ),
        (None, e) => format!("{what}: FAILED {}", e.as_deref().unwrap_or("")),
    }
}

fn design(kind: &str, p: &Parsed) -> Result<Design, CliError> {
    let counts = |from: u64, to: u64| -> Result<Vec<usize>, CliError> {
        let from = p.whole("from")?.unwrap_or(from);
        let to = p.whole("to")?.unwrap_or(to);
        let step = p.whole("step")?.unwrap_or(1);
        if step == 0 || to < from {
            return Err(CliError::usage(format!(
                "--from {from} --to {to} --step {step} gives no count to run"
            )));
        }
        Ok((from..=to)
            .step_by(step as usize)
            .map(|n| n as usize)
            .collect())
    };
    Ok(match kind {
        "sax-count" => Design::SaxCount {
            counts: counts(2, 15)?,
            lax: p.whole("lax")?.map(|k| k as usize),
        },
        "lax-count" => Design::LaxCount {
            counts: counts(1, 8)?,
            sax: p.whole("sax")?.unwrap_or(4) as usize,
        },
        "population" => {
            let Design::Population { levels, .. } = Design::population(1) else {
                return Err(CliError::Failed("internal: population design".into()));
            };
            Design::Population {
                levels: match p.value("levels") {
                    Some(v) => levels_from(v)?,
                    None => levels,
                },
                seed: p.whole("seed")?.unwrap_or(1),
            }
        }
        "misalignment" => {
            let Design::Misalignment { levels, seeds } = Design::misalignment() else {
                return Err(CliError::Failed("internal: misalignment design".into()));
            };
            Design::Misalignment {
                levels: match p.value("levels") {
                    Some(v) => levels_from(v)?,
                    None => levels,
                },
                seeds: match p.whole("seeds")? {
                    Some(0) => return Err(CliError::usage("--seeds must be at least 1")),
                    Some(n) => (1..=n).collect(),
                    None => seeds,
                },
            }
        }
        _ => {
            let Design::Sweep { grid } = Design::sweep() else {
                return Err(CliError::Failed("internal: sweep design".into()));
            };
            let mut out = Vec::new();
            for (name, default) in grid {
                let flag = name.replace('_', "-");
                let values = match p.value(&flag) {
                    Some(v) => list(&flag, v)?,
                    None => default,
                };
                out.push((name, values));
            }
            Design::Sweep { grid: out }
        }
    })
}

/// `--lax K` for every subject of misalignment and population: 0 (a short-axis stack only, no
/// long-axis view: the paper's "parallel SAX only" case, where no long-axis curve reaches an end)
/// up to the paper's 8 angles.
fn lax_override(p: &Parsed) -> Result<Option<usize>, CliError> {
    match p.whole("lax")? {
        Some(k) if k as usize > PAPER_LAX_ANGLES_DEG.len() => Err(CliError::usage(format!(
            "--lax {k}: at most {} long-axis views (0: short-axis slices only)",
            PAPER_LAX_ANGLES_DEG.len()
        ))),
        k => Ok(k.map(|k| k as usize)),
    }
}

/// `0:0,1:1,2` -> [(0,0), (1,1), (2,2)] (a bare number: the same shift in mm and tilt in degrees).
fn levels_from(v: &str) -> Result<Vec<(f64, f64)>, CliError> {
    let bad = || {
        CliError::usage(format!(
            "--levels: {v:?} is not SHIFT:TILT,... (e.g. 0:0,2:2)"
        ))
    };
    v.split(',')
        .map(|item| {
            let parts: Vec<&str> = item.split(':').collect();
            let nums: Vec<f64> = parts
                .iter()
                .map(|s| s.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
                .collect::<Option<Vec<_>>>()
                .ok_or_else(bad)?;
            match nums.as_slice() {
                [s] => Ok((*s, *s)),
                [s, t] => Ok((*s, *t)),
                _ => Err(bad()),
            }
        })
        .collect()
}

fn list(flag: &str, v: &str) -> Result<Vec<f64>, CliError> {
    v.split(',')
        .map(|s| s.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
        .collect::<Option<Vec<_>>>()
        .filter(|l| !l.is_empty())
        .ok_or_else(|| CliError::usage(format!("--{flag}: {v:?} is not a list of numbers")))
}

/// The built-in truth: the default parametric LV with a 4 mm regional bulge at mid-ventricle
/// (as in the accuracy tests), finely triangulated.
pub fn parametric_lv() -> Result<heartmesh_core::TriMesh, CliError> {
    ParametricLv::bulged_truth().map_err(|e| CliError::Failed(format!("parametric-lv: {e}")))
}

fn subject(arg: &str) -> Result<Subject, CliError> {
    if arg == "parametric-lv" {
        return Ok(Subject::new("parametric-lv", parametric_lv()?));
    }
    let split = (!Path::new(arg).exists())
        .then(|| arg.split_once('@'))
        .flatten();
    match split {
        Some((shape, lv)) => {
            let mesh = rv_surface(shape)?;
            // The LV's anatomical axis (apex to mitral centre), as a scanner plans the RV views.
            let axis = anatomical_axis(&read_surface(lv)?, AcquisitionSpec::default().join_gap_mm)
                .map_err(|e| CliError::input(lv, e))?;
            Subject::planned_on(stem(shape), mesh, axis).map_err(|e| CliError::input(shape, e))
        }
        None => Ok(Subject::new(stem(arg), read_surface(arg)?)),
    }
}

/// Shapes drawn when --count is not given: the paper's population size.
const DEFAULT_POPULATION: usize = 40;

/// An RV surface: a file, or `FREEWALL+SEPTUM` (the free wall closed by the part of SEPTUM, an LV
/// epicardium, that it faces within 40 mm, as `sim::cavity` builds a CMR-like RV cavity).
fn rv_surface(arg: &str) -> Result<heartmesh_core::TriMesh, CliError> {
    match (!Path::new(arg).exists())
        .then(|| arg.split_once('+'))
        .flatten()
    {
        Some((wall, septum)) => rv_cavity(&read_surface(wall)?, &read_surface(septum)?, 40.0)
            .map_err(|e| CliError::input(arg, e)),
        None => read_surface(arg),
    }
}

/// A base shape of the population: `parametric-lv`, an LV surface file, or `RV@LV` as for the
/// other experiments, optionally labelled `NAME=...` (members are named `pNN-NAME`).
fn population_base(arg: &str) -> Result<Base, CliError> {
    if let Some((name, rest)) = (!Path::new(arg).exists())
        .then(|| arg.split_once('='))
        .flatten()
    {
        return Ok(Base {
            name: name.to_string(),
            ..population_base(rest)?
        });
    }
    if arg == "parametric-lv" {
        return Ok(Base {
            name: "parametric".into(),
            source: Source::Parametric,
            plan: Plan::Lv,
        });
    }
    match (!Path::new(arg).exists())
        .then(|| arg.split_once('@'))
        .flatten()
    {
        Some((shape, lv)) => Ok(Base {
            name: stem(shape.split('+').next().unwrap_or(shape)),
            source: Source::Mesh(rv_surface(shape)?),
            plan: Plan::Rv {
                lv: read_surface(lv)?,
            },
        }),
        None => Ok(Base {
            name: stem(arg),
            source: Source::Mesh(read_surface(arg)?),
            plan: Plan::Lv,
        }),
    }
}

/// What was drawn for each population member, one row each (scales, sag and offset in mm).
fn members_csv(members: &[Member]) -> String {
    let mut out = String::from(
        "shape,base,scale_x,scale_y,scale_z,sag_mm,bumps,max_bump_mm,warp_lipschitz,\
         rotation_deg,offset_x,offset_y,offset_z\n",
    );
    for m in members {
        let v = &m.variation;
        let max_bump = v
            .bumps
            .iter()
            .map(|b| b.displacement.norm())
            .fold(0.0, f64::max);
        out.push_str(&format!(
            "{},{},{:.3},{:.3},{:.3},{:.2},{},{:.2},{:.3},{:.1},{:.1},{:.1},{:.1}\n",
            m.subject.name,
            m.base,
            v.scale[0],
            v.scale[1],
            v.scale[2],
            v.sag_mm,
            v.bumps.len(),
            max_bump,
            v.warp_lipschitz(),
            v.rotation.angle().to_degrees(),
            v.offset.x,
            v.offset.y,
            v.offset.z
        ));
    }
    out
}

fn stem(path: &str) -> String {
    Path::new(path)
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_else(|| path.to_string())
}
