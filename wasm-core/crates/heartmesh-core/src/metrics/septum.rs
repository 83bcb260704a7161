//! Where the septum lies around the LV's long axis, from what a contour file says about the RV:
//! the AHA segments ([`super::segments`]) are placed from it.
//!
//! The RV insertion points (biv-me's `RV_INSERT` landmarks, two per short-axis slice) are the
//! standard's own reference: the septum runs between the anterior and the inferior ones, so its
//! middle is the bisector of the two groups' mean directions. A slice's two insertions go one to
//! each group (the one a positive turn ahead of the other is the anterior), whichever side of the
//! RV's centre they lie on (near the apex both may lie on one); other points are grouped by side
//! of the RV's centre (or of their own mean), which keeps a slice with one insertion point from
//! tipping the bisector; points on one side only (one insertion line marked) defer to the RV's
//! centre.
//! Insertions that name their side (cvi42's reference points) need no grouping, and one side is
//! enough: the septum's middle is 60 degrees on from either, as the standard's segments run.
//! Without them the RV contours' centre gives the direction (the septum faces the RV; on the
//! biv-me patients the two agree within 11 degrees). Without either, nothing does: an LV-only
//! file cannot say which side is septal.

use super::function::winding_number;
use super::segments::{Cavity, Orientation};
use crate::contours::plane::fit_plane;
use crate::contours::ContourSet;
use crate::geometry::Vec3;
use crate::mesh::wall::Wall;

/// Landmark names read as RV insertion points (compared without case).
fn is_insertion(name: &str) -> bool {
    let n = name.to_ascii_uppercase();
    n.contains("RV") && n.contains("INSERT")
}

/// Which insertion a landmark names, where its file tells them apart (cvi42's superior and
/// inferior SAX reference points, read as `RV_INSERT_ANTERIOR` and `RV_INSERT_INFERIOR`);
/// biv-me's `RV_INSERT` does not.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Side {
    Anterior,
    Inferior,
}

fn side(name: &str) -> Option<Side> {
    let n = name.to_ascii_uppercase();
    if n.contains("ANTERIOR") || n.contains("SUPERIOR") {
        Some(Side::Anterior)
    } else if n.contains("INFERIOR") {
        Some(Side::Inferior)
    } else {
        None
    }
}

/// Degrees from an RV insertion to the middle of the septum: the standard's basal and mid
/// segments are 60 degrees each, and the anteroseptal one (2, 8) runs from the anterior insertion
/// to the septum's middle. cvi42 and Segment place the segments from one reference point so.
const INSERTION_TO_SEPTUM_DEG: f64 = 60.0;

/// `v` (across `n`) turned by `deg` degrees about `n`, right-handed.
fn turned(v: &Vec3, n: &Vec3, deg: f64) -> Vec3 {
    let (s, c) = deg.to_radians().sin_cos();
    v * c + n.cross(v) * s
}

