use super::*;
use crate::geometry::v3;
use crate::mesh::TriMesh;
use crate::metrics::anatomical::build as layout_of;
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

fn shell(layout: Layout, layers: usize) -> HexWall {
    let base = Plane::new(v3(0.0, 0.0, BASE_Z), v3(0.0, 0.0, 1.0)).unwrap();
    let o = Orientation {
        septum: v3(1.0, 0.0, 0.0),
        source: "test",
        points: 1,
    };
    let endo = layout_of(&ellipsoid(25.0, 20.0, 40.0), &base, &o, layout).unwrap();
    let epi = layout_of(&ellipsoid(33.0, 28.0, 47.0), &base, &o, layout).unwrap();
    build(&endo, &epi, layout, &base, layers).unwrap()
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
fn layers_are_held_to_their_range() {
    let layout = Layout::new(4, 8).unwrap();
    let base = Plane::new(v3(0.0, 0.0, BASE_Z), v3(0.0, 0.0, 1.0)).unwrap();
    let o = Orientation {
        septum: v3(1.0, 0.0, 0.0),
        source: "test",
        points: 1,
    };
    let endo = layout_of(&ellipsoid(25.0, 20.0, 40.0), &base, &o, layout).unwrap();
    let epi = layout_of(&ellipsoid(33.0, 28.0, 47.0), &base, &o, layout).unwrap();
    for bad in [0, 21] {
        let e = build(&endo, &epi, layout, &base, bad).unwrap_err();
        assert!(e.to_string().contains("1-20 layers"), "{e}");
    }
    let other = Layout::new(5, 8).unwrap();
    let e = build(&endo, &epi, other, &base, 2).unwrap_err();
    assert!(e.to_string().contains("5x8"), "{e}");
    // Inside out (the epicardium inside the endocardium): every cell inverted, and said.
    let w = build(&epi, &endo, layout, &base, 2).unwrap();
    assert_eq!(w.summary.inverted_cells, w.cells.len());
    assert!(w.summary.volume_ml < 0.0);
}
