//! Developer study: how well breath-hold alignment (`contours::align`) recovers the long-axis
//! views' shifts along the long axis (docs/VALIDATION.md, "Session 10: long-axis views along the
//! axis"). Simulated acquisitions with KNOWN per-plane motions; each view's shift error (up to the
//! across-axis gauge) split into its along- and across-axis parts, before and after alignment; a
//! pure along-axis shift of the views on clean acquisitions; the crossings' information per
//! direction; and the real biv-me files' view shifts.
//! `cargo run --release --example lax_axis -- DATA_DIR [population count]` (DATA_DIR holds
//! meshes/ and contours/, e.g. /work/shared/data).
use heartmesh_core::contours::align::{align_slices, Alignment};
use heartmesh_core::contours::{Contour, ContourKind, ContourSet, Polyline};
use heartmesh_core::geometry::Vec3;
use heartmesh_core::io;
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::sim::planes::draw_motion;
use heartmesh_core::sim::population::{generate, Base, Plan, Source};
use heartmesh_core::sim::prng::SplitMix64;
use heartmesh_core::sim::repair::{orient_consistently, weld};
use heartmesh_core::sim::slice::{join_chains, polyline_length, resample};
use heartmesh_core::sim::{simulate, slice_mesh, AcquisitionSpec, Misalignment};
use nalgebra::{Matrix3, Rotation3};
use std::collections::HashMap;

fn truth(dir: &str, name: &str) -> TriMesh {
    let path = format!("{dir}/meshes/{name}");
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let m = io::read_mesh(name, &bytes)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .mesh;
    orient_consistently(&weld(&m, 1e-6).0).0
}

/// The acquisitions' misalignment: every image shifted up to 2 mm and tilted up to 2 degrees.
const TWO_MM_TWO_DEG: Misalignment = Misalignment {
    shift_mm: 2.0,
    tilt_deg: 2.0,
};

/// One simulated case: the contours, each contour id's true in-plane correction (the image's
/// shift, projected into its nominal plane) and plane normal, and the long axis.
struct Case {
    name: String,
    set: ContourSet,
    truth: HashMap<String, (Vec3, Vec3)>,
    axis: Vec3,
    /// Mean shift of the short-axis images along the axis (through their planes; mm).
    sax_through: f64,
}

/// `sim::simulate` with 2 mm / 2 degree misalignment; the motions redrawn to know the shifts.
fn lv_case(name: &str, mesh: &TriMesh, base: &AcquisitionSpec, seed: u64) -> Option<Case> {
    let spec = AcquisitionSpec {
        misalignment: Some(TWO_MM_TWO_DEG),
        seed,
        ..base.clone()
    };
    let acq = simulate(mesh, &spec).ok()?;
    let mut rng = SplitMix64::new(seed);
    let mut truth = HashMap::new();
    let mut through = Vec::new();
    let named = acq
        .sax_planes
        .iter()
        .enumerate()
        .map(|(k, p)| (format!("sax{:02}", k + 1), p))
        .chain(
            acq.lax_planes
                .iter()
                .enumerate()
                .map(|(k, p)| (format!("lax{:02}", k + 1), p)),
        );
    for (id, plane) in named {
        let m = draw_motion(&mut rng, plane, TWO_MM_TWO_DEG);
        let n = plane.normal;
        if id.starts_with("sax") {
            through.push(m.shift.dot(&n));
        }
        truth.insert(id, (m.shift - n * m.shift.dot(&n), n));
    }
    Some(Case {
        name: format!("{name} s{seed}"),
        set: acq.contours,
        truth,
        axis: acq.axis.direction,
        sax_through: through.iter().sum::<f64>() / through.len().max(1) as f64,
    })
}

/// Which parts of each image's motion an acquisition keeps.
#[derive(Clone, Copy)]
struct Parts {
    /// The 2-degree tilts.
    tilt: bool,
    /// The shifts' components through the images' own planes: short-axis, long-axis images.
    through_sax: bool,
    through_lax: bool,
}

const ALL_PARTS: Parts = Parts {
    tilt: true,
    through_sax: true,
    through_lax: true,
};

