//! A load-time check: closed loops of one surface that share a short-axis slice but lie apart.
//!
//! The method reconstructs one cavity per surface: the initial tube follows one loop per slice
//! (the longest closed one, [`super::rings::join_pieces`]), yet every contour point is an
//! attractor. A second loop beside the first in the same slice (a basal slice that also cuts the
//! outflow tract, an RV body and its outflow, a structure drawn with the wrong label) therefore
//! pulls a spike or a membrane out of the surface towards it without any message: in the held-out
//! study of session 13 a 10 mm loop 30 mm beside the basal LV ring of the CAP LV moved the
//! Hausdorff distance from 0.5 to 27 mm while the contour-to-mesh mean stayed 0.07 mm
//! (docs/VALIDATION.md, "Session 13: held-out acquisitions"). The run goes ahead (the user may want
//! exactly that); the warning says which loop and how far it lies from the one the tube follows.

use super::axis::{analyse, Layout};
use super::checks::surface_groups;
use super::clean::{cleaned_contour, length};
use super::plane::fit_plane;
use super::set_aside::set_aside;
use super::{Contour, ContourSet, Polyline};
use crate::geometry::Vec3;
use crate::spatial::segments::segment_distance_sq;

/// A loop whose points lie, at the median, further than this (mm) from the slice's main loop is
/// a second loop: three times the 1-5 mm segmentation disagreement of METHOD.md would be 3-15;
/// this is the low end, since two delineations of one wall (a duplicate, a redrawn ring) lie
/// within about 1 mm of each other while anything a tube cannot follow lies well beyond 3 mm.
const SECOND_LOOP_MM: f64 = 3.0;

/// Above this many contours per surface the check is skipped (the layout is quadratic in the
/// number of contours; such files are generated or hostile).
const MAX_CONTOURS: usize = 2000;

/// The cleaned contours of each surface a load-time check looks at, with their layout: loops a
/// reconstruction leaves out (specks, strays) are named by their own warning, so set aside here.
fn surface_layouts(set: &ContourSet) -> Vec<(Vec<Contour>, Layout)> {
    surface_groups(set)
        .into_iter()
        .filter(|surface| (2..=MAX_CONTOURS).contains(&surface.len()))
        .filter_map(|surface| {
            let cleaned: Vec<Contour> = surface.iter().filter_map(|c| cleaned_contour(c)).collect();
            let (cleaned, _) = set_aside(cleaned);
            let layout = analyse(&cleaned).ok()?;
            Some((cleaned, layout))
        })
        .collect()
}

/// One warning line naming the closed loops that lie apart from the main loop of their slice.
pub fn second_loop_warnings(set: &ContourSet) -> Vec<String> {
    let mut flagged: Vec<String> = Vec::new();
    for (cleaned, layout) in surface_layouts(set) {
        for apart in second_loops(&cleaned, &layout) {
            let (Some(c), Some(main)) = (cleaned.get(apart.contour), cleaned.get(apart.main))
            else {
                continue;
            };
            flagged.push(c.cite(&format!("{:.0} mm from {:?}", apart.gap_mm, main.id)));
        }
    }
    match flagged.as_slice() {
        [] => Vec::new(),
        [one] => vec![format!(
            "contour {one} is a second closed loop in a short-axis slice: a surface is one \
             cavity, so the surface is pulled out towards it; another structure? Give it its own \
             surface label"
        )],
        more => {
            let shown: Vec<&str> = more.iter().take(3).map(String::as_str).collect();
            let rest = if more.len() > 3 { "; ..." } else { "" };
            vec![format!(
                "{} contours ({}{rest}) are second closed loops in short-axis slices: a surface \
                 is one cavity, so the surface is pulled out towards them; other structures? Give \
                 them their own surface label",
                more.len(),
                shown.join("; ")
            )]
        }
    }
}

/// Whether `warning` is the line [`second_loop_warnings`] writes: front ends add a note on the
/// option that leaves such loops out (`Params::drop_second_loops`), in their own words.
pub fn is_second_loop_warning(warning: &str) -> bool {
    warning.contains("is a second closed loop in a short-axis slice")
        || warning.contains("are second closed loops in short-axis slices")
}

