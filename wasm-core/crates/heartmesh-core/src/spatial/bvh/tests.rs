use super::*;
use crate::geometry::v3;
use crate::spatial::testutil::{random_soup, uv_sphere, SplitMix64};
use crate::spatial::triangle::closest_point_on_triangle;

fn brute(mesh: &TriMesh, q: Vec3) -> Option<ClosestHit> {
    let mut best: Option<ClosestHit> = None;
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.corners(t);
        let p = closest_point_on_triangle(&q, &a, &b, &c);
        let d = (q - p).norm_squared();
        if best.is_none_or(|h| d < h.distance_sq) {
            best = Some(ClosestHit {
                point: p,
                distance_sq: d,
                triangle: t as u32,
            });
        }
    }
    best
}

fn check_against_brute(mesh: &TriMesh, bvh: &Bvh, queries: &[Vec3]) {
    for q in queries {
        let got = bvh.closest_point(mesh, *q).expect("non-empty mesh");
        let want = brute(mesh, *q).expect("non-empty mesh");
        assert_eq!(got, want, "query {q:?}");
    }
}

#[test]
fn random_soups_equal_brute_force() {
    let mut rng = SplitMix64::new(42);
    for (nv, nt) in [(3, 1), (10, 7), (60, 100), (400, 1500)] {
        let mesh = random_soup(&mut rng, nv, nt);
        let bvh = Bvh::build(&mesh);
        let queries: Vec<Vec3> = (0..300).map(|_| rng.vec3(-15.0, 15.0)).collect();
        check_against_brute(&mesh, &bvh, &queries);
    }
}

#[test]
fn sphere_queries_equal_brute_force() {
    let mut rng = SplitMix64::new(3);
    let mut mesh = uv_sphere(30.0, 24, 40);
    // Jitter the vertices so the sphere is not symmetric, and query near and far from it.
    for p in &mut mesh.positions {
        *p += rng.vec3(-0.5, 0.5);
    }
    let bvh = Bvh::build(&mesh);
    assert!(bvh.depth() < STACK);
    let mut queries: Vec<Vec3> = (0..200).map(|_| rng.vec3(-40.0, 40.0)).collect();
    queries.extend(mesh.positions.iter().take(50).copied()); // on vertices: exact ties
    check_against_brute(&mesh, &bvh, &queries);
    // A query on a shared vertex has distance 0 and the lowest incident triangle.
    let h = bvh.closest_point(&mesh, mesh.positions[0]).unwrap();
    assert_eq!(h.distance_sq, 0.0);
    assert_eq!(h.triangle, 0);
}

#[test]
fn refit_equals_rebuild_for_queries() {
    let mut rng = SplitMix64::new(11);
    let mut mesh = uv_sphere(20.0, 24, 40);
    let mut bvh = Bvh::build(&mesh);
    let nodes_before = bvh.node_count();
    // A smooth, large deformation: anisotropic stretch plus a bend.
    for p in &mut mesh.positions {
        *p = v3(1.6 * p.x + 0.01 * p.z * p.z, 0.7 * p.y, p.z + 0.2 * p.x) + rng.vec3(-0.3, 0.3);
    }
    bvh.refit(&mesh).unwrap();
    assert_eq!(bvh.node_count(), nodes_before);
    let rebuilt = Bvh::build(&mesh);
    // Every box contains its triangles' corners.
    for node in &bvh.nodes {
        if node.count > 0 {
            let s = node.start as usize;
            for &t in &bvh.order[s..s + node.count as usize] {
                for p in mesh.corners(t as usize) {
                    for k in 0..3 {
                        assert!(node.lo[k] <= p[k] && p[k] <= node.hi[k]);
                    }
                }
            }
        }
    }
    let queries: Vec<Vec3> = (0..300).map(|_| rng.vec3(-40.0, 40.0)).collect();
    for q in &queries {
        let a = bvh.closest_point(&mesh, *q).unwrap();
        let b = rebuilt.closest_point(&mesh, *q).unwrap();
        assert_eq!(a, b);
        assert_eq!(Some(a), brute(&mesh, *q));
    }
    // Refitting back to the original positions gives the original boxes exactly.
    let original = uv_sphere(20.0, 24, 40);
    bvh.refit(&original).unwrap();
    assert_eq!(bvh, Bvh::build(&original));
}

