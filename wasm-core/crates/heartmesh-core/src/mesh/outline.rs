//! Keeping the cavities' outlines in the base plane inside the epicardium's and apart from each
//! other, before a wall's base ring is built between them.
//!
//! The wall's 3D pushes ([`super::inset::push`]) move a vertex along the normal of the nearest
//! face of the other surface, and an outline vertex must then stay in the base plane, so its
//! move is projected onto it. Near the base the surfaces often run nearly along the plane (a
//! biventricular epicardium turning over towards the valves), and what is left of the move after
//! the projection is too little: with breath-hold offsets between the images an RV outline can
//! end 1-2 mm outside the epicardium's, and the ring between them does not exist. In the plane
//! the repair is plain 2D geometry: each cavity's outline vertex goes `depth` inside the outer
//! outline and `depth` outside the other cavities', and an outer outline vertex that still
//! reaches into a cavity (a corner of the outer outline between two inner vertices) moves the
//! inner edge it crosses away from it.

use super::clip::Clipped;
use super::inset::Pushed;
use crate::geometry::Vec3;
use crate::sim::slice::Plane;
use nalgebra::{Point2, Vector2};

/// Rounds of moves: moving one outline off another can bring it near a third (the septum
/// between the LV's and RV's outlines inside the epicardium's).
const ROUNDS: usize = 8;

/// Shortfalls below this (mm) are rounding: a vertex already moved to exactly `depth` must not
/// count as moving again (the wall's separation rounds stop when nothing moves).
const TOLERANCE_MM: f64 = 1e-6;

/// An orthonormal basis (u, v) of the plane with u x v = normal.
pub(super) fn plane_basis(n: &Vec3) -> (Vec3, Vec3) {
    let helper = if n.x.abs() < 0.9 {
        Vec3::new(1.0, 0.0, 0.0)
    } else {
        Vec3::new(0.0, 1.0, 0.0)
    };
    let u = n.cross(&helper).normalize();
    let v = n.cross(&u);
    (u, v)
}

/// Even-odd point-in-polygon test.
pub(super) fn inside(poly: &[Point2<f64>], p: Point2<f64>) -> bool {
    let mut odd = false;
    let mut j = poly.len() - 1;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[j]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y) {
            odd = !odd;
        }
        j = i;
    }
    odd
}

/// The nearest point to `p` on the closed polygon `poly`: (segment index, point, distance).
fn nearest_on(poly: &[Point2<f64>], p: Point2<f64>) -> Option<(usize, Point2<f64>, f64)> {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            let ab = b - a;
            let len_sq = ab.norm_squared();
            let t = if len_sq > 0.0 {
                ((p - a).dot(&ab) / len_sq).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let q = a + ab * t;
            (i, q, (p - q).norm())
        })
        .min_by(|x, y| x.2.total_cmp(&y.2))
}

/// Where `p` must go to be `depth` from `poly` on the side `want_inside` says, or None when it
/// already is. The way out is from the nearest point on the polygon to `p` (or back, when `p`
/// is on the wrong side); at a point on the polygon itself, across its nearest segment.
fn clear_of(
    poly: &[Point2<f64>],
    p: Point2<f64>,
    depth: f64,
    want_inside: bool,
) -> Option<Point2<f64>> {
    let (seg, q, dist) = nearest_on(poly, p)?;
    let is_inside = inside(poly, p);
    if is_inside == want_inside && dist >= depth - TOLERANCE_MM {
        return None;
    }
    let away = if dist > 1e-12 {
        let d: Vector2<f64> = (p - q) / dist;
        if is_inside == want_inside {
            d
        } else {
            -d
        }
    } else {
        let n = poly.len();
        let e = poly[(seg + 1) % n] - poly[seg];
        let normal = Vector2::new(e.y, -e.x).try_normalize(0.0)?;
        // The side of the segment the polygon's inside lies on.
        let probe = q + normal * 1e-6;
        if inside(poly, probe) == want_inside {
            normal
        } else {
            -normal
        }
    };
    Some(q + away * depth)
}

