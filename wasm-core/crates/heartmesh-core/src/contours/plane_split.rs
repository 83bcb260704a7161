//! Contours that hold the curves of several image planes under one name, split into one contour
//! per plane at load.
//!
//! A contour is a section in one image plane, and every later step (the short-/long-axis split,
//! the slice order, the tube's rings) takes it for one. Files break that in two ways: one name
//! for several slices (a `contour` column that holds the surface, `sax` for every short-axis
//! ring, an exporter that numbers the contours of each view from 1), read as one run of points
//! that jumps from slice to slice; or a name that comes back later in the file on another slice,
//! read as a second piece. Either way the tube built on such a "ring" folds through itself and
//! every remesh is refused (the fuzzer's merged contours: 700-1400 crossing triangle pairs). Where
//! the points fall cleanly into planar curves (each run between jumps lies in its plane), each
//! plane's curves become a contour of their own, named after the first (`sax`, `sax (2)`, ...),
//! and a warning says so. Anything less clean is left as read, with the non-planar warning.

use super::checks::{one_line, NON_PLANAR_MM};
use super::clean::SPIKE_POINTS;
use super::plane::{fit_plane, PlaneFit};
use super::{Contour, Polyline};
use crate::geometry::Vec3;

/// Whether points lie within [`NON_PLANAR_MM`] of one plane (collinear points and fewer than
/// three do: they fix no plane of their own).
fn planar(points: &[Vec3]) -> bool {
    fit_plane(points.iter()).is_none_or(|f| f.max_residual <= NON_PLANAR_MM)
}

/// A step between slices is at least this many times the run's median step to be cut there: a
/// jump from one slice's curve to the next is the slice gap (6-10 mm) against points 0.3-5 mm
/// apart; a curve whose steps are all alike (a helix, a noisy tilted curve) offers no cut.
const CUT_STEP_FACTOR: f64 = 2.0;

/// Most image planes one name is split into, and most cuts tried in one run: far above any
/// acquisition (20 short-axis slices and 6 long-axis views), low enough that a hostile file of a
/// million points jumping about is given up on in a bounded time instead of tried cut by cut.
const MAX_PLANES: usize = 256;

/// One run of consecutive points of one name, cut where it leaves its plane: when the whole run
/// is not planar, at its longest steps (each at least [`CUT_STEP_FACTOR`] x the median step; at
/// most [`MAX_PLANES`] of them), the longest first, until every part between cuts is planar (the
/// curves of several slices read one after another); then the cuts no plane needs are dropped,
/// and parts of one or two points may be no more than the others. Otherwise, or when no such
/// cuts exist, the run as it is.
pub fn split_run(run: Vec<Vec3>) -> Vec<Vec<Vec3>> {
    if run.len() < 6 || planar(&run) {
        return vec![run];
    }
    let steps: Vec<f64> = run.windows(2).map(|w| (w[1] - w[0]).norm()).collect();
    let mut sorted = steps.clone();
    sorted.sort_by(f64::total_cmp);
    let floor = CUT_STEP_FACTOR * sorted[sorted.len() / 2];
    let mut candidates: Vec<usize> = (0..steps.len()).filter(|&k| steps[k] > floor).collect();
    candidates.sort_by(|&a, &b| steps[b].total_cmp(&steps[a]));
    candidates.truncate(MAX_PLANES);
    // Part starts (cut k starts a part at point k + 1), each with whether it is planar; a cut
    // re-checks only the part it splits.
    let mut parts: std::collections::BTreeMap<usize, bool> = std::iter::once((0, false)).collect();
    let mut bent = 1usize;
    let end_of = |parts: &std::collections::BTreeMap<usize, bool>, start: usize| {
        parts
            .range(start + 1..)
            .next()
            .map_or(run.len(), |(&s, _)| s)
    };
    for k in candidates {
        let at = k + 1;
        let Some((&start, &was)) = parts.range(..at).next_back() else {
            continue;
        };
        let end = end_of(&parts, start);
        let (left, right) = (planar(&run[start..at]), planar(&run[at..end]));
        bent = bent + usize::from(!left) + usize::from(!right) - usize::from(!was);
        parts.insert(start, left);
        parts.insert(at, right);
        if bent > 0 {
            continue;
        }
        let ranges: Vec<std::ops::Range<usize>> =
            parts.keys().map(|&s| s..end_of(&parts, s)).collect();
        // Cuts between parts of one plane go again (a jump within one slice's curve: a
        // long-axis curve stored from mid-way, its valve gap), so that the run of each slice is
        // read as a file's run of one name always is.
        let slices: Vec<&[Vec3]> = ranges.iter().map(|r| &run[r.clone()]).collect();
        let Some(label) = group_by_plane(&slices) else {
            break;
        };
        let mut kept: Vec<std::ops::Range<usize>> = Vec::new();
        for (i, r) in ranges.into_iter().enumerate() {
            match kept.last_mut() {
                Some(last) if label[i] == label[i - 1] => last.end = r.end,
                _ => kept.push(r),
            }
        }
        // A run cut mostly into bits of a point or two is a wandering curve, not slices.
        let bits = kept.iter().filter(|r| r.len() < 3).count();
        return if bits <= kept.len() - bits {
            kept.into_iter().map(|r| run[r].to_vec()).collect()
        } else {
            vec![run]
        };
    }
    vec![run]
}

