//! Specks: short-axis slices whose ring is a tiny fraction of the ring one slice away, anywhere
//! but at the apex.
//!
//! The initial tube runs through one ring per short-axis slice ([`super::rings::tube_rings`]).
//! A slice that holds only a speck (a 1-3 mm loop where a slice past the base grazes the rim, a
//! stray click of an automatic segmentation or a hurried delineation) makes the tube narrow to a
//! point there and the deformation never recovers: in the held-out study of session 13 a 3-point,
//! 2.8 mm loop 3-6 mm past the base of the spasm LV epicardium became the last tube ring 22 mm off
//! the axis (Hausdorff 1.7 -> 14.5 mm, volume -9.7 %; docs/VALIDATION.md, "Session 14: specks and
//! stray contours"). Only at the apex does a ventricle's section shrink to nothing (a slice
//! grazing the tip gives a ring of any size: the apical RV ring of biv-me patient 1 ES is a
//! 3-point, 8.5 mm loop, 0.11 of the ring above it and outside its outline), so the apical end of
//! the stack is never a speck. Which end is the apex is decided from the other slices' rings,
//! since a speck at the base of a short stack can flip the layout's own apex-to-base order
//! ([`super::axis::analyse`] orders by ring size).

use super::axis::Layout;
use super::clean::length;
use super::rings::join_pieces;
use super::{Contour, Polyline};

/// A slice's ring shorter than this fraction of the longer ring of its adjacent slices is a speck
/// (unless it is at the apex). Away from the apex a ventricle's section does not shrink to a tenth
/// within one slice gap: the smallest such ratio measured is 0.51 on the real files (SurFCo,
/// biv-me patients 1 and 2, ED and ES, every surface) and 0.22 over the 497 held-out acquisitions
/// of session 13 (the biv-me RV sliced into its outflow on a stack tilted 15 degrees), against 0.014
/// for the speck there. A ratio is used because cavities of every size (a child's RV, an adult's
/// LV epicardium) must be judged alike.
pub const SPECK_RATIO: f64 = 0.1;

/// The ring one slice gives the tube, with its slice and perimeter.
#[derive(Debug, Clone, PartialEq)]
pub struct SliceRing {
    /// Index of the slice in `Layout::slices` (apex to base as the layout ordered them).
    pub slice: usize,
    /// Points of the joined loop and its perimeter (mm).
    pub points: usize,
    pub perimeter_mm: f64,
    /// Height of the slice along the layout's axis (mm).
    pub height: f64,
}

/// A speck: its slice, and the adjacent slice whose ring it was measured against.
#[derive(Debug, Clone, PartialEq)]
pub struct Speck {
    pub ring: SliceRing,
    pub next: SliceRing,
}

impl Speck {
    /// Perimeter over the adjacent ring's.
    pub fn ratio(&self) -> f64 {
        self.ring.perimeter_mm / self.next.perimeter_mm
    }
}

/// The tube ring of every slice that has one (at least 3 points), in the layout's slice order.
pub fn slice_rings(contours: &[Contour], layout: &Layout) -> Vec<SliceRing> {
    layout
        .slices
        .iter()
        .enumerate()
        .filter_map(|(i, s)| {
            let pieces: Vec<&Polyline> = s
                .contours
                .iter()
                .filter_map(|&j| contours.get(j))
                .flat_map(|c| c.pieces.iter())
                .collect();
            let pts = join_pieces(&pieces);
            (pts.len() >= 3).then(|| SliceRing {
                slice: i,
                points: pts.len(),
                perimeter_mm: length(&pts, true),
                height: s.height,
            })
        })
        .collect()
}

/// The specks among the slices of `layout` (contours of one surface, cleaned), the most obvious
/// first: a speck next to another speck is measured against the ring beyond once the first is
/// set aside.
pub fn specks(contours: &[Contour], layout: &Layout) -> Vec<Speck> {
    let mut rings = slice_rings(contours, layout);
    let mut out = Vec::new();
    while let Some(k) = (0..rings.len()).find(|&k| speck_next(&rings, k).is_some()) {
        if let Some(next) = speck_next(&rings, k) {
            let ring = rings.remove(k);
            out.push(Speck { ring, next });
        }
    }
    out
}

/// The adjacent ring that makes `rings[k]` a speck, if it is one.
fn speck_next(rings: &[SliceRing], k: usize) -> Option<SliceRing> {
    let ring = rings.get(k)?;
    let next = [k.checked_sub(1), Some(k + 1)]
        .into_iter()
        .flatten()
        .filter_map(|j| rings.get(j))
        .max_by(|a, b| a.perimeter_mm.total_cmp(&b.perimeter_mm))?;
    if ring.perimeter_mm >= SPECK_RATIO * next.perimeter_mm {
        return None;
    }
    let at_end = k == 0 || k + 1 == rings.len();
    (!(at_end && at_apex(rings, k))).then(|| next.clone())
}

