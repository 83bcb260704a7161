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

use super::clip::{clip_below, keep_piece_of, mean_edge_length, Clipped};
use super::inset::{clear_crossings, push, Keep, Pushed};
use super::intersect::crossing_pairs;
use super::outline::{inside, plane_basis, separate_outlines};
use super::quality::folded_edges_within;
use super::topology::validity;
use super::TriMesh;
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::io::{write_mesh_with, MeshFormat, Regions};
use crate::metrics::function::MYOCARDIAL_DENSITY_G_PER_ML;
use crate::metrics::{stats, Stats};
use crate::sim::slice::Plane;
use crate::spatial::Bvh;
use nalgebra::Point2;
use serde::Serialize;
use spade::{ConstrainedDelaunayTriangulation, Triangulation};

/// The regions of an LV wall's triangles, in the order of their ids.
pub const REGION_NAMES: [&str; 3] = ["epicardium", "endocardium", "base"];
/// The regions of a biventricular wall's triangles ([`build_biventricular`]): the outer surface,
/// the two cavities' surfaces, the base, as biventricular simulation meshes label them.
pub const BIV_REGION_NAMES: [&str; 4] = ["epicardium", "lv_endocardium", "rv_endocardium", "base"];
/// Region id of epicardial triangles.
pub const EPICARDIUM: u32 = 0;
/// Region id of endocardial triangles (of the LV wall; in a biventricular wall the LV's).
pub const ENDOCARDIUM: u32 = 1;
/// Region id of the base ring's triangles in an LV wall (the last region in any wall).
pub const BASE: u32 = 2;

/// Vertices this close to the base plane, as a share of the mean edge length, are moved onto it
/// before cutting (no sliver triangles along the cut).
const SNAP_SHARE: f64 = 0.2;

/// A myocardium wall.
#[derive(Debug, Clone)]
pub struct Wall {
    /// Closed, manifold, outward-facing (the endocardium faces into the cavity).
    pub mesh: TriMesh,
    /// Region id of every triangle, an index into `region_names`.
    pub regions: Vec<u32>,
    /// [`REGION_NAMES`] or [`BIV_REGION_NAMES`]: the epicardium, each cavity, the base.
    pub region_names: &'static [&'static str],
    /// Wall thickness at every vertex (mm): the distance from an epicardial vertex to the
    /// endocardium and from an endocardial one to the epicardium (base-ring vertices are on
    /// one of the two).
    pub thickness: Vec<f64>,
    /// The base plane (normal towards the base).
    pub base: Plane,
    /// Enclosed volume of the wall (ml).
    pub volume_ml: f64,
    /// Volume of the (first, the LV) cavity below the base (ml): its endocardium closed by the
    /// base plane.
    pub cavity_ml: f64,
    /// Every cavity's volume below the base (ml), in region order.
    pub cavities_ml: Vec<f64>,
    /// Pairs of triangles that pass through each other: nonzero where the endocardium crosses
    /// the epicardium (a wall thinner than the reconstructions' error).
    pub self_intersections: usize,
    /// Those pairs by the regions they join (each pair of regions once, in region order).
    pub crossings: Vec<Crossing>,
    /// Endocardial vertices moved before the wall was built (all cavities together, by where
    /// they ended): under the epicardium, out of the other cavity, and relaxed where those moves
    /// folded a cavity through itself.
    pub pushed: Pushed,
    /// Epicardial vertices moved out over the endocardium (where it still poked in between
    /// the endocardium's moved vertices).
    pub epi_pushed: Pushed,
    /// Triangles per region, in `region_names` order.
    pub triangles_per_region: Vec<usize>,
    /// What the build left out or changed beyond the moves above, one sentence each (a fold of
    /// a surface dipping below the base on its own).
    pub notes: Vec<String>,
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
    let cavities = [Cavity {
        mesh: endo,
        name: "endocardium",
    }];
    let parts = Parts {
        epi,
        cavities: &cavities,
        names: &REGION_NAMES,
        min_thickness_mm,
    };
    build_solid(&parts, base)
}