/// Moves the cavities' outline vertices (`cavities[k].loops[0]`, in the plane) until each is at
/// least `depth` inside the epicardium's outline and `depth` outside every other cavity's, and
/// no epicardial outline vertex is inside or within `depth` of a cavity's outline; the vertices
/// stay in the plane. Returns how many cavity vertices moved and the farthest (net).
pub(super) fn separate_outlines(
    cavities: &mut [Clipped],
    epi: &Clipped,
    base: &Plane,
    depth: f64,
) -> Pushed {
    if !(depth.is_finite() && depth > 0.0) || epi.loops.is_empty() {
        return Pushed::default();
    }
    let (u, v) = plane_basis(&base.normal);
    let flat = |p: &Vec3| {
        let d = p - base.origin;
        Point2::new(d.dot(&u), d.dot(&v))
    };
    let lift = |q: Point2<f64>| base.origin + u * q.x + v * q.y;
    let outer: Vec<Point2<f64>> = epi.loops[0]
        .iter()
        .map(|&i| flat(&epi.mesh.positions[i as usize]))
        .collect();
    let mut inner: Vec<Vec<Point2<f64>>> = cavities
        .iter()
        .map(|c| {
            c.loops
                .first()
                .map(|l| {
                    l.iter()
                        .map(|&i| flat(&c.mesh.positions[i as usize]))
                        .collect()
                })
                .unwrap_or_default()
        })
        .collect();
    if outer.len() < 3 || inner.iter().any(|l| l.len() < 3) {
        return Pushed::default();
    }
    let start = inner.clone();
    for _ in 0..ROUNDS {
        let mut moved = false;
        for k in 0..inner.len() {
            for i in 0..inner[k].len() {
                let mut p = inner[k][i];
                if let Some(t) = clear_of(&outer, p, depth, true) {
                    p = t;
                    moved = true;
                }
                for j in (0..inner.len()).filter(|&j| j != k) {
                    if let Some(t) = clear_of(&inner[j], p, depth, false) {
                        p = t;
                        moved = true;
                    }
                }
                inner[k][i] = p;
            }
            unfold(&mut inner[k]);
            // Outer corners reaching into the cavity between two of its vertices.
            for &o in &outer {
                let poly = &inner[k];
                let Some((seg, q, dist)) = nearest_on(poly, o) else {
                    continue;
                };
                let reaches_in = inside(poly, o);
                if !reaches_in && dist >= depth - TOLERANCE_MM {
                    continue;
                }
                let away = if dist > 1e-12 {
                    let d = (q - o) / dist;
                    if reaches_in {
                        -d
                    } else {
                        d
                    }
                } else {
                    continue;
                };
                let shift = away * (depth + if reaches_in { dist } else { -dist });
                let n = inner[k].len();
                for s in [seg, (seg + 1) % n] {
                    inner[k][s] += shift;
                }
                moved = true;
            }
        }
        if !moved {
            break;
        }
    }
    let mut pushed = Pushed::default();
    for (k, c) in cavities.iter_mut().enumerate() {
        let Some(l) = c.loops.first() else { continue };
        for (i, &vi) in l.iter().enumerate() {
            let d = (inner[k][i] - start[k][i]).norm();
            if d > 0.0 {
                c.mesh.positions[vi as usize] = lift(inner[k][i]);
                pushed.vertices += 1;
                pushed.max_mm = pushed.max_mm.max(d);
            }
        }
    }
    pushed
}

/// Whether segments ab and cd cross at a point inside both.
fn segments_cross(a: Point2<f64>, b: Point2<f64>, c: Point2<f64>, d: Point2<f64>) -> bool {
    let orient = |p: Point2<f64>, q: Point2<f64>, r: Point2<f64>| {
        (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x)
    };
    orient(a, b, c) * orient(a, b, d) < 0.0 && orient(c, d, a) * orient(c, d, b) < 0.0
}