/// LV and RV cut by the same misaligned images (as tests/alignment.rs `biventricular`).
fn biv_case(name: &str, lv: &TriMesh, rv: &TriMesh, seed: u64) -> Option<Case> {
    let base = AcquisitionSpec::default();
    own_case(
        name,
        &[("LV_ENDO", lv), ("RV_ENDO", rv)],
        &base,
        seed,
        ALL_PARTS,
    )
}

/// Surfaces cut by the same misaligned images planned on the first (motions drawn as `sim` draws
/// them), keeping only `parts` of each motion.
fn own_case(
    name: &str,
    surfaces: &[(&str, &TriMesh)],
    base: &AcquisitionSpec,
    seed: u64,
    parts: Parts,
) -> Option<Case> {
    let nominal = simulate(surfaces.first()?.1, base).ok()?;
    let planes = nominal
        .sax_planes
        .iter()
        .map(|p| ("sax", *p))
        .chain(nominal.lax_planes.iter().map(|p| ("lax", *p)));
    let mut rng = SplitMix64::new(seed);
    let mut set = ContourSet::default();
    let mut truth = HashMap::new();
    let mut through = Vec::new();
    for (k, (kind, plane)) in planes.enumerate() {
        let mut m = draw_motion(&mut rng, &plane, TWO_MM_TWO_DEG);
        if !parts.tilt {
            m.rotation = Rotation3::identity();
        }
        if !(if kind == "sax" {
            parts.through_sax
        } else {
            parts.through_lax
        }) {
            m.shift -= plane.normal * m.shift.dot(&plane.normal);
        }
        let imaged = m.apply_to_plane(&plane);
        let n = plane.normal;
        if kind == "sax" {
            through.push(m.shift.dot(&n));
        }
        for &(surf, mesh) in surfaces {
            let mut pieces = join_chains(slice_mesh(mesh, &imaged), 3.0, &imaged);
            pieces.sort_by(|a, b| polyline_length(b).total_cmp(&polyline_length(a)));
            let Some(first) = pieces.first() else {
                continue;
            };
            let piece = resample(first, 1.0);
            if piece.points.len() < 5 {
                continue;
            }
            let points = piece.points.iter().map(|p| m.inverse_apply(p)).collect();
            let id = format!("{kind}{k:02}_{surf}");
            truth.insert(id.clone(), (m.shift - n * m.shift.dot(&n), n));
            set.contours.push(Contour {
                id,
                surface: Some(surf.into()),
                pieces: vec![Polyline {
                    points,
                    closed: kind == "sax",
                }],
                first_line: 0,
            });
        }
    }
    Some(Case {
        name: format!("{name} s{seed}"),
        set,
        truth,
        axis: nominal.axis.direction,
        sax_through: through.iter().sum::<f64>() / through.len().max(1) as f64,
    })
}

/// Per view: (along-axis error, across-axis error) before and after, in mm, up to the gauge (a
/// common translation across the axis, fitted to the errors); and the views' information.
struct ViewErrors {
    before: Vec<(f64, f64)>,
    after: Vec<(f64, f64)>,
    sax_before: Vec<f64>,
    sax_after: Vec<f64>,
    info: Vec<(f64, f64)>,
}

fn errors(case: &Case, al: &Alignment) -> ViewErrors {
    let a = case.axis;
    let q = Matrix3::identity() - a * a.transpose();
    // (kind, shift found, true correction, plane normal, information along / across)
    type Row = (ContourKind, Vec3, Vec3, Vec3, (f64, f64));
    let rows: Vec<Row> = al
        .groups
        .iter()
        .filter_map(|g| {
            let (t, n) = case.truth.get(g.contour_ids.first()?)?;
            let i = &g.information;
            Some((
                g.kind,
                Vec3::from(g.shift_mm),
                *t,
                *n,
                (i.along_axis, i.across_axis),
            ))
        })
        .collect();
    let split = |found: &dyn Fn(&Vec3) -> Vec3| {
        let mut m = a * a.transpose();
        let mut b = Vec3::zeros();
        for (_, f, t, n, _) in &rows {
            let p = Matrix3::identity() - n * n.transpose();
            m += q * p * q;
            b += q * p * (found(f) - t);
        }
        let c = m.try_inverse().map_or(Vec3::zeros(), |inv| inv * b);
        let mut views = Vec::new();
        let mut slices = Vec::new();
        for (kind, f, t, n, _) in &rows {
            let p = Matrix3::identity() - n * n.transpose();
            let e = found(f) - t - p * c;
            if *kind == ContourKind::Lax {
                let along = (a - n * a.dot(n)).normalize();
                let across = n.cross(&along);
                views.push((e.dot(&along), e.dot(&across)));
            } else {
                slices.push(e.norm());
            }
        }
        (views, slices)
    };
    let (before, sax_before) = split(&|_| Vec3::zeros());
    let (after, sax_after) = split(&|f| *f);
    let info = rows
        .iter()
        .filter(|r| r.0 == ContourKind::Lax)
        .map(|r| r.4)
        .collect();
    ViewErrors {
        before,
        after,
        sax_before,
        sax_after,
        info,
    }
}

