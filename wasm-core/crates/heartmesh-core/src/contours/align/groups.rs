//! The rigid units of breath-hold alignment: each short-axis image slice and each long-axis view,
//! with every surface's curves in it. One breath-hold moves the whole image, so an LV ring, its
//! epicardium and the RV crescent of one slice move together; the LV's closed rings then decide
//! the shift far better than the RV's open crescent could on its own.

use crate::contours::axis::analyse;
use crate::contours::plane::{axis_angle_deg, fit_plane, PlaneFit};
use crate::contours::undamaged::cleaned_undamaged;
use crate::contours::{Contour, ContourKind, ContourSet};
use crate::geometry::{lexicographic, Vec3};

/// More contours than any acquisition: the SAX/LAX analysis is quadratic in the count, so such a
/// file is left as it is (the reconstruction refuses it anyway, `pipeline::prepare`).
const MAX_CONTOURS: usize = 1000;

/// More points than any acquisition (real files have a few thousand): the estimate's cost grows
/// with crossings x points, so such a file is left as it is rather than stalling a browser tab.
const MAX_POINTS: usize = 200_000;

/// Long-axis curves whose normals are within this angle lie in one view. Views of a study are
/// tens of degrees apart (2-, 3-, 4-chamber); the curves of one image share its plane exactly, up
/// to the fit noise of short or nearly straight pieces.
const SAME_VIEW_DEG: f64 = 10.0;

/// ... and whose points lie this close to the view's plane (RMS, mm, plus three times the plane
/// fit's own RMS residual): as `contours::axis` groups short-axis contours into slices, a fraction
/// of a typical 6-10 mm slice thickness.
const SAME_VIEW_MM: f64 = 1.5;

/// A piece below this flatness ratio (smaller to larger in-plane extent) has no trustworthy
/// normal of its own: only its distance to a view's plane decides whether it belongs there.
const MIN_FLATNESS: f64 = 0.1;

/// Segments per bounding box of a piece's chunks: closest-point queries skip whole chunks
/// farther than the best segment found (a ring of 250 points is then a few boxes, not 250
/// segments, per crossing).
pub(super) const CHUNK: usize = 16;

/// One cleaned polyline of a group, tagged with its surface.
#[derive(Debug, Clone)]
pub(super) struct Piece {
    /// Index of the contour's surface label (contours without one share their own index).
    pub surface: u32,
    pub points: Vec<Vec3>,
    pub closed: bool,
    /// Axis-aligned bounds, for skipping pieces far from a query point.
    pub lo: Vec3,
    pub hi: Vec3,
    /// Bounds of segments [CHUNK k, CHUNK (k + 1)) (segment i joins points i and i + 1, the
    /// last of a closed piece back to point 0).
    pub chunks: Vec<(Vec3, Vec3)>,
}

/// A short-axis slice or a long-axis view: the contours that move together, and their plane.
#[derive(Debug, Clone)]
pub(super) struct Group {
    pub kind: ContourKind,
    pub label: String,
    /// Indices into the input set's contours.
    pub members: Vec<usize>,
    pub centroid: Vec3,
    /// Unit normal: the long axis for a slice, the fitted plane's normal for a view.
    pub normal: Vec3,
    pub pieces: Vec<Piece>,
}

impl Group {
    /// `v` without its component along the group's normal (shifts stay in the image plane).
    pub fn in_plane(&self, v: &Vec3) -> Vec3 {
        v - self.normal * v.dot(&self.normal)
    }
}

/// The groups of a set and the data's length scale (mm), or why there is nothing to align.
pub(super) struct Grouping {
    pub groups: Vec<Group>,
    /// Median RMS radius of the short-axis rings (closed pieces; all short-axis pieces when none
    /// is closed): the size of the ventricle, against which residual and shift caps are set.
    pub scale_mm: f64,
    /// The short-axis stack's axis (unit; the slices' normal).
    pub axis: Vec3,
}

