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
//! With `--population SEED:COUNT`, the truths are instead the bases of a population drawn as
//! `heartmesh experiment population --seed SEED --count COUNT` draws it (member k from base k mod
//! n, warped and posed at random), each member sliced as that experiment slices it with `--lax 0`:
//! at its base acquisition, aligned and at 2 mm / 2 deg with seed SEED + k.
//!
//! Session 17 ("the apex floor on RV crescents") adds, per stack, intrinsic measures of the
//! apical ring (its thickness t = area / half-perimeter, its length L = half-perimeter, its
//! solidity = area / convex-hull area, the share of its length that curves inward) and candidate
//! depths, each the shallower of session 14's floor ("floor s14": the 4-ring dome on the areas
//! under the floor's guards; NaN where it places nothing) and another model: the same dome
//! (`dome::tip_depth`, 4 rings) on t^2, on L^2 and on L sqrt(A) instead of the area (all equal to
//! the area up to a constant on round rings, so an LV's rings give its dome back), the apical
//! ring's thickness as a cap ("floor^t1"), and the mean of the floor's and the L^2 dome's depths.
//! Since session 17 "floor" (what `apex_floor::taper` places) is "floor^L.sqrtA"
//! (`pipeline::crescent`). Statistics are printed for all stacks, and for the LV and the RV truths
//! (an RV is a truth given as `X@LV`, or a population base planned on an LV).
//! With APEX_DOME_RINGS set, each stack's row is followed by its five most apical rings' height,
//! area, length, thickness and solidity.
//! `cargo run --release --example apex_dome -- [--misaligned N | --population SEED:COUNT]
//! [TRUTH.obj | parametric-lv | RV.obj@LV.obj | FREEWALL.obj+SEPTUM.obj@LV.obj]...`
use heartmesh_core::contours::axis::analyse;
use heartmesh_core::contours::rings::tube_rings;
use heartmesh_core::geometry::Vec3;
use heartmesh_core::io;
use heartmesh_core::pipeline::apex_floor::{apical_sections, taper};
use heartmesh_core::pipeline::dome::{paraboloid_depth, tip_depth, Section};
use heartmesh_core::sim::cavity::rv_cavity;
use heartmesh_core::sim::experiment_design::Subject;
use heartmesh_core::sim::planes::anatomical_axis;
use heartmesh_core::sim::population::{generate, Base, Plan, Source};
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

/// A truth as a population base (`--population`): named after its file (the RV's wall), planned
/// on its own axis or, for `X@LV`, on the LV's.
fn base(arg: &str) -> Res<Base> {
    let name = stem(arg);
    if arg == "parametric-lv" {
        return Ok(Base {
            name,
            source: Source::Parametric,
            plan: Plan::Lv,
        });
    }
    let Some((shape, lv)) = arg.split_once('@') else {
        return Ok(Base {
            name,
            source: Source::Mesh(read(arg)?),
            plan: Plan::Lv,
        });
    };
    let mesh = match shape.split_once('+') {
        Some((wall, septum)) => rv_cavity(&read(wall)?, &read(septum)?, 40.0)?,
        None => read(shape)?,
    };
    Ok(Base {
        name,
        source: Source::Mesh(mesh),
        plan: Plan::Rv { lv: read(lv)? },
    })
}

/// The file stem of a truth argument (the RV's wall for `X+Y@LV`).
fn stem(arg: &str) -> String {
    std::path::Path::new(arg.split(['@', '+']).next().unwrap_or(arg))
        .file_stem()
        .and_then(|n| n.to_str())
        .unwrap_or(arg)
        .to_string()
}

/// Intrinsic measures of one ring, in its plane (normal to the stack's axis).
#[derive(Debug, Clone, Copy)]
struct Shape {
    area: f64,
    /// Half the perimeter: a thin crescent's length, pi r for a circle.
    half_perimeter: f64,
    /// Area over convex-hull area.
    solidity: f64,
    /// Share of the ring's length at vertices that turn inward (against its orientation).
    concave: f64,
}

impl Shape {
    /// Area / half-perimeter: a thin crescent's width, the radius of a circle.
    fn thickness(&self) -> f64 {
        self.area / self.half_perimeter
    }
}

