//! End caps (`Params::end_caps`, pipeline/ends.rs; docs/VALIDATION.md "Session 10: closing open
//! ends"): at an end no curve closes, synthetic lid points stop the mesh at the data instead of
//! letting it run on past it. The phantom is scripts/phantoms.py's `ell-lax-top`: a prolate
//! half-ellipsoid (radius 25 mm, half-length 60 mm) cut at its equator, short-axis rings every
//! 8 mm up to the cut and two long-axis curves through the apex that end exactly in the top plane.
//! Analytic volume 2/3 pi a^2 c = 78.54 ml. Measured values are in the comments.

mod common;

use common::{check_closed_manifold_outward, contour_to_mesh_of, mean};
use heartmesh_core::pipeline::Reconstruction;
use heartmesh_core::{io, EndCapMode, Params};
use std::f64::consts::{PI, TAU};

const A: f64 = 25.0;
const C: f64 = 60.0;

fn half_ellipsoid_csv(lax: bool) -> String {
    let mut csv = String::from("contour,x,y,z,surface\n");
    for (k, z) in [-48.0f64, -40.0, -32.0, -24.0, -16.0, -8.0, 0.0]
        .iter()
        .enumerate()
    {
        let r = A * (1.0 - (z / C) * (z / C)).sqrt();
        for i in 0..60 {
            let t = TAU * i as f64 / 60.0;
            csv += &format!("s{k},{},{},{z},LV_ENDO\n", r * t.cos(), r * t.sin());
        }
    }
    if lax {
        for (k, phi) in [0.3f64, 1.9].iter().enumerate() {
            // From the top plane on one side, through the apex, to the top plane on the other.
            for i in 0..=80 {
                let t = PI * (0.5 + i as f64 / 80.0);
                let (u, z) = (A * t.sin(), C * t.cos());
                let z = if z.abs() < 1e-9 { 0.0 } else { z };
                csv += &format!("l{k},{},{},{z},LV_ENDO\n", u * phi.cos(), u * phi.sin());
            }
        }
    }
    csv
}

struct Outcome {
    base_mm: f64,
    apex_mm: f64,
    ml: f64,
    c2m: f64,
    base_capped: bool,
    apex_capped: bool,
    points: usize,
}

fn run(lax: bool, mode: EndCapMode) -> Outcome {
    run_with(lax, mode, Params::default().apex_floor)
}

/// `run` with the apex floor on or off (`Params::apex_floor`, the default since session 14).
fn run_with(lax: bool, mode: EndCapMode, apex_floor: bool) -> Outcome {
    let set = io::read_contours("phantom.csv", half_ellipsoid_csv(lax).as_bytes())
        .unwrap_or_else(|e| panic!("read: {e}"));
    let params = Params {
        end_caps: mode,
        apex_floor,
        ..Params::default()
    };
    let mut rec = Reconstruction::new(&set, params).unwrap_or_else(|e| panic!("new: {e}"));
    rec.run().unwrap_or_else(|e| panic!("run: {e}"));
    check_closed_manifold_outward(rec.mesh()).unwrap_or_else(|e| panic!("mesh: {e}"));
    let past = rec.past_data().unwrap_or_else(|| panic!("no extent"));
    let caps = rec.end_caps();
    assert_eq!(caps.mode, mode.name());
    assert_eq!(caps.points, rec.end_cap_points().len());
    // The lid points are not data: the contour distances count exactly the contour points.
    let d = rec.contour_distances();
    assert_eq!(
        d.overall.count,
        rec.contours()
            .iter()
            .map(|c| c.point_count())
            .sum::<usize>()
    );
    let out = Outcome {
        base_mm: past.base_mm,
        apex_mm: past.apex_mm,
        ml: rec.mesh().volume_ml(),
        c2m: mean(&contour_to_mesh_of(rec.contours(), rec.mesh())),
        base_capped: caps.base,
        apex_capped: caps.apex,
        points: caps.points,
    };
    eprintln!(
        "lax {lax} {}: past base {:+.2} apex {:+.2} mm, {:.2} ml, c2m {:.4} mm, caps {}/{}/{}",
        mode.name(),
        out.base_mm,
        out.apex_mm,
        out.ml,
        out.c2m,
        out.base_capped,
        out.apex_capped,
        out.points
    );
    out
}