/// The septum's middle from insertion points that say their side (`n` from the apex to the
/// base). Anterior lies a positive turn about `n` from the septum ([`super::segments`]), so the
/// septum is a negative turn on from the anterior insertion and a positive one from the
/// inferior. With both sides: the middle of the arc from the anterior group's mean direction to
/// the inferior's, taken the way the anatomy runs (through the septum, not the lateral wall).
fn from_sides(sided: &[(Side, Vec3)], n: &Vec3) -> Option<Vec3> {
    let mean = |want: Side| {
        sided
            .iter()
            .filter(|(s, _)| *s == want)
            .map(|(_, d)| d)
            .sum::<Vec3>()
            .try_normalize(1e-9)
    };
    match (mean(Side::Anterior), mean(Side::Inferior)) {
        (Some(a), Some(i)) => {
            let arc = a.cross(&i).dot(n);
            let middle = (a + i).try_normalize(1e-9);
            match middle {
                // The inferior insertion lies a negative turn (under half a turn) from the
                // anterior: the arc between them through the septum is the short one.
                Some(m) if arc < 0.0 => Some(m),
                Some(m) => Some(-m),
                None => Some(turned(&a, n, -90.0)),
            }
        }
        (Some(a), None) => Some(turned(&a, n, -INSERTION_TO_SEPTUM_DEG)),
        (None, Some(i)) => Some(turned(&i, n, INSERTION_TO_SEPTUM_DEG)),
        (None, None) => None,
    }
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
    let sided: Vec<(Side, Vec3)> = set
        .landmarks
        .iter()
        .filter(|(name, _)| is_insertion(name))
        .filter_map(|(name, p)| Some((side(name)?, across(p)?)))
        .collect();
    // Insertions that say their side are the reference the user set for the segments: one side
    // is enough, and it outranks the RV's centre.
    if let Some(septum) = from_sides(&sided, &n) {
        let both = sided.iter().any(|s| s.0 == Side::Anterior)
            && sided.iter().any(|s| s.0 == Side::Inferior);
        return Some(Orientation {
            septum,
            source: if both {
                "anterior and inferior RV insertion points"
            } else {
                "RV insertion points of one side, the septum 60 degrees on"
            },
            points: sided.len(),
        });
    }
    let points: Vec<Vec3> = set
        .landmarks
        .iter()
        .filter(|(name, _)| is_insertion(name))
        .filter(|(_, p)| across(p).is_some())
        .map(|(_, p)| *p)
        .collect();
    let inserts: Vec<Vec3> = points.iter().filter_map(across).collect();
    if inserts.len() >= 2 {
        let slices = same_slice_pairs(set, &points, &n);
        if let Some(septum) = bisector(&inserts, &slices, rv_direction, &n) {
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

/// How far (mm) an insertion point may lie from a short-axis contour's plane and still be of its
/// slice: biv-me marks the insertions on the slice's image, so they lie on its plane (0.1 mm off
/// on patient 1); the next slice is 8-10 mm away.
const ON_PLANE_MM: f64 = 1.5;

/// Short-axis contours are those whose plane lies across `n` within this angle (degrees).
const SAX_TILT_DEG: f64 = 30.0;

/// Pairs (indices into `points`) of insertion points that lie on one short-axis slice and are
/// its only two: biv-me's `RV_INSERT` marks both insertions on each slice without saying which
/// is which, and within a slice the anterior one is always the one a positive turn about the
/// axis ahead of the other. A slice's plane is that of its short-axis contours.
fn same_slice_pairs(set: &ContourSet, points: &[Vec3], n: &Vec3) -> Vec<(usize, usize)> {
    let cos_tilt = SAX_TILT_DEG.to_radians().cos();
    let planes: Vec<(Vec3, Vec3)> = set
        .contours
        .iter()
        .filter_map(|c| fit_plane(c.points()))
        .filter(|f| f.normal.dot(n).abs() >= cos_tilt && f.max_residual < ON_PLANE_MM)
        .map(|f| (f.centroid, f.normal))
        .collect();
    // Each point's slice: the first plane it lies on (planes of one slice lie within rounding).
    let slice_of = |p: &Vec3| {
        planes
            .iter()
            .position(|(c, m)| (p - c).dot(m).abs() < ON_PLANE_MM)
    };
    let slices: Vec<Option<usize>> = points.iter().map(slice_of).collect();
    // Planes of one slice (the LV and RV curves of one image) are one slice.
    let same = |a: usize, b: usize| {
        let ((ca, ma), (cb, _)) = (planes[a], planes[b]);
        (cb - ca).dot(&ma).abs() < ON_PLANE_MM
    };
    let mut pairs = Vec::new();
    for i in 0..points.len() {
        let Some(si) = slices[i] else { continue };
        let mates: Vec<usize> = (0..points.len())
            .filter(|&j| j != i && slices[j].is_some_and(|sj| same(si, sj)))
            .collect();
        if let [j] = mates[..] {
            if i < j {
                pairs.push((i, j));
            }
        }
    }
    pairs
}

/// The middle of the septum from insertion directions: the two sides of `reference` (the RV's
/// direction, else the points' own mean) averaged apart, then halved. A slice's two insertions
/// (`pairs`) go one to each side, the one a positive turn ahead of the other to the first, even
/// where both lie on one side of the reference (near the apex, where the RV's crescent is not
/// where its centre is). None when every point lies on one side of the RV's direction (one
/// insertion line marked: its mean would be 60 degrees off the septum's middle, where the RV's
/// centre is not).
fn bisector(
    directions: &[Vec3],
    pairs: &[(usize, usize)],
    reference: Option<Vec3>,
    n: &Vec3,
) -> Option<Vec3> {
    let mean = directions.iter().sum::<Vec3>();
    let rv_given = reference.is_some();
    let reference = reference.or_else(|| mean.try_normalize(1e-9))?;
    let side = n.cross(&reference);
    // Turn about n from the reference, in (-pi, pi].
    let turn = |d: &Vec3| d.dot(&side).atan2(d.dot(&reference));
    let mut first = vec![None; directions.len()];
    for &(i, j) in pairs {
        let ahead = turn(&directions[i]) >= turn(&directions[j]);
        first[i] = Some(ahead);
        first[j] = Some(!ahead);
    }
    let (mut a, mut b) = (Vec3::zeros(), Vec3::zeros());
    for (d, paired) in directions.iter().zip(first) {
        if paired.unwrap_or(d.dot(&side) >= 0.0) {
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