fn shape(ring: &[Vec3], axis: &Vec3) -> Option<Shape> {
    let n = ring.len();
    if n < 3 {
        return None;
    }
    let any = if axis.x.abs() < 0.9 {
        Vec3::x()
    } else {
        Vec3::y()
    };
    let u = axis.cross(&any).normalize();
    let v = axis.cross(&u);
    let pts: Vec<[f64; 2]> = ring.iter().map(|p| [p.dot(&u), p.dot(&v)]).collect();
    let shoelace = |q: &[[f64; 2]]| {
        (0..q.len())
            .map(|i| {
                let (a, b) = (q[i], q[(i + 1) % q.len()]);
                a[0] * b[1] - a[1] * b[0]
            })
            .sum::<f64>()
            * 0.5
    };
    let signed = shoelace(&pts);
    let orient = signed.signum();
    let len = |a: [f64; 2], b: [f64; 2]| (b[0] - a[0]).hypot(b[1] - a[1]);
    let mut perimeter = 0.0;
    let mut concave = 0.0;
    for i in 0..n {
        let (a, b, c) = (pts[(i + n - 1) % n], pts[i], pts[(i + 1) % n]);
        let turn = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
        let half = 0.5 * (len(a, b) + len(b, c));
        perimeter += len(b, c);
        if turn * orient < 0.0 {
            concave += half;
        }
    }
    let hull = convex_hull(&pts);
    Some(Shape {
        area: signed.abs(),
        half_perimeter: 0.5 * perimeter,
        solidity: signed.abs() / shoelace(&hull).abs(),
        concave: concave / perimeter,
    })
}

