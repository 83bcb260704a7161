//! Developer tool (session 9 study, docs/VALIDATION.md "overrun past the data"): where does a
//! mesh run on past the last contour data along the long axis? Runs one contour file step by step
//! and, at every remesh, replays that remesh's stages on the mesh of the step before it (the
//! pipeline remeshes after one more deformation step, so the replay is one step early), printing
//! how far the mesh reaches past the highest / lowest contour point along the long axis (its
//! farthest vertex: the cap's top where no curve closes an end) after each stage:
//! subdivision, Laplacian smoothing, the affine shrink correction (with its axial and radial
//! scale), the decimation; then the pipeline's own mesh after the remesh step and after the
//! deformation steps up to the next remesh. Column `span`: the same affine correction fitted only
//! on the vertices within the data's axial span (applied to all), for comparison.
//! `cargo run --release --example overrun -- FILE [SURFACE]`
use heartmesh_core::geometry::Vec3;
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::refine::{affine_fit, decimate, laplacian, subdivide};
use heartmesh_core::{io, Params, Reconstruction};
use nalgebra::{Matrix3x4, Vector4};

type Res<T> = Result<T, Box<dyn std::error::Error>>;

/// How far the points reach past the data along `axis`: (above the top, below the bottom), mm.
fn past(points: &[Vec3], axis: &Vec3, (lo, hi): (f64, f64)) -> (f64, f64) {
    let (mut a, mut b) = (f64::NEG_INFINITY, f64::INFINITY);
    for p in points {
        let t = p.dot(axis);
        a = a.max(t);
        b = b.min(t);
    }
    (a - hi, lo - b)
}

fn apply(map: &Matrix3x4<f64>, points: &[Vec3]) -> Vec<Vec3> {
    points
        .iter()
        .map(|p| map * Vector4::new(p.x, p.y, p.z, 1.0))
        .collect()
}

/// The map's scale along the axis and its mean scale across it.
fn scales(map: &Matrix3x4<f64>, axis: &Vec3) -> (f64, f64) {
    let lin = map.fixed_view::<3, 3>(0, 0);
    let a = axis.dot(&(lin * axis));
    let helper = if axis.x.abs() < 0.9 {
        Vec3::x()
    } else {
        Vec3::y()
    };
    let u = axis.cross(&helper).normalize();
    let v = axis.cross(&u);
    (a, 0.5 * (u.dot(&(lin * u)) + v.dot(&(lin * v))))
}

fn fmt((top, bottom): (f64, f64)) -> String {
    format!("{top:+6.2}/{bottom:+6.2}")
}

/// One remesh replayed stage by stage on `mesh` (mm); returns the decimated result.
fn replay(mesh: &TriMesh, p: &Params, axis: &Vec3, span: (f64, f64)) -> Res<TriMesh> {
    let sub = subdivide(mesh)?;
    let lap = laplacian(&sub, p.smoothing_iterations, p.smoothing_factor)?;
    let map = affine_fit(&lap.positions, &sub.positions).ok_or("no affine map")?;
    let aff = apply(&map, &lap.positions);
    let (sa, sr) = scales(&map, axis);
    // The same correction fitted inside the data's axial span only.
    let inside: Vec<usize> = (0..sub.positions.len())
        .filter(|&i| {
            let t = sub.positions[i].dot(axis);
            t >= span.0 && t <= span.1
        })
        .collect();
    let pick = |v: &[Vec3]| inside.iter().map(|&i| v[i]).collect::<Vec<_>>();
    let span_map = affine_fit(&pick(&lap.positions), &pick(&sub.positions));
    let span_past = span_map.map(|m| past(&apply(&m, &lap.positions), axis, span));
    let dec = decimate(
        &TriMesh {
            positions: aff.clone(),
            triangles: lap.triangles.clone(),
        },
        p.target_reduction,
    )?;
    print!(
        "{} | {} | {} | {} ax {:.4} rad {:.4} | {} | span {}",
        fmt(past(&mesh.positions, axis, span)),
        fmt(past(&sub.positions, axis, span)),
        fmt(past(&lap.positions, axis, span)),
        fmt(past(&aff, axis, span)),
        sa,
        sr,
        fmt(past(&dec.positions, axis, span)),
        span_past.map(fmt).unwrap_or_else(|| "-".into()),
    );
    Ok(dec)
}

fn run() -> Res<()> {
    let args: Vec<String> = std::env::args().collect();
    let path = args.get(1).ok_or("usage: overrun FILE [SURFACE]")?;
    let set = io::read_contours(path, &std::fs::read(path)?)?;
    let params = Params {
        surface: args.get(2).cloned(),
        ..Params::default()
    };
    let mut r = Reconstruction::new(&set, params.clone())?;
    let axis = r.long_axis().normalize();
    let heights: Vec<f64> = r
        .contours()
        .iter()
        .flat_map(|c| c.points().map(|p| p.dot(&axis)).collect::<Vec<_>>())
        .collect();
    let lo = heights.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = heights.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let span = (lo, hi);
    println!("past the data top/bottom (mm) at each stage of each remesh");
    println!("it | before | subdivided | laplacian | affine (scales) | decimated | span-fitted affine | pipeline after step | before next remesh");
    let mut prev: Option<TriMesh> = None;
    let mut pending = false;
    while !r.is_done() {
        let s = r.step()?;
        let now = past(&r.mesh().positions, &axis, span);
        if s.topology_changed {
            if pending {
                println!();
            }
            print!("{:3} | ", s.iteration);
            match &prev {
                Some(m) => {
                    replay(m, &params, &axis, span)?;
                }
                None => print!("(initial tube: lids at the end rings' planes)"),
            }
            print!(" | {}", fmt(now));
            pending = true;
        }
        if s.done {
            print!(" | end {}", fmt(now));
        }
        prev = Some(r.mesh().clone());
        // The step before the next remesh (or the last step) closes the line.
        if pending && !s.topology_changed && (s.iteration + 1) % params.remesh_every == 0 {
            print!(" | {}", fmt(now));
        }
    }
    println!();
    println!(
        "final: past top {:+.2} mm, past bottom {:+.2} mm, volume {:.2} ml",
        past(&r.mesh().positions, &axis, span).0,
        past(&r.mesh().positions, &axis, span).1,
        r.mesh().volume_ml()
    );
    Ok(())
}

fn main() {
    if let Err(e) = run() {
        eprintln!("overrun: {e}");
        std::process::exit(1);
    }
}
