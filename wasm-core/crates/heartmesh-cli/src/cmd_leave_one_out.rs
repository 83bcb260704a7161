//! `heartmesh leave-one-out CONTOURS [--json]`: rebuild without each contour in turn and report that
//! contour's distance to the new mesh (Villard et al. 2018, Figures 10-11).

use heartmesh_core::contours::ContourKind;
use heartmesh_core::sim::leave_one_out::leave_one_out;
use heartmesh_core::Params;

use crate::args::{parse, Spec};
use crate::contours;
use crate::error::CliError;

pub const USAGE: &str =
    "heartmesh leave-one-out CONTOURS.csv [--surface LABEL] [--leave-out ID[,ID...]] [--json]
  For each contour: reconstruct at the defaults without it, then measure its points' distance to
  that mesh (mm: mean, median, p95, max). --leave-out: contours out of every rebuild (as
  reconstruct's), not held out in turn. --json prints {contours: [{id, kind, stats, error}],
  worst, mean_of_means}.";

pub fn run(args: &[String]) -> Result<(), CliError> {
    let p = parse(
        args,
        &Spec {
            with_value: &["surface", "leave-out"],
            switches: &["json"],
            aliases: &[],
        },
    )?;
    let [input] = p.positional.as_slice() else {
        return Err(CliError::usage(format!(
            "leave-one-out needs exactly one contour file, got {}",
            p.positional.len()
        )));
    };
    let loaded = contours::load(input, None)?;
    let mut params = Params {
        surface: p.value("surface").map(str::to_string),
        ..loaded.session_params.unwrap_or_default()
    };
    crate::cmd_reconstruct::add_leave_out(&p, &mut params);
    params.validate().map_err(CliError::param)?;
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
