//! Developer tool for the accuracy cases (tests/accuracy.rs): slice a reference shape as the tests
//! do, reconstruct, and show WHERE the error is and whether the contours hold the information.
//! `cargo run --release --example probe -- CASE [iterations]`
//! CASE: bivme-lv | cap-endo | cap-epi | spasm-endo | spasm-epi | bivme-rv | spasm-rv | param
//!       (suffix `-mis` for the 2 mm / 2 degree misaligned acquisition, seed 1..3 as in the tests).
//! PROBE_POP=SEED:K: the case's shape as member K of the population drawn with SEED
//! (`heartmesh experiment population --seed SEED`, member `pK-...` of that base; misaligned with
//! seed SEED + K as there).
//! PROBE_METHOD=NAME: the remesh smoothing method (`--smoothing-method` of the CLI).
use heartmesh_core::geometry::Vec3;
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::metrics::compare::compare;
use heartmesh_core::sim::repair::{orient_consistently, weld};
use heartmesh_core::sim::{simulate, slice_mesh, AcquisitionSpec, LongAxis, Misalignment};
use heartmesh_core::spatial::Bvh;
use heartmesh_core::{io, Params, Reconstruction};
use std::path::PathBuf;

mod folds;

fn data(sub: &str) -> PathBuf {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    manifest
        .ancestors()
        .map(|a| a.join("shared/data"))
        .find(|d| d.is_dir())
        .unwrap_or_default()
        .join(sub)
}

type Res<T> = Result<T, Box<dyn std::error::Error>>;

fn truth(name: &str) -> Res<TriMesh> {
    let bytes = std::fs::read(data(&format!("meshes/{name}")))?;
    let m = io::read_mesh(name, &bytes)?.mesh;
    Ok(orient_consistently(&weld(&m, 1e-6).0).0)
}

type Case = (TriMesh, usize, Option<(LongAxis, Vec3)>);

/// An LV case: 3 LAX, planned on the shape's own axis.
fn lv(t: TriMesh) -> Case {
    (t, 3, None)
}

/// An RV case: SAX planned on the LV's axis, one LAX through that axis and the RV centre.
fn rv(t: TriMesh, lv_file: &str) -> Res<Case> {
    let axis = heartmesh_core::sim::planes::anatomical_axis(&truth(lv_file)?, 3.0)?;
    let c = heartmesh_core::sim::axis::area_centroid(&t)?.0;
    let r = c - axis.centre;
    Ok((t, 1, Some((axis, r))))
}

fn main() {
    if let Err(e) = run() {
        eprintln!("probe: {e}");
        std::process::exit(1);
    }
}