/// A closed loop lying apart from the main loop of its slice.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ApartLoop {
    /// Index of its contour and of its piece in that contour.
    pub contour: usize,
    pub piece: usize,
    /// Index of the contour holding the slice's main (longest closed) loop.
    pub main: usize,
    /// Median distance of its points from the main loop (mm).
    pub gap_mm: f64,
}

/// The closed loops of `contours` (one surface, cleaned, `layout` from [`analyse`]) that lie
/// more than [`SECOND_LOOP_MM`] from the longest closed loop of their slice.
pub fn second_loops(contours: &[Contour], layout: &Layout) -> Vec<ApartLoop> {
    other_loops(contours, layout)
        .into_iter()
        .filter(|l| l.gap_mm > SECOND_LOOP_MM)
        .collect()
}

/// The closed loops of other contours that trace the main loop of their slice again, within
/// [`SECOND_LOOP_MM`] at the median but not point for point (exact copies have their own
/// warning): two images of one slice position, both delineated (biv-me's test patient 1, slices
/// 18 and 19), or a ring drawn twice. The tube follows one, the spline is pulled by both and
/// settles between them, so the user should know the slice counts twice.
pub fn repeated_loops(contours: &[Contour], layout: &Layout) -> Vec<ApartLoop> {
    let piece = |j: usize, k: usize| contours.get(j).and_then(|c| c.pieces.get(k));
    let main_piece = |l: &ApartLoop| {
        contours
            .get(l.main)?
            .pieces
            .iter()
            .filter(|p| p.closed && p.points.len() >= 3)
            .max_by(|a, b| length(&a.points, true).total_cmp(&length(&b.points, true)))
    };
    other_loops(contours, layout)
        .into_iter()
        .filter(|l| l.gap_mm <= SECOND_LOOP_MM && l.contour != l.main)
        .filter(|l| match (contours.get(l.contour), contours.get(l.main)) {
            (Some(c), Some(m)) => !c.points().eq(m.points()),
            _ => false,
        })
        .filter(|l| match (piece(l.contour, l.piece), main_piece(l)) {
            (Some(p), Some(main)) => {
                in_one_plane(&p.points, &main.points) && traces_most_of(&p.points, &main.points)
            }
            _ => false,
        })
        .collect()
}

/// Whether a loop is long enough to be the ring again: a second image of the slice or a ring
/// drawn twice runs all the way round (its length within the few tens of percent a breath-hold
/// changes), whereas a short closed piece beside the ring (a few points of a septum piece where
/// a thin basal crescent narrows) is part of it, not a repeat.
fn traces_most_of(points: &[Vec3], ring: &[Vec3]) -> bool {
    length(points, true) >= 0.5 * length(ring, true)
}

/// Planes closer than this (mm, plus three times the main loop's own residual) are one image
/// plane. Two images of one slice position share their plane exactly (a breath-hold moves the
/// heart, not the plane), so their curves lie in it up to rounding; neighbouring slices of the
/// densest stacks are 1 mm apart and fall in one slice of the layout (its tolerance is 1.5 mm),
/// so the gap along the normal, not the layout, tells a repeat from a neighbour.
const SAME_PLANE_MM: f64 = 0.25;

/// Whether `points` lie in the plane of `ring` (their centroid's distance from it).
fn in_one_plane(points: &[Vec3], ring: &[Vec3]) -> bool {
    let (Some(plane), false) = (fit_plane(ring.iter()), points.is_empty()) else {
        return false;
    };
    let centroid = points.iter().fold(Vec3::zeros(), |a, p| a + p) / points.len() as f64;
    (centroid - plane.centroid).dot(&plane.normal).abs() <= SAME_PLANE_MM + 3.0 * plane.rms_residual
}

/// Every closed loop of each slice but the slice's longest, with its median distance from it.
fn other_loops(contours: &[Contour], layout: &Layout) -> Vec<ApartLoop> {
    let mut out = Vec::new();
    for slice in &layout.slices {
        let loops: Vec<(usize, usize, &Polyline)> = slice
            .contours
            .iter()
            .filter_map(|&j| contours.get(j).map(|c| (j, c)))
            .flat_map(|(j, c)| c.pieces.iter().enumerate().map(move |(k, p)| (j, k, p)))
            .filter(|(_, _, p)| p.closed && p.points.len() >= 3)
            .collect();
        let Some(&(main_j, main_k, main)) = loops
            .iter()
            .max_by(|a, b| length(&a.2.points, true).total_cmp(&length(&b.2.points, true)))
        else {
            continue;
        };
        for &(j, k, p) in &loops {
            if (j, k) != (main_j, main_k) {
                out.push(ApartLoop {
                    contour: j,
                    piece: k,
                    main: main_j,
                    gap_mm: median_distance(&p.points, &main.points),
                });
            }
        }
    }
    out
}

