use super::legal::quality;
use super::*;
use crate::mesh::shapes::{cylinder_tube, icosphere};
use crate::mesh::topology::validity;
use crate::refine::butterfly::subdivide;

fn noisy(mut m: TriMesh, amplitude: f64, seed: u64) -> TriMesh {
    let mut state = seed;
    for p in &mut m.positions {
        for c in p.iter_mut() {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            *c += ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 2.0 * amplitude;
        }
    }
    m
}

fn assert_clean(m: &TriMesh, closed: bool, what: &str) {
    let v = validity(m);
    assert!(v.manifold && v.oriented, "{what}: {}", v.describe());
    assert_eq!(v.closed, closed, "{what}: {}", v.describe());
    assert_eq!(v.duplicate_triangles, 0, "{what}");
    assert_eq!(v.unreferenced_vertices, 0, "{what}");
}

#[test]
fn icosphere_keeps_shape_and_topology() {
    let m = icosphere(10.0, 4);
    let d = decimate(&m, 0.72).unwrap();
    assert_clean(&d, true, "icosphere");
    let expected = (0.28 * m.triangles.len() as f64).round() as usize;
    assert!(
        d.triangles.len() <= expected + 2 && d.triangles.len() + 50 > expected,
        "{} triangles, expected ~{expected}",
        d.triangles.len()
    );
    let worst = d
        .positions
        .iter()
        .map(|p| (p.norm() - 10.0).abs())
        .fold(0.0, f64::max);
    assert!(worst < 0.3, "max radius error {worst} mm");
    assert!(d.signed_volume() > 0.0);
    assert_eq!(validity(&d).euler_characteristic, 2);
}

#[test]
fn length_penalty_keeps_edges_even_on_a_tube() {
    // A long tube is flat along its axis: the quadric error is ~0 for every collapse along
    // it, so only the length term decides which go first.
    let m = subdivide(&cylinder_tube(10.0, 60.0, 40, 13, false)).unwrap();
    let stats = |weight: Option<f64>| {
        let centre =
            m.positions.iter().fold(Vec3::zeros(), |s, p| s + p) / m.positions.len() as f64;
        let mut state = Decimator::new(&m, centre, Known::Manifold).unwrap();
        if let Some(w) = weight {
            state.length_weight = w;
        }
        state.run((0.28 * m.triangles.len() as f64).round() as usize);
        let d = state.finish(centre);
        assert_clean(&d, false, "tube");
        let mut longest = 0.0f64;
        let mut worst = 1.0f64;
        for t in 0..d.triangles.len() {
            let c = d.corners(t);
            let n = (c[1] - c[0]).cross(&(c[2] - c[0])).norm();
            worst = worst.min(quality(&c, n));
            for k in 0..3 {
                longest = longest.max((c[(k + 1) % 3] - c[k]).norm());
            }
        }
        (longest, worst)
    };
    let (long_with, worst_with) = stats(None);
    let (long_without, worst_without) = stats(Some(0.0));
    eprintln!(
        "tube: longest edge {long_without:.2} -> {long_with:.2} mm, \
         worst quality {worst_without:.3} -> {worst_with:.3}"
    );
    // Measured: longest edge 50.0 -> 5.2 mm (the subdivided tube's edges are 1-4 mm), worst
    // quality 0.02 -> 0.47.
    assert!(
        long_without > 30.0 && long_with < 8.0,
        "{long_with} vs {long_without}"
    );
    assert!(worst_with > 0.3, "{worst_with} vs {worst_without}");
}

#[test]
fn lidded_tube_with_valence_50_apex_stays_closed() {
    let m = subdivide(&cylinder_tube(10.0, 30.0, 50, 7, true)).unwrap();
    let d = decimate(&m, 0.72).unwrap();
    assert_clean(&d, true, "lidded tube");
    assert!(d.triangles.len() < m.triangles.len() / 2);
    let v0 = m.signed_volume();
    assert!((d.signed_volume() / v0 - 1.0).abs() < 0.03);
    // Even the raw tube (apex valence 50, long thin fan triangles) decimates cleanly.
    let raw = cylinder_tube(10.0, 30.0, 50, 7, true);
    let d = decimate(&raw, 0.72).unwrap();
    assert_clean(&d, true, "raw lidded tube");
}

#[test]
fn open_tube_keeps_its_two_boundaries() {
    let m = subdivide(&cylinder_tube(10.0, 30.0, 50, 7, false)).unwrap();
    let d = decimate(&m, 0.72).unwrap();
    assert_clean(&d, false, "open tube");
    let v = validity(&d);
    assert_eq!(v.boundary_loops, 2);
    assert_eq!(v.euler_characteristic, 0);
    // The boundary stays on the end circles.
    for p in &d.positions {
        if p.z.abs() < 1e-6 || (p.z - 30.0).abs() < 1e-6 {
            assert!((p.xy().norm() - 10.0).abs() < 0.2, "{p:?}");
        }
    }
    let (lo, hi) = d.bounds().unwrap();
    assert!(lo.z.abs() < 1e-6 && (hi.z - 30.0).abs() < 1e-6);
}

#[test]
fn noisy_sphere_stays_manifold() {
    let m = noisy(subdivide(&icosphere(10.0, 3)).unwrap(), 0.3, 7);
    let d = decimate(&m, 0.72).unwrap();
    assert_clean(&d, true, "noisy sphere");
    let d = decimate(&m, 0.95).unwrap();
    assert_clean(&d, true, "noisy sphere, 95%");
    assert!(d.triangles.len() < 300, "{}", d.triangles.len());
}

