//! A hexahedral volume mesh of the LV myocardium, for finite-element simulation: the layers of
//! cells between the anatomical layouts ([`crate::metrics::anatomical`]) of the endocardium and
//! the epicardium, laid out on one base plane from one septum, so that vertex k of one surface
//! faces vertex k of the other.
//!
//! Cardiac mechanics and electrophysiology codes (FEniCS, Chaste, CHeart, openCARP with a
//! hexahedral front end) start from such a mesh far more often than from a surface: its cells
//! follow the wall, and the three coordinates of the layout come with it, which is what
//! rule-based fibre directions are computed from (transmural depth above all). Each layer is
//! the straight interpolation between the two layouts, so the mesh has exactly the wall's
//! outer and inner surfaces at its first and last layer, and every cell spans the same
//! fraction of the wall.
//!
//! Cells: between consecutive rings, hexahedra (VTK_HEXAHEDRON, 8 points); around the apex,
//! where every ring-1 quad meets vertex 0, wedges (VTK_WEDGE, 6 points). Both are ordered as
//! VTK's parametric cells are (the first face's normal, by the right-hand rule, points into the
//! cell towards the opposite face), from endocardium to epicardium, so a valid cell has a
//! positive Jacobian at every corner. The base (the layouts' lids) is left open: the wall stops
//! at the base plane.
//!
//! Per point: `transmural` (0 on the endocardium, 1 on the epicardium), `longitudinal` (0 at
//! the apex, 1 at the base: the ring's index over the rings), `circumferential_deg` (the
//! layout's angle from the septum's middle towards anterior; 0 at the apex), and unit vectors
//! `fibre` (rule-based, a helix angle from +60 degrees at the endocardium to -60 at the
//! epicardium by default) and `sheet` (transmural). Per cell: its AHA
//! segment (1-17, [`crate::metrics::segments::segment_of`] at the cell's centre, the cavity's
//! depth the endocardial layout's length).

use super::cells;
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::metrics::anatomical::{Anatomical, Layout};
use crate::metrics::segments::segment_of;
use crate::sim::slice::Plane;
use serde::Serialize;

/// Allowed transmural layers (inclusive).
pub const LAYERS: (usize, usize) = (1, 20);
/// Streeter's helix angles (degrees): +60 at the endocardium, -60 at the epicardium.
pub const DEFAULT_HELIX_DEG: (f64, f64) = (60.0, -60.0);

/// The default: three layers, the fewest that give a sub-endocardial, a mid-wall and a
/// sub-epicardial cell through the wall.
pub const DEFAULT_LAYERS: usize = 3;

/// One cell: VTK's linear hexahedron or wedge, point indices in VTK's order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cell {
    Hexahedron([u32; 8]),
    Wedge([u32; 6]),
}

impl Cell {
    /// VTK's cell type number (12 hexahedron, 13 wedge).
    pub fn vtk_type(&self) -> u8 {
        match self {
            Cell::Hexahedron(_) => cells::HEXAHEDRON,
            Cell::Wedge(_) => cells::WEDGE,
        }
    }

    pub fn points(&self) -> &[u32] {
        match self {
            Cell::Hexahedron(p) => p,
            Cell::Wedge(p) => p,
        }
    }
}

/// What a report says of the mesh.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    pub rings: usize,
    pub points_per_ring: usize,
    pub layers: usize,
    pub points: usize,
    pub hexahedra: usize,
    pub wedges: usize,
    /// The cells' total volume (ml), and the volume between the two layouts' surfaces (the
    /// epicardial layout's less the endocardial one's): they differ by how the cells' and the
    /// surfaces' quads are split into triangles.
    pub volume_ml: f64,
    pub layouts_volume_ml: f64,
    /// The smallest scaled Jacobian over every corner of every cell (1 for a cube's corner,
    /// 0 for a flat one, negative for an inverted one) and the cells with a corner at or below 0.
    pub min_scaled_jacobian: f64,
    pub inverted_cells: usize,
    /// The fibres' helix angle at the endocardium and at the epicardium (degrees).
    pub helix_deg: [f64; 2],
    /// Endocardial vertices moved in along their rays to keep the wall the minimum thickness.
    pub endocardium_moved: usize,
}

/// A built mesh.
#[derive(Debug, Clone)]
pub struct HexWall {
    pub points: Vec<Vec3>,
    pub cells: Vec<Cell>,
    pub transmural: Vec<f64>,
    pub longitudinal: Vec<f64>,
    pub circumferential_deg: Vec<f64>,
    /// Per point, unit vectors: the rule-based fibre direction and the transmural (sheet)
    /// direction ([`fibres`]).
    pub fibre: Vec<Vec3>,
    pub sheet: Vec<Vec3>,
    /// One AHA segment (1-17) per cell.
    pub aha_segment: Vec<u32>,
    pub summary: Summary,
}