/// The biventricular myocardium: the closed biventricular epicardium (`BIV_EPI`) minus the LV
/// and RV cavities, below `base`, as one solid ([`BIV_REGION_NAMES`]). Everything
/// [`build_wall`] does, and with `min_thickness_mm` the two cavities are also kept that far
/// apart (the septum).
pub fn build_biventricular(
    lv_endo: &TriMesh,
    rv_endo: &TriMesh,
    biv_epi: &TriMesh,
    base: &Plane,
    min_thickness_mm: Option<f64>,
) -> Result<Wall> {
    let cavities = [
        Cavity {
            mesh: lv_endo,
            name: "LV endocardium",
        },
        Cavity {
            mesh: rv_endo,
            name: "RV endocardium",
        },
    ];
    let parts = Parts {
        epi: biv_epi,
        cavities: &cavities,
        names: &BIV_REGION_NAMES,
        min_thickness_mm,
    };
    build_solid(&parts, base)
}

/// Steps (mm) in which the base moves towards the apex when the surfaces cannot be joined at the
/// plane given, and how far it may go: less than half the usual 8-10 mm slice spacing, so the
/// base stays nearer the most basal slice than the next one.
const BASE_STEP_MM: f64 = 1.0;
const BASE_MAX_SHIFT_MM: f64 = 4.0;

/// One cavity of a wall: its closed surface and its name in messages.
struct Cavity<'a> {
    mesh: &'a TriMesh,
    name: &'a str,
}

/// What a wall is made of, whatever plane cuts it: [`build_solid`] tries it at several planes,
/// so the parts travel together instead of as the same five arguments at every try.
#[derive(Clone, Copy)]
struct Parts<'a> {
    epi: &'a TriMesh,
    /// The cavities inside `epi`.
    cavities: &'a [Cavity<'a>],
    /// The epicardium's region, one per cavity, then the base's.
    names: &'static [&'static str],
    min_thickness_mm: Option<f64>,
}

/// The solid between the epicardium and the cavities inside it, below `base`. Where the
/// surfaces cannot be joined at `base`, or only with triangles passing through each other (at
/// the most basal slice, misaligned images can leave a fold of one surface dipping through the
/// plane, an outline across another, a cavity far out through the epicardium just under the
/// plane), the base moves towards the apex in [`BASE_STEP_MM`] steps, at most
/// [`BASE_MAX_SHIFT_MM`], to the first plane that gives a solid without crossings; the wall's
/// `base` is the plane used and a note says why it moved (crossings only count with a minimum
/// thickness: without it the surfaces are wanted as they are). When none does, the wall at
/// `base` or its error.
fn build_solid(parts: &Parts, base: &Plane) -> Result<Wall> {
    let first = build_solid_at(parts, base);
    let why = match &first {
        // Without the thickness rule the surfaces are wanted as reconstructed, crossings and all.
        Ok(wall) if wall.self_intersections == 0 || parts.min_thickness_mm.is_none() => {
            return first
        }
        Ok(wall) => format!(
            "the wall had {} pairs of triangles passing through each other",
            wall.self_intersections
        ),
        Err(CoreError::Degenerate(m) | CoreError::InvalidMesh(m)) => m.clone(),
        Err(other) => other.to_string(),
    };
    let steps = (BASE_MAX_SHIFT_MM / BASE_STEP_MM).round() as usize;
    for k in 1..=steps {
        let shift = k as f64 * BASE_STEP_MM;
        let lower = Plane {
            origin: base.origin - base.normal * shift,
            normal: base.normal,
        };
        match build_solid_at(parts, &lower) {
            Ok(mut wall) if wall.self_intersections == 0 => {
                wall.notes.insert(
                    0,
                    format!(
                        "the base was moved {shift:.0} mm towards the apex: at the plane given, \
                         {why}"
                    ),
                );
                return Ok(wall);
            }
            _ => continue,
        }
    }
    first
}

