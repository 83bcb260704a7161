//! `heartmesh simulate TRUTH -o CONTOURS.csv`: slice a reference surface like a CMR acquisition
//! (SAX stack, radial LAX, breath-hold misalignment, noise) to get contours with a known truth.

use heartmesh_core::io;
use heartmesh_core::sim::planes::anatomical_axis;
use heartmesh_core::sim::repair::{orient_consistently, weld};
use heartmesh_core::sim::{simulate, AcquisitionSpec, Misalignment, SaxStack};

use crate::args::{parse, Parsed, Spec};
use crate::cmd_convert::file_name;
use crate::error::CliError;
use crate::files;

pub const USAGE: &str = "heartmesh simulate TRUTH.obj -o CONTOURS.csv [--sax N | --sax-spacing MM]
    [--lax K] [--misalign MM,DEG] [--noise MM] [--seed S] [--surface LABEL] [--axis-from LV.obj]
    [--quiet]
  TRUTH: obj, stl, ply, vtk or vtp surface in mm. SAX planes every 10 mm by default, from 3 mm
  below the valve rim (or where the section stops being one loop) towards the apex; LAX planes
  contain the long axis at 0, 90, 45, 135, 22.5, 157.5, 112.5, 67.5 degrees (default 3);
  --misalign shifts each plane up to MM and tilts it up to DEG (breath-hold model, seeded);
  --noise adds in-plane Gaussian noise (sd in mm); --axis-from plans the planes on another
  surface's long axis (e.g. the LV of the same subject for an RV).";

pub fn run(args: &[String]) -> Result<(), CliError> {
    let p = parse(
        args,
        &Spec {
            with_value: &[
                "output",
                "sax",
                "sax-spacing",
                "lax",
                "misalign",
                "noise",
                "seed",
                "surface",
                "axis-from",
            ],
            switches: &["quiet"],
            aliases: &[("-o", "output"), ("-q", "quiet")],
        },
    )?;
    let [input] = p.positional.as_slice() else {
        return Err(CliError::usage(format!(
            "simulate needs exactly one reference surface, got {}",
            p.positional.len()
        )));
    };
    let output = p
        .value("output")
        .ok_or_else(|| CliError::usage("simulate needs -o CONTOURS.csv"))?;
    if io::extension(output) != "csv" {
        return Err(CliError::usage(format!(
            "simulate writes canonical CSV: {output} should end in .csv"
        )));
    }
    files::check_output(output)?;
    let inputs: Vec<&str> = std::iter::once(input.as_str())
        .chain(p.value("axis-from"))
        .collect();
    files::check_distinct(&inputs, &[("-o", output)])?;
    let mut spec = spec_from(&p)?;
    let truth = read_surface(input)?;
    if let Some(lv) = p.value("axis-from") {
        let lv_mesh = read_surface(lv)?;
        // Planned like a scanner: through the LV apex and mitral centre, as `simulate` does.
        let axis =
            anatomical_axis(&lv_mesh, spec.join_gap_mm).map_err(|e| CliError::input(lv, e))?;
        spec.axis = Some(axis);
    }
    let acq = simulate(&truth, &spec).map_err(|e| match e {
        heartmesh_core::CoreError::ParamOutOfRange { .. } => CliError::param(e),
        other => CliError::input(input, other),
    })?;
    let csv = io::csv::write_csv(&acq.contours, None)
        .map_err(|e| CliError::Failed(format!("{output}: {e}")))?;
    files::write(output, &csv)?;
    if !p.switch("quiet") {
        for w in &acq.contours.warnings {
            eprintln!("heartmesh: warning: {input}: {w}");
        }
        let o = acq.clip.origin;
        let n = acq.clip.normal;
        outln!(
            "{output}: {} SAX + {} LAX contours, {} points from {}; most basal SAX plane through \
             ({:.2}, {:.2}, {:.2}) normal ({:.4}, {:.4}, {:.4})",
            acq.sax_planes.len(),
            acq.contours.contours.len() - acq.sax_planes.len(),
            acq.contours.point_count(),
            file_name(input),
            o.x,
            o.y,
            o.z,
            n.x,
            n.y,
            n.z
        );
    }
    Ok(())
}

/// A reference surface, welded (unwelded poles read as holes) and consistently oriented (mixed
/// orientations spoil volumes).
pub fn read_surface(path: &str) -> Result<heartmesh_core::TriMesh, CliError> {
    let bytes = files::read(path)?;
    let data = io::read_mesh(path, &bytes).map_err(|e| CliError::input(path, e))?;
    Ok(orient_consistently(&weld(&data.mesh, 1e-6).0).0)
}

fn spec_from(p: &Parsed) -> Result<AcquisitionSpec, CliError> {
    let mut spec = AcquisitionSpec::default();
    match (p.whole("sax")?, p.number("sax-spacing")?) {
        (Some(_), Some(_)) => {
            return Err(CliError::usage(
                "give either --sax or --sax-spacing, not both",
            ))
        }
        (Some(n), None) => spec.sax = SaxStack::Count(n as usize),
        (None, Some(s)) => spec.sax = SaxStack::SpacingMm(s),
        (None, None) => {}
    }
    if let Some(k) = p.whole("lax")? {
        spec.lax_count = k as usize;
    }
    if let Some(m) = p.value("misalign") {
        let parts: Vec<&str> = m.split(',').collect();
        let parsed: Vec<f64> = parts
            .iter()
            .filter_map(|s| s.trim().parse::<f64>().ok())
            .collect();
        let [shift_mm, tilt_deg] = parsed.as_slice() else {
            return Err(CliError::usage(format!(
                "--misalign: {m:?} is not MM,DEG (e.g. 2,2)"
            )));
        };
        if parts.len() != 2 {
            return Err(CliError::usage(format!(
                "--misalign: {m:?} is not MM,DEG (e.g. 2,2)"
            )));
        }
        spec.misalignment = Some(Misalignment {
            shift_mm: *shift_mm,
            tilt_deg: *tilt_deg,
        });
    }
    if let Some(n) = p.number("noise")? {
        spec.noise_mm = n;
    }
    if let Some(s) = p.whole("seed")? {
        spec.seed = s;
    }
    spec.surface = p.value("surface").map(str::to_string);
    Ok(spec)
}
