//! Stray contours: a small group of contours lying further from the rest of their surface than
//! the span of that rest (another series, a wrong coordinate or plane position, two curves of
//! another patient pasted in).
//!
//! The surface would be pulled towards them (one such contour 200 mm away costs ~10 ml and 9 mm of
//! contour distance, and the tube threaded through it makes the mesh pass through itself:
//! docs/VALIDATION.md, session 13), so a reconstruction leaves them out (`contours::set_aside`).
//!
//! Session 14's rule looked at one contour at a time (further from every other contour than the
//! span of the others), so two strays side by side hid each other, and it let a ring 85 mm from
//! a heart 90 mm long pass. The rule is now applied to groups: cut the contours' minimum spanning
//! tree (distance = gap between bounding boxes) at one edge; its weight is then the gap between
//! the two sides. The smaller side is stray when it is at most half the larger's size and that
//! gap exceeds both half the larger side's span and three times the median gap inside the larger
//! side (the data's own spacing). The size condition keeps two comparable halves (which side is
//! the heart?) both in. The tree is built on bounding-box gaps (cheap, a lower bound of the point
//! gaps); where a cut's box gap falls short of the span share, the gap between the two sides'
//! nearest points decides (session 23: an RV crescent's box is mostly empty, and two rings 89 mm
//! from its curves were 46 mm from its box, under half its 110 mm length, and were kept).

use super::Contour;
use crate::geometry::Vec3;
use crate::spatial::SegmentTree;

/// Above this many contours the check is skipped (it is quadratic, and a file that large is either
/// generated or hostile; `pipeline::prepare` refuses it anyway).
const MAX_CONTOURS: usize = 2000;

/// A group stands apart when its gap to the rest exceeds this share of the rest's span (half:
/// further than the heart's own half-length from any of its curves) ...
pub(crate) const SPAN_SHARE: f64 = 0.5;

/// ... and this many times the rest's own spacing, the median gap of its spanning tree (a slice
/// spacing; about zero where long-axis curves cross the rings; a median, so that strays further
/// in do not inflate it), so that a sparse stack's end slice is not taken for a stray.
const GAP_FACTOR: f64 = 3.0;

type Bounds = (Vec3, Vec3);

/// Axis-aligned bounds of a contour's points (None without points).
fn bounds(c: &Contour) -> Option<Bounds> {
    let mut pts = c.points();
    let first = *pts.next()?;
    Some(pts.fold((first, first), |(lo, hi), p| (lo.inf(p), hi.sup(p))))
}

/// Distance between two boxes (0 when they overlap); a lower bound of the points' distance.
fn box_gap(a: &Bounds, b: &Bounds) -> f64 {
    let d = (b.0 - a.1).sup(&(a.0 - b.1)).sup(&Vec3::zeros());
    d.norm()
}

/// Largest side of the union of some boxes (0 for none).
fn span<'a>(boxes: impl Iterator<Item = &'a Bounds>) -> f64 {
    boxes
        .copied()
        .reduce(|(lo, hi), (l, h)| (lo.inf(&l), hi.sup(&h)))
        .map_or(0.0, |(lo, hi)| (hi - lo).amax())
}

/// Smallest distance between a point of group `a`'s contours and one of group `b`'s (indices
/// into `members`): the true gap, which the boxes' gap only bounds from below. `b`'s points go
/// into a box tree (as zero-length segments), so a dense file costs a tree walk per point of `a`
/// rather than every pair.
fn point_gap(contours: &[Contour], members: &[(usize, Bounds)], a: &[usize], b: &[usize]) -> f64 {
    let points = |g: &[usize]| -> Vec<Vec3> {
        g.iter()
            .flat_map(|&i| contours[members[i].0].points().copied())
            .collect()
    };
    let (small, large) = {
        let (pa, pb) = (points(a), points(b));
        if pa.len() <= pb.len() {
            (pa, pb)
        } else {
            (pb, pa)
        }
    };
    let tree = SegmentTree::new(large.into_iter().map(|p| (p, p)).collect());
    small
        .iter()
        .map(|p| tree.distance(p))
        .fold(f64::INFINITY, f64::min)
}

