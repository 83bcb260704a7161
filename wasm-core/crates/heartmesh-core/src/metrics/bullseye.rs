//! The 17 segments' wall thickness as the bullseye cardiologists read (an SVG): the apex in the
//! middle, the basal ring outside, anterior at the top and the septum on the left, as the AHA
//! standard draws it. One drawing for the command line (`myocardium --bullseye`) and the app
//! (the same text through the wasm), so the two never disagree.
//!
//! The colour scale starts at 0 mm and ends at 15 mm (or the next 5 mm above the thickest
//! segment): a fixed top keeps two patients' plots comparable by colour, which a scale stretched
//! to each wall's own range would not. Viridis, as the app's distance and thickness colours.

use super::segments::Segments;
use super::thickening::Thickening;
use crate::io::xml_escape;
use std::fmt::Write;

/// Viridis at 0, 0.1, ..., 1 (the app's `web/src/viewer/colormap.ts` anchors).
const VIRIDIS: [[u8; 3]; 11] = [
    [0x44, 0x01, 0x54],
    [0x48, 0x24, 0x75],
    [0x41, 0x44, 0x87],
    [0x35, 0x5f, 0x8d],
    [0x2a, 0x78, 0x8e],
    [0x21, 0x91, 0x8c],
    [0x22, 0xa8, 0x84],
    [0x44, 0xbf, 0x70],
    [0x7a, 0xd1, 0x51],
    [0xbd, 0xdf, 0x26],
    [0xfd, 0xe7, 0x25],
];

const WIDTH: f64 = 460.0;
const HEIGHT: f64 = 530.0;
const CX: f64 = 230.0;
const CY: f64 = 255.0;
/// Ring borders from the middle out: apex, apical, mid, basal.
const RADII: [f64; 5] = [0.0, 38.0, 82.0, 126.0, 170.0];
/// Thinnest scale top (mm).
const SCALE_TOP_MM: f64 = 15.0;

