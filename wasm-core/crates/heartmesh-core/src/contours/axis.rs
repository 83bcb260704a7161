//! The long axis, the SAX/LAX split and the apex-to-base order of the short-axis slices
//! (Villard et al. 2018, section 2.1).
//!
//! The central direction is the contour normal with the smallest sum of log(180 + angle) to all other
//! normals: a robust location that a few long-axis views cannot pull away from the short-axis stack.

use super::plane::{axis_angle_deg, fit_plane, PlaneFit};
use super::undamaged::cleaned_undamaged;
use super::{Contour, ContourKind, ContourSet};
use crate::error::{CoreError, Result};
use crate::geometry::{order_free_sum, order_free_vec_sum, Vec3};

/// Contours whose normal is within this angle of the central direction are short-axis.
pub const SAX_MAX_ANGLE_DEG: f64 = 20.0;

/// Short-axis contours closer than this to each other's plane (mm, plus a multiple of the fit
/// residuals) lie in the same image slice (e.g. RV free wall and septum).
const SAME_SLICE_MM: f64 = 1.5;

/// One short-axis image slice: the contours that lie in it and its height along the axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Slice {
    pub contours: Vec<usize>,
    /// Mean of point . axis over the slice's points (mm).
    pub height: f64,
}

/// The geometric layout of a contour set.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    pub kinds: Vec<ContourKind>,
    /// Plane fits (None for contours whose points are collinear or fewer than 3).
    pub planes: Vec<Option<PlaneFit>>,
    /// Long axis, unit, pointing from apex to base.
    pub axis: Vec3,
    /// In-plane frame completing a right-handed (x, y, axis).
    pub frame_x: Vec3,
    pub frame_y: Vec3,
    /// Short-axis slices sorted apex to base.
    pub slices: Vec<Slice>,
}

/// Principal direction of a point set (for collinear contours, which have no plane).
fn principal_direction(c: &Contour) -> Option<Vec3> {
    let pts: Vec<&Vec3> = c.points().collect();
    if pts.len() < 2 {
        return None;
    }
    let first = pts[0];
    let far = pts
        .iter()
        .max_by(|a, b| (**a - first).norm().total_cmp(&(**b - first).norm()))?;
    let d = *far - first;
    (d.norm() > 0.0).then(|| d.normalize())
}

fn mean_height(c: &Contour, axis: &Vec3) -> f64 {
    let n = c.point_count().max(1) as f64;
    c.points().map(|p| p.dot(axis)).sum::<f64>() / n
}

/// Completes `axis` to a right-handed orthonormal frame.
pub fn frame_for(axis: &Vec3) -> (Vec3, Vec3) {
    let helper = if axis.x.abs() < 0.9 {
        Vec3::x()
    } else {
        Vec3::y()
    };
    let x = (helper - axis * helper.dot(axis)).normalize();
    let y = axis.cross(&x);
    (x, y)
}

/// The SAX/LAX split of contours with their plane fits: the mean short-axis normal (sign still
/// free) and each contour's kind. Needs two contours that span a plane.
struct Split {
    axis: Vec3,
    kinds: Vec<ContourKind>,
}

