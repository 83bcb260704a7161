//! Developer study: how well breath-hold alignment (`contours::align`) recovers the long-axis
//! views' shifts along the long axis (docs/VALIDATION.md, "Session 10: long-axis views along the
//! axis"). Simulated acquisitions with KNOWN per-plane motions; each view's shift error (up to the
//! across-axis gauge) split into its along- and across-axis parts, before and after alignment; a
//! pure along-axis shift of the views on clean acquisitions; the crossings' information per
//! direction; and the real biv-me files' view shifts. Session 11 ("Session 11: through-plane
//! alignment"): every table twice, in-plane only (the product) and with the study switch
//! `Options::through_plane` (each slice's offset along its normal), the slices' through-plane
//! error, and mesh-to-truth / contour-to-mesh of both.
//! `cargo run --release --example lax_axis -- DATA_DIR [population count] [lv|clean|biv|parts|pop|pure|real]`
//! (DATA_DIR holds meshes/ and contours/, e.g. /work/shared/data).
mod cases;
mod meshes;

use cases::{biv_case, clean_case, lv_case, own_case, truth, Case, Parts, ALL_PARTS};
use heartmesh_core::contours::align::{align_slices, align_slices_with, Alignment, Options};
use heartmesh_core::contours::{ContourKind, ContourSet};
use heartmesh_core::geometry::Vec3;
use heartmesh_core::io;
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::sim::population::{generate, Base, Plan, Source};
use heartmesh_core::sim::{simulate, AcquisitionSpec};
use meshes::{meshes_vs_truth, run, BOTH};
use nalgebra::Matrix3;
use std::collections::HashMap;

/// Per view: (along-axis error, across-axis error) before and after, in mm, up to the gauge (a
/// common translation across the axis, fitted to the errors); and the views' information.
struct ViewErrors {
    before: Vec<(f64, f64)>,
    after: Vec<(f64, f64)>,
    sax_before: Vec<f64>,
    sax_after: Vec<f64>,
    info: Vec<(f64, f64)>,
    /// Slices' through-plane error (mm, up to the stack's mean), before and after; information.
    through_before: Vec<f64>,
    through_after: Vec<f64>,
    through_info: Vec<f64>,
    /// Views' along-axis error with the whole-stack gauge (the slices' mean through-plane error
    /// taken out: a common translation along the axis changes no crossing).
    along3_before: Vec<f64>,
    along3_after: Vec<f64>,
}

fn errors(case: &Case, al: &Alignment) -> ViewErrors {
    let a = case.axis;
    let q = Matrix3::identity() - a * a.transpose();
    // (kind, shift found, true correction, plane normal, information along / across)
    type Row = (ContourKind, Vec3, Vec3, Vec3, (f64, f64));
    // Slices: (found through-plane, true through-plane, information).
    let sax: Vec<(f64, f64, f64)> = al
        .groups
        .iter()
        .filter(|g| g.kind == ContourKind::Sax)
        .filter_map(|g| {
            let (_, _, th) = case.truth.get(g.contour_ids.first()?)?;
            Some((g.through_plane_mm, *th, g.through_information))
        })
        .collect();
    let mean = |v: &dyn Fn(&(f64, f64, f64)) -> f64| {
        sax.iter().map(v).sum::<f64>() / sax.len().max(1) as f64
    };
    let (mf, mt) = (mean(&|x| x.0), mean(&|x| x.1));
    let through_before: Vec<f64> = sax.iter().map(|x| -(x.1 - mt)).collect();
    let through_after: Vec<f64> = sax.iter().map(|x| (x.0 - mf) - (x.1 - mt)).collect();
    let through_info: Vec<f64> = sax.iter().map(|x| x.2).collect();
    let rows: Vec<Row> = al
        .groups
        .iter()
        .filter_map(|g| {
            let (t, n, _) = case.truth.get(g.contour_ids.first()?)?;
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
            b += q * p * (p * found(f) - t);
        }
        let c = m.try_inverse().map_or(Vec3::zeros(), |inv| inv * b);
        let mut views = Vec::new();
        let mut slices = Vec::new();
        for (kind, f, t, n, _) in &rows {
            let p = Matrix3::identity() - n * n.transpose();
            // In-plane errors only (a slice's through-plane offset is measured on its own).
            let e = p * found(f) - t - p * c;
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
    // Views' along-axis error against the slices' mean through-plane error (the common gauge).
    let along3_before = before.iter().map(|x| x.0 + mt).collect();
    let along3_after = after.iter().map(|x| x.0 - (mf - mt)).collect();
    ViewErrors {
        before,
        after,
        sax_before,
        sax_after,
        info,
        through_before,
        through_after,
        through_info,
        along3_before,
        along3_after,
    }
}

fn tables(title: &str, cases: &[Case]) {
    for (tag, o) in meshes::BOTH {
        table(&format!("{title} [{tag}]"), cases, o);
    }
}

fn rms(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x * x, n + 1));
    (s / n.max(1) as f64).sqrt()
}

