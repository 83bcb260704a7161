//! Assembles contours from a stream of points, the shape every contour reader produces.
//!
//! The rules follow the canonical CSV of ../shared/data/README.md: the points of a contour are
//! consecutive and ordered along the curve; an identifier that reappears after another one is the
//! same contour continued (biv-me files store some curves in two pieces), so it gets a new piece.

use std::collections::HashMap;

use crate::contours::clean::{JUMP_FACTOR, SPIKE_POINTS};
use crate::contours::{checks, plane_split, set_aside, slice_loops, Contour, ContourSet, Polyline};
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;

/// Largest number of points accepted from one file: far above any real cardiac data set (tens of
/// thousands of points), low enough that a browser tab survives a hostile file.
pub const MAX_POINTS: usize = 2_000_000;

/// Collects points run by run and turns each run into a [`Polyline`].
#[derive(Debug, Default)]
pub struct ContourBuilder {
    contours: Vec<Contour>,
    /// (identifier, surface) -> index into `contours`.
    index: HashMap<(String, Option<String>), usize>,
    /// Contour receiving the current run.
    current: Option<usize>,
    run: Vec<Vec3>,
    /// The file line of each point of `run`.
    run_lines: Vec<usize>,
    /// Per contour, the file line of each piece's first point (for contours split by plane).
    piece_lines: Vec<Vec<usize>>,
    total: usize,
    landmarks: Vec<(String, Vec3)>,
    warnings: Vec<String>,
}

impl ContourBuilder {
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends point `p` of contour `id` read at 1-based `line`.
    ///
    /// A contour is its identifier within its surface: files that number the slices of each
    /// surface from 1 (`1,LV_ENDO` ... `1,LV_EPI`) hold different contours under one name, which
    /// [`ContourBuilder::finish`] then qualifies with the surface.
    pub fn push(&mut self, id: &str, surface: Option<&str>, p: Vec3, line: usize) -> Result<()> {
        let same = self.current.is_some_and(|c| {
            self.contours
                .get(c)
                .is_some_and(|c| c.id == id && c.surface.as_deref() == surface)
        });
        if !same {
            self.flush();
            let key = (id.to_string(), surface.map(str::to_string));
            let idx = match self.index.get(&key) {
                Some(&i) => i,
                None => {
                    self.contours.push(Contour {
                        id: id.to_string(),
                        surface: surface.map(str::to_string),
                        pieces: Vec::new(),
                        first_line: line,
                    });
                    self.piece_lines.push(Vec::new());
                    self.index.insert(key, self.contours.len() - 1);
                    self.contours.len() - 1
                }
            };
            self.current = Some(idx);
        }
        self.count(line)?;
        self.run.push(p);
        self.run_lines.push(line);
        Ok(())
    }

    /// Appends a whole piece at once. `ring` is the file's own statement (DICOM's geometric type)
    /// when it has one; `None` leaves the decision to the end-point heuristic of
    /// [`polyline_from_run`]. The piece always ends here: a following piece with the same
    /// identifier becomes another piece of the same contour.
    pub fn push_piece(
        &mut self,
        id: &str,
        surface: Option<&str>,
        points: Vec<Vec3>,
        ring: Option<bool>,
        line: usize,
    ) -> Result<()> {
        self.break_run();
        for &p in &points {
            self.push(id, surface, p, line)?;
        }
        let run = std::mem::take(&mut self.run);
        self.run_lines.clear();
        if run.is_empty() {
            return Ok(());
        }
        let mut piece = polyline_from_run(run);
        if let Some(ring) = ring {
            if !ring && !piece.closed && piece.points.len() + 1 == points.len() {
                // The heuristic dropped a repeated end point of a curve declared open: keep it.
                piece.points = points;
            }
            piece.closed = ring && piece.points.len() >= 3;
        }
        if let Some(i) = self.current.filter(|&i| i < self.contours.len()) {
            self.contours[i].pieces.push(piece);
            self.piece_lines[i].push(line);
        }
        self.current = None;
        Ok(())
    }

    /// Ends the current run: the next point starts a new piece even with the same identifier.
    pub fn break_run(&mut self) {
        self.flush();
        self.current = None;
    }

    /// Records a named single point (valve, apex, ...).
    pub fn landmark(&mut self, name: &str, p: Vec3, line: usize) -> Result<()> {
        self.count(line)?;
        self.landmarks.push((name.to_string(), p));
        Ok(())
    }

