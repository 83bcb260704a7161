//! The automatic attractor count: the paper's max(150, 25 x contours), with the slices of a
//! dense stack counted at the spacing the paper's count assumes.
//!
//! Twenty-five attractors per contour put them about a twenty-fifth of a ring apart along each
//! curve (the in-plane spacing, s). Cine stacks are 8-10 mm apart, wider than s, and the count
//! then samples the surface about as finely across the slices as along them. A stack resliced
//! from a 3D segmentation every 1-2 mm has ten times the slices of the same heart, and the count
//! grows with them while the surface it describes does not: the patient-1-sized CAP atlas mean
//! at 1 mm has 2112 attractors instead of 325, and the spline's solve, cubic in the count, takes
//! 12 s of a 13 s run (55 s in the browser) for no measurable gain (docs/VALIDATION.md, session
//! 16). So short-axis slices closer than s / 2 count as if they were s / 2 apart: the attractors
//! are never more than twice as dense across the slices as the paper's along them. A stack whose
//! slices are s / 2 or more apart (every cine acquisition measured) keeps the paper's count.

use crate::contours::axis::Layout;
use crate::contours::clean::length;
use crate::contours::{Contour, ContourKind};

/// The paper's attractors per contour.
pub const PER_CONTOUR: usize = 25;
/// The paper's fewest automatic attractors.
pub const MIN_AUTO: usize = 150;

/// The automatic attractor count of `contours` (laid out as `layout`), at most `max`.
pub fn auto_attractors(contours: &[Contour], layout: &Layout, max: usize) -> usize {
    let sax = layout
        .kinds
        .iter()
        .filter(|k| **k == ContourKind::Sax)
        .count();
    let others = contours.len().saturating_sub(sax);
    let counted = others as f64 + sax as f64 * dense_stack_factor(contours, layout);
    ((PER_CONTOUR as f64 * counted).ceil() as usize).clamp(MIN_AUTO, max.max(MIN_AUTO))
}

/// The share of a short-axis stack's slices the count takes: 1 when the median gap between
/// neighbouring slices is at least half the in-plane attractor spacing (the median ring's
/// length / 25), else the gap over that half spacing.
pub fn dense_stack_factor(contours: &[Contour], layout: &Layout) -> f64 {
    let mut rings: Vec<f64> = layout
        .slices
        .iter()
        .map(|s| {
            s.contours
                .iter()
                .filter_map(|&i| contours.get(i))
                .flat_map(|c| &c.pieces)
                .map(|p| length(&p.points, p.closed))
                .sum::<f64>()
        })
        .filter(|l| *l > 0.0)
        .collect();
    let mut gaps: Vec<f64> = layout
        .slices
        .windows(2)
        .map(|w| (w[1].height - w[0].height).abs())
        .collect();
    let (Some(ring), Some(gap)) = (median(&mut rings), median(&mut gaps)) else {
        return 1.0;
    };
    let half_spacing = ring / PER_CONTOUR as f64 / 2.0;
    if !(gap > 0.0 && half_spacing > 0.0) || gap >= half_spacing {
        1.0
    } else {
        gap / half_spacing
    }
}

