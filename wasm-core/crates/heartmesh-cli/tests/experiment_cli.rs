//! Integration tests of `heartmesh experiment` (issue 5 item 4): each paper experiment on the
//! built-in parametric LV with reduced settings (few iterations, few runs), asserting on the
//! numbers in the CSV and on the shape of the SVG; and the usage errors (exit 2, one line).

use std::collections::HashMap;
mod common;
use common::{bin, run, scratch};
use std::path::Path;

/// The CSV as one map per row (column name -> text).
fn read_csv(path: &Path) -> Vec<HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    lines
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            assert_eq!(cells.len(), header.len(), "ragged row {l}");
            header
                .iter()
                .cloned()
                .zip(cells.iter().map(|c| c.to_string()))
                .collect()
        })
        .collect()
}

fn num(row: &HashMap<String, String>, col: &str) -> f64 {
    row[col]
        .parse()
        .unwrap_or_else(|_| panic!("{col} = {:?}", row[col]))
}

/// Average of the two directed means.
fn mean(row: &HashMap<String, String>) -> f64 {
    0.5 * (num(row, "mesh_to_truth_mean") + num(row, "truth_to_mesh_mean"))
}

fn experiment(kind: &str, dir: &Path, extra: &[&str]) -> Vec<HashMap<String, String>> {
    let out = dir.to_str().unwrap();
    let mut args = vec!["experiment", kind, "parametric-lv", "-o", out, "--quiet"];
    args.extend_from_slice(extra);
    let (code, stdout, err) = run(bin().args(&args));
    assert_eq!(code, 0, "{err}");
    assert!(stdout.is_empty(), "--quiet printed {stdout}");
    let svg = std::fs::read_to_string(dir.join(format!("{kind}.svg"))).unwrap();
    assert!(svg.starts_with("<?xml") && svg.trim_end().ends_with("</svg>"));
    read_csv(&dir.join(format!("{kind}.csv")))
}

#[test]
fn sax_count_more_slices_less_error() {
    let d = scratch("sax");
    let rows = experiment(
        "sax-count",
        &d,
        &[
            "--from",
            "2",
            "--to",
            "8",
            "--step",
            "3",
            "--iterations",
            "60",
        ],
    );
    assert_eq!(rows.len(), 3);
    let sax: Vec<f64> = rows.iter().map(|r| num(r, "sax")).collect();
    assert_eq!(sax, [2.0, 5.0, 8.0]);
    for r in &rows {
        assert_eq!(r["shape"], "parametric-lv");
        assert_eq!(num(r, "sax_contours"), num(r, "sax"));
        assert_eq!(num(r, "lax_contours"), 3.0);
        assert_eq!(num(r, "iterations"), 60.0);
        assert!(r["error"].is_empty());
    }
    let (m2, m8) = (mean(&rows[0]), mean(&rows[2]));
    eprintln!(
        "EXPERIMENT sax-count parametric LV: mean {m2:.3} mm (2 SAX) -> {:.3} (5) -> {m8:.3} (8)",
        mean(&rows[1])
    );
    // Two slices leave the bulge and the apex to the long axes alone: ~0.3 mm at 60 iterations;
    // eight: ~0.07 mm (0.288 -> 0.068 and 0.267 -> 0.070 with the two tube seams of session 6).
    assert!(m8 < 0.35 * m2, "8 SAX {m8:.3} mm vs 2 SAX {m2:.3} mm");
    assert!(m8 < 0.2, "8 SAX mean {m8:.3} mm");
    assert!(num(&rows[2], "hausdorff") < num(&rows[0], "hausdorff"));
    let svg = std::fs::read_to_string(d.join("sax-count.svg")).unwrap();
    // Two panels (mean, Hausdorff), one line each for the one shape.
    assert_eq!(svg.matches("<polyline").count(), 2);
    assert_eq!(svg.matches("<circle").count(), 6);
}

