//! The anatomical layout: one LV surface resampled onto a fixed grid of vertices placed by the
//! heart's own landmarks, so that every heart (every patient, every phase) gives a mesh with the
//! same vertices in the same order and the same triangles. Shape analysis needs exactly that
//! (point correspondence: a mean shape, principal modes, per-vertex motion from ED to ES), and
//! the reconstruction cannot give it: its remeshing leaves every heart its own triangles.
//!
//! The grid is the one cardiologists already read the LV by (the AHA segments, [`super::segments`]):
//! around the long axis from the septum, in levels from the apex to the base.
//! - Angles: vertex j of every ring lies at 360 j / points degrees from the septum's middle,
//!   positive towards the anterior wall (the direction [`super::segments`] calls anterior), so
//!   j = 0 is mid-septal on every ring of every heart.
//! - The apical cap (the apical third of the length above the surface's lowest point, a third of
//!   the rings): rays from the centre of the section the cap stands on, in the meridian plane at
//!   each angle, tilted from straight down (vertex 0, the apex) to level (the cap's top ring)
//!   in equal steps. Rays, not sections, because a section near a flat apex says little about
//!   where its bottom is: on a nearly flat apex the lowest vertex wanders across it with the
//!   slightest change of the surface.
//! - The wall above it: the other rings at equal height steps up to the base plane (the most
//!   basal short-axis slice), each vertex where a level ray from its section's centre leaves it.
//! - The last vertex is the base plane's centre, joined to the top ring by a flat lid (region
//!   `base`; the rest is `wall`), so the mesh is closed and has a volume; shape-analysis tools
//!   that want the open surface drop the `base` triangles.
//!
//! A ray leaving a dented section more than once takes its outermost crossing, the same choice on
//! every heart.
//!
//! Every grid vertex lies on the reconstructed surface (on a section of it: a ring's plane or a
//! meridian plane),
//! so the layout moves no point of it; its triangles chord the surface between them, by what
//! `to_surface` reports. The septum comes from the file (RV insertion landmarks or RV contours,
//! [`super::septum`]): an LV-only file cannot say where it is, and a layout started anywhere
//! else would not correspond between hearts. The RV's crescent sections have no centre a ray
//! could leave from once, so the layout is the LV's alone.

use super::compare::{compare, ClipPlane};
use super::segments::Orientation;
use super::septum;
use crate::contours::{ContourSet, Polyline};
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::TriMesh;
use crate::sim::slice::{signed_area, slice_mesh, Plane};
use serde::Serialize;

/// Region names of the layout's triangles, as the mesh writers label them (`region` 1 and 2).
pub const REGION_NAMES: [&str; 2] = ["wall", "base"];
/// Index of the `wall` region in [`REGION_NAMES`].
pub const WALL: u32 = 0;
/// Index of the `base` region in [`REGION_NAMES`].
pub const BASE: u32 = 1;

/// How many rings and how many vertices per ring.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Layout {
    pub rings: usize,
    pub points: usize,
}

impl Layout {
    /// 24 x 48: rings 2-6 mm apart along a meridian and vertices 2-4 mm apart around an adult
    /// LV, about the reconstruction's own spacing (1154 vertices).
    pub const DEFAULT: Layout = Layout {
        rings: 24,
        points: 48,
    };
    /// Allowed rings (inclusive).
    pub const RINGS: (usize, usize) = (2, 200);
    /// Allowed vertices per ring (inclusive).
    pub const POINTS: (usize, usize) = (8, 720);

    /// A layout checked against [`Layout::RINGS`] and [`Layout::POINTS`].
    pub fn new(rings: usize, points: usize) -> std::result::Result<Layout, String> {
        let within = |v: usize, (lo, hi): (usize, usize)| (lo..=hi).contains(&v);
        if !within(rings, Self::RINGS) || !within(points, Self::POINTS) {
            return Err(format!(
                "the anatomical layout must have {}-{} rings of {}-{} points (got {rings}x{points})",
                Self::RINGS.0,
                Self::RINGS.1,
                Self::POINTS.0,
                Self::POINTS.1
            ));
        }
        Ok(Layout { rings, points })
    }

