//! The biventricular epicardium (`BIV_EPI`): one surface around both ventricles, from a file's LV
//! and RV epicardial curves.
//!
//! A file with both surfaces holds the epicardium of the whole heart in two parts: the RV epicardium
//! is the free wall's outer curve, and the LV epicardium is, in biv-me / Cardiac Atlas Project
//! guide points, the LV free wall's (its septal side is the RV's cavity wall, not epicardium). Taken
//! together, plane by plane, they outline both ventricles, and the method reconstructs that outline
//! like any surface (the free-wall and septum pieces of an RV slice are joined into one ring the
//! same way). Where the LV epicardium is drawn as whole rings instead, its septal side lies inside
//! the outline and would pull the surface in: the LV points inside the RV epicardium's region of
//! their plane (the RV curve closed by its chord) are left out first. A modeller gets the surface
//! that 3D printing and whole-heart meshes need, which neither part gives alone.

use super::clean::cleaned_contour;
use super::plane::{axis_angle_deg, fit_plane};
use super::{Contour, ContourSet, Polyline};
use crate::geometry::Vec3;

/// The derived surface's label.
pub const BIV_EPI: &str = "BIV_EPI";
const LV_EPI: &str = "LV_EPI";
const RV_EPI: &str = "RV_EPI";

/// Curves within this angle (degrees) and distance (mm, between their planes) lie in one image.
const SAME_PLANE_DEG: f64 = 10.0;
const SAME_PLANE_MM: f64 = 2.0;

fn is(c: &Contour, label: &str) -> bool {
    c.surface
        .as_deref()
        .is_some_and(|s| s.eq_ignore_ascii_case(label))
}

/// Whether curves labelled `label` go into a reconstruction of `surface`: its own, and for
/// [`BIV_EPI`] the LV and RV epicardial ones (their load-time warnings concern it too).
pub fn part_of(label: &str, surface: &str) -> bool {
    label.eq_ignore_ascii_case(surface)
        || (surface.eq_ignore_ascii_case(BIV_EPI)
            && (label.eq_ignore_ascii_case(LV_EPI) || label.eq_ignore_ascii_case(RV_EPI)))
}

/// Whether `set` can give a biventricular epicardium: it has both epicardial surfaces and no
/// surface of that name of its own.
pub fn available(set: &ContourSet) -> bool {
    let has = |l: &str| set.contours.iter().any(|c| is(c, l));
    has(LV_EPI) && has(RV_EPI) && !has(BIV_EPI)
}

/// The contours of the biventricular epicardium, labelled [`BIV_EPI`]: the RV epicardial curves
/// as they are, the LV ones without their points inside the RV's region of the same plane. Empty
/// when the set has no LV or no RV epicardium.
pub fn contours(set: &ContourSet) -> Vec<Contour> {
    if !(set.contours.iter().any(|c| is(c, LV_EPI)) && set.contours.iter().any(|c| is(c, RV_EPI))) {
        return Vec::new();
    }
    let rv: Vec<Contour> = set
        .contours
        .iter()
        .filter(|c| is(c, RV_EPI))
        .filter_map(cleaned_contour)
        .collect();
    let mut out = Vec::new();
    for c in &set.contours {
        let mut c = if is(c, LV_EPI) {
            match cleaned_contour(c) {
                Some(lv) => without_rv_region(lv, &rv),
                None => continue,
            }
        } else if is(c, RV_EPI) {
            c.clone()
        } else {
            continue;
        };
        c.surface = Some(BIV_EPI.to_string());
        if c.pieces.iter().any(|p| !p.points.is_empty()) {
            out.push(c);
        }
    }
    out
}

/// `set` with the biventricular epicardium's contours added when `requested` asks for it and the
/// file has none of its own (None otherwise: the set is used as it is).
pub fn with_derived(set: &ContourSet, requested: Option<&str>) -> Option<ContourSet> {
    let wanted = requested.is_some_and(|s| s.eq_ignore_ascii_case(BIV_EPI));
    if !(wanted && available(set)) {
        return None;
    }
    let mut out = set.clone();
    out.contours.extend(contours(set));
    Some(out)
}

