//! A surface's contours as every look at them before fitting sees them: cleaned, with their
//! damaged pieces left out (far from the rest of their surface, [`super::far_pieces`]; off their
//! contour's plane, [`super::off_plane`]), and each contour that lost any read again from its
//! rows without those points.
//!
//! Read again rather than merely without the piece: the damaged rows took the jumps with them,
//! so the curve reads as if they had never been in the file. Left out as a piece, a damaged row
//! at the wrap of a curve stored from its middle (biv-me's long-axis free walls start mid-curve
//! and close back on their first row) kept the curve cut in two there: the last two rows of
//! biv-me patient 1 ES's `s08_LAX_RV_FREEWALL` moved 13 mm left an 8 mm gap between its two
//! halves that the rows' own spacing would have bridged, and the RV came out 74.2 ml against
//! 71.3 with those two rows deleted (71.6 intact). A damaged stretch of a closed ring likewise
//! left the ring open.

use std::collections::HashSet;

use super::clean::{cleaned_contour, cleaned_contours};
use super::far_pieces::take_far_pieces;
use super::off_plane::take_off_plane_pieces;
use super::{Contour, Polyline};
use crate::geometry::Vec3;

/// The cleaned contours of `contours` (any surfaces, each judged on its own) without their
/// damaged pieces, with, for each, its index in `contours` (those left empty by cleaning are
/// dropped). Far pieces are judged first, then off-plane ones on what is left, the order in which
/// the warnings name them.
pub fn cleaned_undamaged(contours: &[&Contour]) -> (Vec<usize>, Vec<Contour>) {
    let (index, mut cleaned) = cleaned_contours(contours);
    let far = take_far_pieces(&mut cleaned);
    let off = take_off_plane_pieces(&mut cleaned);
    for (k, c) in cleaned.iter_mut().enumerate() {
        let gone: HashSet<[u64; 3]> = far[k]
            .iter()
            .map(|f| &f.points)
            .chain(off[k].iter().map(|o| &o.points))
            .flatten()
            .map(key)
            .collect();
        if gone.is_empty() {
            continue;
        }
        let Some(raw) = index.get(k).and_then(|&i| contours.get(i)) else {
            continue;
        };
        if let Some(again) = cleaned_contour(&without(raw, &gone)) {
            *c = again;
        }
    }
    (index, cleaned)
}

/// `raw` without every point whose coordinates `gone` holds: cleaning only drops points, so a
/// cleaned piece's points are the rows' own values, bit for bit.
fn without(raw: &Contour, gone: &HashSet<[u64; 3]>) -> Contour {
    Contour {
        pieces: raw
            .pieces
            .iter()
            .map(|p| Polyline {
                points: p
                    .points
                    .iter()
                    .filter(|q| !gone.contains(&key(q)))
                    .copied()
                    .collect(),
                closed: p.closed,
            })
            .collect(),
        ..raw.clone()
    }
}

fn key(p: &Vec3) -> [u64; 3] {
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    fn contour(id: &str, points: Vec<Vec3>, closed: bool) -> Contour {
        Contour {
            id: id.into(),
            surface: None,
            pieces: vec![Polyline { points, closed }],
            first_line: 0,
        }
    }

    /// `n` points at 2 mm steps round a circle of radius 30 at height `z`.
    fn arc(n: usize, z: f64) -> Vec<Vec3> {
        (0..n)
            .map(|i| {
                let a = i as f64 * 2.0 / 30.0;
                v3(30.0 * a.cos(), 30.0 * a.sin(), z)
            })
            .collect()
    }

    /// A closed ring of 90 points (2.09 mm apart) of radius 30 at height `z`.
    fn ring(z: f64) -> Vec<Vec3> {
        (0..90)
            .map(|i| {
                let a = i as f64 * std::f64::consts::TAU / 90.0;
                v3(30.0 * a.cos(), 30.0 * a.sin(), z)
            })
            .collect()
    }

    fn with_others(damaged: &Contour, others: &[Contour]) -> (Vec<usize>, Vec<Contour>) {
        let mut all: Vec<&Contour> = vec![damaged];
        all.extend(others.iter());
        cleaned_undamaged(&all)
    }

    #[test]
    fn a_ring_that_loses_damaged_rows_stays_one_closed_ring() {
        // Rows 40-42 of a ring 12 mm out of its plane: a jump out and one back (over 5 x 2.09
        // mm), too blunt for a spike (the rows either side lie 8.4 mm apart), a piece off the
        // plane of the rest.
        let mut rows = ring(0.0);
        for p in &mut rows[40..43] {
            p.z += 12.0;
        }
        let damaged = contour("s0", rows, true);
        let others: Vec<Contour> = (1..4)
            .map(|s| contour(&format!("s{s}"), ring(-10.0 * s as f64), true))
            .collect();
        let (index, cleaned) = with_others(&damaged, &others);
        assert_eq!(index, vec![0, 1, 2, 3]);
        let pieces = &cleaned[0].pieces;
        assert_eq!(pieces.len(), 1, "{pieces:?}");
        assert!(pieces[0].closed);
        assert_eq!(pieces[0].points.len(), 87);
        assert!(pieces[0].points.iter().all(|p| p.z == 0.0));
        // Left out as a piece only, the ring was open where the rows were.
        let mut all: Vec<&Contour> = vec![&damaged];
        all.extend(others.iter());
        let (_, mut pieces_only) = cleaned_contours(&all);
        take_off_plane_pieces(&mut pieces_only);
        assert_eq!(pieces_only[0].pieces.len(), 1);
        assert!(!pieces_only[0].pieces[0].closed);
    }

    #[test]
    fn an_open_curve_stored_from_its_middle_closes_over_its_wrap_again() {
        // An open arc of 40 points stored from its 30th: rows 30..40 then 0..30, a closed
        // polyline (its last row is its first's neighbour) with one jump, the arc's own gap.
        let full = arc(40, 0.0);
        let mut rows: Vec<Vec3> = full[30..].to_vec();
        rows.extend_from_slice(&full[..30]);
        // The last two rows 11 mm out of the plane: blunt, a jump from either neighbour.
        let n = rows.len();
        for p in &mut rows[n - 2..] {
            p.z += 11.0;
        }
        let damaged = contour("lax", rows, true);
        let others: Vec<Contour> = (1..4)
            .map(|s| contour(&format!("s{s}"), arc(40, -10.0 * s as f64), false))
            .collect();
        let (_, cleaned) = with_others(&damaged, &others);
        let pieces = &cleaned[0].pieces;
        assert_eq!(pieces.len(), 1, "{pieces:?}");
        // One curve from the arc's start through the file's wrap to its end, rows 28-29 missing.
        assert_eq!(pieces[0].points.len(), 38);
        assert_eq!(pieces[0].points[0], full[0]);
        assert_eq!(pieces[0].points[27], full[27]);
        assert_eq!(pieces[0].points[28], full[30]);
        assert_eq!(pieces[0].points[37], full[39]);
    }
}
