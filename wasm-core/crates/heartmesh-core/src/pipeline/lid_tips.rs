//! The plane of a lid that long-axis curves reach (`ends::tip_plane`), from the curves' tips
//! (docs/VALIDATION.md, "Session 16: the base lid where long-axis curves end at different
//! heights").
//!
//! The lid is one-sided, a ceiling (`lid_pull`): where the mesh lies under it the lid does nothing,
//! where the mesh runs past it the lid pulls it back. So a lid under a tip pulls the wall down
//! where a curve says the cavity goes on, while a lid over a tip leaves the wall there to the data
//! and the extrapolation. The tips' least-squares plane ([`least_squares`], session 10) goes
//! through the middle of a rim, but when one curve stopped short (a view drawn 5-25 mm short) it
//! tilts towards that tip and lies under the full curves' tips: on simulated acquisitions with
//! such curves it sat a median 6 mm under the truth's rim where a curve was cut, the mesh stopped
//! 5 mm short there and the volume fell by 3 % (the "dip"). [`valve_plane`] keeps the
//! least-squares plane while the tips read as one rim and takes the [`ceiling`], the lowest plane
//! that no tip lies above, when some tips lie alone far under the others.
//!
//! The ceiling: among the planes over every tip (slope at most `max_gradient`) the lowest,
//! measured halfway out from the ring's centre towards the tips on the plane's uphill side (height
//! at the centre plus half the tips' mean radius times the slope). Why halfway: measured at the
//! centre alone, a plane whose centre lies near the edge of the tips' spread can tilt freely, and
//! it tipped 45 degrees down towards two short curves; measured at the tips' radius, a flat plane
//! at the highest tip ties with the tilted plane through tips that agree. Candidates are the
//! planes through one tip (flat), two (tilted along them only) and three tips; the flat plane at
//! the highest tip is always one of them, so there is always an answer.

/// A tip in the lid's frame: position across the axis (mm, from the ring's centre) and height.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tip {
    pub x: f64,
    pub y: f64,
    pub h: f64,
}

/// A plane over the lid: height `a` at the ring's centre and slope (`gx`, `gy`) per mm across.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ceiling {
    pub a: f64,
    pub gx: f64,
    pub gy: f64,
}

impl Ceiling {
    pub fn height(&self, x: f64, y: f64) -> f64 {
        self.a + self.gx * x + self.gy * y
    }

    fn slope(&self) -> f64 {
        self.gx.hypot(self.gy)
    }
}

/// At most this many tips (the highest) bound the ceiling: candidates grow with the cube of the
/// count (a file with a dozen views has 24 tips; 40 take ~10^4 candidate planes).
pub const MAX_TIPS: usize = 40;

/// The lowest plane (see the module's doc) on or above every tip with a slope of at most
/// `max_gradient`; None without tips or with non-finite ones.
pub fn ceiling(tips: &[Tip], max_gradient: f64) -> Option<Ceiling> {
    if tips.is_empty()
        || !tips
            .iter()
            .all(|t| t.x.is_finite() && t.y.is_finite() && t.h.is_finite())
    {
        return None;
    }
    let mut tips = tips.to_vec();
    tips.sort_by(|a, b| b.h.total_cmp(&a.h));
    tips.truncate(MAX_TIPS);
    let reach = tips
        .iter()
        .map(|t| t.x.hypot(t.y))
        .fold(0.0f64, f64::max)
        .max(f64::MIN_POSITIVE);
    let mean_radius = tips.iter().map(|t| t.x.hypot(t.y)).sum::<f64>() / tips.len() as f64;
    // Rounding allowance for "on or above" (a plane through three tips passes the third within
    // rounding), relative to the tips' spread in height and across.
    let span = tips[0].h - tips[tips.len() - 1].h;
    let eps = 1e-9 * (reach + span.abs() + tips[0].h.abs());
    let above_all = |c: &Ceiling| tips.iter().all(|t| c.height(t.x, t.y) >= t.h - eps);
    let cost = |c: &Ceiling| c.a + 0.5 * mean_radius * c.slope();
    let mut best: Option<(f64, Ceiling)> = None;
    let mut consider = |c: Ceiling| {
        if !(c.a.is_finite() && c.slope() <= max_gradient + 1e-12 && above_all(&c)) {
            return;
        }
        let k = cost(&c);
        // Ties (within rounding) go to the flatter plane.
        let better =
            best.is_none_or(|(bk, b)| k < bk - eps || (k <= bk + eps && c.slope() < b.slope()));
        if better {
            best = Some((k, c));
        }
    };
    let n = tips.len();
    for i in 0..n {
        consider(flat(&tips[i]));
        for j in i + 1..n {
            if let Some(c) = through_two(&tips[i], &tips[j], reach) {
                consider(c);
            }
            for k in j + 1..n {
                if let Some(c) = through_three(&tips[i], &tips[j], &tips[k], reach) {
                    consider(c);
                }
            }
        }
    }
    best.map(|(_, c)| c)
}

