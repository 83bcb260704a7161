//! `heartmesh leave-one-out CONTOURS [--json]`: rebuild without each contour in turn and report that
//! contour's distance to the new mesh (Villard et al. 2018, Figures 10-11).

use heartmesh_core::contours::ContourKind;
use heartmesh_core::sim::leave_one_out::leave_one_out;
use heartmesh_core::{CoreError, Params};

use crate::cmd_reconstruct::{apex_lid, params_from, parse_with_inputs};
use crate::contours;
use crate::error::CliError;

pub const USAGE: &str =
    "heartmesh leave-one-out CONTOURS.csv [--surface LABEL] [--leave-out ID[,ID...]] [--json]
    [reconstruct's parameter options: --iterations ... --end-caps ... --align-slices ...]
  For each contour: reconstruct without it (at the defaults, a session's parameters or those the
  options give), then measure its points' distance to that mesh (mm: mean, median, p95, max):
  the figure `reconstruct --leave-out ID` reports for it; with --align-slices each rebuild aligns
  the file without it and measures it where its slice or view moved. --leave-out: contours out of
  every rebuild (as reconstruct's), not held out in turn. --json prints {contours: [{id, kind,
  stats, error}], worst, mean_of_means}.";

pub fn run(args: &[String]) -> Result<(), CliError> {
    let p = parse_with_inputs(
        args,
        &[],
        &["json"],
        &[],
        "leave-one-out needs one contour file",
    )?;
    let [input] = p.positional.as_slice() else {
        return Err(CliError::usage(format!(
            "leave-one-out needs exactly one contour file, got {}",
            p.positional.len()
        )));
    };
    // A usage error should not wait for the file.
    params_from(&p, Params::default())?;
    let loaded = contours::load(input, None)?;
    let mut params = params_from(&p, loaded.session_params.unwrap_or_default())?;
    if p.value("lids") == Some("apex") {
        params.lids = apex_lid(&loaded.set, params.surface.as_deref()).ok_or_else(|| {
            CliError::input(
                input,
                CoreError::parse(0, "--lids apex needs an APEX_POINT landmark in the file"),
            )
        })?;
    }
    let result = leave_one_out(&loaded.set, &params).map_err(|e| CliError::input(input, e))?;
    if p.switch("json") {
        let text =
            serde_json::to_string_pretty(&result).map_err(|e| CliError::Failed(e.to_string()))?;
        outln!("{text}");
        return Ok(());
    }
    for c in &result.contours {
        let kind = match c.kind {
            ContourKind::Sax => "SAX",
            ContourKind::Lax => "LAX",
        };
        match (&c.stats, &c.error) {
            (Some(s), _) => outln!(
                "{:<24} {kind}  mean {:.3}  median {:.3}  p95 {:.3}  max {:.3} mm",
                c.id,
                s.mean,
                s.median,
                s.p95,
                s.max
            ),
            (None, Some(e)) => outln!("{:<24} {kind}  not rebuilt: {e}", c.id),
            (None, None) => {}
        }
    }
    if let Some(w) = &result.worst {
        outln!(
            "worst: {w}; mean of per-contour means {:.3} mm",
            result.mean_of_means
        );
    }
    Ok(())
}