    /// `RINGSxPOINTS`, e.g. `24x48` (the command line's `--anatomical-layout`).
    pub fn parse(text: &str) -> std::result::Result<Layout, String> {
        let bad = || format!("expected RINGSxPOINTS such as 24x48, got {text:?}");
        let (r, p) = text.trim().split_once(['x', 'X']).ok_or_else(bad)?;
        let rings = r.trim().parse::<usize>().map_err(|_| bad())?;
        let points = p.trim().parse::<usize>().map_err(|_| bad())?;
        Layout::new(rings, points)
    }

    /// Vertex count: the apex, the rings, the base centre.
    pub fn vertices(&self) -> usize {
        self.rings * self.points + 2
    }

    /// Index of ring `ring` (1-based, apex to base), vertex `j` (0 = mid-septal).
    pub fn index(&self, ring: usize, j: usize) -> usize {
        1 + (ring - 1) * self.points + j % self.points
    }
}

impl Default for Layout {
    fn default() -> Self {
        Layout::DEFAULT
    }
}

/// What a report says of a layout built.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    pub rings: usize,
    pub points: usize,
    pub vertices: usize,
    pub triangles: usize,
    /// Where the septum's direction came from, e.g. "RV_INSERT landmarks (10)".
    pub septum_from: String,
    /// Unit vectors (file coordinates): ring vertex 0's direction, a quarter turn on (vertex
    /// points/4), and the long axis from the apex to the base.
    pub septum_direction: [f64; 3],
    pub anterior_direction: [f64; 3],
    pub axis: [f64; 3],
    /// Vertex 0 (mm).
    pub apex: [f64; 3],
    /// From the apex to the base plane along the axis (mm).
    pub length_mm: f64,
    /// The closed layout's volume and the surface's below the base plane (ml): they differ by
    /// what the chords cut off.
    pub volume_ml: f64,
    pub surface_volume_ml: f64,
    /// Distances between the layout's wall and the surface below the base plane (mm,
    /// area-weighted mean both ways, and the largest either way).
    pub to_surface_mean_mm: f64,
    pub to_surface_max_mm: f64,
}

/// The apical cap's share of the length (from the lowest point), its rings' share of the rings:
/// the apical third, as the AHA segments' apical level.
const CAP_HEIGHT: f64 = 1.0 / 3.0;

/// How many of `rings` make the apical cap: a third, at least one, and one ring at least left
/// for the wall above it.
fn cap_rings(rings: usize) -> usize {
    ((rings as f64 / 3.0).round() as usize).clamp(1, rings - 1)
}

/// A built layout: the mesh, one region per triangle ([`REGION_NAMES`]) and its summary.
#[derive(Debug, Clone)]
pub struct Anatomical {
    pub mesh: TriMesh,
    pub regions: Vec<u32>,
    pub summary: Summary,
    /// Per vertex, the unit direction of the ray it was found along (the apex's straight down,
    /// the lid's centre zero): two layouts of one frame ([`build_pair`]) share them, and the
    /// wall between them is measured along them.
    pub rays: Vec<Vec3>,
}

/// Why a surface of `set` can have no layout (checked before any run): an RV or biventricular
/// surface, or a file that does not say where the septum is.
pub fn refusal(set: &ContourSet, surface: Option<&str>) -> Option<String> {
    let named = surface.map(str::to_string).or_else(|| {
        let all = set.surfaces();
        (all.len() == 1).then(|| all[0].clone())
    });
    if let Some(why) = named.as_deref().and_then(surface_refusal) {
        return Some(why);
    }
    (!septum::said(set)).then(|| {
        "the anatomical layout starts at the septum, and the file has no RV_INSERT landmarks \
         and no RV contours to place it by"
            .to_string()
    })
}

/// Why a surface named `surface` can have no layout whatever its file says: an RV or
/// biventricular surface (the crescent has no centre a ray leaves once).
pub fn surface_refusal(surface: &str) -> Option<String> {
    let s = surface.to_ascii_uppercase();
    (s.starts_with("RV") || s.starts_with("BIV")).then(|| {
        format!(
            "the anatomical layout is the LV's (LV_ENDO, LV_EPI); {s} has no centre for its rays"
        )
    })
}