/// Whether the end ring `rings[k]` lies at the apex: the other rings shrink towards its end
/// (least-squares slope of perimeter against height). With fewer than two other rings, or no
/// slope, the apex cannot be told and the ring is kept.
fn at_apex(rings: &[SliceRing], k: usize) -> bool {
    let others: Vec<&SliceRing> = rings
        .iter()
        .enumerate()
        .filter(|(j, _)| *j != k)
        .map(|(_, r)| r)
        .collect();
    if others.len() < 2 {
        return true;
    }
    let n = others.len() as f64;
    let mh = others.iter().map(|r| r.height).sum::<f64>() / n;
    let mp = others.iter().map(|r| r.perimeter_mm).sum::<f64>() / n;
    let slope: f64 = others
        .iter()
        .map(|r| (r.height - mh) * (r.perimeter_mm - mp))
        .sum();
    let below = rings.get(k).is_some_and(|r| r.height < mh);
    // Rings growing with height put the apex low; shrinking, high.
    slope == 0.0 || (slope > 0.0) == below
}

/// Rings for the tests of this module and of `set_aside`: a circle of `n` points and a dome of
/// five of them, each contour's first line where a CSV of 60-point rings would put it.
#[cfg(test)]
pub(crate) mod fixtures {
    use crate::contours::{Contour, Polyline};
    use crate::geometry::{v3, Vec3};

    pub fn ring(id: &str, r: f64, z: f64, cx: f64, n: usize, line: usize) -> Contour {
        let points = (0..n)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / n as f64;
                v3(cx + r * t.cos(), r * t.sin(), z)
            })
            .collect();
        contour(id, points, true, line)
    }

    /// An LV_EPI contour of one piece.
    pub fn contour(id: &str, points: Vec<Vec3>, closed: bool, line: usize) -> Contour {
        Contour {
            id: id.into(),
            surface: Some("LV_EPI".into()),
            pieces: vec![Polyline { points, closed }],
            first_line: line,
        }
    }

    /// A dome: rings every 10 mm from a 12 mm apical ring to a 60 mm basal one (radii).
    pub fn dome() -> Vec<Contour> {
        [6.0, 12.0, 20.0, 26.0, 30.0]
            .iter()
            .enumerate()
            .map(|(k, &r)| ring(&format!("s{k}"), r, 10.0 * k as f64, 0.0, 60, 2 + 60 * k))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::fixtures::{dome, ring as ring_at};
    use super::*;
    use crate::contours::axis::analyse;

    fn ring(id: &str, r: f64, z: f64, cx: f64, n: usize) -> Contour {
        ring_at(id, r, z, cx, n, 2)
    }

    fn found(contours: &[Contour]) -> Vec<(usize, f64)> {
        let layout = analyse(contours).unwrap();
        specks(contours, &layout)
            .iter()
            .map(|s| (s.ring.slice, s.ratio()))
            .collect()
    }

    #[test]
    fn a_tiny_loop_past_the_base_is_a_speck_and_the_apex_is_not() {
        let mut c = dome();
        assert!(found(&c).is_empty());
        // A 3-point loop 0.5 mm across on the wall, 5 mm past the basal ring.
        c.push(ring("past", 0.5, 45.0, 29.0, 3));
        let f = found(&c);
        assert_eq!(f.len(), 1, "{f:?}");
        assert_eq!(f[0].0, 5);
        assert!(f[0].1 < 0.02, "{f:?}");
        // The same loop at the apex end, 0.07 of the apical ring, on the axis or off it: the tip
        // of the cavity.
        for cx in [0.0, 5.5] {
            let mut c = dome();
            c.push(ring("tip", 0.5, -5.0, cx, 3));
            let layout = analyse(&c).unwrap();
            let rings = slice_rings(&c, &layout);
            assert!(rings[0].perimeter_mm / rings[1].perimeter_mm < SPECK_RATIO);
            assert!(found(&c).is_empty());
        }
    }

    #[test]
    fn a_speck_that_flips_a_short_stack_is_still_found() {
        // Four rings (the apical one 10 mm) and a speck past the base: ordered by ring size the
        // layout may take the speck's end for the apex; the other rings say it is not.
        let mut c: Vec<Contour> = [5.0, 10.0, 15.0, 15.5]
            .iter()
            .enumerate()
            .map(|(k, &r)| ring(&format!("s{k}"), r, 10.0 * k as f64, 0.0, 60))
            .collect();
        c.push(ring("past", 0.25, 40.0, 15.0, 3));
        let f = found(&c);
        assert_eq!(f.len(), 1, "{f:?}");
        let layout = analyse(&c).unwrap();
        let s = &specks(&c, &layout)[0];
        assert!((s.ring.height.abs() - 40.0).abs() < 1e-9, "{s:?}");
    }

    #[test]
    fn two_specks_and_a_pinch_in_the_middle_are_found() {
        let mut c = dome();
        c.push(ring("past1", 0.4, 44.0, 29.0, 3));
        c.push(ring("past2", 0.4, 49.0, 28.0, 3));
        assert_eq!(found(&c).len(), 2);
        let mut c = dome();
        c[2] = ring("s2", 0.8, 20.0, 5.0, 4);
        let f = found(&c);
        assert_eq!(f.len(), 1);
        assert_eq!(f[0].0, 2);
    }

    #[test]
    fn small_rings_that_are_a_tenth_or_more_are_kept() {
        // A basal ring a fifth of the one below it (an outflow tract cut past the base).
        let mut c = dome();
        c.push(ring("outflow", 6.0, 45.0, 20.0, 20));
        assert!(found(&c).is_empty());
    }
}