#[test]
fn lax_count_rows_and_counts() {
    let d = scratch("lax");
    let out = d.to_str().unwrap();
    let (code, _, err) = run(bin().args([
        "experiment",
        "lax-count",
        "parametric-lv",
        "-o",
        out,
        "--from",
        "0",
        "--to",
        "3",
        "--sax",
        "3",
        "--iterations",
        "40",
        "--tag",
        "t1",
        "--quiet",
    ]));
    assert_eq!(code, 0, "{err}");
    assert!(d.join("lax-count-t1.svg").exists());
    let all = read_csv(&d.join("lax-count-t1.csv"));
    assert_eq!(all.len(), 4);
    // Parallel SAX only: the lids sit at the end rings' centroids and the apex dome is guessed.
    let m0 = mean(&all[0]);
    let rows = &all[1..];
    assert_eq!(rows.len(), 3);
    for (k, r) in rows.iter().enumerate() {
        assert_eq!(num(r, "lax"), (k + 1) as f64);
        assert_eq!(num(r, "lax_contours"), (k + 1) as f64);
        assert_eq!(num(r, "sax_contours"), 3.0);
    }
    let (m1, m3) = (mean(&rows[0]), mean(&rows[2]));
    eprintln!(
        "EXPERIMENT lax-count parametric LV, 3 SAX: mean {m0:.3} mm (0 LAX) -> {m1:.3} (1) -> \
         {m3:.3} (3)"
    );
    assert!(m1 < m0, "1 LAX {m1:.3} mm vs 0 LAX {m0:.3} mm");
    assert!(m3 < m1, "3 LAX {m3:.3} mm vs 1 LAX {m1:.3} mm");
}

#[test]
fn misalignment_raises_the_error() {
    let d = scratch("mis");
    let rows = experiment(
        "misalignment",
        &d,
        &["--levels", "0,3:3", "--seeds", "2", "--iterations", "30"],
    );
    // The aligned level runs once, the misaligned one per seed.
    assert_eq!(rows.len(), 3);
    assert_eq!(num(&rows[0], "shift_mm"), 0.0);
    assert_eq!(num(&rows[2], "seed"), 2.0);
    // Different seeds, different acquisitions.
    assert_ne!(
        rows[1]["contour_to_mesh_max"],
        rows[2]["contour_to_mesh_max"]
    );
    for r in &rows[1..] {
        eprintln!(
            "EXPERIMENT misalignment 3 mm / 3 deg seed {}: contour->mesh mean {:.3} mm (aligned \
             {:.3}), mean to truth {:.3} mm (aligned {:.3})",
            r["seed"],
            num(r, "contour_to_mesh_mean"),
            num(&rows[0], "contour_to_mesh_mean"),
            mean(r),
            mean(&rows[0])
        );
        // Contours that disagree cannot all be met, and the truth is missed by about the shift.
        assert!(num(r, "contour_to_mesh_mean") > 2.0 * num(&rows[0], "contour_to_mesh_mean"));
        assert!(mean(r) > 2.0 * mean(&rows[0]));
        assert!(mean(r) < 3.0, "misaligned mean {:.3} mm", mean(r));
    }
}

#[test]
fn population_of_posed_parametric_shapes() {
    let d = scratch("pop");
    let rows = experiment(
        "population",
        &d,
        &["--count", "3", "--seed", "5", "--iterations", "40"],
    );
    // Three shapes, each aligned and at 2 mm / 2 degrees, misaligned with seed 5 + k.
    assert_eq!(rows.len(), 6);
    assert_eq!(rows[0]["shape"], "p00-parametric");
    assert_eq!(rows[5]["shape"], "p02-parametric");
    assert_eq!(num(&rows[3], "shift_mm"), 2.0);
    assert_eq!(num(&rows[3], "seed"), 6.0);
    let shapes = std::fs::read_to_string(d.join("population-shapes.csv")).unwrap();
    let lines: Vec<&str> = shapes.lines().collect();
    assert_eq!(lines.len(), 4, "{shapes}");
    assert!(lines[0].starts_with("shape,base,scale_x"));
    for r in &rows {
        eprintln!(
            "EXPERIMENT population {} shift {}: mean {:.3} mm, Hausdorff {:.2} mm, folds {}",
            r["shape"],
            r["shift_mm"],
            mean(r),
            num(r, "hausdorff"),
            r["folded_edges"]
        );
        assert_eq!(r["closed_manifold_outward"], "1");
        assert_eq!(r["folded_edges"], "0");
        // 40 iterations, posed hundreds of mm from the origin: still well under a millimetre
        // aligned, and about the misalignment when misaligned.
        let limit = if num(r, "shift_mm") == 0.0 { 0.2 } else { 1.5 };
        assert!(mean(r) < limit, "{}: mean {:.3} mm", r["shape"], mean(r));
    }
}