/// The layout of `surface` (a closed LV surface reconstructed from `set`), up to `base` (its
/// most basal short-axis plane, normal pointing from the apex to the base), placed by what `set`
/// says of the septum; else a sentence saying why there is none.
pub fn of_file(
    set: &ContourSet,
    surface_name: Option<&str>,
    surface: &TriMesh,
    base: &ClipPlane,
    layout: Layout,
) -> std::result::Result<Anatomical, String> {
    if let Some(why) = refusal(set, surface_name) {
        return Err(why);
    }
    let orientation = orientation_of(set, surface, base)?;
    build(surface, base, &orientation, layout).map_err(|e| reason(&e))
}

/// A build's failure as the sentence a report's note gives (a layout's own refusals carry no
/// "degenerate input: ").
pub fn reason(e: &CoreError) -> String {
    match e {
        CoreError::Degenerate(why) => why.clone(),
        e => e.to_string(),
    }
}

/// The septum's direction for layouts of `surface` (a closed LV surface of `set`) up to `base`,
/// seen from the surface's centre below the base: one orientation for the layouts of two
/// surfaces that must correspond (a wall's endo- and epicardium, [`crate::mesh::hex_wall`]).
pub fn orientation_of(
    set: &ContourSet,
    surface: &TriMesh,
    base: &ClipPlane,
) -> std::result::Result<Orientation, String> {
    let centre = centre_below(surface, base)
        .ok_or_else(|| "the surface has no part below its base plane".to_string())?;
    septum::orientation_around(set, &centre, &base.normal).ok_or_else(|| {
        "the file's RV landmarks and contours give no direction across the long axis".to_string()
    })
}

/// The layout's file header: what every vertex is, for whoever opens the file without this
/// documentation (the command line's and the app's files say the same).
pub fn header_comment(summary: &Summary, surface: &str, file_name: &str) -> String {
    let name = file_name.rsplit(['/', '\\']).next().unwrap_or(file_name);
    let (r, k) = (summary.rings, summary.points);
    format!(
        "anatomical layout {r}x{k} of {surface} reconstructed from {name}; units mm, the contour \
         file's coordinates; vertex 0 the apex, then {r} rings of {k} from the apex to the base \
         plane, vertex j of a ring at 360*j/{k} degrees from the septum towards anterior, last \
         the base lid's centre; region 1 wall, 2 base"
    )
}

/// The area-weighted centre of the triangles of `mesh` below `base`.
fn centre_below(mesh: &TriMesh, base: &Plane) -> Option<Vec3> {
    let (mut sum, mut area) = (Vec3::zeros(), 0.0);
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let centroid = (a + b + c) / 3.0;
        if base.signed_distance(&centroid) < 0.0 {
            let w = (b - a).cross(&(c - a)).norm();
            sum += centroid * w;
            area += w;
        }
    }
    (area > 0.0).then(|| sum / area)
}

/// The layout of `surface` below `base`, vertex 0 of every ring towards `orientation.septum`.
pub fn build(
    surface: &TriMesh,
    base: &ClipPlane,
    orientation: &Orientation,
    layout: Layout,
) -> Result<Anatomical> {
    let frame = Frame::of(surface, base, layout)?;
    build_in(surface, base, orientation, layout, &frame)
}

/// The layouts of a wall's two surfaces, both laid out from the inner one's frame (its length,
/// its cap's centre and its rings' section centres): vertex k of the outer surface then lies on
/// the same ray as vertex k of the inner one, at the same height on the rings, so the line
/// between them crosses the wall instead of running along it. Each surface laid out on its own
/// frame would put the epicardium's rings lower (its apex is lower) and slant those lines by up
/// to 45 degrees, and a groove of the epicardium then folds the cells between them.
pub fn build_pair(
    inner: &TriMesh,
    outer: &TriMesh,
    base: &ClipPlane,
    orientation: &Orientation,
    layout: Layout,
) -> Result<(Anatomical, Anatomical)> {
    let frame = Frame::of(inner, base, layout)?;
    Ok((
        build_in(inner, base, orientation, layout, &frame)?,
        build_in(outer, base, orientation, layout, &frame)?,
    ))
}