/// Straightens the folds of a closed outline: where two of its segments cross, the shorter run
/// of vertices between them goes evenly onto the chord across the fold. Pushes from both sides
/// of a narrow part (the tip of an RV crescent between the epicardium and the LV, each pushing
/// its vertices `depth` away) carry its vertices past each other; a run of the outline folded
/// back on itself bounds no region and the ring cannot be built on it.
fn unfold(poly: &mut [Point2<f64>]) {
    let n = poly.len();
    if n < 4 {
        return;
    }
    // Each straightening removes a crossing; a pass finds one at a time.
    for _ in 0..n {
        let Some((i, j)) = (0..n).find_map(|i| {
            (i + 2..n)
                .filter(|&j| (j + 1) % n != i)
                .find(|&j| segments_cross(poly[i], poly[(i + 1) % n], poly[j], poly[(j + 1) % n]))
                .map(|j| (i, j))
        }) else {
            return;
        };
        // The two runs between the crossing segments: i+1..=j, and j+1..=i round the end.
        let (from, count) = if j - i <= n - (j - i) {
            (i, j - i)
        } else {
            (j, n - (j - i))
        };
        let a = poly[from];
        let b = poly[(from + count + 1) % n];
        for step in 1..=count {
            let t = step as f64 / (count + 1) as f64;
            poly[(from + step) % n] = a + (b - a) * t;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::TriMesh;

    /// A "clipped" made of just a loop of points in the plane z = 0 (no triangles needed here).
    fn loop_of(points: &[(f64, f64)]) -> Clipped {
        let positions: Vec<Vec3> = points.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
        let n = positions.len() as u32;
        Clipped {
            mesh: TriMesh::new(positions, Vec::new()),
            loops: vec![(0..n).collect()],
        }
    }

    fn circle(cx: f64, cy: f64, r: f64, n: usize) -> Vec<(f64, f64)> {
        (0..n)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / n as f64;
                (cx + r * t.cos(), cy + r * t.sin())
            })
            .collect()
    }

    fn z_plane() -> Plane {
        Plane {
            origin: Vec3::zeros(),
            normal: Vec3::new(0.0, 0.0, 1.0),
        }
    }

    fn radius(c: &Clipped, centre: (f64, f64)) -> (f64, f64) {
        let r: Vec<f64> = c.loops[0]
            .iter()
            .map(|&i| {
                let p = c.mesh.positions[i as usize];
                ((p.x - centre.0).powi(2) + (p.y - centre.1).powi(2)).sqrt()
            })
            .collect();
        (
            r.iter().copied().fold(f64::INFINITY, f64::min),
            r.iter().copied().fold(0.0, f64::max),
        )
    }

    /// A cavity outline poking 2 mm out of the epicardium's comes back to 1 mm inside it; the
    /// rest of it, already 3 mm in, stays where it was; every vertex stays in the plane.
    #[test]
    fn an_outline_poking_out_comes_back_inside() {
        let epi = loop_of(&circle(0.0, 0.0, 20.0, 200));
        let mut cav = vec![loop_of(&circle(5.0, 0.0, 17.0, 120))];
        let before = cav[0].mesh.positions.clone();
        let pushed = separate_outlines(&mut cav, &epi, &z_plane(), 1.0);
        let (_, rmax) = radius(&cav[0], (0.0, 0.0));
        assert!(rmax <= 19.0 + 0.01, "farthest {rmax}");
        assert!(
            pushed.vertices > 0 && (pushed.max_mm - 3.0).abs() < 0.1,
            "{pushed:?}"
        );
        for (a, b) in before.iter().zip(&cav[0].mesh.positions) {
            assert_eq!(b.z, 0.0);
            // Vertices on the far side (x < 0 side, 12 mm from the epicardium) do not move.
            if a.x < -5.0 {
                assert_eq!(a, b);
            }
        }
    }

    /// Two cavities overlapping by 2 mm end at least 1 mm apart.
    #[test]
    fn overlapping_outlines_end_apart() {
        let epi = loop_of(&circle(0.0, 0.0, 40.0, 300));
        let mut cav = vec![
            loop_of(&circle(-10.0, 0.0, 11.0, 100)),
            loop_of(&circle(10.0, 0.0, 11.0, 100)),
        ];
        separate_outlines(&mut cav, &epi, &z_plane(), 1.0);
        let flat = |c: &Clipped| -> Vec<Point2<f64>> {
            c.loops[0]
                .iter()
                .map(|&i| {
                    let p = c.mesh.positions[i as usize];
                    Point2::new(p.x, p.y)
                })
                .collect()
        };
        let (a, b) = (flat(&cav[0]), flat(&cav[1]));
        let gap = a
            .iter()
            .filter_map(|p| nearest_on(&b, *p).map(|x| x.2))
            .fold(f64::INFINITY, f64::min);
        assert!(gap >= 0.99, "gap {gap}");
        assert!(a.iter().all(|p| !inside(&b, *p)) && b.iter().all(|p| !inside(&a, *p)));
    }

    /// A loop folded over itself (a figure-eight tip) is straightened; every vertex stays.
    #[test]
    fn a_folded_outline_is_straightened() {
        let mut poly: Vec<Point2<f64>> = [
            (0.0, 0.0),
            (10.0, 0.0),
            (10.0, 10.0),
            (6.0, 10.0),
            (4.0, 12.0),
            (5.0, 13.0),
            (6.0, 12.0),
            (4.0, 10.0),
            (0.0, 10.0),
        ]
        .iter()
        .map(|&(x, y)| Point2::new(x, y))
        .collect();
        unfold(&mut poly);
        let n = poly.len();
        for i in 0..n {
            for j in i + 2..n {
                if (j + 1) % n == i {
                    continue;
                }
                assert!(
                    !segments_cross(poly[i], poly[(i + 1) % n], poly[j], poly[(j + 1) % n]),
                    "{i} {j}: {poly:?}"
                );
            }
        }
        assert!(poly.iter().all(|p| p.y <= 10.0 + 1e-12), "{poly:?}");
        assert_eq!(poly[0], Point2::new(0.0, 0.0));
    }

    /// A corner of the outer outline reaching in between two coarse cavity vertices moves the
    /// cavity's edge off it.
    #[test]
    fn an_outer_corner_between_two_vertices_moves_the_edge() {
        // A square epicardium with a notch reaching in at x = 0 down to y = 8.
        let epi = loop_of(&[
            (-20.0, -20.0),
            (20.0, -20.0),
            (20.0, 20.0),
            (0.5, 20.0),
            (0.0, 8.0),
            (-0.5, 20.0),
            (-20.0, 20.0),
        ]);
        // A coarse cavity whose top edge runs from (-10, 10) to (10, 10), under the notch's tip
        // only between its two vertices.
        let mut cav = vec![loop_of(&[
            (-10.0, -10.0),
            (10.0, -10.0),
            (10.0, 10.0),
            (-10.0, 10.0),
        ])];
        separate_outlines(&mut cav, &epi, &z_plane(), 1.0);
        let p = &cav[0].mesh.positions;
        // The top edge (vertices 2 and 3) now passes at least ~1 mm under the tip at (0, 8).
        let top = (p[2].y + p[3].y) / 2.0;
        assert!(top <= 7.0 + 1e-6, "top edge at {top}");
    }
}
