//! The LV myocardium as one closed solid: the epicardium and the endocardium below the base,
//! joined across the base by a flat ring.
//!
//! Simulation pipelines (a volume mesher such as gmsh or TetGen, then a finite-element solver)
//! and 3D printers need the wall, not two separate cavities: one watertight, outward-facing
//! surface whose triangles say which part of the boundary they are (epicardium, endocardium,
//! base), so the solver can put its boundary conditions on each. The base is a plane at the
//! most basal short-axis slice both surfaces were drawn on: below it both surfaces stand on
//! data; above it they run on to their lids, which belong to no wall.
//!
//! The ring is a constrained Delaunay triangulation (spade) of the region between the two
//! outlines in the base plane, using only their vertices, so the three parts share their edges
//! and the solid is closed by construction.

use super::clip::{clip_below, mean_edge_length, Clipped};
use super::inset::{push, Keep, Pushed};
use super::intersect::self_intersections;
use super::quality::{dihedral_deg, face_normals, FOLD_DEG};
use super::topology::{validity, EdgeMap};
use super::TriMesh;
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::io::{write_mesh_with, MeshFormat, Regions};
use crate::metrics::function::MYOCARDIAL_DENSITY_G_PER_ML;
use crate::metrics::{stats, Stats};
use crate::sim::slice::Plane;
use crate::spatial::Bvh;
use serde::Serialize;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

/// The regions of a wall's triangles, in the order of their ids.
pub const REGION_NAMES: [&str; 3] = ["epicardium", "endocardium", "base"];
/// Region id of epicardial triangles.
pub const EPICARDIUM: u32 = 0;
/// Region id of endocardial triangles.
pub const ENDOCARDIUM: u32 = 1;
/// Region id of the base ring's triangles.
pub const BASE: u32 = 2;

/// Vertices this close to the base plane, as a share of the mean edge length, are moved onto it
/// before cutting (no sliver triangles along the cut).
const SNAP_SHARE: f64 = 0.2;

/// A myocardium wall.
#[derive(Debug, Clone)]
pub struct Wall {
    /// Closed, manifold, outward-facing (the endocardium faces into the cavity).
    pub mesh: TriMesh,
    /// Region id of every triangle ([`REGION_NAMES`]).
    pub regions: Vec<u32>,
    /// Wall thickness at every vertex (mm): the distance from an epicardial vertex to the
    /// endocardium and from an endocardial one to the epicardium (base-ring vertices are on
    /// one of the two).
    pub thickness: Vec<f64>,
    /// The base plane (normal towards the base).
    pub base: Plane,
    /// Enclosed volume of the wall (ml).
    pub volume_ml: f64,
    /// Volume of the cavity below the base (ml): the endocardium closed by the base plane.
    pub cavity_ml: f64,
    /// Pairs of triangles that pass through each other: nonzero where the endocardium crosses
    /// the epicardium (a wall thinner than the reconstructions' error).
    pub self_intersections: usize,
    /// Endocardial vertices moved under the epicardium before the wall was built.
    pub pushed: Pushed,
    /// Epicardial vertices moved out over the endocardium (where it still poked in between
    /// the endocardium's moved vertices).
    pub epi_pushed: Pushed,
    /// Triangles per region, in [`REGION_NAMES`] order.
    pub triangles_per_region: [usize; 3],
}