/// Where a layout's rays start and at which heights: the length from the base plane to the
/// reference surface's lowest point (only its depth: where on a flat apex it lies is left to the
/// rays), the centre of the section the apical cap stands on, and each wall ring's depth and
/// section centre.
struct Frame {
    cap_centre: Vec3,
    rings: Vec<(f64, Vec3)>,
}

impl Frame {
    fn of(surface: &TriMesh, base: &ClipPlane, layout: Layout) -> Result<Frame> {
        Layout::new(layout.rings, layout.points).map_err(|message| CoreError::ParamInvalid {
            name: "layout".into(),
            message,
        })?;
        let n = normal_of(base)?;
        let length = surface
            .positions
            .iter()
            .filter(|p| p.iter().all(|x| x.is_finite()))
            .map(|p| -base.signed_distance(p))
            .fold(f64::NEG_INFINITY, f64::max);
        if length.is_nan() || length <= 0.0 {
            return Err(CoreError::Degenerate(
                "the surface has no part below its base plane".into(),
            ));
        }
        let centre_at = |below_base: f64| -> Result<Vec3> {
            let (loop_, _) = ring_section(surface, base, &n, below_base)?;
            Ok(polygon_centre(&loop_.points, &n))
        };
        let cap_centre = centre_at(length * (1.0 - CAP_HEIGHT))?;
        let wall_rings = layout.rings - cap_rings(layout.rings);
        let rings = (1..=wall_rings)
            .map(|k| {
                let below_base = length * (1.0 - CAP_HEIGHT) * (1.0 - k as f64 / wall_rings as f64);
                centre_at(below_base).map(|c| (below_base, c))
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Frame { cap_centre, rings })
    }
}

/// The base plane's unit normal (the long axis, towards the base).
fn normal_of(base: &ClipPlane) -> Result<Vec3> {
    base.normal
        .try_normalize(1e-12)
        .ok_or_else(|| CoreError::Degenerate("the base plane has no normal".into()))
}

/// The section of `surface` `below_base` mm below the base plane (its largest closed loop).
fn ring_section(
    surface: &TriMesh,
    base: &ClipPlane,
    n: &Vec3,
    below_base: f64,
) -> Result<(Polyline, Plane)> {
    let plane = Plane::new(base.origin - n * below_base, *n)
        .ok_or_else(|| CoreError::Degenerate("a ring's plane is not finite".into()))?;
    let loop_ = section(surface, &plane).ok_or_else(|| {
        CoreError::Degenerate(format!(
            "the surface has no closed section {below_base:.1} mm below its base plane"
        ))
    })?;
    Ok((loop_, plane))
}

/// `surface` sampled on `frame`'s rays.
fn build_in(
    surface: &TriMesh,
    base: &ClipPlane,
    orientation: &Orientation,
    layout: Layout,
    frame: &Frame,
) -> Result<Anatomical> {
    let degenerate = |why: String| CoreError::Degenerate(why);
    let n = normal_of(base)?;
    let septum = (orientation.septum - n * orientation.septum.dot(&n))
        .try_normalize(1e-9)
        .ok_or_else(|| degenerate("the septum's direction lies along the long axis".into()))?;
    let anterior = n.cross(&septum);
    let around = |j: usize| {
        let angle = std::f64::consts::TAU * j as f64 / layout.points as f64;
        septum * angle.cos() + anterior * angle.sin()
    };
    let not_star = |what: &str| {
        degenerate(format!(
            "a ray from {what} leaves no edge of the surface's section (not star-shaped around it)"
        ))
    };
    let cap_rings = cap_rings(layout.rings);
    let cap_centre = frame.cap_centre;
    let mut positions = vec![Vec3::zeros(); layout.vertices()];
    let mut rays = vec![Vec3::zeros(); layout.vertices()];
    rays[0] = -n;
    let mut apex = None;
    for j in 0..layout.points {
        let out = around(j);
        // The meridian plane through the cap's centre at angle j: the ventricle's long-axis
        // profile there.
        let plane = Plane::new(cap_centre, n.cross(&out))
            .ok_or_else(|| degenerate("a meridian plane is not finite".into()))?;
        // An open surface (reconstructed without lids, or a truth mesh open at its base) gives
        // an open profile: its piece through the apex serves as well.
        let profile = profile(surface, &plane);
        let hit = |polar: f64| {
            let d = out * polar.sin() - n * polar.cos();
            farthest_hit_of(&profile, &cap_centre, &d, &plane.normal)
                .ok_or_else(|| not_star("the apical cap's centre"))
        };
        if j == 0 {
            // Straight down from inside the cavity and nothing there: no apex to start from.
            let down = farthest_hit_of(&profile, &cap_centre, &-n, &plane.normal);
            apex = Some(down.ok_or_else(|| {
                degenerate(
                    "the surface is open below its apical third (no apex: a surface \
                     reconstructed with --lids none may stop short of it)"
                        .into(),
                )
            })?);
        }
        for ring in 1..=cap_rings {
            let polar = std::f64::consts::FRAC_PI_2 * ring as f64 / cap_rings as f64;
            positions[layout.index(ring, j)] = hit(polar)?;
            rays[layout.index(ring, j)] = out * polar.sin() - n * polar.cos();
        }
    }
    let apex = apex.ok_or_else(|| degenerate("the layout has no points per ring".into()))?;
    positions[0] = apex;
    let mut top = cap_centre;
    for (k, &(below_base, centre)) in frame.rings.iter().enumerate() {
        let (loop_, _) = ring_section(surface, base, &n, below_base)?;
        let ring = ring_points(&loop_, &centre, &septum, &n, layout.points)
            .ok_or_else(|| not_star("a section's centre"))?;
        for (j, p) in ring.into_iter().enumerate() {
            let v = layout.index(cap_rings + k + 1, j);
            positions[v] = p;
            rays[v] = around(j);
        }
        // The base ring's centre (this surface's own) closes the lid.
        top = polygon_centre(&loop_.points, &n);
    }
    let last = positions.len() - 1;
    positions[last] = top;
    let (triangles, regions) = grid_triangles(layout);
    let mut mesh = TriMesh {
        positions,
        triangles,
    };
    if mesh.signed_volume() < 0.0 {
        // Never for a section oriented as slice_mesh orients it; kept outward regardless.
        for t in &mut mesh.triangles {
            t.swap(1, 2);
        }
    }
    let summary = summarise(surface, base, &mesh, &regions, layout, orientation, apex, n)?;
    Ok(Anatomical {
        mesh,
        regions,
        summary,
        rays,
    })
}

/// The closed loop of `surface` in `plane` with the largest area (the ventricle's own section,
/// not a speck the plane grazes).
fn section(surface: &TriMesh, plane: &Plane) -> Option<Polyline> {
    slice_mesh(surface, plane)
        .into_iter()
        .filter(|p| p.closed && p.points.len() >= 3)
        .max_by(|a, b| {
            signed_area(&a.points, &plane.normal)
                .abs()
                .total_cmp(&signed_area(&b.points, &plane.normal).abs())
        })
}

/// The long-axis profile of `surface` in a meridian `plane`: every piece of the section (one
/// loop for a closed ventricle; an open surface, reconstructed without lids or a truth open at
/// its base, gives open pieces, one on each side of the axis where it is open at both ends).
fn profile(surface: &TriMesh, plane: &Plane) -> Vec<Polyline> {
    slice_mesh(surface, plane)
        .into_iter()
        .filter(|p| p.points.len() >= 2)
        .collect()
}

/// `count` points round a closed section (normal `n`), point j where the section first reaches
/// the angle 360 j / count degrees from `septum` round `centre` (counter-clockwise about `n`),
/// walking the loop onwards from where the septum's ray leaves it last.
///
/// On a section that is star-shaped around its centre this is the ray's one crossing. Where a
/// section dents inwards (the epicardium at the interventricular grooves, a bumpy surface), a
/// ray can cross it three times and the outermost crossing of neighbouring rays can lie on
/// different sides of the dent: the grid then folds over itself (inverted cells in the
/// hexahedra made of it). Walking the loop keeps the points in the loop's own order, so a ring
/// never folds; the dent is bridged from the first point that reaches past it.
fn ring_points(
    section: &Polyline,
    centre: &Vec3,
    septum: &Vec3,
    n: &Vec3,
    count: usize,
) -> Option<Vec<Vec3>> {
    let mut pts = section.points.clone();
    if signed_area(&pts, n) < 0.0 {
        pts.reverse();
    }
    let start_point = farthest_hit(section, centre, septum, n)?;
    // The edge the septum's ray leaves through: the walk starts on it.
    let anterior = n.cross(septum);
    let angle_of = |p: &Vec3| {
        let d = p - centre;
        d.dot(&anterior).atan2(d.dot(septum))
    };
    let m = pts.len();
    let start = (0..m).min_by(|&a, &b| {
        let on = |k: usize| {
            let (p, q) = (pts[k], pts[(k + 1) % m]);
            crate::spatial::triangle::closest_point_on_segment(&start_point, &p, &q)
                .metric_distance(&start_point)
        };
        on(a).total_cmp(&on(b))
    })?;
    // The loop from the start point round to it again, with each vertex's unwrapped angle from
    // the septum (0 at the start, about 2 pi back at it).
    let mut walk: Vec<(Vec3, f64)> = vec![(start_point, 0.0)];
    let mut previous = 0.0;
    for step in 1..=m {
        let p = pts[(start + step) % m];
        let raw = angle_of(&p);
        let mut a = raw;
        while a - previous > std::f64::consts::PI {
            a -= std::f64::consts::TAU;
        }
        while a - previous < -std::f64::consts::PI {
            a += std::f64::consts::TAU;
        }
        walk.push((p, a));
        previous = a;
    }
    walk.push((start_point, std::f64::consts::TAU));
    let mut out = Vec::with_capacity(count);
    out.push(start_point);
    let mut reached = 0.0;
    let mut k = 0;
    for j in 1..count {
        let target = std::f64::consts::TAU * j as f64 / count as f64;
        // The first edge of the walk whose far end reaches the target angle beyond any
        // angle reached before it.
        while k + 1 < walk.len() && walk[k + 1].1.max(reached) < target {
            reached = reached.max(walk[k + 1].1);
            k += 1;
        }
        let (p, _) = walk[k];
        let (q, _) = *walk.get(k + 1)?;
        // Where the ray at the target angle crosses that edge (the edge's end when the ray
        // passes it by a rounding).
        let d = septum * target.cos() + anterior * target.sin();
        let edge = q - p;
        let denom = d.cross(&edge).dot(n);
        let t = if denom.abs() > 1e-15 {
            ((p - centre).cross(&d).dot(n) / denom).clamp(0.0, 1.0)
        } else {
            1.0
        };
        out.push(p + edge * t);
    }
    Some(out)
}

/// [`farthest_hit`] over several pieces of one section: the outermost crossing of any.
fn farthest_hit_of(pieces: &[Polyline], centre: &Vec3, direction: &Vec3, n: &Vec3) -> Option<Vec3> {
    pieces
        .iter()
        .filter_map(|p| farthest_hit(p, centre, direction, n))
        .max_by(|a, b| {
            (a - centre)
                .dot(direction)
                .total_cmp(&(b - centre).dot(direction))
        })
}

/// The area centroid of a planar polygon (normal `n`); its vertex mean when its area vanishes.
fn polygon_centre(points: &[Vec3], n: &Vec3) -> Vec3 {
    let origin = points[0];
    let (mut sum, mut area) = (Vec3::zeros(), 0.0);
    for w in points[1..].windows(2) {
        let a = (w[0] - origin).cross(&(w[1] - origin)).dot(n);
        sum += (origin + w[0] + w[1]) * (a / 3.0);
        area += a;
    }
    if area.abs() > 1e-12 {
        sum / area
    } else {
        points.iter().sum::<Vec3>() / points.len() as f64
    }
}

/// Where the ray from `centre` along `direction` (both in the section's plane, normal `n`)
/// crosses the section last: the outermost crossing, the same choice on every heart even where
/// a section dents inwards. A point of the section's own edge, so on the surface.
fn farthest_hit(section: &Polyline, centre: &Vec3, direction: &Vec3, n: &Vec3) -> Option<Vec3> {
    // 2D cross product in the plane: (a x b) . n.
    let cross = |a: &Vec3, b: &Vec3| a.cross(b).dot(n);
    let points = &section.points;
    let edges = if section.closed {
        points.len()
    } else {
        points.len().saturating_sub(1)
    };
    let mut best: Option<(f64, Vec3)> = None;
    for k in 0..edges {
        let a = points[k];
        let b = points[(k + 1) % points.len()];
        let edge = b - a;
        let denom = cross(direction, &edge);
        if denom.abs() < 1e-15 {
            continue;
        }
        let to_a = a - centre;
        let t = cross(&to_a, &edge) / denom;
        let s = cross(&to_a, direction) / denom;
        if t > 0.0 && (0.0..=1.0).contains(&s) && best.is_none_or(|(bt, _)| t > bt) {
            best = Some((t, a + edge * s));
        }
    }
    best.map(|(_, p)| p)
}

/// The grid's triangles (outward for rings counter-clockwise about the axis seen from the base)
/// and their regions: the apex fan, two per grid quad, the base lid fan.
fn grid_triangles(layout: Layout) -> (Vec<[u32; 3]>, Vec<u32>) {
    let k = layout.points;
    let v = |ring: usize, j: usize| layout.index(ring, j) as u32;
    let mut triangles = Vec::with_capacity(2 * layout.rings * k);
    let mut regions = Vec::with_capacity(2 * layout.rings * k);
    for j in 0..k {
        triangles.push([0, v(1, j + 1), v(1, j)]);
        regions.push(WALL);
    }
    for ring in 1..layout.rings {
        for j in 0..k {
            triangles.push([v(ring, j), v(ring, j + 1), v(ring + 1, j)]);
            triangles.push([v(ring, j + 1), v(ring + 1, j + 1), v(ring + 1, j)]);
            regions.extend([WALL, WALL]);
        }
    }
    let lid = (layout.vertices() - 1) as u32;
    for j in 0..k {
        triangles.push([lid, v(layout.rings, j), v(layout.rings, j + 1)]);
        regions.push(BASE);
    }
    (triangles, regions)
}

#[allow(clippy::too_many_arguments)]
fn summarise(
    surface: &TriMesh,
    base: &ClipPlane,
    mesh: &TriMesh,
    regions: &[u32],
    layout: Layout,
    orientation: &Orientation,
    apex: Vec3,
    n: Vec3,
) -> Result<Summary> {
    // Without the lid's centre (the last vertex): a point of no wall triangle would count as
    // a wall point a radius from the surface.
    let wall = TriMesh {
        positions: mesh.positions[..mesh.positions.len() - 1].to_vec(),
        triangles: mesh
            .triangles
            .iter()
            .zip(regions)
            .filter(|(_, &r)| r == WALL)
            .map(|(t, _)| *t)
            .collect(),
    };
    let c = compare(surface, &wall, Some(base))?;
    let v = |x: Vec3| [x.x, x.y, x.z];
    let septum = (orientation.septum - n * orientation.septum.dot(&n)).normalize();
    Ok(Summary {
        rings: layout.rings,
        points: layout.points,
        vertices: mesh.positions.len(),
        triangles: mesh.triangles.len(),
        septum_from: format!("{} ({})", orientation.source, orientation.points),
        septum_direction: v(septum),
        anterior_direction: v(n.cross(&septum)),
        axis: v(n),
        apex: v(apex),
        length_mm: -base.signed_distance(&apex),
        volume_ml: mesh.volume_ml(),
        surface_volume_ml: c.volume_truth_ml,
        to_surface_mean_mm: 0.5 * (c.mesh_to_truth.mean + c.truth_to_mesh.mean),
        to_surface_max_mm: c.hausdorff,
    })
}

#[cfg(test)]
mod tests;
