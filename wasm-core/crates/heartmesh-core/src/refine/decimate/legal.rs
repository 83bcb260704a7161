//! Whether a collapse may run: the link condition (the mesh stays manifold), the fan-size and
//! boundary rules, and the soundness of the merged fan (no triangle flips or becomes a sliver).

use super::{Decimator, MIN_NORMAL_COS, MIN_QUALITY};
use crate::geometry::Vec3;

impl Decimator {
    /// Whether collapsing (a, b) to `p` keeps the mesh manifold, oriented and non-degenerate.
    pub(super) fn legal(&mut self, a: u32, b: u32, p: Vec3) -> bool {
        let mut edge_triangles = 0usize;
        let mut opposite = [u32::MAX; 2];
        // Live fan sizes are counted on the walks the tests need anyway (a here, b in the link
        // test) instead of walking both lists again for the fan-size test.
        let mut live_a = 0usize;
        for i in self.list(a) {
            let t = self.refs[i] as usize;
            if !self.triangle_alive[t] {
                continue;
            }
            live_a += 1;
            let tri = self.triangles[t];
            if tri.contains(&b) {
                if edge_triangles < 2 {
                    opposite[edge_triangles] = tri
                        .into_iter()
                        .find(|&w| w != a && w != b)
                        .unwrap_or(u32::MAX);
                }
                edge_triangles += 1;
            }
        }
        if edge_triangles == 0 || edge_triangles > 2 {
            return false;
        }
        let (ba, bb) = (self.boundary[a as usize], self.boundary[b as usize]);
        if edge_triangles == 2 && ba && bb {
            return false;
        }

        // Link condition: the common neighbours of a and b are exactly the edge's opposite vertices.
        let m = self.next_mark();
        for i in self.list(a) {
            let t = self.refs[i] as usize;
            if self.triangle_alive[t] {
                for w in self.triangles[t] {
                    self.marks[w as usize] = m;
                }
            }
        }
        let mut common = 0usize;
        let mut live_b = 0usize;
        for i in self.list(b) {
            let t = self.refs[i] as usize;
            if !self.triangle_alive[t] {
                continue;
            }
            live_b += 1;
            // Branch-free: whether a neighbour of b is also one of a is a coin toss.
            for w in self.triangles[t] {
                let slot = &mut self.marks[w as usize];
                let hit = w != a && w != b && *slot == m;
                *slot = if hit { m + 1 } else { *slot };
                common += usize::from(hit);
            }
        }
        if common != edge_triangles {
            return false;
        }

        // Fans must stay big enough to remain disks (a tetrahedron must not fold into a fin).
        let minimum = |boundary: bool| if boundary { 1 } else { 3 };
        let merged = live_a + live_b - 2 * edge_triangles;
        if merged < minimum(ba || bb) {
            return false;
        }
        for &o in &opposite[..edge_triangles] {
            if o == u32::MAX || self.live_count(o) < minimum(self.boundary[o as usize]) + 1 {
                return false;
            }
        }

        // Geometry: no flipped or degenerate triangle around the moved vertex.
        let mut fan = std::mem::take(&mut self.fan);
        fan.clear();
        // Inside a knot (`KNOT_EDGE`) only degenerate triangles are refused; the repair rounds
        // keep every test, since they collapse folds, not knots.
        let (pa, pb) = (self.positions[a as usize], self.positions[b as usize]);
        let knot = !self.guard_folds && (pb - pa).norm_squared() < self.knot_edge2;
        let ok = self.fan_is_sound(a, b, p, knot, &mut fan)
            && (!self.guard_folds || self.fan_is_unfolded(a, b, &fan));
        self.fan = fan;
        ok
    }

    /// Every triangle of the merged fan keeps its orientation (turns by less than ~80 degrees)
    /// and does not become (nearly) degenerate, or, for a `knot` edge, keeps an area; in the
    /// repair rounds (`guard_folds`) collects the fan's triangles (b renamed a) and their new
    /// normals into `fan`.
    fn fan_is_sound(
        &self,
        a: u32,
        b: u32,
        p: Vec3,
        knot: bool,
        fan: &mut Vec<([u32; 3], Vec3)>,
    ) -> bool {
        for (v, other) in [(a, b), (b, a)] {
            for i in self.list(v) {
                let t = self.refs[i] as usize;
                if !self.triangle_alive[t] {
                    continue;
                }
                let tri = self.triangles[t];
                if tri.contains(&other) {
                    continue;
                }
                let old = tri.map(|w| self.positions[w as usize]);
                let new = tri.map(|w| {
                    if w == v {
                        p
                    } else {
                        self.positions[w as usize]
                    }
                });
                let n_old = (old[1] - old[0]).cross(&(old[2] - old[0]));
                let n_new = (new[1] - new[0]).cross(&(new[2] - new[0]));
                let (l_old, l_new) = (n_old.norm(), n_new.norm());
                if l_new.is_nan() || l_new <= 0.0 {
                    return false;
                }
                if knot {
                    continue;
                }
                if n_old.dot(&n_new) < MIN_NORMAL_COS * l_old * l_new {
                    return false;
                }
                let q_new = quality(&new, l_new);
                if q_new < MIN_QUALITY && q_new < quality(&old, l_old) {
                    return false;
                }
                if self.guard_folds {
                    fan.push((tri.map(|w| if w == b { a } else { w }), n_new));
                }
            }
        }
        true
    }
}

pub(super) fn quality(corners: &[Vec3; 3], cross_norm: f64) -> f64 {
    let sum = (corners[1] - corners[0]).norm_squared()
        + (corners[2] - corners[1]).norm_squared()
        + (corners[0] - corners[2]).norm_squared();
    if sum > 0.0 {
        2.0 * 3f64.sqrt() * cross_norm / sum
    } else {
        0.0
    }
}
