//! Volume and shape of linear volume cells (VTK's tetrahedron 10, hexahedron 12, wedge 13 and
//! pyramid 14, point orders as VTK defines them): what a simulation mesh's user checks first
//! (the total volume, the smallest scaled Jacobian, inverted cells), for the hexahedra heartmesh
//! writes and for any volume mesh `heartmesh info` is given.

use crate::geometry::Vec3;
use serde::Serialize;

/// VTK cell type numbers measured here.
pub const TETRA: u8 = 10;
pub const HEXAHEDRON: u8 = 12;
pub const WEDGE: u8 = 13;
pub const PYRAMID: u8 = 14;

/// At each corner, the corner and three neighbours whose edges form a right-handed frame in a
/// valid cell (the scaled Jacobian's corners).
const TETRA_CORNERS: [[usize; 4]; 4] = [[0, 1, 2, 3], [1, 2, 0, 3], [2, 0, 1, 3], [3, 2, 1, 0]];
const HEX_CORNERS: [[usize; 4]; 8] = [
    [0, 1, 3, 4],
    [1, 2, 0, 5],
    [2, 3, 1, 6],
    [3, 0, 2, 7],
    [4, 7, 5, 0],
    [5, 4, 6, 1],
    [6, 5, 7, 2],
    [7, 6, 4, 3],
];
const WEDGE_CORNERS: [[usize; 4]; 6] = [
    [0, 1, 2, 3],
    [1, 2, 0, 4],
    [2, 0, 1, 5],
    [3, 5, 4, 0],
    [4, 3, 5, 1],
    [5, 4, 3, 2],
];
/// The pyramid's base corners (its apex has four edges: no single frame).
const PYRAMID_CORNERS: [[usize; 4]; 4] = [[0, 1, 3, 4], [1, 2, 0, 4], [2, 3, 1, 4], [3, 0, 2, 4]];

/// Tetrahedra that fill each cell, positively oriented in a valid cell: its volume (the
/// hexahedron's around its diagonal 0-6).
const TETRA_TETS: [[usize; 4]; 1] = [[0, 1, 2, 3]];
const HEX_TETS: [[usize; 4]; 6] = [
    [0, 1, 2, 6],
    [0, 2, 3, 6],
    [0, 3, 7, 6],
    [0, 7, 4, 6],
    [0, 4, 5, 6],
    [0, 5, 1, 6],
];
const WEDGE_TETS: [[usize; 4]; 3] = [[0, 1, 2, 3], [1, 2, 3, 4], [2, 3, 4, 5]];
const PYRAMID_TETS: [[usize; 4]; 2] = [[0, 1, 2, 4], [0, 2, 3, 4]];

/// Four point positions in a cell: a corner with its three edges' ends, or a tetrahedron.
type Quad = [usize; 4];

/// A cell type's point count, its corners and the tetrahedra that fill it.
struct Tables {
    points: usize,
    corners: &'static [Quad],
    tets: &'static [Quad],
}

/// The tables of a VTK cell type; None for a type not measured here.
fn tables(vtk_type: u8) -> Option<Tables> {
    let (points, corners, tets): (usize, &'static [Quad], &'static [Quad]) = match vtk_type {
        TETRA => (4, &TETRA_CORNERS, &TETRA_TETS),
        HEXAHEDRON => (8, &HEX_CORNERS, &HEX_TETS),
        WEDGE => (6, &WEDGE_CORNERS, &WEDGE_TETS),
        PYRAMID => (5, &PYRAMID_CORNERS, &PYRAMID_TETS),
        _ => return None,
    };
    Some(Tables {
        points,
        corners,
        tets,
    })
}

/// How many points a cell of `vtk_type` has (None: not one of the types measured here).
pub fn point_count(vtk_type: u8) -> Option<usize> {
    tables(vtk_type).map(|t| t.points)
}

/// A readable name of a VTK cell type, for reports.
pub fn type_name(vtk_type: u8) -> String {
    match vtk_type {
        1 => "vertex".into(),
        3 => "line".into(),
        5 => "triangle".into(),
        9 => "quad".into(),
        TETRA => "tetrahedron".into(),
        HEXAHEDRON => "hexahedron".into(),
        WEDGE => "wedge".into(),
        PYRAMID => "pyramid".into(),
        24 => "quadratic tetrahedron".into(),
        25 => "quadratic hexahedron".into(),
        t => format!("VTK cell type {t}"),
    }
}

/// The measures of a set of cells.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CellQuality {
    /// Cells measured (those of the types above with their point count).
    pub measured: usize,
    /// Their total volume (mm3 when the points are in mm).
    pub volume: f64,
    /// The smallest corner's scaled Jacobian (1 a right-angled corner, 0 flat, below 0 turned
    /// inside out); infinite when nothing was measured.
    pub min_scaled_jacobian: f64,
    /// Cells with a corner at or below 0.
    pub inverted: usize,
}

