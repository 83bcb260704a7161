//! Developer tool (session 16, docs/VALIDATION.md "Session 16: the base lid where long-axis curves
//! end at different heights"): what the base lid does when the long-axis (LAX) curves stop at very
//! different heights.
//!
//! `cargo run --release --example uneven_tips -- real FILE [SURFACE]`: per LAX tip at the base
//! (an open curve's endpoint at or beyond the basal short-axis ring), its height above the ring,
//! the lid's height there (the plane of the lid points) and the tip's signed distance to the mesh
//! (+: the tip lies outside the mesh, the mesh stops short of it); the report's past_data and the
//! volume.
//!
//! `cargo run --release --example uneven_tips -- family [N] [SEED]`: the uneven-tip family, N
//! cases (default 60) drawn from SEED: a reference shape sliced as `heartmesh simulate` does (10 mm
//! SAX stack, 3 LAX at 0 / 90 / 45 degrees turned by a random angle), the top one or two SAX slices
//! left out (so the tips lie 13-23 mm past the basal ring, as on the real files' 22-32 mm), and
//! one or two LAX curves cut short at their basal end by 5-25 mm of height (one tip, one tip each of
//! two views, or both tips of one view: a view drawn short), or the truth's valve plane tilted by
//! 10-30 degrees (every tip lower on one side: the lid should follow). One CSV row per case:
//! clipped accuracy (at the basal SAX plane), the truth's wall above that plane (truth->mesh), the
//! signed distance of every original tip to the mesh, the lid's height at the cut tips and the
//! kept ones, the overrun past the data and the unclipped volume against the truth closed at its
//! rim.
//! `cargo run --release --example uneven_tips -- sweep TRUTH|parametric DROP`: one shape, one
//! pattern per line (none; one tip, two tips, one view cut by 5-25 mm; tilts of 10-30 degrees).
//! Environment: CAPS=off reconstructs with `--end-caps off`; USUAL=1 makes `family` draw
//! acquisitions with every curve whole (0-2 slices left out); DUMP=DIR writes each case's
//! contours and truth; TRUTH=OBJ adds the truth's top to `real`'s profile.
//! Summaries: `scripts/uneven_tips.py A.csv B.csv ...`.
use heartmesh_core::contours::{ContourKind, ContourSet};
use heartmesh_core::geometry::Vec3;
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::metrics::compare::{compare, directed};
use heartmesh_core::pipeline::lid_tips;
use heartmesh_core::sim::prng::SplitMix64 as Prng;
use heartmesh_core::sim::repair::{close_small_holes, orient_consistently, weld};
use heartmesh_core::sim::shapes::ParametricLv;
use heartmesh_core::sim::slice::Plane;
use heartmesh_core::sim::{simulate, AcquisitionSpec};
use heartmesh_core::spatial::Bvh;
use heartmesh_core::{io, Params, Reconstruction};

#[path = "shared/probe_mesh.rs"]
mod probe_mesh;
use probe_mesh::signed;

type Res<T> = Result<T, Box<dyn std::error::Error>>;

const MESHES: &str = "/work/shared/data/meshes";

fn truth(arg: &str) -> Res<TriMesh> {
    if arg == "parametric" {
        return Ok(ParametricLv::bulged_truth()?);
    }
    let path = if arg.contains('/') {
        arg.to_string()
    } else {
        format!("{MESHES}/{arg}")
    };
    let bytes = std::fs::read(&path)?;
    let m = io::read_mesh(&path, &bytes)?.mesh;
    Ok(orient_consistently(&weld(&m, 1e-6).0).0)
}

/// A tip of an open LAX curve at the base: contour index, which end, the point.
#[derive(Clone, Copy, Debug)]
struct Tip {
    contour: usize,
    last: bool,
    point: Vec3,
}

