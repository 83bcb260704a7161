use super::*;
use crate::contours::{Contour, Polyline};
use crate::geometry::v3;
use crate::sim::shapes::uv_sphere;
use crate::sim::slice::Plane;
use std::f64::consts::TAU;

/// Semi-axes of the end-diastolic ellipsoid (mm) and its base plane's height.
const A: f64 = 25.0;
const B: f64 = 20.0;
const C: f64 = 40.0;
const BASE_Z: f64 = 12.0;

/// The ellipsoid with its cross-section scaled by `across` (the same length along z).
fn cavity(across: f64) -> TriMesh {
    let mut m = uv_sphere(v3(0.0, 0.0, 0.0), 1.0, 256, 128);
    for p in &mut m.positions {
        *p = v3(p.x * A * across, p.y * B * across, p.z * C);
    }
    m
}

fn base() -> Plane {
    Plane::new(v3(0.0, 0.0, BASE_Z), v3(0.0, 0.0, 1.0)).unwrap()
}

/// A closed ring of 12 points, radius 18 mm, at height `z`, centred at (cx, cy).
fn ring(id: &str, surface: &str, (cx, cy): (f64, f64), z: f64) -> Contour {
    let points = (0..12)
        .map(|k| {
            let a = k as f64 * TAU / 12.0;
            v3(cx + 18.0 * a.cos(), cy + 18.0 * a.sin(), z)
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

/// An LV file whose RV centre lies 45 mm away at `deg` degrees from -x (towards -y); no RV
/// at all with None.
fn file(rv_deg: Option<f64>) -> ContourSet {
    let mut set = ContourSet::default();
    set.contours.push(ring("lv", "LV_ENDO", (0.0, 0.0), 0.0));
    if let Some(deg) = rv_deg {
        let a = deg.to_radians();
        set.contours.push(ring(
            "rv",
            "RV_ENDO",
            (-45.0 * a.cos(), -45.0 * a.sin()),
            -5.0,
        ));
    }
    set
}

/// One phase's surface of the study.
fn item<'a>(
    phase: &'a str,
    surface: &'a str,
    set: &'a ContourSet,
    mesh: Option<(&'a TriMesh, &'a ClipPlane)>,
) -> PhaseSurface<'a> {
    PhaseSurface {
        phase,
        surface,
        set,
        mesh,
    }
}

fn layout() -> Layout {
    Layout::new(6, 16).unwrap()
}

#[test]
fn every_phase_is_turned_by_the_reference_phases_septum() {
    let (ed_set, es_set) = (file(Some(0.0)), file(Some(5.0)));
    let (ed, es, plane) = (cavity(1.0), cavity(0.9), base());
    let items = [
        item("ED", "LV_ENDO", &ed_set, Some((&ed, &plane))),
        item("ES", "LV_ENDO", &es_set, Some((&es, &plane))),
    ];
    let study = of_study(&items, Some("ED"), layout()).unwrap();
    assert_eq!(study.septum.phase, "ED");
    assert_eq!(
        study.septum.source,
        "the RV contours' centre (12) of phase ED"
    );
    let d = study.septum.direction;
    assert!((d[0] + 1.0).abs() < 1e-9 && d[1].abs() < 1e-9, "{d:?}");
    let [l_ed, l_es] = [&study.layouts[0], &study.layouts[1]];
    let (a_ed, a_es) = (l_ed.built.as_ref().unwrap(), l_es.built.as_ref().unwrap());
    assert_eq!(a_es.summary.septum_from, study.septum.source);
    // ES's own file puts its septum 5 degrees round; its layout keeps ED's.
    assert!(l_ed.septum_turn_deg.unwrap() < 1e-6);
    assert!(
        (l_es.septum_turn_deg.unwrap() - 5.0).abs() < 0.01,
        "{:?}",
        l_es.septum_turn_deg
    );
    for ring in 1..=6 {
        let p = a_es.mesh.positions[1 + (ring - 1) * 16];
        assert!(p.x < 0.0 && p.y.abs() < 1e-6, "ES ring {ring}: {p:?}");
    }
    // Displacement from ED: none at ED; on the wall rings (level rays from the axis) a tenth of
    // the ED vertex's distance from the axis, as the cross-section shrank by a tenth.
    assert_eq!(l_ed.displacement_stats(), Some((0.0, 0.0)));
    let shift = l_es.displacement_mm.as_ref().unwrap();
    assert_eq!(shift.len(), a_ed.mesh.positions.len());
    let wall_ring_start = 1 + 2 * 16; // rings 3..=6 lie above the apical cap (a third, 2 rings)
    let wall = wall_ring_start..=6 * 16;
    for (v, (p, d)) in a_ed.mesh.positions.iter().zip(shift).enumerate() {
        if wall.contains(&v) {
            let expected = 0.1 * (p.x * p.x + p.y * p.y).sqrt();
            assert!((d - expected).abs() < 0.02, "vertex {v}: {d} vs {expected}");
        }
    }
    let (mean, max) = l_es.displacement_stats().unwrap();
    assert!(mean > 0.5 && max <= 0.1 * A + 0.02, "{mean} {max}");
}

#[test]
fn a_phase_without_a_septum_is_laid_out_on_another_phases() {
    let (ed_set, es_set) = (file(Some(0.0)), file(None));
    let (ed, es, plane) = (cavity(1.0), cavity(0.9), base());
    let items = [
        item("ED", "LV_ENDO", &ed_set, Some((&ed, &plane))),
        item("ES", "LV_ENDO", &es_set, Some((&es, &plane))),
    ];
    // ES preferred (as if it were the larger), but its file cannot say: ED's septum for both.
    let study = of_study(&items, Some("ES"), layout()).unwrap();
    assert_eq!(study.septum.phase, "ED");
    let es_layout = &study.layouts[1];
    assert!(es_layout.built.is_ok());
    assert_eq!(es_layout.septum_turn_deg, None);
    // Displacement is from ED, the phase the septum came from.
    assert!(es_layout.displacement_stats().unwrap().0 > 0.5);
}

#[test]
fn what_cannot_be_laid_out_says_why() {
    let (lv_only, with_rv) = (file(None), file(Some(0.0)));
    let (ed, plane) = (cavity(1.0), base());
    let lv_only_item = item("ED", "LV_ENDO", &lv_only, Some((&ed, &plane)));
    let e = of_study(&[lv_only_item], None, layout()).unwrap_err();
    assert!(
        e.contains("no RV_INSERT landmarks and no RV contours"),
        "{e}"
    );
    let e = of_study(&[], None, layout()).unwrap_err();
    assert!(e.contains("no phase has a closed LV surface"), "{e}");
    let bad = Layout {
        rings: 1,
        points: 16,
    };
    assert!(of_study(&[lv_only_item], None, bad)
        .unwrap_err()
        .contains("2-200 rings"));
    // An RV surface and a failed run get their reasons; the LV its layout.
    let items = [
        item("ED", "RV_ENDO", &with_rv, Some((&ed, &plane))),
        item("ED", "LV_EPI", &with_rv, None),
        item("ED", "LV_ENDO", &with_rv, Some((&ed, &plane))),
    ];
    let study = of_study(&items, Some("ED"), layout()).unwrap();
    assert!(study.layouts[0]
        .built
        .as_ref()
        .unwrap_err()
        .contains("the LV's"));
    assert!(study.layouts[1]
        .built
        .as_ref()
        .unwrap_err()
        .contains("no closed mesh"));
    assert!(study.layouts[2].built.is_ok());
    assert_eq!(study.septum.surface, "LV_ENDO");
}

#[test]
fn the_septum_is_taken_across_each_phases_own_axis() {
    let with_rv = file(Some(0.0));
    let ed = cavity(1.0);
    // ES's long axis tilted 10 degrees towards the septum (-x): its base normal too.
    let tilt = 10f64.to_radians();
    let normal = v3(-tilt.sin(), 0.0, tilt.cos());
    let tilted = Plane::new(normal * BASE_Z, normal).unwrap();
    let rot = nalgebra::Rotation3::rotation_between(&v3(0.0, 0.0, 1.0), &normal).unwrap();
    let mut es = cavity(0.9);
    es.positions.iter_mut().for_each(|p| *p = rot * *p);
    let plane = base();
    let items = [
        item("ED", "LV_ENDO", &with_rv, Some((&ed, &plane))),
        item("ES", "LV_ENDO", &with_rv, Some((&es, &tilted))),
    ];
    let study = of_study(&items, Some("ED"), layout()).unwrap();
    let s = &study.layouts[1].built.as_ref().unwrap().summary;
    let septum = Vec3::from(s.septum_direction);
    assert!(septum.dot(&normal).abs() < 1e-9, "across the phase's axis");
    // -x taken across the tilted axis.
    assert!(
        (septum - rot * v3(-1.0, 0.0, 0.0)).norm() < 1e-9,
        "{septum:?}"
    );
}