/// Prim's minimum spanning tree over `boxes` (complete graph, box gaps) as edges `(a, b, gap)`.
fn spanning_tree(boxes: &[Bounds]) -> Vec<(usize, usize, f64)> {
    let n = boxes.len();
    let mut edges = Vec::with_capacity(n.saturating_sub(1));
    // For each vertex not yet in the tree: its smallest gap to the tree and the vertex at the
    // other end.
    let mut best: Vec<(f64, usize)> = vec![(f64::INFINITY, 0); n];
    let mut done = vec![false; n];
    let mut next = 0;
    for _ in 1..n {
        done[next] = true;
        let mut pick: Option<usize> = None;
        for v in (0..n).filter(|&v| !done[v]) {
            let g = box_gap(&boxes[next], &boxes[v]);
            if g < best[v].0 {
                best[v] = (g, next);
            }
            if pick.is_none_or(|p| best[v].0 < best[p].0) {
                pick = Some(v);
            }
        }
        let Some(v) = pick else { break };
        edges.push((best[v].1, v, best[v].0));
        next = v;
    }
    edges
}

/// The vertices reached from `from` over the tree's live edges, the edge `cut` excepted
/// (`adjacent[v]`: each neighbour of `v` in the tree and the index of the edge to it).
fn side_of(adjacent: &[Vec<(usize, usize)>], live: &[bool], cut: usize, from: usize) -> Vec<bool> {
    let mut seen = vec![false; adjacent.len()];
    seen[from] = true;
    let mut stack = vec![from];
    while let Some(v) = stack.pop() {
        for &(other, k) in &adjacent[v] {
            if k != cut && live[k] && !seen[other] {
                seen[other] = true;
                stack.push(other);
            }
        }
    }
    seen
}