/// [`build_solid`] at exactly `base`.
fn build_solid_at(parts: &Parts, base: &Plane) -> Result<Wall> {
    let Parts {
        epi,
        cavities,
        names,
        min_thickness_mm,
    } = *parts;
    let mut notes = Vec::new();
    let mut epi_cut = cut(epi, base, "epicardium", &mut notes)?;
    let mut cuts = cavities
        .iter()
        .map(|c| cut(c.mesh, base, c.name, &mut notes))
        .collect::<Result<Vec<_>>>()?;
    // Checked before any vertex moves: pushing a whole surface through the other would hide it.
    let epi_ml = closed_by_plane_ml(&epi_cut.mesh, base);
    for (c, cavity) in cuts.iter().zip(cavities) {
        if closed_by_plane_ml(&c.mesh, base) >= epi_ml {
            return Err(CoreError::Degenerate(format!(
                "below the base the {} encloses at least as much as the epicardium: are the \
                 surfaces' names swapped?",
                cavity.name
            )));
        }
    }
    let (pushed, epi_pushed) = match min_thickness_mm {
        Some(depth) => separate(&mut cuts, &mut epi_cut, base, depth),
        None => (Pushed::default(), Pushed::default()),
    };

    let mut positions = epi_cut.mesh.positions.clone();
    let mut triangles: Vec<[u32; 3]> = epi_cut.mesh.triangles.clone();
    let mut regions = vec![EPICARDIUM; triangles.len()];
    // Where each surface's vertices start in the solid: epicardium, then each cavity.
    let mut starts = vec![0usize];
    let mut loops = vec![epi_cut.loops[0].clone()];
    for (k, c) in cuts.iter().enumerate() {
        let first = positions.len() as u32;
        starts.push(positions.len());
        positions.extend_from_slice(&c.mesh.positions);
        for t in &c.mesh.triangles {
            // Reversed: an endocardium faces into its cavity, out of the wall.
            triangles.push([t[0] + first, t[2] + first, t[1] + first]);
            regions.push(k as u32 + 1);
        }
        loops.push(c.loops[0].iter().map(|&v| v + first).collect());
    }
    let base_region = cuts.len() as u32 + 1;
    for t in ring(&positions, &loops, cavities, base)? {
        triangles.push(t);
        regions.push(base_region);
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
    let surfaces: Vec<&TriMesh> = std::iter::once(&epi_cut.mesh)
        .chain(cuts.iter().map(|c| &c.mesh))
        .collect();
    let thickness = thickness(&mesh, &starts, &surfaces);
    let mut triangles_per_region = vec![0usize; names.len()];
    for &r in &regions {
        triangles_per_region[r as usize] += 1;
    }
    let cavities_ml: Vec<f64> = cuts
        .iter()
        .map(|c| closed_by_plane_ml(&c.mesh, base))
        .collect();
    let pairs = crossing_pairs(&mesh);
    let mut by_regions: std::collections::BTreeMap<(u32, u32), usize> = Default::default();
    for (a, b) in &pairs {
        let (ra, rb) = (regions[*a], regions[*b]);
        *by_regions.entry((ra.min(rb), ra.max(rb))).or_default() += 1;
    }
    let crossings = by_regions
        .into_iter()
        .map(|((a, b), pairs)| Crossing {
            regions: [names[a as usize], names[b as usize]],
            pairs,
        })
        .collect();
    Ok(Wall {
        self_intersections: pairs.len(),
        crossings,
        cavity_ml: cavities_ml[0],
        cavities_ml,
        mesh,
        regions,
        region_names: names,
        thickness,
        base: *base,
        volume_ml,
        pushed,
        epi_pushed,
        triangles_per_region,
        notes,
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
    /// Each cavity below the base (one for an LV wall; the LV's and the RV's for a
    /// biventricular one).
    pub cavities: Vec<CavityVolume>,
    /// Pairs of triangles passing through each other, all regions together (the name of the
    /// LV wall's only case).
    pub endo_epi_crossings: usize,
    /// The same by pair of regions.
    pub crossings: Vec<Crossing>,
    pub endocardium_moved: Moved,
    pub epicardium_moved: Moved,
    /// [`Wall::notes`].
    pub notes: Vec<String>,
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

/// Triangles of two regions (or of one, folded through itself) that pass through each other.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Crossing {
    pub regions: [&'static str; 2],
    pub pairs: usize,
}

/// A cavity's volume below the base, by its region's name.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CavityVolume {
    pub region: &'static str,
    pub volume_ml: f64,
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
            names: self.region_names,
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
            regions: self
                .region_names
                .iter()
                .zip(&self.triangles_per_region)
                .enumerate()
                .map(|(i, (&name, &triangles))| RegionCount {
                    id: i + 1,
                    name,
                    triangles,
                })
                .collect(),
            cavities: self
                .region_names
                .iter()
                .skip(1)
                .zip(&self.cavities_ml)
                .map(|(&region, &volume_ml)| CavityVolume { region, volume_ml })
                .collect(),
            endo_epi_crossings: self.self_intersections,
            crossings: self.crossings.clone(),
            endocardium_moved: moved(self.pushed),
            epicardium_moved: moved(self.epi_pushed),
            notes: self.notes.clone(),
        }
    }

    /// Edges where neighbouring triangles of one region turn against each other by more than
    /// a right angle (folds of a surface); the rim, where the base meets the walls at about a
    /// right angle by design, is left out.
    pub fn folded_edges_off_rim(&self) -> usize {
        folded_edges_within(&self.mesh, &self.regions)
    }
}

/// Rounds of [`separate`]: a wall needing more is not a wall the contours describe.
const SEPARATION_ROUNDS: usize = 6;

/// Passes of [`clear_crossings`] at most: each moves a crossing triangle's corners by a step
/// of half the depth (at least 0.25 mm), so 24 passes reach 6 mm, twice the thickness of a
/// right-ventricular free wall.
const CROSSING_PASSES: usize = 24;

/// Moves each endocardium under the epicardium by `depth` mm ([`push`]) and out of the other
/// cavities by as much (the septum between two), then the epicardium out over the endocardia
/// where their triangles still span across it (a coarse endocardial triangle over a finer
/// epicardial bump), until nothing moves or after [`SEPARATION_ROUNDS`]; then, where an
/// endocardial triangle still passes through the epicardium with its corners at the depth
/// under their nearest faces (an inward crease of the epicardium between them), its corners
/// go under the face crossed ([`clear_crossings`]) and the rounds run again. Outline vertices
/// stay in the base plane. Returns the endocardia's moves (together) and the epicardium's.
fn separate(
    cavities: &mut [Clipped],
    epi: &mut Clipped,
    base: &Plane,
    depth: f64,
) -> (Pushed, Pushed) {
    let mask = |c: &Clipped| {
        let mut m = vec![false; c.mesh.positions.len()];
        for &v in &c.loops[0] {
            m[v as usize] = true;
        }
        m
    };
    let masks: Vec<Vec<bool>> = cavities.iter().map(mask).collect();
    let epi_mask = mask(epi);
    let before: Vec<Vec<Vec3>> = cavities.iter().map(|c| c.mesh.positions.clone()).collect();
    let epi_before = epi.mesh.positions.clone();
    let rounds = |cavities: &mut [Clipped], epi: &mut Clipped| {
        for _ in 0..SEPARATION_ROUNDS {
            if separation_round(cavities, epi, base, depth, &masks, &epi_mask) == 0 {
                break;
            }
        }
        for (c, m) in cavities.iter_mut().zip(&masks) {
            untangle(&mut c.mesh, m);
        }
    };
    rounds(cavities, epi);
    let step = 0.5 * depth.max(0.5);
    let mut cleared = false;
    for _ in 0..CROSSING_PASSES {
        let mut moved = 0;
        for (c, m) in cavities.iter_mut().zip(&masks) {
            moved += clear_crossings(&mut c.mesh, &epi.mesh, m, depth, step).vertices;
        }
        if moved == 0 {
            break;
        }
        cleared = true;
    }
    if cleared {
        rounds(cavities, epi);
    }
    let cavity_moves = before
        .iter()
        .zip(cavities.iter())
        .map(|(b, c)| net_moves(b, &c.mesh.positions))
        .fold(Pushed::default(), |acc, p| Pushed {
            vertices: acc.vertices + p.vertices,
            max_mm: acc.max_mm.max(p.max_mm),
        });
    (cavity_moves, net_moves(&epi_before, &epi.mesh.positions))
}

/// One round of [`separate`]'s pushes; returns how many vertices moved.
fn separation_round(
    cavities: &mut [Clipped],
    epi: &mut Clipped,
    base: &Plane,
    depth: f64,
    masks: &[Vec<bool>],
    epi_mask: &[bool],
) -> usize {
    let mut moved = 0;
    for k in 0..cavities.len() {
        let epi_closed = capped(epi, base);
        let p = &mut cavities[k].mesh;
        moved += push(
            p,
            &epi.mesh,
            &epi_closed,
            depth,
            Keep::Inside,
            Some((base, &masks[k])),
        )
        .vertices;
        for j in (0..cavities.len()).filter(|&j| j != k) {
            let other = cavities[j].mesh.clone();
            let other_closed = capped(&cavities[j], base);
            let p = &mut cavities[k].mesh;
            moved += push(
                p,
                &other,
                &other_closed,
                depth,
                Keep::Outside,
                Some((base, &masks[k])),
            )
            .vertices;
        }
    }
    for c in cavities.iter() {
        moved += push(
            &mut epi.mesh,
            &c.mesh,
            &capped(c, base),
            depth,
            Keep::Outside,
            Some((base, epi_mask)),
        )
        .vertices;
    }
    // Last in the round: the pushes above may have moved outline vertices (projected into
    // the plane) too little or too far, and the ring needs the outlines clear of each other.
    moved + separate_outlines(cavities, epi, base, depth).vertices
}

/// Passes of [`untangle`]: each relaxes the crossing triangles' corners and their neighbours.
const UNTANGLE_PASSES: usize = 10;

/// Relaxes a surface where pushes folded it through itself: a cavity narrower than twice the
/// minimum thickness (an RV near its apex at end-systole) has both its sides pushed inwards,
/// past each other. The corners of the crossing triangles and their neighbours move to the mean
/// of their neighbours until nothing crosses (at most [`UNTANGLE_PASSES`] times); `fixed`
/// vertices (the outline in the base plane) stay.
fn untangle(mesh: &mut TriMesh, fixed: &[bool]) {
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); mesh.positions.len()];
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k] as usize, t[(k + 1) % 3]);
            if !neighbours[a].contains(&b) {
                neighbours[a].push(b);
                neighbours[b as usize].push(t[k]);
            }
        }
    }
    for _ in 0..UNTANGLE_PASSES {
        let pairs = crossing_pairs(mesh);
        if pairs.is_empty() {
            return;
        }
        let mut chosen = vec![false; mesh.positions.len()];
        for (a, b) in pairs {
            for v in mesh.triangles[a].iter().chain(&mesh.triangles[b]) {
                chosen[*v as usize] = true;
                for &w in &neighbours[*v as usize] {
                    chosen[w as usize] = true;
                }
            }
        }
        let before = mesh.positions.clone();
        for (v, _) in chosen.iter().enumerate().filter(|(_, &c)| c) {
            if fixed.get(v).copied().unwrap_or(true) || neighbours[v].is_empty() {
                continue;
            }
            let sum = neighbours[v]
                .iter()
                .fold(Vec3::zeros(), |acc, &w| acc + before[w as usize]);
            mesh.positions[v] = sum / neighbours[v].len() as f64;
        }
    }
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