/// Builds the wall between the closed `endo` and `epi` meshes below `base` (its normal points to
/// the base, away from the apex).
/// With `min_thickness_mm`, endocardial vertices outside the epicardium or closer to it than
/// that are first moved that far under it, and then epicardial vertices still within that of
/// the endocardium out over it ([`separate`]; the wall's `pushed` and `epi_pushed` say how many
/// and how far); None leaves the surfaces as given.
pub fn build_wall(
    endo: &TriMesh,
    epi: &TriMesh,
    base: &Plane,
    min_thickness_mm: Option<f64>,
) -> Result<Wall> {
    let mut endo_cut = cut(endo, base, "endocardium")?;
    let mut epi_cut = cut(epi, base, "epicardium")?;
    // Checked before any vertex moves: pushing a whole surface through the other would hide it.
    if closed_by_plane_ml(&endo_cut.mesh, base) >= closed_by_plane_ml(&epi_cut.mesh, base) {
        return Err(CoreError::Degenerate(
            "below the base the endocardium encloses at least as much as the epicardium: are the \
             two surfaces' names swapped?"
                .into(),
        ));
    }
    let (pushed, epi_pushed) = match min_thickness_mm {
        Some(depth) => separate(&mut endo_cut, &mut epi_cut, base, depth),
        None => (Pushed::default(), Pushed::default()),
    };
    let (outer, inner) = (&epi_cut.loops[0], &endo_cut.loops[0]);

    let nv_epi = epi_cut.mesh.positions.len() as u32;
    let mut positions = epi_cut.mesh.positions.clone();
    positions.extend_from_slice(&endo_cut.mesh.positions);
    let mut triangles: Vec<[u32; 3]> = epi_cut.mesh.triangles.clone();
    let mut regions = vec![EPICARDIUM; triangles.len()];
    for t in &endo_cut.mesh.triangles {
        // Reversed: the endocardium faces into the cavity, out of the wall.
        triangles.push([t[0] + nv_epi, t[2] + nv_epi, t[1] + nv_epi]);
        regions.push(ENDOCARDIUM);
    }
    let ring_outer: Vec<u32> = outer.clone();
    let ring_inner: Vec<u32> = inner.iter().map(|&v| v + nv_epi).collect();
    for t in ring(&positions, &ring_outer, &ring_inner, base)? {
        triangles.push(t);
        regions.push(BASE);
    }
    let mesh = TriMesh::new(positions, triangles);
    let v = validity(&mesh);
    if !v.is_closed_manifold() {
        return Err(CoreError::InvalidMesh(format!(
            "the myocardium wall is not a closed manifold ({})",
            v.describe()
        )));
    }
    let volume_ml = mesh.volume_ml();
    if volume_ml <= 0.0 {
        return Err(CoreError::InvalidMesh(format!(
            "the myocardium wall encloses no volume ({volume_ml:.3} ml): is the endocardium \
             inside the epicardium?"
        )));
    }
    let thickness = thickness(&mesh, nv_epi as usize, &endo_cut.mesh, &epi_cut.mesh);
    let mut triangles_per_region = [0usize; 3];
    for &r in &regions {
        triangles_per_region[r as usize] += 1;
    }
    Ok(Wall {
        self_intersections: self_intersections(&mesh),
        cavity_ml: closed_by_plane_ml(&endo_cut.mesh, base),
        mesh,
        regions,
        thickness,
        base: *base,
        volume_ml,
        pushed,
        epi_pushed,
        triangles_per_region,
    })
}

/// A wall's figures under the names of `heartmesh myocardium`'s report (the app shows the same).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WallSummary {
    pub wall_volume_ml: f64,
    /// 1.05 g/ml times the wall volume: the myocardium below the base only.
    pub myocardial_mass_g: f64,
    pub cavity_volume_ml: f64,
    pub base_plane: BasePlane,
    /// Over the vertices (mm).
    pub thickness_mm: Stats,
    pub regions: Vec<RegionCount>,
    pub endo_epi_crossings: usize,
    pub endocardium_moved: Moved,
    pub epicardium_moved: Moved,
}

/// The base plane in the file's coordinates (mm); the normal points to the base.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BasePlane {
    pub origin: [f64; 3],
    pub normal: [f64; 3],
}

/// One region of the wall: its id in files (1-based), name and triangle count.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RegionCount {
    pub id: usize,
    pub name: &'static str,
    pub triangles: usize,
}

/// Vertices moved to keep the minimum thickness (none asked for: `min_thickness_mm` null).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Moved {
    pub min_thickness_mm: Option<f64>,
    pub vertices: usize,
    pub max_mm: f64,
}

impl Wall {
    /// The wall as a mesh file: regions as `region` cell data (OBJ groups; none in STL) and the
    /// thickness as point data `thickness`, as `heartmesh myocardium` and the app write it.
    pub fn write(&self, format: MeshFormat, header_comment: &str) -> Result<Vec<u8>> {
        let regions = Regions {
            array: "region",
            ids: &self.regions,
            names: &REGION_NAMES,
        };
        write_mesh_with(
            &self.mesh,
            format,
            Some(("thickness", self.thickness.as_slice())),
            Some(&regions),
            header_comment,
        )
    }

