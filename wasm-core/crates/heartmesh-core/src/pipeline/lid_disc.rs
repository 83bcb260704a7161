//! The lid's disc: grid points filling an end ring's outline in the lid's plane (`ends`).

use crate::geometry::{centroid, Vec3};

/// Lid points filling `ring`'s outline moved along `axis` to the height of `lid`: a square grid of
/// pitch `spacing` anchored at the outline's centroid and turned to the ring's first point (the
/// tube's seam, so the points do not depend on the scanner frame), keeping the grid points inside
/// the outline and at least `inset` from it.
pub fn disc_points(ring: &[Vec3], lid: &Vec3, axis: &Vec3, spacing: f64, inset: f64) -> Vec<Vec3> {
    if ring.len() < 3 || !(spacing.is_finite() && spacing > 0.0) {
        return Vec::new();
    }
    let h = lid.dot(axis);
    let outline: Vec<Vec3> = ring.iter().map(|p| p + axis * (h - p.dot(axis))).collect();
    let c = centroid(&outline);
    let Some(u) = (outline[0] - c).try_normalize(1e-300) else {
        return Vec::new();
    };
    let v = axis.cross(&u);
    let flat: Vec<(f64, f64)> = outline
        .iter()
        .map(|p| ((p - c).dot(&u), (p - c).dot(&v)))
        .collect();
    let reach = flat.iter().map(|(x, y)| x.hypot(*y)).fold(0.0, f64::max);
    let steps = (reach / spacing).ceil();
    if !steps.is_finite() || steps > 1e4 {
        return Vec::new();
    }
    let steps = steps as i64;
    let mut out = Vec::new();
    for j in -steps..=steps {
        for i in -steps..=steps {
            let (x, y) = (i as f64 * spacing, j as f64 * spacing);
            if inside(&flat, x, y) && edge_distance(&flat, x, y) >= inset {
                out.push(c + u * x + v * y);
            }
        }
    }
    out
}

/// Even-odd point-in-polygon test.
fn inside(poly: &[(f64, f64)], x: f64, y: f64) -> bool {
    let mut odd = false;
    for (k, a) in poly.iter().enumerate() {
        let b = poly[(k + 1) % poly.len()];
        if (a.1 > y) != (b.1 > y) && x < a.0 + (y - a.1) / (b.1 - a.1) * (b.0 - a.0) {
            odd = !odd;
        }
    }
    odd
}

/// Distance from (x, y) to the polygon's edges.
fn edge_distance(poly: &[(f64, f64)], x: f64, y: f64) -> f64 {
    let mut best = f64::INFINITY;
    for (k, a) in poly.iter().enumerate() {
        let b = poly[(k + 1) % poly.len()];
        let (ex, ey) = (b.0 - a.0, b.1 - a.1);
        let len2 = ex * ex + ey * ey;
        let t = if len2 > 0.0 {
            (((x - a.0) * ex + (y - a.1) * ey) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        best = best.min((x - a.0 - t * ex).hypot(y - a.1 - t * ey));
    }
    best
}
