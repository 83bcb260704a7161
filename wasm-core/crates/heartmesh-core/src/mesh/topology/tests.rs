use super::*;
use crate::geometry::v3;
use crate::mesh::shapes::{cylinder_tube, icosphere};

fn tetra() -> TriMesh {
    crate::mesh::shapes::unit_tetrahedron()
}

#[test]
fn tetra_is_closed_manifold() {
    let v = validity(&tetra());
    assert!(v.is_closed_manifold(), "{}", v.describe());
    assert_eq!(v.euler_characteristic, 2);
    assert_eq!(v.boundary_edges, 0);
    assert_eq!(v.boundary_loops, 0);
    assert_eq!(v.degenerate_triangles, 0);
    assert_eq!(v.duplicate_triangles, 0);
}

#[test]
fn single_triangle_is_open_disk() {
    let m = TriMesh::new(
        vec![
            v3(0., 0., 0.),
            v3(1., 0., 0.),
            v3(0., 1., 0.),
            v3(5., 5., 5.),
        ],
        vec![[0, 1, 2]],
    );
    let v = validity(&m);
    assert!(!v.closed);
    assert!(v.manifold);
    assert_eq!(v.boundary_edges, 3);
    assert_eq!(v.boundary_loops, 1);
    assert_eq!(v.euler_characteristic, 1);
    assert_eq!(v.unreferenced_vertices, 1);
    let c = compact(&m).unwrap();
    assert_eq!(c.positions.len(), 3);
    assert_eq!(validity(&c).unreferenced_vertices, 0);
}

#[test]
fn flipped_face_is_not_oriented_and_orient_fixes_it() {
    let mut m = tetra();
    m.triangles[3].swap(1, 2);
    let v = validity(&m);
    assert!(!v.oriented);
    assert!(!v.manifold);
    orient_outward(&mut m).unwrap();
    let v = validity(&m);
    assert!(v.is_closed_manifold());
    assert!((m.signed_volume() - 1.0 / 6.0).abs() < 1e-12);

    // Fully inverted: consistent but inward; orient_outward makes the volume positive.
    let mut inv = tetra();
    inv.flip_orientation();
    assert!(inv.signed_volume() < 0.0);
    orient_outward(&mut inv).unwrap();
    assert!((inv.signed_volume() - 1.0 / 6.0).abs() < 1e-12);
}

#[test]
fn health_agrees_with_validity() {
    let mut meshes = vec![tetra(), TriMesh::new(tetra().positions, vec![[0, 1, 2]])];
    let mut flipped = tetra();
    flipped.triangles[3].swap(1, 2);
    meshes.push(flipped);
    let mut pinched = tetra();
    pinched
        .positions
        .extend([v3(-1., 0., 0.), v3(0., -1., 0.), v3(0., 0., -1.)]);
    pinched
        .triangles
        .extend([[0, 4, 5], [0, 6, 4], [0, 5, 6], [4, 6, 5]]);
    meshes.push(pinched);
    let mut fin = tetra();
    fin.triangles.push([0, 1, 2]);
    meshes.push(fin);
    let mut flat = tetra();
    flat.positions[3] = flat.positions[0];
    meshes.push(flat);
    let mut verdicts = Vec::new();
    for m in &meshes {
        let map = EdgeMap::new(m);
        let (v, h) = (validity_with_map(m, &map), health_with_map(m, &map));
        assert_eq!(
            (h.closed, h.manifold, h.oriented),
            (v.closed, v.manifold, v.oriented)
        );
        verdicts.push(h.manifold);
    }
    // Only the tetrahedron and the lone triangle are manifold.
    assert_eq!(verdicts, [true, true, false, false, false, false]);
}

#[test]
fn fin_and_pinch_are_not_manifold() {
    // Two tetrahedra sharing only vertex 0: every edge is fine, the vertex fan is not.
    let mut m = tetra();
    m.positions
        .extend([v3(-1., 0., 0.), v3(0., -1., 0.), v3(0., 0., -1.)]);
    m.triangles
        .extend([[0, 4, 5], [0, 6, 4], [0, 5, 6], [4, 6, 5]]);
    orient_outward(&mut m).unwrap();
    let v = validity(&m);
    assert!(v.closed && v.oriented);
    assert!(!v.manifold, "pinched vertex must be non-manifold");
    assert_eq!(v.euler_characteristic, 3);

    // A fin: a triangle repeated with the opposite orientation on a closed tetrahedron.
    let mut f = tetra();
    f.triangles.push([0, 1, 2]);
    let v = validity(&f);
    assert_eq!(v.duplicate_triangles, 1);
    assert!(!v.manifold);
}

#[test]
fn degenerate_and_out_of_range_do_not_panic() {
    let m = TriMesh::new(
        vec![v3(0., 0., 0.), v3(1., 0., 0.), v3(2., 0., 0.)],
        vec![[0, 1, 2], [0, 0, 1], [0, 1, 7]],
    );
    let v = validity(&m);
    assert_eq!(v.degenerate_triangles, 3);
    assert!(!v.manifold);
    assert!(compact(&m).is_err());
    let mut m2 = m.clone();
    assert!(orient_outward(&mut m2).is_err());
}

#[test]
fn sphere_and_tubes() {
    let s = icosphere(10.0, 3);
    let v = validity(&s);
    assert!(v.is_closed_manifold());
    assert_eq!(v.euler_characteristic, 2);

    let open = cylinder_tube(10.0, 30.0, 50, 7, false);
    let v = validity(&open);
    assert!(v.manifold && v.oriented && !v.closed);
    assert_eq!(v.boundary_loops, 2);
    assert_eq!(v.boundary_edges, 100);
    assert_eq!(v.euler_characteristic, 0);
    let mask = boundary_vertices(&open);
    assert_eq!(mask.iter().filter(|&&b| b).count(), 100);

    let lidded = cylinder_tube(10.0, 30.0, 50, 7, true);
    let v = validity(&lidded);
    assert!(v.is_closed_manifold(), "{}", v.describe());
    assert_eq!(v.euler_characteristic, 2);
    assert!(lidded.signed_volume() > 0.0);
    let nb = vertex_neighbours(&lidded);
    let max_valence = (0..nb.vertex_count()).map(|v| nb.valence(v)).max();
    assert_eq!(max_valence, Some(50));
}

#[test]
fn neighbours_are_symmetric_and_sorted() {
    let s = icosphere(1.0, 1);
    let nb = vertex_neighbours(&s);
    for v in 0..nb.vertex_count() {
        let ring = nb.of(v);
        assert!(ring.windows(2).all(|w| w[0] < w[1]));
        for &w in ring {
            assert!(nb.of(w as usize).contains(&(v as u32)));
        }
        assert!(nb.valence(v) == 5 || nb.valence(v) == 6);
    }
}