fn flat(t: &Tip) -> Ceiling {
    Ceiling {
        a: t.h,
        gx: 0.0,
        gy: 0.0,
    }
}

/// The plane through two tips tilted along the line between them only (no tilt across: one view's
/// two tips say nothing about the slope across the view).
fn through_two(p: &Tip, q: &Tip, reach: f64) -> Option<Ceiling> {
    let (dx, dy) = (q.x - p.x, q.y - p.y);
    let l2 = dx * dx + dy * dy;
    if l2 <= (1e-9 * reach).powi(2) {
        return None;
    }
    let s = (q.h - p.h) / l2;
    let (gx, gy) = (s * dx, s * dy);
    Some(Ceiling {
        a: p.h - gx * p.x - gy * p.y,
        gx,
        gy,
    })
}

/// The plane through three tips; None when they (nearly) lie on a line across the axis.
fn through_three(p: &Tip, q: &Tip, r: &Tip, reach: f64) -> Option<Ceiling> {
    let (ux, uy, uh) = (q.x - p.x, q.y - p.y, q.h - p.h);
    let (vx, vy, vh) = (r.x - p.x, r.y - p.y, r.h - p.h);
    let det = ux * vy - uy * vx;
    // Twice the triangle's area against the tips' reach squared: a sliver says nothing reliable
    // about the slope across it.
    if det.abs() <= 1e-6 * reach * reach {
        return None;
    }
    let gx = (uh * vy - vh * uy) / det;
    let gy = (ux * vh - vx * uh) / det;
    Some(Ceiling {
        a: p.h - gx * p.x - gy * p.y,
        gx,
        gy,
    })
}

/// Share of the ring's radius squared, per tip, added to the least-squares normal equations'
/// slope terms: negligible against tips spread across the end, enough to make one view's two
/// tips a well-posed fit with no slope across the view (session 10).
pub const RIDGE_PER_RADIUS_SQ: f64 = 1e-3;

/// The least-squares plane of the tips' heights on their positions (session 10's valve plane),
/// with the ridge `ridge_per_tip` (mm^2 per tip) on the slope and the slope capped at
/// `max_gradient`.
pub fn least_squares(tips: &[Tip], ridge_per_tip: f64, max_gradient: f64) -> Option<Ceiling> {
    if tips.is_empty() {
        return None;
    }
    let mut m = nalgebra::Matrix3::<f64>::zeros();
    let mut rhs = nalgebra::Vector3::<f64>::zeros();
    for t in tips {
        let row = nalgebra::Vector3::new(1.0, t.x, t.y);
        m += row * row.transpose();
        rhs += row * t.h;
    }
    let ridge = ridge_per_tip * tips.len() as f64;
    m[(1, 1)] += ridge;
    m[(2, 2)] += ridge;
    let sol = m.lu().solve(&rhs)?;
    if !sol.iter().all(|x| x.is_finite()) {
        return None;
    }
    let (mut gx, mut gy) = (sol.y, sol.z);
    let g = gx.hypot(gy);
    if g > max_gradient {
        gx *= max_gradient / g;
        gy *= max_gradient / g;
    }
    Some(Ceiling { a: sol.x, gx, gy })
}

