use super::*;
use crate::geometry::v3;
use crate::mesh::TriMesh;
use crate::metrics::anatomical::{build_pair, Anatomical};
use crate::metrics::segments::Orientation;
use crate::sim::shapes::uv_sphere;
use std::f64::consts::PI;

const BASE_Z: f64 = 12.0;

/// An ellipsoid of semi-axes (a, b, c) centred at the origin, finely tessellated.
fn ellipsoid(a: f64, b: f64, c: f64) -> TriMesh {
    let mut m = uv_sphere(v3(0.0, 0.0, 0.0), 1.0, 256, 128);
    for p in &mut m.positions {
        *p = v3(p.x * a, p.y * b, p.z * c);
    }
    m
}

/// Volume of that ellipsoid below z = BASE_Z (ml).
fn clipped_ml(a: f64, b: f64, c: f64) -> f64 {
    let h = BASE_Z;
    PI * a * b * ((h + c) - (h.powi(3) + c.powi(3)) / (3.0 * c * c)) / 1000.0
}

/// The base plane z = BASE_Z.
fn base() -> Plane {
    Plane::new(v3(0.0, 0.0, BASE_Z), v3(0.0, 0.0, 1.0)).unwrap()
}

/// The layouts of two ellipsoids (semi-axes `inner`, `outer`) on the inner one's frame, the
/// septum towards +x.
fn pair(inner: [f64; 3], outer: [f64; 3], layout: Layout) -> (Anatomical, Anatomical) {
    let o = Orientation {
        septum: v3(1.0, 0.0, 0.0),
        source: "test",
        points: 1,
    };
    let [a, b, c] = inner;
    let [d, e, f] = outer;
    build_pair(
        &ellipsoid(a, b, c),
        &ellipsoid(d, e, f),
        &base(),
        &o,
        layout,
    )
    .unwrap()
}

fn shell(layout: Layout, layers: usize) -> HexWall {
    let (endo, epi) = pair([25.0, 20.0, 40.0], [33.0, 28.0, 47.0], layout);
    build(&endo, &epi, layout, &base(), layers).unwrap()
}

#[test]
fn an_ellipsoidal_shell_gives_valid_cells_of_its_volume() {
    let layout = Layout::DEFAULT;
    let w = shell(layout, 3);
    let s = &w.summary;
    assert_eq!(s.points, 4 * (24 * 48 + 1));
    assert_eq!(s.wedges, 3 * 48);
    assert_eq!(s.hexahedra, 3 * 23 * 48);
    assert_eq!(w.cells.len(), w.aha_segment.len());
    assert_eq!(s.inverted_cells, 0);
    // The apex's wedges meet at 360/48 = 7.5 degrees: sin 7.5 = 0.13 at that corner.
    assert!(s.min_scaled_jacobian > 0.1, "{s:?}");
    let exact = clipped_ml(33.0, 28.0, 47.0) - clipped_ml(25.0, 20.0, 40.0);
    assert!(
        (s.volume_ml - exact).abs() < 0.015 * exact,
        "{} vs {exact}",
        s.volume_ml
    );
    assert!(
        (s.volume_ml - s.layouts_volume_ml).abs() < 0.005 * exact,
        "{} vs {}",
        s.volume_ml,
        s.layouts_volume_ml
    );
    // The first layer is the endocardial layout, the last the epicardial one.
    assert_eq!(w.transmural[0], 0.0);
    assert_eq!(*w.transmural.last().unwrap(), 1.0);
    assert!((w.points[0] - v3(0.0, 0.0, -40.0)).norm() < 1e-6);
    assert!((w.points[3 * (24 * 48 + 1)] - v3(0.0, 0.0, -47.0)).norm() < 1e-6);
    // Every AHA segment has cells; the apex's outer cells are segment 17.
    for k in 1..=17 {
        assert!(w.aha_segment.contains(&k), "segment {k}");
    }
    let outer_apex = 2 * (48 + 23 * 48); // the first cell of the outer layer: an apex wedge
    assert_eq!(w.aha_segment[outer_apex], 17);
    // A basal cell at the septum (j = 0..1 towards anterior): basal anteroseptal (2).
    // Layer 0: 48 wedges, then a band of 48 hexahedra per ring pair; the top band's first.
    assert_eq!(w.aha_segment[48 + 22 * 48], 2);
}