    /// The figures a report or a panel gives; `min_thickness_mm` is what [`build_wall`] was
    /// given.
    pub fn summary(&self, min_thickness_mm: Option<f64>) -> WallSummary {
        let finite: Vec<f64> = self
            .thickness
            .iter()
            .copied()
            .filter(|t| t.is_finite())
            .collect();
        let moved = |p: Pushed| Moved {
            min_thickness_mm,
            vertices: p.vertices,
            max_mm: p.max_mm,
        };
        let v = |x: Vec3| [x.x, x.y, x.z];
        WallSummary {
            wall_volume_ml: self.volume_ml,
            myocardial_mass_g: MYOCARDIAL_DENSITY_G_PER_ML * self.volume_ml,
            cavity_volume_ml: self.cavity_ml,
            base_plane: BasePlane {
                origin: v(self.base.origin),
                normal: v(self.base.normal),
            },
            thickness_mm: stats(&finite),
            regions: REGION_NAMES
                .iter()
                .enumerate()
                .map(|(i, &name)| RegionCount {
                    id: i + 1,
                    name,
                    triangles: self.triangles_per_region[i],
                })
                .collect(),
            endo_epi_crossings: self.self_intersections,
            endocardium_moved: moved(self.pushed),
            epicardium_moved: moved(self.epi_pushed),
        }
    }

    /// Edges where neighbouring triangles of one region turn against each other by more than
    /// a right angle (folds of a surface); the rim, where the base meets the walls at about a
    /// right angle by design, is left out.
    pub fn folded_edges_off_rim(&self) -> usize {
        let map = EdgeMap::new(&self.mesh);
        let normals = face_normals(&self.mesh);
        (0..map.edges.len())
            .filter(|&e| {
                let same_region = match map.half_edges_of(e) {
                    &[h, g] => self.regions[h as usize / 3] == self.regions[g as usize / 3],
                    _ => false,
                };
                same_region && dihedral_deg(&map, &normals, e).is_some_and(|a| a > FOLD_DEG)
            })
            .count()
    }
}

/// Rounds of [`separate`]: a wall needing more is not a wall the contours describe.
const SEPARATION_ROUNDS: usize = 3;

/// Moves the endocardium under the epicardium by `depth` mm ([`push`]), then the epicardium out
/// over the endocardium where the latter's triangles still span across it (a coarse endocardial
/// triangle over a finer epicardial bump), until neither moves or after
/// [`SEPARATION_ROUNDS`]. Outline vertices stay in the base plane. Returns the endocardium's
/// and the epicardium's moves.
fn separate(endo: &mut Clipped, epi: &mut Clipped, base: &Plane, depth: f64) -> (Pushed, Pushed) {
    let mask = |c: &Clipped| {
        let mut m = vec![false; c.mesh.positions.len()];
        for &v in &c.loops[0] {
            m[v as usize] = true;
        }
        m
    };
    let (endo_mask, epi_mask) = (mask(endo), mask(epi));
    let (endo_before, epi_before) = (endo.mesh.positions.clone(), epi.mesh.positions.clone());
    for _ in 0..SEPARATION_ROUNDS {
        let a = push(
            &mut endo.mesh,
            &epi.mesh,
            &capped(epi, base),
            depth,
            Keep::Inside,
            Some((base, &endo_mask)),
        );
        let b = push(
            &mut epi.mesh,
            &endo.mesh,
            &capped(endo, base),
            depth,
            Keep::Outside,
            Some((base, &epi_mask)),
        );
        if a.vertices + b.vertices == 0 {
            break;
        }
    }
    (
        net_moves(&endo_before, &endo.mesh.positions),
        net_moves(&epi_before, &epi.mesh.positions),
    )
}

/// How many vertices ended up elsewhere, and the farthest (a vertex moved in several rounds
/// counts once, by where it ended).
fn net_moves(before: &[Vec3], after: &[Vec3]) -> Pushed {
    before
        .iter()
        .zip(after)
        .map(|(a, b)| (b - a).norm())
        .filter(|&d| d > 0.0)
        .fold(Pushed::default(), |acc, d| Pushed {
            vertices: acc.vertices + 1,
            max_mm: acc.max_mm.max(d),
        })
}

