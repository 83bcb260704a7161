use super::*;
use crate::contours::Contour;
use crate::geometry::v3;
use crate::mesh::topology::validity;
use crate::sim::shapes::uv_sphere;
use nalgebra::{Rotation3, Unit, Vector3};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Semi-axes of the test ellipsoid (mm): 25 across towards +x, 20 towards +y, 40 along z.
const A: f64 = 25.0;
const B: f64 = 20.0;
const C: f64 = 40.0;
/// Its base plane's height (the apex is at z = -C).
const BASE_Z: f64 = 12.0;

/// A finely tessellated ellipsoid centred at the origin (chords sag under 0.003 mm).
fn ellipsoid() -> TriMesh {
    let mut m = uv_sphere(v3(0.0, 0.0, 0.0), 1.0, 256, 128);
    for p in &mut m.positions {
        *p = v3(p.x * A, p.y * B, p.z * C);
    }
    m
}

fn base() -> Plane {
    Plane::new(v3(0.0, 0.0, BASE_Z), v3(0.0, 0.0, 1.0)).unwrap()
}

fn septum_towards(d: Vec3) -> Orientation {
    Orientation {
        septum: d,
        source: "test",
        points: 1,
    }
}

/// Where the analytic ellipsoid's section at height `z` leaves the axis at `angle` (radians
/// from +x towards +y).
fn analytic(z: f64, angle: f64) -> Vec3 {
    let rho = (1.0 - (z / C).powi(2)).max(0.0).sqrt();
    let r = rho / ((angle.cos() / A).powi(2) + (angle.sin() / B).powi(2)).sqrt();
    v3(r * angle.cos(), r * angle.sin(), z)
}

/// Where the ray from (0, 0, zc), `polar` from straight down towards `angle`, leaves the
/// ellipsoid.
fn cap_ray(zc: f64, polar: f64, angle: f64) -> Vec3 {
    let d = v3(
        polar.sin() * angle.cos(),
        polar.sin() * angle.sin(),
        -polar.cos(),
    );
    let qa = (d.x / A).powi(2) + (d.y / B).powi(2) + (d.z / C).powi(2);
    let qb = 2.0 * zc * d.z / (C * C);
    let qc = (zc / C).powi(2) - 1.0;
    let t = (-qb + (qb * qb - 4.0 * qa * qc).sqrt()) / (2.0 * qa);
    v3(0.0, 0.0, zc) + d * t
}

#[test]
fn layouts_parse_and_are_held_to_their_ranges() {
    assert_eq!(Layout::parse("24x48"), Ok(Layout::DEFAULT));
    assert_eq!(Layout::parse(" 10X16 "), Ok(Layout::new(10, 16).unwrap()));
    for bad in ["24", "x48", "24x", "24x48x2", "a x b", "-3x48", ""] {
        assert!(Layout::parse(bad).is_err(), "{bad}");
    }
    let e = Layout::parse("1x48").unwrap_err();
    assert!(e.contains("2-200 rings of 8-720 points"), "{e}");
    assert!(Layout::parse("24x7").is_err());
    assert!(Layout::parse("201x48").is_err());
    assert!(Layout::parse("24x721").is_err());
    let l = Layout::new(3, 8).unwrap();
    assert_eq!(l.vertices(), 26);
    assert_eq!(l.index(1, 0), 1);
    assert_eq!(l.index(2, 8), 9, "j wraps round the ring");
    assert_eq!(l.index(3, 7), 24);
}

