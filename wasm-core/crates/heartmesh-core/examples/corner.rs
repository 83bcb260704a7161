//! Developer tool (session 11, docs/VALIDATION.md "Session 11: the cap-to-wall corner"): where
//! and which way do `--end-caps auto` and `off` differ near the basal SAX plane? Slices a truth
//! like tests/accuracy.rs (10 mm SAX stack + 3 LAX), reconstructs with both, and prints per band
//! of depth below the clip plane (the most basal SAX plane) the truth->mesh max and mean signed
//! distance (+: truth outside the mesh, the mesh pulled in; -: the mesh pushed out past the truth),
//! and the lid's height.
//! Also the radial profile through the worst truth->mesh point: mesh minus truth radius at every
//! mm of height from 12 below to 10 above the clip plane (`m`/`t`: only the mesh / truth there).
//! `cargo run --release --example corner -- parametric|FILE.obj [misaligned]`
use heartmesh_core::geometry::Vec3;
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::metrics::compare::compare;
use heartmesh_core::params::EndCapMode;
use heartmesh_core::sim::repair::{orient_consistently, weld};
use heartmesh_core::sim::shapes::ParametricLv;
use heartmesh_core::sim::{simulate, AcquisitionSpec, Misalignment};
use heartmesh_core::spatial::Bvh;
use heartmesh_core::{io, Params, Reconstruction};

#[path = "shared/probe_mesh.rs"]
mod probe_mesh;
use probe_mesh::signed;

type Res<T> = Result<T, Box<dyn std::error::Error>>;

fn truth(arg: &str) -> Res<TriMesh> {
    if arg == "parametric" {
        return Ok(ParametricLv::bulged_truth()?);
    }
    let bytes = std::fs::read(arg)?;
    let m = io::read_mesh(arg, &bytes)?.mesh;
    Ok(orient_consistently(&weld(&m, 1e-6).0).0)
}

fn run(set: &heartmesh_core::contours::ContourSet, mode: EndCapMode) -> Res<(TriMesh, Vec<Vec3>)> {
    let params = Params {
        end_caps: mode,
        ..Params::default()
    };
    let mut rec = Reconstruction::new(set, params)?;
    while !rec.step()?.done {}
    Ok((rec.mesh().clone(), rec.end_cap_points()))
}

/// Farthest hit of the ray from `o` along `u` with `mesh` (distance along u), brute force.
fn ray(mesh: &TriMesh, o: &Vec3, u: &Vec3) -> Option<f64> {
    probe_mesh::hits(mesh, o, u).reduce(f64::max)
}

fn main() -> Res<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let t = truth(args.first().map_or("parametric", |s| s.as_str()))?;
    let misaligned = args.iter().any(|a| a == "misaligned");
    let spec = AcquisitionSpec {
        lax_count: 3,
        misalignment: misaligned.then_some(Misalignment {
            shift_mm: 2.0,
            tilt_deg: 2.0,
        }),
        seed: 1,
        ..AcquisitionSpec::default()
    };
    let acq = simulate(&t, &spec)?;
    let clip = acq.clip;
    let (lo, hi, _) = acq.axis.extent(&t).ok_or("extent")?;
    let clip_h = acq.axis.height(&clip.origin);
    println!(
        "truth: apex {:.2} top {:.2} mm (relative to the clip plane); clip at height {:.3}",
        lo - clip_h,
        hi - clip_h,
        (clip_h - lo) / (hi - lo)
    );
    let bands = [
        (-1e9, 0.0),
        (0.0, 1.0),
        (1.0, 2.0),
        (2.0, 4.0),
        (4.0, 7.0),
        (7.0, 12.0),
        (12.0, 1e9),
    ];
    for mode in [EndCapMode::Off, EndCapMode::Auto] {
        let (mesh, lid) = run(&acq.contours, mode)?;
        let r = compare(&t, &mesh, Some(&clip))?;
        let bvh = Bvh::build(&mesh);
        let top = mesh
            .positions
            .iter()
            .map(|p| acq.axis.height(p))
            .fold(f64::MIN, f64::max);
        let lid_h: Vec<f64> = lid.iter().map(|p| acq.axis.height(p) - clip_h).collect();
        let lid_range = if lid_h.is_empty() {
            "none".to_string()
        } else {
            let (lo, hi) = lid_h
                .iter()
                .fold((f64::MAX, f64::MIN), |a, &h| (a.0.min(h), a.1.max(h)));
            format!("{} pts {lo:+.2}..{hi:+.2} mm", lid_h.len())
        };
        let w = Vec3::from(r.truth_to_mesh.max_at);
        let m = Vec3::from(r.mesh_to_truth.max_at);
        println!(
            "{}: m2t mean {:.4} max {:.3} at {:+.2} mm; t2m mean {:.4} max {:.3} at {:+.2} mm (signed {:+.3}); mesh top {:+.2}; lid {}",
            mode.name(),
            r.mesh_to_truth.mean,
            r.mesh_to_truth.max,
            acq.axis.height(&m) - clip_h,
            r.truth_to_mesh.mean,
            r.truth_to_mesh.max,
            acq.axis.height(&w) - clip_h,
            signed(&bvh, &mesh, &w),
            top - clip_h,
            lid_range
        );
        // Radial profile through the worst truth->mesh point: truth and mesh radius per height.
        let dir = acq.axis.direction;
        let base =
            acq.axis.centre + dir * (acq.axis.height(&w) - acq.axis.height(&acq.axis.centre));
        let radial = w - base;
        let u = radial - dir * radial.dot(&dir);
        let u = u.normalize();
        let mut line = String::new();
        for k in -12..=10 {
            let h = k as f64;
            let o = acq.axis.centre + dir * (clip_h + h - acq.axis.height(&acq.axis.centre));
            let rt = ray(&t, &o, &u);
            let rm = ray(&mesh, &o, &u);
            match (rt, rm) {
                (Some(a), Some(b)) => line += &format!(" {k:+}:{:+.2}", b - a),
                (None, Some(b)) => line += &format!(" {k:+}:m{b:.1}"),
                (Some(a), None) => line += &format!(" {k:+}:t{a:.1}"),
                _ => {}
            }
        }
        println!("  profile (height: mesh - truth radius, mm):{line}");
        for (a, b) in bands {
            // Depth below the clip plane: band (a, b] of -signed distance.
            let s: Vec<f64> = t
                .positions
                .iter()
                .filter(|p| {
                    let d = -clip.signed_distance(p);
                    d > a && d <= b
                })
                .map(|p| signed(&bvh, &mesh, p))
                .collect();
            if s.is_empty() {
                continue;
            }
            let mx = s
                .iter()
                .cloned()
                .fold(0.0f64, |x, y| if y.abs() > x.abs() { y } else { x });
            let mean = s.iter().sum::<f64>() / s.len() as f64;
            println!(
                "  depth ({:>5}, {:>5}] mm: {:5} truth vertices, signed mean {:+.3}, worst {:+.3}",
                if a < -1e8 {
                    "-inf".into()
                } else {
                    format!("{a}")
                },
                if b > 1e8 {
                    "inf".into()
                } else {
                    format!("{b}")
                },
                s.len(),
                mean,
                mx
            );
        }
    }
    Ok(())
}