fn split(contours: &[Contour], planes: &[Option<PlaneFit>]) -> Result<Split> {
    let normals: Vec<(usize, Vec3)> = planes
        .iter()
        .enumerate()
        .filter_map(|(i, p)| p.map(|p| (i, p.normal)))
        .collect();
    if normals.len() < 2 {
        return Err(CoreError::NoSaxGroup(format!(
            "only {} contour(s) span a plane",
            normals.len()
        )));
    }
    // Central direction: the normal minimising sum_j log(180 + angle) (ties: the first listed).
    let cost = |n: &Vec3| -> f64 {
        order_free_sum(
            normals
                .iter()
                .map(|(_, m)| (180.0 + axis_angle_deg(n, m)).ln()),
        )
    };
    let mut candidates: Vec<(f64, Vec3)> = normals.iter().map(|(_, n)| (cost(n), *n)).collect();
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    let Some(&(_, central)) = candidates.first() else {
        return Err(CoreError::NoSaxGroup("no contour normals".into()));
    };
    let first = split_about(contours, planes, &normals, central);
    if group_slices(contours, planes, &first.kinds, &first.axis).len() >= 2 {
        return Ok(first);
    }
    // The most central normal's group is not a stack (long-axis views outnumber the short-axis
    // slices and lie within 20 degrees of each other: they all contain the axis, so they form one
    // "slice"). Try the next directions by cost, one per 20-degree cone, for a group that is a
    // stack of parallel slices at different heights; if none is, keep the first (its error).
    let mut tried = vec![central];
    for &(_, n) in candidates.iter().skip(1) {
        if tried
            .iter()
            .any(|t| axis_angle_deg(t, &n) <= SAX_MAX_ANGLE_DEG)
        {
            continue;
        }
        tried.push(n);
        let other = split_about(contours, planes, &normals, n);
        if group_slices(contours, planes, &other.kinds, &other.axis).len() >= 2 {
            return Ok(other);
        }
    }
    Ok(first)
}

/// The split about a given central direction: contours within [`SAX_MAX_ANGLE_DEG`] of it are
/// short-axis, the axis their robust mean normal.
fn split_about(
    contours: &[Contour],
    planes: &[Option<PlaneFit>],
    normals: &[(usize, Vec3)],
    central: Vec3,
) -> Split {
    let sax_normals: Vec<Vec3> = normals
        .iter()
        .filter(|(_, n)| axis_angle_deg(n, &central) <= SAX_MAX_ANGLE_DEG)
        .map(|(_, n)| *n)
        .collect();
    // Robust mean of the SAX normals: their medoid by sum of angles, then the sign-aligned average.
    let medoid = sax_normals
        .iter()
        .map(|n| {
            let s = order_free_sum(sax_normals.iter().map(|m| axis_angle_deg(n, m)));
            (s, *n)
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, n)| n)
        .unwrap_or(central);
    let sum =
        order_free_vec_sum(
            sax_normals
                .iter()
                .map(|n| if n.dot(&medoid) < 0.0 { -n } else { *n }),
        );
    let axis = if sum.norm() > 0.0 {
        sum.normalize()
    } else {
        medoid
    };

    let kinds: Vec<ContourKind> = contours
        .iter()
        .zip(planes)
        .map(|(c, p)| match p {
            Some(p) if axis_angle_deg(&p.normal, &central) <= SAX_MAX_ANGLE_DEG => ContourKind::Sax,
            Some(_) => ContourKind::Lax,
            // A straight piece: it lies in a short-axis plane if it runs across the axis.
            None => match principal_direction(c) {
                Some(d) if axis_angle_deg(&d, &axis) > 90.0 - SAX_MAX_ANGLE_DEG => ContourKind::Sax,
                _ => ContourKind::Lax,
            },
        })
        .collect();
    Split { axis, kinds }
}

/// Classifies contours, finds the long axis and groups the short-axis contours into slices.
pub fn analyse(contours: &[Contour]) -> Result<Layout> {
    let planes: Vec<Option<PlaneFit>> = contours.iter().map(|c| fit_plane(c.points())).collect();
    let Split {
        mut axis, kinds, ..
    } = split(contours, &planes)?;
    let mut slices = group_slices(contours, &planes, &kinds, &axis);
    if slices.len() < 2 {
        return Err(CoreError::NoSaxGroup(format!(
            "found {} short-axis slice(s); at least 2 parallel slices at different heights are needed",
            slices.len()
        )));
    }
    if !apex_is_low(contours, &slices, &axis) {
        axis = -axis;
        for s in &mut slices {
            s.height = -s.height;
        }
        slices.reverse();
    }
    let (frame_x, frame_y) = frame_for(&axis);
    Ok(Layout {
        kinds,
        planes,
        axis,
        frame_x,
        frame_y,
        slices,
    })
}