#[test]
fn an_ellipsoid_gives_its_analytic_grid() {
    let layout = Layout::DEFAULT;
    let a = build(
        &ellipsoid(),
        &base(),
        &septum_towards(v3(1.0, 0.0, 0.0)),
        layout,
    )
    .unwrap();
    let m = &a.mesh;
    assert_eq!(m.positions.len(), layout.vertices());
    assert_eq!(m.triangles.len(), 2 * layout.rings * layout.points);
    assert_eq!(a.regions.len(), m.triangles.len());
    assert_eq!(
        a.regions.iter().filter(|&&r| r == BASE).count(),
        layout.points
    );
    // Vertex 0: the pole, straight below the cap's centre.
    assert!(
        (m.positions[0] - v3(0.0, 0.0, -C)).norm() < 1e-6,
        "{:?}",
        m.positions[0]
    );
    let length = BASE_Z + C;
    // The cap stands on the section a third of the length up; 8 of the 24 rings are its.
    let zc = -C + length / 3.0;
    let mut worst: f64 = 0.0;
    for ring in 1..=layout.rings {
        for j in 0..layout.points {
            let angle = TAU * j as f64 / layout.points as f64;
            let p = m.positions[layout.index(ring, j)];
            let expected = if ring <= 8 {
                let polar = FRAC_PI_2 * ring as f64 / 8.0;
                cap_ray(zc, polar, angle)
            } else {
                let z = zc + (BASE_Z - zc) * (ring - 8) as f64 / 16.0;
                assert!((p.z - z).abs() < 1e-9, "ring {ring} at z {} not {z}", p.z);
                analytic(z, angle)
            };
            worst = worst.max((p - expected).norm());
        }
    }
    assert!(worst < 0.01, "grid vertices {worst} mm off the ellipsoid");
    // Septal vertices towards +x, anterior (a quarter turn on) towards +y: axis x septum.
    let mid = layout.index(12, 0);
    assert!(m.positions[mid].x > 0.0 && m.positions[mid].y.abs() < 1e-6);
    let ant = layout.index(12, layout.points / 4);
    assert!(m.positions[ant].y > 0.0 && m.positions[ant].x.abs() < 1e-6);
    // The lid's centre on the axis in the base plane.
    assert!((m.positions[layout.vertices() - 1] - v3(0.0, 0.0, BASE_Z)).norm() < 1e-6);
    // Closed, manifold, outward; its volume that of the clipped ellipsoid less the chords'.
    let v = validity(m);
    assert!(v.is_closed_manifold() && v.oriented, "{}", v.describe());
    let exact_ml = PI * A * B * (length - (BASE_Z.powi(3) + C.powi(3)) / (3.0 * C * C)) / 1000.0;
    let s = &a.summary;
    assert!(
        (s.surface_volume_ml - exact_ml).abs() < 0.002 * exact_ml,
        "{} vs {exact_ml}",
        s.surface_volume_ml
    );
    assert!(s.volume_ml < s.surface_volume_ml && s.volume_ml > 0.99 * exact_ml);
    assert!(s.to_surface_max_mm < 0.6, "{s:?}");
    assert!(s.to_surface_mean_mm < 0.05, "{s:?}");
    assert!((s.length_mm - length).abs() < 1e-9);
    assert_eq!(s.septum_direction, [1.0, 0.0, 0.0]);
    assert_eq!(s.anterior_direction, [0.0, 1.0, 0.0]);
}

#[test]
fn a_moved_heart_gives_the_moved_grid() {
    let layout = Layout::new(12, 20).unwrap();
    let still = build(
        &ellipsoid(),
        &base(),
        &septum_towards(v3(1.0, 0.2, 0.3)),
        layout,
    )
    .unwrap();
    let rot = Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::new(0.3, -1.0, 0.5)), 1.1);
    let shift = v3(-140.0, 35.5, 210.0);
    let move_ = |p: &Vec3| rot * p + shift;
    let mut moved_mesh = ellipsoid();
    moved_mesh.positions.iter_mut().for_each(|p| *p = move_(p));
    let moved_base = Plane::new(move_(&base().origin), rot * base().normal).unwrap();
    let moved = build(
        &moved_mesh,
        &moved_base,
        &septum_towards(rot * v3(1.0, 0.2, 0.3)),
        layout,
    )
    .unwrap();
    assert_eq!(moved.mesh.triangles, still.mesh.triangles);
    let worst = still
        .mesh
        .positions
        .iter()
        .zip(&moved.mesh.positions)
        .map(|(a, b)| (move_(a) - b).norm())
        .fold(0.0, f64::max);
    assert!(worst < 1e-6, "{worst} mm");
    // Turning the septum turns the grid: vertex j then sits where j + points/4 was.
    let turned = build(
        &ellipsoid(),
        &base(),
        &septum_towards(v3(0.0, 1.0, 0.0)),
        layout,
    )
    .unwrap();
    let a = &turned.mesh.positions[layout.index(5, 0)];
    let b = &build(
        &ellipsoid(),
        &base(),
        &septum_towards(v3(1.0, 0.0, 0.0)),
        layout,
    )
    .unwrap()
    .mesh
    .positions[layout.index(5, layout.points / 4)];
    assert!((a - b).norm() < 1e-9);
}