/// Contours of one surface that are strays by the group rule above: each one's index and the gap
/// (mm, between the nearest points) from its group to the contours kept.
///
/// The groups are peeled off from the widest gap inwards: cutting the heaviest live edge of the
/// tree splits what is left in two, the smaller side goes if it is a stray group, and the larger
/// is examined again. The first cut whose smaller side stays ends it, so that two comparable
/// groups far apart are both kept whole rather than picked apart at a narrower gap.
pub fn strays(contours: &[Contour]) -> Vec<(usize, f64)> {
    let members: Vec<(usize, Bounds)> = contours
        .iter()
        .enumerate()
        .filter_map(|(i, c)| bounds(c).map(|b| (i, b)))
        .collect();
    let n = members.len();
    if !(3..=MAX_CONTOURS).contains(&n) {
        return Vec::new();
    }
    let boxes: Vec<Bounds> = members.iter().map(|(_, b)| *b).collect();
    let edges = spanning_tree(&boxes);
    let mut adjacent: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
    for (k, &(x, y, _)) in edges.iter().enumerate() {
        adjacent[x].push((y, k));
        adjacent[y].push((x, k));
    }
    let mut live = vec![true; edges.len()];
    let mut kept = vec![true; n];
    let mut gap_of: Vec<Option<f64>> = vec![None; n];
    loop {
        let heaviest = edges
            .iter()
            .enumerate()
            .filter(|(k, _)| live[*k])
            .max_by(|x, y| x.1 .2.total_cmp(&y.1 .2));
        let Some((cut, &(a, b, weight))) = heaviest else {
            break;
        };
        let side_a = side_of(&adjacent, &live, cut, a);
        let rest: Vec<usize> = (0..n).filter(|&v| kept[v]).collect();
        let (on_a, off_a): (Vec<usize>, Vec<usize>) = rest.iter().partition(|&&v| side_a[v]);
        let (small, large) = if on_a.len() <= off_a.len() {
            (on_a, off_a)
        } else {
            (off_a, on_a)
        };
        let large_span = span(large.iter().map(|&v| &boxes[v]));
        let in_large = |v: usize| kept[v] && side_a[v] == side_a[large[0]];
        let mut inside: Vec<f64> = edges
            .iter()
            .enumerate()
            .filter(|&(k, &(x, y, _))| k != cut && live[k] && in_large(x) && in_large(y))
            .map(|(_, e)| e.2)
            .collect();
        inside.sort_by(f64::total_cmp);
        let spacing = inside
            .get(inside.len().saturating_sub(1) / 2)
            .copied()
            .unwrap_or(0.0);
        if 2 * small.len() > large.len() || large_span <= 0.0 {
            break;
        }
        // The boxes' gap is a lower bound: where it falls short, the points' own gap decides (an
        // RV crescent's box is mostly empty, so two rings 90 mm from its curves are 46 mm from
        // its box).
        let needed = (SPAN_SHARE * large_span).max(GAP_FACTOR * spacing);
        let gap = if weight > SPAN_SHARE * large_span {
            weight
        } else if point_gap(contours, &members, &[a], &[b]) <= needed {
            // The two contours the cut parts are this close: so are the sides (an upper bound,
            // and the usual case, curves crossing or a slice apart: no tree to build).
            break;
        } else {
            point_gap(contours, &members, &small, &large)
        };
        let apart = gap > SPAN_SHARE * large_span && gap > GAP_FACTOR * spacing;
        if !apart {
            break;
        }
        for &v in &small {
            kept[v] = false;
            gap_of[v] = Some(gap);
        }
        // The tree's edges that touch the group go with it, and so does the cut.
        for (k, &(x, y, _)) in edges.iter().enumerate() {
            if !kept[x] || !kept[y] {
                live[k] = false;
            }
        }
        live[cut] = false;
    }
    members
        .iter()
        .zip(&gap_of)
        .filter_map(|((i, _), g)| g.map(|g| (*i, g)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contours::specks::fixtures;
    use crate::geometry::{v3, Vec3};

    /// A 24-point ring of radius `r` about `centre`, in a plane of constant z.
    fn ring(id: &str, centre: Vec3, r: f64) -> Contour {
        let mut c = fixtures::ring(id, r, centre.z, centre.x, 24, 2);
        for p in c.pieces.iter_mut().flat_map(|p| p.points.iter_mut()) {
            p.y += centre.y;
        }
        c
    }

    /// Crescents 10 mm apart (an RV's sections: arcs of radius 40 mm over +-60 degrees, closed
    /// across their chord), 11 of them: 100 mm long, each box 20 x 69 mm and mostly empty.
    fn crescents() -> Vec<Contour> {
        (0..11)
            .map(|k| {
                let z = 10.0 * k as f64;
                let points = (0..=24)
                    .map(|i| {
                        let t = (-60.0 + 5.0 * i as f64).to_radians();
                        v3(40.0 * t.cos(), 40.0 * t.sin(), z)
                    })
                    .collect();
                fixtures::contour(&format!("c{k}"), points, true, 2)
            })
            .collect()
    }

    /// Two rings in the crescents' concavity, 40 mm from the nearest crescent's box but 52 mm
    /// from its points (over half the 100 mm length): strays by their points, not by the boxes.
    #[test]
    fn the_nearest_points_decide_where_the_boxes_are_closer() {
        let mut contours = crescents();
        contours.push(ring("far0", v3(-25.0, 0.0, 40.0), 5.0));
        contours.push(ring("far1", v3(-25.0, 0.0, 50.0), 5.0));
        let found = strays(&contours);
        let ids: Vec<&str> = found
            .iter()
            .map(|(i, _)| contours[*i].id.as_str())
            .collect();
        assert_eq!(ids, ["far0", "far1"]);
        // The gap reported is the points': from the rings (radius 5 about (-25, 0)) to the arc's
        // tips at (20, +-34.6).
        let want = (45.0f64.powi(2) + (40.0 * 60f64.to_radians().sin()).powi(2)).sqrt() - 5.0;
        for (_, gap) in &found {
            assert!((gap - want).abs() < 0.5, "{gap} against {want}");
        }
        // Nearer in, their points within half the length: kept.
        let mut near = crescents();
        near.push(ring("n0", v3(-5.0, 0.0, 40.0), 5.0));
        near.push(ring("n1", v3(-5.0, 0.0, 50.0), 5.0));
        assert!(strays(&near).is_empty());
    }

    /// Five rings 10 mm apart, radius 25 (span 50 mm).
    fn stack() -> Vec<Contour> {
        (0..5)
            .map(|k| ring(&format!("s{k}"), v3(0.0, 0.0, 10.0 * k as f64), 25.0))
            .collect()
    }

    #[test]
    fn one_far_contour_is_a_stray_and_a_sparse_stack_is_not() {
        let mut set = stack();
        assert!(strays(&set).is_empty());
        // Three slices 30 mm apart: the end ones are 30 mm from the rest, whose span is 50 mm.
        let sparse: Vec<Contour> = (0..3)
            .map(|k| ring(&format!("t{k}"), v3(0.0, 0.0, 30.0 * k as f64), 25.0))
            .collect();
        assert!(strays(&sparse).is_empty());
        set.push(ring("stray", v3(200.0, 0.0, 0.0), 25.0));
        assert_eq!(strays(&set), vec![(5, 150.0)]);
    }

    #[test]
    fn two_strays_side_by_side_are_both_found() {
        // Session 14's rule missed these: each is 10 mm from the other.
        let mut set = stack();
        set.push(ring("far-a", v3(200.0, 0.0, 0.0), 25.0));
        set.push(ring("far-b", v3(200.0, 0.0, 10.0), 25.0));
        assert_eq!(strays(&set), vec![(5, 150.0), (6, 150.0)]);
        // A third further away the other way: all three, each with its own group's gap.
        set.push(ring("far-c", v3(0.0, -400.0, 0.0), 25.0));
        assert_eq!(strays(&set), vec![(5, 150.0), (6, 150.0), (7, 350.0)]);
    }

    #[test]
    fn two_comparable_groups_are_both_kept() {
        // Three rings and three rings 150 mm apart: neither side is a clear minority.
        let mut set: Vec<Contour> = stack().into_iter().take(3).collect();
        for k in 0..3 {
            set.push(ring(
                &format!("o{k}"),
                v3(200.0, 0.0, 10.0 * k as f64),
                25.0,
            ));
        }
        assert!(strays(&set).is_empty());
        // Two against four: the two are the strays.
        set.remove(5);
        set.insert(0, ring("s-1", v3(0.0, 0.0, -10.0), 25.0));
        assert_eq!(strays(&set), vec![(4, 150.0), (5, 150.0)]);
    }

    #[test]
    fn a_missing_slice_is_no_gap_but_a_ring_far_past_the_stack_is() {
        // Two apical rings below a stack of rings 10 mm apart (50 mm span), one slice missing
        // (20 mm): kept, 20 mm is under three slice spacings.
        let mut set = stack();
        set.push(ring("a0", v3(0.0, 0.0, -20.0), 10.0));
        set.push(ring("a1", v3(0.0, 0.0, -30.0), 8.0));
        assert!(strays(&set).is_empty());
        // A ring 40 mm past the top ring: 40 > 25 (half the span) and > 30 (three spacings).
        set.push(ring("past", v3(0.0, 0.0, 80.0), 25.0));
        assert_eq!(strays(&set), vec![(7, 40.0)]);
        // With a long-axis curve through every ring from a0 to the top (box gaps 0; span 70 mm)
        // the same ring is as far apart.
        let mut lax = fixtures::ring("lax", 25.0, 0.0, 0.0, 24, 2);
        for p in lax.pieces.iter_mut().flat_map(|p| p.points.iter_mut()) {
            (p.y, p.z) = (0.0, 5.0 + p.y * 1.4);
        }
        set.push(lax);
        assert_eq!(strays(&set), vec![(7, 40.0)]);
    }
}