/// One warning line naming the contours that repeat another's loop in its slice
/// ([`repeated_loops`]).
pub fn repeated_loop_warnings(set: &ContourSet) -> Vec<String> {
    let mut pairs: Vec<(String, f64)> = Vec::new();
    for (cleaned, layout) in surface_layouts(set) {
        for again in repeated_loops(&cleaned, &layout) {
            let (Some(c), Some(main)) = (cleaned.get(again.contour), cleaned.get(again.main))
            else {
                continue;
            };
            let pair = format!("{} and {}", main.cite(""), c.cite(""));
            pairs.push((pair, again.gap_mm));
        }
    }
    const ADVICE: &str = "two images of one slice position, or a ring drawn twice? Both are \
                          used and the surface settles between them; remove one if that is not \
                          meant";
    match pairs.as_slice() {
        [] => Vec::new(),
        [(pair, gap)] => vec![format!(
            "contours {pair} trace one wall in one short-axis slice ({gap:.1} mm apart at the \
             median): {ADVICE}"
        )],
        more => {
            let shown: Vec<String> = more
                .iter()
                .take(3)
                .map(|(pair, gap)| format!("{pair}, {gap:.1} mm"))
                .collect();
            let rest = if more.len() > 3 { "; ..." } else { "" };
            vec![format!(
                "{} pairs of contours trace one wall in one short-axis slice each ({}{rest}): \
                 {ADVICE}",
                more.len(),
                shown.join("; ")
            )]
        }
    }
}

/// `contours` without the loops [`second_loops`] finds (contours left without a piece are
/// dropped), and how many loops went. Behind `Params::drop_second_loops` (CLI
/// `--drop-second-loops`; off by default): the surface then follows the main loop of each slice
/// only, for when the other loop is another structure.
pub fn without_second_loops(contours: &[Contour], layout: &Layout) -> (Vec<Contour>, usize) {
    let apart = second_loops(contours, layout);
    let kept = contours
        .iter()
        .enumerate()
        .filter_map(|(j, c)| {
            let pieces: Vec<Polyline> = c
                .pieces
                .iter()
                .enumerate()
                .filter(|(k, _)| !apart.iter().any(|a| (a.contour, a.piece) == (j, *k)))
                .map(|(_, p)| p.clone())
                .collect();
            (!pieces.is_empty()).then(|| Contour {
                pieces,
                ..c.clone()
            })
        })
        .collect();
    (kept, apart.len())
}

/// Median over `points` of the distance to the closed polyline `ring` (mm).
fn median_distance(points: &[Vec3], ring: &[Vec3]) -> f64 {
    let mut d: Vec<f64> = points.iter().map(|q| distance_to_ring(q, ring)).collect();
    if d.is_empty() {
        return 0.0;
    }
    d.sort_by(f64::total_cmp);
    d[d.len() / 2]
}