/// The colour of `t` in 0..=1 as `#rrggbb`.
fn viridis(t: f64) -> String {
    let x = t.clamp(0.0, 1.0) * 10.0;
    let k = (x.floor() as usize).min(9);
    let f = x - k as f64;
    let c: Vec<u8> = (0..3)
        .map(|i| {
            let a = f64::from(VIRIDIS[k][i]);
            let b = f64::from(VIRIDIS[k + 1][i]);
            (a + (b - a) * f).round() as u8
        })
        .collect();
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// A point at `radius` and screen angle `deg` (counter-clockwise from the right) round the middle.
fn at(radius: f64, deg: f64) -> (f64, f64) {
    let a = deg.to_radians();
    (CX + radius * a.cos(), CY - radius * a.sin())
}

/// The outline of ring `ring` (0 apex .. 3 basal) between screen angles `from` and `to`.
fn sector(ring: usize, from: f64, to: f64) -> String {
    let (r0, r1) = (RADII[ring], RADII[ring + 1]);
    if ring == 0 {
        return format!(
            "M {} {} m -{r1} 0 a {r1} {r1} 0 1 0 {} 0 a {r1} {r1} 0 1 0 -{} 0 Z",
            CX,
            CY,
            2.0 * r1,
            2.0 * r1
        );
    }
    let p = |r, d| {
        let (x, y) = at(r, d);
        format!("{x:.2} {y:.2}")
    };
    format!(
        "M {} A {r1} {r1} 0 0 0 {} L {} A {r0} {r0} 0 0 1 {} Z",
        p(r1, from),
        p(r1, to),
        p(r0, to),
        p(r0, from)
    )
}

/// Ring and screen angles of segment `k` (0-based): anterior (1, 7, 13) at the top, the
/// septum (2-3, 8-9, 14) on the left.
fn place(k: usize) -> (usize, f64, f64) {
    match k {
        0..=5 => (3, 60.0 + 60.0 * k as f64, 120.0 + 60.0 * k as f64),
        6..=11 => (
            2,
            60.0 + 60.0 * (k - 6) as f64,
            120.0 + 60.0 * (k - 6) as f64,
        ),
        12..=15 => (
            1,
            45.0 + 90.0 * (k - 12) as f64,
            135.0 + 90.0 * (k - 12) as f64,
        ),
        _ => (0, 0.0, 360.0),
    }
}

/// What one bullseye shows: a value per segment on a scale from 0.
struct Drawing<'a> {
    heading: &'a str,
    title: &'a str,
    /// Segments 1-17 in order: name and value (None: nothing measured there).
    values: Vec<(&'a str, Option<f64>)>,
    unit: &'a str,
    /// The scale's top; values above it (and below 0) take the end colours.
    top: f64,
    /// One line or more under the scale.
    footer: String,
}

/// The bullseye of `segments` (wall thickness, mm) as an SVG document; `title` heads it (a file
/// name, a phase).
pub fn svg(segments: &Segments, title: &str) -> String {
    let values: Vec<(&str, Option<f64>)> = segments
        .segments
        .iter()
        .map(|s| (s.name, s.mean_mm))
        .collect();
    let thickest = values.iter().filter_map(|v| v.1).fold(0.0f64, f64::max);
    draw(&Drawing {
        heading: "Wall thickness by AHA segment (mm)",
        title,
        values,
        unit: "mm",
        top: SCALE_TOP_MM.max((thickest / 5.0).ceil() * 5.0),
        footer: format!(
            "septum from {}; levels: thirds of the cavity below the base",
            segments.septum_from
        ),
    })
}

/// Thinnest scale top of a thickening bullseye (%): a normal segment thickens by 40-100 %.
const THICKENING_TOP_PERCENT: f64 = 100.0;

/// The bullseye of a study's systolic thickening by segment (%, [`super::thickening`]), headed
/// by its two phases, the septum's sources under it.
pub fn thickening_svg(t: &Thickening) -> String {
    let values: Vec<(&str, Option<f64>)> = t
        .segments
        .iter()
        .map(|c| (c.name, c.thickening_percent))
        .collect();
    let most = values.iter().filter_map(|v| v.1).fold(0.0f64, f64::max);
    let [ed, es] = &t.septum_from;
    let from = if ed == es {
        format!("septum from {ed}")
    } else {
        format!("septum from {ed} at ED, {es} at ES")
    };
    draw(&Drawing {
        heading: "Systolic wall thickening by AHA segment (%)",
        title: &format!("ED {} to ES {}", t.ed_phase, t.es_phase),
        values,
        unit: "%",
        top: THICKENING_TOP_PERCENT.max((most / 50.0).ceil() * 50.0),
        footer: format!("100 x (ES - ED) / ED of each segment's mean wall thickness\n{from}"),
    })
}

fn draw(d: &Drawing) -> String {
    let top = d.top;
    let mut out = String::new();
    let _ = write!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{WIDTH}\" height=\"{HEIGHT}\" \
         viewBox=\"0 0 {WIDTH} {HEIGHT}\" font-family=\"sans-serif\">\n\
         <rect width=\"{WIDTH}\" height=\"{HEIGHT}\" fill=\"#ffffff\"/>\n\
         <text x=\"{CX}\" y=\"22\" text-anchor=\"middle\" font-size=\"15\" font-weight=\"bold\">\
         {}</text>\n\
         <text x=\"{CX}\" y=\"40\" text-anchor=\"middle\" font-size=\"12\" \
         fill=\"#444\">{}</text>\n",
        xml_escape(d.heading),
        xml_escape(d.title)
    );
    for (k, &(name, value)) in d.values.iter().enumerate().take(17) {
        let (ring, from, to) = place(k);
        let (fill, ink, label) = match value {
            Some(v) => {
                let t = v / top;
                let decimals = if d.unit == "%" { 0 } else { 1 };
                (
                    viridis(t),
                    if t < 0.55 { "#ffffff" } else { "#000000" },
                    format!("{v:.decimals$}"),
                )
            }
            None => ("#d0d0d0".to_string(), "#000000", "–".to_string()),
        };
        let _ = writeln!(
            out,
            "<path d=\"{}\" fill=\"{fill}\" stroke=\"#ffffff\" stroke-width=\"2\">\
             <title>{} {name}: {label} {}</title></path>",
            sector(ring, from, to),
            k + 1,
            d.unit
        );
        let mid = (RADII[ring] + RADII[ring + 1]) / 2.0;
        let (x, y) = if ring == 0 {
            (CX, CY)
        } else {
            at(mid, (from + to) / 2.0)
        };
        let _ = writeln!(
            out,
            "<text x=\"{x:.1}\" y=\"{:.1}\" text-anchor=\"middle\" font-size=\"13\" \
             font-weight=\"bold\" fill=\"{ink}\">{label}</text>\
             <text x=\"{x:.1}\" y=\"{:.1}\" text-anchor=\"middle\" font-size=\"9\" \
             fill=\"{ink}\">{}</text>",
            y + 2.0,
            y + 13.0,
            k + 1
        );
    }
    for (text, deg, anchor) in [
        ("anterior", 90.0, "middle"),
        ("septal", 180.0, "end"),
        ("inferior", 270.0, "middle"),
        ("lateral", 0.0, "start"),
    ] {
        let (x, y) = at(RADII[4] + 8.0, deg);
        let dy = match deg as i32 {
            90 => -2.0,
            270 => 11.0,
            _ => 4.0,
        };
        let _ = writeln!(
            out,
            "<text x=\"{x:.1}\" y=\"{:.1}\" text-anchor=\"{anchor}\" font-size=\"11\" \
             fill=\"#444\">{text}</text>",
            y + dy
        );
    }
    scale_bar(&mut out, top, d.unit);
    // The footer's lines upwards from the bottom edge.
    let lines: Vec<&str> = d.footer.lines().collect();
    for (k, line) in lines.iter().enumerate() {
        let from_bottom = (lines.len() - 1 - k) as f64;
        let _ = writeln!(
            out,
            "<text x=\"{CX}\" y=\"{}\" text-anchor=\"middle\" font-size=\"10\" \
             fill=\"#666\">{}</text>",
            HEIGHT - 8.0 - 13.0 * from_bottom,
            xml_escape(line)
        );
    }
    out.push_str("</svg>\n");
    out
}

