//! The two kinds of experiment plot: side-by-side panels of lines and dots against one varied
//! setting (SAX count, LAX count, misalignment level), and parallel coordinates for parameter
//! sweeps (Inselberg, "The plane with parallel coordinates", The Visual Computer, 1985): one
//! vertical axis per parameter and per measure, one polyline per run.

use crate::svg::{colour, Scale, Svg};

/// One line and/or set of dots in a panel.
pub struct Series {
    pub name: String,
    /// Palette index: series of the same shape share it.
    pub colour: usize,
    pub points: Vec<(f64, f64)>,
    pub line: bool,
    pub dots: bool,
    /// Listed in the legend (one entry per shape, not per dot series).
    pub legend: bool,
}

/// One plot area with its own y axis; all panels of a chart share the x axis.
pub struct Panel {
    pub title: String,
    pub y_label: String,
    pub y_log: bool,
    pub series: Vec<Series>,
}

pub struct Chart {
    pub title: String,
    pub x_label: String,
    /// Explicit x ticks (e.g. categories); None: nice ticks over the data.
    pub x_ticks: Option<Vec<(f64, String)>>,
    pub panels: Vec<Panel>,
}

const PANEL_W: f64 = 430.0;
const PANEL_H: f64 = 300.0;
const LEFT: f64 = 64.0;
const RIGHT: f64 = 16.0;
const TOP: f64 = 64.0;
const BOTTOM: f64 = 48.0;
const LEGEND_ROW: f64 = 18.0;

pub fn chart(c: &Chart) -> String {
    let legend: Vec<(&str, usize)> = c
        .panels
        .first()
        .map(|p| {
            p.series
                .iter()
                .filter(|s| s.legend)
                .map(|s| (s.name.as_str(), s.colour))
                .collect()
        })
        .unwrap_or_default();
    let per_row = 2usize;
    let rows = legend.len().div_ceil(per_row);
    let width = PANEL_W * c.panels.len().max(1) as f64;
    // Bottom of the plot areas; x labels and the legend below.
    let y0 = TOP + PANEL_H - 40.0;
    let legend_top = y0 + BOTTOM + 10.0;
    let height = legend_top + rows as f64 * LEGEND_ROW + 8.0;
    let mut svg = Svg::new(width, height);
    svg.text(width / 2.0, 22.0, 15.0, "middle", 0.0, &c.title);

    let xs = c
        .panels
        .iter()
        .flat_map(|p| p.series.iter())
        .flat_map(|s| s.points.iter().map(|p| p.0));
    let x_values: Vec<f64> = match &c.x_ticks {
        Some(t) => t.iter().map(|t| t.0).chain(xs).collect(),
        None => xs.collect(),
    };
    for (k, panel) in c.panels.iter().enumerate() {
        let x0 = k as f64 * PANEL_W + LEFT;
        let x1 = (k + 1) as f64 * PANEL_W - RIGHT;
        let y1 = TOP;
        let mut xscale = Scale::covering(x_values.iter().copied(), x0, x1, false);
        if c.x_ticks.is_some() {
            // Categories: half a step of room at each end.
            let (lo, hi) = x_values
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                    (a.min(v), b.max(v))
                });
            xscale.lo = lo - 0.5;
            xscale.hi = hi + 0.5;
        }
        let yscale = Scale::covering(
            panel
                .series
                .iter()
                .flat_map(|s| s.points.iter().map(|p| p.1)),
            y0,
            y1,
            panel.y_log,
        );
        svg.text(
            (x0 + x1) / 2.0,
            TOP - 14.0,
            13.0,
            "middle",
            0.0,
            &panel.title,
        );
        // Grid and y ticks.
        for (v, l) in yscale.ticks() {
            let y = yscale.px(v);
            svg.line(x0, y, x1, y, "#e4e4e4", 1.0);
            svg.text(x0 - 6.0, y + 4.0, 11.0, "end", 0.0, &l);
        }
        let x_ticks = c.x_ticks.clone().unwrap_or_else(|| xscale.ticks());
        for (v, l) in &x_ticks {
            let x = xscale.px(*v);
            svg.line(x, y0, x, y0 + 5.0, "#444", 1.0);
            svg.text(x, y0 + 18.0, 11.0, "middle", 0.0, l);
        }
        svg.line(x0, y0, x1, y0, "#444", 1.0);
        svg.line(x0, y0, x0, y1, "#444", 1.0);
        svg.text((x0 + x1) / 2.0, y0 + 38.0, 12.0, "middle", 0.0, &c.x_label);
        svg.text(
            x0 - 46.0,
            (y0 + y1) / 2.0,
            12.0,
            "middle",
            -90.0,
            &panel.y_label,
        );
        for s in &panel.series {
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .filter(|p| p.0.is_finite() && p.1.is_finite() && (!panel.y_log || p.1 > 0.0))
                .map(|&(x, y)| (xscale.px(x), yscale.px(y)))
                .collect();
            if s.line {
                svg.polyline(&pts, colour(s.colour), 2.0, 1.0);
            }
            if s.dots {
                for &(x, y) in &pts {
                    svg.circle(x, y, 3.0, colour(s.colour), if s.line { 1.0 } else { 0.55 });
                }
            }
        }
    }
    draw_legend(&mut svg, &legend, legend_top, per_row, width);
    svg.finish()
}