const ANALYTIC_ML: f64 = 2.0 / 3.0 * PI * A * A * C / 1000.0;

/// The curves close the apex, not the top: only the top is capped, and the mesh stops there
/// (measured +1.00 mm, 79.25 ml, 37 lid points, one-sided lid; without caps +11.51 mm, 94.10 ml).
#[test]
fn capped_top_stops_at_the_data() {
    let on = run(true, EndCapMode::Auto);
    assert!(on.base_capped && !on.apex_capped && on.points > 0);
    assert!(on.base_mm < 0.1 * A, "past the top: {} mm", on.base_mm);
    assert!(on.apex_mm.abs() < 0.5, "past the apex: {} mm", on.apex_mm);
    assert!(
        (on.ml / ANALYTIC_ML - 1.0).abs() < 0.04,
        "{} ml vs {ANALYTIC_ML} ml",
        on.ml
    );
    assert!(on.c2m < 0.1, "contour-to-mesh {} mm", on.c2m);
    // Off: the paper's method, running on past the top (the figure the caps remove).
    let off = run(true, EndCapMode::Off);
    assert!(!off.base_capped && !off.apex_capped && off.points == 0);
    assert!(
        off.base_mm > 0.3 * A,
        "off: past the top {} mm",
        off.base_mm
    );
    assert!(off.ml > 1.15 * ANALYTIC_ML, "off: {} ml", off.ml);
}

/// Short-axis rings only (docs/VALIDATION.md "Session 12: end caps where no long-axis curve
/// reaches"): no curve reaches either end. Without the apex floor (`apex_floor: false`, the
/// default before session 14) the apex gets no lid points and is extrapolated as the paper does
/// (the true apex lies 12 mm below the lowest ring; measured +8.55 mm); the base a ceiling one
/// 8 mm slice spacing beyond the top ring (measured +8.27 mm past the data, 89.67 ml, 9 lid
/// points; off: +11.32 / +8.41 mm, 92.78 ml). The volume lies between the shape's below its top ring
/// (78.54 ml) and that plus the ceiling's slab (pi a^2 x 8 mm: 94.25 ml). (Session 11 capped both
/// ends at their rings: 76.40 ml, +1.50 / +1.12 mm.) At the defaults the apex floor adds one
/// point at the dome's tip, which is exact for an ellipsoid: see `sax_only_floors_the_apex`.
#[test]
fn sax_only_caps_the_base_at_the_next_slice() {
    let on = run_with(false, EndCapMode::Auto, false);
    assert!(on.base_capped && !on.apex_capped && on.points > 0);
    assert!(
        (on.base_mm - 8.0).abs() < 1.0,
        "past the top: {} mm",
        on.base_mm
    );
    assert!(
        on.apex_mm > 0.2 * A && on.apex_mm < 12.0 + 0.1 * A,
        "past the apex: {} mm",
        on.apex_mm
    );
    let slab = ANALYTIC_ML + PI * A * A * 8.0 / 1000.0;
    assert!(
        on.ml > ANALYTIC_ML && on.ml < slab,
        "{} ml, not between {ANALYTIC_ML} and {slab} ml",
        on.ml
    );
    assert!(on.c2m < 0.1, "contour-to-mesh {} mm", on.c2m);
    let off = run(false, EndCapMode::Off);
    assert!(
        off.base_mm > on.base_mm + 0.1 * A,
        "off {} mm past the top, auto {} mm",
        off.base_mm,
        on.base_mm
    );
}

/// The same short-axis-only stack at the defaults (the apex floor on since session 14): the
/// base gets the same ceiling, the apex one floor point at the dome's tip, and the mesh ends at
/// the analytic apex, 12 mm below the lowest ring (phantoms: 11.94 mm, 90.42 ml), where the
/// extrapolation stopped at +8.55. Asserted: within 0.5 mm of 12, one point more than without.
/// With end caps off there is no floor (it is a lid point).
#[test]
fn sax_only_floors_the_apex() {
    assert!(Params::default().apex_floor);
    let on = run(false, EndCapMode::Auto);
    let without = run_with(false, EndCapMode::Auto, false);
    assert!(on.base_capped && on.apex_capped);
    assert_eq!(on.points, without.points + 1);
    assert!(
        (on.apex_mm - 12.0).abs() < 0.5,
        "past the apex: {} mm",
        on.apex_mm
    );
    assert!(
        (on.base_mm - 8.0).abs() < 1.0,
        "past the top: {} mm",
        on.base_mm
    );
    let slab = ANALYTIC_ML + PI * A * A * 8.0 / 1000.0;
    assert!(on.ml > ANALYTIC_ML && on.ml < slab, "{} ml", on.ml);
    let off = run(false, EndCapMode::Off);
    assert!(!off.apex_capped && off.points == 0);
}