/// The basal endpoints of the open LAX curves of `set` (both ends of a U lie at the base): an end
/// is basal when it lies above the curve's lowest point by more than half the curve's height
/// range.
fn base_tips(set: &ContourSet, axis: &Vec3, is_lax: &dyn Fn(&str) -> bool) -> Vec<Tip> {
    let mut out = Vec::new();
    for (k, c) in set.contours.iter().enumerate() {
        if !is_lax(&c.id) {
            continue;
        }
        let pts: Vec<Vec3> = c.points().copied().collect();
        let (Some(first), Some(last)) = (pts.first(), pts.last()) else {
            continue;
        };
        let hs: Vec<f64> = pts.iter().map(|p| p.dot(axis)).collect();
        let lo = hs.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = hs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        for (p, is_last) in [(first, false), (last, true)] {
            if p.dot(axis) - lo > 0.5 * (hi - lo) {
                out.push(Tip {
                    contour: k,
                    last: is_last,
                    point: *p,
                });
            }
        }
    }
    out
}

/// Least-squares plane through the lid points above `h0` along `axis`: height = a + g . across.
/// Returns a closure giving the lid height at a point (None without three lid points).
fn lid_plane(lid: &[Vec3], axis: &Vec3, h0: f64) -> Option<impl Fn(&Vec3) -> f64> {
    let pts: Vec<Vec3> = lid
        .iter()
        .filter(|p| p.dot(axis) > h0 - 1e-6)
        .copied()
        .collect();
    if pts.len() < 3 {
        return None;
    }
    let c = pts.iter().sum::<Vec3>() / pts.len() as f64;
    let u = axis.cross(&Vec3::x());
    let u = if u.norm() > 0.5 {
        u.normalize()
    } else {
        axis.cross(&Vec3::y()).normalize()
    };
    let v = axis.cross(&u);
    let mut m = nalgebra::Matrix3::<f64>::zeros();
    let mut r = Vec3::zeros();
    for p in &pts {
        let d = p - c;
        let row = Vec3::new(1.0, d.dot(&u), d.dot(&v));
        m += row * row.transpose();
        r += row * p.dot(axis);
    }
    let s = m.lu().solve(&r)?;
    Some(move |p: &Vec3| {
        let d = p - c;
        s.x + s.y * d.dot(&u) + s.z * d.dot(&v)
    })
}

fn reconstruct(set: &ContourSet, surface: Option<String>) -> Res<Reconstruction> {
    let off = std::env::var("CAPS").is_ok_and(|v| v == "off");
    let params = Params {
        surface,
        end_caps: if off {
            heartmesh_core::EndCapMode::Off
        } else {
            heartmesh_core::EndCapMode::Auto
        },
        ..Params::default()
    };
    let mut rec = Reconstruction::new(set, params)?;
    while !rec.step()?.done {}
    Ok(rec)
}

