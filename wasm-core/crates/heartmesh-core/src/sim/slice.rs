//! Plane sections of triangle meshes: what a scanner "sees" of a reference shape in one image plane.
//!
//! Classic marching-triangles sectioning (e.g. Lorensen & Cline 1987 in 2D form): every triangle whose
//! vertices lie on both sides of the plane contributes one segment between two crossed edges, and
//! segments sharing a mesh edge are chained. Vertices exactly on the plane are treated as lying
//! strictly above it (a symbolic perturbation in the spirit of Edelsbrunner & Muecke's "simulation
//! of simplicity", 1990), so every crossed triangle has exactly two crossed edges and no degenerate
//! case needs special handling; the resulting duplicate points are merged afterwards.

use crate::contours::Polyline;
use crate::geometry::Vec3;
use crate::mesh::TriMesh;
use std::collections::HashMap;

/// An oriented plane: points `p` with `normal . (p - origin) = 0`. `normal` need not be unit length
/// on input to [`Plane::new`], which normalises it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    pub origin: Vec3,
    pub normal: Vec3,
}

impl Plane {
    /// None when the normal is zero or not finite.
    pub fn new(origin: Vec3, normal: Vec3) -> Option<Plane> {
        let n = normal.norm();
        if !(n.is_finite() && n > 0.0 && origin.iter().all(|c| c.is_finite())) {
            return None;
        }
        Some(Plane {
            origin,
            normal: normal / n,
        })
    }

    /// Signed distance in mm (positive on the side the normal points to).
    #[inline]
    pub fn signed_distance(&self, p: &Vec3) -> f64 {
        self.normal.dot(&(p - self.origin))
    }
}

/// Sections `mesh` with `plane`: closed loops where the section is closed, open chains where it runs
/// into the mesh boundary. Loops are oriented counter-clockwise about the plane normal; they do not
/// repeat their first point. Pieces with fewer than two distinct points are dropped.
pub fn slice_mesh(mesh: &TriMesh, plane: &Plane) -> Vec<Polyline> {
    let d: Vec<f64> = mesh
        .positions
        .iter()
        .map(|p| plane.signed_distance(p))
        .collect();
    let above = |i: u32| d[i as usize] >= 0.0;

    // Crossed mesh edges are the nodes of the section graph; each crossed triangle is one segment.
    let mut node_of_edge: HashMap<(u32, u32), usize> = HashMap::new();
    let mut node_points: Vec<Vec3> = Vec::new();
    let mut segments: Vec<[usize; 2]> = Vec::new();
    for tri in &mesh.triangles {
        if tri.iter().any(|&v| v as usize >= mesh.positions.len()) {
            continue;
        }
        let mut ends = [0usize; 2];
        let mut count = 0;
        for k in 0..3 {
            let (u, v) = (tri[k], tri[(k + 1) % 3]);
            if above(u) == above(v) || u == v {
                continue;
            }
            let key = (u.min(v), u.max(v));
            let node = *node_of_edge.entry(key).or_insert_with(|| {
                let (a, b) = (key.0 as usize, key.1 as usize);
                // Opposite symbolic sides guarantee d[a] != d[b].
                let t = d[a] / (d[a] - d[b]);
                let p = mesh.positions[a] + (mesh.positions[b] - mesh.positions[a]) * t;
                node_points.push(p);
                node_points.len() - 1
            });
            if count < 2 {
                ends[count] = node;
            }
            count += 1;
        }
        if count == 2 && ends[0] != ends[1] {
            segments.push(ends);
        }
    }
    chain_segments(&node_points, &segments, plane)
}