/// `--lax 0` (misalignment and population): short-axis slices only, the arm of the paired end-cap
/// gate where no long-axis curve reaches an end (docs/VALIDATION.md, session 12). The parametric
/// LV's 8 slices are 10 mm apart: with `--end-caps auto` the base gets a ceiling at the next slice
/// position (measured 10.52 mm past the basal slice; off runs on to 10.62 mm; session 11's lid at
/// the ring stopped it within ~2 mm) and the apex, which without the apex floor gets no lid, is
/// extrapolated as off does (5.388 / 5.389 mm; `--no-apex-floor`, since the floor is the default:
/// see `apex_floor_on_a_simulated_short_axis_only_stack`).
#[test]
fn lax_zero_gives_short_axis_only_stacks() {
    let mut past = Vec::new();
    for caps in ["off", "auto"] {
        let d = scratch(&format!("lax0-{caps}"));
        let rows = experiment(
            "misalignment",
            &d,
            &[
                "--levels",
                "0:0",
                "--seeds",
                "1",
                "--lax",
                "0",
                "--end-caps",
                caps,
                "--no-apex-floor",
            ],
        );
        assert_eq!(rows.len(), 1);
        assert_eq!(
            (
                rows[0]["sax_contours"].as_str(),
                rows[0]["lax_contours"].as_str()
            ),
            ("8", "0")
        );
        past.push((num(&rows[0], "past_base_mm"), num(&rows[0], "past_apex_mm")));
    }
    let ((off_base, off_apex), (auto_base, auto_apex)) = (past[0], past[1]);
    assert!(off_base > 10.0, "off: {off_base} mm past the base");
    assert!(
        auto_base > 8.0 && auto_base < 11.0,
        "auto: {auto_base} mm past the base"
    );
    assert!(
        (auto_apex - off_apex).abs() < 0.1,
        "apex {auto_apex} vs {off_apex} mm"
    );
    // population: every shape gets the override (3 LAX without it).
    let d = scratch("lax0-pop");
    for (extra, lax) in [(&["--lax", "0"][..], "0"), (&[][..], "3")] {
        let mut args = vec!["--count", "2", "--levels", "0:0", "--iterations", "5"];
        args.extend_from_slice(extra);
        let rows = experiment("population", &d, &args);
        assert_eq!(rows.len(), 2);
        assert!(rows.iter().all(|r| r["lax_contours"] == lax), "{rows:?}");
    }
}

/// The apex floor's dome model on a simulated short-axis-only stack (session 14): the built-in
/// parametric LV (a bulged half-spheroid) sliced every 10 mm with no long-axis view, whose apex
/// lies 6.75 mm below the apical slice. With `--no-apex-floor` the paper's extrapolation stops
/// 1.36 mm short of it (as every run did before session 14); at the defaults the floor is on and
/// the mesh ends 0.11 mm short (the session-13 paraboloid: 0.30 mm past), as with `--apex-floor`,
/// still accepted. Asserted: short by more than 1 mm without, within 0.5 mm either way at the
/// defaults, `--apex-floor` the same row.
#[test]
fn apex_floor_on_a_simulated_short_axis_only_stack() {
    let mut error = Vec::new();
    for (name, flag) in [
        ("off", Some("--no-apex-floor")),
        ("default", None),
        ("on", Some("--apex-floor")),
    ] {
        let d = scratch(&format!("apex-floor-sim-{name}"));
        let mut args = vec!["--levels", "0:0", "--seeds", "1", "--lax", "0"];
        args.extend(flag);
        let rows = experiment("misalignment", &d, &args);
        assert_eq!(rows.len(), 1);
        error.push(num(&rows[0], "past_apex_mm") - num(&rows[0], "truth_past_apex_mm"));
    }
    let (plain, floored) = (error[0], error[1]);
    assert_eq!(error[2], floored, "--apex-floor is the default");
    assert!(
        plain < -1.0,
        "the extrapolation stops short: {plain:+.2} mm"
    );
    assert!(
        floored.abs() < 0.5,
        "apex error with the floor: {floored:+.2} mm"
    );
}