fn draw_legend(svg: &mut Svg, entries: &[(&str, usize)], top: f64, per_row: usize, width: f64) {
    let col_w = width / per_row as f64;
    for (k, (name, c)) in entries.iter().enumerate() {
        let x = LEFT + (k % per_row) as f64 * col_w;
        let y = top + (k / per_row) as f64 * LEGEND_ROW;
        svg.rect(x, y - 9.0, 18.0, 10.0, colour(*c), "none");
        svg.text(x + 24.0, y, 11.0, "start", 0.0, name);
    }
}

/// One vertical axis of a parallel-coordinates plot.
pub struct ParallelAxis {
    pub name: String,
    pub log: bool,
}

/// A parallel-coordinates plot: `lines` are (group, one value per axis); groups are coloured and
/// named in the legend. Non-finite values break a line.
pub fn parallel(
    title: &str,
    axes: &[ParallelAxis],
    lines: &[(usize, Vec<f64>)],
    groups: &[String],
) -> String {
    let spacing = 130.0;
    let (top, height_axis) = (56.0, 300.0);
    let per_row = 2usize;
    let rows = groups.len().div_ceil(per_row);
    let width = LEFT + spacing * (axes.len().max(2) - 1) as f64 + 90.0;
    let height = top + height_axis + 56.0 + rows as f64 * LEGEND_ROW;
    let mut svg = Svg::new(width, height);
    svg.text(width / 2.0, 22.0, 15.0, "middle", 0.0, title);
    let y0 = top + height_axis;
    let scales: Vec<Scale> = axes
        .iter()
        .enumerate()
        .map(|(k, a)| {
            Scale::covering(
                lines.iter().filter_map(|l| l.1.get(k).copied()),
                y0,
                top,
                a.log,
            )
        })
        .collect();
    let x_of = |k: usize| LEFT + spacing * k as f64;
    for (group, values) in lines {
        let mut run: Vec<(f64, f64)> = Vec::new();
        for (k, v) in values.iter().enumerate().take(axes.len()) {
            if v.is_finite() && (!axes[k].log || *v > 0.0) {
                run.push((x_of(k), scales[k].px(*v)));
            } else {
                svg.polyline(&run, colour(*group), 1.5, 0.55);
                run.clear();
            }
        }
        svg.polyline(&run, colour(*group), 1.5, 0.55);
    }
    for (k, (axis, scale)) in axes.iter().zip(&scales).enumerate() {
        let x = x_of(k);
        svg.line(x, y0, x, top, "#333", 1.2);
        for (v, l) in scale.ticks() {
            let y = scale.px(v);
            svg.line(x - 4.0, y, x, y, "#333", 1.0);
            svg.text(x - 6.0, y + 4.0, 10.0, "end", 0.0, &l);
        }
        svg.text(x, y0 + 20.0, 11.0, "middle", 0.0, &axis.name);
    }
    let legend: Vec<(&str, usize)> = groups
        .iter()
        .enumerate()
        .map(|(k, g)| (g.as_str(), k))
        .collect();
    draw_legend(&mut svg, &legend, y0 + 48.0, per_row, width);
    svg.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chart_has_one_polyline_per_line_series_and_dots() {
        let doc = chart(&Chart {
            title: "t".into(),
            x_label: "SAX slices".into(),
            x_ticks: None,
            panels: vec![Panel {
                title: "mean".into(),
                y_label: "mm".into(),
                y_log: true,
                series: vec![
                    Series {
                        name: "a".into(),
                        colour: 0,
                        points: vec![(2.0, 5.0), (3.0, 1.0), (4.0, 0.2)],
                        line: true,
                        dots: true,
                        legend: true,
                    },
                    Series {
                        name: "b".into(),
                        colour: 1,
                        points: vec![(2.0, f64::NAN), (3.0, 0.5)],
                        line: false,
                        dots: true,
                        legend: false,
                    },
                ],
            }],
        });
        assert_eq!(doc.matches("<polyline").count(), 1);
        assert_eq!(doc.matches("<circle").count(), 4);
        assert!(doc.contains(">SAX slices</text>"));
    }

    #[test]
    fn parallel_breaks_lines_at_missing_values() {
        let axes: Vec<ParallelAxis> = ["lambda", "mean"]
            .iter()
            .map(|n| ParallelAxis {
                name: n.to_string(),
                log: true,
            })
            .collect();
        let doc = parallel(
            "sweep",
            &axes,
            &[(0, vec![1e3, 0.2]), (1, vec![1e5, f64::NAN])],
            &["a".into(), "b".into()],
        );
        assert_eq!(doc.matches("<polyline").count(), 1);
        assert!(doc.contains(">lambda</text>"));
    }
}