/// Links segments that share a node into maximal chains, open ones (starting at nodes of degree 1)
/// first, then loops. Deterministic: follows segment order.
fn chain_segments(points: &[Vec3], segments: &[[usize; 2]], plane: &Plane) -> Vec<Polyline> {
    let mut incident: Vec<Vec<usize>> = vec![Vec::new(); points.len()];
    for (s, seg) in segments.iter().enumerate() {
        incident[seg[0]].push(s);
        incident[seg[1]].push(s);
    }
    let mut used = vec![false; segments.len()];
    let mut out = Vec::new();

    let walk = |start_node: usize, used: &mut Vec<bool>| -> Option<(Vec<usize>, bool)> {
        let mut nodes = vec![start_node];
        let mut node = start_node;
        loop {
            let next = incident[node].iter().copied().find(|&s| !used[s])?;
            used[next] = true;
            let seg = segments[next];
            node = if seg[0] == node { seg[1] } else { seg[0] };
            if node == start_node {
                return Some((nodes, true));
            }
            nodes.push(node);
            if !incident[node].iter().any(|&s| !used[s]) {
                return Some((nodes, false));
            }
        }
    };

    let mut starts: Vec<usize> = (0..points.len())
        .filter(|&n| incident[n].len() == 1)
        .collect();
    // Then every node (to catch loops), in a deterministic order.
    starts.extend(0..points.len());
    for n in starts {
        while incident[n].iter().any(|&s| !used[s]) {
            if let Some((nodes, closed)) = walk(n, &mut used) {
                if let Some(pl) = make_polyline(points, &nodes, closed, plane) {
                    out.push(pl);
                }
            }
        }
    }
    out
}

fn make_polyline(
    points: &[Vec3],
    nodes: &[usize],
    closed: bool,
    plane: &Plane,
) -> Option<Polyline> {
    let scale = nodes
        .iter()
        .map(|&n| points[n].norm())
        .fold(1.0f64, f64::max);
    let tol = 1e-9 * scale;
    let mut pts: Vec<Vec3> = Vec::with_capacity(nodes.len());
    for &n in nodes {
        let p = points[n];
        if pts.last().is_none_or(|q: &Vec3| (p - q).norm() > tol) {
            pts.push(p);
        }
    }
    if closed {
        while pts.len() > 1 && (pts[0] - pts[pts.len() - 1]).norm() <= tol {
            pts.pop();
        }
    }
    let min_points = if closed { 3 } else { 2 };
    if pts.len() < min_points {
        return None;
    }
    if closed && signed_area(&pts, &plane.normal) < 0.0 {
        pts.reverse();
    }
    Some(Polyline {
        points: pts,
        closed,
    })
}

/// Joins open chains whose ends are at most `max_gap_mm` apart (closest pair first), and closes a
/// chain whose own ends come that close. Sections of composite surfaces need it: an RV cavity made
/// of the free wall and the septal part of the LV epicardium gives two arcs per plane that meet
/// across a small gap, drawn by an analyst as one ring. Open slivers shorter than the gap (where the
/// two surfaces overlap) are dropped first.
pub fn join_chains(pieces: Vec<Polyline>, max_gap_mm: f64, plane: &Plane) -> Vec<Polyline> {
    let (mut closed, mut open): (Vec<Polyline>, Vec<Polyline>) =
        pieces.into_iter().partition(|p| p.closed);
    if max_gap_mm > 0.0 {
        open.retain(|p| polyline_length(p) >= max_gap_mm);
    }
    loop {
        // (gap, i, i_end_is_last, j, j_end_is_last)
        let mut best: Option<(f64, usize, bool, usize, bool)> = None;
        for i in 0..open.len() {
            let ends_i = [open[i].points[0], open[i].points[open[i].points.len() - 1]];
            // Own ends: close the chain (only if it is not a short stub).
            let own = (ends_i[0] - ends_i[1]).norm();
            if open[i].points.len() >= 3
                && polyline_length(&open[i]) > 4.0 * own
                && best.is_none_or(|b| own < b.0)
            {
                best = Some((own, i, true, i, false));
            }
            for (j, other) in open.iter().enumerate().skip(i + 1) {
                let ends_j = [other.points[0], other.points[other.points.len() - 1]];
                for (a, pa) in ends_i.iter().enumerate() {
                    for (b, pb) in ends_j.iter().enumerate() {
                        let g = (pa - pb).norm();
                        if best.is_none_or(|x| g < x.0) {
                            best = Some((g, i, a == 1, j, b == 1));
                        }
                    }
                }
            }
        }
        let Some((gap, i, i_last, j, j_last)) = best else {
            break;
        };
        if gap > max_gap_mm {
            break;
        }
        if i == j {
            let mut pl = open.swap_remove(i);
            pl.closed = true;
            if signed_area(&pl.points, &plane.normal) < 0.0 {
                pl.points.reverse();
            }
            closed.push(pl);
            continue;
        }
        let mut b = open.swap_remove(j); // j > i, so i stays valid
        let a = &mut open[i];
        if !i_last {
            a.points.reverse();
        }
        if j_last {
            b.points.reverse();
        }
        a.points.extend(b.points);
    }
    closed.extend(open);
    closed
}