/// One surface cut at the base: exactly one outline, or an error that says what the plane met.
fn cut(mesh: &TriMesh, base: &Plane, name: &str) -> Result<Clipped> {
    let snap = SNAP_SHARE * mean_edge_length(mesh);
    let clipped = clip_below(mesh, base, snap)
        .map_err(|e| CoreError::InvalidMesh(format!("{name} at the base plane: {e}")))?;
    let mut clipped = clipped;
    // Open reference surfaces (atlas models open at the base) may face either way: what is kept
    // below the plane, closed by it, must enclose a positive volume.
    if closed_by_plane_ml(&clipped.mesh, base) < 0.0 {
        clipped.mesh.flip_orientation();
        for ring in &mut clipped.loops {
            ring.reverse();
        }
    }
    match clipped.loops.len() {
        1 => Ok(clipped),
        0 => Err(CoreError::Degenerate(format!(
            "the base plane does not cut the {name} (the surface lies wholly on one side of it)"
        ))),
        n => Err(CoreError::Degenerate(format!(
            "the base plane cuts the {name} in {n} outlines, not one"
        ))),
    }
}

/// The cut surface closed by a fan across its outline (facing along the plane's normal): a
/// closed surface for inside tests.
fn capped(cut: &Clipped, base: &Plane) -> TriMesh {
    let mut mesh = cut.mesh.clone();
    let ring = &cut.loops[0];
    let centre = ring
        .iter()
        .fold(Vec3::zeros(), |acc, &v| acc + mesh.positions[v as usize])
        / ring.len() as f64;
    let c = mesh.positions.len() as u32;
    mesh.positions.push(centre);
    let mut fan: Vec<[u32; 3]> = (0..ring.len())
        .map(|k| [c, ring[k], ring[(k + 1) % ring.len()]])
        .collect();
    let facing: f64 = fan
        .iter()
        .map(|t| {
            let [a, b, d] = t.map(|i| mesh.positions[i as usize]);
            (b - a).cross(&(d - a)).dot(&base.normal)
        })
        .sum();
    if facing < 0.0 {
        for t in &mut fan {
            t.swap(1, 2);
        }
    }
    mesh.triangles.extend(fan);
    mesh
}

/// An orthonormal basis (u, v) of the plane with u x v = normal.
fn plane_basis(n: &Vec3) -> (Vec3, Vec3) {
    let helper = if n.x.abs() < 0.9 {
        Vec3::new(1.0, 0.0, 0.0)
    } else {
        Vec3::new(0.0, 1.0, 0.0)
    };
    let u = n.cross(&helper).normalize();
    let v = n.cross(&u);
    (u, v)
}