#[test]
fn empty_and_invalid_meshes_do_not_panic() {
    let empty = TriMesh::default();
    let bvh = Bvh::build(&empty);
    assert!(bvh.is_empty());
    assert_eq!(bvh.closest_point(&empty, v3(1., 2., 3.)), None);
    let mut out = vec![];
    bvh.closest_points(&empty, &[v3(0., 0., 0.)], &mut out);
    assert!(out.is_empty());

    // A triangle with a missing vertex is left out; the valid one still answers.
    let mesh = TriMesh::new(
        vec![v3(0., 0., 0.), v3(1., 0., 0.), v3(0., 1., 0.)],
        vec![[0, 1, 7], [0, 1, 2]],
    );
    let bvh = Bvh::build(&mesh);
    let h = bvh.closest_point(&mesh, v3(0.2, 0.2, 1.0)).unwrap();
    assert_eq!(h.triangle, 1);
    assert!((h.distance_sq - 1.0).abs() < 1e-15);
    // Refit with a different topology is an error, not a panic.
    let mut bvh = bvh;
    assert!(bvh.refit(&TriMesh::default()).is_err());
    bvh.refit(&mesh).unwrap(); // the left-out triangle is not refitted either
    let mut shrunk = mesh.clone();
    shrunk.positions.truncate(2);
    assert_eq!(bvh.refit(&shrunk).unwrap_err().code(), "invalid_mesh");

    // A NaN vertex poisons only its own triangles: the others still answer.
    let mut mesh = uv_sphere(5.0, 8, 12);
    mesh.positions[3] = v3(f64::NAN, 0.0, 0.0);
    let mut bvh = Bvh::build(&mesh);
    bvh.refit(&mesh).unwrap();
    let h = bvh.closest_point(&mesh, v3(0.0, 0.0, 9.0)).unwrap();
    assert!((h.distance_sq.sqrt() - 4.0).abs() < 1e-9, "{h:?}");

    // Many identical triangles (all centroids equal) still build a shallow tree.
    let mesh = TriMesh::new(
        vec![v3(0., 0., 0.), v3(1., 0., 0.), v3(0., 1., 0.)],
        vec![[0, 1, 2]; 1000],
    );
    let bvh = Bvh::build(&mesh);
    assert!(bvh.depth() <= 12, "depth {}", bvh.depth());
    assert_eq!(
        bvh.closest_point(&mesh, v3(0.1, 0.1, 0.0))
            .unwrap()
            .triangle,
        0
    );
}

#[test]
fn any_hint_gives_the_same_hit() {
    let mut rng = SplitMix64::new(17);
    let mut mesh = uv_sphere(30.0, 24, 40);
    for p in &mut mesh.positions {
        *p += rng.vec3(-0.5, 0.5);
    }
    let n = mesh.triangles.len() as u32;
    let bvh = Bvh::build(&mesh);
    let mut queries: Vec<Vec3> = (0..200).map(|_| rng.vec3(-40.0, 40.0)).collect();
    queries.extend(mesh.positions.iter().take(50).copied()); // exact ties on vertices
    let mut hinted = 0;
    for q in &queries {
        let want = brute(&mesh, *q).unwrap();
        let near = bvh.closest_point(&mesh, *q).unwrap().triangle;
        // The answer itself, a neighbour-ish index, a random one, and invalid ones.
        let r = (rng.range(0.0, n as f64) as u32).min(n - 1);
        for hint in [near, near.saturating_sub(1), r, n, u32::MAX] {
            assert_eq!(
                bvh.closest_point_near(&mesh, *q, hint),
                Some(want),
                "hint {hint}"
            );
            hinted += 1;
        }
    }
    assert_eq!(hinted, 5 * 250);
    // A soup with a left-out triangle: its index as a hint is ignored.
    let mesh = TriMesh::new(
        vec![v3(0., 0., 0.), v3(1., 0., 0.), v3(0., 1., 0.)],
        vec![[0, 1, 7], [0, 1, 2]],
    );
    let bvh = Bvh::build(&mesh);
    let h = bvh.closest_point_near(&mesh, v3(0.2, 0.2, 1.0), 0).unwrap();
    assert_eq!(h.triangle, 1);
}

#[test]
fn batch_matches_single_queries() {
    let mut rng = SplitMix64::new(5);
    let mesh = uv_sphere(10.0, 16, 30);
    let bvh = Bvh::build(&mesh);
    let queries: Vec<Vec3> = (0..100).map(|_| rng.vec3(-20.0, 20.0)).collect();
    let mut out = Vec::new();
    bvh.closest_points(&mesh, &queries, &mut out);
    assert_eq!(out.len(), queries.len());
    for (q, h) in queries.iter().zip(&out) {
        assert_eq!(Some(*h), bvh.closest_point(&mesh, *q));
        // On a sphere of radius 10 the distance is close to | |q| - 10 |.
        assert!((h.distance_sq.sqrt() - (q.norm() - 10.0).abs()).abs() < 0.2);
    }
}