#[test]
fn sweep_grid_and_parallel_coordinates() {
    let d = scratch("sweep");
    let rows = experiment(
        "sweep",
        &d,
        &[
            "--lambda",
            "1e3,1e5",
            "--smoothing-iterations",
            "200",
            "--target-reduction",
            "0.72",
            "--attractor-spacing",
            "0,3",
            "--iterations",
            "30",
        ],
    );
    assert_eq!(rows.len(), 4);
    let lambdas: Vec<f64> = rows.iter().map(|r| num(r, "lambda")).collect();
    assert_eq!(lambdas, [1e3, 1e3, 1e5, 1e5]);
    // Low lambda: smooth, near-elliptical shapes that miss the bulge and the apex.
    let (lo, hi) = (mean(&rows[0]), mean(&rows[2]));
    eprintln!("EXPERIMENT sweep parametric LV: mean {lo:.3} mm (lambda 1e3) vs {hi:.3} (1e5)");
    assert!(hi < 0.5 * lo, "lambda 1e5 {hi:.3} mm vs 1e3 {lo:.3} mm");
    let svg = std::fs::read_to_string(d.join("sweep.svg")).unwrap();
    assert_eq!(svg.matches("<polyline").count(), 4);
    for axis in [
        "lambda",
        "attractor_spacing",
        "mean distance (mm)",
        "seconds",
    ] {
        assert!(svg.contains(&format!(">{axis}</text>")), "{axis}");
    }
}

#[test]
fn usage_errors_exit_2_with_one_line() {
    let d = scratch("errors");
    let out = d.to_str().unwrap();
    let missing = d.join("missing.obj");
    let missing = missing.to_str().unwrap();
    // A kind of experiment on the built-in LV into `out`, with `flags`: most cases differ only
    // there.
    let on = |kind: &'static str, flags: &[&'static str]| {
        let mut args = vec!["experiment", kind, "parametric-lv", "-o", out];
        args.extend_from_slice(flags);
        args
    };
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["experiment"], "needs a kind"),
        (on("nonsense", &[]), "unknown experiment"),
        (
            vec!["experiment", "sax-count", "parametric-lv"],
            "-o OUT_DIR",
        ),
        (
            vec!["experiment", "sax-count", "-o", out],
            "at least one TRUTH",
        ),
        (
            on("population", &["--count", "0"]),
            "--count must be at least 1",
        ),
        (on("sax-count", &["--from", "9", "--to", "3"]), "no count"),
        (on("sax-count", &["--from", "1"]), "sax"),
        (
            on("sax-count", &["--levels", "1"]),
            "unknown option --levels",
        ),
        (
            on("misalignment", &["--lax", "9"]),
            "--lax 9: at most 8 long-axis views",
        ),
        (on("lax-count", &["--lax", "0"]), "unknown option --lax"),
        (
            on("misalignment", &["--apex-floor", "--no-apex-floor"]),
            "not both",
        ),
        (on("sweep", &["--lambda", "abc"]), "not a list of numbers"),
        (on("sweep", &["--lambda", "-5"]), "lambda"),
        (on("misalignment", &["--levels", "1:2:3"]), "SHIFT:TILT"),
        (on("lax-count", &["--to", "9"]), "lax"),
        (
            vec!["experiment", "lax-count", missing, "-o", out],
            "missing.obj",
        ),
    ];
    for (args, needle) in cases {
        let (code, _, err) = run(bin().args(&args));
        assert_eq!(code, 2, "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    // Nothing was written by the failed runs.
    assert!(!d.join("sax-count.csv").exists());
}

#[test]
fn smoothing_method_reaches_every_run() {
    // The same acquisition with the remesh smoothing switched: the meshes differ, so the flag
    // reached the runs; an unknown name is a usage error naming the allowed ones.
    let d = scratch("smoothing");
    let row = |method: &str| {
        let extra = [
            "--levels",
            "0:0",
            "--seeds",
            "1",
            "--iterations",
            "40",
            "--smoothing-method",
            method,
            "--tag",
            method,
        ];
        let out = d.to_str().unwrap();
        let mut args = vec!["experiment", "misalignment", "parametric-lv", "-o", out];
        args.extend_from_slice(&["--quiet"]);
        args.extend_from_slice(&extra);
        let (code, _, err) = run(bin().args(&args));
        assert_eq!(code, 0, "{err}");
        let rows = read_csv(&d.join(format!("misalignment-{method}.csv")));
        assert_eq!(rows.len(), 1);
        mean(&rows[0])
    };
    let (a, h) = (row("laplacian-affine"), row("laplacian-hc"));
    eprintln!(
        "EXPERIMENT smoothing method, parametric LV, 40 iterations: mean {a:.4} -> {h:.4} mm"
    );
    assert!(a.is_finite() && h.is_finite() && a != h, "{a} {h}");
    let out = d.to_str().unwrap();
    let (code, _, err) = run(bin().args([
        "experiment",
        "misalignment",
        "parametric-lv",
        "-o",
        out,
        "--smoothing-method",
        "gauss",
    ]));
    assert_eq!(code, 2);
    assert!(err.contains("laplacian-twicing"), "{err}");
}