/// The mesh between `endo` and `epi`, two layouts of one `layout` built on `base` from one
/// septum, `layers` cells through the wall, fibres at [`DEFAULT_HELIX_DEG`].
pub fn build(
    endo: &Anatomical,
    epi: &Anatomical,
    layout: Layout,
    base: &Plane,
    layers: usize,
) -> Result<HexWall> {
    build_with_helix(endo, epi, layout, base, layers, DEFAULT_HELIX_DEG, None)
}

/// [`build`] with the fibres' helix angle `helix_deg` (at the endocardium, at the epicardium;
/// each within +-90 degrees), linear through the wall, and, with `min_thickness_mm`, the wall
/// kept at least that thick along each vertex's ray ([`keep_apart`]).
pub fn build_with_helix(
    endo: &Anatomical,
    epi: &Anatomical,
    layout: Layout,
    base: &Plane,
    layers: usize,
    helix_deg: (f64, f64),
    min_thickness_mm: Option<f64>,
) -> Result<HexWall> {
    let (h_endo, h_epi) = helix_deg;
    if !(h_endo.abs() <= 90.0 && h_epi.abs() <= 90.0) {
        return Err(CoreError::ParamInvalid {
            name: "helix angles".into(),
            message: format!("each within -90 to 90 degrees (got {h_endo}, {h_epi})"),
        });
    }
    if !(LAYERS.0..=LAYERS.1).contains(&layers) {
        return Err(CoreError::ParamInvalid {
            name: "layers".into(),
            message: format!(
                "{}-{} layers through the wall (got {layers})",
                LAYERS.0, LAYERS.1
            ),
        });
    }
    // The fields are public: a layout made without `Layout::new` is checked here.
    Layout::new(layout.rings, layout.points).map_err(|message| CoreError::ParamInvalid {
        name: "layout".into(),
        message,
    })?;
    let per_layer = layout.vertices() - 1; // the lid's centre is not part of the wall
    for (grid, what) in [(endo, "endocardial"), (epi, "epicardial")] {
        if grid.mesh.positions.len() != layout.vertices() {
            return Err(CoreError::InvalidMesh(format!(
                "the {what} layout has {} vertices, not the {}x{} layout's {}",
                grid.mesh.positions.len(),
                layout.rings,
                layout.points,
                layout.vertices()
            )));
        }
    }
    let (inner, moved) = keep_apart(endo, epi, per_layer, min_thickness_mm);
    let mut points = Vec::with_capacity(per_layer * (layers + 1));
    let mut transmural = Vec::with_capacity(points.capacity());
    let mut longitudinal = Vec::with_capacity(points.capacity());
    let mut circumferential_deg = Vec::with_capacity(points.capacity());
    for l in 0..=layers {
        let t = l as f64 / layers as f64;
        for (v, (&a, &b)) in inner.iter().zip(&epi.mesh.positions).enumerate() {
            points.push(a + (b - a) * t);
            transmural.push(t);
            let (ring, j) = if v == 0 {
                (0, 0)
            } else {
                ((v - 1) / layout.points + 1, (v - 1) % layout.points)
            };
            longitudinal.push(ring as f64 / layout.rings as f64);
            circumferential_deg.push(360.0 * j as f64 / layout.points as f64);
        }
    }
    let (fibre, sheet) = fibres(&points, per_layer, layers, layout, &base.normal, helix_deg);
    let at = |l: usize, v: usize| (l * per_layer + v) as u32;
    let grid = |ring: usize, j: usize| layout.index(ring, j);
    let mut cells = Vec::with_capacity(layers * layout.points * layout.rings);
    for l in 0..layers {
        for j in 0..layout.points {
            // The ring-1 triangle seen from inside the cavity: reversed, its normal points out
            // through the wall (the apex's epicardial side), towards layer l + 1.
            let tri = [0, grid(1, j + 1), grid(1, j)];
            cells.push(Cell::Wedge([
                at(l, tri[0]),
                at(l, tri[1]),
                at(l, tri[2]),
                at(l + 1, tri[0]),
                at(l + 1, tri[1]),
                at(l + 1, tri[2]),
            ]));
        }
        for ring in 1..layout.rings {
            for j in 0..layout.points {
                // Round the axis (towards anterior) then up: the outward normal.
                let quad = [
                    grid(ring, j),
                    grid(ring, j + 1),
                    grid(ring + 1, j + 1),
                    grid(ring + 1, j),
                ];
                cells.push(Cell::Hexahedron([
                    at(l, quad[0]),
                    at(l, quad[1]),
                    at(l, quad[2]),
                    at(l, quad[3]),
                    at(l + 1, quad[0]),
                    at(l + 1, quad[1]),
                    at(l + 1, quad[2]),
                    at(l + 1, quad[3]),
                ]));
            }
        }
    }
    let cavity_depth = endo.summary.length_mm;
    let aha_segment = cells
        .iter()
        .map(|c| {
            let ids = c.points();
            let centre = ids.iter().map(|&i| points[i as usize]).sum::<Vec3>() / ids.len() as f64;
            let depth = -base.signed_distance(&centre);
            let angle = cell_angle(c, &circumferential_deg, layout);
            segment_of(depth, cavity_depth, angle) as u32 + 1
        })
        .collect();
    let q = cells::quality(&points, cells.iter().map(|c| (c.vtk_type(), c.points())));
    let wedges = cells.iter().filter(|c| matches!(c, Cell::Wedge(_))).count();
    let summary = Summary {
        rings: layout.rings,
        points_per_ring: layout.points,
        layers,
        points: points.len(),
        hexahedra: cells.len() - wedges,
        wedges,
        volume_ml: q.volume / 1000.0,
        layouts_volume_ml: epi.summary.volume_ml - endo.summary.volume_ml,
        min_scaled_jacobian: q.min_scaled_jacobian,
        inverted_cells: q.inverted,
        helix_deg: [helix_deg.0, helix_deg.1],
        endocardium_moved: moved,
    };
    Ok(HexWall {
        points,
        cells,
        transmural,
        longitudinal,
        circumferential_deg,
        fibre,
        sheet,
        aha_segment,
        summary,
    })
}