fn rms(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x * x, n + 1));
    (s / n.max(1) as f64).sqrt()
}

/// Runs the cases of one table; prints each and the RMS over all views.
fn table(title: &str, cases: &[Case]) {
    println!("\n## {title}: view errors (mm, RMS over the views) along / across the axis, before -> after; slices; view information along / across (weighted crossings)");
    let mut all = Vec::new();
    for case in cases {
        let (_, al) = align_slices(&case.set);
        let e = errors(case, &al);
        println!(
            "{:28} along {:.2} -> {:.2}  across {:.2} -> {:.2}  SAX {:.2} -> {:.2}  info {}",
            case.name,
            rms(e.before.iter().map(|x| x.0)),
            rms(e.after.iter().map(|x| x.0)),
            rms(e.before.iter().map(|x| x.1)),
            rms(e.after.iter().map(|x| x.1)),
            rms(e.sax_before.iter().copied()),
            rms(e.sax_after.iter().copied()),
            e.info
                .iter()
                .map(|(a, c)| format!("{a:.1}/{c:.1}"))
                .collect::<Vec<_>>()
                .join(" ")
        );
        all.push(e);
    }
    let views = |f: &dyn Fn(&ViewErrors) -> Vec<f64>| rms(all.iter().flat_map(f));
    // The views' common along-axis error per case (what the slices' own through-plane motion
    // would give all views alike) and the rest.
    let common: Vec<f64> = all
        .iter()
        .map(|e| e.after.iter().map(|x| x.0).sum::<f64>() / e.after.len().max(1) as f64)
        .collect();
    let rest = rms(all
        .iter()
        .zip(&common)
        .flat_map(|(e, m)| e.after.iter().map(move |x| x.0 - m)));
    let worse = all
        .iter()
        .flat_map(|e| e.before.iter().zip(&e.after))
        .filter(|(b, a)| a.0.abs() > b.0.abs())
        .count();
    let total: usize = all.iter().map(|e| e.after.len()).sum();
    println!("ALL {title}: views whose along-axis error grew: {worse} of {total}");
    let through: Vec<f64> = cases.iter().map(|c| c.sax_through).collect();
    let (mc, mt) = (
        common.iter().sum::<f64>() / common.len() as f64,
        through.iter().sum::<f64>() / through.len() as f64,
    );
    let cov: f64 = common
        .iter()
        .zip(&through)
        .map(|(c, t)| (c - mc) * (t - mt))
        .sum();
    let var_c: f64 = common.iter().map(|c| (c - mc).powi(2)).sum();
    let var_t: f64 = through.iter().map(|t| (t - mt).powi(2)).sum();
    if var_t > 1e-12 {
        println!(
        "ALL {title}: correlation of the common along-axis error with the slices' mean through-plane shift {:.2} (slope {:.2}); that mean's RMS {:.3} mm",
            cov / (var_c * var_t).sqrt(),
            cov / var_t,
            rms(through.iter().copied())
        );
    }
    println!(
        "ALL {title}: along-axis error after: common to a case's views RMS {:.3}, the rest {rest:.3} mm",
        rms(common.iter().copied())
    );
    let ratio: Vec<f64> = all
        .iter()
        .flat_map(|e| e.info.iter().map(|(a, c)| a / c.max(1e-12)))
        .collect();
    let mut sorted = ratio.clone();
    sorted.sort_by(f64::total_cmp);
    println!(
        "ALL {title}: along {:.3} -> {:.3}  across {:.3} -> {:.3}  SAX {:.3} -> {:.3}  mm; along/across information median {:.3} (range {:.3}-{:.3}); views {}",
        views(&|e| e.before.iter().map(|x| x.0).collect()),
        views(&|e| e.after.iter().map(|x| x.0).collect()),
        views(&|e| e.before.iter().map(|x| x.1).collect()),
        views(&|e| e.after.iter().map(|x| x.1).collect()),
        views(&|e| e.sax_before.clone()),
        views(&|e| e.sax_after.clone()),
        sorted.get(sorted.len() / 2).copied().unwrap_or(f64::NAN),
        sorted.first().copied().unwrap_or(f64::NAN),
        sorted.last().copied().unwrap_or(f64::NAN),
        ratio.len()
    );
}

