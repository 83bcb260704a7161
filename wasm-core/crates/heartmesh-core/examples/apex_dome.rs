//! Developer tool (session 14 study, docs/VALIDATION.md "Session 14: a dome model for the apex
//! floor"): how close do the dome models put the apex of a short-axis-only stack? Slices each
//! truth short-axis only (no long-axis view) at 7-14 mm spacing, builds the pipeline's own tube
//! rings from the contours, and prints, per stack, how far each model's predicted tip lies past
//! the truth's lowest point along the stack's axis (mm; positive: past the truth, negative: short
//! of it), then the distribution of each over all stacks. Columns: the two-ring paraboloid
//! (session 13); `pipeline::dome::tip_depth` on the 3, 4 and 5 most apical rings (the shallower
//! of the paraboloid and the quadric fitted to them) and the shallower of the 3- and 4-ring
//! ones; "floor": what `pipeline::apex_floor::taper` places (4 rings, guards included; NaN: no
//! floor); and, for comparison only, a three-ring power law A ~ (h - h_tip)^p.
//! With `--misaligned N`, each stack is drawn N times instead with 2 mm / 2 deg breath-hold
//! misalignment (seeds 1..N; the shift has a through-plane part, which moves the sections'
//! heights against the slice positions the models see).
//! `cargo run --release --example apex_dome -- [--misaligned N] [TRUTH.obj | parametric-lv |
//! RV.obj@LV.obj | FREEWALL.obj+SEPTUM.obj@LV.obj]...`
use heartmesh_core::contours::axis::analyse;
use heartmesh_core::contours::rings::tube_rings;
use heartmesh_core::io;
use heartmesh_core::pipeline::apex_floor::{apical_sections, taper};
use heartmesh_core::pipeline::dome::{paraboloid_depth, tip_depth, Section};
use heartmesh_core::sim::cavity::rv_cavity;
use heartmesh_core::sim::experiment_design::Subject;
use heartmesh_core::sim::planes::anatomical_axis;
use heartmesh_core::sim::repair::{orient_consistently, weld};
use heartmesh_core::sim::shapes::ParametricLv;
use heartmesh_core::sim::{simulate, AcquisitionSpec, Misalignment, SaxStack};
use heartmesh_core::{Params, Reconstruction, TriMesh};

type Res<T> = Result<T, Box<dyn std::error::Error>>;

fn read(path: &str) -> Res<TriMesh> {
    let bytes = std::fs::read(path)?;
    let data = io::read_mesh(path, &bytes)?;
    Ok(orient_consistently(&weld(&data.mesh, 1e-6).0).0)
}

/// A truth and how to plan its stack: `parametric-lv`, an LV file, or an RV as the experiments
/// take it (`RV@LV` or `FREEWALL+SEPTUM@LV`: planned on the LV's anatomical axis).
fn truth(arg: &str) -> Res<(TriMesh, AcquisitionSpec)> {
    if arg == "parametric-lv" {
        return Ok((ParametricLv::bulged_truth()?, AcquisitionSpec::default()));
    }
    let Some((shape, lv)) = arg.split_once('@') else {
        return Ok((read(arg)?, AcquisitionSpec::default()));
    };
    let mesh = match shape.split_once('+') {
        Some((wall, septum)) => rv_cavity(&read(wall)?, &read(septum)?, 40.0)?,
        None => read(shape)?,
    };
    let axis = anatomical_axis(&read(lv)?, AcquisitionSpec::default().join_gap_mm)?;
    let spec = Subject::planned_on("rv", mesh.clone(), axis)?.base;
    Ok((mesh, spec))
}