fn real(path: &str, surface: Option<String>) -> Res<()> {
    let truth_mesh = std::env::var("TRUTH").ok().map(|t| truth(&t)).transpose()?;
    let set = io::read_contours(path, &std::fs::read(path)?)?;
    let rec = reconstruct(&set, surface)?;
    let axis = rec.long_axis().normalize();
    let top = rec
        .slice_heights()
        .into_iter()
        .fold(f64::NEG_INFINITY, f64::max);
    let kinds = rec.kinds().to_vec();
    let mut used = ContourSet {
        contours: rec.contours().to_vec(),
        ..ContourSet::default()
    };
    let lax_ids: Vec<String> = used
        .contours
        .iter()
        .zip(&kinds)
        .filter(|(_, k)| **k == ContourKind::Lax)
        .map(|(c, _)| c.id.clone())
        .collect();
    used.contours.retain(|c| lax_ids.contains(&c.id));
    let tips = base_tips(&used, &axis, &|_| true);
    let lid = rec.end_cap_points();
    let plane = lid_plane(&lid, &axis, top);
    let mesh = rec.mesh();
    let bvh = Bvh::build(mesh);
    let report = rec.end_caps();
    let past = rec.past_data();
    println!(
        "{path} {:?}: basal ring at {top:.2}; end caps {report:?}; past base {:.2} mm; volume {:.1} ml; mesh top {:+.2} mm over the ring",
        rec.params().surface,
        past.map_or(f64::NAN, |p| p.base_mm),
        mesh.volume_ml(),
        mesh.positions
            .iter()
            .map(|p| p.dot(&axis))
            .fold(f64::NEG_INFINITY, f64::max)
            - top
    );
    for t in &tips {
        let h = t.point.dot(&axis) - top;
        let lid_h = plane.as_ref().map_or(f64::NAN, |f| f(&t.point) - top);
        println!(
            "  {:<40} {}: tip {:+7.2} mm over the ring; lid there {:+7.2} (lid - tip {:+6.2}); tip to mesh {:+6.2} mm",
            used.contours[t.contour].id,
            if t.last { "last " } else { "first" },
            h,
            lid_h,
            lid_h - h,
            signed(&bvh, mesh, &t.point)
        );
    }
    // Both rules' planes through the tips (frame: the tips' centroid), for the landmarks.
    let tc = tips.iter().map(|t| t.point).sum::<Vec3>() / tips.len().max(1) as f64;
    let bu = axis.cross(&Vec3::x()).normalize();
    let bv = axis.cross(&bu);
    let lt: Vec<lid_tips::Tip> = tips
        .iter()
        .map(|t| {
            let d = t.point - tc;
            lid_tips::Tip {
                x: d.dot(&bu),
                y: d.dot(&bv),
                h: t.point.dot(&axis),
            }
        })
        .collect();
    let r2 = {
        let d: Vec<f64> = tips
            .iter()
            .map(|t| {
                let d = t.point - tc;
                (d - axis * d.dot(&axis)).norm_squared()
            })
            .collect();
        d.iter().sum::<f64>() / d.len().max(1) as f64
    };
    let lsq = lid_tips::least_squares(&lt, 1e-3 * r2, 1.0);
    let top_plane = lid_tips::ceiling(&lt, 1.0);
    let at = |c: &Option<lid_tips::Ceiling>, p: &Vec3| {
        let d = p - tc;
        c.map_or(f64::NAN, |c| c.height(d.dot(&bu), d.dot(&bv)) - top)
    };
    for (name, p) in set.landmarks.iter().filter(|(n, _)| n.contains("VALVE")) {
        let h = p.dot(&axis) - top;
        println!(
            "  valve landmark {name:<16}: {h:+7.2} over the ring; least squares - point {:+6.2}; ceiling - point {:+6.2}",
            at(&lsq, p) - h,
            at(&top_plane, p) - h
        );
    }
    for (name, p) in &set.landmarks {
        let h = p.dot(&axis) - top;
        let lid_h = plane.as_ref().map_or(f64::NAN, |f| f(p) - top);
        println!(
            "  landmark {name:<28}: {h:+7.2} mm over the ring; lid there {lid_h:+7.2} (lid - point {:+6.2}); to mesh {:+6.2} mm",
            lid_h - h,
            signed(&bvh, mesh, p)
        );
    }
    // The mesh's top (highest crossing of a line along the axis) over the basal ring, at radius
    // fractions of the ring's mean radius, every 30 degrees from the first tip's direction; the
    // lid plane's height in brackets.
    let ring: Vec<Vec3> = rec
        .contours()
        .iter()
        .zip(&kinds)
        .filter(|(c, k)| {
            **k == ContourKind::Sax
                && (c.points().next().map_or(f64::NAN, |p| p.dot(&axis)) - top).abs() < 1.0
        })
        .flat_map(|(c, _)| c.points().copied().collect::<Vec<_>>())
        .collect();
    if let (Some(t0), false) = (tips.first(), ring.is_empty()) {
        let c = ring.iter().sum::<Vec3>() / ring.len() as f64;
        let radius = ring
            .iter()
            .map(|p| {
                let d = p - c;
                (d - axis * d.dot(&axis)).norm()
            })
            .sum::<f64>()
            / ring.len() as f64;
        let d0 = t0.point - c;
        let u = (d0 - axis * d0.dot(&axis)).normalize();
        let v = axis.cross(&u);
        println!("  mesh top over the ring (mm) by azimuth from the first tip, radius 0 / 0.3 / 0.6 / 0.8 / 0.95 R (R {radius:.1}) [lid plane]");
        for k in 0..12 {
            let a = (k as f64 * 30.0).to_radians();
            let dir = u * a.cos() + v * a.sin();
            let mut line = format!("  {:4.0} deg:", k as f64 * 30.0);
            for f in [0.0, 0.3, 0.6, 0.8, 0.95] {
                let o = c + dir * (f * radius) + axis * (top + 200.0 - c.dot(&axis));
                let hit = ray_first(mesh, &o, &(-axis));
                let lidh = plane.as_ref().map_or(f64::NAN, |g| g(&o) - top);
                let th = truth_mesh.as_ref().and_then(|t| ray_first(t, &o, &(-axis)));
                line += &format!(
                    " {:+6.2} [{:+6.2}]",
                    hit.map_or(f64::NAN, |d| 200.0 - d),
                    lidh
                );
                if truth_mesh.is_some() {
                    line += &format!(" t{:+6.2}", th.map_or(f64::NAN, |d| 200.0 - d));
                }
            }
            // Nearest tip's azimuth.
            println!("{line}");
        }
    }
    Ok(())
}

