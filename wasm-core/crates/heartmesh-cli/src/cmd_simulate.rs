//! `heartmesh simulate TRUTH -o CONTOURS.csv`: slice a reference surface like a CMR acquisition
//! (SAX stack, radial LAX, breath-hold misalignment, noise) to get contours with a known truth;
//! `LABEL=TRUTH ...`: several surfaces of one heart on one acquisition (a multi-surface file).

use heartmesh_core::contours::CoordinateSystem;
use heartmesh_core::io;
use heartmesh_core::sim::planes::anatomical_axis;
use heartmesh_core::sim::planes::simulate_surfaces;
use heartmesh_core::sim::repair::{orient_consistently, weld};
use heartmesh_core::sim::{simulate, AcquisitionSpec, Misalignment, SaxStack};
use heartmesh_core::TriMesh;

use crate::args::{parse, Parsed, Spec};
use crate::cmd_convert::file_name;
use crate::error::CliError;
use crate::files;

pub const USAGE: &str = "heartmesh simulate TRUTH.obj -o CONTOURS.csv [--sax N | --sax-spacing MM]
    [--lax K] [--misalign MM,DEG] [--noise MM] [--seed S] [--surface LABEL] [--axis-from LV.obj]
    [--quiet]
  heartmesh simulate LV_ENDO=lv.obj LV_EPI=epi.obj [RV_ENDO=rv.obj ...] -o CONTOURS.csv [...]
  TRUTH: obj, stl, ply, vtk or vtp surface in mm. SAX planes every 10 mm by default, from 3 mm
  below the valve rim (or where the section stops being one loop) towards the apex; LAX planes
  contain the long axis at 0, 90, 45, 135, 22.5, 157.5, 112.5, 67.5 degrees (default 3);
  --misalign shifts each plane up to MM and tilts it up to DEG (breath-hold model, seeded);
  --noise adds in-plane Gaussian noise (sd in mm); --axis-from plans the planes on another
  surface's long axis (e.g. the LV of the same subject for an RV).
  LABEL=TRUTH (several surfaces of one heart): one acquisition, planned on the first surface
  (or --axis-from), its stack from the lowest apex to the base they share; every image cuts
  every surface with the same breath-hold motion, as one scanner image shows them all; each
  contour gets its surface's label (the surface column) and its image's id (sax03_LV_ENDO);
  the file then feeds `reconstruct --surface all` or `myocardium`.";

