//! The plot of each experiment, drawn from its rows: error against the SAX or LAX count (one line
//! per truth shape), against the misalignment level (one dot per seed, a line through the
//! medians), and parallel coordinates for a parameter sweep. Mirrors the figures of Villard, Grau
//! & Zacur (J. Imaging 2018, section 3) so the two can be read side by side.

use heartmesh_core::sim::experiment::{Design, Row};
use heartmesh_core::Params;

use crate::svg_plot::{chart, parallel, Chart, Panel, ParallelAxis, ParallelLine, Series};

/// Mean surface distance: the average of the two directed means (mm).
pub fn mean_distance(r: &Row) -> Option<f64> {
    Some(0.5 * (r.metric("mesh_to_truth_mean")? + r.metric("truth_to_mesh_mean")?))
}

type Measure = (&'static str, &'static str, bool, fn(&Row) -> Option<f64>);

const MEAN: Measure = (
    "mean surface distance (both ways)",
    "mm",
    true,
    mean_distance,
);
const HAUSDORFF: Measure = ("Hausdorff distance", "mm", true, |r| r.metric("hausdorff"));
const C2M_MEAN: Measure = ("contour-to-mesh mean", "mm", false, |r| {
    r.metric("contour_to_mesh_mean")
});
const C2M_MAX: Measure = ("contour-to-mesh max", "mm", false, |r| {
    r.metric("contour_to_mesh_max")
});

/// The SVG for `rows` of `design`; `shapes` are the subjects' names in order.
pub fn plot(design: &Design, rows: &[Row], shapes: &[String], params: &Params) -> String {
    let iters = if params.iterations == Params::default().iterations {
        String::new()
    } else {
        format!(", {} iterations", params.iterations)
    };
    match design {
        Design::SaxCount { lax, .. } => {
            let lax = lax.map_or("LAX fixed per shape".to_string(), |k| format!("{k} LAX"));
            by_count(
                &format!("Error against the number of SAX slices ({lax}{iters})"),
                "SAX slices",
                "sax",
                rows,
                shapes,
            )
        }
        Design::LaxCount { sax, .. } => by_count(
            &format!("Error against the number of LAX views ({sax} SAX{iters})"),
            "LAX views (0, 90, 45, 135, 22.5, 157.5, 112.5, 67.5 degrees)",
            "lax",
            rows,
            shapes,
        ),
        Design::Misalignment { levels, .. } => misalignment(
            levels,
            rows,
            shapes,
            &[C2M_MEAN, C2M_MAX, MEAN],
            &format!(
                "Breath-hold misalignment: each plane shifted and tilted at random (dots: seeds; \
                 lines: medians{iters})"
            ),
        ),
        Design::Population { levels, .. } => {
            // One series per base shape (member names are `pNN-<base>`), one dot per member.
            let base = |name: &str| name.split_once('-').map_or(name, |(_, b)| b).to_string();
            let grouped: Vec<Row> = rows
                .iter()
                .map(|r| Row {
                    shape: base(&r.shape),
                    ..r.clone()
                })
                .collect();
            let mut bases: Vec<String> = Vec::new();
            for s in shapes.iter().map(|s| base(s)) {
                if !bases.contains(&s) {
                    bases.push(s);
                }
            }
            misalignment(
                levels,
                &grouped,
                &bases,
                &[MEAN, HAUSDORFF, C2M_MEAN],
                &format!(
                    "Population: {} shapes drawn from {} bases (dots: shapes; lines: medians{iters})",
                    shapes.len(),
                    bases.len()
                ),
            )
        }
        Design::Sweep { grid } => sweep(grid, rows, shapes, &iters),
    }
}

fn by_count(title: &str, x_label: &str, setting: &str, rows: &[Row], shapes: &[String]) -> String {
    let panels = [MEAN, HAUSDORFF]
        .iter()
        .map(|&(name, unit, log, f)| Panel {
            title: name.into(),
            y_label: format!("{unit} (log scale)"),
            y_log: log,
            series: shapes
                .iter()
                .enumerate()
                .map(|(k, shape)| Series {
                    name: shape.clone(),
                    colour: k,
                    points: rows
                        .iter()
                        .filter(|r| r.shape == *shape)
                        .filter_map(|r| Some((r.setting(setting)?, f(r)?)))
                        .collect(),
                    line: true,
                    dots: true,
                    legend: true,
                })
                .collect(),
        })
        .collect();
    chart(&Chart {
        title: title.into(),
        x_label: x_label.into(),
        x_ticks: None,
        panels,
    })
}

