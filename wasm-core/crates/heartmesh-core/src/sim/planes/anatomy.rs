//! Where a CMR planner puts the long axis of a shape ([`anatomical_axis`]), and how far along it
//! the short-axis sections are single closed loops ([`single_loop_span`]): the plan the
//! simulated acquisitions follow.

use crate::error::Result;
use crate::geometry::Vec3;
use crate::mesh::TriMesh;
use crate::sim::axis::LongAxis;
use crate::sim::repair::{boundary_loops, loop_diameter};
use crate::sim::slice::{join_chains, polyline_length, resample, slice_mesh, Plane};

/// Rounds of [`anatomical_axis`]: apex and base centre settle after two (the first moves the axis by
/// a few degrees from the principal direction, the second by hundredths of a degree).
const AXIS_ROUNDS: usize = 3;

/// The long axis a CMR planner would use: the line from the apex to the centre of the most basal
/// closed section (the mitral valve plane's centre), found from the principal axis by a few rounds
/// of: base centre = centroid of the highest single-loop section, apex = the surface point farthest
/// from it. The long-axis views (2, 3, 4 chamber) are planned through this line, so they all pass
/// through the apex; the principal axis through the centroid need not (a ventricle's apex is
/// often off its centroid line), which would leave the apex between the long-axis planes.
///
/// An open shape is also tried from its valve rim (apex = the surface point farthest from the rim
/// centre), and the start whose axis gives closed SAX sections over the longer length wins (the
/// principal one on a tie): the principal axis is the long axis only while the ventricle is
/// longer than wide, and a dilated, near-spherical ventricle can turn it into the base plane,
/// where the rounds cannot recover and the SAX planes cut the rim (found by the session-7
/// population study). A scanner's stack is a pile of closed rings; the plan that allows the
/// longer pile is the one that follows the ventricle.
pub fn anatomical_axis(mesh: &TriMesh, join_gap_mm: f64) -> Result<LongAxis> {
    let (pca, _) = LongAxis::from_mesh(mesh)?;
    let principal = refine_axis(mesh, pca, join_gap_mm);
    let Some(rim) = rim_axis(mesh) else {
        return Ok(principal);
    };
    // Same centre height convention as the rounds.
    let h = rim.height(&pca.centre);
    let from_rim = refine_axis(
        mesh,
        LongAxis {
            centre: rim.centre + rim.direction * h,
            direction: rim.direction,
        },
        join_gap_mm,
    );
    let span =
        |a: &LongAxis| single_loop_span(mesh, a, join_gap_mm).map_or(0.0, |(lo, hi)| hi - lo);
    Ok(if span(&from_rim) > span(&principal) {
        from_rim
    } else {
        principal
    })
}

/// The rounds of [`anatomical_axis`] from a starting axis.
pub(super) fn refine_axis(mesh: &TriMesh, mut axis: LongAxis, join_gap_mm: f64) -> LongAxis {
    for _ in 0..AXIS_ROUNDS {
        let Some((_, top)) = single_loop_span(mesh, &axis, join_gap_mm) else {
            break;
        };
        let plane = Plane {
            origin: axis.centre + axis.direction * top,
            normal: axis.direction,
        };
        let pieces = join_chains(slice_mesh(mesh, &plane), join_gap_mm, &plane);
        let Some(ring) = pieces
            .iter()
            .filter(|p| p.closed)
            .max_by(|a, b| polyline_length(a).total_cmp(&polyline_length(b)))
        else {
            break;
        };
        let base = resample(ring, 1.0);
        let base_centre =
            base.points.iter().fold(Vec3::zeros(), |a, p| a + p) / base.points.len().max(1) as f64;
        let Some(apex) = mesh
            .positions
            .iter()
            .filter(|p| axis.height(p) < top)
            .max_by(|a, b| {
                (*a - base_centre)
                    .norm_squared()
                    .total_cmp(&(*b - base_centre).norm_squared())
            })
        else {
            break;
        };
        // Keep the axis centre at the same height so heights stay comparable between rounds.
        let Some(next) = LongAxis::new(*apex, base_centre - apex) else {
            break;
        };
        let h = next.height(&axis.centre);
        axis = LongAxis {
            centre: next.centre + next.direction * h,
            direction: next.direction,
        };
    }
    axis
}