    pub fn warn(&mut self, message: impl Into<String>) {
        self.warnings.push(message.into());
    }

    /// Number of points (contour points and landmarks) so far.
    pub fn total(&self) -> usize {
        self.total
    }

    fn count(&mut self, line: usize) -> Result<()> {
        self.total += 1;
        if self.total > MAX_POINTS {
            return Err(CoreError::parse(
                line,
                format!("too many points: the limit is {MAX_POINTS} points per file"),
            ));
        }
        Ok(())
    }

    fn flush(&mut self) {
        if self.run.is_empty() {
            return;
        }
        let run = std::mem::take(&mut self.run);
        let lines = std::mem::take(&mut self.run_lines);
        let Some(i) = self.current.filter(|&i| i < self.contours.len()) else {
            return;
        };
        // The curves of several slices read as one run: one piece each (plane_split).
        let mut start = 0;
        for part in plane_split::split_run(run) {
            let line = lines.get(start).copied().unwrap_or(0);
            start += part.len();
            self.contours[i].pieces.push(polyline_from_run(part));
            self.piece_lines[i].push(line);
        }
    }

    /// Finishes the set; refuses input without any contour point and adds the warnings of
    /// [`checks`] (units, non-curves, reused names), [`set_aside`] (strays and specks, left out of
    /// a reconstruction), [`slice_loops`] (second loops) and of this module.
    pub fn finish(mut self) -> Result<ContourSet> {
        self.flush();
        let split = plane_split::split_by_plane(&mut self.contours, &self.piece_lines);
        self.contours.retain(|c| c.point_count() > 0);
        if self.contours.is_empty() {
            return Err(CoreError::parse(0, "no contour points found"));
        }
        qualify_shared_ids(&mut self.contours);
        let mut set = ContourSet {
            contours: self.contours,
            landmarks: self.landmarks,
            warnings: self.warnings,
            ..ContourSet::default()
        };
        let parts = surface_parts(&set);
        split_warnings(&mut set, !parts.is_empty(), split);
        // Contours that are not curves first: on failure the first warning is the hint.
        scoped(&mut set, &parts, checks::few_point_warnings);
        if let Some(w) = checks::unit_warning(&set) {
            set.warnings.push(w);
        }
        // Across surfaces: a ring copied into another surface is a mistake about both.
        let dups = duplicate_warnings(&set);
        set.warnings.extend(dups);
        let checks: [fn(&ContourSet) -> Vec<String>; 10] = [
            checks::spike_warnings,
            checks::stray_point_warnings,
            checks::far_piece_warnings,
            checks::off_plane_warnings,
            checks::non_planar_warnings,
            order_warnings,
            set_aside::set_aside_warnings,
            checks::reused_id_warnings,
            slice_loops::second_loop_warnings,
            slice_loops::repeated_loop_warnings,
        ];
        for check in checks {
            scoped(&mut set, &parts, check);
        }
        Ok(set)
    }
}

/// The file's contours by surface label, when it holds more than one labelled surface (empty
/// otherwise): the checks that are about one surface's contours run on each part alone, so that
/// every warning line concerns one surface.
fn surface_parts(set: &ContourSet) -> Vec<(Option<String>, ContourSet)> {
    if set.surfaces().len() < 2 {
        return Vec::new();
    }
    checks::surface_groups(set)
        .into_iter()
        .map(|group| {
            let label = group.first().and_then(|c| c.surface.clone());
            let part = ContourSet {
                contours: group.into_iter().cloned().collect(),
                ..ContourSet::default()
            };
            (label, part)
        })
        .collect()
}

/// Adds the warning on contours split by image plane ([`plane_split`]): one line per surface,
/// recorded as about that surface when the file has several (as [`scoped`] does).
fn split_warnings(set: &mut ContourSet, by_surface: bool, split: Vec<(Option<String>, String)>) {
    let mut surfaces: Vec<Option<String>> = Vec::new();
    for (surface, _) in &split {
        if !surfaces.contains(surface) {
            surfaces.push(surface.clone());
        }
    }
    for surface in surfaces {
        let cited: Vec<String> = split
            .iter()
            .filter(|(s, _)| *s == surface)
            .map(|(_, c)| c.clone())
            .collect();
        for w in plane_split::split_warnings(cited) {
            if let (true, Some(label)) = (by_surface, &surface) {
                set.surface_warnings.push((label.clone(), w.clone()));
            }
            set.warnings.push(w);
        }
    }
}

