//! The automatic attractor count: the paper's max(150, 25 x contours), a contour being one image
//! plane's delineation of the surface, with the slices of a dense stack counted at the spacing the
//! paper's count assumes.
//!
//! Planes, not names: files split one plane's curve as they please (biv-me stores the RV
//! endocardium of each slice and view as a free wall and a septum, other tools one curve per
//! slice, and a file may give one name to all of them). Counted by name, patient 1's ED RV had 400
//! attractors as biv-me writes it and 200 with a name per slice, and the mesh differed by 5 ml
//! (181.3 against 185.8 ml: the attractor spacing also sets the base lid's, 21 lid points
//! against 4).
//! The paper's stacks, the phantoms every accuracy figure comes from, have one curve per plane,
//! so the count per plane keeps their figures and makes the mesh independent of the naming.
//!
//! Twenty-five attractors per contour put them about a twenty-fifth of a ring apart along each
//! curve (the in-plane spacing, s). Cine stacks are 8-10 mm apart, wider than s, and the count
//! then samples the surface about as finely across the slices as along them. A stack resliced
//! from a 3D segmentation every 1-2 mm has ten times the slices of the same heart, and the count
//! grows with them while the surface it describes does not: the patient-1-sized CAP atlas mean
//! at 1 mm has 2112 attractors instead of 325, and the spline's solve, cubic in the count, takes
//! 12 s of a 13 s run (55 s in the browser) for no measurable gain (docs/VALIDATION.md, session
//! 16). So short-axis slices closer than s / 2 count as if they were s / 2 apart: the attractors
//! are never more than twice as dense across the slices as the paper's along them. A stack whose
//! slices are s / 2 or more apart (every cine acquisition measured) keeps the paper's count.

use crate::contours::axis::Layout;
use crate::contours::clean::length;
use crate::contours::plane::fit_plane;
use crate::contours::{Contour, ContourKind};
use crate::geometry::Vec3;

/// The paper's attractors per contour.
pub const PER_CONTOUR: usize = 25;
/// The paper's fewest automatic attractors.
pub const MIN_AUTO: usize = 150;

/// The automatic attractor count of `contours` (laid out as `layout`), at most `max`.
pub fn auto_attractors(contours: &[Contour], layout: &Layout, max: usize) -> usize {
    let sax = curves(contours, &layout.kinds, ContourKind::Sax);
    let lax = curves(contours, &layout.kinds, ContourKind::Lax);
    let counted = lax as f64 + sax as f64 * dense_stack_factor(contours, layout);
    ((PER_CONTOUR as f64 * counted).ceil() as usize).clamp(MIN_AUTO, max.max(MIN_AUTO))
}

/// Two curves lie in one image when no point of either is further from the plane fitted to both
/// than this share of their extent (the diagonal of their bounding box): curves drawn on one image
/// are coplanar to the file's rounding, while two slices of a dense 1 mm stack, 0.5 mm from their
/// mean plane over a 60 mm RV, are not (a share, so that a mouse heart pools as a human's).
const SAME_IMAGE_PER_EXTENT: f64 = 2e-3;

/// Most point visits the pairing may take, (curves - 1) x their points (each pair fits a plane to
/// both): a dense stack resliced every 1 mm with each slice in two parts takes about a million;
/// past this bound (a hostile file of thousands of curves) each curve counts alone.
const MAX_POOLING_WORK: usize = 20_000_000;

/// The contours of `kind` counted as the paper counts them, one per image's delineation: the
/// curves of one image ([`one_image`], grouped pair by pair, so the count does not depend on the
/// file's order of curves) count as many as the closed loops among them, and once when all are
/// open (a free wall and a septum; a ring stored in two parts; a tiny apical free wall that closes
/// on itself beside its septum is still one slice). Loops apart, each a contour of its own as
/// before: a dense stack's rings (each in its own image), a second loop beside a slice's ring.
fn curves(contours: &[Contour], kinds: &[ContourKind], kind: ContourKind) -> usize {
    let of_kind: Vec<&Contour> = contours
        .iter()
        .zip(kinds)
        .filter(|(c, k)| **k == kind && c.point_count() > 0)
        .map(|(c, _)| c)
        .collect();
    let closed = |c: &Contour| c.pieces.iter().any(|p| p.closed);
    let points: usize = of_kind.iter().map(|c| c.point_count()).sum();
    if of_kind.len().saturating_sub(1).saturating_mul(points) > MAX_POOLING_WORK {
        return of_kind.len();
    }
    // Union-find over the pairs that share an image.
    let mut root: Vec<usize> = (0..of_kind.len()).collect();
    fn find(root: &mut [usize], mut i: usize) -> usize {
        while root[i] != i {
            root[i] = root[root[i]];
            i = root[i];
        }
        i
    }
    for i in 0..of_kind.len() {
        for j in i + 1..of_kind.len() {
            if one_image(of_kind[i], of_kind[j]) {
                let (a, b) = (find(&mut root, i), find(&mut root, j));
                root[a.max(b)] = a.min(b);
            }
        }
    }
    let mut loops = vec![0usize; of_kind.len()];
    let mut groups = vec![false; of_kind.len()];
    for (i, c) in of_kind.iter().enumerate() {
        let g = find(&mut root, i);
        groups[g] = true;
        loops[g] += usize::from(closed(c));
    }
    (0..of_kind.len())
        .filter(|&g| groups[g])
        .map(|g| loops[g].max(1))
        .sum()
}