/// Andrew's monotone chain (counter-clockwise, no repeated end point).
fn convex_hull(pts: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut p = pts.to_vec();
    p.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(2 * p.len());
    for pass in 0..2 {
        let start = hull.len();
        for &q in &p {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
        if pass == 0 {
            p.reverse();
        }
    }
    hull
}

/// The dome model (`dome::tip_depth`) on another quantity of the first `n` rings: the
/// sections' heights with `f` of each ring's shape in place of its area.
fn dome_on(s: &[Section], shapes: &[Shape], n: usize, f: impl Fn(&Shape) -> f64) -> Option<f64> {
    let q: Vec<Section> = s
        .iter()
        .zip(shapes)
        .take(n)
        .map(|(s, sh)| Section {
            height: s.height,
            area: f(sh),
        })
        .collect();
    tip_depth(&q).map(|(d, _)| d)
}

fn stats(name: &str, errs: &[f64]) {
    let mut e: Vec<f64> = errs.iter().copied().filter(|x| x.is_finite()).collect();
    e.sort_by(f64::total_cmp);
    let mut a: Vec<f64> = e.iter().map(|x| x.abs()).collect();
    a.sort_by(f64::total_cmp);
    let q = |v: &[f64], f: f64| v[((v.len() - 1) as f64 * f).round() as usize];
    if e.is_empty() {
        println!("{name:>12}: no predictions");
        return;
    }
    let worst = e.iter().copied().max_by(|x, y| x.abs().total_cmp(&y.abs()));
    println!(
        "{name:>12}: n {:3}  median {:+.2}  |.| median {:.2} p90 {:.2}  worst {:+.2}  \
         >2 short {:3}  >2 past {:3}  min {:+.2} max {:+.2}",
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

/// One stack to slice: its truth, how it is planned and sliced, and its labels.
struct Stack {
    name: String,
    rv: bool,
    mesh: TriMesh,
    spec: AcquisitionSpec,
    label: String,
}

fn stacks(
    args: &[String],
    draws: &[Option<u64>],
    population: Option<(u64, usize)>,
) -> Res<Vec<Stack>> {
    let mut out = Vec::new();
    if let Some((seed, count)) = population {
        let bases = args.iter().map(|a| base(a)).collect::<Res<Vec<_>>>()?;
        for (k, m) in generate(&bases, count, seed)?.into_iter().enumerate() {
            let rv = matches!(bases[k % bases.len()].plan, Plan::Rv { .. });
            for (shift_mm, tilt_deg) in [(0.0, 0.0), (2.0, 2.0)] {
                let spec = AcquisitionSpec {
                    lax_count: 0,
                    misalignment: Some(Misalignment { shift_mm, tilt_deg }),
                    seed: seed.wrapping_add(k as u64),
                    ..m.subject.base.clone()
                };
                out.push(Stack {
                    name: m.subject.name.clone(),
                    rv,
                    mesh: m.subject.mesh.clone(),
                    label: format!("{shift_mm} {}", seed.wrapping_add(k as u64)),
                    spec,
                });
            }
        }
        return Ok(out);
    }
    for arg in args {
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
            out.push(Stack {
                name: stem(arg),
                rv: arg.contains('@'),
                mesh: mesh.clone(),
                label: format!("{spacing} {}", draw.unwrap_or(0)),
                spec,
            });
        }
    }
    Ok(out)
}

fn main() -> Res<()> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut draws: Vec<Option<u64>> = vec![None];
    let mut population = None;
    match args.first().map(String::as_str) {
        Some("--misaligned") => {
            let n: u64 = args.get(1).ok_or("--misaligned N")?.parse()?;
            draws = (1..=n).map(Some).collect();
            args.drain(..2);
        }
        Some("--population") => {
            let v = args.get(1).ok_or("--population SEED:COUNT")?;
            let (s, c) = v.split_once(':').ok_or("--population SEED:COUNT")?;
            population = Some((s.parse()?, c.parse()?));
            args.drain(..2);
        }
        _ => {}
    }
    let names = [
        "paraboloid",
        "quadric 3",
        "quadric 4",
        "quadric 5",
        "min(3,4)",
        "floor",
        "power law",
        "floor s14",
        "dome t^2",
        "dome L^2",
        "floor^t",
        "floor^L",
        "floor^t^L",
        "floor^t1",
        "floor^L.sqrtA",
        "floor^mean(L)",
    ];
    let mut errs: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    let mut is_rv: Vec<bool> = Vec::new();
    println!(
        "truth rv spacing|shift seed below_ring {} t1 truth/t1 floor/t1 solidity1 concave1 concave2",
        names.map(|n| n.replace(' ', "_")).join(" ")
    );
    for st in stacks(&args, &draws, population)? {
        let acq = simulate(&st.mesh, &st.spec)?;
        let rec = Reconstruction::new(&acq.contours, Params::default())?;
        let layout = analyse(rec.contours())?;
        let slices: Vec<Vec<usize>> = layout.slices.iter().map(|s| s.contours.clone()).collect();
        let rings = tube_rings(rec.contours(), &slices, &layout.axis, 50);
        let axis = layout.axis;
        let low = st
            .mesh
            .positions
            .iter()
            .map(|p| p.dot(&axis))
            .fold(f64::INFINITY, f64::min);
        let ring_h = rings[0].iter().map(|p| p.dot(&axis)).sum::<f64>() / 50.0;
        let truth_depth = ring_h - low;
        let s = apical_sections(&rings, &axis, 5).ok_or("no sections")?;
        let shapes: Vec<Shape> = rings.iter().filter_map(|r| shape(r, &axis)).collect();
        let past = |d: Option<f64>| d.map_or(f64::NAN, |d| d - truth_depth);
        // Past the truth: the predicted depth beyond the truth's. "floor": what
        // `apex_floor::taper` places, guards included (NaN: no floor).
        let floor = taper(&rings, &axis).map(|t| ring_h - t.tip.dot(&axis));
        let thick = dome_on(&s, &shapes, 4, |sh| sh.thickness().powi(2));
        let length = dome_on(&s, &shapes, 4, |sh| sh.half_perimeter.powi(2));
        // The shallower of the floor and another model; the floor alone where that model has no
        // tip (its quantity does not taper).
        // Session 14's floor: the same guards (a floor exactly where `taper` places one), the
        // dome on the areas of the 4 most apical rings.
        let floor_s14 = floor.and(model_depth(&s, 4).or_else(|| model_depth(&s, s.len())));
        let shallower = |other: Option<f64>| floor_s14.map(|f| other.map_or(f, |o| f.min(o)));
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
            past(floor_s14),
            past(thick),
            past(length),
            past(shallower(thick)),
            past(shallower(length)),
            past(shallower(thick).map(|f| length.map_or(f, |l| f.min(l)))),
            past(shallower(shapes.first().map(Shape::thickness))),
            past(shallower(dome_on(&s, &shapes, 4, |sh| {
                sh.half_perimeter * sh.area.sqrt()
            }))),
            past(shallower(floor_s14.zip(length).map(|(f, l)| 0.5 * (f + l)))),
        ];
        let t1 = shapes.first().map_or(f64::NAN, Shape::thickness);
        let cells: Vec<String> = row.iter().map(|e| format!("{e:+.2}")).collect();
        let concave = |k: usize| shapes.get(k).map_or(f64::NAN, |sh| sh.concave);
        println!(
            "{} {} {} {truth_depth:.2} {} {t1:.2} {:.2} {:.2} {:.3} {:.3} {:.3}",
            st.name,
            u8::from(st.rv),
            st.label,
            cells.join(" "),
            truth_depth / t1,
            floor_s14.map_or(f64::NAN, |f| f / t1),
            shapes.first().map_or(f64::NAN, |sh| sh.solidity),
            concave(0),
            concave(1),
        );
        if std::env::var_os("APEX_DOME_RINGS").is_some() {
            for (k, (sec, sh)) in s.iter().zip(&shapes).enumerate() {
                println!(
                    "  ring {k}: height {:.2} area {:.1} length {:.2} thickness {:.2} solidity {:.3}",
                    sec.height,
                    sh.area,
                    sh.half_perimeter,
                    sh.thickness(),
                    sh.solidity
                );
            }
        }
        for (list, e) in errs.iter_mut().zip(row) {
            list.push(e);
        }
        is_rv.push(st.rv);
    }
    for (group, keep) in [("all", None), ("LV", Some(false)), ("RV", Some(true))] {
        println!("-- {group}");
        for (name, list) in names.iter().zip(&errs) {
            let picked: Vec<f64> = list
                .iter()
                .zip(&is_rv)
                .filter(|(_, rv)| keep.is_none_or(|k| k == **rv))
                .map(|(e, _)| *e)
                .collect();
            stats(name, &picked);
        }
    }
    Ok(())
}