/// The endocardial layout's vertices, each moved in along its ray where the epicardium's vertex
/// on the same ray lies less than `min_thickness_mm` outside it (a thinned apex, a groove of the
/// epicardium, images from different breath-holds: the two surfaces touch or cross there and
/// the cells between them would be flat or inverted), and how many moved. The wall solid's
/// `--min-thickness` does the same to its endocardium. Layouts of one frame ([`build_pair`])
/// share their rays; layouts of two frames are left as they are.
///
/// [`build_pair`]: crate::metrics::anatomical::build_pair
fn keep_apart(
    endo: &Anatomical,
    epi: &Anatomical,
    per_layer: usize,
    min_thickness_mm: Option<f64>,
) -> (Vec<Vec3>, usize) {
    let mut inner: Vec<Vec3> = endo.mesh.positions[..per_layer].to_vec();
    let Some(min) = min_thickness_mm.filter(|m| *m > 0.0) else {
        return (inner, 0);
    };
    let mut moved = 0;
    for (v, p) in inner.iter_mut().enumerate() {
        // Layouts assembled by hand may carry no rays: nothing to measure along.
        let (Some(&ray), Some(&other)) = (endo.rays.get(v), epi.rays.get(v)) else {
            continue;
        };
        if ray.norm() < 0.5 || (ray - other).norm() > 1e-9 {
            continue;
        }
        let outer = epi.mesh.positions[v];
        if (outer - *p).dot(&ray) < min {
            *p = outer - ray * min;
            moved += 1;
        }
    }
    (inner, moved)
}

/// A unit vector perpendicular to `v` (x, else y, crossed with it).
fn across(v: &Vec3) -> Vec3 {
    v.cross(&Vec3::x())
        .try_normalize(1e-9)
        .or_else(|| v.cross(&Vec3::y()).try_normalize(1e-9))
        .unwrap_or_else(Vec3::z)
}