/// Runs the cases of one table; prints each and the RMS over all views.
fn table(title: &str, cases: &[Case], options: Options) {
    println!("\n## {title}: view errors (mm, RMS over the views) along / across the axis, before -> after; slices; view information along / across (weighted crossings)");
    let mut all = Vec::new();
    for case in cases {
        let (_, al) = align_slices_with(&case.set, options);
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
    let mut ti: Vec<f64> = all.iter().flat_map(|e| e.through_info.clone()).collect();
    ti.sort_by(f64::total_cmp);
    println!(
        "ALL {title}: SAX through-plane (up to the stack mean) {:.3} -> {:.3} mm, grew in {} of {}; views along with the stack gauge {:.3} -> {:.3} mm; through-plane information median {:.2} (range {:.2}-{:.2})",
        views(&|e| e.through_before.clone()),
        views(&|e| e.through_after.clone()),
        all.iter()
            .flat_map(|e| e.through_before.iter().zip(&e.through_after))
            .filter(|(b, a)| a.abs() > b.abs())
            .count(),
        ti.len(),
        views(&|e| e.along3_before.clone()),
        views(&|e| e.along3_after.clone()),
        ti.get(ti.len() / 2).copied().unwrap_or(f64::NAN),
        ti.first().copied().unwrap_or(f64::NAN),
        ti.last().copied().unwrap_or(f64::NAN),
    );
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
        for (tag, o) in BOTH {
            let (_, al) = align_slices_with(&set, o);
            let a = Vec3::from(al.axis);
            let slices: Vec<String> = al
                .groups
                .iter()
                .filter(|g| g.kind == ContourKind::Sax)
                .map(|g| format!("{:+.2} ({:.2})", g.through_plane_mm, g.through_information))
                .collect();
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
            "{file} [{tag}]: residual {:.3} -> {:.3}, {} rounds; {}; slices through-plane (information) {}",
            al.residual_before_mm,
            al.residual_after_mm,
            al.rounds,
            views.join("; "),
            slices.join(" ")
        );
            for surf in set.surfaces() {
                let (shifted, _) = align_slices_with(&set, o);
                let Some(mesh) = run(&shifted, Some(surf.clone())) else {
                    continue;
                };
                let c2m = |s: &ContourSet| {
                    let pts: Vec<Vec3> = s
                        .contours
                        .iter()
                        .filter(|c| c.surface.as_deref() == Some(surf.as_str()))
                        .flat_map(|c| c.points().copied())
                        .collect();
                    let d = heartmesh_core::metrics::points_to_mesh(&pts, &mesh);
                    d.iter().sum::<f64>() / d.len().max(1) as f64
                };
                println!(
                "  {surf} [{tag}]: c2m to the shifted contours {:.3}, to as given {:.3}; folds {}; volume {:.1} ml",
                c2m(&shifted),
                c2m(&set),
                heartmesh_core::mesh::quality::quality(&mesh).folded_edges,
                mesh.volume_ml()
            );
            }
        }
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
    // Each shape's acquisition at its own long-axis count.
    let spec = |lax: usize| AcquisitionSpec {
        lax_count: lax,
        ..AcquisitionSpec::default()
    };
    if only.is_empty() || only == "lv" {
        let mut cases = Vec::new();
        for (name, mesh, lax) in &meshes {
            cases.extend((1..=4).filter_map(|s| lv_case(name, mesh, &spec(*lax), s)));
        }
        tables("16 misaligned LVs (tests/alignment.rs)", &cases);
        meshes_vs_truth("16 misaligned LVs", &cases);
    }
    if only.is_empty() || only == "clean" {
        let mut cases = Vec::new();
        for (name, mesh, lax) in &meshes {
            cases.extend(clean_case(name, mesh, &spec(*lax)));
        }
        meshes_vs_truth("4 clean LVs", &cases);
        for case in &cases {
            let (_, al) = align_slices_with(&case.set, BOTH[1].1);
            println!(
                "{}: largest shift {:.3} mm, largest through-plane {:.3} mm",
                case.name,
                al.max_shift_mm(),
                al.groups
                    .iter()
                    .map(|g| g.through_plane_mm.abs())
                    .fold(0.0, f64::max)
            );
        }
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
        tables("6 LV+RV (tests/alignment.rs)", &cases);
        meshes_vs_truth("6 LV+RV", &cases);
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
            tables(&format!("16 LVs, {label}"), &cases);
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
        tables(&format!("{count} population LVs x 2 seeds"), &cases);
        meshes_vs_truth(&format!("{count} population LVs x 2 seeds"), &cases);
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