/// Largest distance (mm) of `points` from the plane of `fit`, but for up to [`SPIKE_POINTS`] of
/// them at the run's ends when it is longer than twice that (the smallest such largest
/// distance). A damaged first or last row thrown out of the image plane, on a curve so straight
/// that the two still fit a plane of their own, would otherwise make the run another slice's
/// (biv-me patient 1 ES's RV free wall s03, its last three rows 32 mm out: a contour
/// `s03_SAX_RV_FREEWALL (2)` of 14 points taken for a slice); within the plane but for those rows,
/// it is this plane's, and its contour leaves them out (`super::off_plane`).
fn off_plane(points: &[Vec3], fit: &PlaneFit) -> f64 {
    let d: Vec<f64> = points
        .iter()
        .map(|p| (p - fit.centroid).dot(&fit.normal).abs())
        .collect();
    let most = |r: &[f64]| r.iter().copied().fold(0.0, f64::max);
    if d.len() <= 2 * SPIKE_POINTS {
        return most(&d);
    }
    (0..=SPIKE_POINTS)
        .flat_map(|a| (0..=SPIKE_POINTS - a).map(move |b| (a, b)))
        .map(|(a, b)| most(&d[a..d.len() - b]))
        .fold(f64::INFINITY, f64::min)
}

/// Each planar run of points's plane group (numbered in the order of the runs' first appearance;
/// None past [`MAX_PLANES`] planes):
/// seeded by the largest runs (a short arc fixes its plane less well than a ring), each run
/// with the plane it lies nearest when within [`NON_PLANAR_MM`] of it, else a plane of its own
/// (a straight run far from every plane, a group of its own); a run of at most [`SPIKE_POINTS`]
/// points (a damaged row or three) goes with the nearest plane. Nearest, not first: a long-axis
/// curve's points near the axis lie close to every long-axis plane.
fn group_by_plane(runs: &[&[Vec3]]) -> Option<Vec<usize>> {
    let mut order: Vec<usize> = (0..runs.len()).collect();
    order.sort_by_key(|&k| std::cmp::Reverse(runs[k].len()));
    let mut fits: Vec<Option<PlaneFit>> = Vec::new();
    let mut label = vec![0usize; runs.len()];
    for k in order {
        if fits.len() > MAX_PLANES {
            return None;
        }
        let home = fits
            .iter()
            .enumerate()
            .filter_map(|(g, fit)| fit.as_ref().map(|f| (g, off_plane(runs[k], f))))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        label[k] = match (home, fit_plane(runs[k].iter())) {
            (Some((g, off)), _) if off <= NON_PLANAR_MM => g,
            // A run of a few points is no slice's curve: with the plane it lies nearest, whose
            // contour then leaves it out if damaged (`super::off_plane`), rather than a contour of
            // its own that the tube takes for a slice.
            (Some((g, _)), _) if runs[k].len() <= SPIKE_POINTS => g,
            (_, Some(fit)) => {
                fits.push(Some(fit));
                fits.len() - 1
            }
            // A straight run of its own far from every plane: a group of its own.
            (Some(_), None) if runs[k].len() >= 3 => {
                fits.push(None);
                fits.len() - 1
            }
            (Some((g, _)), None) => g,
            (None, None) if fits.is_empty() => {
                fits.push(None);
                0
            }
            (None, None) => 0,
        };
    }
    // Renumbered in the order the runs come.
    let mut seen: Vec<usize> = Vec::new();
    for &l in &label {
        if !seen.contains(&l) {
            seen.push(l);
        }
    }
    Some(
        label
            .iter()
            .map(|l| seen.iter().position(|s| s == l).unwrap_or(0))
            .collect(),
    )
}