fn distance_to_ring(q: &Vec3, ring: &[Vec3]) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|i| segment_distance_sq(q, &ring[i], &ring[(i + 1) % n]))
        .fold(f64::INFINITY, f64::min)
        .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    fn ring(id: &str, cx: f64, r: f64, z: f64, line: usize) -> Contour {
        let points = (0..40)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / 40.0;
                v3(cx + r * t.cos(), r * t.sin(), z)
            })
            .collect();
        Contour {
            id: id.into(),
            surface: Some("LV_ENDO".into()),
            pieces: vec![Polyline {
                points,
                closed: true,
            }],
            first_line: line,
        }
    }

    fn stack() -> Vec<Contour> {
        (0..5)
            .map(|k| ring(&format!("s{k}"), 0.0, 20.0, 10.0 * k as f64, 2 + 40 * k))
            .collect()
    }

    #[test]
    fn a_loop_beside_the_basal_ring_is_named_with_its_distance() {
        let mut contours = stack();
        // A 6 mm loop whose centre lies 32 mm from the axis: 13 mm outside the 20 mm ring at the median.
        contours.push(ring("s4b", 32.0, 6.0, 40.0, 202));
        let set = ContourSet {
            contours,
            ..Default::default()
        };
        let w = second_loop_warnings(&set);
        assert!(w.iter().all(|line| is_second_loop_warning(line)), "{w:?}");
        assert_eq!(w.len(), 1);
        assert!(
            w[0].starts_with("contour \"s4b\" (line 202, 13 mm from \"s4\") is a second"),
            "{w:?}"
        );
    }

    #[test]
    fn without_second_loops_keeps_every_other_curve() {
        let mut contours = stack();
        contours.push(ring("s4b", 32.0, 6.0, 40.0, 202));
        let mut two_pieces = ring("s2", 0.0, 20.0, 20.0, 82);
        two_pieces
            .pieces
            .push(ring("x", -30.0, 5.0, 20.0, 0).pieces.remove(0));
        contours[2] = two_pieces;
        let layout = analyse(&contours).unwrap();
        let (kept, dropped) = without_second_loops(&contours, &layout);
        assert_eq!(dropped, 2);
        let ids: Vec<&str> = kept.iter().map(|c| c.id.as_str()).collect();
        assert_eq!(ids, ["s0", "s1", "s2", "s3", "s4"]);
        assert_eq!(kept[2].pieces.len(), 1);
        assert_eq!(kept[2].pieces[0], contours[2].pieces[0]);
    }

    /// Two images of one slice position, both delineated: named once, with the gap; an exact
    /// copy is left to the duplicate warning, a ring in another slice is not a repeat.
    #[test]
    fn a_ring_traced_twice_in_one_slice_is_named() {
        let mut contours = stack();
        contours.push(ring("s3again", 0.8, 20.5, 30.0, 340));
        // A neighbouring slice 1 mm away (a dense stack) shares the layout's slice, not the plane.
        contours.push(ring("s1next", 0.3, 20.2, 11.0, 380));
        contours.push(ring("s2copy", 0.0, 20.0, 20.0, 300));
        let set = ContourSet {
            contours,
            ..Default::default()
        };
        let w = repeated_loop_warnings(&set);
        assert_eq!(w.len(), 1, "{w:?}");
        // The longer ring is the slice's main loop and is named first.
        assert!(
            w[0].starts_with(
                "contours \"s3again\" (line 340) and \"s3\" (line 122) trace one wall in one \
                 short-axis slice (0.4 mm apart at the median): two images"
            ),
            "{w:?}"
        );
        assert!(repeated_loop_warnings(&ContourSet {
            contours: stack(),
            ..Default::default()
        })
        .is_empty());
    }

    /// A short closed piece lying on the ring (the few septum points of a thin basal RV
    /// crescent, biv-me's automated contours) is part of it, not a second image of the slice.
    #[test]
    fn a_short_loop_on_the_ring_is_no_repeat() {
        let mut contours = stack();
        contours.push(ring("s3piece", 19.0, 1.5, 30.0, 340));
        let set = ContourSet {
            contours,
            ..Default::default()
        };
        assert!(repeated_loop_warnings(&set).is_empty());
    }

    #[test]
    fn copies_redrawn_rings_and_separate_slices_are_not_flagged() {
        let mut contours = stack();
        contours.push(ring("s2copy", 0.0, 20.0, 20.0, 300)); // a duplicate: 0 mm
        contours.push(ring("s3redrawn", 0.8, 20.5, 30.0, 340)); // redrawn: within 1.3 mm
        let set = ContourSet {
            contours,
            ..Default::default()
        };
        assert!(second_loop_warnings(&set).is_empty());
        // Each surface is its own cavity: an RV ring beside every LV ring is not a second loop.
        let mut contours = stack();
        for k in 0..5 {
            let mut rv = ring(&format!("rv{k}"), 45.0, 15.0, 10.0 * k as f64, 500 + k);
            rv.surface = Some("RV_ENDO".into());
            contours.push(rv);
        }
        let set = ContourSet {
            contours,
            ..Default::default()
        };
        assert!(second_loop_warnings(&set).is_empty());
    }
}
