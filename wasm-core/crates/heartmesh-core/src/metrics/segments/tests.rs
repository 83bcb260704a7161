use super::*;
use crate::contours::{Contour, ContourSet, Polyline};
use crate::geometry::v3;
use crate::mesh::wall::build_wall;
use crate::metrics::septum::orientation;
use crate::sim::shapes::uv_sphere;
use crate::sim::slice::Plane;

/// A hemispherical shell whose epicardium sits 3 mm towards +x: 13 mm thick on the +x side,
/// 7 mm on the -x side, 10 mm a quarter turn round.
fn shifted_shell() -> Wall {
    let endo = uv_sphere(v3(0.0, 0.0, 0.0), 20.0, 96, 48);
    let epi = uv_sphere(v3(3.0, 0.0, 0.0), 30.0, 128, 64);
    let base = Plane::new(v3(0.0, 0.0, -1.3), v3(0.0, 0.0, 1.0)).unwrap();
    build_wall(&endo, &epi, &base, None).unwrap()
}

fn towards(x: f64, y: f64) -> Orientation {
    Orientation {
        septum: v3(x, y, 0.0),
        source: "test",
        points: 1,
    }
}

fn mean_of(s: &Segments, id: usize) -> f64 {
    s.segments[id - 1].mean_mm.unwrap()
}

#[test]
fn levels_and_angles_pick_the_standard_segments() {
    // Cavity 30 mm deep: thirds at 10 and 20 mm.
    let at = |depth, angle| segment_of(depth, 30.0, angle) + 1;
    // Basal: anterior centred a quarter turn from the septum, the septum at the 2|3 border.
    assert_eq!(at(5.0, 90.0), 1);
    assert_eq!(at(5.0, 30.0), 2);
    assert_eq!(at(5.0, -30.0), 3);
    assert_eq!(at(5.0, -90.0), 4);
    assert_eq!(at(5.0, -150.0), 5);
    assert_eq!(at(5.0, 150.0), 6);
    assert_eq!(at(5.0, -179.0), 5);
    assert_eq!(at(5.0, 179.0), 6);
    assert_eq!(at(15.0, 30.0), 8);
    assert_eq!(at(15.0, 150.0), 12);
    // Apical: four quarters, the septal one centred on the septum.
    assert_eq!(at(25.0, 0.0), 14);
    assert_eq!(at(25.0, 90.0), 13);
    assert_eq!(at(25.0, -90.0), 15);
    assert_eq!(at(25.0, 180.0), 16);
    assert_eq!(at(25.0, -179.0), 16);
    assert_eq!(at(31.0, 45.0), 17);
}

#[test]
fn the_thick_side_is_where_the_septum_is_said_to_be() {
    let wall = shifted_shell();
    let s = segments(&wall, &towards(1.0, 0.0)).unwrap();
    // Anterior: the axis (+z, apex to base) crossed with the septum (+x).
    let a = s.anterior_direction;
    assert!((a[1] - 1.0).abs() < 1e-12 && a[0].abs() < 1e-12, "{a:?}");
    assert!(
        (s.level_depths_mm[3] - 18.7).abs() < 0.1,
        "{:?}",
        s.level_depths_mm
    );
    for seg in &s.segments {
        assert!(seg.area_mm2 > 0.0, "{} has no wall", seg.name);
    }
    // Basal ring (0-6 mm below the base, nearly upright): 10 + 3 cos(angle) averaged over each
    // 60-degree segment: 12.48 on the septal pair, 7.52 on the lateral pair, 10 front and back.
    let want = [
        (2, 12.48),
        (3, 12.48),
        (5, 7.52),
        (6, 7.52),
        (1, 10.0),
        (4, 10.0),
    ];
    for (id, mm) in want {
        let got = mean_of(&s, id);
        assert!((got - mm).abs() < 0.5, "segment {id}: {got} vs {mm}");
    }
    // Mid and apical: the same order, the difference shrinking towards the apex.
    assert!(mean_of(&s, 8) > mean_of(&s, 12) + 3.0);
    assert!(mean_of(&s, 14) > mean_of(&s, 16) + 1.5);
    assert!((mean_of(&s, 13) - mean_of(&s, 15)).abs() < 0.2);
    // The same wall with the septum said to be on the other side: the figures trade places.
    let flipped = segments(&wall, &towards(-1.0, 0.0)).unwrap();
    for (a, b) in [
        (2, 5),
        (3, 6),
        (1, 4),
        (8, 11),
        (14, 16),
        (13, 15),
        (17, 17),
    ] {
        let (x, y) = (mean_of(&s, a), mean_of(&flipped, b));
        assert!((x - y).abs() < 0.05, "{a} {x} vs {b} {y}");
    }
    // Every segment's min and max bracket its mean.
    for seg in &s.segments {
        let (lo, m, hi) = (
            seg.min_mm.unwrap(),
            seg.mean_mm.unwrap(),
            seg.max_mm.unwrap(),
        );
        assert!(lo <= m && m <= hi, "{}", seg.name);
    }
}