/// Nearest hit of the ray from `o` along `u` with `mesh` (distance along u), brute force.
fn ray_first(mesh: &TriMesh, o: &Vec3, u: &Vec3) -> Option<f64> {
    probe_mesh::hits(mesh, o, u).reduce(f64::min)
}

/// How a case changes the planner's acquisition.
#[derive(Clone, Debug)]
enum Pattern {
    None,
    /// Cut these (view, last end) tips by `mm` of height.
    Cut(Vec<(usize, bool)>, f64),
    /// The truth cut by a plane tilted by this many degrees through the axis 2 mm under the rim's
    /// top: one side of the rim lower (a tilted valve plane where it cuts, the rim elsewhere).
    Tilt(f64),
}

impl Pattern {
    fn name(&self) -> String {
        match self {
            Pattern::None => "none".into(),
            Pattern::Cut(t, mm) => {
                let views: std::collections::BTreeSet<usize> = t.iter().map(|x| x.0).collect();
                let kind = match (t.len(), views.len()) {
                    (1, _) => "one-tip",
                    (2, 1) => "one-view",
                    (2, 2) => "two-tips",
                    _ => "cut",
                };
                format!("{kind}-{mm:.0}")
            }
            Pattern::Tilt(d) => format!("tilt-{d:.0}"),
        }
    }
}

/// Removes from the `last` (or first) end of the curve's points those higher than its tip less
/// `mm` along `axis`.
fn cut(points: &mut Vec<Vec3>, last: bool, mm: f64, axis: &Vec3) {
    if !last {
        points.reverse();
    }
    if let Some(tip) = points.last().map(|p| p.dot(axis)) {
        while points.len() > 3 && points.last().is_some_and(|p| p.dot(axis) > tip - mm) {
            points.pop();
        }
    }
    if !last {
        points.reverse();
    }
}

/// The truth with everything past the plane through `origin` with normal `n` removed (whole
/// triangles with any vertex past it; the rim stays ragged at the triangles' size, ~1-2 mm).
fn clip_truth(t: &TriMesh, origin: &Vec3, n: &Vec3) -> TriMesh {
    let keep: Vec<bool> = t
        .positions
        .iter()
        .map(|p| (p - origin).dot(n) <= 0.0)
        .collect();
    let triangles: Vec<[u32; 3]> = t
        .triangles
        .iter()
        .filter(|tr| tr.iter().all(|&i| keep[i as usize]))
        .copied()
        .collect();
    TriMesh {
        positions: t.positions.clone(),
        triangles,
    }
}

struct Case {
    truth_name: String,
    truth: TriMesh,
    drop: usize,
    turn_deg: f64,
    pattern: Pattern,
    seed: u64,
}