/// Rule-based fibre directions (Streeter et al., Circ Res 1969; the linear rule of Bayer et al.,
/// Ann Biomed Eng 2012) at every point: the local frame is the transmural direction (the
/// point's line from the endocardial to the epicardial layout: the `sheet`), the circumferential
/// one (along its ring, towards anterior: counterclockwise seen from the base) and the
/// longitudinal one (their cross product, towards the base); the fibre turns from the
/// circumferential towards the longitudinal direction by the helix angle, `helix_deg.0` on the
/// endocardium to `helix_deg.1` on the epicardium, linear in the transmural coordinate. A
/// positive angle makes a right-handed helix (Streeter's endocardium, +60 degrees), a negative
/// one a left-handed helix (his epicardium, -60). The apex, where no ring runs round, takes the
/// frame of ring 1's first vertex.
fn fibres(
    points: &[Vec3],
    per_layer: usize,
    layers: usize,
    layout: Layout,
    axis: &Vec3,
    helix_deg: (f64, f64),
) -> (Vec<Vec3>, Vec<Vec3>) {
    let mut fibre = Vec::with_capacity(points.len());
    let mut sheet = Vec::with_capacity(points.len());
    for l in 0..=layers {
        let at = |v: usize| points[l * per_layer + v];
        let t = l as f64 / layers as f64;
        let helix = (helix_deg.0 + (helix_deg.1 - helix_deg.0) * t).to_radians();
        for v in 0..per_layer {
            // The apex borrows ring 1's first vertex's frame.
            let (ring, j) = if v == 0 {
                (1, 0)
            } else {
                ((v - 1) / layout.points + 1, (v - 1) % layout.points)
            };
            let w = layout.index(ring, j);
            let outward = points[layers * per_layer + w] - points[w];
            // Where the two layouts meet (no wall: never on a valid wall), any direction across
            // the axis keeps the vectors finite.
            let transmural = outward.try_normalize(1e-12).unwrap_or_else(|| across(axis));
            let k = layout.points;
            let round = at(layout.index(ring, j + 1)) - at(layout.index(ring, j + k - 1));
            let circumferential = (round - transmural * round.dot(&transmural))
                .try_normalize(1e-12)
                .or_else(|| axis.cross(&transmural).try_normalize(1e-12))
                .unwrap_or_else(|| across(&transmural));
            let longitudinal = transmural.cross(&circumferential);
            fibre.push(circumferential * helix.cos() + longitudinal * helix.sin());
            sheet.push(transmural);
        }
    }
    (fibre, sheet)
}

/// The file's header: what the cells and arrays are (the command line's and the app's files
/// say the same).
pub fn comment(h: &HexWall, file_name: &str, endo: &str, epi: &str) -> String {
    let name = file_name.rsplit(['/', '\\']).next().unwrap_or(file_name);
    let s = &h.summary;
    format!(
        "LV myocardium hexahedra {}x{}x{} of {name} ({endo} + {epi}); units mm, the contour \
         file's coordinates; points transmural 0-1, longitudinal 0-1, circumferential_deg from \
         the septum, fibre, sheet; cells aha_segment 1-17",
        s.rings, s.points_per_ring, s.layers
    )
}

impl HexWall {
    /// The mesh as a VTK legacy unstructured grid (ParaView, meshio, and through meshio most
    /// simulation codes): point data `transmural`, `longitudinal`, `circumferential_deg` and the
    /// vectors `fibre` and `sheet`, cell data `aha_segment`.
    pub fn to_vtk(&self, header_comment: &str) -> Vec<u8> {
        self.to_vtk_with(header_comment, None)
    }

    /// [`HexWall::to_vtk`] with one more per-point vector array (`volumes --hex-meshes`: each
    /// point's displacement from end-diastole).
    pub fn to_vtk_with(&self, header_comment: &str, extra: Option<(&str, &[Vec3])>) -> Vec<u8> {
        let mut vectors: Vec<(&str, &[Vec3])> =
            vec![("fibre", &self.fibre), ("sheet", &self.sheet)];
        vectors.extend(extra);
        let cells: Vec<(u8, &[u32])> = self
            .cells
            .iter()
            .map(|c| (c.vtk_type(), c.points()))
            .collect();
        crate::io::vtk::write_unstructured(
            &self.points,
            &cells,
            &[
                ("transmural", &self.transmural),
                ("longitudinal", &self.longitudinal),
                ("circumferential_deg", &self.circumferential_deg),
            ],
            &vectors,
            &[("aha_segment", &self.aha_segment)],
            header_comment,
        )
    }
}

/// The angle of a cell's middle from the septum (degrees, -180 to 180 as
/// [`segment_of`] takes it): half a step on from its first vertex round the ring.
fn cell_angle(cell: &Cell, circumferential_deg: &[f64], layout: Layout) -> f64 {
    // Corner 0 of a hexahedron and corner 2 of a wedge are vertex j of their ring (corner 0 of
    // a wedge is the apex).
    let first = circumferential_deg[cell.points()[match cell {
        Cell::Hexahedron(_) => 0,
        Cell::Wedge(_) => 2,
    }] as usize];
    let middle = first + 180.0 / layout.points as f64;
    (middle + 180.0).rem_euclid(360.0) - 180.0
}

#[cfg(test)]
mod tests;