/// A tick spacing for a scale from 0 to `top`: 1, 2 or 5 times a power of ten, at least a sixth
/// of it (3 to 6 intervals).
fn tick_step(top: f64) -> f64 {
    let rough = top / 6.0;
    let power = 10f64.powf(rough.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * power)
        .find(|&s| s >= rough)
        .unwrap_or(10.0 * power)
}

/// The colour scale under the bullseye, 0 to `top` (in `unit`).
fn scale_bar(out: &mut String, top: f64, unit: &str) {
    let (x0, y0, w, h) = (80.0, 468.0, 300.0, 12.0);
    let _ = writeln!(
        out,
        "<defs><linearGradient id=\"viridis\" x1=\"0\" x2=\"1\" y1=\"0\" y2=\"0\">"
    );
    for i in 0..=10 {
        let t = f64::from(i) / 10.0;
        let _ = writeln!(out, "<stop offset=\"{t}\" stop-color=\"{}\"/>", viridis(t));
    }
    let _ = writeln!(
        out,
        "</linearGradient></defs><rect x=\"{x0}\" y=\"{y0}\" width=\"{w}\" height=\"{h}\" \
         fill=\"url(#viridis)\"/>"
    );
    let step = tick_step(top);
    let mut v = 0.0;
    while v <= top + 1e-9 {
        let x = x0 + w * v / top;
        let _ = writeln!(
            out,
            "<line x1=\"{x:.1}\" y1=\"{}\" x2=\"{x:.1}\" y2=\"{}\" stroke=\"#333\"/>\
             <text x=\"{x:.1}\" y=\"{}\" text-anchor=\"middle\" font-size=\"10\">{v}</text>",
            y0 + h,
            y0 + h + 4.0,
            y0 + h + 15.0
        );
        v += step;
    }
    let _ = writeln!(
        out,
        "<text x=\"{}\" y=\"{}\" font-size=\"10\">{unit}</text>",
        x0 + w + 8.0,
        y0 + h - 1.0
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends_and_middle() {
        assert_eq!(viridis(0.0), "#440154");
        assert_eq!(viridis(1.0), "#fde725");
        assert_eq!(viridis(0.5), "#21918c");
        assert_eq!(viridis(-3.0), "#440154");
    }

    #[test]
    fn ticks_are_round_numbers() {
        assert_eq!(tick_step(15.0), 5.0);
        assert_eq!(tick_step(20.0), 5.0);
        assert_eq!(tick_step(30.0), 5.0);
        assert_eq!(tick_step(100.0), 20.0);
        assert_eq!(tick_step(150.0), 50.0);
    }

    #[test]
    fn segments_tile_each_ring() {
        // Each ring's sectors cover 360 degrees, anterior centred on the top.
        for ring in 1..=3 {
            let total: f64 = (0..17)
                .map(place)
                .filter(|p| p.0 == ring)
                .map(|(_, a, b)| b - a)
                .sum();
            assert_eq!(total, 360.0);
        }
        for k in [0, 6, 12] {
            let (_, a, b) = place(k);
            assert_eq!((a + b) / 2.0, 90.0);
        }
        // Septum on the left: the anteroseptal/inferoseptal border and apical septal at 180.
        assert_eq!(place(1).2, 180.0);
        assert_eq!(place(7).2, 180.0);
        assert_eq!((place(13).1 + place(13).2) / 2.0, 180.0);
    }
}
