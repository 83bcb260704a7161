//! `heartmesh compare TRUTH MESH [--clip-contours CONTOURS] [--json]`: surface distances both ways,
//! Hausdorff and volumes, clipped at the most basal SAX plane of the contours (as the paper does).

use heartmesh_core::contours::CoordinateSystem;
use heartmesh_core::metrics::compare::{clip_plane_from_contours, compare, CompareReport};
use heartmesh_core::Params;

use crate::args::{parse, Spec};
use crate::cmd_simulate::read_surface_and_frame;
use crate::contours;
use crate::error::CliError;

pub const USAGE: &str = "heartmesh compare TRUTH.obj MESH.obj [--clip-contours CONTOURS.csv]
    [--surface LABEL] [--json]
  Distances in mm from the mesh to the truth and from the truth to the mesh (area-weighted mean,
  median, p95; max over samples and vertices), Hausdorff, volumes in ml. With --clip-contours,
  both surfaces are clipped at the most basal SAX plane of those contours (volumes of the parts
  below it, capped flat). When the files state their patient frames (SPACE=LPS / SPACE=RAS)
  and these differ, MESH and the contours are taken into TRUTH's frame. --json prints
  {mesh_to_truth, truth_to_mesh, hausdorff, volume_truth_ml, volume_mesh_ml, clipped,
  coordinate_system (TRUTH's, or null), mesh_converted_from (null unless MESH was taken into it)}.";

pub fn run(args: &[String]) -> Result<(), CliError> {
    let p = parse(
        args,
        &Spec {
            with_value: &["clip-contours", "surface"],
            switches: &["json"],
            aliases: &[],
        },
    )?;
    let [truth_path, mesh_path] = p.positional.as_slice() else {
        let n = p.positional.len();
        return Err(CliError::usage(format!(
            "compare needs TRUTH and MESH, got {n} file name{}",
            if n == 1 { "" } else { "s" }
        )));
    };
    let (truth, truth_frame) = read_surface_and_frame(truth_path)?;
    let (mut mesh, mesh_frame) = read_surface_and_frame(mesh_path)?;
    // Files that state mirrored frames (a NIfTI-made RAS mesh against a DICOM-made LPS one) are
    // compared in the truth's frame, never as they stand: their distances would be nonsense.
    if let (Some(from), Some(to)) = (mesh_frame, truth_frame) {
        if from != to {
            for v in &mut mesh.positions {
                *v = from.convert(to, v);
            }
            frame_note(mesh_path, from, truth_path, to);
        }
    }
    let clip = match p.value("clip-contours") {
        Some(path) => {
            let mut loaded = contours::load(path, None)?;
            let stated = loaded.set.coordinate_system;
            if let (Some(from), Some(to)) = (stated, truth_frame) {
                if loaded.set.express_in(to) {
                    frame_note(path, from, truth_path, to);
                }
            }
            let params = Params {
                surface: p.value("surface").map(str::to_string),
                ..Params::default()
            };
            Some(
                clip_plane_from_contours(&loaded.set, params)
                    .map_err(|e| CliError::input(path, e))?,
            )
        }
        None => None,
    };
    let report = compare(&truth, &mesh, clip.as_ref())
        .map_err(|e| CliError::Failed(format!("{mesh_path}: {e}")))?;
    if p.switch("json") {
        let mut value =
            serde_json::to_value(&report).map_err(|e| CliError::Failed(e.to_string()))?;
        if let serde_json::Value::Object(map) = &mut value {
            // The frame the distances are in (the truth's, when its file states one) and the
            // frame MESH's file stated when it was taken into it.
            let name = |f: Option<CoordinateSystem>| f.map(CoordinateSystem::name);
            let converted = mesh_frame.filter(|m| truth_frame.is_some_and(|t| t != *m));
            map.insert("coordinate_system".into(), name(truth_frame).into());
            map.insert("mesh_converted_from".into(), name(converted).into());
        }
        let text =
            serde_json::to_string_pretty(&value).map_err(|e| CliError::Failed(e.to_string()))?;
        outln!("{text}");
    } else {
        out!("{}", human(&report));
    }
    Ok(())
}

/// Says on stderr that `path`'s points were taken from its frame into the truth's.
fn frame_note(path: &str, from: CoordinateSystem, truth_path: &str, to: CoordinateSystem) {
    eprintln!(
        "heartmesh: note: {path} is in {} and {truth_path} in {}: its points are taken into {} \
         (x and y negated)",
        from.name(),
        to.name(),
        to.name()
    );
}

fn human(r: &CompareReport) -> String {
    let line = |name: &str, s: &heartmesh_core::metrics::compare::DistanceStats| {
        format!(
            "{name}: mean {:.3} median {:.3} p95 {:.3} max {:.3} mm ({} samples)\n",
            s.mean, s.median, s.p95, s.max, s.count
        )
    };
    format!(
        "{}{}hausdorff {:.3} mm; volume truth {:.2} ml, mesh {:.2} ml{}\n",
        line("mesh -> truth", &r.mesh_to_truth),
        line("truth -> mesh", &r.truth_to_mesh),
        r.hausdorff,
        r.volume_truth_ml,
        r.volume_mesh_ml,
        if r.clipped {
            " (clipped at the most basal SAX plane)"
        } else {
            ""
        }
    )
}