fn header() -> &'static str {
    "shape,pattern,drop,seed,lid_points,tips_kept,lid_minus_cut_orig,lid_minus_kept_max,lid_minus_kept_mean,tip_out_cut_orig,tip_out_kept_max,tip_out_all_max,m2t_mean,m2t_max,t2m_mean,t2m_max,hausdorff,vol_pct,band_t2m_mean,band_t2m_p95,band_t2m_max,band_max_h,past_base,truth_past_base,vol_unclipped,vol_truth_closed,vol_unclipped_pct,folds"
}

fn run_case(case: &Case) -> Res<String> {
    let spec = AcquisitionSpec {
        lax_count: 3,
        lax_angles_deg: vec![case.turn_deg, 90.0 + case.turn_deg, 45.0 + case.turn_deg],
        seed: case.seed,
        ..AcquisitionSpec::default()
    };
    let mut truth = case.truth.clone();
    let base_acq = simulate(&truth, &spec)?;
    let axis = base_acq.axis.direction.normalize();
    if let Pattern::Tilt(deg) = case.pattern {
        // A valve plane tilted by `deg` about an axis across the long axis (the 0-degree view's
        // normal), through the rim's top less 2 mm: every tip on one side stops lower.
        let (_, hi, _) = base_acq.axis.extent(&truth).ok_or("extent")?;
        let across = base_acq
            .lax_planes
            .first()
            .map(|p| p.normal)
            .ok_or("no LAX")?;
        let dir = (axis.cross(&across)).normalize();
        let n = (axis * deg.to_radians().cos() + dir * deg.to_radians().sin()).normalize();
        let origin = base_acq.axis.centre + axis * (hi - 2.0);
        truth = clip_truth(&truth, &origin, &n);
    }
    let acq = simulate(&truth, &spec)?;
    let mut set = acq.contours.clone();
    // Leave out the `drop` most basal SAX slices.
    let mut sax: Vec<(usize, f64)> = set
        .contours
        .iter()
        .enumerate()
        .filter(|(_, c)| c.id.starts_with("sax"))
        .map(|(k, c)| {
            let n = c.points().count().max(1) as f64;
            (k, c.points().map(|p| p.dot(&axis)).sum::<f64>() / n)
        })
        .collect();
    sax.sort_by(|a, b| b.1.total_cmp(&a.1));
    let dropped: Vec<usize> = sax.iter().take(case.drop).map(|x| x.0).collect();
    let ids: Vec<String> = dropped
        .iter()
        .map(|&k| set.contours[k].id.clone())
        .collect();
    set.contours.retain(|c| !ids.contains(&c.id));
    let lax_of = |id: &str| id.starts_with("lax");
    let tips0 = base_tips(&set, &axis, &lax_of);
    let laxes: Vec<usize> = set
        .contours
        .iter()
        .enumerate()
        .filter(|(_, c)| lax_of(&c.id))
        .map(|(k, _)| k)
        .collect();
    let mut cut_tips: Vec<Tip> = Vec::new();
    if let Pattern::Cut(which, mm) = &case.pattern {
        for &(view, last) in which {
            let Some(&k) = laxes.get(view) else { continue };
            let Some(t) = tips0.iter().find(|t| t.contour == k && t.last == last) else {
                continue;
            };
            cut_tips.push(*t);
            let c = &mut set.contours[k];
            if let Some(piece) = c.pieces.first_mut() {
                cut(&mut piece.points, last, *mm, &axis);
            }
        }
    }
    if let Ok(dir) = std::env::var("DUMP") {
        let stem = format!(
            "{dir}/{}-{}-d{}",
            case.truth_name,
            case.pattern.name(),
            case.drop
        );
        std::fs::write(
            format!("{stem}.csv"),
            heartmesh_core::io::csv::write_csv(&set, None)?,
        )?;
        std::fs::write(
            format!("{stem}-truth.obj"),
            io::write_mesh(&truth, io::MeshFormat::Obj, None, "")?,
        )?;
    }
    let rec = reconstruct(&set, None)?;
    let top = rec
        .slice_heights()
        .into_iter()
        .fold(f64::NEG_INFINITY, f64::max);
    let raxis = rec.long_axis().normalize();
    let clip = Plane::new(raxis * top, raxis).ok_or("clip")?;
    let mesh = rec.mesh();
    let r = compare(&truth, mesh, Some(&clip))?;
    let above = Plane::new(raxis * top, -raxis).ok_or("clip")?;
    let bvh = Bvh::build(mesh);
    let band = directed(&truth, mesh, &bvh, Some(&above)).ok();
    let lid = rec.end_cap_points();
    let plane = lid_plane(&lid, &raxis, top + 1e-3);
    let lid_at = |p: &Vec3| plane.as_ref().map_or(f64::NAN, |f| f(p) - p.dot(&raxis));
    let kept: Vec<&Tip> = tips0
        .iter()
        .filter(|t| {
            !cut_tips
                .iter()
                .any(|c| c.contour == t.contour && c.last == t.last)
        })
        .collect();
    let maxf = |v: &mut dyn Iterator<Item = f64>| v.fold(f64::NAN, f64::max);
    // The lowest lid over a cut tip's original position (the deepest dip).
    let lid_cut = cut_tips
        .iter()
        .map(|t| lid_at(&t.point))
        .fold(f64::NAN, f64::min);
    let lid_kept: Vec<f64> = kept.iter().map(|t| lid_at(&t.point)).collect();
    let out = |t: &Tip| signed(&bvh, mesh, &t.point);
    let closed = close_small_holes(&truth, 1e9).0;
    let vt = closed.volume_ml();
    let vm = mesh.volume_ml();
    let past = rec.past_data();
    let tpast = rec.past_data_of(&truth.positions);
    let q = heartmesh_core::mesh::quality::quality(mesh);
    let band_h = band
        .as_ref()
        .map_or(f64::NAN, |b| Vec3::from(b.max_at).dot(&raxis) - top);
    Ok(format!(
        "{},{},{},{},{},{},{:.3},{:.3},{:.3},{:.3},{:.3},{:.3},{:.4},{:.3},{:.4},{:.3},{:.3},{:.2},{:.3},{:.3},{:.3},{:.2},{:.2},{:.2},{:.2},{:.2},{:.2},{}",
        case.truth_name,
        case.pattern.name(),
        case.drop,
        case.seed,
        lid.len(),
        kept.len(),
        lid_cut,
        maxf(&mut lid_kept.iter().copied()),
        lid_kept.iter().sum::<f64>() / lid_kept.len().max(1) as f64,
        cut_tips.iter().map(out).fold(f64::NAN, f64::max),
        maxf(&mut kept.iter().map(|t| out(t))),
        maxf(&mut tips0.iter().map(out)),
        r.mesh_to_truth.mean,
        r.mesh_to_truth.max,
        r.truth_to_mesh.mean,
        r.truth_to_mesh.max,
        r.hausdorff,
        100.0 * (r.volume_mesh_ml - r.volume_truth_ml) / r.volume_truth_ml,
        band.as_ref().map_or(f64::NAN, |b| b.mean),
        band.as_ref().map_or(f64::NAN, |b| b.p95),
        band.as_ref().map_or(f64::NAN, |b| b.max),
        band_h,
        past.map_or(f64::NAN, |p| p.base_mm),
        tpast.map_or(f64::NAN, |p| p.base_mm),
        vm,
        vt,
        100.0 * (vm - vt) / vt,
        q.folded_edges
    ))
}