/// A cavity of radius A, a half-ellipsoid below z = 0 and a cylinder above it, short-axis rings
/// every 10 mm from z = -50 up to the basal ring at z = 20, and two long-axis views (at 0.3 and
/// 1.9 rad) whose ends stop at the heights `ends` (the first end on the view's +side).
fn cylinder_top_csv(ends: [(f64, f64); 2]) -> String {
    let wall = |z: f64| {
        if z >= 0.0 {
            A
        } else {
            A * (1.0 - (z / C) * (z / C)).max(0.0).sqrt()
        }
    };
    let mut csv = String::from("contour,x,y,z,surface\n");
    for (k, z) in (-5..=2).map(|k| 10.0 * k as f64).enumerate() {
        for i in 0..60 {
            let t = TAU * i as f64 / 60.0;
            let r = wall(z);
            csv += &format!("s{k},{},{},{z},LV_ENDO\n", r * t.cos(), r * t.sin());
        }
    }
    // One side of a view, top down to the apex, as (signed in-plane offset, height).
    let side = |s: f64, top: f64| -> Vec<(f64, f64)> {
        let straight = (0..top.ceil() as usize).map(move |j| (s * A, top - j as f64));
        let dome = (0..=90).map(move |i| {
            let a = PI / 2.0 * i as f64 / 90.0;
            (s * A * a.cos(), -C * a.sin())
        });
        straight.filter(|(_, z)| *z > 0.0).chain(dome).collect()
    };
    for (k, (phi, (up, down))) in [0.3f64, 1.9].iter().zip(ends).enumerate() {
        let mut back = side(-1.0, down);
        back.reverse();
        for (u, z) in side(1.0, up).into_iter().chain(back.into_iter().skip(1)) {
            csv += &format!("l{k},{},{},{z},LV_ENDO\n", u * phi.cos(), u * phi.sin());
        }
    }
    csv
}

/// One view drawn 3 mm short of the basal ring (z = 17) on one side, 8 mm past it on the other,
/// the other view 1 mm past it: the tips' plane falls inside the ring's plane on the short side,
/// where the ring says the cavity runs on. The lid is floored two tolerances outside the ring's
/// plane there, so the mesh stays beyond the disc the ring bounds. Measured: lowest point of the
/// top within 0.7 A of the axis 21.00 mm; with the floor in the ring's plane (sessions 10-17)
/// 19.92, 0.08 mm inside the ring's plane, which a comparison clipped there keeps as a piece of
/// lid (a held-out acquisition's Hausdorff 17.4 mm, docs/VALIDATION.md "Session 18").
#[test]
fn a_lid_tilted_into_the_basal_ring_stays_beyond_it() {
    let csv = cylinder_top_csv([(21.0, 21.0), (28.0, 17.0)]);
    let set = io::read_contours("cylinder.csv", csv.as_bytes()).unwrap();
    let mut rec = Reconstruction::new(&set, Params::default()).unwrap();
    rec.run().unwrap();
    check_closed_manifold_outward(rec.mesh()).unwrap_or_else(|e| panic!("mesh: {e}"));
    assert!(rec.end_caps().base);
    let lowest = rec
        .mesh()
        .positions
        .iter()
        .filter(|v| v.x.hypot(v.y) < 0.7 * A && v.z > 5.0)
        .map(|v| v.z)
        .fold(f64::INFINITY, f64::min);
    eprintln!("lowest point of the top within 0.7 A: {lowest:.3} mm (basal ring at 20)");
    assert!(lowest > 20.0 && lowest < 22.0, "{lowest}");
    let c2m = mean(&contour_to_mesh_of(rec.contours(), rec.mesh()));
    assert!(c2m < 0.15, "contour-to-mesh {c2m} mm");
}