/// The pieces of one contour grouped by image plane (indices into `pieces`, each group in file
/// order, the groups in the order of their first piece); None when the contour is one plane's
/// or its pieces do not fall cleanly into planes (a piece that is not planar itself).
fn plane_groups(pieces: &[Polyline]) -> Option<Vec<Vec<usize>>> {
    if pieces.len() < 2 || pieces.iter().any(|p| !planar(&p.points)) {
        return None;
    }
    let runs: Vec<&[Vec3]> = pieces.iter().map(|p| p.points.as_slice()).collect();
    let label = group_by_plane(&runs)?;
    let count = label.iter().max().map_or(0, |m| m + 1);
    if count < 2 {
        return None;
    }
    Some(
        (0..count)
            .map(|g| (0..pieces.len()).filter(|&k| label[k] == g).collect())
            .collect(),
    )
}

/// Splits every contour whose pieces lie in several image planes into one contour per plane
/// (`piece_lines[c][k]`: the file line of contour `c`'s piece `k`, 0 when unknown), and returns
/// each split contour's surface and citation for [`split_warnings`]. A new name never takes one
/// the file already uses.
pub fn split_by_plane(
    contours: &mut Vec<Contour>,
    piece_lines: &[Vec<usize>],
) -> Vec<(Option<String>, String)> {
    let mut taken: std::collections::HashSet<(String, Option<String>)> = contours
        .iter()
        .map(|c| (c.id.clone(), c.surface.clone()))
        .collect();
    let mut out: Vec<Contour> = Vec::with_capacity(contours.len());
    let mut flagged: Vec<(Option<String>, String)> = Vec::new();
    for (c, contour) in std::mem::take(contours).into_iter().enumerate() {
        let Some(groups) = plane_groups(&contour.pieces) else {
            out.push(contour);
            continue;
        };
        let lines = piece_lines.get(c);
        let mut names: Vec<String> = Vec::new();
        for (g, group) in groups.iter().enumerate() {
            let id = if g == 0 {
                contour.id.clone()
            } else {
                let mut n = g + 1;
                loop {
                    let id = format!("{} ({n})", contour.id);
                    if taken.insert((id.clone(), contour.surface.clone())) {
                        break id;
                    }
                    n += 1;
                }
            };
            names.push(format!("{id:?}"));
            out.push(Contour {
                id,
                surface: contour.surface.clone(),
                pieces: group.iter().map(|&k| contour.pieces[k].clone()).collect(),
                first_line: lines
                    .and_then(|l| l.get(group[0]).copied())
                    .filter(|&l| l > 0)
                    .unwrap_or(contour.first_line),
            });
        }
        // A long list of names would bury the line: six, then the count.
        let shown = if names.len() > 6 {
            format!("{}, ...", names[..6].join(", "))
        } else {
            names.join(", ")
        };
        let cited = contour.cite(&format!("{} image planes, read as {shown}", groups.len()));
        flagged.push((contour.surface, cited));
    }
    *contours = out;
    flagged
}