const SHAPES: [&str; 5] = [
    "parametric",
    "cap-atlas-mean-ED-LV_ENDO-open.obj",
    "cap-atlas-mean-ED-LV_EPI-open.obj",
    "cardiomesh-spasm-LV_endo.obj",
    "cardiomesh-spasm-LV_epi.obj",
];

fn short(name: &str) -> String {
    match name {
        "parametric" => "param".into(),
        "cap-atlas-mean-ED-LV_ENDO-open.obj" => "cap-endo".into(),
        "cap-atlas-mean-ED-LV_EPI-open.obj" => "cap-epi".into(),
        "cardiomesh-spasm-LV_endo.obj" => "spasm-endo".into(),
        "cardiomesh-spasm-LV_epi.obj" => "spasm-epi".into(),
        other => other.into(),
    }
}

fn family(n: usize, seed: u64) -> Res<()> {
    let truths: Vec<TriMesh> = SHAPES.iter().map(|s| truth(s)).collect::<Res<_>>()?;
    let mut rng = Prng::new(seed);
    println!("case,{}", header());
    for i in 0..n {
        let s = (rng.next_f64() * SHAPES.len() as f64) as usize % SHAPES.len();
        let drop = if std::env::var("USUAL").is_ok() {
            (rng.next_f64() * 3.0) as usize % 3
        } else {
            1 + (rng.next_f64() * 2.0) as usize % 2
        };
        let turn = rng.uniform(0.0, 180.0);
        let mm = rng.uniform(5.0, 25.0);
        let view = (rng.next_f64() * 3.0) as usize % 3;
        let other = (view + 1 + (rng.next_f64() * 2.0) as usize % 2) % 3;
        let end = rng.next_f64() < 0.5;
        let kind = if std::env::var("USUAL").is_ok() {
            2.0
        } else {
            rng.next_f64()
        };
        let pattern = if kind > 1.5 {
            Pattern::None
        } else if kind < 0.3 {
            Pattern::Cut(vec![(view, end)], mm)
        } else if kind < 0.55 {
            Pattern::Cut(vec![(view, end), (other, rng.next_f64() < 0.5)], mm)
        } else if kind < 0.8 {
            Pattern::Cut(vec![(view, false), (view, true)], mm)
        } else {
            Pattern::Tilt(rng.uniform(10.0, 30.0))
        };
        let case = Case {
            truth_name: short(SHAPES[s]),
            truth: truths[s].clone(),
            drop,
            turn_deg: turn,
            pattern,
            seed: seed * 1000 + i as u64,
        };
        match run_case(&case) {
            Ok(row) => println!("{i},{row}"),
            Err(e) => println!("{i},{},{},error {e}", case.truth_name, case.pattern.name()),
        }
    }
    Ok(())
}

