//! Where the septum lies around the LV's long axis, from what a contour file says about the RV:
//! the AHA segments ([`super::segments`]) are placed from it.
//!
//! The RV insertion points (biv-me's `RV_INSERT` landmarks, two per short-axis slice) are the
//! standard's own reference: the septum runs between the anterior and the inferior ones, so its
//! middle is the bisector of the two groups' mean directions. Grouping them by side of the RV's
//! centre (or of their own mean) keeps a slice with one insertion point from tipping the
//! bisector; points on one side only (one insertion line marked) defer to the RV's centre.
//! Without them the RV contours' centre gives the direction (the septum faces the RV; on the
//! biv-me patients the two agree within 11 degrees). Without either, nothing does: an LV-only
//! file cannot say which side is septal.

use super::function::winding_number;
use super::segments::{Cavity, Orientation};
use crate::contours::ContourSet;
use crate::geometry::Vec3;
use crate::mesh::wall::Wall;

/// Landmark names read as RV insertion points (compared without case).
fn is_insertion(name: &str) -> bool {
    let n = name.to_ascii_uppercase();
    n.contains("RV") && n.contains("INSERT")
}

/// A surface name read as the RV's (RV_ENDO, RV_EPI, RV_FREEWALL, ...).
fn is_rv(surface: &str) -> bool {
    surface.to_ascii_uppercase().starts_with("RV")
}

/// RV points (of surfaces other than an epicardium) below the base that [`encloses_rv`] tests, at
/// most: each costs a winding number over every triangle of the wall, and the answer is a
/// majority far from even (nearly all inside a wall around the RV, nearly none otherwise), so 64
/// evenly taken decide it (300 took 7.7 ms on patient 1's wall, as long as building it).
const RV_SAMPLES: usize = 64;

/// Whether the wall holds the RV cavity: most of the file's RV cavity points below the base lie
/// inside the solid. Its "LV epicardium" is then a biventricular one (label maps painted from
/// biventricular models ring both cavities with one myocardium label), so the wall counts the RV
/// cavity as septum: 30 mm and more where 10 would be. Such a wall has no segments.
pub fn encloses_rv(set: &ContourSet, wall: &Wall) -> bool {
    let n = wall.base.normal.normalize();
    let below: Vec<Vec3> = set
        .contours
        .iter()
        .filter(|c| {
            c.surface
                .as_deref()
                .is_some_and(|s| is_rv(s) && !s.to_ascii_uppercase().contains("EPI"))
        })
        .flat_map(|c| c.points().copied())
        .filter(|p| p.iter().all(|x| x.is_finite()) && (wall.base.origin - p).dot(&n) > 0.0)
        .collect();
    if below.is_empty() {
        return false;
    }
    let step = below.len().div_ceil(RV_SAMPLES);
    let sampled: Vec<&Vec3> = below.iter().step_by(step).collect();
    let inside = sampled
        .iter()
        .filter(|p| winding_number(&wall.mesh, p) > 0.5)
        .count();
    2 * inside > sampled.len()
}

/// Whether `set` says where the septum is (RV insertion landmarks or RV contours), before any
/// wall is built.
pub fn said(set: &ContourSet) -> bool {
    set.landmarks.iter().any(|(name, _)| is_insertion(name))
        || set
            .contours
            .iter()
            .any(|c| c.surface.as_deref().is_some_and(is_rv))
}

/// The septum's direction for `wall`, from `set`'s RV insertion landmarks, else its RV contours.
pub fn orientation(set: &ContourSet, wall: &Wall) -> Option<Orientation> {
    let cavity = Cavity::of(wall)?;
    orientation_around(set, &cavity.centre, &wall.base.normal)
}

/// The septum's direction across `axis` seen from `centre` (a point on the LV's long axis: a
/// cavity's centre), from `set`'s RV insertion landmarks, else its RV contours. One surface
/// without a wall needs it too (the anatomical layout, [`super::anatomical`]).
pub fn orientation_around(set: &ContourSet, centre: &Vec3, axis: &Vec3) -> Option<Orientation> {
    let n = axis.try_normalize(1e-12)?;
    // A point a reader let through unfinished (NaN, infinite) says nothing of a direction.
    let across = |p: &Vec3| {
        let v = p - centre;
        (v - n * v.dot(&n))
            .try_normalize(1e-9)
            .filter(|d| d.iter().all(|x| x.is_finite()))
    };
    let rv: Vec<Vec3> = set
        .contours
        .iter()
        .filter(|c| c.surface.as_deref().is_some_and(is_rv))
        .flat_map(|c| c.points().copied())
        .filter(|p| p.iter().all(|x| x.is_finite()))
        .collect();
    let rv_direction = (!rv.is_empty())
        .then(|| across(&(rv.iter().sum::<Vec3>() / rv.len() as f64)))
        .flatten();
    let inserts: Vec<Vec3> = set
        .landmarks
        .iter()
        .filter(|(name, _)| is_insertion(name))
        .filter_map(|(_, p)| across(p))
        .collect();
    if inserts.len() >= 2 {
        if let Some(septum) = bisector(&inserts, rv_direction, &n) {
            return Some(Orientation {
                septum,
                source: "RV_INSERT landmarks",
                points: inserts.len(),
            });
        }
    }
    rv_direction.map(|septum| Orientation {
        septum,
        source: "the RV contours' centre",
        points: rv.len(),
    })
}

/// The middle of the septum from insertion directions: the two sides of `reference` (the RV's
/// direction, else the points' own mean) averaged apart, then halved. None when every point
/// lies on one side of the RV's direction (one insertion line marked: its mean would be 60
/// degrees off the septum's middle, where the RV's centre is not).
fn bisector(directions: &[Vec3], reference: Option<Vec3>, n: &Vec3) -> Option<Vec3> {
    let mean = directions.iter().sum::<Vec3>();
    let rv_given = reference.is_some();
    let reference = reference.or_else(|| mean.try_normalize(1e-9))?;
    let side = n.cross(&reference);
    let (mut a, mut b) = (Vec3::zeros(), Vec3::zeros());
    for d in directions {
        if d.dot(&side) >= 0.0 {
            a += d;
        } else {
            b += d;
        }
    }
    match (a.try_normalize(1e-9), b.try_normalize(1e-9)) {
        (Some(a), Some(b)) => (a + b).try_normalize(1e-9),
        _ if rv_given => None,
        _ => mean.try_normalize(1e-9),
    }
}