/// The lid's plane from the tips: their least-squares plane (the valve plane of session 10),
/// unless the tips fall into two groups, their depths under the [`ceiling`] over them separated by
/// a gap wider than `short` (mm): then the ceiling itself.
///
/// A valve rim seen through complete curves spreads its tips' depths under the ceiling evenly (a
/// tilted or saddle-shaped annulus, an irregular rim: measured depths 0-15 mm with 10 mm slices on
/// the simulated spasm shapes, with no empty band wider than a slice spacing), and the
/// least-squares plane through the middle of them is kept, as before session 16. A curve that
/// stopped short leaves its tip alone far under the others: fitted through, it tilts the plane
/// towards it and under the full curves' tips across the base, so the lid is then the ceiling,
/// which lies under no tip.
pub fn valve_plane(
    tips: &[Tip],
    short: f64,
    ridge_per_tip: f64,
    max_gradient: f64,
) -> Option<Ceiling> {
    let top = ceiling(tips, max_gradient)?;
    let mut depths: Vec<f64> = tips.iter().map(|t| top.height(t.x, t.y) - t.h).collect();
    depths.sort_by(|a, b| a.total_cmp(b));
    let widest = depths.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
    if widest > short {
        Some(top)
    } else {
        least_squares(tips, ridge_per_tip, max_gradient)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tip(deg: f64, r: f64, h: f64) -> Tip {
        let a = deg.to_radians();
        Tip {
            x: r * a.cos(),
            y: r * a.sin(),
            h,
        }
    }

    /// Three views at 0, 45 and 90 degrees, tips at radius 20: angles 0/180, 45/225, 90/270.
    const ANGLES: [f64; 6] = [0.0, 180.0, 45.0, 225.0, 90.0, 270.0];

    #[test]
    fn tips_that_agree_give_their_plane() {
        // A valve plane rising 0.3 mm per mm along x, 10 mm over the ring at the centre.
        let tips: Vec<Tip> = ANGLES
            .iter()
            .map(|&d| {
                let t = tip(d, 20.0, 0.0);
                Tip {
                    h: 10.0 + 0.3 * t.x,
                    ..t
                }
            })
            .collect();
        let c = ceiling(&tips, 1.0).unwrap();
        assert!((c.a - 10.0).abs() < 1e-9, "{c:?}");
        assert!((c.gx - 0.3).abs() < 1e-12 && c.gy.abs() < 1e-12, "{c:?}");
    }

    #[test]
    fn a_short_curve_does_not_pull_the_plane_down() {
        // Every tip 20 mm over the ring but one cut 15 mm short, then also a second view's tip:
        // the ceiling stays flat at 20 (least squares: 17.5 at the centre, tilted 0.375 / mm
        // down towards the short tip, 7.5 mm under the truth there).
        let mut tips: Vec<Tip> = ANGLES.iter().map(|&d| tip(d, 20.0, 20.0)).collect();
        tips[1].h = 5.0;
        let c = ceiling(&tips, 1.0).unwrap();
        assert_eq!((c.a, c.gx, c.gy), (20.0, 0.0, 0.0));
        tips[4].h = 8.0;
        let c = ceiling(&tips, 1.0).unwrap();
        assert_eq!((c.a, c.gx, c.gy), (20.0, 0.0, 0.0));
        // Both tips of one view short: the same.
        let mut view: Vec<Tip> = ANGLES.iter().map(|&d| tip(d, 20.0, 20.0)).collect();
        view[2].h = 9.0;
        view[3].h = 9.0;
        assert_eq!(ceiling(&view, 1.0).unwrap().a, 20.0);
    }

    #[test]
    fn never_under_a_tip() {
        // A saddle (high at 0/180, low at 90/270) and scattered heights: every tip on or under.
        let saddle: Vec<Tip> = ANGLES
            .iter()
            .map(|&d| tip(d, 20.0, 15.0 + 5.0 * (2.0 * d.to_radians()).cos()))
            .collect();
        let c = ceiling(&saddle, 1.0).unwrap();
        assert!(saddle.iter().all(|t| c.height(t.x, t.y) >= t.h - 1e-9));
        // Flat at the high tips: tilting would raise one of them or the far side.
        assert!(
            (c.a - 20.0).abs() < 1e-9 && c.gx.hypot(c.gy) < 1e-9,
            "{c:?}"
        );
        let hs = [15.24, 11.92, 8.49, 21.27, 19.12, 22.05];
        let scattered: Vec<Tip> = ANGLES
            .iter()
            .zip(hs)
            .map(|(&d, h)| tip(d + 10.0, 25.0, h))
            .collect();
        let c = ceiling(&scattered, 1.0).unwrap();
        assert!(scattered.iter().all(|t| c.height(t.x, t.y) >= t.h - 1e-9));
        assert!(c.gx.hypot(c.gy) <= 1.0);
        assert!(c.a <= 22.05 + 1e-9, "{c:?}");
    }

    #[test]
    fn one_view_and_one_tip() {
        // One view's two tips: the line through them, no tilt across; one tip: flat there.
        let two = [tip(0.0, 10.0, 12.0), tip(180.0, 10.0, 8.0)];
        let c = ceiling(&two, 1.0).unwrap();
        assert!((c.a - 10.0).abs() < 1e-12 && (c.gx - 0.2).abs() < 1e-12 && c.gy.abs() < 1e-12);
        let c = ceiling(&two[..1], 1.0).unwrap();
        assert_eq!((c.a, c.gx, c.gy), (12.0, 0.0, 0.0));
        // Steeper than allowed (4 mm over 2 mm): flat at the higher tip instead.
        let steep = [tip(0.0, 1.0, 12.0), tip(180.0, 1.0, 8.0)];
        assert_eq!(ceiling(&steep, 1.0).unwrap().a, 12.0);
        assert!(ceiling(&[], 1.0).is_none());
        assert!(ceiling(&[tip(0.0, 1.0, f64::NAN)], 1.0).is_none());
    }

    #[test]
    fn least_squares_until_a_tip_is_short() {
        // Six tips 20 mm up, scattered +-2 mm (a saddle): depths 0, 0, 2, 2, 4, 4 under the
        // ceiling (22), no gap over 5 mm, so the least-squares plane, flat at their mean 20 (the
        // ridge only shrinks a zero slope).
        let hs = [22.0, 22.0, 20.0, 20.0, 18.0, 18.0];
        let mut tips: Vec<Tip> = ANGLES
            .iter()
            .zip(hs)
            .map(|(&d, h)| tip(d, 20.0, h))
            .collect();
        let c = valve_plane(&tips, 5.0, 0.4, 1.0).unwrap();
        assert!(
            (c.a - 20.0).abs() < 1e-12 && c.gx.hypot(c.gy) < 1e-12,
            "{c:?}"
        );
        // One tip cut to 10: 12 mm under the ceiling, 8 under the next deepest: the ceiling (flat
        // at 22).
        tips[5].h = 10.0;
        let c = valve_plane(&tips, 5.0, 0.4, 1.0).unwrap();
        assert!(
            (c.a - 22.0).abs() < 1e-12 && c.gx.hypot(c.gy) < 1e-12,
            "{c:?}"
        );
        // Least squares would have tilted towards it (the short tip is at 270 degrees, -y): 18.67
        // at the centre, rising 0.15 mm per mm away from it, 15.7 over the short tip and 21.7
        // over the 90-degree tip at 18.
        let l = least_squares(&tips, 0.4, 1.0).unwrap();
        assert!((l.a - 56.0 / 3.0).abs() < 1e-9, "{l:?}");
        assert!(l.gy > 0.149 && l.gy < 0.15, "{l:?}");
        // Depths spread evenly over 12 mm (0, 0, 3, 6, 9, 12): no gap over 5 mm, least squares.
        let even: Vec<Tip> = ANGLES
            .iter()
            .zip([22.0, 22.0, 19.0, 16.0, 13.0, 10.0])
            .map(|(&d, h)| tip(d, 20.0, h))
            .collect();
        let c = valve_plane(&even, 5.0, 0.4, 1.0).unwrap();
        assert_eq!(Some(c), least_squares(&even, 0.4, 1.0));
    }

    #[test]
    fn many_tips_keep_the_highest() {
        let tips: Vec<Tip> = (0..100)
            .map(|k| tip(k as f64 * 3.6, 20.0, if k == 7 { 30.0 } else { 10.0 }))
            .collect();
        let c = ceiling(&tips, 1.0).unwrap();
        assert!(c.height(tips[7].x, tips[7].y) >= 30.0 - 1e-9);
    }
}