/// Adds the warnings of `check`: over the whole set, or part by part (see [`surface_parts`]),
/// each line recorded as about its part's surface.
fn scoped(
    set: &mut ContourSet,
    parts: &[(Option<String>, ContourSet)],
    check: fn(&ContourSet) -> Vec<String>,
) {
    if parts.is_empty() {
        let found = check(set);
        set.warnings.extend(found);
        return;
    }
    for (label, part) in parts {
        for w in check(part) {
            if let Some(label) = label {
                set.surface_warnings.push((label.clone(), w.clone()));
            }
            set.warnings.push(w);
        }
    }
}

/// Names an identifier that several surfaces use (`3` of LV_ENDO and `3` of LV_EPI) after its
/// surface in every contour that has it (`3 LV_ENDO`, `3 LV_EPI`), so that each contour keeps a
/// name of its own in warnings, reports and saved files.
fn qualify_shared_ids(contours: &mut [Contour]) {
    let mut surfaces: HashMap<&str, Option<&str>> = HashMap::new();
    let mut shared: Vec<String> = Vec::new();
    for c in contours.iter() {
        match surfaces.get(c.id.as_str()) {
            Some(s) if *s != c.surface.as_deref() => shared.push(c.id.clone()),
            Some(_) => {}
            None => {
                surfaces.insert(&c.id, c.surface.as_deref());
            }
        }
    }
    if shared.is_empty() {
        return;
    }
    let shared: std::collections::HashSet<String> = shared.into_iter().collect();
    for c in contours.iter_mut().filter(|c| shared.contains(&c.id)) {
        c.id = format!(
            "{} {}",
            c.id,
            c.surface.as_deref().unwrap_or("(no surface)")
        );
    }
}

/// A delineated curve's path is a few times its width (a circle: pi; a U-shaped long-axis curve:
/// about 2.5). Far beyond that, its points zig-zag across the curve: shuffled by an exporter, or
/// noise much larger than their spacing. Either way the surface would chase the zig-zag.
const MAX_PATH_TO_WIDTH: f64 = 10.0;

/// Contours with a piece whose path is more than [`MAX_PATH_TO_WIDTH`] times its width (twice the
/// largest distance from its centroid, which does not depend on the scanner frame). One message
/// for all of them: a shuffling exporter shuffles every curve, and one line is what a user reads.
fn order_warnings(set: &ContourSet) -> Vec<String> {
    let mut flagged: Vec<(String, f64)> = Vec::new();
    for c in &set.contours {
        let worst = c
            .pieces
            .iter()
            .filter(|piece| piece.points.len() >= 8)
            .map(|piece| {
                let pts = &piece.points;
                let centroid = pts.iter().fold(Vec3::zeros(), |a, p| a + p) / pts.len() as f64;
                let width = 2.0
                    * pts
                        .iter()
                        .map(|p| (p - centroid).norm())
                        .fold(0.0, f64::max);
                let mut path: f64 = pts.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
                if piece.closed {
                    path += (pts[0] - pts[pts.len() - 1]).norm();
                }
                if width > 0.0 {
                    path / width
                } else {
                    0.0
                }
            })
            .fold(0.0, f64::max);
        if worst > MAX_PATH_TO_WIDTH {
            flagged.push((c.cite(""), worst));
        }
    }
    let question = "out of order, or very noisy?";
    match flagged.as_slice() {
        [] => Vec::new(),
        [(name, ratio)] => vec![format!(
            "contour {name}: its path is {ratio:.0} times its width; are its points {question}"
        )],
        many => {
            let (lo, hi) = many
                .iter()
                .fold((f64::INFINITY, 0.0f64), |(lo, hi), (_, r)| {
                    (lo.min(*r), hi.max(*r))
                });
            let names: Vec<&str> = many.iter().take(3).map(|(n, _)| n.as_str()).collect();
            let more = if many.len() > 3 { ", ..." } else { "" };
            vec![format!(
                "{} contours ({}{more}): their paths are {lo:.0}-{hi:.0} times their width; are \
                 their points {question}",
                many.len(),
                names.join(", ")
            )]
        }
    }
}