/// Clean acquisitions whose views alone are moved along the axis by +-`s` (alternating): the
/// along-axis shift found against the one applied.
fn pure_along(name: &str, mesh: &TriMesh, base: &AcquisitionSpec) {
    let Ok(acq) = simulate(mesh, base) else {
        return;
    };
    let a = acq.axis.direction;
    let mut line = format!("{name:28}");
    for s in [0.0, 1.0, 2.0, 3.0, 4.0, 5.0] {
        let mut set = acq.contours.clone();
        let mut applied = HashMap::new();
        let mut sign = 1.0;
        for c in set.contours.iter_mut().filter(|c| c.id.starts_with("lax")) {
            let d = a * (s * sign);
            sign = -sign;
            for p in c.pieces.iter_mut().flat_map(|p| p.points.iter_mut()) {
                *p += d;
            }
            applied.insert(c.id.clone(), d);
        }
        let (_, al) = align_slices(&set);
        // Error of the views' along-axis positions after the shift found (0 = fully undone).
        let err: Vec<f64> = al
            .groups
            .iter()
            .filter(|g| g.kind == ContourKind::Lax)
            .filter_map(|g| {
                let d = applied.get(g.contour_ids.first()?)?;
                Some((d + Vec3::from(g.shift_mm)).dot(&a))
            })
            .collect();
        let sax = al
            .groups
            .iter()
            .filter(|g| g.kind == ContourKind::Sax)
            .map(|g| Vec3::from(g.shift_mm).norm())
            .fold(0.0, f64::max);
        line += &format!(
            " | {s:.0}: {:.2} (SAX {:.2})",
            rms(err.iter().copied()),
            sax
        );
    }
    println!("{line}");
}