#[test]
fn fibres_turn_from_plus_to_minus_sixty_degrees_through_the_wall() {
    let layout = Layout::DEFAULT;
    let w = shell(layout, 2);
    let per_layer = 24 * 48 + 1;
    // Ring 16 of 24 lies near the ellipsoids' equator (8 cap rings, then 16 up to z = 12):
    // the wall runs straight up there, so the longitudinal direction is +z.
    let mut equator = None;
    for ring in 9..=24 {
        let v = layout.index(ring, 12);
        if w.points[v].z.abs() < 2.5 {
            equator = Some(v);
        }
    }
    let v = equator.expect("a ring near z = 0");
    for (layer, helix) in [(0, 60.0f64), (1, 0.0), (2, -60.0)] {
        let k = layer * per_layer + v;
        let (f, s) = (w.fibre[k], w.sheet[k]);
        assert!((f.norm() - 1.0).abs() < 1e-12 && (s.norm() - 1.0).abs() < 1e-12);
        assert!(f.dot(&s).abs() < 1e-12, "the fibre lies in the wall");
        // Vertex 12 of 48 is a quarter turn from +x: +y, where counterclockwise seen from the
        // base (+z) is -x; the sheet points out (+y), tilted down a little towards the
        // epicardium's own ring (its apex lies lower); the longitudinal direction is then the
        // sheet crossed with -x, mostly up.
        assert!(s.y > 0.95, "{s:?}");
        let round = v3(-1.0, 0.0, 0.0);
        let up = s.cross(&round);
        assert!(up.z > 0.95, "{up:?}");
        let angle = f.dot(&up).atan2(f.dot(&round)).to_degrees();
        assert!(
            (angle - helix).abs() < 3.0,
            "layer {layer}: {angle} degrees, not {helix}"
        );
    }
    // The endocardium's fibres climb counterclockwise (seen from the base): a right-handed helix.
    let f = w.fibre[v];
    assert!(f.z > 0.8 && -f.x > 0.4, "{f:?}");
    // Other angles through the wall, and their range.
    let base = base();
    let (endo, epi) = pair([25.0, 20.0, 40.0], [33.0, 28.0, 47.0], layout);
    let flat = build_with_helix(&endo, &epi, layout, &base, 2, (0.0, 0.0), None).unwrap();
    assert!(flat.fibre[v].z.abs() < 0.05, "{:?}", flat.fibre[v]);
    let e = build_with_helix(&endo, &epi, layout, &base, 2, (95.0, -60.0), None).unwrap_err();
    assert!(e.to_string().contains("-90 to 90"), "{e}");
}

#[test]
fn a_wall_thinner_than_the_minimum_is_kept_that_thick_along_its_rays() {
    let layout = Layout::new(12, 24).unwrap();
    let base = base();
    // An epicardium 0.6 mm outside the endocardium towards +x only, 8 mm elsewhere: the +x
    // side is a wall thinner than 1 mm.
    let (endo, epi) = pair([25.0, 20.0, 40.0], [25.6, 28.0, 47.0], layout);
    let thin = build_with_helix(&endo, &epi, layout, &base, 2, DEFAULT_HELIX_DEG, None).unwrap();
    let kept =
        build_with_helix(&endo, &epi, layout, &base, 2, DEFAULT_HELIX_DEG, Some(1.0)).unwrap();
    assert_eq!(thin.summary.endocardium_moved, 0);
    assert!(kept.summary.endocardium_moved > 0);
    let per_layer = 12 * 24 + 1;
    let mut thinnest = f64::INFINITY;
    for v in 0..per_layer {
        let along = (kept.points[2 * per_layer + v] - kept.points[v]).dot(&endo.rays[v]);
        thinnest = thinnest.min(along);
    }
    assert!(thinnest >= 1.0 - 1e-9, "{thinnest} mm");
    assert!(kept.summary.min_scaled_jacobian >= thin.summary.min_scaled_jacobian);
    assert_eq!(kept.summary.inverted_cells, 0);
}

#[test]
fn layers_are_held_to_their_range() {
    let layout = Layout::new(4, 8).unwrap();
    let base = base();
    let (endo, epi) = pair([25.0, 20.0, 40.0], [33.0, 28.0, 47.0], layout);
    for bad in [0, 21] {
        let e = build(&endo, &epi, layout, &base, bad).unwrap_err();
        assert!(e.to_string().contains("1-20 layers"), "{e}");
    }
    let other = Layout::new(5, 8).unwrap();
    let e = build(&endo, &epi, other, &base, 2).unwrap_err();
    assert!(e.to_string().contains("5x8"), "{e}");
    // A layout made without its checks is refused, not a panic.
    let bad = Layout {
        rings: 0,
        points: 8,
    };
    let e = build(&endo, &epi, bad, &base, 2).unwrap_err();
    assert!(e.to_string().contains("2-200 rings"), "{e}");
    // Inside out (the epicardium inside the endocardium): every cell inverted, and said.
    let w = build(&epi, &endo, layout, &base, 2).unwrap();
    assert_eq!(w.summary.inverted_cells, w.cells.len());
    assert!(w.summary.volume_ml < 0.0);
}