/// The warning line for contours split by [`split_by_plane`] (their citations).
pub fn split_warnings(flagged: Vec<String>) -> Vec<String> {
    one_line(
        flagged,
        "holds the curves of several slices under one name; each slice's is read as a contour",
        "hold the curves of several slices under one name; each slice's is read as a contour",
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    fn ring(z: f64, r: f64, n: usize) -> Vec<Vec3> {
        crate::geometry::ellipse(r, r, z, n)
    }

    #[test]
    fn damaged_end_rows_off_the_plane_are_no_slice_of_their_own() {
        // A curve stored in two runs (three quarters of a ring, then a straight stretch across
        // the open side), its last three rows thrown 25 mm out of the plane: the straight
        // stretch and those rows fit a plane of their own, yet they are this slice's.
        let mut run: Vec<Vec3> = (0..27)
            .map(|i| {
                let a = i as f64 / 27.0 * 1.5 * std::f64::consts::PI;
                v3(20.0 * a.cos(), 20.0 * a.sin(), 0.0)
            })
            .collect();
        run.extend((0..11).map(|i| v3(-5.0 + 3.0 * i as f64, -25.0, 0.0)));
        let whole = run.clone();
        run.extend((0..3).map(|i| v3(28.0 + 3.0 * i as f64, -25.0, 25.0)));
        let parts = split_run(run.clone());
        assert_eq!(
            parts.len(),
            1,
            "{:?}",
            parts.iter().map(Vec::len).collect::<Vec<_>>()
        );
        // Four rows out are more than a damaged row or three: a slice of their own.
        let mut four = whole.clone();
        four.extend((0..4).map(|i| v3(28.0 + 3.0 * i as f64, -25.0, 25.0)));
        assert_eq!(split_run(four).len(), 2);
        // Two runs of one name (a piece each), the second with those rows: one plane.
        let pieces = vec![
            Polyline {
                points: whole[..27].to_vec(),
                closed: false,
            },
            Polyline {
                points: run[27..].to_vec(),
                closed: false,
            },
        ];
        assert!(plane_groups(&pieces).is_none());
    }

    #[test]
    fn a_run_through_several_slices_is_cut_at_its_jumps() {
        let run: Vec<Vec3> = [0.0, 10.0, 20.0]
            .iter()
            .flat_map(|&z| ring(z, 20.0, 40))
            .collect();
        let parts = split_run(run.clone());
        assert_eq!(parts.len(), 3);
        assert!(parts.iter().all(|p| p.len() == 40));
        assert!((parts[2][0].z - 20.0).abs() < 1e-12);
        // One slice's ring, or a run that wanders out of plane without a jump: as it is.
        assert_eq!(split_run(ring(0.0, 20.0, 40)).len(), 1);
        let helix: Vec<Vec3> = (0..80)
            .map(|i| {
                let a = i as f64 * 0.2;
                v3(20.0 * a.cos(), 20.0 * a.sin(), i as f64 * 0.5)
            })
            .collect();
        assert_eq!(split_run(helix).len(), 1);
        // Small rings 6 mm apart, 0.3 mm steps: cut, each part a slice's; 3 mm apart they lie
        // within the tolerance of one plane and stay one run.
        let close =
            |dz: f64| -> Vec<Vec3> { [0.0, dz].iter().flat_map(|&z| ring(z, 5.0, 100)).collect() };
        assert_eq!(split_run(close(6.0)).len(), 2);
        assert_eq!(split_run(close(3.0)).len(), 1);
        // A ring, then an open curve with its last two points across a 40 mm gap (biv-me's long-
        // axis curves): cut between the slices only, the gap left to the curve's run.
        let mut run = ring(0.0, 20.0, 40);
        let lax: Vec<Vec3> = (0..30)
            .map(|i| {
                let t = i as f64 / 29.0 * std::f64::consts::PI;
                v3(0.0, 20.0 * t.cos(), -40.0 * t.sin())
            })
            .collect();
        run.extend(&lax);
        run.extend([v3(0.0, 20.0, 45.0), v3(0.0, 22.0, 44.0)]);
        let parts = split_run(run);
        let sizes: Vec<usize> = parts.iter().map(Vec::len).collect();
        assert_eq!(sizes, [40, 32]);
    }

    #[test]
    fn pieces_of_several_planes_become_one_contour_each() {
        let piece = |points: Vec<Vec3>, closed| Polyline { points, closed };
        // "c5": its ring at z 40, then (the name again, later) a quarter arc at z 50 and the rest
        // of its ring; "lax": a curve in two pieces in one plane; "c9" is taken.
        let arc: Vec<Vec3> = ring(50.0, 20.0, 40)[..10].to_vec();
        let mut contours = vec![
            Contour {
                id: "c5".into(),
                surface: None,
                pieces: vec![
                    piece(ring(40.0, 20.0, 40)[..30].to_vec(), false),
                    piece(arc, false),
                    piece(ring(40.0, 20.0, 40)[30..].to_vec(), false),
                ],
                first_line: 2,
            },
            Contour {
                id: "lax".into(),
                surface: None,
                pieces: vec![
                    piece(
                        vec![v3(0.0, 0.0, 0.0), v3(0.0, 5.0, 30.0), v3(0.0, 9.0, 60.0)],
                        false,
                    ),
                    piece(
                        vec![v3(0.0, 20.0, 60.0), v3(0.0, 25.0, 30.0), v3(0.0, 29.0, 0.0)],
                        false,
                    ),
                ],
                first_line: 90,
            },
        ];
        let flagged = split_by_plane(&mut contours, &[vec![2, 41, 51], vec![90, 93]]);
        let w = split_warnings(flagged.into_iter().map(|f| f.1).collect());
        let ids: Vec<&str> = contours.iter().map(|c| c.id.as_str()).collect();
        assert_eq!(ids, ["c5", "c5 (2)", "lax"]);
        assert_eq!(contours[0].pieces.len(), 2);
        assert_eq!(contours[1].pieces.len(), 1);
        assert_eq!(contours[1].first_line, 41);
        assert!(contours[1].pieces[0].points.iter().all(|p| p.z == 50.0));
        assert_eq!(
            w,
            [
                "contour \"c5\" (line 2, 2 image planes, read as \"c5\", \"c5 (2)\") holds the \
                 curves of several slices under one name; each slice's is read as a contour"
            ]
        );
        // A name already in the file is not reused.
        let mut taken = vec![
            Contour {
                id: "s".into(),
                surface: None,
                pieces: vec![
                    piece(ring(0.0, 9.0, 12), true),
                    piece(ring(9.0, 9.0, 12), true),
                ],
                first_line: 0,
            },
            Contour {
                id: "s (2)".into(),
                surface: None,
                pieces: vec![piece(ring(20.0, 9.0, 12), true)],
                first_line: 0,
            },
        ];
        split_by_plane(&mut taken, &[]);
        let ids: Vec<&str> = taken.iter().map(|c| c.id.as_str()).collect();
        assert_eq!(ids, ["s", "s (3)", "s (2)"]);
    }

    #[test]
    fn a_piece_that_is_not_planar_leaves_the_contour_as_read() {
        let twisted: Vec<Vec3> = (0..30)
            .map(|i| {
                let a = i as f64 * 0.2;
                v3(20.0 * a.cos(), 20.0 * a.sin(), i as f64)
            })
            .collect();
        let mut contours = vec![Contour {
            id: "t".into(),
            surface: None,
            pieces: vec![
                Polyline {
                    points: twisted,
                    closed: false,
                },
                Polyline {
                    points: ring(60.0, 20.0, 30),
                    closed: true,
                },
            ],
            first_line: 1,
        }];
        assert!(split_by_plane(&mut contours, &[]).is_empty());
        assert_eq!(contours.len(), 1);
        assert_eq!(contours[0].pieces.len(), 2);
    }
}