#[test]
fn a_septum_along_the_axis_or_a_biventricular_wall_is_refused() {
    let wall = shifted_shell();
    let along = Orientation {
        septum: v3(0.0, 0.0, 1.0),
        source: "test",
        points: 1,
    };
    assert!(segments(&wall, &along).is_err());
    let mut biv = wall.clone();
    biv.region_names = &crate::mesh::wall::BIV_REGION_NAMES;
    assert!(segments(&biv, &towards(1.0, 0.0)).is_err());
}

fn ring(id: &str, surface: &str, centre: Vec3, radius: f64) -> Contour {
    let points = (0..24)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 24.0;
            centre + v3(radius * a.cos(), radius * a.sin(), 0.0)
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
fn the_septum_comes_from_the_insertion_points_else_the_rv() {
    let wall = shifted_shell();
    // An RV beside the LV towards -y.
    let mut set = ContourSet::default();
    for (k, z) in [-5.0, -10.0].into_iter().enumerate() {
        set.contours
            .push(ring(&format!("rv{k}"), "RV_ENDO", v3(0.0, -40.0, z), 15.0));
    }
    let o = orientation(&set, &wall).unwrap();
    assert!(
        (o.septum - v3(0.0, -1.0, 0.0)).norm() < 1e-6,
        "{:?}",
        o.septum
    );
    assert_eq!(o.source, "the RV contours' centre");
    // Insertion points at -45 and -120 degrees round +z, two slices (one slice missing its
    // inferior point): the bisector of the two groups is -82.5 degrees, not the plain mean.
    let dir = |deg: f64| v3(deg.to_radians().cos(), deg.to_radians().sin(), 0.0);
    for (deg, z) in [(-45.0, -5.0), (-45.0, -10.0), (-120.0, -5.0)] {
        set.landmarks
            .push(("RV_INSERT".into(), dir(deg) * 22.0 + v3(0.0, 0.0, z)));
    }
    let o = orientation(&set, &wall).unwrap();
    assert_eq!(o.source, "RV_INSERT landmarks");
    assert_eq!(o.points, 3);
    assert!((o.septum - dir(-82.5)).norm() < 1e-6, "{:?}", o.septum);
    // Insertion points on one side of the RV only (one insertion line marked): the RV's centre
    // places the septum, not their mean 45 degrees off it.
    set.landmarks.retain(|(_, p)| p.x > 0.0);
    assert_eq!(set.landmarks.len(), 2);
    let o = orientation(&set, &wall).unwrap();
    assert_eq!(o.source, "the RV contours' centre");
    assert!(
        (o.septum - v3(0.0, -1.0, 0.0)).norm() < 1e-6,
        "{:?}",
        o.septum
    );
    // An LV-only file says nothing of the septum.
    set.contours.clear();
    set.landmarks.clear();
    set.contours
        .push(ring("lv", "LV_ENDO", v3(0.0, 0.0, -5.0), 18.0));
    assert!(orientation(&set, &wall).is_none());
}

#[test]
fn a_slices_two_insertions_go_one_to_each_side_of_the_septum() {
    let wall = shifted_shell();
    let dir = |deg: f64| v3(deg.to_radians().cos(), deg.to_radians().sin(), 0.0);
    // The RV towards -y (its rings on three slices); each slice's two insertions unnamed, as
    // biv-me marks them: -30 and -150 degrees on two slices, and on the apical one -40 and -80,
    // both on the anterior side of the RV's centre (where patient 1's apical pair lies).
    let mut set = ContourSet::default();
    for (k, z) in [-4.0, -10.0, -16.0].into_iter().enumerate() {
        set.contours
            .push(ring(&format!("rv{k}"), "RV_ENDO", v3(0.0, -40.0, z), 15.0));
    }
    for (deg, z) in [
        (-30.0, -4.0),
        (-150.0, -4.0),
        (-30.0, -10.0),
        (-150.0, -10.0),
        (-40.0, -16.0),
        (-80.0, -16.0),
    ] {
        set.landmarks
            .push(("RV_INSERT".into(), dir(deg) * 22.0 + v3(0.0, 0.0, z)));
    }
    let middle = |a: Vec3, b: Vec3| (a.normalize() + b.normalize()).normalize();
    // Paired by slice: -80 is the apical slice's inferior insertion.
    let paired = middle(
        dir(-30.0) * 2.0 + dir(-40.0),
        dir(-150.0) * 2.0 + dir(-80.0),
    );
    // Grouped by side of the RV's centre it would join the anterior ones, 12 degrees off.
    let sided = middle(
        dir(-30.0) * 2.0 + dir(-40.0) + dir(-80.0),
        dir(-150.0) * 2.0,
    );
    let o = orientation(&set, &wall).unwrap();
    assert_eq!((o.source, o.points), ("RV_INSERT landmarks", 6));
    assert!(
        (o.septum - paired).norm() < 1e-9,
        "{:?} vs {paired:?}",
        o.septum
    );
    let apart = paired.dot(&sided).acos().to_degrees();
    assert!(apart > 10.0, "{apart}");
    // A slice holding three points (or one) is grouped by side, as before.
    set.landmarks
        .push(("RV_INSERT".into(), dir(-60.0) * 22.0 + v3(0.0, 0.0, -16.0)));
    let o = orientation(&set, &wall).unwrap();
    let three = middle(
        dir(-30.0) * 2.0 + dir(-40.0) + dir(-60.0) + dir(-80.0),
        dir(-150.0) * 2.0,
    );
    assert!(
        (o.septum - three).norm() < 1e-9,
        "{:?} vs {three:?}",
        o.septum
    );
}

#[test]
fn insertions_that_name_their_side_place_the_septum_alone() {
    let wall = shifted_shell();
    let dir = |deg: f64| v3(deg.to_radians().cos(), deg.to_radians().sin(), 0.0);
    // The RV towards -y, anterior towards +x (a positive turn about +z, apex to base, from the
    // septum), and the user's reference points 10 degrees off that: they win.
    let mut set = ContourSet::default();
    set.contours
        .push(ring("rv", "RV_ENDO", v3(0.0, -40.0, -5.0), 15.0));
    let at = |deg: f64, z: f64| dir(deg) * 22.0 + v3(0.0, 0.0, z);
    for z in [-5.0, -10.0] {
        set.landmarks
            .push(("RV_INSERT_ANTERIOR".into(), at(-20.0, z)));
        set.landmarks
            .push(("RV_INSERT_INFERIOR".into(), at(-140.0, z)));
    }
    let o = orientation(&set, &wall).unwrap();
    assert_eq!(o.source, "anterior and inferior RV insertion points");
    assert_eq!(o.points, 4);
    assert!((o.septum - dir(-80.0)).norm() < 1e-6, "{:?}", o.septum);
    // Either side alone: the septum's middle 60 degrees on, towards the other.
    let only = |keep: &str| {
        let mut one = set.clone();
        one.landmarks.retain(|(n, _)| n == keep);
        orientation(&one, &wall).unwrap()
    };
    let a = only("RV_INSERT_ANTERIOR");
    assert_eq!(
        a.source,
        "RV insertion points of one side, the septum 60 degrees on"
    );
    assert!((a.septum - dir(-80.0)).norm() < 1e-6, "{:?}", a.septum);
    assert!((only("RV_INSERT_INFERIOR").septum - dir(-80.0)).norm() < 1e-6);
    // Insertions more than half a turn apart the short way round through the lateral wall: the
    // middle is still taken through the septum (the arc from anterior to inferior runs negative).
    let mut wide = ContourSet::default();
    wide.landmarks
        .push(("RV_INSERT_ANTERIOR".into(), at(40.0, -5.0)));
    wide.landmarks
        .push(("RV_INSERT_INFERIOR".into(), at(160.0, -5.0)));
    let w = orientation(&wide, &wall).unwrap();
    assert!((w.septum - dir(-80.0)).norm() < 1e-6, "{:?}", w.septum);
    // Without the RV contours, the sides alone still say where the septum is.
    let mut lv_only = set.clone();
    lv_only.contours.clear();
    assert!((orientation(&lv_only, &wall).unwrap().septum - dir(-80.0)).norm() < 1e-6);
}

#[test]
fn points_that_are_not_finite_are_passed_over() {
    let wall = shifted_shell();
    let mut set = ContourSet::default();
    let mut rv = ring("rv", "RV_ENDO", v3(0.0, -40.0, -5.0), 15.0);
    rv.pieces[0].points.push(v3(f64::NAN, 0.0, 0.0));
    rv.pieces[0].points.push(v3(f64::INFINITY, 0.0, -5.0));
    set.contours.push(rv);
    set.landmarks
        .push(("RV_INSERT".into(), v3(f64::NAN, 1.0, -5.0)));
    set.landmarks
        .push(("RV_INSERT".into(), v3(1.0, f64::NEG_INFINITY, -5.0)));
    // The two insertion points are no points: the RV's 24 finite ones place the septum.
    let o = orientation(&set, &wall).unwrap();
    assert_eq!(o.source, "the RV contours' centre");
    assert_eq!(o.points, 24);
    assert!(
        (o.septum - v3(0.0, -1.0, 0.0)).norm() < 1e-6,
        "{:?}",
        o.septum
    );
    let s = segments(&wall, &o).unwrap();
    assert!(s
        .segments
        .iter()
        .all(|g| g.mean_mm.is_some_and(f64::is_finite)));
}

#[test]
fn thickening_is_the_change_over_the_end_diastolic_thickness() {
    let wall = shifted_shell();
    let ed = segments(&wall, &towards(1.0, 0.0)).unwrap();
    let mut es = ed.clone();
    es.segments[0].mean_mm = es.segments[0].mean_mm.map(|t| 1.5 * t);
    es.segments[1].mean_mm = es.segments[1].mean_mm.map(|t| 0.9 * t);
    es.segments[2].mean_mm = None;
    let t = thickening(&ed, &es);
    assert_eq!(t.len(), 17);
    assert!((t[0].thickening_percent.unwrap() - 50.0).abs() < 1e-9);
    assert!(
        (t[1].thickening_percent.unwrap() + 10.0).abs() < 1e-9,
        "a segment that thins"
    );
    assert_eq!(t[2].thickening_percent, None);
    assert_eq!(t[3].thickening_percent, Some(0.0));
    assert_eq!((t[16].id, t[16].name), (17, "apex"));
}