fn misalignment(
    levels: &[(f64, f64)],
    rows: &[Row],
    shapes: &[String],
    measures: &[Measure],
    title: &str,
) -> String {
    let level_of = |r: &Row| {
        let (s, t) = (r.setting("shift_mm")?, r.setting("tilt_deg")?);
        levels.iter().position(|&(a, b)| a == s && b == t)
    };
    let n = shapes.len().max(1) as f64;
    let panels = measures
        .iter()
        .map(|&(name, unit, _, f)| {
            let mut series = Vec::new();
            for (k, shape) in shapes.iter().enumerate() {
                // Shapes side by side within a level, so their dots do not hide each other.
                let offset = 0.5 * (k as f64 - (n - 1.0) / 2.0) / n;
                let mine: Vec<&Row> = rows.iter().filter(|r| r.shape == *shape).collect();
                let dots: Vec<(f64, f64)> = mine
                    .iter()
                    .filter_map(|r| Some((level_of(r)? as f64 + offset, f(r)?)))
                    .collect();
                let medians: Vec<(f64, f64)> = (0..levels.len())
                    .filter_map(|l| {
                        let mut v: Vec<f64> = mine
                            .iter()
                            .filter(|r| level_of(r) == Some(l))
                            .filter_map(|r| f(r))
                            .collect();
                        v.sort_by(f64::total_cmp);
                        (!v.is_empty()).then(|| (l as f64 + offset, median(&v)))
                    })
                    .collect();
                series.push(Series {
                    name: shape.clone(),
                    colour: k,
                    points: medians,
                    line: true,
                    dots: false,
                    legend: true,
                });
                series.push(Series {
                    name: format!("{shape} runs"),
                    colour: k,
                    points: dots,
                    line: false,
                    dots: true,
                    legend: false,
                });
            }
            Panel {
                title: name.into(),
                y_label: unit.into(),
                y_log: false,
                series,
            }
        })
        .collect();
    chart(&Chart {
        title: title.into(),
        x_label: "max shift (mm) / max tilt (degrees)".into(),
        x_ticks: Some(
            levels
                .iter()
                .enumerate()
                .map(|(k, (s, t))| (k as f64, format!("{s} / {t}")))
                .collect(),
        ),
        panels,
    })
}

fn sweep(grid: &[(String, Vec<f64>)], rows: &[Row], shapes: &[String], iters: &str) -> String {
    let mut axes: Vec<ParallelAxis> = grid
        .iter()
        .map(|(name, _)| ParallelAxis {
            name: name.clone(),
            log: name == "lambda",
        })
        .collect();
    for name in ["mean distance (mm)", "Hausdorff (mm)", "seconds"] {
        axes.push(ParallelAxis {
            name: name.into(),
            log: name != "seconds",
        });
    }
    // Emphasise each shape's best quarter of runs by mean distance: shapes differ in scale, so
    // ranks are per shape.
    let best: Vec<bool> = rows
        .iter()
        .map(|r| {
            let Some(m) = mean_distance(r) else {
                return false;
            };
            let mine: Vec<f64> = rows
                .iter()
                .filter(|o| o.shape == r.shape)
                .filter_map(mean_distance)
                .collect();
            let better = mine.iter().filter(|&&o| o < m).count();
            better < mine.len().div_ceil(4)
        })
        .collect();
    let lines: Vec<ParallelLine> = rows
        .iter()
        .zip(best)
        .map(|(r, emphasis)| {
            let group = shapes.iter().position(|s| *s == r.shape).unwrap_or(0);
            let mut v: Vec<f64> = grid
                .iter()
                .map(|(n, _)| r.setting(n).unwrap_or(f64::NAN))
                .collect();
            v.push(mean_distance(r).unwrap_or(f64::NAN));
            v.push(r.metric("hausdorff").unwrap_or(f64::NAN));
            v.push(if r.metrics.is_some() {
                r.seconds
            } else {
                f64::NAN
            });
            ParallelLine {
                group,
                values: v,
                emphasis,
            }
        })
        .collect();
    parallel(
        &format!("Parameter sweep: one line per run{iters}"),
        &axes,
        &lines,
        shapes,
        "bold: the best quarter of each shape's runs by mean distance",
    )
}

fn median(sorted: &[f64]) -> f64 {
    let n = sorted.len();
    if n % 2 == 1 {
        sorted[n / 2]
    } else {
        0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
    }
}