/// Outlines of separate pieces may be left out of a surface's cut while together they enclose
/// at most this share of the area its main outline does: folds of a surface's top that dip
/// below the base on their own (a misaligned basal slice), not a second lobe of the cavity.
const STRAY_PIECE_SHARE: f64 = 0.05;

/// One surface cut at the base: one outline (with any small separate pieces below the plane
/// left out, said in `notes`), or an error that says what the plane met.
fn cut(mesh: &TriMesh, base: &Plane, name: &str, notes: &mut Vec<String>) -> Result<Clipped> {
    let snap = SNAP_SHARE * mean_edge_length(mesh);
    let at = |e: CoreError| CoreError::InvalidMesh(format!("{name} at the base plane: {e}"));
    // Snapping a vertex onto the plane where the surface only comes near it can pinch two
    // outlines together at that vertex; the exact cut has no such vertex.
    let mut clipped = match clip_below(mesh, base, snap) {
        Ok(c) => c,
        Err(_) if snap > 0.0 => clip_below(mesh, base, 0.0).map_err(at)?,
        Err(e) => return Err(at(e)),
    };
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
        n => {
            let areas: Vec<f64> = clipped
                .loops
                .iter()
                .map(|l| outline_area(&clipped.mesh, l, base))
                .collect();
            let main = (0..n)
                .max_by(|&a, &b| areas[a].total_cmp(&areas[b]))
                .unwrap_or(0);
            let stray: f64 = areas.iter().sum::<f64>() - areas[main];
            let kept = (stray <= STRAY_PIECE_SHARE * areas[main])
                .then(|| keep_piece_of(&clipped, main))
                .flatten();
            match kept {
                Some(piece) => {
                    notes.push(format!(
                        "the base plane also cut {} separate fold{} of the {name} dipping below \
                         it ({stray:.1} mm2 at the base, {:.1}% of its outline's area): left out",
                        n - 1,
                        if n > 2 { "s" } else { "" },
                        100.0 * stray / areas[main]
                    ));
                    Ok(piece)
                }
                None => Err(CoreError::Degenerate(format!(
                    "the base plane cuts the {name} in {n} outlines, not one"
                ))),
            }
        }
    }
}