/// Contours whose points repeat an earlier contour's exactly (a copy-paste or export slip that
/// would double the weight of one curve). Candidates are found by a hash of the coordinates, so
/// that a file of a hundred thousand tiny contours is linear, not quadratic (it was: 100 s).
fn duplicate_warnings(set: &ContourSet) -> Vec<String> {
    use std::hash::{Hash, Hasher};
    let key = |c: &Contour| {
        let mut h = std::collections::hash_map::DefaultHasher::new();
        for p in c.points() {
            // + 0.0 makes -0.0 hash like 0.0, as they compare equal.
            for v in p.iter() {
                (v + 0.0).to_bits().hash(&mut h);
            }
        }
        h.finish()
    };
    let mut seen: HashMap<u64, Vec<usize>> = HashMap::new();
    let mut out = Vec::new();
    for (j, b) in set.contours.iter().enumerate() {
        let bucket = seen.entry(key(b)).or_default();
        let first = bucket
            .iter()
            .map(|&i| &set.contours[i])
            .find(|a| a.point_count() == b.point_count() && a.points().eq(b.points()));
        match first {
            Some(a) => out.push(format!(
                "contour {} repeats the points of contour {}",
                b.cite(""),
                a.cite("")
            )),
            None => bucket.push(j),
        }
    }
    if out.len() > 3 {
        let more = out.len() - 3;
        out.truncate(3);
        out.push(format!(
            "{more} more contours repeat the points of earlier ones"
        ));
    }
    out
}

/// Decides whether a run of points is a ring.
///
/// Files rarely say so: a ring is recognised when its ends are within twice the median spacing of
/// consecutive points, or no farther apart than its widest step short of a jump (a ring traced
/// with uneven steps, SurFCo's 0.01-1.6 mm, must not turn open because the file happens to start
/// after a long one; a curve stored in two pieces has a jump wider than any gap, which says
/// nothing about its ends); a repeated first point at the end is dropped. U-shaped long-axis
/// curves (open at the valves) have ends far apart and stay open. A ring whose first or last
/// rows (up to [`SPIKE_POINTS`]) are damaged values, entered by a jump, is still a ring: judged
/// open, its damaged rows could not be told from a curve's lone end points, and the surface grew
/// a finger to reach them (one row of biv-me patient 1 ED's LV epicardium ring s05 105 mm out:
/// 301.3 -> 418.2 ml); closed, they come straight back to its start and are left out as spikes
/// (`contours::clean::spikes`).
pub fn polyline_from_run(mut points: Vec<Vec3>) -> Polyline {
    if points.len() < 3 {
        return Polyline {
            points,
            closed: false,
        };
    }
    let mut gaps: Vec<f64> = points.windows(2).map(|w| (w[1] - w[0]).norm()).collect();
    gaps.sort_by(f64::total_cmp);
    let median = gaps[gaps.len() / 2];
    let first = points[0];
    let last = points[points.len() - 1];
    let ends = (last - first).norm();
    // "The same point" relative to the curve's size, so that float noise in a repeat counts.
    let tiny = 1e-9 * (1.0 + first.amax());
    if ends <= tiny {
        points.pop();
        return Polyline {
            closed: points.len() >= 3,
            points,
        };
    }
    let closed = closes(&points, median, 0) || closes_past_damaged_ends(&points, median);
    Polyline { closed, points }
}

/// Whether `points` close into a ring (the rules of [`polyline_from_run`]) for a curve of
/// median spacing `median` that is `missing` rows short at its closing gap (each widens it by a
/// step).
fn closes(points: &[Vec3], median: f64, missing: usize) -> bool {
    let (Some(first), Some(last)) = (points.first(), points.last()) else {
        return false;
    };
    let ends = (last - first).norm();
    // Equal steps of a ring differ in their last bits: a closing step as wide as the widest is one.
    let widest = points
        .windows(2)
        .map(|w| (w[1] - w[0]).norm())
        .fold(0.0, f64::max)
        * (1.0 + 1e-9);
    // Three or four points in a line (a septum piece of a thin basal crescent) have their ends
    // within two spacings too; a ring's path runs well beyond the gap that closes it.
    let path: f64 = points.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    let near = (2 + missing) as f64 * median;
    (ends <= near || (ends <= widest && ends <= JUMP_FACTOR * median)) && path > 1.5 * ends
}