/// Area of a closed planar polygon projected on `normal` (Newell's formula), signed: positive when
/// counter-clockwise about `normal`.
pub fn signed_area(points: &[Vec3], normal: &Vec3) -> f64 {
    let mut acc = Vec3::zeros();
    for i in 0..points.len() {
        let j = (i + 1) % points.len();
        acc += points[i].cross(&points[j]);
    }
    0.5 * acc.dot(normal)
}

/// Length of a polyline in mm (including the closing segment of a loop).
pub fn polyline_length(pl: &Polyline) -> f64 {
    let n = pl.points.len();
    let mut len: f64 = pl.points.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    if pl.closed && n > 2 {
        len += (pl.points[0] - pl.points[n - 1]).norm();
    }
    len
}

/// Resamples a polyline to points equally spaced by arc length, about `spacing` mm apart (at least
/// 3 points for a loop, 2 for a chain); the end points of an open chain are kept.
pub fn resample(pl: &Polyline, spacing: f64) -> Polyline {
    let n = pl.points.len();
    if n < 2 || !(spacing.is_finite() && spacing > 0.0) {
        return pl.clone();
    }
    let mut verts = pl.points.clone();
    if pl.closed {
        verts.push(pl.points[0]);
    }
    let mut cum = vec![0.0];
    for w in verts.windows(2) {
        let last = cum[cum.len() - 1];
        cum.push(last + (w[1] - w[0]).norm());
    }
    let total = cum[cum.len() - 1];
    if total <= 0.0 {
        return pl.clone();
    }
    let segs = ((total / spacing).round() as usize).max(if pl.closed { 3 } else { 1 });
    let count = if pl.closed { segs } else { segs + 1 };
    let mut out = Vec::with_capacity(count);
    let mut j = 0;
    for k in 0..count {
        let s = total * k as f64 / segs as f64;
        while j + 2 < cum.len() && cum[j + 1] < s {
            j += 1;
        }
        let seg_len = cum[j + 1] - cum[j];
        let t = if seg_len > 0.0 {
            ((s - cum[j]) / seg_len).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(verts[j] + (verts[j + 1] - verts[j]) * t);
    }
    Polyline {
        points: out,
        closed: pl.closed,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;
    use crate::sim::shapes::uv_sphere;

    #[test]
    fn sphere_section_is_one_circle() {
        let m = uv_sphere(v3(1.0, 2.0, 3.0), 10.0, 64, 32);
        let plane = Plane::new(v3(1.0, 2.0, 3.0 + 6.0), v3(0.0, 0.0, 1.0)).unwrap();
        let pieces = slice_mesh(&m, &plane);
        assert_eq!(pieces.len(), 1);
        let pl = &pieces[0];
        assert!(pl.closed);
        // Radius of the section is 8 mm; the polygon inscribed in the faceted sphere is a bit smaller.
        for p in &pl.points {
            assert!(plane.signed_distance(p).abs() < 1e-9);
            let r = ((p.x - 1.0).powi(2) + (p.y - 2.0).powi(2)).sqrt();
            assert!((r - 8.0).abs() < 0.1, "r = {r}");
        }
        let len = polyline_length(pl);
        assert!(
            (len - 2.0 * std::f64::consts::PI * 8.0).abs() < 0.3,
            "len {len}"
        );
        assert!(signed_area(&pl.points, &plane.normal) > 0.0);
    }

    #[test]
    fn vertices_on_the_plane_do_not_break_loops() {
        // A UV sphere has whole rings of vertices at the latitudes; cut exactly through one.
        let m = uv_sphere(v3(0.0, 0.0, 0.0), 10.0, 32, 16);
        let z_ring = m.positions[1 + 32 * 7].z; // a latitude ring
        let plane = Plane::new(v3(0.0, 0.0, z_ring), v3(0.0, 0.0, 1.0)).unwrap();
        let pieces = slice_mesh(&m, &plane);
        assert_eq!(pieces.len(), 1);
        assert!(pieces[0].closed);
        assert_eq!(pieces[0].points.len(), 32);
        // Through the poles: a great circle.
        let plane = Plane::new(v3(0.0, 0.0, 0.0), v3(1.0, 0.0, 0.0)).unwrap();
        let pieces = slice_mesh(&m, &plane);
        assert_eq!(pieces.len(), 1);
        assert!(pieces[0].closed);
        let len = polyline_length(&pieces[0]);
        assert!(
            (len - 2.0 * std::f64::consts::PI * 10.0).abs() < 1.0,
            "len {len}"
        );
    }

    #[test]
    fn open_mesh_gives_open_chain_and_miss_gives_nothing() {
        let mut m = uv_sphere(v3(0.0, 0.0, 0.0), 10.0, 32, 16);
        // Drop the upper half: an open bowl.
        let keep: Vec<[u32; 3]> = m
            .triangles
            .iter()
            .copied()
            .filter(|t| t.iter().all(|&v| m.positions[v as usize].z < 0.5))
            .collect();
        m.triangles = keep;
        let plane = Plane::new(v3(0.0, 0.0, 0.0), v3(1.0, 0.0, 0.0)).unwrap();
        let pieces = slice_mesh(&m, &plane);
        assert_eq!(pieces.len(), 1);
        assert!(!pieces[0].closed);
        let len = polyline_length(&pieces[0]);
        assert!((len - std::f64::consts::PI * 10.0).abs() < 0.5, "len {len}");
        let far = Plane::new(v3(0.0, 0.0, 50.0), v3(0.0, 0.0, 1.0)).unwrap();
        assert!(slice_mesh(&m, &far).is_empty());
    }

    #[test]
    fn two_arcs_with_small_gaps_become_one_ring() {
        let plane = Plane::new(v3(0.0, 0.0, 0.0), v3(0.0, 0.0, 1.0)).unwrap();
        let arc = |from: f64, to: f64, n: usize| Polyline {
            points: (0..=n)
                .map(|k| {
                    let t = (from + (to - from) * k as f64 / n as f64).to_radians();
                    v3(10.0 * t.cos(), 10.0 * t.sin(), 0.0)
                })
                .collect(),
            closed: false,
        };
        // Gaps of ~1.7 mm at 0 and 180 degrees; the second arc runs backwards.
        let pieces = vec![arc(5.0, 175.0, 30), arc(355.0, 185.0, 30)];
        let joined = join_chains(pieces.clone(), 2.0, &plane);
        assert_eq!(joined.len(), 1);
        assert!(joined[0].closed);
        assert_eq!(joined[0].points.len(), 62);
        assert!(signed_area(&joined[0].points, &plane.normal) > 0.0);
        // Gaps larger than allowed: left alone.
        assert_eq!(join_chains(pieces, 1.0, &plane).len(), 2);
        // A U-shape with far ends stays open.
        let u = vec![arc(200.0, 340.0, 20)];
        let kept = join_chains(u, 3.0, &plane);
        assert!(!kept[0].closed);
    }

    #[test]
    fn resample_spacing() {
        let sq = Polyline {
            points: vec![
                v3(0., 0., 0.),
                v3(10., 0., 0.),
                v3(10., 10., 0.),
                v3(0., 10., 0.),
            ],
            closed: true,
        };
        let r = resample(&sq, 1.0);
        assert_eq!(r.points.len(), 40);
        assert!((polyline_length(&r) - 40.0).abs() < 1e-9);
        let open = Polyline {
            points: vec![v3(0., 0., 0.), v3(10., 0., 0.)],
            closed: false,
        };
        let r = resample(&open, 3.0);
        assert_eq!(r.points.len(), 4);
        assert!((r.points[3] - v3(10., 0., 0.)).norm() < 1e-12);
    }
}