/// Area (mm2) an outline of vertices in the plane encloses, whichever way it runs.
fn outline_area(mesh: &TriMesh, ring: &[u32], base: &Plane) -> f64 {
    let n = ring.len();
    let twice: Vec3 = (0..n).fold(Vec3::zeros(), |acc, k| {
        let (a, b) = (ring[k] as usize, ring[(k + 1) % n] as usize);
        acc + (mesh.positions[a] - base.origin).cross(&(mesh.positions[b] - base.origin))
    });
    0.5 * twice.dot(&base.normal).abs()
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

/// Triangles of the flat ring between the outer outline `loops[0]` and the inner ones (one per
/// cavity, named by `cavities`), vertex indices into `positions`, all in the plane, facing
/// along the plane's normal.
fn ring(
    positions: &[Vec3],
    loops: &[Vec<u32>],
    cavities: &[Cavity],
    base: &Plane,
) -> Result<Vec<[u32; 3]>> {
    let (u, v) = plane_basis(&base.normal);
    let flat = |i: &u32| {
        let d = positions[*i as usize] - base.origin;
        Point2::new(d.dot(&u), d.dot(&v))
    };
    let flat_loops: Vec<Vec<Point2<f64>>> =
        loops.iter().map(|l| l.iter().map(flat).collect()).collect();
    for (k, cavity) in cavities.iter().enumerate() {
        let inner = &flat_loops[k + 1];
        if inner.iter().any(|p| !inside(&flat_loops[0], *p)) {
            return Err(CoreError::Degenerate(format!(
                "the {}'s outline at the base is not inside the epicardium's (the two surfaces \
                 cross there)",
                cavity.name
            )));
        }
        // A cavity inside another would turn the ring's parity inside out.
        for (j, other) in cavities.iter().enumerate().filter(|&(j, _)| j != k) {
            if inner.iter().any(|p| inside(&flat_loops[j + 1], *p)) {
                return Err(CoreError::Degenerate(format!(
                    "the {}'s outline at the base overlaps the {}'s (the two cavities cross \
                     there)",
                    cavity.name, other.name
                )));
            }
        }
    }
    let ids: Vec<u32> = loops.iter().flatten().copied().collect();
    let points: Vec<spade::Point2<f64>> = flat_loops
        .iter()
        .flatten()
        .map(|p| spade::Point2::new(p.x, p.y))
        .collect();
    let mut edges = Vec::with_capacity(points.len());
    let mut start = 0;
    for l in loops {
        let len = l.len();
        for k in 0..len {
            edges.push([start + k, start + (k + 1) % len]);
        }
        start += len;
    }
    let mut conflicts = 0usize;
    let cdt = ConstrainedDelaunayTriangulation::<spade::Point2<f64>>::try_bulk_load_cdt(
        points.clone(),
        edges,
        |_| conflicts += 1,
    )
    .map_err(|e| CoreError::Degenerate(format!("the base ring cannot be triangulated: {e:?}")))?;
    if conflicts > 0 || cdt.num_vertices() != points.len() {
        return Err(CoreError::Degenerate(
            "the surfaces' outlines at the base touch or cross themselves or each other".into(),
        ));
    }
    // Faces between the outer outline and the inner ones are an odd number of constraint edges
    // in from the outside (the holes inside the endocardia, an even number: any walk from the
    // outer face crosses the nested loops with that parity). Counted by walking across edges, which needs no
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

/// Distance from each vertex to the nearest other surface (an epicardial vertex to the
/// endocardia, an endocardial one to the epicardium or the other cavity, across a septum);
/// surface `k`'s vertices start at `starts[k]`.
fn thickness(wall: &TriMesh, starts: &[usize], surfaces: &[&TriMesh]) -> Vec<f64> {
    let bvhs: Vec<Bvh> = surfaces.iter().map(|m| Bvh::build(m)).collect();
    wall.positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let own = starts.iter().rposition(|&s| s <= i).unwrap_or(0);
            surfaces
                .iter()
                .zip(&bvhs)
                .enumerate()
                .filter(|&(k, _)| k != own)
                .filter_map(|(_, (m, bvh))| bvh.closest_point(m, *p))
                .map(|h| h.distance_sq.sqrt())
                .fold(f64::NAN, f64::min)
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

    /// Two spherical cavities side by side in a big sphere, cut 8 mm above their equator: the
    /// solid's volume is the big cap less the two small ones, the septum between the cavities
    /// is the 3 mm gap, and the base ring has two holes.
    #[test]
    fn two_cavities_in_one_epicardium_make_a_biventricular_solid() {
        let epi = uv_sphere(v3(0.0, 0.0, 0.0), 40.0, 160, 80);
        let lv = uv_sphere(v3(-12.0, 0.0, 0.0), 15.0, 96, 48);
        let rv = uv_sphere(v3(18.0, 0.0, 0.0), 12.0, 96, 48);
        // Above the spheres' equator, where the septum is thinnest: 8 mm of it below the base.
        let z = 8.0;
        let wall = build_biventricular(&lv, &rv, &epi, &base_at(z), Some(1.0)).unwrap();
        // A sphere's volume below z: the cap of height r + z.
        let cap = |r: f64| {
            let h = r + z;
            PI * h * h * (3.0 * r - h) / 3.0 / 1000.0
        };
        let expected = cap(40.0) - cap(15.0) - cap(12.0);
        assert!(
            (wall.volume_ml - expected).abs() / expected < 0.01,
            "{} vs {expected}",
            wall.volume_ml
        );
        for (got, r) in wall.cavities_ml.iter().zip([15.0, 12.0]) {
            assert!((got - cap(r)).abs() / cap(r) < 0.01, "{got} vs {}", cap(r));
        }
        assert_eq!(wall.region_names, &BIV_REGION_NAMES);
        let v = validity(&wall.mesh);
        assert!(v.is_closed_manifold(), "{}", v.describe());
        assert_eq!((wall.self_intersections, wall.pushed.vertices), (0, 0));
        assert_eq!(wall.triangles_per_region.len(), 4);
        assert!(wall.triangles_per_region.iter().all(|&n| n > 100));
        // Every vertex's thickness is the distance to the nearest other sphere: across the
        // 3 mm septum, the cavities' free walls, the epicardium to the nearer cavity.
        let (c_lv, c_rv) = (v3(-12.0, 0.0, 0.0), v3(18.0, 0.0, 0.0));
        let mut septal = 0;
        // Well below the base, where no nearest point was cut away with the part above it.
        for (p, t) in wall.mesh.positions.iter().zip(&wall.thickness) {
            if p.z > z - 8.0 {
                continue;
            }
            let to_lv = ((p - c_lv).norm() - 15.0).abs();
            let to_rv = ((p - c_rv).norm() - 12.0).abs();
            let to_epi = 40.0 - p.norm();
            let want = if to_epi < 0.01 {
                to_lv.min(to_rv)
            } else if to_lv < 0.01 {
                to_rv.min(to_epi)
            } else {
                to_lv.min(to_epi)
            };
            assert!((t - want).abs() < 0.05, "{t} vs {want} at {p:?}");
            septal += usize::from((want - 3.0).abs() < 0.3);
        }
        assert!(septal > 10, "{septal}");
        let s = wall.summary(Some(1.0));
        let regions: Vec<&str> = s.regions.iter().map(|r| r.name).collect();
        assert_eq!(regions, BIV_REGION_NAMES);
        assert_eq!(s.cavities.len(), 2);
        assert_eq!(s.cavities[1].region, "rv_endocardium");
        // Base triangles: the big disc less the two small ones.
        let base_area: f64 = (0..wall.mesh.triangles.len())
            .filter(|&t| wall.regions[t] == 3)
            .map(|t| wall.mesh.triangle_area(t))
            .sum();
        let disc = |r: f64| PI * (r * r - z * z);
        let ring = disc(40.0) - disc(15.0) - disc(12.0);
        assert!(
            (base_area - ring).abs() / ring < 0.01,
            "{base_area} vs {ring}"
        );
    }

    /// Cavities that overlap at the base cannot make a solid; ones that overlap only below it
    /// are pushed apart by the minimum thickness (the septum kept).
    #[test]
    fn overlapping_cavities_are_refused_or_pushed_apart() {
        let epi = uv_sphere(v3(0.0, 0.0, 0.0), 40.0, 128, 64);
        let lv = uv_sphere(v3(-10.0, 0.0, 0.0), 15.0, 64, 32);
        let rv = uv_sphere(v3(12.0, 0.0, 0.0), 12.0, 64, 32);
        let e = build_biventricular(&lv, &rv, &epi, &base_at(-1.3), None).unwrap_err();
        assert!(
            e.to_string().contains("overlaps") || e.to_string().contains("cross"),
            "{e}"
        );
        // Centres 26 mm apart, radii 15 + 12: 1 mm into each other at their equator (z = -2),
        // 1.9 mm apart where the base cuts them (z = 4).
        let lv = uv_sphere(v3(-12.0, 0.0, -2.0), 15.0, 96, 48);
        let rv = uv_sphere(v3(14.0, 0.0, -2.0), 12.0, 96, 48);
        let base = base_at(4.0);
        let crossing = build_biventricular(&lv, &rv, &epi, &base, None).unwrap();
        assert!(crossing.self_intersections > 0);
        assert_eq!(
            crossing
                .crossings
                .iter()
                .map(|c| c.regions)
                .collect::<Vec<_>>(),
            [["lv_endocardium", "rv_endocardium"]]
        );
        let wall = build_biventricular(&lv, &rv, &epi, &base, Some(1.0)).unwrap();
        assert!(wall.pushed.vertices > 10, "{:?}", wall.pushed);
        assert_eq!(wall.self_intersections, 0, "{:?}", wall.crossings);
        let v = validity(&wall.mesh);
        assert!(v.is_closed_manifold(), "{}", v.describe());
    }

    /// Two closed meshes as one (a cavity with a separate blob: a fold of the surface that dips
    /// below the base on its own).
    fn with_blob(main: &TriMesh, blob: &TriMesh) -> TriMesh {
        let n = main.positions.len() as u32;
        let mut positions = main.positions.clone();
        positions.extend_from_slice(&blob.positions);
        let mut triangles = main.triangles.clone();
        triangles.extend(blob.triangles.iter().map(|t| t.map(|v| v + n)));
        TriMesh::new(positions, triangles)
    }

    /// A small blob of the endocardium dipping 0.5 mm below the base on its own (its section
    /// 2 % of the cavity's) is left out, and the note says so; the wall is the one without it.
    #[test]
    fn a_small_separate_fold_below_the_base_is_left_out() {
        let z = -1.3;
        let epi = uv_sphere(v3(0.0, 0.0, 0.0), 40.0, 128, 64);
        let cavity = uv_sphere(v3(-12.0, 0.0, 0.0), 12.0, 96, 48);
        let endo = with_blob(&cavity, &uv_sphere(v3(14.0, 0.0, z + 2.5), 3.0, 48, 24));
        let wall = build_wall(&endo, &epi, &base_at(z), Some(1.0)).unwrap();
        let plain = build_wall(&cavity, &epi, &base_at(z), Some(1.0)).unwrap();
        assert_eq!(wall.notes.len(), 1, "{:?}", wall.notes);
        assert!(
            wall.notes[0].contains("1 separate fold of the endocardium"),
            "{}",
            wall.notes[0]
        );
        assert!((wall.volume_ml - plain.volume_ml).abs() < 1e-9);
        assert_eq!(wall.base.origin.z, z);
        let v = validity(&wall.mesh);
        assert!(v.is_closed_manifold(), "{}", v.describe());
    }

    /// A larger blob dipping 0.5 mm below the base (its section 7 % of the cavity's, too much to
    /// drop): the base moves 1 mm towards the apex, where only the cavity is cut, and the note
    /// says why.
    #[test]
    fn the_base_moves_towards_the_apex_when_the_plane_cannot_join_the_surfaces() {
        let z = -1.3;
        let epi = uv_sphere(v3(0.0, 0.0, 0.0), 40.0, 128, 64);
        let cavity = uv_sphere(v3(-12.0, 0.0, 0.0), 12.0, 96, 48);
        let endo = with_blob(&cavity, &uv_sphere(v3(12.0, 0.0, z + 9.5), 10.0, 96, 48));
        let wall = build_wall(&endo, &epi, &base_at(z), Some(1.0)).unwrap();
        assert!(
            (wall.base.origin.z - (z - 1.0)).abs() < 1e-12,
            "{:?}",
            wall.base
        );
        assert_eq!(wall.notes.len(), 1, "{:?}", wall.notes);
        assert!(
            wall.notes[0].starts_with(
                "the base was moved 1 mm towards the apex: at the plane given, the base plane \
                 cuts the endocardium in 2 outlines"
            ),
            "{}",
            wall.notes[0]
        );
        let plain = build_wall(&cavity, &epi, &base_at(z - 1.0), Some(1.0)).unwrap();
        assert!((wall.volume_ml - plain.volume_ml).abs() < 1e-9);
        assert_eq!(wall.summary(Some(1.0)).notes, wall.notes);
        // Without a way out within 4 mm, the first error.
        let deep = with_blob(&cavity, &uv_sphere(v3(12.0, 0.0, z), 10.0, 96, 48));
        let e = build_wall(&deep, &epi, &base_at(z), Some(1.0)).unwrap_err();
        assert!(e.to_string().contains("2 outlines"), "{e}");
    }
}