/// Depth below the first section where A = k (h + t)^p through three sections: the t > 0 at
/// which the exponents from sections (1, 2) and (1, 3) agree, by bisection on a log scale; None
/// when no such t lies within 1e-3 .. 1e3 mm.
fn power_law_depth(s: &[Section]) -> Option<f64> {
    let [a, b, c] = [s.first()?, s.get(1)?, s.get(2)?];
    let f = |t: f64| {
        (b.area / a.area).ln() * ((c.height + t) / t).ln()
            - (c.area / a.area).ln() * ((b.height + t) / t).ln()
    };
    let (mut lo, mut hi) = (1e-3f64, 1e3f64);
    if f(lo).signum() == f(hi).signum() {
        return None;
    }
    for _ in 0..200 {
        let mid = (lo * hi).sqrt();
        if f(mid).signum() == f(lo).signum() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some((lo * hi).sqrt())
}

/// The model's rule on the first `n` sections: the shallower of the two-ring paraboloid and the
/// quadric fitted to the `n` sections (`pipeline::dome::tip_depth`), without the floor's guards.
fn model_depth(s: &[Section], n: usize) -> Option<f64> {
    tip_depth(s.get(..n)?).map(|(d, _)| d)
}

fn stats(name: &str, errs: &[f64]) {
    let mut e: Vec<f64> = errs.iter().copied().filter(|x| x.is_finite()).collect();
    e.sort_by(f64::total_cmp);
    let mut a: Vec<f64> = e.iter().map(|x| x.abs()).collect();
    a.sort_by(f64::total_cmp);
    let q = |v: &[f64], f: f64| v[((v.len() - 1) as f64 * f).round() as usize];
    if e.is_empty() {
        println!("{name}: no predictions");
        return;
    }
    let worst = e.iter().copied().max_by(|x, y| x.abs().total_cmp(&y.abs()));
    println!(
        "{name:>10}: n {:2}  median {:+.2}  |.| median {:.2} p90 {:.2}  worst {:+.2}  \
         >2 short {:2}  >2 past {:2}  min {:+.2} max {:+.2}",
        e.len(),
        q(&e, 0.5),
        q(&a, 0.5),
        q(&a, 0.9),
        worst.unwrap_or(f64::NAN),
        e.iter().filter(|x| **x < -2.0).count(),
        e.iter().filter(|x| **x > 2.0).count(),
        e[0],
        e[e.len() - 1],
    );
}

fn main() -> Res<()> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut draws: Vec<Option<u64>> = vec![None];
    if args.first().map(String::as_str) == Some("--misaligned") {
        let n: u64 = args.get(1).ok_or("--misaligned N")?.parse()?;
        draws = (1..=n).map(Some).collect();
        args.drain(..2);
    }
    let names = [
        "paraboloid",
        "quadric 3",
        "quadric 4",
        "quadric 5",
        "min(3,4)",
        "floor",
        "power law",
    ];
    let mut errs: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    println!("truth spacing seed below_ring {}", names.join(" "));
    for arg in &args {
        let (mesh, base) = truth(arg)?;
        for (spacing, draw) in (7..=14).flat_map(|s| draws.iter().map(move |d| (s, *d))) {
            let spec = AcquisitionSpec {
                sax: SaxStack::SpacingMm(spacing as f64),
                lax_count: 0,
                misalignment: draw.map(|_| Misalignment {
                    shift_mm: 2.0,
                    tilt_deg: 2.0,
                }),
                seed: draw.unwrap_or(1),
                ..base.clone()
            };
            let acq = simulate(&mesh, &spec)?;
            let rec = Reconstruction::new(&acq.contours, Params::default())?;
            let layout = analyse(rec.contours())?;
            let slices: Vec<Vec<usize>> =
                layout.slices.iter().map(|s| s.contours.clone()).collect();
            let rings = tube_rings(rec.contours(), &slices, &layout.axis, 50);
            let axis = layout.axis;
            let low = mesh
                .positions
                .iter()
                .map(|p| p.dot(&axis))
                .fold(f64::INFINITY, f64::min);
            let ring_h = rings[0].iter().map(|p| p.dot(&axis)).sum::<f64>() / 50.0;
            let truth_depth = ring_h - low;
            let s = apical_sections(&rings, &axis, 5).ok_or("no sections")?;
            let past = |d: Option<f64>| d.map_or(f64::NAN, |d| d - truth_depth);
            // Past the truth: the predicted depth beyond the truth's. "floor": what
            // `apex_floor::taper` places, guards included (NaN: no floor).
            let floor = taper(&rings, &axis).map(|t| ring_h - t.tip.dot(&axis));
            let row = [
                past(s.get(1).and_then(|b| paraboloid_depth(&s[0], b))),
                past(model_depth(&s, 3)),
                past(model_depth(&s, 4)),
                past(model_depth(&s, 5)),
                past(
                    model_depth(&s, 3)
                        .zip(model_depth(&s, 4))
                        .map(|(a, b)| a.min(b)),
                ),
                past(floor),
                past(power_law_depth(&s)),
            ];
            let name = std::path::Path::new(arg.split(['@', '+']).next().unwrap_or(arg))
                .file_stem()
                .and_then(|n| n.to_str())
                .unwrap_or(arg);
            let cells: Vec<String> = row.iter().map(|e| format!("{e:+.2}")).collect();
            println!(
                "{name} {spacing} {} {truth_depth:.2} {}",
                draw.unwrap_or(0),
                cells.join(" ")
            );
            for (list, e) in errs.iter_mut().zip(row) {
                list.push(e);
            }
        }
    }
    for (name, list) in names.iter().zip(&errs) {
        stats(name, list);
    }
    Ok(())
}
