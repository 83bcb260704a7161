//! Wall thickness by the American Heart Association's 17 segments (Cerqueira et al., Circulation
//! 2002), the regional figure cardiologists read a myocardium by: six basal, six mid and four
//! apical segments around the long axis, and the apical cap.
//!
//! The levels are thirds of the cavity's length along the long axis, from the wall's base plane
//! (the most basal short-axis slice both surfaces were drawn on) down to the endocardium's
//! lowest point; the apical cap (segment 17) is the muscle beyond that point. Around the axis,
//! the segments are placed from the septum's direction ([`super::septum`]): the middle of the
//! septum is the border of segments 2 and 3 (8 and 9), so the RV insertion points fall near the
//! 1|2 and 3|4 borders as the standard draws them, and segment 14 (apical septal) is centred on it.
//! Anterior lies a quarter turn from the septum in the sense a right-handed patient frame (DICOM
//! LPS, or RAS) gives when the axis points from the apex to the base.
//!
//! Each segment's thickness is area-weighted over the wall's epicardial and endocardial surfaces
//! (the base ring's triangles carry no thickness of their own): a vertex counts with a third of
//! the area of its wall triangles, so a finely meshed patch does not outweigh a coarse one.

use crate::contours::ContourSet;
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::wall::{Wall, ENDOCARDIUM, EPICARDIUM, REGION_NAMES};
use serde::Serialize;

/// Segment names in the order of their numbers (1-17).
pub const NAMES: [&str; 17] = [
    "basal anterior",
    "basal anteroseptal",
    "basal inferoseptal",
    "basal inferior",
    "basal inferolateral",
    "basal anterolateral",
    "mid anterior",
    "mid anteroseptal",
    "mid inferoseptal",
    "mid inferior",
    "mid inferolateral",
    "mid anterolateral",
    "apical anterior",
    "apical septal",
    "apical inferior",
    "apical lateral",
    "apex",
];

/// Where the septum is, and what the wall's segments are placed by.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orientation {
    /// Unit direction from the long axis to the middle of the septum, across the axis.
    pub septum: Vec3,
    /// What the direction was found from, in words for a report ("RV_INSERT landmarks (10)").
    pub source: &'static str,
    /// How many points it was found from.
    pub points: usize,
}

/// One segment's figures.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Segment {
    /// 1 to 17.
    pub id: usize,
    pub name: &'static str,
    /// Area-weighted mean wall thickness (mm); null where no wall surface falls in the segment.
    pub mean_mm: Option<f64>,
    pub min_mm: Option<f64>,
    pub max_mm: Option<f64>,
    /// Wall surface (epicardium and endocardium together) in the segment, mm^2.
    pub area_mm2: f64,
}

/// The 17 segments of a wall and the frame they were drawn in.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Segments {
    /// What the septum's direction came from.
    pub septum_from: String,
    /// Unit directions across the long axis (file coordinates): to the middle of the septum,
    /// and to the middle of the anterior wall.
    pub septum_direction: [f64; 3],
    pub anterior_direction: [f64; 3],
    /// Unit long axis, from the apex to the base.
    pub axis: [f64; 3],
    /// Heights along the axis of the level borders, measured down from the base plane (mm):
    /// base, basal|mid, mid|apical, apical|apex (the endocardium's lowest point), and the
    /// epicardium's lowest point.
    pub level_depths_mm: [f64; 5],
    pub segments: Vec<Segment>,
}

/// Which of the 17 segments a point at `depth` below the base (mm) and `angle` (degrees, from
/// the septum, positive towards the anterior wall) falls in: 0-based.
pub fn segment_of(depth: f64, cavity_depth: f64, angle: f64) -> usize {
    let third = cavity_depth / 3.0;
    let turn = |start: f64, width: f64| ((start - angle).rem_euclid(360.0) / width) as usize;
    if depth > cavity_depth {
        16
    } else if depth > 2.0 * third {
        // Anterior is centred a quarter turn from the septum: 12 + 4 quarters.
        12 + turn(135.0, 90.0).min(3)
    } else if depth > third {
        6 + turn(120.0, 60.0).min(5)
    } else {
        turn(120.0, 60.0).min(5)
    }
}

/// The wall's thickness by segment. Only an LV wall ([`crate::mesh::wall::build_wall`]) has
/// these segments; a biventricular one is refused.
pub fn segments(wall: &Wall, orientation: &Orientation) -> Result<Segments> {
    if wall.region_names != REGION_NAMES.as_slice() {
        return Err(CoreError::Degenerate(
            "the 17 segments are the LV wall's (a biventricular wall has none)".into(),
        ));
    }
    let n = wall.base.normal.normalize();
    let Some(septum) = (orientation.septum - n * orientation.septum.dot(&n)).try_normalize(1e-9)
    else {
        return Err(CoreError::Degenerate(
            "the septum's direction lies along the long axis".into(),
        ));
    };
    let anterior = n.cross(&septum);
    let Some(cavity) = Cavity::of(wall) else {
        return Err(CoreError::Degenerate(
            "the wall has no endocardium below its base".into(),
        ));
    };
    let Cavity {
        weights,
        centre,
        depth: cavity_depth,
        wall_depth,
    } = cavity;
    let depth_of = |p: &Vec3| (wall.base.origin - p).dot(&n);
    let mut sums = [(0.0f64, 0.0f64, f64::INFINITY, f64::NEG_INFINITY); 17];
    for (i, p) in wall.mesh.positions.iter().enumerate() {
        let area = weights[i][0] + weights[i][1];
        let t = wall.thickness.get(i).copied().unwrap_or(f64::NAN);
        if !(area > 0.0 && t.is_finite()) {
            continue;
        }
        let across = (p - centre) - n * (p - centre).dot(&n);
        let angle = across
            .dot(&anterior)
            .atan2(across.dot(&septum))
            .to_degrees();
        let s = &mut sums[segment_of(depth_of(p), cavity_depth, angle)];
        s.0 += area;
        s.1 += area * t;
        s.2 = s.2.min(t);
        s.3 = s.3.max(t);
    }
    let v = |x: Vec3| [x.x, x.y, x.z];
    Ok(Segments {
        septum_from: format!("{} ({})", orientation.source, orientation.points),
        septum_direction: v(septum),
        anterior_direction: v(anterior),
        axis: v(n),
        level_depths_mm: [
            0.0,
            cavity_depth / 3.0,
            2.0 * cavity_depth / 3.0,
            cavity_depth,
            wall_depth.max(cavity_depth),
        ],
        segments: sums
            .iter()
            .enumerate()
            .map(|(k, &(area, weighted, lo, hi))| {
                let some = area > 0.0;
                Segment {
                    id: k + 1,
                    name: NAMES[k],
                    mean_mm: some.then(|| weighted / area),
                    min_mm: some.then_some(lo),
                    max_mm: some.then_some(hi),
                    area_mm2: area,
                }
            })
            .collect(),
    })
}