/// Groups SAX contours lying in one plane into slices, sorted by height along `axis`.
fn group_slices(
    contours: &[Contour],
    planes: &[Option<PlaneFit>],
    kinds: &[ContourKind],
    axis: &Vec3,
) -> Vec<Slice> {
    let mut sax: Vec<(usize, f64)> = (0..contours.len())
        .filter(|&i| kinds[i] == ContourKind::Sax && contours[i].point_count() > 0)
        .map(|i| (i, mean_height(&contours[i], axis)))
        .collect();
    sax.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
    let mut slices: Vec<Slice> = Vec::new();
    for (i, h) in sax {
        let joins = slices.last().is_some_and(|s| {
            s.contours
                .iter()
                .all(|&j| same_slice(&contours[i], planes[i], &contours[j], planes[j], axis))
        });
        match slices.last_mut() {
            Some(s) if joins => s.contours.push(i),
            _ => slices.push(Slice {
                contours: vec![i],
                height: h,
            }),
        }
    }
    for s in &mut slices {
        let heights = s
            .contours
            .iter()
            .flat_map(|&j| contours[j].points().map(|p| p.dot(axis)));
        let n: usize = s.contours.iter().map(|&j| contours[j].point_count()).sum();
        s.height = order_free_sum(heights) / n.max(1) as f64;
    }
    slices
}

/// Whether two SAX contours lie in one image plane: each one's points are close to the other's plane
/// (or, for straight pieces without a plane, at the same height).
fn same_slice(
    a: &Contour,
    pa: Option<PlaneFit>,
    b: &Contour,
    pb: Option<PlaneFit>,
    axis: &Vec3,
) -> bool {
    let offset = |c: &Contour, p: &PlaneFit| -> f64 {
        let n = c.point_count().max(1) as f64;
        (c.points()
            .map(|q| (q - p.centroid).dot(&p.normal))
            .sum::<f64>()
            / n)
            .abs()
    };
    let tol = |p: &Option<PlaneFit>| SAME_SLICE_MM + 3.0 * p.map_or(0.0, |p| p.rms_residual);
    match (pa, pb) {
        (Some(pa), Some(pb)) => {
            offset(b, &pa) <= tol(&Some(pa)) && offset(a, &pb) <= tol(&Some(pb))
        }
        (Some(p), None) => offset(b, &p) <= tol(&Some(p)),
        (None, Some(p)) => offset(a, &p) <= tol(&Some(p)),
        (None, None) => (mean_height(a, axis) - mean_height(b, axis)).abs() <= SAME_SLICE_MM,
    }
}

/// The ventricles taper towards the apex: slices grow with height when the axis points apex to base.
/// Decided by the sign of the regression slope of each slice's extent (RMS radius about its centroid)
/// against its height.
fn apex_is_low(contours: &[Contour], slices: &[Slice], axis: &Vec3) -> bool {
    let stats: Vec<(f64, f64)> = slices
        .iter()
        .map(|s| {
            let pts: Vec<&Vec3> = s
                .contours
                .iter()
                .flat_map(|&j| contours[j].points())
                .collect();
            let n = pts.len().max(1) as f64;
            let c = order_free_vec_sum(pts.iter().map(|p| **p)) / n;
            let r2 = order_free_sum(pts.iter().map(|p| {
                let d = *p - c;
                (d - axis * d.dot(axis)).norm_squared()
            })) / n;
            (s.height, r2.sqrt())
        })
        .collect();
    let n = stats.len() as f64;
    let mh = stats.iter().map(|s| s.0).sum::<f64>() / n;
    let mr = stats.iter().map(|s| s.1).sum::<f64>() / n;
    let slope: f64 = stats.iter().map(|s| (s.0 - mh) * (s.1 - mr)).sum();
    slope >= 0.0
}