fn sweep(name: &str, drop: usize) -> Res<()> {
    let t = truth(name)?;
    println!("{}", header());
    let mut patterns = vec![Pattern::None];
    for mm in [5.0, 10.0, 15.0, 20.0, 25.0] {
        patterns.push(Pattern::Cut(vec![(0, true)], mm));
        patterns.push(Pattern::Cut(vec![(0, true), (1, false)], mm));
        patterns.push(Pattern::Cut(vec![(2, false), (2, true)], mm));
    }
    for d in [10.0, 20.0, 30.0] {
        patterns.push(Pattern::Tilt(d));
    }
    for pattern in patterns {
        let case = Case {
            truth_name: short(name),
            truth: t.clone(),
            drop,
            turn_deg: 0.0,
            pattern,
            seed: 1,
        };
        match run_case(&case) {
            Ok(row) => println!("{row}"),
            Err(e) => println!("{},{},error {e}", case.truth_name, case.pattern.name()),
        }
    }
    Ok(())
}

fn main() -> Res<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(|s| s.as_str()) {
        Some("real") => real(
            args.get(1).ok_or("real FILE [SURFACE]")?,
            args.get(2).cloned(),
        ),
        Some("family") => family(
            args.get(1).map_or(Ok(60), |s| s.parse())?,
            args.get(2).map_or(Ok(1), |s| s.parse())?,
        ),
        Some("sweep") => sweep(
            args.get(1).map_or("parametric", |s| s.as_str()),
            args.get(2).map_or(Ok(1), |s| s.parse())?,
        ),
        _ => Err(
            "usage: uneven_tips real FILE [SURFACE] | family [N] [SEED] | sweep TRUTH DROP".into(),
        ),
    }
}