/// Whether two curves lie in one image plane (within [`SAME_IMAGE_PER_EXTENT`] of their extent
/// from the plane fitted to both; collinear points fix no plane and are never pooled).
fn one_image(a: &Contour, b: &Contour) -> bool {
    let points: Vec<Vec3> = a.points().chain(b.points()).copied().collect();
    let Some(fit) = fit_plane(points.iter()) else {
        return false;
    };
    let (lo, hi) = points.iter().fold(
        (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    );
    fit.max_residual <= SAME_IMAGE_PER_EXTENT * (hi - lo).norm()
}

/// The share of a short-axis stack's slices the count takes: 1 when the median gap between
/// neighbouring slices is at least half the in-plane attractor spacing (the median ring's
/// length / 25), else the gap over that half spacing.
pub fn dense_stack_factor(contours: &[Contour], layout: &Layout) -> f64 {
    let mut rings: Vec<f64> = layout
        .slices
        .iter()
        .map(|s| {
            s.contours
                .iter()
                .filter_map(|&i| contours.get(i))
                .flat_map(|c| &c.pieces)
                .map(|p| length(&p.points, p.closed))
                .sum::<f64>()
        })
        .filter(|l| *l > 0.0)
        .collect();
    let mut gaps: Vec<f64> = layout
        .slices
        .windows(2)
        .map(|w| (w[1].height - w[0].height).abs())
        .collect();
    let (Some(ring), Some(gap)) = (median(&mut rings), median(&mut gaps)) else {
        return 1.0;
    };
    let half_spacing = ring / PER_CONTOUR as f64 / 2.0;
    if !(gap > 0.0 && half_spacing > 0.0) || gap >= half_spacing {
        1.0
    } else {
        gap / half_spacing
    }
}

fn median(v: &mut [f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contours::axis::analyse;
    use crate::contours::{Contour, Polyline};
    use crate::geometry::v3;

    /// Rings of radius `r` every `gap` mm over 80 mm, plus two long-axis curves.
    fn stack(r: f64, gap: f64) -> Vec<Contour> {
        let mut out = Vec::new();
        let n = (80.0 / gap).round() as usize + 1;
        for k in 0..n {
            let z = k as f64 * gap;
            let pts = (0..60)
                .map(|i| {
                    let t = i as f64 / 60.0 * std::f64::consts::TAU;
                    v3(r * t.cos(), r * t.sin(), z)
                })
                .collect();
            out.push(contour(&format!("s{k}"), pts, true));
        }
        for (j, a) in [0.0f64, 1.5].iter().enumerate() {
            // A U through the axis: down one side of the stack and up the other.
            let pts = (0..=40)
                .map(|i| {
                    let u = i as f64 / 20.0 - 1.0;
                    v3(u * r * a.cos(), u * r * a.sin(), 80.0 * u * u)
                })
                .collect();
            out.push(contour(&format!("l{j}"), pts, false));
        }
        out
    }

    fn contour(id: &str, points: Vec<crate::geometry::Vec3>, closed: bool) -> Contour {
        Contour {
            id: id.into(),
            surface: None,
            pieces: vec![Polyline { points, closed }],
            first_line: 1,
        }
    }

    #[test]
    fn cine_stacks_keep_the_papers_count_and_dense_ones_count_slices_at_half_the_spacing() {
        // A 60-gon of radius 20 mm: 125.6 mm round, attractors 5.0 mm apart along it.
        let half_spacing = 120.0 * 20.0 * (std::f64::consts::PI / 60.0).sin() / 50.0;
        for (gap, slices) in [(10.0, 9), (2.6, 32), (2.0, 41), (1.0, 81)] {
            let set = stack(20.0, gap);
            let layout = analyse(&set).unwrap();
            let factor = f64::min(1.0, gap / half_spacing);
            let f = dense_stack_factor(&set, &layout);
            assert!(
                (f - factor).abs() < 1e-9,
                "{gap} mm: factor {f}, not {factor}"
            );
            let count = (25.0 * (2.0 + slices as f64 * factor)).ceil() as usize;
            assert_eq!(auto_attractors(&set, &layout, 5000), count, "{gap} mm");
        }
        assert!(half_spacing > 2.5 && half_spacing < 2.6);
        // The paper's floor and the cap still hold.
        let few = stack(20.0, 40.0);
        assert_eq!(auto_attractors(&few, &analyse(&few).unwrap(), 5000), 150);
        let set = stack(20.0, 1.0);
        assert_eq!(auto_attractors(&set, &analyse(&set).unwrap(), 400), 400);
    }

    #[test]
    fn every_real_acquisition_keeps_the_papers_count_of_one_contour_per_plane() {
        use crate::deform::attractors::Budget;
        use crate::pipeline::Reconstruction;
        use crate::Params;
        let files = [
            ("contours/surfco-example.csv", vec![None]),
            (
                "contours/bivme-example-patient1/patient1-ED.csv",
                vec![
                    Some("LV_ENDO"),
                    Some("LV_EPI"),
                    Some("RV_ENDO"),
                    Some("RV_EPI"),
                ],
            ),
            (
                "contours/bivme-test-patient2/patient2-ES.csv",
                vec![Some("LV_ENDO"), Some("LV_EPI"), Some("RV_ENDO")],
            ),
            // Its apical free wall (6 mm across) closes on itself beside its septum.
            (
                "contours/bivme-example-patient1/patient1-ES.csv",
                vec![Some("RV_ENDO")],
            ),
            (
                "contours/bivme-test-patient2/patient2-ED.csv",
                vec![Some("RV_ENDO")],
            ),
        ];
        for (file, surfaces) in files {
            let set = crate::io::read_contours(file, &crate::io::sample(file)).unwrap();
            for surface in surfaces {
                let params = Params {
                    surface: surface.map(str::to_string),
                    ..Params::default()
                };
                let rec = Reconstruction::new(&set, params).unwrap();
                // One contour per image plane: biv-me's RV free wall and septum count once.
                let mut planes: Vec<String> = rec
                    .contours
                    .iter()
                    .map(|c| c.id.replace("_RV_FREEWALL", "").replace("_RV_SEPTUM", ""))
                    .collect();
                planes.sort();
                planes.dedup();
                let paper = (25 * planes.len()).clamp(150, 5000);
                assert_eq!(
                    rec.attractor_budget,
                    Budget::Count(paper),
                    "{file} {surface:?}"
                );
            }
        }
    }

    /// `c`'s single piece cut in two at `at` (a fraction of its points), as two contours.
    fn halves(c: &Contour, at: f64) -> [Contour; 2] {
        let pts = &c.pieces[0].points;
        let k = (pts.len() as f64 * at) as usize;
        [
            contour(&format!("{}a", c.id), pts[..k].to_vec(), false),
            contour(&format!("{}b", c.id), pts[k..].to_vec(), false),
        ]
    }

    #[test]
    fn curves_of_one_plane_under_two_names_count_as_one_contour() {
        // Every ring and long-axis curve stored as two curves, as biv-me stores an RV's free wall
        // and septum: the count is the stack's as one curve per plane gives it.
        let set = stack(20.0, 10.0);
        let whole = auto_attractors(&set, &analyse(&set).unwrap(), 5000);
        assert_eq!(whole, 25 * (9 + 2));
        let split: Vec<Contour> = set.iter().flat_map(|c| halves(c, 0.6)).collect();
        assert_eq!(split.len(), 2 * set.len());
        let layout = analyse(&split).unwrap();
        assert_eq!(curves(&split, &layout.kinds, ContourKind::Lax), 2);
        assert_eq!(curves(&split, &layout.kinds, ContourKind::Sax), 9);
        assert_eq!(auto_attractors(&split, &layout, 5000), whole);
        // Slices 1 mm apart, each ring in two halves: a slice's halves pool, neighbours' do not;
        // at a tenth of the size (a mouse heart) alike.
        for scale in [1.0, 0.1] {
            let dense: Vec<Contour> = stack(20.0, 1.0)
                .iter()
                .flat_map(|c| halves(c, 0.3))
                .map(|mut c| {
                    c.pieces[0].points.iter_mut().for_each(|p| *p *= scale);
                    c
                })
                .collect();
            let layout = analyse(&dense).unwrap();
            assert_eq!(
                curves(&dense, &layout.kinds, ContourKind::Sax),
                81,
                "x{scale}"
            );
            assert_eq!(
                curves(&dense, &layout.kinds, ContourKind::Lax),
                2,
                "x{scale}"
            );
        }
    }

    #[test]
    fn the_rule_does_not_depend_on_the_units_scale() {
        // A mouse heart (a tenth of the size, slices a tenth as far apart) counts the same.
        let big = stack(20.0, 1.0);
        let small: Vec<Contour> = big
            .iter()
            .map(|c| {
                let pts = c.points().map(|p| p * 0.1).collect();
                contour(&c.id, pts, c.pieces[0].closed)
            })
            .collect();
        let (a, b) = (analyse(&big).unwrap(), analyse(&small).unwrap());
        assert_eq!(
            auto_attractors(&big, &a, 5000),
            auto_attractors(&small, &b, 5000)
        );
    }
}