fn real(dir: &str) {
    println!("\n## real biv-me files: per view shift along / across the axis (mm), information along / across; residual");
    for file in [
        "bivme-example-patient1/patient1-ED.csv",
        "bivme-example-patient1/patient1-ES.csv",
        "bivme-test-patient2/patient2-ED.csv",
        "bivme-test-patient2/patient2-ES.csv",
    ] {
        let path = format!("{dir}/contours/{file}");
        let Ok(bytes) = std::fs::read(&path) else {
            println!("{path}: missing");
            continue;
        };
        let Ok(set) = io::read_contours(file, &bytes) else {
            continue;
        };
        let (_, al) = align_slices(&set);
        let a = Vec3::from(al.axis);
        let views: Vec<String> = al
            .groups
            .iter()
            .filter(|g| g.kind == ContourKind::Lax)
            .map(|g| {
                let t = Vec3::from(g.shift_mm);
                let i = &g.information;
                format!(
                    "{} {:+.2}/{:.2} (info {:.1}/{:.1})",
                    g.label.split('_').next().unwrap_or(""),
                    t.dot(&a),
                    (t - a * t.dot(&a)).norm(),
                    i.along_axis,
                    i.across_axis
                )
            })
            .collect();
        println!(
            "{file}: residual {:.3} -> {:.3}, {} rounds; {}",
            al.residual_before_mm,
            al.residual_after_mm,
            al.rounds,
            views.join("; ")
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dir = args.get(1).cloned().unwrap_or("/work/shared/data".into());
    let count: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(8);
    let only = args.get(3).cloned().unwrap_or_default();
    let shapes = [
        ("cap endo", "cap-atlas-mean-ED-LV_ENDO-open.obj", 3),
        ("spasm endo", "cardiomesh-spasm-LV_endo.obj", 2),
        ("spasm epi", "cardiomesh-spasm-LV_epi.obj", 3),
        ("bivme LV", "bivme-patient1-ED-LV_ENDO-closed.obj", 3),
    ];
    let meshes: Vec<(&str, TriMesh, usize)> = shapes
        .iter()
        .map(|(n, f, l)| (*n, truth(&dir, f), *l))
        .collect();
    if only.is_empty() || only == "lv" {
        let mut cases = Vec::new();
        for (name, mesh, lax) in &meshes {
            let base = AcquisitionSpec {
                lax_count: *lax,
                ..AcquisitionSpec::default()
            };
            cases.extend((1..=4).filter_map(|s| lv_case(name, mesh, &base, s)));
        }
        table("16 misaligned LVs (tests/alignment.rs)", &cases);
    }
    if only.is_empty() || only == "biv" {
        let spasm_rv = heartmesh_core::sim::cavity::rv_cavity(
            &truth(&dir, "cardiomesh-spasm-RV_endo.obj"),
            &meshes[2].1,
            40.0,
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let bivme_rv = truth(&dir, "bivme-patient1-ED-RV_ENDO-closed.obj");
        let mut cases = Vec::new();
        for (name, lv, rv) in [
            ("spasm", &meshes[1].1, &spasm_rv),
            ("bivme", &meshes[3].1, &bivme_rv),
        ] {
            cases.extend((1..=3).filter_map(|s| biv_case(name, lv, rv, s)));
        }
        table("6 LV+RV (tests/alignment.rs)", &cases);
    }
    if only.is_empty() || only == "parts" {
        println!("\n## which part of the motion leaves the views' along-axis error: the 16 LVs sliced here with parts of each image's motion");
        let parts = |tilt, through_sax, through_lax| Parts {
            tilt,
            through_sax,
            through_lax,
        };
        for (label, parts) in [
            ("all", ALL_PARTS),
            ("no tilt", parts(false, true, true)),
            ("no through-plane shift", parts(true, false, false)),
            ("no SAX through-plane shift", parts(true, false, true)),
            ("no LAX through-plane shift", parts(true, true, false)),
            ("in-plane shifts only", parts(false, false, false)),
        ] {
            let mut cases = Vec::new();
            for (name, mesh, lax) in &meshes {
                let base = AcquisitionSpec {
                    lax_count: *lax,
                    ..AcquisitionSpec::default()
                };
                cases.extend(
                    (1..=4).filter_map(|s| own_case(name, &[("LV", mesh)], &base, s, parts)),
                );
            }
            table(&format!("16 LVs, {label}"), &cases);
        }
    }
    let bases = [
        Base {
            name: "param".into(),
            source: Source::Parametric,
            plan: Plan::Lv,
        },
        Base {
            name: "cap".into(),
            source: Source::Mesh(meshes[0].1.clone()),
            plan: Plan::Lv,
        },
        Base {
            name: "spasm".into(),
            source: Source::Mesh(meshes[1].1.clone()),
            plan: Plan::Lv,
        },
        Base {
            name: "bivme".into(),
            source: Source::Mesh(meshes[3].1.clone()),
            plan: Plan::Lv,
        },
    ];
    let members = generate(&bases, count, 7).unwrap_or_else(|e| panic!("{e}"));
    if only.is_empty() || only == "pop" {
        let mut cases = Vec::new();
        for m in &members {
            for s in 1..=2 {
                cases.extend(lv_case(
                    &m.subject.name,
                    &m.subject.mesh,
                    &m.subject.base,
                    s,
                ));
            }
        }
        table(&format!("{count} population LVs x 2 seeds"), &cases);
    }
    if only.is_empty() || only == "pure" {
        println!("\n## clean acquisitions, views moved +-s mm along the axis (alternating): RMS along-axis error left (mm) at s = 0..5 (largest SAX shift)");
        for (name, mesh, lax) in &meshes {
            let base = AcquisitionSpec {
                lax_count: *lax,
                ..AcquisitionSpec::default()
            };
            pure_along(name, mesh, &base);
        }
        for m in members.iter().take(4) {
            pure_along(&m.subject.name, &m.subject.mesh, &m.subject.base);
        }
    }
    if only.is_empty() || only == "real" {
        real(&dir);
    }
}