#[test]
fn what_cannot_be_laid_out_says_why() {
    let surface = ellipsoid();
    // A septum along the axis.
    let e = build(
        &surface,
        &base(),
        &septum_towards(v3(0.0, 0.0, 2.0)),
        Layout::DEFAULT,
    )
    .unwrap_err();
    assert!(e.to_string().contains("along the long axis"), "{e}");
    // A layout made without its checks.
    for (rings, points) in [(1, 48), (0, 48), (24, 0), (24, 7)] {
        let e = build(
            &surface,
            &base(),
            &septum_towards(v3(1.0, 0.0, 0.0)),
            Layout { rings, points },
        )
        .unwrap_err();
        assert!(e.to_string().contains("2-200 rings of 8-720 points"), "{e}");
    }
    // A base plane below the whole surface.
    let low = Plane::new(v3(0.0, 0.0, -50.0), v3(0.0, 0.0, 1.0)).unwrap();
    let e = build(
        &surface,
        &low,
        &septum_towards(v3(1.0, 0.0, 0.0)),
        Layout::DEFAULT,
    )
    .unwrap_err();
    assert!(e.to_string().contains("no part below"), "{e}");
    // An open surface whose sections are open chains near its base.
    let mut open = surface.clone();
    open.triangles
        .retain(|t| t.iter().all(|&v| open_below(&surface, v, BASE_Z - 5.0)));
    let e = build(
        &open,
        &base(),
        &septum_towards(v3(1.0, 0.0, 0.0)),
        Layout::DEFAULT,
    )
    .unwrap_err();
    assert!(e.to_string().contains("no closed"), "{e}");
}

fn open_below(m: &TriMesh, v: u32, z: f64) -> bool {
    m.positions[v as usize].z < z
}

fn ring(id: &str, surface: &str, z: f64) -> Contour {
    let points = (0..12)
        .map(|k| {
            let a = k as f64 * TAU / 12.0;
            v3(18.0 * a.cos(), 18.0 * a.sin(), z)
        })
        .collect();
    Contour {
        id: id.into(),
        surface: Some(surface.into()),
        pieces: vec![Polyline {
            points,
            closed: true,
        }],
        first_line: 0,
    }
}

#[test]
fn rv_surfaces_and_files_without_a_septum_are_refused_before_any_run() {
    let mut set = ContourSet::default();
    set.contours.push(ring("a", "LV_ENDO", 0.0));
    let why = refusal(&set, None).unwrap();
    assert!(
        why.contains("no RV_INSERT landmarks and no RV contours"),
        "{why}"
    );
    set.contours.push(ring("b", "RV_ENDO", 0.0));
    assert_eq!(refusal(&set, Some("LV_ENDO")), None);
    let why = refusal(&set, Some("rv_endo")).unwrap();
    assert!(why.contains("the LV's"), "{why}");
    assert!(refusal(&set, Some("BIV_EPI")).is_some());
    // The septum from the file: the RV's centre lies towards -x of this LV.
    let mut rv = ring("c", "RV_ENDO", -5.0);
    rv.pieces[0].points.iter_mut().for_each(|p| p.x -= 45.0);
    set.contours[1] = rv;
    let a = of_file(
        &set,
        Some("LV_ENDO"),
        &ellipsoid(),
        &base(),
        Layout::new(6, 8).unwrap(),
    )
    .unwrap();
    assert_eq!(a.summary.septum_from, "the RV contours' centre (12)");
    // Every ring's vertex 0 towards -x (the base ring's 24 mm out).
    for ring in 1..=6 {
        let p = a.mesh.positions[1 + (ring - 1) * 8];
        assert!(p.x < 0.0 && p.y.abs() < 1e-6, "ring {ring}: {p:?}");
    }
    assert!(a.mesh.positions[41].x < -20.0, "{:?}", a.mesh.positions[41]);
}
