//! `volumes --plot`: each cavity's volume over the phases as an SVG line chart, the shape of the
//! cycle a table of 20-50 frames hides (the app's Function panel draws the same curve). Only
//! cavities: an epicardium's volume holds the wall, not blood. A phase without a closed mesh
//! leaves a gap in its cavity's line, never a zero.

use heartmesh_core::metrics::function::{is_cavity, Function};

use crate::svg_plot::{chart, Chart, Panel, Series};

/// At most this many phase names under the x axis (a 430 px panel); the others are thinned out,
/// the first and last always kept.
const MAX_X_LABELS: usize = 10;

/// The chart of `volumes[phase][surface]` (ml, None: no volume), with each ventricle's ejection
/// fraction above the plot.
pub fn curve(
    phases: &[String],
    surfaces: &[String],
    volumes: &[Vec<Option<f64>>],
    function: &Function,
) -> String {
    let mut series = Vec::new();
    for (colour, (k, surface)) in surfaces
        .iter()
        .enumerate()
        .filter(|(_, s)| is_cavity(s))
        .enumerate()
    {
        let column = volumes.iter().map(|row| row.get(k).copied().flatten());
        for (n, run) in runs(column).into_iter().enumerate() {
            series.push(Series {
                name: surface.clone(),
                colour,
                points: run,
                line: true,
                dots: true,
                legend: n == 0,
            });
        }
    }
    let ef: Vec<String> = function
        .ventricles
        .iter()
        .map(|v| format!("{} EF {:.1} %", v.surface, v.ef_percent))
        .collect();
    chart(&Chart {
        title: "Cavity volumes over the phases".into(),
        x_label: "phase".into(),
        x_ticks: Some(x_ticks(phases)),
        panels: vec![Panel {
            title: ef.join(", "),
            y_label: "volume (ml)".into(),
            y_log: false,
            series,
        }],
    })
}

/// The stretches of consecutive phases with a volume, as (phase index, ml) points.
fn runs(column: impl Iterator<Item = Option<f64>>) -> Vec<Vec<(f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut open = false;
    for (i, v) in column.enumerate() {
        match v.filter(|v| v.is_finite()) {
            Some(ml) if open => out
                .last_mut()
                .into_iter()
                .for_each(|r| r.push((i as f64, ml))),
            Some(ml) => {
                out.push(vec![(i as f64, ml)]);
                open = true;
            }
            None => open = false,
        }
    }
    out
}

/// Every phase's name when they fit, else every k-th and the last (a k-th closer than k to the
/// last would crowd it, and goes).
fn x_ticks(phases: &[String]) -> Vec<(f64, String)> {
    let step = phases.len().div_ceil(MAX_X_LABELS).max(1);
    let last = phases.len().saturating_sub(1);
    phases
        .iter()
        .enumerate()
        .filter(|&(i, _)| i == last || (i % step == 0 && (last - i >= step || i == 0)))
        .map(|(i, name)| (i as f64, name.clone()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_phase_without_a_volume_splits_the_line() {
        let column = [
            Some(1.0),
            Some(2.0),
            None,
            Some(4.0),
            Some(f64::NAN),
            Some(6.0),
        ];
        assert_eq!(
            runs(column.into_iter()),
            vec![
                vec![(0.0, 1.0), (1.0, 2.0)],
                vec![(3.0, 4.0)],
                vec![(5.0, 6.0)]
            ]
        );
    }

    #[test]
    fn names_are_thinned_to_ten_or_fewer_the_last_kept() {
        let names = |n: usize| (0..n).map(|i| i.to_string()).collect::<Vec<_>>();
        let shown = |n: usize| -> Vec<f64> { x_ticks(&names(n)).iter().map(|t| t.0).collect() };
        assert_eq!(shown(3), vec![0.0, 1.0, 2.0]);
        assert_eq!(shown(10).len(), 10);
        let thirty = shown(30);
        assert_eq!(
            thirty,
            vec![0.0, 3.0, 6.0, 9.0, 12.0, 15.0, 18.0, 21.0, 24.0, 29.0]
        );
        let fifty = shown(50);
        assert!(fifty.len() <= MAX_X_LABELS + 1, "{fifty:?}");
        assert_eq!(fifty.first(), Some(&0.0));
        assert_eq!(fifty.last(), Some(&49.0));
    }
}