/// Why a wall around the RV cavity has no segments ([`super::septum::encloses_rv`]).
pub const ENCLOSES_RV: &str = "the epicardium encloses the RV cavity (a biventricular \
     epicardium): the LV wall would count the RV cavity as septum";

/// The segments of `wall`, placed by what `set` (the file its surfaces came from) says of the
/// septum ([`super::septum::orientation`]); else a sentence saying why there are none, for a
/// report's `segments_note` and the app.
pub fn of_file(set: &ContourSet, wall: &Wall) -> std::result::Result<Segments, String> {
    if super::septum::encloses_rv(set, wall) {
        return Err(ENCLOSES_RV.to_string());
    }
    let orientation = super::septum::orientation(set, wall).ok_or_else(|| {
        "the file has no RV_INSERT landmarks and no RV contours to place the septum by".to_string()
    })?;
    segments(wall, &orientation).map_err(|e| match e {
        CoreError::Degenerate(why) => why,
        e => e.to_string(),
    })
}

/// One segment's systolic wall thickening: how much thicker the wall is at end-systole than at
/// end-diastole, the regional contraction a bullseye of thickening shows (a dyskinetic segment
/// thins: negative).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SegmentThickening {
    pub id: usize,
    pub name: &'static str,
    pub ed_mm: Option<f64>,
    pub es_mm: Option<f64>,
    /// 100 x (ES - ED) / ED; null where either phase has no wall in the segment.
    pub thickening_percent: Option<f64>,
}

/// Each segment's thickening from end-diastole (`ed`) to end-systole (`es`). The two walls'
/// segments are placed each in its own phase (its base, cavity and septum), as the anatomy
/// moves between them.
pub fn thickening(ed: &Segments, es: &Segments) -> Vec<SegmentThickening> {
    ed.segments
        .iter()
        .zip(&es.segments)
        .map(|(d, s)| SegmentThickening {
            id: d.id,
            name: d.name,
            ed_mm: d.mean_mm,
            es_mm: s.mean_mm,
            thickening_percent: match (d.mean_mm, s.mean_mm) {
                (Some(a), Some(b)) if a > 0.0 => Some(100.0 * (b - a) / a),
                _ => None,
            },
        })
        .collect()
}

/// The cavity a wall's segments are measured around.
pub struct Cavity {
    /// Each vertex's share of the epicardium's and the endocardium's area.
    weights: Vec<[f64; 2]>,
    /// The endocardium's area-weighted centre: the long axis runs through it.
    pub centre: Vec3,
    /// The endocardium's lowest point below the base plane (mm).
    pub depth: f64,
    /// The epicardium's lowest point below the base plane (mm).
    wall_depth: f64,
}

impl Cavity {
    /// None when the wall has no endocardium below its base.
    pub fn of(wall: &Wall) -> Option<Cavity> {
        let n = wall.base.normal.normalize();
        let weights = vertex_areas(wall);
        let depth_of = |p: &Vec3| (wall.base.origin - p).dot(&n);
        let mut depth = f64::NEG_INFINITY;
        let mut wall_depth = f64::NEG_INFINITY;
        let mut centre = Vec3::zeros();
        let mut endo_area = 0.0;
        for (p, &[on_epi, on_endo]) in wall.mesh.positions.iter().zip(&weights) {
            if on_endo > 0.0 {
                depth = depth.max(depth_of(p));
                centre += p * on_endo;
                endo_area += on_endo;
            }
            if on_epi > 0.0 {
                wall_depth = wall_depth.max(depth_of(p));
            }
        }
        (endo_area > 0.0 && depth > 0.0).then(|| Cavity {
            weights,
            centre: centre / endo_area,
            depth,
            wall_depth,
        })
    }
}

/// Each vertex's share of the epicardium's and the endocardium's area (a third of each wall
/// triangle it is a corner of); base-ring triangles give none.
fn vertex_areas(wall: &Wall) -> Vec<[f64; 2]> {
    let mut out = vec![[0.0; 2]; wall.mesh.positions.len()];
    for (t, region) in wall.mesh.triangles.iter().zip(&wall.regions) {
        let slot = match *region {
            EPICARDIUM => 0,
            ENDOCARDIUM => 1,
            _ => continue,
        };
        let [a, b, c] = t.map(|i| wall.mesh.positions[i as usize]);
        let third = (b - a).cross(&(c - a)).norm() / 6.0;
        for &i in t {
            out[i as usize][slot] += third;
        }
    }
    out
}

#[cfg(test)]
mod tests;