/// How a request for [`BIV_EPI`] is named when the file cannot give it (the error lists the
/// surfaces it has): what the derived surface needs.
pub fn requested_name(requested: &str) -> String {
    if requested.eq_ignore_ascii_case(BIV_EPI) {
        format!("{requested} (the biventricular epicardium, made of {LV_EPI} and {RV_EPI} curves)")
    } else {
        requested.to_string()
    }
}

/// The LV curve without its points inside the region any RV epicardial curve of its plane bounds.
fn without_rv_region(lv: Contour, rv: &[Contour]) -> Contour {
    let Some(plane) = fit_plane(lv.points()) else {
        return lv;
    };
    let regions: Vec<Region> = rv
        .iter()
        .filter(|r| {
            fit_plane(r.points()).is_some_and(|p| {
                axis_angle_deg(&p.normal, &plane.normal) <= SAME_PLANE_DEG
                    && (p.centroid - plane.centroid).dot(&plane.normal).abs() <= SAME_PLANE_MM
            })
        })
        .flat_map(|r| r.pieces.iter())
        .filter(|p| p.points.len() >= 3)
        .map(|p| Region::new(&p.points, &plane.normal))
        .collect();
    if regions.is_empty() {
        return lv;
    }
    let inside = |q: &Vec3| regions.iter().any(|r| r.contains(q));
    let pieces = lv
        .pieces
        .iter()
        .flat_map(|p| kept_runs(p, &inside))
        .collect();
    Contour { pieces, ..lv }
}

/// The runs of a piece's points `inside` rejects, each an open piece (a ring cut open where points
/// were left out; the piece itself when none was).
fn kept_runs(p: &Polyline, inside: &impl Fn(&Vec3) -> bool) -> Vec<Polyline> {
    let out: Vec<bool> = p.points.iter().map(inside).collect();
    let Some(first_out) = out.iter().position(|&o| o) else {
        return vec![p.clone()];
    };
    // A ring is walked from a left-out point so that no run wraps round its start.
    let n = p.points.len();
    let order: Vec<usize> = if p.closed {
        (0..n).map(|k| (first_out + k) % n).collect()
    } else {
        (0..n).collect()
    };
    let mut runs = Vec::new();
    let mut run: Vec<Vec3> = Vec::new();
    for i in order {
        if out[i] {
            if run.len() >= 2 {
                runs.push(Polyline {
                    points: std::mem::take(&mut run),
                    closed: false,
                });
            }
            run.clear();
        } else {
            run.push(p.points[i]);
        }
    }
    if run.len() >= 2 {
        runs.push(Polyline {
            points: run,
            closed: false,
        });
    }
    runs
}

/// A curve closed by its chord, in 2D coordinates of its plane.
struct Region {
    origin: Vec3,
    u: Vec3,
    v: Vec3,
    polygon: Vec<(f64, f64)>,
}

impl Region {
    fn new(points: &[Vec3], normal: &Vec3) -> Self {
        let u = normal.cross(&Vec3::new(1.0, 0.0, 0.0));
        let u = if u.norm() < 0.5 {
            normal.cross(&Vec3::new(0.0, 1.0, 0.0))
        } else {
            u
        }
        .normalize();
        let v = normal.cross(&u);
        let origin = points[0];
        let polygon = points
            .iter()
            .map(|p| ((p - origin).dot(&u), (p - origin).dot(&v)))
            .collect();
        Region {
            origin,
            u,
            v,
            polygon,
        }
    }