/// Even-odd point-in-polygon test in the plane's coordinates.
fn inside(poly: &[Point2<f64>], p: Point2<f64>) -> bool {
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

/// Triangles of the flat ring between the `outer` and `inner` outlines (vertex indices into
/// `positions`, all in the plane), facing along the plane's normal.
fn ring(positions: &[Vec3], outer: &[u32], inner: &[u32], base: &Plane) -> Result<Vec<[u32; 3]>> {
    let (u, v) = plane_basis(&base.normal);
    let flat = |i: u32| {
        let d = positions[i as usize] - base.origin;
        Point2::new(d.dot(&u), d.dot(&v))
    };
    let outer_2d: Vec<Point2<f64>> = outer.iter().map(|&i| flat(i)).collect();
    let inner_2d: Vec<Point2<f64>> = inner.iter().map(|&i| flat(i)).collect();
    if inner_2d.iter().any(|p| !inside(&outer_2d, *p)) {
        return Err(CoreError::Degenerate(
            "the endocardium's outline at the base is not inside the epicardium's (the two \
             surfaces cross there)"
                .into(),
        ));
    }
    let ids: Vec<u32> = outer.iter().chain(inner).copied().collect();
    let points: Vec<Point2<f64>> = outer_2d.iter().chain(&inner_2d).copied().collect();
    let mut edges = Vec::with_capacity(points.len());
    for (start, len) in [(0, outer.len()), (outer.len(), inner.len())] {
        for k in 0..len {
            edges.push([start + k, start + (k + 1) % len]);
        }
    }
    let mut conflicts = 0usize;
    let cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::try_bulk_load_cdt(
        points.clone(),
        edges,
        |_| conflicts += 1,
    )
    .map_err(|e| CoreError::Degenerate(format!("the base ring cannot be triangulated: {e:?}")))?;
    if conflicts > 0 || cdt.num_vertices() != points.len() {
        return Err(CoreError::Degenerate(
            "the outlines of the endocardium and the epicardium at the base touch or cross \
             themselves or each other"
                .into(),
        ));
    }
    // Faces between the two outlines are an odd number of constraint edges in from the outside
    // (the hole inside the endocardium, an even number: any walk from the outer face crosses
    // the two nested loops with that parity). Counted by walking across edges, which needs no
    // point-in-polygon test on slivers along nearly straight outlines.
    let mut depth: Vec<Option<u32>> = vec![None; cdt.num_all_faces()];
    let outer_face = cdt.outer_face();
    depth[outer_face.fix().index()] = Some(0);
    let mut queue = std::collections::VecDeque::from([outer_face.fix()]);
    while let Some(f) = queue.pop_front() {
        let d = depth[f.index()].unwrap_or(0);
        let face = cdt.face(f);
        let edges: Vec<_> = match face.as_inner() {
            Some(inner) => inner.adjacent_edges().to_vec(),
            None => cdt
                .directed_edges()
                .filter(|e| e.face().fix() == f)
                .collect(),
        };
        for e in edges {
            let next = e.rev().face().fix();
            if depth[next.index()].is_none() {
                depth[next.index()] = Some(d + u32::from(e.is_constraint_edge()));
                queue.push_back(next);
            }
        }
    }
    let mut out = Vec::new();
    for face in cdt.inner_faces() {
        if depth[face.fix().index()].is_none_or(|d| d % 2 == 0) {
            continue;
        }
        let [a, b, c] = face.vertices().map(|h| h.fix().index());
        // spade's faces run counter-clockwise in (u, v): their normal is u x v = the base's.
        out.push([ids[a], ids[b], ids[c]]);
    }
    Ok(out)
}

/// Distance from each vertex to the other surface: vertices before `nv_epi` are epicardial.
fn thickness(wall: &TriMesh, nv_epi: usize, endo: &TriMesh, epi: &TriMesh) -> Vec<f64> {
    let (endo_bvh, epi_bvh) = (Bvh::build(endo), Bvh::build(epi));
    wall.positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let (bvh, other) = if i < nv_epi {
                (&endo_bvh, endo)
            } else {
                (&epi_bvh, epi)
            };
            bvh.closest_point(other, *p)
                .map_or(f64::NAN, |h| h.distance_sq.sqrt())
        })
        .collect()
}