#[test]
fn extreme_reduction_stops_at_a_valid_mesh() {
    let m = icosphere(10.0, 2);
    let d = decimate(&m, 0.99).unwrap();
    assert_clean(&d, true, "99%");
    assert!(d.triangles.len() >= 4);
    assert_eq!(validity(&d).euler_characteristic, 2);
}

#[test]
fn far_from_origin_same_result_up_to_translation() {
    let m = noisy(icosphere(10.0, 3), 0.2, 3);
    let offset = Vec3::new(-150.0, 220.0, 80.0);
    let moved = TriMesh::new(
        m.positions.iter().map(|p| p + offset).collect(),
        m.triangles.clone(),
    );
    let a = decimate(&m, 0.72).unwrap();
    let b = decimate(&moved, 0.72).unwrap();
    // Rounding of the centroid may break a few ties differently; the outcome must not change.
    assert!(a.triangles.len().abs_diff(b.triangles.len()) <= 4);
    assert_clean(&b, true, "moved");
    let worst = b
        .positions
        .iter()
        .map(|p| ((p - offset).norm() - 10.0).abs())
        .fold(0.0, f64::max);
    assert!(worst < 0.6, "max radius error {worst} mm");
}

#[test]
fn deterministic() {
    let m = noisy(subdivide(&icosphere(10.0, 3)).unwrap(), 0.2, 11);
    let a = decimate(&m, 0.72).unwrap();
    let b = decimate(&m, 0.72).unwrap();
    assert_eq!(a, b);
}

#[test]
fn rejects_bad_input() {
    let m = icosphere(1.0, 1);
    assert!(matches!(
        decimate(&m, 1.0),
        Err(CoreError::ParamOutOfRange { .. })
    ));
    assert!(decimate(&m, -0.1).is_err());
    let mut bad = m.clone();
    bad.triangles.push(bad.triangles[0]);
    assert!(matches!(
        decimate(&bad, 0.5),
        Err(CoreError::InvalidMesh(_))
    ));
    let mut nan = m;
    nan.positions[0].x = f64::NAN;
    assert!(decimate(&nan, 0.5).is_err());
    assert_eq!(
        decimate(&TriMesh::default(), 0.5).unwrap(),
        TriMesh::default()
    );
}

/// A patch crushed into a ball of tiny triangles facing every way (what a remesh meets where the
/// deformation squeezed the surface, `KNOT_EDGE`): every collapse inside it turns a triangle
/// over, so the turn test alone leaves the ball as it is, and each later subdivision would
/// quadruple it. With the knot rule the decimation takes it out and the sphere stays sound.
#[test]
fn a_crushed_knot_is_collapsed() {
    let sphere = icosphere(10.0, 3);
    let centre_vertex = 0usize;
    let p0 = sphere.positions[centre_vertex];
    // The knot: every vertex within two edges of vertex 0, crushed to within 0.005 mm of it.
    let neighbours = |v: usize| -> Vec<usize> {
        sphere
            .triangles
            .iter()
            .filter(|t| t.contains(&(v as u32)))
            .flat_map(|t| t.map(|w| w as usize))
            .collect()
    };
    let mut knot: Vec<usize> = neighbours(centre_vertex)
        .into_iter()
        .flat_map(neighbours)
        .collect();
    knot.sort_unstable();
    knot.dedup();
    let crushed = {
        let jitter = noisy(
            TriMesh::new(vec![Vec3::zeros(); knot.len()], Vec::new()),
            0.005,
            7,
        );
        let mut m = sphere.clone();
        for (k, &v) in knot.iter().enumerate() {
            m.positions[v] = p0 + jitter.positions[k];
        }
        m
    };
    let in_knot = |m: &TriMesh| {
        m.positions
            .iter()
            .filter(|p| (*p - p0).norm() < 0.05)
            .count()
    };
    assert_eq!(in_knot(&crushed), knot.len());
    assert!(knot.len() >= 15, "{} vertices in the knot", knot.len());
    let decimated = |knot_edge2: Option<f64>| {
        let centre = crushed.positions.iter().fold(Vec3::zeros(), |s, p| s + p)
            / crushed.positions.len() as f64;
        let mut state = Decimator::new(&crushed, centre, Known::Nothing).unwrap();
        if let Some(k) = knot_edge2 {
            state.knot_edge2 = k;
        }
        state.run(crushed.triangles.len() / 2);
        state.unfold();
        state.finish(centre)
    };
    let without = decimated(Some(0.0));
    let with = decimated(None);
    eprintln!(
        "vertices within 0.05 mm of the knot: {} crushed, {} without the rule, {} with it",
        knot.len(),
        in_knot(&without),
        in_knot(&with)
    );
    // Measured: 16 crushed, 8 left without the rule, 1 with it.
    assert!(in_knot(&without) >= 5, "{}", in_knot(&without));
    assert!(in_knot(&with) <= 2, "{}", in_knot(&with));
    assert_clean(&with, true, "sphere with a knot");
    let ratio = with.signed_volume() / sphere.signed_volume();
    assert!((0.95..1.0).contains(&ratio), "volume ratio {ratio:.4}");
}
