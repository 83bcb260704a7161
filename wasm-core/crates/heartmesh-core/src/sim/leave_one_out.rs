//! Leave-one-out validation on real contours (Villard, Grau & Zacur, J. Imaging 2018, section 3.3,
//! Figures 10-11): rebuild the surface without contour j and measure how far contour j's points
//! lie from the new mesh. Where no truth exists, this shows how well the method predicts a slice
//! it has not seen, and which contour disagrees most with the others.

use crate::contours::set_aside::Why;
use crate::contours::{Contour, ContourKind, ContourSet};
use crate::error::Result;
use crate::mesh::TriMesh;
use crate::metrics::{points_to_mesh, stats, Stats};
use crate::params::Params;
use crate::pipeline::Reconstruction;
use serde::Serialize;

/// One left-out contour.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LeftOut {
    pub id: String,
    pub kind: ContourKind,
    /// Distances (mm) of the left-out contour's points to the mesh built without it; None when
    /// the reconstruction without it was impossible (then `error` says why).
    pub stats: Option<Stats>,
    pub error: Option<String>,
}

/// The whole analysis, in the order of the pipeline's contours.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LeaveOneOut {
    pub contours: Vec<LeftOut>,
    /// The contour with the largest mean distance (the one that disagrees most).
    pub worst: Option<String>,
    /// Mean over contours of the per-contour mean distance.
    pub mean_of_means: f64,
}

/// One rebuild of the analysis: the contour held out, its kind, and what the rebuild runs on:
/// the whole file with the parameters naming that contour in `leave_out`.
#[derive(Debug, Clone)]
pub struct HeldOut {
    pub contour: Contour,
    pub kind: ContourKind,
    pub rest: ContourSet,
    pub params: Params,
}

/// The analysis planned but not run: the cleaned contours of the selected surface, their kinds,
/// and one [`HeldOut`] job per contour (in that order). Shared by the one-shot [`leave_one_out`]
/// and the app's stepped batch, so both leave out exactly the same contours. Fails only if the
/// full set itself is not a valid input.
///
/// Each rebuild is `reconstruct --leave-out ID` of that contour (the caller's `leave_out` list
/// kept: those are out of every rebuild), so the figure is the one the run's `set_aside` gives
/// ([`held_out_stats`]) and a contour left out by hand reads the same in both. With the
/// breath-hold alignment on, every rebuild aligns the file without the held-out contour and
/// measures it where its image moved: the rebuild is never aligned twice (the full run's
/// shifted contours aligned again), and the held-out curve does not steer the shifts that
/// place the mesh it is measured against.
pub struct Plan {
    pub cleaned: Vec<Contour>,
    pub kinds: Vec<ContourKind>,
    pub jobs: Vec<HeldOut>,
}

/// Validates the full input (which also selects the surface and cleans the contours) and plans
/// one rebuild per contour.
pub fn plan(set: &ContourSet, params: &Params) -> Result<Plan> {
    let full = Reconstruction::new(set, params.clone())?;
    let cleaned = full.contours().to_vec();
    let kinds = full.kinds().to_vec();
    drop(full);
    let jobs = cleaned
        .iter()
        .enumerate()
        .map(|(j, held)| {
            let mut params = params.clone();
            if !params.leave_out.contains(&held.id) {
                params.leave_out.push(held.id.clone());
            }
            HeldOut {
                contour: held.clone(),
                kind: kinds.get(j).copied().unwrap_or(ContourKind::Sax),
                rest: set.clone(),
                params,
            }
        })
        .collect();
    Ok(Plan {
        cleaned,
        kinds,
        jobs,
    })
}

/// Distances (mm) of the held-out contour's points to the mesh rebuilt without it: the rebuild's
/// `set_aside` figure for it (where the alignment moved it, when on); measured on the mesh
/// directly if the rebuild did not list it (no rebuild of a plan fails to).
pub fn held_out_stats(held: &Contour, rebuilt: &Reconstruction) -> Stats {
    rebuilt
        .set_aside()
        .iter()
        .position(|s| s.id == held.id && s.line == held.first_line && s.why == Why::ByUser)
        .and_then(|k| rebuilt.set_aside_stats().get(k).copied())
        .unwrap_or_else(|| measure(held, rebuilt.mesh()))
}

/// Distances (mm) of the held-out contour's points to the mesh rebuilt without it.
pub fn measure(held: &Contour, mesh: &TriMesh) -> Stats {
    let pts: Vec<_> = held.points().copied().collect();
    stats(&points_to_mesh(&pts, mesh))
}

/// Runs the analysis; `params` are used for every rebuild (and select the surface; the contours
/// their `leave_out` names are out of every rebuild and not held out in turn). Fails only if the
/// full set itself cannot be reconstructed.
pub fn leave_one_out(set: &ContourSet, params: &Params) -> Result<LeaveOneOut> {
    let plan = plan(set, params)?;
    let mut out = Vec::with_capacity(plan.jobs.len());
    for job in plan.jobs {
        let rebuilt = Reconstruction::new(&job.rest, job.params).and_then(|mut rec| {
            rec.run()?;
            Ok(rec)
        });
        let (stats, error) = match rebuilt {
            Ok(rec) => (Some(held_out_stats(&job.contour, &rec)), None),
            Err(e) => (None, Some(e.to_string())),
        };
        out.push(LeftOut {
            id: job.contour.id,
            kind: job.kind,
            stats,
            error,
        });
    }
    let measured: Vec<(&str, f64)> = out
        .iter()
        .filter_map(|c| c.stats.map(|s| (c.id.as_str(), s.mean)))
        .collect();
    let worst = measured
        .iter()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(id, _)| id.to_string());
    let mean_of_means = if measured.is_empty() {
        f64::NAN
    } else {
        measured.iter().map(|m| m.1).sum::<f64>() / measured.len() as f64
    };
    Ok(LeaveOneOut {
        contours: out,
        worst,
        mean_of_means,
    })
}