/// Whether `points` close into a ring once up to [`SPIKE_POINTS`] first or last rows, entered
/// by a jump (over [`JUMP_FACTOR`] x `median`), are set aside: a ring with damaged end rows.
fn closes_past_damaged_ends(points: &[Vec3], median: f64) -> bool {
    let n = points.len();
    let jump = |a: usize| (points[a + 1] - points[a]).norm() > JUMP_FACTOR * median;
    (1..=SPIKE_POINTS)
        .filter(|&k| n >= k + 3 + SPIKE_POINTS)
        .any(|k| {
            (jump(n - k - 1) && closes(&points[..n - k], median, k))
                || (jump(k - 1) && closes(&points[k..], median, k))
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;

    #[test]
    fn shuffled_points_are_flagged_and_ordered_ones_are_not() {
        // A 30 mm ring of 60 points in order, then the same points in a fixed shuffled order.
        let ordered = ring(60, 15.0, false);
        let shuffled: Vec<Vec3> = (0..60).map(|i| ordered[(i * 37) % 60]).collect();
        let csv = |pts: &[Vec3], z: f64| -> String {
            pts.iter()
                .map(|p| format!("c{z},{},{},{}\n", p.x, p.y, z))
                .collect()
        };
        // The warnings of a file with ring `a` at z = 0 and ring `b` at z = 10.
        let warnings = |a: &[Vec3], b: &[Vec3]| {
            let text = format!("contour,x,y,z\n{}{}", csv(a, 0.0), csv(b, 10.0));
            crate::io::read_contours("rings.csv", text.as_bytes())
                .unwrap()
                .warnings
        };
        assert!(warnings(&ordered, &ordered).is_empty());
        let one = warnings(&ordered, &shuffled);
        assert_eq!(one.len(), 1, "{one:?}");
        assert!(
            one[0].starts_with("contour \"c10\" (line 62): its path is"),
            "{}",
            one[0]
        );
        // Every curve shuffled: one message for all of them.
        let all = warnings(&shuffled, &shuffled);
        assert_eq!(all.len(), 1, "{all:?}");
        let expected = "2 contours (\"c0\" (line 2), \"c10\" (line 62)): their paths are";
        assert!(all[0].starts_with(expected), "{}", all[0]);
    }

    #[test]
    fn a_warning_about_one_surface_is_left_out_of_the_others_runs() {
        // Two shuffled rings, one of LV_ENDO and one of RV_ENDO, and a 1-point RV contour.
        let ordered = ring(60, 15.0, false);
        let shuffled: Vec<Vec3> = (0..60).map(|i| ordered[(i * 37) % 60]).collect();
        let mut text = String::from("contour,surface,x,y,z\n");
        for (id, surface, z) in [("lv", "LV_ENDO", 0.0), ("rv", "RV_ENDO", 10.0)] {
            for p in &shuffled {
                text += &format!("{id},{surface},{},{},{z}\n", p.x, p.y);
            }
        }
        text += "dot,RV_ENDO,1,2,20\n";
        let set = crate::io::read_contours("biv.csv", text.as_bytes()).unwrap();
        // One line per surface and kind: RV not-a-curve, LV path, RV path.
        assert_eq!(set.warnings.len(), 3, "{:?}", set.warnings);
        let lv = set.warnings_for(Some("LV_ENDO"));
        assert_eq!(lv.len(), 1, "{lv:?}");
        assert!(lv[0].starts_with("contour \"lv\" (line 2)"), "{lv:?}");
        let rv = set.warnings_for(Some("rv_endo"));
        assert_eq!(rv.len(), 2, "{rv:?}");
        assert!(rv
            .iter()
            .all(|w| w.contains("\"dot\"") || w.contains("\"rv\"")));
        assert_eq!(set.warnings_for(None), set.warnings);
        // A warning about contours of two surfaces (a ring copied into another) stays with each.
        let copied = format!(
            "{text}{}",
            text.lines()
                .skip(1)
                .take(60)
                .map(|l| { format!("{}\n", l.replace("lv,LV_ENDO", "copy,LV_EPI")) })
                .collect::<String>()
        );
        let set = crate::io::read_contours("biv.csv", copied.as_bytes()).unwrap();
        let rv = set.warnings_for(Some("RV_ENDO"));
        assert_eq!(rv.len(), 3, "{rv:?}");
        assert!(
            rv.iter().any(|w| w.contains("repeats the points")),
            "{rv:?}"
        );
    }

    fn ring(n: usize, r: f64, repeat_first: bool) -> Vec<Vec3> {
        let mut v: Vec<Vec3> = (0..n)
            .map(|i| {
                let a = i as f64 / n as f64 * std::f64::consts::TAU;
                v3(r * a.cos(), r * a.sin(), 0.0)
            })
            .collect();
        if repeat_first {
            v.push(v[0]);
        }
        v
    }

    #[test]
    fn rings_and_open_curves() {
        let p = polyline_from_run(ring(40, 20.0, false));
        assert!(p.closed);
        assert_eq!(p.points.len(), 40);
        let p = polyline_from_run(ring(40, 20.0, true));
        assert!(p.closed);
        assert_eq!(p.points.len(), 40, "repeated first point dropped");
        // A U: three quarters of the ring, ends ~28 mm apart with 3 mm spacing.
        let u: Vec<Vec3> = ring(40, 20.0, false).into_iter().take(30).collect();
        assert!(!polyline_from_run(u).closed);
        // Three points in a line: the ends are two spacings apart, yet it is no ring.
        let line = vec![v3(0.0, 0.0, 0.0), v3(1.8, 0.0, 0.0), v3(3.7, 0.1, 0.0)];
        assert!(!polyline_from_run(line).closed);
        let triangle = vec![v3(0.0, 0.0, 0.0), v3(2.0, 0.0, 0.0), v3(1.0, 1.7, 0.0)];
        assert!(polyline_from_run(triangle).closed);
    }

    /// A ring traced with uneven steps (SurFCo's run from 0.01 to 1.6 mm, median 0.43) is a ring
    /// whichever point the file starts it at, even right after its widest step; it used to turn
    /// open when the step that closed it was more than twice the median.
    #[test]
    fn a_ring_with_uneven_steps_is_closed_from_any_start() {
        // Equal steps, every tenth 2.6 times as long: a start after a long step leaves a closing
        // gap of more than twice the median step.
        let steps: Vec<f64> = (0..60)
            .map(|i| if i % 10 == 4 { 2.6 } else { 1.0 })
            .collect();
        let total: f64 = steps.iter().sum();
        let pts: Vec<Vec3> = steps
            .iter()
            .scan(0.0, |a, s| {
                let t = *a / total * std::f64::consts::TAU;
                *a += s;
                Some(v3(20.0 * t.cos(), 20.0 * t.sin(), 0.0))
            })
            .collect();
        for start in 0..pts.len() {
            let mut rolled = pts.clone();
            rolled.rotate_left(start);
            assert!(polyline_from_run(rolled).closed, "start {start}");
        }
        // A U stored in two pieces (biv-me's s08 LAX curves): its ends, 25 mm apart, are nearer
        // than the jump between the pieces, yet far beyond any step: open.
        let u: Vec<Vec3> = ring(40, 20.0, false).into_iter().take(32).collect();
        let (a, b) = u.split_at(14);
        let two_pieces: Vec<Vec3> = a
            .iter()
            .copied()
            .chain(b.iter().skip(10).copied())
            .collect();
        assert!(!polyline_from_run(two_pieces).closed);
    }

    /// A ring whose first or last rows (1-3) are damaged values is still a ring, so that they
    /// come straight back to its start and are spikes; a U with a damaged last row, or with a
    /// lone point past a jump, stays open.
    #[test]
    fn a_ring_with_damaged_end_rows_is_still_a_ring() {
        for k in 1..=3 {
            let mut last = ring(40, 20.0, false);
            let n = last.len();
            for p in &mut last[n - k..] {
                *p += v3(60.0, 0.0, 0.0);
            }
            let p = polyline_from_run(last);
            assert!(p.closed, "last {k} rows out");
            assert_eq!(p.points.len(), 40);
            let spikes = crate::contours::clean::despike(&p).1;
            assert_eq!(spikes.iter().map(|s| s.len).sum::<usize>(), k, "{spikes:?}");
            let mut first = ring(40, 20.0, false);
            for p in &mut first[..k] {
                *p += v3(0.0, 0.0, 45.0);
            }
            let p = polyline_from_run(first);
            assert!(p.closed, "first {k} rows out");
            let spikes = crate::contours::clean::despike(&p).1;
            assert_eq!(spikes.iter().map(|s| s.len).sum::<usize>(), k, "{spikes:?}");
        }
        // Four rows out: more than damaged values; the curve stays open, as before.
        let mut four = ring(40, 20.0, false);
        for p in &mut four[36..] {
            *p += v3(60.0, 0.0, 0.0);
        }
        assert!(!polyline_from_run(four).closed);
        // A U with a damaged last row: without it the ends are still 28 mm apart.
        let mut u: Vec<Vec3> = ring(40, 20.0, false).into_iter().take(30).collect();
        u.push(v3(80.0, 0.0, 0.0));
        assert!(!polyline_from_run(u).closed);
        // A last row near the ring's own start but not entered by a jump is the ring's own.
        let mut near = ring(40, 20.0, false);
        near.push(v3(22.0, 1.0, 0.0));
        assert!(polyline_from_run(near).closed);
    }

    #[test]
    fn reappearing_id_is_a_new_piece() {
        let mut b = ContourBuilder::new();
        for (i, id) in ["a", "a", "b", "a", "a"].iter().enumerate() {
            b.push(id, None, v3(i as f64 * 10.0, 0.0, 0.0), i + 2)
                .unwrap();
        }
        let set = b.finish().unwrap();
        assert_eq!(set.contours.len(), 2);
        assert_eq!(set.contours[0].pieces.len(), 2);
        assert_eq!(set.contours[0].point_count(), 4);
        assert_eq!(set.contours[0].first_line, 2);
        assert_eq!(set.contours[1].first_line, 4);
    }

    #[test]
    fn point_limit_is_refused_with_the_limit() {
        let mut b = ContourBuilder::new();
        let mut result = Ok(());
        for i in 0..=MAX_POINTS {
            result = b.push("a", None, v3(i as f64, 0.0, 0.0), i + 2);
            if result.is_err() {
                break;
            }
        }
        let e = result.unwrap_err();
        assert_eq!(e.line(), Some(MAX_POINTS + 2));
        assert!(e.to_string().contains("2000000"), "{e}");
    }

    #[test]
    fn duplicates_are_reported() {
        let mut b = ContourBuilder::new();
        for (k, id) in ["a", "b", "c"].iter().enumerate() {
            for i in 0..4 {
                let z = if k == 2 { 5.0 } else { 0.0 };
                b.push(id, None, v3(10.0 * i as f64, 3.0, z), 2 + 4 * k + i)
                    .unwrap();
            }
        }
        let set = b.finish().unwrap();
        assert_eq!(
            set.warnings,
            vec!["contour \"b\" (line 6) repeats the points of contour \"a\" (line 2)"]
        );
    }

    #[test]
    fn one_name_in_two_surfaces_is_two_contours_and_units() {
        // Slices numbered per surface: "1" of LV_ENDO and "1" of LV_EPI are two contours, each
        // named after its surface; "2" (one surface only) keeps its name.
        let mut b = ContourBuilder::new();
        for (k, (id, s)) in [
            ("1", "LV_ENDO"),
            ("2", "LV_ENDO"),
            ("1", "LV_EPI"),
            ("1", "LV_ENDO"),
        ]
        .iter()
        .enumerate()
        {
            for i in 0..3 {
                // All in one plane (z = 0): a name met again on another plane would be split.
                let p = v3(10.0 * i as f64 + 40.0 * k as f64, 7.0 * (i * i) as f64, 0.0);
                b.push(id, Some(s), p, 3 * k + i + 2).unwrap();
            }
        }
        let set = b.finish().unwrap();
        let names: Vec<(&str, usize, usize)> = set
            .contours
            .iter()
            .map(|c| (c.id.as_str(), c.pieces.len(), c.first_line))
            .collect();
        assert_eq!(
            names,
            [("1 LV_ENDO", 2, 2), ("2", 1, 5), ("1 LV_EPI", 1, 8)]
        );
        let mut b = ContourBuilder::new();
        b.push("a", None, v3(0.0, 0.0, 0.0), 2).unwrap();
        b.push("a", None, v3(0.05, 0.02, 0.0), 3).unwrap();
        // A third point: lone points and two-point segments say nothing about units.
        b.push("a", None, v3(0.02, 0.04, 0.0), 4).unwrap();
        let set = b.finish().unwrap();
        assert!(set.warnings[0].starts_with("coordinates span 0.0500; expected mm"));
    }
}