fn run() -> Res<()> {
    let args: Vec<String> = std::env::args().collect();
    let case = args.get(1).cloned().unwrap_or_else(|| "spasm-epi".into());
    let iterations: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(250);
    let (base, mis) = match case.strip_suffix("-mis") {
        Some(b) => (b.to_string(), true),
        None => (case.clone(), false),
    };
    let (t, lax, rvax) = match base.as_str() {
        "bivme-lv" => lv(truth("bivme-patient1-ED-LV_ENDO-closed.obj")?),
        "cap-endo" => lv(truth("cap-atlas-mean-ED-LV_ENDO-open.obj")?),
        "cap-epi" => lv(truth("cap-atlas-mean-ED-LV_EPI-open.obj")?),
        "spasm-endo" => lv(truth("cardiomesh-spasm-LV_endo.obj")?),
        "spasm-epi" => lv(truth("cardiomesh-spasm-LV_epi.obj")?),
        "bivme-rv" => rv(
            truth("bivme-patient1-ED-RV_ENDO-closed.obj")?,
            "bivme-patient1-ED-LV_ENDO-closed.obj",
        )?,
        "spasm-rv" => rv(
            heartmesh_core::sim::cavity::rv_cavity(
                &truth("cardiomesh-spasm-RV_endo.obj")?,
                &truth("cardiomesh-spasm-LV_epi.obj")?,
                40.0,
            )?,
            "cardiomesh-spasm-LV_endo.obj",
        )?,
        "param" => lv(heartmesh_core::sim::shapes::ParametricLv::bulged_truth()?),
        other => return Err(format!("unknown case {other}").into()),
    };
    let mut seed = match base.as_str() {
        "cap-endo" => 1,
        "spasm-epi" => 2,
        _ => 3,
    };
    let (t, rvax) = match std::env::var("PROBE_POP") {
        Ok(v) => {
            use heartmesh_core::sim::population::{generate, Base, Plan, Source};
            let (s, k) = v.split_once(':').ok_or("PROBE_POP=SEED:K")?;
            let (s, k): (u64, usize) = (s.parse()?, k.parse()?);
            let plan = match rvax {
                Some(_) => Plan::Rv {
                    lv: truth(match base.as_str() {
                        "bivme-rv" => "bivme-patient1-ED-LV_ENDO-closed.obj",
                        _ => "cardiomesh-spasm-LV_endo.obj",
                    })?,
                },
                None => Plan::Lv,
            };
            let source = match base.as_str() {
                "param" => Source::Parametric,
                _ => Source::Mesh(t),
            };
            let members = generate(
                &[Base {
                    name: base.clone(),
                    source,
                    plan,
                }],
                k + 1,
                s,
            )?;
            let m = members.last().ok_or("no member")?;
            println!("member {} variation {:?}", m.subject.name, m.variation);
            seed = s + k as u64;
            let sub = &m.subject;
            let rvax = sub
                .base
                .axis
                .zip(sub.base.lax_reference)
                .filter(|_| rvax.is_some());
            (sub.mesh.clone(), rvax)
        }
        Err(_) => (t, rvax),
    };
    let spec = AcquisitionSpec {
        axis: rvax.map(|r| r.0),
        lax_reference: rvax.map(|r| r.1),
        join_gap_mm: if rvax.is_some() { 6.0 } else { 3.0 },
        misalignment: mis.then_some(Misalignment {
            shift_mm: 2.0,
            tilt_deg: 2.0,
        }),
        seed: if mis { seed } else { 1 },
        // PROBE_SAX=5: a denser stack, to tell an information limit from a fitting error.
        sax: heartmesh_core::sim::planes::SaxStack::SpacingMm(
            std::env::var("PROBE_SAX")
                .ok()
                .and_then(|s| s.parse().ok())
                .unwrap_or(10.0),
        ),
        lax_count: std::env::var("PROBE_LAX")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(lax),
        ..AcquisitionSpec::default()
    };
    let acq = simulate(&t, &spec)?;
    if std::env::var("PROBE_SECTIONS").is_ok() {
        use heartmesh_core::sim::slice::{join_chains, polyline_length, Plane};
        let (lo, hi, _) = acq.axis.extent(&t).ok_or("no extent")?;
        let mut h = lo + 0.5;
        while h < hi {
            let plane = Plane {
                origin: acq.axis.centre + acq.axis.direction * h,
                normal: acq.axis.direction,
            };
            let pieces = join_chains(slice_mesh(&t, &plane), spec.join_gap_mm, &plane);
            let d: Vec<String> = pieces
                .iter()
                .map(|p| {
                    format!(
                        "{:.0}{}",
                        polyline_length(p),
                        if p.closed { "c" } else { "o" }
                    )
                })
                .collect();
            println!("section {:.1}: {}", h - lo, d.join(" "));
            h += 2.0;
        }
    }
    let mut params = Params {
        iterations,
        ..Params::default()
    };
    for kv in std::env::var("PROBE_PARAMS").unwrap_or_default().split(',') {
        let Some((k, v)) = kv.split_once('=') else {
            continue;
        };
        let f: f64 = v.parse()?;
        match k {
            "remesh_every" => params.remesh_every = f as usize,
            "resample" => params.resample_attractors_every = f as usize,
            "attractors" => params.attractors = heartmesh_core::AttractorMode::Count(f as usize),
            "spacing" => params.attractors = heartmesh_core::AttractorMode::SpacingMm(f),
            "lambda" => params.lambda = f,
            "beta" => params.beta = f,
            "smooth" => params.smoothing_iterations = f as usize,
            "soften" => params.soften_conflicts = f != 0.0,
            _ => return Err(format!("unknown param {k}").into()),
        }
    }
    if let Ok(m) = std::env::var("PROBE_METHOD") {
        params.set_smoothing_method(&m)?;
    }
    let mut rec = Reconstruction::new(&acq.contours, params)?;
    let (lo0, _, _) = acq.axis.extent(&t).ok_or("no extent")?;
    let t0 = std::time::Instant::now();
    let trace_folds = std::env::var("PROBE_FOLDS").is_ok();
    let mut snaps: Vec<folds::Snapshot> = Vec::new();
    while !rec.is_done() {
        let s = rec.step()?;
        if trace_folds {
            let q = heartmesh_core::mesh::quality::quality(rec.mesh());
            if q.folded_edges > 0 || s.topology_changed {
                println!(
                    "  step {} {:?}: folds {} max dihedral {:.0}",
                    s.iteration, s.phase, q.folded_edges, q.max_dihedral_deg
                );
            }
        }
        if std::env::var("PROBE_STAGES")
            .ok()
            .and_then(|v| v.parse().ok())
            == Some(s.iteration)
        {
            folds::stages(rec.mesh())?;
        }
        if trace_folds && s.iteration + 50 >= iterations {
            snaps.push(folds::Snapshot {
                iteration: s.iteration,
                mesh: rec.mesh().clone(),
                attractors: rec.attractors(),
            });
        }
        if s.iteration.is_multiple_of(10) || s.done || s.iteration < 3 {
            let low = rec
                .mesh()
                .positions
                .iter()
                .map(|p| acq.axis.height(p) - lo0)
                .fold(f64::INFINITY, f64::min);
            println!(
                "it {:3} {:?} attractor max {:.3} mean {:.3} mesh low {low:.1}",
                s.iteration, s.phase, s.max_distance_mm, s.mean_distance_mm
            );
        }
    }
    let secs = t0.elapsed().as_secs_f64();
    if trace_folds {
        let tagged: Vec<(Vec3, bool)> = acq
            .contours
            .contours
            .iter()
            .flat_map(|c| c.points().map(move |p| (*p, c.id.starts_with("lax"))))
            .collect();
        let kind_of = |q: &Vec3| {
            tagged
                .iter()
                .min_by(|a, b| (a.0 - q).norm().total_cmp(&(b.0 - q).norm()))
                .is_some_and(|t| t.1)
        };
        let (lo, _, _) = acq.axis.extent(&t).ok_or("no extent")?;
        folds::report(&snaps, &kind_of, &|p| acq.axis.height(p) - lo);
    }
    let mut mesh = rec.mesh().clone();
    if std::env::var("PROBE_SUBDIV").is_ok() {
        mesh = heartmesh_core::refine::subdivide(&mesh)?;
    }
    let r = compare(&t, &mesh, Some(&acq.clip))?;
    {
        use heartmesh_core::mesh::quality::{dihedral_deg, face_normals, quality, FOLD_DEG};
        use heartmesh_core::mesh::topology::EdgeMap;
        let q = quality(&mesh);
        let qt = quality(&t);
        println!(
            "folds {} (max dihedral {:.0} deg); {} vertices; truth folds {} (max dihedral {:.0})",
            q.folded_edges,
            q.max_dihedral_deg,
            mesh.positions.len(),
            qt.folded_edges,
            qt.max_dihedral_deg
        );
        // Where the folds are: height, nearest contour point, and the truth's own sharpest
        // dihedral within 5 mm (a fold on a creased truth is faithful, not a defect).
        let (map, normals) = (EdgeMap::new(&mesh), face_normals(&mesh));
        let (tmap, tnormals) = (EdgeMap::new(&t), face_normals(&t));
        let tsharp: Vec<(Vec3, f64)> = (0..tmap.edges.len())
            .filter_map(|e| {
                let a = dihedral_deg(&tmap, &tnormals, e)?;
                let [u, v] = tmap.edges[e];
                Some(((t.positions[u as usize] + t.positions[v as usize]) * 0.5, a))
            })
            .collect();
        let pts = acq.contours.all_points();
        let w = r.truth_to_mesh.max_at;
        let w = Vec3::new(w[0], w[1], w[2]);
        let sharp_near = |radius: f64| {
            tsharp
                .iter()
                .filter(|(p, _)| (p - w).norm() < radius)
                .map(|(_, a)| *a)
                .fold(0.0, f64::max)
        };
        println!(
            "  truth's sharpest dihedral near the worst truth point: {:.0} deg within 3 mm, {:.0} within 6 mm",
            sharp_near(3.0),
            sharp_near(6.0)
        );
        for e in 0..map.edges.len() {
            let Some(a) = dihedral_deg(&map, &normals, e) else {
                continue;
            };
            if a <= FOLD_DEG {
                continue;
            }
            let [u, v] = map.edges[e];
            let m = (mesh.positions[u as usize] + mesh.positions[v as usize]) * 0.5;
            let near = pts
                .iter()
                .map(|p| (p - m).norm())
                .fold(f64::INFINITY, f64::min);
            let sharp = tsharp
                .iter()
                .filter(|(p, _)| (p - m).norm() < 5.0)
                .map(|(_, a)| *a)
                .fold(0.0, f64::max);
            let (lo, _, _) = acq.axis.extent(&t).ok_or("no extent")?;
            let turn = folds::sharpest_turn(&acq.contours, &m, 5.0);
            println!(
                "  fold {a:.0} deg at h {:.1} mm; nearest contour point {near:.2} mm; truth's sharpest dihedral within 5 mm {sharp:.0} deg; contours' sharpest turn within 5 mm {turn:.0} deg",
                acq.axis.height(&m) - lo
            );
        }
    }
    let (lo, hi, _) = acq.axis.extent(&t).ok_or("no extent")?;
    let hfrac = |p: &Vec3| (acq.axis.height(p) - lo) / (hi - lo);
    println!(
        "{case}: m->t mean {:.3} max {:.3}; t->m mean {:.3} max {:.3}; vol {:.2}/{:.2} ml; {:.2} s",
        r.mesh_to_truth.mean,
        r.mesh_to_truth.max,
        r.truth_to_mesh.mean,
        r.truth_to_mesh.max,
        r.volume_truth_ml,
        r.volume_mesh_ml,
        secs
    );
    {
        let m = r.mesh_to_truth.max_at;
        let m = Vec3::new(m[0], m[1], m[2]);
        let near_t = (0..mesh.triangles.len())
            .min_by(|&a, &b| {
                let c = |t: usize| mesh.corners(t).iter().fold(Vec3::zeros(), |s, p| s + p) / 3.0;
                (c(a) - m).norm().total_cmp(&(c(b) - m).norm())
            })
            .unwrap_or(0);
        let [a, b, c] = mesh.corners(near_t);
        println!(
            "  mesh->truth max at h {:.1} mm; nearest triangle edges {:.1} {:.1} {:.1} mm; mean edge {:.2} mm",
            acq.axis.height(&m) - lo,
            (a - b).norm(),
            (b - c).norm(),
            (c - a).norm(),
            {
                let mut s = 0.0;
                for t in 0..mesh.triangles.len() {
                    let [a, b, c] = mesh.corners(t);
                    s += (a - b).norm() + (b - c).norm() + (c - a).norm();
                }
                s / (3 * mesh.triangles.len()).max(1) as f64
            }
        );
    }
    let sax_h: Vec<f64> = acq
        .sax_planes
        .iter()
        .map(|p| acq.axis.height(&p.origin) - lo)
        .collect();
    println!(
        "shape length {:.1} mm; SAX heights (mm above apex) {:?}",
        hi - lo,
        sax_h
            .iter()
            .map(|h| (h * 10.0).round() / 10.0)
            .collect::<Vec<_>>()
    );
    for c in &acq.contours.contours {
        let hs: Vec<f64> = c.points().map(|p| acq.axis.height(p) - lo).collect();
        let (a, b) = hs
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), h| {
                (a.min(*h), b.max(*h))
            });
        if c.id.starts_with("lax") {
            println!("  {} heights {:.1}..{:.1} mm", c.id, a, b);
        }
    }
    let mh: Vec<f64> = mesh
        .positions
        .iter()
        .map(|p| acq.axis.height(p) - lo)
        .collect();
    println!(
        "  mesh heights {:.1}..{:.1} mm",
        mh.iter().cloned().fold(f64::INFINITY, f64::min),
        mh.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
    );
    let pts = acq.contours.all_points();
    let near_contour = |p: &Vec3| {
        pts.iter()
            .map(|q| (p - q).norm())
            .fold(f64::INFINITY, f64::min)
    };
    if let Ok(file) = std::env::var("PROBE_SECTION") {
        // SVG of the long-axis section through the worst truth point: truth black, mesh red,
        // contour points within 1 mm of the plane blue (SAX) and green (LAX), the point orange.
        use heartmesh_core::sim::slice::Plane;
        let w = r.truth_to_mesh.max_at;
        let w = Vec3::new(w[0], w[1], w[2]);
        let (c, z) = (acq.axis.centre, acq.axis.direction);
        let radial = {
            let v = w - c;
            (v - z * z.dot(&v)).normalize()
        };
        let plane = Plane {
            origin: c,
            normal: z.cross(&radial).normalize(),
        };
        let uv = |p: &Vec3| ((p - c).dot(&radial), -(acq.axis.height(p) - lo));
        let mut svg = String::new();
        let mut all = Vec::new();
        for (m, colour) in [(&t, "black"), (&mesh, "red")] {
            for piece in slice_mesh(m, &plane) {
                let pts: Vec<(f64, f64)> = piece.points.iter().map(&uv).collect();
                all.extend(pts.iter().copied());
                let d: Vec<String> = pts.iter().map(|(x, y)| format!("{x:.2},{y:.2}")).collect();
                svg += &format!(
                    "<polyline points=\"{}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"0.3\"/>\n",
                    d.join(" ")
                );
            }
        }
        for ct in &acq.contours.contours {
            let colour = if ct.id.starts_with("lax") {
                "green"
            } else {
                "blue"
            };
            for p in ct.points().filter(|p| plane.signed_distance(p).abs() < 1.0) {
                let (x, y) = uv(p);
                svg +=
                    &format!("<circle cx=\"{x:.2}\" cy=\"{y:.2}\" r=\"0.4\" fill=\"{colour}\"/>\n");
            }
        }
        let (x, y) = uv(&w);
        svg += &format!(
            "<circle cx=\"{x:.2}\" cy=\"{y:.2}\" r=\"1.5\" fill=\"none\" stroke=\"orange\" stroke-width=\"0.4\"/>\n"
        );
        let (x0, x1, y0, y1) = all.iter().fold(
            (
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ),
            |(a, b, c, d), (x, y)| (a.min(*x), b.max(*x), c.min(*y), d.max(*y)),
        );
        let (wd, ht) = (x1 - x0 + 20.0, y1 - y0 + 20.0);
        let doc = format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"800\" height=\"{:.0}\" viewBox=\"{:.1} {:.1} {wd:.1} {ht:.1}\">\n\
             <rect x=\"{:.1}\" y=\"{:.1}\" width=\"{wd:.1}\" height=\"{ht:.1}\" fill=\"white\"/>\n{svg}\
             <text x=\"{:.1}\" y=\"{:.1}\" font-size=\"{:.2}\">{case}, worst truth point {:.2} mm: truth black, mesh red, SAX blue, LAX green; bar 10 mm</text>\n\
             <line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"black\" stroke-width=\"0.6\"/>\n</svg>\n",
            800.0 * ht / wd,
            x0 - 10.0,
            y0 - 10.0,
            x0 - 10.0,
            y0 - 10.0,
            x0 - 8.0,
            y0 - 6.0,
            wd / 40.0,
            r.truth_to_mesh.max,
            x0 - 8.0,
            y1 + 6.0,
            x0 + 2.0,
            y1 + 6.0,
        );
        std::fs::write(&file, doc)?;
    }
    if std::env::var("PROBE_SIGNED").is_ok() {
        // Truth->mesh signed error (+: truth outside the mesh, i.e. the mesh sags inwards) binned by
        // the truth point's distance to the nearest contour point.
        let bvh = Bvh::build(&mesh);
        let mut bins = [(0usize, 0.0f64, 0.0f64, 0.0f64); 8];
        for p in t
            .positions
            .iter()
            .filter(|p| acq.clip.signed_distance(p) <= 0.0)
        {
            let Some(h) = bvh.closest_point(&mesh, *p) else {
                continue;
            };
            let [a, b, c] = mesh.corners(h.triangle as usize);
            let n = (b - a).cross(&(c - a));
            let d = h.distance_sq.sqrt();
            let s = if (p - h.point).dot(&n) >= 0.0 { d } else { -d };
            let k = (near_contour(p).floor() as usize).min(7);
            bins[k].0 += 1;
            bins[k].1 += s;
            bins[k].2 += d;
            bins[k].3 = bins[k].3.max(d);
        }
        println!("truth->mesh by distance to contours (n, signed mean +out, abs mean, max):");
        for (k, b) in bins.iter().enumerate() {
            if b.0 > 0 {
                println!(
                    "  {k}-{} mm: n {:5} signed {:+.3} abs {:.3} max {:.3}",
                    k + 1,
                    b.0,
                    b.1 / b.0 as f64,
                    b.2 / b.0 as f64,
                    b.3
                );
            }
        }
    }
    // Error by height band, both directions.
    for (label, from, to) in [("truth->mesh", &t, &mesh), ("mesh->truth", &mesh, &t)] {
        let bvh = Bvh::build(to);
        let mut worst: Vec<(f64, Vec3)> = from
            .positions
            .iter()
            .filter(|p| acq.clip.signed_distance(p) <= 0.0)
            .map(|p| {
                (
                    bvh.closest_point(to, *p)
                        .map_or(0.0, |h| h.distance_sq.sqrt()),
                    *p,
                )
            })
            .collect();
        let mut bands = [(0.0f64, 0usize, 0.0f64); 10];
        for (d, p) in &worst {
            let b = ((hfrac(p) * 10.0).floor().clamp(0.0, 9.0)) as usize;
            bands[b].0 += d;
            bands[b].1 += 1;
            bands[b].2 = bands[b].2.max(*d);
        }
        println!("{label} by height (vertex mean / max):");
        for (k, b) in bands.iter().enumerate() {
            if b.1 > 0 {
                println!(
                    "  {:.1}-{:.1}: n {:5} mean {:.3} max {:.3}",
                    k as f64 / 10.0,
                    (k + 1) as f64 / 10.0,
                    b.1,
                    b.0 / b.1 as f64,
                    b.2
                );
            }
        }
        worst.sort_by(|a, b| b.0.total_cmp(&a.0));
        for (d, p) in worst.iter().take(5) {
            let rad = {
                let v = p - acq.axis.centre;
                (v - acq.axis.direction * acq.axis.direction.dot(&v)).norm()
            };
            println!(
                "  worst {d:.3} at h {:.1} mm ({:.2}), radius {rad:.1}; nearest contour point {:.2} mm; [{:.1},{:.1},{:.1}]",
                acq.axis.height(p) - lo,
                hfrac(p),
                near_contour(p),
                p.x,
                p.y,
                p.z
            );
        }
    }
    {
        let bvh = Bvh::build(&mesh);
        let mut all: Vec<(f64, String, Vec3)> = acq
            .contours
            .contours
            .iter()
            .flat_map(|c| c.points().map(move |p| (c.id.clone(), *p)))
            .map(|(id, p)| {
                (
                    bvh.closest_point(&mesh, p)
                        .map_or(0.0, |h| h.distance_sq.sqrt()),
                    id,
                    p,
                )
            })
            .collect();
        all.sort_by(|a, b| b.0.total_cmp(&a.0));
        for (d, id, p) in all.iter().take(8) {
            println!(
                "  c2m worst {d:.3} on {id} at h {:.1} mm ({:.2}) above clip {:.1}",
                acq.axis.height(p) - lo,
                hfrac(p),
                acq.clip.signed_distance(p)
            );
        }
    }
    let d = rec.contour_distances();
    for c in &d.per_contour {
        println!(
            "  {:8} {:?} mean {:.3} max {:.3}",
            c.id, c.kind, c.stats.mean, c.stats.max
        );
    }
    if let Ok(dir) = std::env::var("PROBE_OUT") {
        std::fs::create_dir_all(&dir)?;
        for (m, n) in [(&mesh, "mesh"), (&t, "truth")] {
            let s = heartmesh_core::io::obj::write_obj(m, "probe");
            std::fs::write(format!("{dir}/{case}-{n}.obj"), s)?;
        }
        let csv = heartmesh_core::io::csv::write_csv(&acq.contours, None)?;
        std::fs::write(format!("{dir}/{case}-contours.csv"), csv)?;
    }
    Ok(())
}