fn median(v: &mut [f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contours::axis::analyse;
    use crate::contours::{Contour, Polyline};
    use crate::geometry::v3;

    /// Rings of radius `r` every `gap` mm over 80 mm, plus two long-axis curves.
    fn stack(r: f64, gap: f64) -> Vec<Contour> {
        let mut out = Vec::new();
        let n = (80.0 / gap).round() as usize + 1;
        for k in 0..n {
            let z = k as f64 * gap;
            let pts = (0..60)
                .map(|i| {
                    let t = i as f64 / 60.0 * std::f64::consts::TAU;
                    v3(r * t.cos(), r * t.sin(), z)
                })
                .collect();
            out.push(contour(&format!("s{k}"), pts, true));
        }
        for (j, a) in [0.0f64, 1.5].iter().enumerate() {
            // A U through the axis: down one side of the stack and up the other.
            let pts = (0..=40)
                .map(|i| {
                    let u = i as f64 / 20.0 - 1.0;
                    v3(u * r * a.cos(), u * r * a.sin(), 80.0 * u * u)
                })
                .collect();
            out.push(contour(&format!("l{j}"), pts, false));
        }
        out
    }

    fn contour(id: &str, points: Vec<crate::geometry::Vec3>, closed: bool) -> Contour {
        Contour {
            id: id.into(),
            surface: None,
            pieces: vec![Polyline { points, closed }],
            first_line: 1,
        }
    }

    #[test]
    fn cine_stacks_keep_the_papers_count_and_dense_ones_count_slices_at_half_the_spacing() {
        // A 60-gon of radius 20 mm: 125.6 mm round, attractors 5.0 mm apart along it.
        let half_spacing = 120.0 * 20.0 * (std::f64::consts::PI / 60.0).sin() / 50.0;
        for (gap, slices) in [(10.0, 9), (2.6, 32), (2.0, 41), (1.0, 81)] {
            let set = stack(20.0, gap);
            let layout = analyse(&set).unwrap();
            let factor = f64::min(1.0, gap / half_spacing);
            let f = dense_stack_factor(&set, &layout);
            assert!(
                (f - factor).abs() < 1e-9,
                "{gap} mm: factor {f}, not {factor}"
            );
            let count = (25.0 * (2.0 + slices as f64 * factor)).ceil() as usize;
            assert_eq!(auto_attractors(&set, &layout, 5000), count, "{gap} mm");
        }
        assert!(half_spacing > 2.5 && half_spacing < 2.6);
        // The paper's floor and the cap still hold.
        let few = stack(20.0, 40.0);
        assert_eq!(auto_attractors(&few, &analyse(&few).unwrap(), 5000), 150);
        let set = stack(20.0, 1.0);
        assert_eq!(auto_attractors(&set, &analyse(&set).unwrap(), 400), 400);
    }

    #[test]
    fn every_real_acquisition_keeps_the_papers_count() {
        use crate::deform::attractors::Budget;
        use crate::pipeline::Reconstruction;
        use crate::Params;
        let files = [
            ("contours/surfco-example.csv", vec![None]),
            (
                "contours/bivme-example-patient1/patient1-ED.csv",
                vec![
                    Some("LV_ENDO"),
                    Some("LV_EPI"),
                    Some("RV_ENDO"),
                    Some("RV_EPI"),
                ],
            ),
            (
                "contours/bivme-test-patient2/patient2-ES.csv",
                vec![Some("LV_ENDO"), Some("LV_EPI"), Some("RV_ENDO")],
            ),
        ];
        for (file, surfaces) in files {
            let set = crate::io::read_contours(file, &crate::io::sample(file)).unwrap();
            for surface in surfaces {
                let params = Params {
                    surface: surface.map(str::to_string),
                    ..Params::default()
                };
                let rec = Reconstruction::new(&set, params).unwrap();
                let paper = (25 * rec.contours.len()).clamp(150, 5000);
                assert_eq!(
                    rec.attractor_budget,
                    Budget::Count(paper),
                    "{file} {surface:?}"
                );
            }
        }
    }

    #[test]
    fn the_rule_does_not_depend_on_the_units_scale() {
        // A mouse heart (a tenth of the size, slices a tenth as far apart) counts the same.
        let big = stack(20.0, 1.0);
        let small: Vec<Contour> = big
            .iter()
            .map(|c| {
                let pts = c.points().map(|p| p * 0.1).collect();
                contour(&c.id, pts, c.pieces[0].closed)
            })
            .collect();
        let (a, b) = (analyse(&big).unwrap(), analyse(&small).unwrap());
        assert_eq!(
            auto_attractors(&big, &a, 5000),
            auto_attractors(&small, &b, 5000)
        );
    }
}