    /// Even-odd rule in the plane (the chord closes the polygon from the last point to the first).
    fn contains(&self, q: &Vec3) -> bool {
        let (x, y) = (
            (q - self.origin).dot(&self.u),
            (q - self.origin).dot(&self.v),
        );
        let n = self.polygon.len();
        let mut inside = false;
        for i in 0..n {
            let (x0, y0) = self.polygon[i];
            let (x1, y1) = self.polygon[(i + 1) % n];
            if (y0 > y) != (y1 > y) && x < x0 + (y - y0) * (x1 - x0) / (y1 - y0) {
                inside = !inside;
            }
        }
        inside
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    fn arc(id: &str, surface: &str, cx: f64, r: f64, z: f64, from: f64, to: f64) -> Contour {
        let points = (0..=40)
            .map(|i| {
                let t = from + (to - from) * i as f64 / 40.0;
                v3(cx + r * t.cos(), r * t.sin(), z)
            })
            .collect();
        Contour {
            id: id.into(),
            surface: Some(surface.into()),
            pieces: vec![Polyline {
                points,
                closed: false,
            }],
            first_line: 1,
        }
    }

    fn ring(id: &str, surface: &str, r: f64, z: f64) -> Contour {
        let mut c = arc(
            id,
            surface,
            0.0,
            r,
            z,
            0.0,
            std::f64::consts::TAU * 39.0 / 40.0,
        );
        c.pieces[0].closed = true;
        c
    }

    /// An LV ring of 20 mm and an RV crescent bulging from its right side (x > 0) in each slice.
    fn heart(lv_closed: bool) -> ContourSet {
        use std::f64::consts::PI;
        let mut contours = Vec::new();
        for k in 0..4 {
            let z = 10.0 * k as f64;
            contours.push(if lv_closed {
                ring(&format!("lv{k}"), LV_EPI, 20.0, z)
            } else {
                // biv-me's convention: the LV free wall only, the septal side (x > 12) absent.
                arc(&format!("lv{k}"), LV_EPI, 0.0, 20.0, z, 1.2, 2.0 * PI - 1.2)
            });
            // The RV: a 30 mm arc centred 15 mm right of the LV, its ends on the LV ring.
            contours.push(arc(&format!("rv{k}"), RV_EPI, 15.0, 19.0, z, -1.9, 1.9));
        }
        ContourSet {
            contours,
            ..Default::default()
        }
    }

    #[test]
    fn both_epicardia_become_one_surface() {
        let set = heart(false);
        assert!(available(&set));
        let biv = contours(&set);
        assert_eq!(biv.len(), 8);
        assert!(biv.iter().all(|c| c.surface.as_deref() == Some(BIV_EPI)));
        // The LV free wall is outside the RV's region: kept whole.
        let lv0 = biv.iter().find(|c| c.id == "lv0").unwrap();
        assert_eq!(lv0.point_count(), 41);
    }

    #[test]
    fn a_whole_lv_ring_loses_its_septal_side_inside_the_rv() {
        let biv = contours(&heart(true));
        let lv0 = biv.iter().find(|c| c.id == "lv0").unwrap();
        // One open arc: the ring cut where it runs inside the RV crescent (x > ~11 mm).
        assert_eq!(lv0.pieces.len(), 1, "{:?}", lv0.pieces.len());
        assert!(!lv0.pieces[0].closed);
        assert!(
            lv0.point_count() < 40 && lv0.point_count() > 25,
            "{}",
            lv0.point_count()
        );
        assert!(lv0.points().all(|p| p.x < 13.0), "septal points left out");
        // The RV curves are untouched.
        let rv0 = biv.iter().find(|c| c.id == "rv0").unwrap();
        assert_eq!(rv0.point_count(), 41);
    }

    #[test]
    fn warnings_of_both_epicardia_concern_it() {
        let mut set = heart(false);
        set.warnings = vec![
            "lv speck".into(),
            "rv stray".into(),
            "endo".into(),
            "file".into(),
        ];
        set.surface_warnings = vec![
            (LV_EPI.into(), "lv speck".into()),
            (RV_EPI.into(), "rv stray".into()),
            ("LV_ENDO".into(), "endo".into()),
        ];
        assert_eq!(
            set.warnings_for(Some("biv_epi")),
            ["lv speck", "rv stray", "file"]
        );
        assert_eq!(set.warnings_for(Some(LV_EPI)), ["lv speck", "file"]);
        assert!(part_of("RV_EPI", "BIV_EPI") && !part_of("RV_ENDO", "BIV_EPI"));
    }

    #[test]
    fn needs_both_epicardia() {
        let mut set = heart(false);
        set.contours.retain(|c| is(c, LV_EPI));
        assert!(!available(&set));
        assert!(contours(&set).is_empty());
        let mut own = heart(false);
        own.contours[0].surface = Some("biv_epi".into());
        assert!(!available(&own), "a file's own BIV_EPI is its own");
    }
}