/// A label for the `surface` column: what the readers accept as one (no separators or quotes).
fn is_label(s: &str) -> bool {
    !s.is_empty()
        && s.len() <= 64
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// The reference surfaces named on the command line: one plain path, or `LABEL=PATH` each (a path
/// that exists is a path even if it holds `=`).
fn truths(positional: &[String]) -> Result<Vec<(Option<String>, String)>, CliError> {
    let named = |arg: &String| -> Option<(String, String)> {
        if std::path::Path::new(arg).exists() {
            return None;
        }
        let (label, path) = arg.split_once('=')?;
        Some((label.to_string(), path.to_string()))
    };
    match positional {
        [] => Err(CliError::usage(
            "simulate needs a reference surface (TRUTH.obj, or LABEL=TRUTH for each of several)",
        )),
        [one] => Ok(vec![match named(one) {
            Some((label, path)) => (Some(label), path),
            None => (None, one.clone()),
        }]),
        many => many
            .iter()
            .map(|arg| {
                named(arg).map(|(l, p)| (Some(l), p)).ok_or_else(|| {
                    CliError::usage(format!(
                        "simulate: {arg} has no label: with several surfaces give each as \
                         LABEL=FILE (e.g. LV_ENDO=lv.obj LV_EPI=epi.obj)"
                    ))
                })
            })
            .collect(),
    }
    .and_then(|list| {
        for (k, (label, path)) in list.iter().enumerate() {
            if let Some(label) = label {
                if !is_label(label) {
                    return Err(CliError::usage(format!(
                        "simulate: {label:?} is no surface label (letters, digits, _ and -, \
                         e.g. LV_ENDO=lv.obj)"
                    )));
                }
                if list[..k]
                    .iter()
                    .any(|(l, _)| l.as_deref().is_some_and(|l| l.eq_ignore_ascii_case(label)))
                {
                    return Err(CliError::usage(format!(
                        "simulate: the label {label} is given twice; give each surface its own"
                    )));
                }
            }
            if path.is_empty() {
                return Err(CliError::usage(format!(
                    "simulate: {} has no file after =",
                    label.as_deref().unwrap_or_default()
                )));
            }
        }
        Ok(list)
    })
}

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
    let truths = truths(&p.positional)?;
    let output = p
        .value("output")
        .ok_or_else(|| CliError::usage("simulate needs -o CONTOURS.csv"))?;
    if io::extension(output) != "csv" {
        return Err(CliError::usage(format!(
            "simulate writes canonical CSV: {output} should end in .csv"
        )));
    }
    files::check_output(output)?;
    let inputs: Vec<&str> = truths
        .iter()
        .map(|(_, path)| path.as_str())
        .chain(p.value("axis-from"))
        .collect();
    files::check_distinct(&inputs, &[("-o", output)])?;
    let mut spec = spec_from(&p)?;
    let labelled = truths.iter().any(|(label, _)| label.is_some());
    if labelled && spec.surface.is_some() {
        return Err(CliError::usage(
            "simulate: give the surface labels as LABEL=FILE or with --surface, not both",
        ));
    }
    let meshes = truths
        .iter()
        .map(|(_, path)| read_surface(path))
        .collect::<Result<Vec<TriMesh>, CliError>>()?;
    if let Some(lv) = p.value("axis-from") {
        let lv_mesh = read_surface(lv)?;
        // Planned like a scanner: through the LV apex and mitral centre, as `simulate` does.
        let axis =
            anatomical_axis(&lv_mesh, spec.join_gap_mm).map_err(|e| CliError::input(lv, e))?;
        spec.axis = Some(axis);
    }
    // Which file a failure is about: the one surface's, or all of them (the core names the
    // label of the surface it could not slice).
    let about = truths
        .iter()
        .map(|(_, path)| path.as_str())
        .collect::<Vec<_>>()
        .join(", ");
    let acq = if labelled {
        let surfaces: Vec<(&str, &TriMesh)> = truths
            .iter()
            .zip(&meshes)
            .map(|((label, _), mesh)| (label.as_deref().unwrap_or_default(), mesh))
            .collect();
        simulate_surfaces(&surfaces, &spec)
    } else {
        simulate(&meshes[0], &spec)
    }
    .map_err(|e| match e {
        heartmesh_core::CoreError::ParamOutOfRange { .. } => CliError::param(e),
        other => CliError::input(&about, other),
    })?;
    let csv = io::csv::write_csv(&acq.contours, None)
        .map_err(|e| CliError::Failed(format!("{output}: {e}")))?;
    files::write(output, &csv)?;
    if !p.switch("quiet") {
        for w in &acq.contours.warnings {
            eprintln!("heartmesh: warning: {about}: {w}");
        }
        let o = acq.clip.origin;
        let n = acq.clip.normal;
        let sources = truths
            .iter()
            .map(|(label, path)| match label {
                Some(label) => format!("{label} {}", file_name(path)),
                None => file_name(path).to_string(),
            })
            .collect::<Vec<_>>()
            .join(", ");
        outln!(
            "{output}: {} SAX + {} LAX images, {} contours, {} points from {}; most basal SAX \
             plane through ({:.2}, {:.2}, {:.2}) normal ({:.4}, {:.4}, {:.4})",
            acq.sax_planes.len(),
            acq.lax_planes.len(),
            acq.contours.contours.len(),
            acq.contours.point_count(),
            sources,
            o.x,
            o.y,
            o.z,
            n.x,
            n.y,
            n.z
        );
        // A surface drawn only lower down is unobserved above its own top slice: compare it with
        // its truth clipped there, not at the stack's top.
        for ((label, _), own) in truths.iter().zip(&acq.surface_clips) {
            if let (Some(label), true) = (label, *own != acq.clip) {
                let o = own.origin;
                outln!(
                    "{label}: closed sections end below the base; its most basal SAX plane                      through ({:.2}, {:.2}, {:.2})",
                    o.x,
                    o.y,
                    o.z
                );
            }
        }
    }
    Ok(())
}

/// A reference surface, welded (unwelded poles read as holes) and consistently oriented (mixed
/// orientations spoil volumes).
pub fn read_surface(path: &str) -> Result<heartmesh_core::TriMesh, CliError> {
    Ok(read_surface_and_frame(path)?.0)
}

/// [`read_surface`] and the patient frame the file states (`SPACE=`), if any.
pub fn read_surface_and_frame(
    path: &str,
) -> Result<(heartmesh_core::TriMesh, Option<CoordinateSystem>), CliError> {
    let bytes = files::read(path)?;
    let data = io::read_mesh(path, &bytes).map_err(|e| CliError::input(path, e))?;
    let mesh = orient_consistently(&weld(&data.mesh, 1e-6).0).0;
    Ok((mesh, data.coordinate_system))
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