/// Groups the contours of `set` (every surface together).
pub(super) fn group(set: &ContourSet) -> Result<Grouping, String> {
    if set.contours.len() > MAX_CONTOURS {
        return Err(format!(
            "{} contours: more than {MAX_CONTOURS}, not aligned",
            set.contours.len()
        ));
    }
    if set.point_count() > MAX_POINTS {
        return Err(format!(
            "{} points: more than {MAX_POINTS}, not aligned",
            set.point_count()
        ));
    }
    let all: Vec<&Contour> = set.contours.iter().collect();
    let (index, cleaned) = cleaned_undamaged(&all);
    let layout = analyse(&cleaned).map_err(|e| format!("no short-axis stack to align ({e})"))?;
    let surfaces = surface_ids(&cleaned);
    let pieces_of = |k: usize| -> Vec<Piece> {
        cleaned[k]
            .pieces
            .iter()
            .filter(|p| !p.points.is_empty())
            .map(|p| piece(surfaces[k], &p.points, p.closed))
            .collect()
    };

    let mut groups = Vec::new();
    for (s, slice) in layout.slices.iter().enumerate() {
        let pieces: Vec<Piece> = slice.contours.iter().flat_map(|&k| pieces_of(k)).collect();
        let Some(centroid) = centroid(pieces.iter().flat_map(|p| p.points.iter())) else {
            continue;
        };
        groups.push(Group {
            kind: ContourKind::Sax,
            label: format!("SAX {}", s + 1),
            members: slice.contours.iter().map(|&k| index[k]).collect(),
            centroid,
            normal: layout.axis,
            pieces,
        });
    }
    let scale_mm = ring_scale(&groups, &layout.axis);

    // Long-axis views: each curve joins the first view whose plane it lies in, the curves taken
    // longest first (the best planes seed the views) and in an order of their own, not the
    // file's: a view's members, its plane and the order of its pieces then do not depend on
    // where the file lists its curves (a short RV septum seeding a view could leave the LV's
    // curves of the same image out of it).
    let mut lax: Vec<usize> = (0..cleaned.len())
        .filter(|&k| layout.kinds[k] == ContourKind::Lax)
        .collect();
    lax.sort_by(|&a, &b| content_order(&cleaned[a], &cleaned[b]));
    let mut views: Vec<(PlaneFit, Vec<usize>)> = Vec::new();
    for k in lax {
        let own = layout.planes[k].filter(|p| p.flatness_ratio >= MIN_FLATNESS);
        let joins = views.iter().position(|(plane, _)| {
            rms_offset(&cleaned[k], plane) <= SAME_VIEW_MM + 3.0 * plane.rms_residual
                && own.is_none_or(|o| axis_angle_deg(&o.normal, &plane.normal) <= SAME_VIEW_DEG)
        });
        match (joins, own) {
            (Some(v), _) => views[v].1.push(k),
            (None, Some(plane)) => views.push((plane, vec![k])),
            // A nearly straight curve in no view: no plane to shift it in; it stays put.
            (None, None) => {}
        }
    }
    for (seed, members) in views {
        let pieces: Vec<Piece> = members.iter().flat_map(|&k| pieces_of(k)).collect();
        let plane = fit_plane(pieces.iter().flat_map(|p| p.points.iter())).unwrap_or(seed);
        // Named and listed in the file's order.
        let mut listed = members.clone();
        listed.sort_unstable();
        let ids: Vec<&str> = listed.iter().map(|&k| cleaned[k].id.as_str()).collect();
        groups.push(Group {
            kind: ContourKind::Lax,
            label: ids.join(", "),
            members: listed.iter().map(|&k| index[k]).collect(),
            centroid: plane.centroid,
            normal: plane.normal,
            pieces,
        });
    }
    Ok(Grouping {
        groups,
        scale_mm,
        axis: layout.axis,
    })
}

/// An order of contours by their content alone: more points first, then point by point.
fn content_order(a: &Contour, b: &Contour) -> std::cmp::Ordering {
    b.point_count().cmp(&a.point_count()).then_with(|| {
        a.points()
            .zip(b.points())
            .map(|(p, q)| lexicographic(p, q))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
    })
}

fn piece(surface: u32, points: &[Vec3], closed: bool) -> Piece {
    let mut lo = Vec3::repeat(f64::INFINITY);
    let mut hi = Vec3::repeat(f64::NEG_INFINITY);
    for p in points {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    let m = points.len();
    let segments = match m {
        0 | 1 => 0,
        _ if closed && m > 2 => m,
        _ => m - 1,
    };
    let chunks = (0..segments.div_ceil(CHUNK))
        .map(|c| {
            let last = ((c + 1) * CHUNK).min(segments);
            (c * CHUNK..=last).fold(
                (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY)),
                |(l, h), i| (l.inf(&points[i % m]), h.sup(&points[i % m])),
            )
        })
        .collect();
    Piece {
        surface,
        points: points.to_vec(),
        closed,
        lo,
        hi,
        chunks,
    }
}

/// Surface label index per contour, in order of first appearance (None is a label of its own).
fn surface_ids(contours: &[Contour]) -> Vec<u32> {
    let mut seen: Vec<Option<&str>> = Vec::new();
    contours
        .iter()
        .map(|c| {
            let s = c.surface.as_deref();
            let k = seen.iter().position(|x| *x == s).unwrap_or_else(|| {
                seen.push(s);
                seen.len() - 1
            });
            k as u32
        })
        .collect()
}

fn centroid<'a>(points: impl Iterator<Item = &'a Vec3>) -> Option<Vec3> {
    let (sum, n) = points.fold((Vec3::zeros(), 0usize), |(s, n), p| (s + p, n + 1));
    (n > 0).then(|| sum / n as f64)
}

/// RMS distance of a contour's points to a plane (mm).
fn rms_offset(c: &Contour, plane: &PlaneFit) -> f64 {
    let (sum, n) = c.points().fold((0.0, 0usize), |(s, n), p| {
        let d = (p - plane.centroid).dot(&plane.normal);
        (s + d * d, n + 1)
    });
    (sum / n.max(1) as f64).sqrt()
}

/// Median RMS radius (about its own centroid, across the axis) of the short-axis closed pieces,
/// or of all short-axis pieces when none is closed; NaN without any.
fn ring_scale(sax: &[Group], axis: &Vec3) -> f64 {
    let radius = |p: &Piece| -> Option<f64> {
        let c = centroid(p.points.iter())?;
        let ss: f64 = p
            .points
            .iter()
            .map(|q| {
                let d = q - c;
                (d - axis * d.dot(axis)).norm_squared()
            })
            .sum();
        Some((ss / p.points.len() as f64).sqrt())
    };
    let all = sax.iter().flat_map(|g| g.pieces.iter());
    let mut r: Vec<f64> = all
        .clone()
        .filter(|p| p.closed)
        .filter_map(radius)
        .collect();
    if r.is_empty() {
        r = all.filter_map(radius).collect();
    }
    r.retain(|v| v.is_finite());
    if r.is_empty() {
        return f64::NAN;
    }
    r.sort_by(f64::total_cmp);
    r[r.len() / 2]
}