/// SAX/LAX kind of every contour of a freshly loaded set, by the same rule as [`analyse`] but
/// without asking for two short-axis slices: the app draws the split before any run. Each surface
/// is split on its own, as a run sees it (contours without a surface together with all others);
/// None where the rule cannot decide: fewer than two contours span a plane, or just two that
/// disagree (either could be the short axis), or a contour left empty by cleaning.
pub fn classify_kinds(set: &ContourSet) -> Vec<Option<ContourKind>> {
    let mut kinds = vec![None; set.contours.len()];
    let surfaces = set.surfaces();
    let all: Vec<usize> = (0..set.contours.len()).collect();
    // (members, whether the split decides every member or only those without a surface).
    let mut groups: Vec<(Vec<usize>, bool)> = Vec::new();
    if surfaces.len() <= 1 {
        groups.push((all, true));
    } else {
        for s in &surfaces {
            let members = all
                .iter()
                .copied()
                .filter(|&i| set.contours[i].surface.as_ref() == Some(s))
                .collect();
            groups.push((members, true));
        }
        if set.contours.iter().any(|c| c.surface.is_none()) {
            groups.push((all, false));
        }
    }
    for (group, decides_all) in groups {
        // Cleaned as a run cleans them (non-finite points and jumps would tilt the planes).
        let members: Vec<&Contour> = group.iter().map(|&i| &set.contours[i]).collect();
        let (kept, cleaned) = cleaned_undamaged(&members);
        let index: Vec<usize> = kept.into_iter().map(|k| group[k]).collect();
        let planes: Vec<Option<PlaneFit>> = cleaned.iter().map(|c| fit_plane(c.points())).collect();
        let Ok(split) = split(&cleaned, &planes) else {
            continue;
        };
        let normals: Vec<&Vec3> = planes.iter().flatten().map(|p| &p.normal).collect();
        if normals.len() == 2 && axis_angle_deg(normals[0], normals[1]) > SAX_MAX_ANGLE_DEG {
            continue;
        }
        for (k, &i) in split.kinds.iter().zip(&index) {
            if decides_all || set.contours[i].surface.is_none() {
                kinds[i] = Some(*k);
            }
        }
    }
    kinds
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contours::Polyline;
    use crate::geometry::v3;

    fn ring(id: &str, z: f64, r: f64) -> Contour {
        Contour {
            id: id.into(),
            surface: None,
            pieces: vec![Polyline {
                points: (0..40)
                    .map(|i| {
                        let a = i as f64 / 40.0 * std::f64::consts::TAU;
                        v3(r * a.cos(), r * a.sin(), z)
                    })
                    .collect(),
                closed: true,
            }],
            first_line: 0,
        }
    }

    fn lax(id: &str, angle: f64) -> Contour {
        let (c, s) = (angle.cos(), angle.sin());
        Contour {
            id: id.into(),
            surface: None,
            pieces: vec![Polyline {
                points: (0..30)
                    .map(|i| {
                        let t = i as f64 / 29.0 * std::f64::consts::PI;
                        let x = 20.0 * t.cos();
                        v3(x * c, x * s, 40.0 - 50.0 * t.sin())
                    })
                    .collect(),
                closed: false,
            }],
            first_line: 0,
        }
    }

    /// Three rings whose radius grows with z (the apex at low z) and three long-axis curves,
    /// shuffled: the stack both `analyse` and `classify_kinds` are checked on.
    fn shuffled_stack() -> Vec<Contour> {
        vec![
            ring("s3", 30.0, 20.0),
            lax("l1", 0.0),
            ring("s1", 10.0, 12.0),
            lax("l2", 1.2),
            ring("s2", 20.0, 17.0),
            lax("l3", 2.0),
        ]
    }

    #[test]
    fn splits_sax_and_lax_and_orders_apex_to_base() {
        let cs = shuffled_stack();
        let l = analyse(&cs).unwrap();
        assert_eq!(
            l.kinds,
            vec![
                ContourKind::Sax,
                ContourKind::Lax,
                ContourKind::Sax,
                ContourKind::Lax,
                ContourKind::Sax,
                ContourKind::Lax
            ]
        );
        assert!(axis_angle_deg(&l.axis, &v3(0., 0., 1.)) < 1e-6);
        assert!(l.axis.z > 0.0);
        let order: Vec<usize> = l.slices.iter().map(|s| s.contours[0]).collect();
        assert_eq!(order, vec![2, 4, 0]);
    }

    #[test]
    fn flips_axis_when_apex_is_high() {
        let cs = vec![
            ring("a", 0.0, 20.0),
            ring("b", 10.0, 15.0),
            ring("c", 20.0, 8.0),
        ];
        let l = analyse(&cs).unwrap();
        assert!(l.axis.z < 0.0);
        assert_eq!(l.slices[0].contours, vec![2]);
    }

    #[test]
    fn pieces_in_one_plane_form_one_slice() {
        let mut a = ring("fw", 10.0, 15.0);
        a.pieces[0].points.truncate(25);
        a.pieces[0].closed = false;
        let mut b = ring("sp", 10.0, 15.0);
        b.pieces[0].points.drain(0..25);
        b.pieces[0].closed = false;
        let cs = vec![a, b, ring("s2", 20.0, 18.0)];
        let l = analyse(&cs).unwrap();
        assert_eq!(l.slices.len(), 2);
        assert_eq!(l.slices[0].contours, vec![0, 1]);
    }

    /// A straight septum piece stored to 3 decimals in a tilted short-axis plane (as biv-me's test
    /// patient 1 has one): its fitted normal is the rounding's, so it used to count as long-axis;
    /// straight, it runs across the axis and lies in its slice's plane, so it joins that slice.
    #[test]
    fn a_rounded_straight_piece_joins_its_slice() {
        // A free-wall arc in the plane z = 10 and a straight 7-point septum across it, both tilted
        // about the y axis with the rest of the stack and rounded to 3 decimals.
        let tilt = |p: Vec3| {
            let (c, s) = (0.3f64.cos(), 0.3f64.sin());
            let q = v3(c * p.x + s * p.z, p.y, -s * p.x + c * p.z);
            v3(
                (q.x * 1e3).round() / 1e3,
                (q.y * 1e3).round() / 1e3,
                (q.z * 1e3).round() / 1e3,
            )
        };
        let tilted = |mut c: Contour| {
            for p in &mut c.pieces[0].points {
                *p = tilt(*p);
            }
            c
        };
        let mut fw = ring("fw", 10.0, 15.0);
        fw.pieces[0].points.truncate(21);
        fw.pieces[0].closed = false;
        let septum = Contour {
            id: "sp".into(),
            surface: None,
            pieces: vec![Polyline {
                points: (0..7)
                    .map(|i| v3(-15.0 + 5.0 * i as f64, 0.0, 10.0))
                    .collect(),
                closed: false,
            }],
            first_line: 0,
        };
        let cs = vec![
            tilted(fw),
            tilted(septum),
            tilted(ring("s2", 20.0, 18.0)),
            tilted(ring("s0", 0.0, 10.0)),
        ];
        let l = analyse(&cs).unwrap();
        assert!(l.planes[1].is_none(), "{:?}", l.planes[1]);
        assert_eq!(l.kinds[1], ContourKind::Sax);
        assert_eq!(l.slices.len(), 3);
        assert_eq!(l.slices[1].contours, vec![0, 1]);
    }

    #[test]
    fn one_plane_only_is_an_error() {
        let cs = vec![ring("a", 0.0, 20.0), ring("b", 0.0, 10.0)];
        assert_eq!(analyse(&cs).unwrap_err().code(), "no_sax_group");
    }

    fn set_of(contours: Vec<Contour>) -> ContourSet {
        ContourSet {
            contours,
            ..Default::default()
        }
    }

    #[test]
    fn kinds_without_two_slices() {
        // One SAX ring and three LAX curves: analyse refuses (one slice), the kinds are known.
        let cs = vec![
            ring("s", 10.0, 15.0),
            lax("l1", 0.0),
            ring("s2", 10.0, 8.0),
            lax("l2", 1.0),
        ];
        assert_eq!(analyse(&cs).unwrap_err().code(), "no_sax_group");
        let k = classify_kinds(&set_of(cs));
        use ContourKind::{Lax, Sax};
        assert_eq!(k, vec![Some(Sax), Some(Lax), Some(Sax), Some(Lax)]);
        // The same kinds as analyse gives when it can decide (the stack without its last curve).
        let mut cs = shuffled_stack();
        cs.pop();
        let expected: Vec<_> = analyse(&cs).unwrap().kinds.into_iter().map(Some).collect();
        assert_eq!(classify_kinds(&set_of(cs)), expected);
    }

    #[test]
    fn undecidable_kinds_are_none() {
        use ContourKind::{Lax, Sax};
        // A single contour, or one ring and one perpendicular curve: no rule decides.
        assert_eq!(
            classify_kinds(&set_of(vec![ring("s", 0.0, 9.0)])),
            vec![None]
        );
        assert_eq!(
            classify_kinds(&set_of(vec![ring("s", 0.0, 9.0), lax("l", 0.0)])),
            vec![None, None]
        );
        // Two parallel rings agree: both short-axis.
        assert_eq!(
            classify_kinds(&set_of(vec![ring("a", 0.0, 9.0), ring("b", 0.0, 5.0)])),
            vec![Some(Sax), Some(Sax)]
        );
        // Per surface: the RV surface here has one ring only (undecided); the LV its own split;
        // a contour without a surface is split among all of them.
        let mut cs = vec![
            ring("lv1", 10.0, 15.0),
            lax("lv2", 0.0),
            ring("lv3", 20.0, 18.0),
            ring("rv1", 10.0, 30.0),
            lax("loose", 1.0),
        ];
        for c in &mut cs[..3] {
            c.surface = Some("LV".into());
        }
        cs[3].surface = Some("RV".into());
        let k = classify_kinds(&set_of(cs));
        assert_eq!(k, vec![Some(Sax), Some(Lax), Some(Sax), None, Some(Lax)]);
        // An empty contour stays undecided.
        let mut empty = ring("e", 0.0, 1.0);
        empty.pieces[0].points.clear();
        let k = classify_kinds(&set_of(vec![
            ring("a", 0.0, 9.0),
            ring("b", 5.0, 5.0),
            empty,
        ]));
        assert_eq!(k, vec![Some(Sax), Some(Sax), None]);
    }

    /// On real files, every surface's kinds at load are the kinds its reconstruction uses.
    #[test]
    fn kinds_at_load_are_the_run_kinds() {
        use crate::io::{read_contours, sample};
        use crate::{Params, Reconstruction};
        let mut checked = 0;
        for rel in [
            "contours/surfco-example.csv",
            "contours/bivme-example-patient1/patient1-ED.csv",
            "contours/bivme-test-patient2/patient2-ES.csv",
        ] {
            let set = read_contours(rel, &sample(rel)).unwrap();
            let kinds = classify_kinds(&set);
            assert!(kinds.iter().all(Option::is_some), "{rel}: {kinds:?}");
            let surfaces = set.surfaces();
            let runs: Vec<Option<String>> = if surfaces.is_empty() {
                vec![None]
            } else {
                surfaces.into_iter().map(Some).collect()
            };
            for surface in runs {
                let params = Params {
                    surface: surface.clone(),
                    ..Params::default()
                };
                let rec = Reconstruction::new(&set, params).unwrap();
                for (c, k) in rec.contours().iter().zip(rec.kinds()) {
                    let i = set
                        .contours
                        .iter()
                        .position(|d| d.id == c.id && d.surface == c.surface)
                        .unwrap();
                    assert_eq!(kinds[i], Some(*k), "{rel} {surface:?} {}", c.id);
                    checked += 1;
                }
            }
        }
        // Every contour of the three files (8 + 40 + 24).
        assert_eq!(checked, 72);
    }
}