/// Volume (ml) of an outward surface cut at `plane` and closed by it: the cap adds nothing when
/// the tetrahedra are taken from a point of the plane.
fn closed_by_plane_ml(mesh: &TriMesh, plane: &Plane) -> f64 {
    let o = plane.origin;
    let mut vol = 0.0;
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.corners(t);
        vol += (a - o).dot(&(b - o).cross(&(c - o))) / 6.0;
    }
    vol / 1000.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;
    use crate::sim::shapes::uv_sphere;
    use std::f64::consts::PI;

    fn base_at(z: f64) -> Plane {
        Plane::new(v3(0.0, 0.0, z), v3(0.0, 0.0, 1.0)).unwrap()
    }

    #[test]
    fn hemispherical_shell_has_the_analytic_volume_and_thickness() {
        let endo = uv_sphere(v3(0.0, 0.0, 0.0), 20.0, 96, 48);
        let epi = uv_sphere(v3(0.0, 0.0, 0.0), 30.0, 128, 64);
        // Cut a little below the equator so no vertex row lies on the plane.
        let z = -1.3;
        let wall = build_wall(&endo, &epi, &base_at(z), Some(1.0)).unwrap();
        let cap = |r: f64| {
            // Sphere volume below z = -h (h > 0 measured from the centre).
            let h = r - z.abs();
            PI * h * h * (3.0 * r - h) / 3.0
        };
        let expected = (cap(30.0) - cap(20.0)) / 1000.0;
        assert!(
            (wall.volume_ml - expected).abs() / expected < 0.01,
            "{} vs {expected}",
            wall.volume_ml
        );
        assert!((wall.cavity_ml - cap(20.0) / 1000.0).abs() / (cap(20.0) / 1000.0) < 0.01);
        let v = validity(&wall.mesh);
        assert!(v.is_closed_manifold(), "{}", v.describe());
        assert_eq!(wall.self_intersections, 0);
        assert_eq!(wall.pushed.vertices, 0, "a 10 mm wall needs no repair");
        assert_eq!(wall.folded_edges_off_rim(), 0);
        assert!(
            crate::mesh::quality::quality(&wall.mesh).folded_edges > 0,
            "the rim"
        );
        // Away from the base ring, the thickness is the 10 mm between the spheres.
        let mut far = 0;
        for (p, t) in wall.mesh.positions.iter().zip(&wall.thickness) {
            if p.z < z - 5.0 {
                assert!((t - 10.0).abs() < 0.1, "{t} at {p:?}");
                far += 1;
            }
        }
        assert!(far > 1000, "{far}");
        // Every base triangle lies in the plane and faces the base.
        let mut base_area = 0.0;
        for (t, &r) in wall.regions.iter().enumerate() {
            let c = wall.mesh.corners(t);
            if r == BASE {
                for p in &c {
                    assert!((p.z - z).abs() < 1e-9);
                }
                let n = (c[1] - c[0]).cross(&(c[2] - c[0]));
                assert!(n.z > 0.0);
                base_area += 0.5 * n.norm();
            }
        }
        let (ro, ri) = (
            (30.0f64 * 30.0 - z * z).sqrt(),
            (20.0f64 * 20.0 - z * z).sqrt(),
        );
        let ring = PI * (ro * ro - ri * ri);
        assert!(
            (base_area - ring).abs() / ring < 0.01,
            "{base_area} vs {ring}"
        );
        assert_eq!(
            wall.triangles_per_region.iter().sum::<usize>(),
            wall.mesh.triangles.len()
        );
    }

    #[test]
    fn crossing_or_missing_surfaces_are_errors() {
        let small = uv_sphere(v3(0.0, 0.0, 0.0), 20.0, 64, 32);
        let big = uv_sphere(v3(0.0, 0.0, 0.0), 30.0, 64, 32);
        // Endocardium outside the epicardium at the base.
        let e = build_wall(&big, &small, &base_at(-1.3), None).unwrap_err();
        assert!(e.to_string().contains("swapped"), "{e}");
        // A plane that misses the surfaces.
        let e = build_wall(&small, &big, &base_at(40.0), None).unwrap_err();
        assert!(e.to_string().contains("does not cut"), "{e}");
        // Shifted endocardium poking through the epicardium below the base: counted.
        let shifted = uv_sphere(v3(8.0, 0.0, -3.0), 24.0, 64, 32);
        let wall = build_wall(&shifted, &big, &base_at(-1.3), None);
        match wall {
            Ok(w) => assert!(w.self_intersections > 0),
            Err(e) => assert!(e.to_string().contains("cross"), "{e}"),
        }
    }

    #[test]
    fn an_endocardium_through_the_epicardium_is_pushed_back_under_it() {
        let epi = uv_sphere(v3(0.0, 0.0, 0.0), 30.0, 96, 48);
        // Pokes 2 mm out on the +x side, below and at the base.
        let endo = uv_sphere(v3(8.0, 0.0, -3.0), 24.0, 96, 48);
        let base = base_at(-1.3);
        let wall = build_wall(&endo, &epi, &base, Some(1.0)).unwrap();
        let v = validity(&wall.mesh);
        assert!(v.is_closed_manifold(), "{}", v.describe());
        assert_eq!(wall.self_intersections, 0);
        assert!(wall.pushed.vertices > 20, "{:?}", wall.pushed);
        assert!(
            wall.pushed.max_mm > 2.5 && wall.pushed.max_mm < 4.5,
            "{:?}",
            wall.pushed
        );
        let nv_epi = wall
            .mesh
            .triangles
            .iter()
            .zip(&wall.regions)
            .filter(|(_, &r)| r == EPICARDIUM)
            .flat_map(|(t, _)| t.iter().copied())
            .max()
            .unwrap() as usize
            + 1;
        // Every endocardial vertex is at least the minimum thickness under the epicardium.
        let min_endo = wall.thickness[nv_epi..]
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        assert!((0.98..1.5).contains(&min_endo), "{min_endo}");
        // The outline stayed in the base plane.
        for (t, &r) in wall.regions.iter().enumerate() {
            if r == BASE {
                for p in wall.mesh.corners(t) {
                    assert!(base.signed_distance(&p).abs() < 1e-9);
                }
            }
        }
    }
}