/// For an open shape, the line from the apex (the vertex farthest from the rim centre) to the
/// centre of its widest boundary loop (the valve rim; smaller loops are mesh defects). The rim
/// centre is length-weighted so uneven rim sampling does not pull it.
fn rim_axis(mesh: &TriMesh) -> Option<LongAxis> {
    let rim = boundary_loops(mesh)
        .into_iter()
        .max_by(|a, b| loop_diameter(mesh, a).total_cmp(&loop_diameter(mesh, b)))?;
    let (mut sum, mut len) = (Vec3::zeros(), 0.0);
    for (k, &v) in rim.iter().enumerate() {
        let a = mesh.positions[v as usize];
        let b = mesh.positions[rim[(k + 1) % rim.len()] as usize];
        let l = (b - a).norm();
        sum += (a + b) * (0.5 * l);
        len += l;
    }
    if !(len > 0.0 && len.is_finite()) {
        return None;
    }
    let centre = sum / len;
    let apex = mesh.positions.iter().max_by(|a, b| {
        (*a - centre)
            .norm_squared()
            .total_cmp(&(*b - centre).norm_squared())
    })?;
    LongAxis::new(*apex, centre - apex)
}

/// Scan step of [`single_loop_span`], mm.
const SCAN_STEP_MM: f64 = 0.5;

/// The heights along `axis` between which every plane perpendicular to it cuts `mesh` in one closed
/// loop, give or take small fragments (the longest such run, scanned every 0.5 mm). SAX planes belong there: below the
/// valve rim of an open shape, below where a closed shape's base splits into valve and outflow
/// tract, above any hole at the apex.
pub fn single_loop_span(mesh: &TriMesh, axis: &LongAxis, join_gap_mm: f64) -> Option<(f64, f64)> {
    let (lo, hi, _) = axis.extent(mesh)?;
    let steps = ((hi - lo) / SCAN_STEP_MM).floor() as usize;
    let mut best: Option<(f64, f64)> = None;
    let mut run_start: Option<f64> = None;
    let mut last_good = lo;
    for k in 0..=steps {
        let h = lo + SCAN_STEP_MM * (k as f64 + 0.5);
        let good = h < hi && single_loop_at(mesh, axis, h, join_gap_mm);
        if good {
            run_start.get_or_insert(h);
            last_good = h;
        } else if let Some(s) = run_start.take() {
            if best.is_none_or(|(a, b)| last_good - s > b - a) {
                best = Some((s, last_good));
            }
        }
    }
    if let Some(s) = run_start {
        if best.is_none_or(|(a, b)| last_good - s > b - a) {
            best = Some((s, last_good));
        }
    }
    best
}

/// Whether the plane across `axis` at height `h` cuts `mesh` in one closed loop: the longest piece
/// is closed and every other piece is small (fragments where the surfaces of a composite truth
/// overlap, or a small separate structure, dropped by `simulate`). A second large loop means the
/// base splits (valve, outflow tract).
pub(super) fn single_loop_at(mesh: &TriMesh, axis: &LongAxis, h: f64, join_gap_mm: f64) -> bool {
    let plane = Plane {
        origin: axis.centre + axis.direction * h,
        normal: axis.direction,
    };
    let pieces = join_chains(slice_mesh(mesh, &plane), join_gap_mm, &plane);
    let lengths: Vec<f64> = pieces.iter().map(polyline_length).collect();
    let longest = lengths.iter().cloned().fold(0.0, f64::max);
    !pieces.is_empty()
        && pieces.iter().zip(&lengths).all(|(p, &l)| {
            if l == longest {
                p.closed
            } else if p.closed {
                l <= 0.2 * longest
            } else {
                l <= 0.1 * longest
            }
        })
}
