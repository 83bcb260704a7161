//! How the mesh grows over a run, predicted before it starts.
//!
//! Every remesh subdivides (x4 triangles) and then decimates by the target reduction, so at the
//! paper's 0.72 each remesh keeps 4 x 0.28 = 1.12 times the triangles: a 2000-triangle mesh ends
//! near 8000 after the default 250 iterations, but reaches the remesh cap
//! ([`super::MAX_REMESH_TRIANGLES`]) after about 1000, where a step takes a second natively and
//! several in a browser (biv-me patient 2 ES LV endocardium: 1500 iterations, 100 002 vertices, 92
//! s). A user who slides the iteration count up sees the run slow down without being told why;
//! the prediction lets the CLI and the app say so before the wait.

use super::{final_steps_without_remesh, MAX_REMESH_TRIANGLES};
use crate::params::Params;

/// When the mesh would reach the remesh cap, if it would within the run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CapReached {
    /// The iteration of the remesh that first reaches it (a run that converges earlier stops
    /// before).
    pub iteration: usize,
    /// Triangles kept per triangle at each remesh: 4 x (1 - target reduction).
    pub growth: f64,
}

/// The first remesh of a run with `params` at which a mesh of `triangles` now (after the remesh
/// before the first step) would reach [`MAX_REMESH_TRIANGLES`], following the step loop's remesh
/// schedule; None when it stays below (a growth of at most 1 never gets there).
pub fn cap_reached(params: &Params, triangles: usize) -> Option<CapReached> {
    let growth = 4.0 * (1.0 - params.target_reduction);
    let every = params.remesh_every.max(1);
    if growth <= 1.0 || triangles == 0 {
        return None;
    }
    let last = params
        .iterations
        .checked_sub(final_steps_without_remesh(params))?;
    let mut t = triangles as f64;
    (1..)
        .map(|k| k * every)
        .take_while(|&it| it <= last && it < params.iterations)
        .find(|_| {
            t *= growth;
            t >= MAX_REMESH_TRIANGLES as f64
        })
        .map(|iteration| CapReached { iteration, growth })
}

/// The one-line note for a run that reaches the cap, or None.
pub fn cap_note(params: &Params, triangles: usize) -> Option<String> {
    let c = cap_reached(params, triangles)?;
    Some(format!(
        "each remesh keeps {:.2}x the triangles (x4 subdivision, {:.0} % kept), so the mesh reaches \
         the {MAX_REMESH_TRIANGLES}-triangle cap by about iteration {} of {}: the steps after it take \
         seconds each; fewer iterations, or a target reduction of 0.75 or more, keep the mesh \
         smaller",
        c.growth,
        100.0 * (1.0 - params.target_reduction),
        c.iteration,
        params.iterations
    ))
}

/// The one-line note for a run whose remeshes would shrink the mesh (a target reduction above
/// 0.75) and so hold it at `floor` triangles, the initial tube's; None when the mesh does not
/// shrink or the run has no remesh after the first.
pub fn floor_note(params: &Params, floor: usize) -> Option<String> {
    let kept = 4.0 * (1.0 - params.target_reduction);
    let remeshes = params.remesh_every.max(1) < params.iterations;
    (kept < 1.0 && remeshes && floor > 0).then(|| {
        format!(
            "each remesh keeps {kept:.2}x the triangles (x4 subdivision, {:.0} % kept), so the \
             mesh is held at the initial tube's {floor} triangles instead of shrinking at every \
             remesh; a target reduction of 0.75 or less lets it refine",
            100.0 * (1.0 - params.target_reduction)
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn with(iterations: usize, target_reduction: f64) -> Params {
        Params {
            iterations,
            target_reduction,
            ..Params::default()
        }
    }

    #[test]
    fn the_defaults_stay_far_below_the_cap_and_long_runs_reach_it() {
        // 2000 triangles: 12 remeshes at 1.12x give about 7800.
        assert_eq!(cap_reached(&Params::default(), 2000), None);
        // 2000 x 1.12^k >= 200 000 from k = 41 (1.12^41 = 104.0), iteration 820.
        let c = cap_reached(&with(1500, 0.72), 2000).unwrap();
        assert_eq!(c.iteration, 820);
        assert!((c.growth - 1.12).abs() < 1e-12);
        // The same run stopped before iteration 820 plus its final steps without a remesh: none.
        assert_eq!(cap_reached(&with(820, 0.72), 2000), None);
        // A reduction of 0.75 or more never grows.
        assert_eq!(cap_reached(&with(2000, 0.75), 2000), None);
        assert_eq!(cap_reached(&with(2000, 0.9), 2000), None);
        // 0.5 doubles at every remesh: from 2000, 7 remeshes (x128).
        assert_eq!(cap_reached(&with(250, 0.5), 2000).unwrap().iteration, 140);
    }

    #[test]
    fn the_note_names_the_iteration_and_what_to_change() {
        let note = cap_note(&with(1500, 0.72), 2000).unwrap();
        assert_eq!(
            note,
            "each remesh keeps 1.12x the triangles (x4 subdivision, 28 % kept), so the mesh \
             reaches the 200000-triangle cap by about iteration 820 of 1500: the steps after it \
             take seconds each; fewer iterations, or a target reduction of 0.75 or more, keep the mesh \
             smaller"
        );
        assert_eq!(cap_note(&Params::default(), 2000), None);
    }
}
