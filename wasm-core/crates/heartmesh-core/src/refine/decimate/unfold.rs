//! Repair of the folds a greedy decimation pass leaves (docs/VALIDATION.md, session 8).
//!
//! Each collapse bounds how far its own triangles turn (`MIN_NORMAL_COS`), not the angle between
//! neighbouring triangles, so two neighbours turning opposite ways can meet in a fold: on the
//! biv-me RV of tests/accuracy.rs the last remesh before the remesh-free final steps left a spike
//! triangle creased at 136-141 degrees against all three neighbours, where the smoothed input's
//! sharpest dihedral was 52 and the truth is smooth. The final steps never remove a crease, so it
//! stayed to the end. Refusing fold-making collapses inside the greedy pass also blocks folds that
//! later collapses remove and changes which collapses run everywhere (SurFCo contour-to-mesh mean
//! 0.061 -> 0.088 mm); a repair after the pass leaves every mesh it has no fold to remove from
//! bit-identical.

use super::Decimator;
use crate::geometry::Vec3;

impl Decimator {
    /// Repair rounds after the greedy pass: every folded edge it left (normals of its two
    /// triangles more than 90 degrees apart) is collapsed, when the collapse is legal and leaves no
    /// fold around the merged vertex. A few rounds: one collapse can expose the next.
    pub(super) fn unfold(&mut self) {
        self.guard_folds = true;
        for _ in 0..super::MAX_PASSES {
            let mut collapsed = 0usize;
            for (a, b) in self.folded_edges() {
                if !self.vertex_alive[a as usize] || !self.vertex_alive[b as usize] {
                    continue;
                }
                let (_, p) = self.evaluate(a, b);
                if self.legal(a, b, p) {
                    self.collapse(a, b, p);
                    collapsed += 1;
                }
            }
            if collapsed == 0 {
                break;
            }
        }
        self.guard_folds = false;
    }

    /// Folded edges (normals of the two triangles more than 90 degrees apart) among the live
    /// triangles, each once as (lower, higher) vertex, in triangle order.
    fn folded_edges(&self) -> Vec<(u32, u32)> {
        let normal = |t: usize| {
            let c = self.triangles[t].map(|w| self.positions[w as usize]);
            (c[1] - c[0]).cross(&(c[2] - c[0]))
        };
        let mut out = Vec::new();
        for (t, tri) in self.triangles.iter().enumerate() {
            if !self.triangle_alive[t] {
                continue;
            }
            let n = normal(t);
            for k in 0..3 {
                let (u, v) = (tri[k], tri[(k + 1) % 3]);
                if u > v {
                    continue;
                }
                for i in self.list(u) {
                    let o = self.refs[i] as usize;
                    if o != t
                        && self.triangle_alive[o]
                        && self.triangles[o].contains(&v)
                        && normal(o).dot(&n) < 0.0
                    {
                        out.push((u, v));
                    }
                }
            }
        }
        out
    }

    /// No edge of the merged fan (spokes at a, and the rim edges to the triangles outside it)
    /// joins two triangles whose normals are more than 90 degrees apart (`fan`: the fan's
    /// triangles with b renamed a, and their new normals).
    pub(super) fn fan_is_unfolded(&self, a: u32, b: u32, fan: &[([u32; 3], Vec3)]) -> bool {
        for (k, (tri, n)) in fan.iter().enumerate() {
            // Spokes: fan triangles sharing a vertex besides a share the spoke edge to it.
            for (other, m) in &fan[k + 1..] {
                let shared = tri
                    .iter()
                    .filter(|&&w| w != a && other.contains(&w))
                    .count();
                if shared > 0 && n.dot(m) < 0.0 {
                    return false;
                }
            }
            // Rim: the edge opposite a, and the unchanged triangle on its other side.
            let Some(i) = tri.iter().position(|&w| w == a) else {
                continue;
            };
            let (w1, w2) = (tri[(i + 1) % 3], tri[(i + 2) % 3]);
            for j in self.list(w1) {
                let t = self.refs[j] as usize;
                let outer = self.triangles[t];
                if !self.triangle_alive[t]
                    || !outer.contains(&w2)
                    || outer.contains(&a)
                    || outer.contains(&b)
                {
                    continue;
                }
                let c = outer.map(|w| self.positions[w as usize]);
                if (c[1] - c[0]).cross(&(c[2] - c[0])).dot(n) < 0.0 {
                    return false;
                }
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Decimator, Known};
    use crate::geometry::Vec3;
    use crate::mesh::quality::quality;
    use crate::mesh::shapes::icosphere;
    use crate::mesh::topology::validity;
    use crate::mesh::TriMesh;

    fn decimated(mesh: &TriMesh, target: usize, repair: bool) -> TriMesh {
        let mut d = Decimator::new(mesh, Vec3::zeros(), Known::Nothing).unwrap();
        d.run(target);
        if repair {
            d.unfold();
        }
        d.finish(Vec3::zeros())
    }

    /// Where the greedy pass leaves no fold, the repair changes nothing (same bits).
    #[test]
    fn the_repair_leaves_an_unfolded_result_alone() {
        let sphere = icosphere(10.0, 3);
        let plain = decimated(&sphere, 300, false);
        assert_eq!(quality(&plain).folded_edges, 0);
        let repaired = decimated(&sphere, 300, true);
        assert_eq!(plain.triangles, repaired.triangles);
        assert_eq!(plain.positions, repaired.positions);
    }

    /// A collapse that would leave a folded edge around its merged vertex is refused in the
    /// repair rounds; folds the repair cannot remove legally (a vertex pushed through the far
    /// side of its ring, whose triangles would have to turn over) stay, and the mesh stays a
    /// closed manifold.
    #[test]
    fn the_repair_never_adds_folds() {
        let mut m = icosphere(10.0, 2);
        let top = (0..m.positions.len())
            .max_by(|&a, &b| m.positions[a].z.total_cmp(&m.positions[b].z))
            .unwrap_or(0);
        m.positions[top] *= -0.2;
        let before = quality(&m).folded_edges;
        assert_eq!(before, 6);
        let out = decimated(&m, m.triangles.len(), true);
        assert!(quality(&out).folded_edges <= before);
        assert!(validity(&out).is_closed_manifold());
    }
}