/// The measures of `cells` (VTK type, point indices) over `points`; cells of other types, with
/// the wrong point count or an index outside `points` are passed over (`measured` says how many
/// were not).
pub fn quality<'a>(
    points: &[Vec3],
    cells: impl IntoIterator<Item = (u8, &'a [u32])>,
) -> CellQuality {
    let mut q = CellQuality {
        measured: 0,
        volume: 0.0,
        min_scaled_jacobian: f64::INFINITY,
        inverted: 0,
    };
    for (ty, ids) in cells {
        let Some(Tables {
            points: n,
            corners,
            tets,
        }) = tables(ty)
        else {
            continue;
        };
        let Some(p) = (ids.len() == n)
            .then(|| {
                ids.iter()
                    .map(|&i| points.get(i as usize).copied())
                    .collect::<Option<Vec<Vec3>>>()
            })
            .flatten()
        else {
            continue;
        };
        let mut worst = f64::INFINITY;
        for &[o, a, b, z] in corners {
            let (ea, eb, ez) = (p[a] - p[o], p[b] - p[o], p[z] - p[o]);
            let scale = ea.norm() * eb.norm() * ez.norm();
            let scaled = if scale > 0.0 {
                ea.cross(&eb).dot(&ez) / scale
            } else {
                0.0
            };
            worst = worst.min(scaled);
        }
        q.min_scaled_jacobian = q.min_scaled_jacobian.min(worst);
        if worst <= 0.0 {
            q.inverted += 1;
        }
        q.volume += tets
            .iter()
            .map(|&[a, b, c, d]| (p[b] - p[a]).cross(&(p[c] - p[a])).dot(&(p[d] - p[a])) / 6.0)
            .sum::<f64>();
        q.measured += 1;
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    /// The unit cube's corners in VTK's hexahedron order, scaled by (a, b, c).
    fn box_points(a: f64, b: f64, c: f64) -> Vec<Vec3> {
        [
            (0., 0., 0.),
            (1., 0., 0.),
            (1., 1., 0.),
            (0., 1., 0.),
            (0., 0., 1.),
            (1., 0., 1.),
            (1., 1., 1.),
            (0., 1., 1.),
        ]
        .iter()
        .map(|&(x, y, z)| v3(x * a, y * b, z * c))
        .collect()
    }

    #[test]
    fn boxes_wedges_tetrahedra_and_pyramids_have_their_volumes() {
        let p = box_points(2.0, 3.0, 4.0);
        let hex: Vec<u32> = (0..8).collect();
        let q = quality(&p, [(HEXAHEDRON, hex.as_slice())]);
        assert!((q.volume - 24.0).abs() < 1e-12);
        assert!((q.min_scaled_jacobian - 1.0).abs() < 1e-12);
        assert_eq!((q.measured, q.inverted), (1, 0));
        // Half the box as a wedge (triangle 0 1 3 under 4 5 7), a corner tetrahedron, the
        // pyramid on the bottom face up to the top's corner 4.
        let wedge = [0, 1, 3, 4, 5, 7];
        let tet = [0, 1, 3, 4];
        let pyramid = [0, 1, 2, 3, 4];
        let q = quality(
            &p,
            [
                (WEDGE, wedge.as_slice()),
                (TETRA, tet.as_slice()),
                (PYRAMID, pyramid.as_slice()),
            ],
        );
        assert!(
            (q.volume - (12.0 + 4.0 + 8.0)).abs() < 1e-12,
            "{}",
            q.volume
        );
        assert_eq!((q.measured, q.inverted), (3, 0));
        assert!(q.min_scaled_jacobian > 0.0);
    }

    #[test]
    fn a_cell_turned_inside_out_is_counted_and_others_passed_over() {
        let p = box_points(1.0, 1.0, 1.0);
        let mirrored: Vec<u32> = vec![4, 5, 6, 7, 0, 1, 2, 3];
        let q = quality(&p, [(HEXAHEDRON, mirrored.as_slice())]);
        assert_eq!(q.inverted, 1);
        assert!((q.volume + 1.0).abs() < 1e-12);
        assert!((q.min_scaled_jacobian + 1.0).abs() < 1e-12);
        let short = [0u32, 1, 2];
        let outside = [0u32, 1, 2, 99];
        let q = quality(
            &p,
            [
                (HEXAHEDRON, short.as_slice()),
                (TETRA, outside.as_slice()),
                (5, short.as_slice()),
            ],
        );
        assert_eq!(q.measured, 0);
        assert_eq!(q.min_scaled_jacobian, f64::INFINITY);
        assert_eq!(point_count(WEDGE), Some(6));
        assert_eq!(type_name(12), "hexahedron");
        assert_eq!(type_name(42), "VTK cell type 42");
    }
}
