use super::anatomy::refine_axis;
use super::*;
use crate::sim::shapes::ParametricLv;

fn lv() -> TriMesh {
    ParametricLv::default().mesh(96, 60).unwrap()
}

/// A dilated, squat open ventricle (wider than long, tilted in the scanner): its principal
/// axis lies in the base plane, and the rounds from it stop more than 14 degrees off (on
/// population member p69 the stack then cut the rim and left a 40 mm gap); the rim start
/// finds the true axis.
#[test]
fn squat_open_ventricle_is_planned_along_its_axis() {
    let squat = ParametricLv {
        length_mm: 50.0,
        radius_mm: 34.0,
        base_radius_mm: 30.0,
        ..ParametricLv::default()
    }
    .mesh(96, 60)
    .unwrap();
    let turn = Rotation3::from_euler_angles(0.4, -0.7, 1.1);
    let offset = Vec3::new(120.0, -250.0, 80.0);
    let truth = TriMesh::new(
        squat.positions.iter().map(|p| turn * p + offset).collect(),
        squat.triangles.clone(),
    );
    let true_axis = turn * Vec3::z();
    let (pca, _) = LongAxis::from_mesh(&truth).unwrap();
    let principal = refine_axis(&truth, pca, 3.0);
    assert!(
        principal.direction.dot(&true_axis).abs() < 0.97,
        "the principal start should fail on this shape: {:?}, dot {}",
        principal.direction,
        principal.direction.dot(&true_axis)
    );
    let axis = anatomical_axis(&truth, 3.0).unwrap();
    assert!(
        axis.direction.dot(&true_axis) > 0.999,
        "{:?} vs {true_axis:?}",
        axis.direction
    );
    let acq = simulate(&truth, &AcquisitionSpec::default()).unwrap();
    let (lo, _, _) = acq.axis.extent(&truth).unwrap();
    let heights: Vec<f64> = acq
        .sax_planes
        .iter()
        .map(|p| acq.axis.height(&p.origin) - lo)
        .collect();
    // A regular 10 mm stack from near the apex to below the rim (50 mm): 3-47 mm.
    assert!(heights.len() >= 4, "{heights:?}");
    assert!(heights
        .windows(2)
        .all(|w| (w[1] - w[0] - 10.0).abs() < 1e-6));
    assert!(
        heights[0] < 10.0 && *heights.last().unwrap() > 40.0,
        "{heights:?}"
    );
}

#[test]
fn default_stack_and_lax() {
    let truth = lv();
    let acq = simulate(&truth, &AcquisitionSpec::default()).unwrap();
    // Base rim at 80 mm, last closed section scanned at 79.75, top slice 3 mm below it, then
    // every 10 mm down to >= 3 mm: 76.75, 66.75, ..., 6.75.
    assert_eq!(acq.sax_planes.len(), 8);
    let (lo, _, _) = acq.axis.extent(&truth).unwrap();
    let top = acq.axis.height(&acq.clip.origin) - lo;
    assert!((top - 76.75).abs() < 1e-6, "top slice at {top}");
    assert_eq!(acq.lax_planes.len(), 3);
    assert_eq!(acq.contours.contours.len(), 11);
    let ids: Vec<&str> = acq
        .contours
        .contours
        .iter()
        .map(|c| c.id.as_str())
        .collect();
    assert_eq!(ids[0], "sax01");
    assert_eq!(ids[8], "lax01");
    let h = |p: &Plane| acq.axis.height(&p.origin);
    assert!((h(&acq.clip) - h(&acq.sax_planes[0]) - 70.0).abs() < 1e-9);
    for (c, plane) in acq.contours.contours.iter().zip(&acq.sax_planes) {
        assert!(c.pieces[0].closed, "{}", c.id);
        assert!(lies_in_plane(&c.pieces[0], plane, 1e-9));
        // ~1 mm spacing.
        let pl = &c.pieces[0];
        let spacing = polyline_length(pl) / pl.points.len() as f64;
        assert!((spacing - 1.0).abs() < 0.05, "{} spacing {spacing}", c.id);
    }
    for c in &acq.contours.contours[8..] {
        // The LV is open at the base: long-axis curves are U-shaped, open.
        assert!(!c.pieces[0].closed, "{}", c.id);
    }
    // 90 degrees between lax01 and lax02.
    let d = acq.lax_planes[0].normal.dot(&acq.lax_planes[1].normal);
    assert!(d.abs() < 1e-12);
}

/// A sheared LV (its base centre moved 24 mm sideways): the planner's axis passes through the
/// apex, the shape's lowest point along it (where the surface is perpendicular to the line from
/// the base centre, the farthest point from it); the principal axis passes 4+ mm from its own.
#[test]
fn anatomical_axis_passes_through_the_apex() {
    let mut truth = lv();
    for p in &mut truth.positions {
        p.x += 0.3 * p.z;
    }
    let off_axis = |a: &LongAxis, p: &Vec3| {
        let v = p - a.centre;
        (v - a.direction * a.direction.dot(&v)).norm()
    };
    let lowest = |a: &LongAxis| {
        *truth
            .positions
            .iter()
            .min_by(|p, q| a.height(p).total_cmp(&a.height(q)))
            .unwrap()
    };
    let axis = anatomical_axis(&truth, 3.0).unwrap();
    let apex = lowest(&axis);
    assert!(off_axis(&axis, &apex) < 0.5, "{}", off_axis(&axis, &apex));
    let (pca, _) = LongAxis::from_mesh(&truth).unwrap();
    assert!(off_axis(&pca, &lowest(&pca)) > 2.0);
    // The long-axis planes of a simulated acquisition contain the apex.
    let acq = simulate(&truth, &AcquisitionSpec::default()).unwrap();
    for plane in &acq.lax_planes {
        assert!(plane.signed_distance(&apex).abs() < 0.5);
    }
    // On the symmetric LV both axes are the z axis through the pole.
    let axis = anatomical_axis(&lv(), 3.0).unwrap();
    assert!(axis.direction.z > 0.99999, "{:?}", axis.direction);
    assert!(off_axis(&axis, &Vec3::zeros()) < 1e-6);
}

#[test]
fn misalignment_is_bounded_and_seeded() {
    let truth = lv();
    let spec = misaligned(7);
    let a = simulate(&truth, &spec).unwrap();
    let b = simulate(&truth, &spec).unwrap();
    assert_eq!(a.contours, b.contours);
    let c = simulate(
        &truth,
        &AcquisitionSpec {
            seed: 8,
            ..spec.clone()
        },
    )
    .unwrap();
    assert_ne!(a.contours, c.contours);
    // Contours stay in their nominal planes (the scanner's coordinates)...
    for (cont, plane) in a.contours.contours.iter().zip(&a.sax_planes) {
        assert!(lies_in_plane(&cont.pieces[0], plane, 1e-9), "{}", cont.id);
    }
    // ...but are displaced from the truth: at most shift + tilt * lever arm.
    let aligned = simulate(&truth, &AcquisitionSpec::default()).unwrap();
    let mut moved = 0;
    for (m, s) in a.contours.contours.iter().zip(&aligned.contours.contours) {
        let cm = centroid(m.points());
        let cs = centroid(s.points());
        let d = (cm - cs).norm();
        assert!(d < 2.0 + 0.04 * 40.0 + 0.5, "{}: centroid moved {d}", m.id);
        if d > 0.2 {
            moved += 1;
        }
    }
    assert!(moved >= 5, "only {moved} contours moved");
}

#[test]
fn count_stack_and_noise() {
    let truth = lv();
    let spec = AcquisitionSpec {
        sax: SaxStack::Count(4),
        lax_count: 0,
        noise_mm: 0.5,
        ..AcquisitionSpec::default()
    };
    let acq = simulate(&truth, &spec).unwrap();
    assert_eq!(acq.contours.contours.len(), 4);
    let h: Vec<f64> = acq
        .sax_planes
        .iter()
        .map(|p| acq.axis.height(&p.origin))
        .collect();
    assert!((h[3] - h[0] - (79.75 - 6.0)).abs() < 1e-6);
    // Noise stays in plane.
    for (c, plane) in acq.contours.contours.iter().zip(&acq.sax_planes) {
        assert!(lies_in_plane(&c.pieces[0], plane, 1e-9));
    }
    let bad = AcquisitionSpec {
        lax_count: 9,
        ..AcquisitionSpec::default()
    };
    assert_eq!(
        simulate(&truth, &bad).unwrap_err().code(),
        "param_out_of_range"
    );
}

#[test]
fn csv_round_trip() {
    let truth = lv();
    let spec = AcquisitionSpec {
        surface: Some("LV_ENDO".into()),
        lax_count: 2,
        ..AcquisitionSpec::default()
    };
    let acq = simulate(&truth, &spec).unwrap();
    let csv = crate::io::csv::write_csv(&acq.contours, None).unwrap();
    let back = crate::io::read_contours("sim.csv", &csv).unwrap();
    assert_eq!(back.contours.len(), acq.contours.contours.len());
    for (a, b) in acq.contours.contours.iter().zip(&back.contours) {
        assert_eq!(a.id, b.id);
        assert_eq!(b.surface.as_deref(), Some("LV_ENDO"));
        assert_eq!(a.pieces.len(), b.pieces.len(), "{}", a.id);
        assert_eq!(a.pieces[0].closed, b.pieces[0].closed, "{}", a.id);
        assert_eq!(a.point_count(), b.point_count(), "{}", a.id);
    }
}

/// The default acquisition with breath-hold motion of up to 2 mm and 2 degrees, drawn by `seed`.
fn misaligned(seed: u64) -> AcquisitionSpec {
    AcquisitionSpec {
        misalignment: Some(Misalignment {
            shift_mm: 2.0,
            tilt_deg: 2.0,
        }),
        seed,
        ..AcquisitionSpec::default()
    }
}

/// Contours of surface `label` whose image id starts with `kind` ("sax", "lax"): how the tests
/// of several surfaces count what each got.
fn contours_of(acq: &Acquisition, label: &str, kind: &str) -> usize {
    acq.contours
        .contours
        .iter()
        .filter(|c| c.surface.as_deref() == Some(label) && c.id.starts_with(kind))
        .count()
}

fn centroid<'a>(pts: impl Iterator<Item = &'a Vec3>) -> Vec3 {
    let (s, n) = pts.fold((Vec3::zeros(), 0usize), |(s, n), p| (s + p, n + 1));
    s / n as f64
}

/// One acquisition of several surfaces: every image moves all of them alike (two copies of one
/// shape get the very same curves), each gets its label and the image's id, a surface shorter
/// than the other gets no slice below its own apex, and one surface alone is `simulate`'s
/// acquisition.
#[test]
fn surfaces_sliced_together_share_each_image_motion() {
    let truth = lv();
    let spec = misaligned(11);
    let both = simulate_surfaces(&[("A", &truth), ("B", &truth)], &spec).unwrap();
    let alone = simulate(&truth, &spec).unwrap();
    assert_eq!(
        both.contours.contours.len(),
        2 * alone.contours.contours.len()
    );
    for (pair, single) in both
        .contours
        .contours
        .chunks(2)
        .zip(&alone.contours.contours)
    {
        assert_eq!(pair[0].id, format!("{}_A", single.id));
        assert_eq!(pair[1].id, format!("{}_B", single.id));
        assert_eq!(pair[0].surface.as_deref(), Some("A"));
        assert_eq!(pair[0].pieces, pair[1].pieces);
        assert_eq!(pair[0].pieces, single.pieces);
    }
    let one = simulate_surfaces(&[("A", &truth)], &spec).unwrap();
    assert_eq!(one.sax_planes, alone.sax_planes);

    // A shorter inner surface (the endocardium's apex above the epicardium's): the stack runs to
    // the lower apex, the inner one only where it has sections.
    // The shape shrunk by a quarter about its base centre (apex at z = 0, base at z = 80).
    let base_centre = Vec3::new(0.0, 0.0, 80.0);
    let inner = TriMesh::new(
        truth
            .positions
            .iter()
            .map(|p| base_centre + (p - base_centre) * 0.75)
            .collect(),
        truth.triangles.clone(),
    );
    let joint = simulate_surfaces(
        &[("OUTER", &truth), ("INNER", &inner)],
        &AcquisitionSpec::default(),
    )
    .unwrap();
    let count = |label: &str, kind: &str| contours_of(&joint, label, kind);
    assert_eq!(count("OUTER", "sax"), joint.sax_planes.len());
    assert!(count("INNER", "sax") < count("OUTER", "sax"));
    assert!(count("INNER", "sax") >= 4);
    assert_eq!(count("INNER", "lax"), 3);
    assert!(simulate_surfaces(&[], &AcquisitionSpec::default()).is_err());
}

/// A surface whose closed sections stop well below the planned surface's base (more than one
/// slice spacing: a composite RV cavity opening into its outflow tract) is drawn only up to its
/// own top and does not take the planned surface's basal slices away; one within a slice of it
/// shares the base (the stack stops under both, as walls need). Each surface's clip is its own
/// most basal slice.
#[test]
fn a_surface_ending_far_below_the_base_keeps_the_others_slices() {
    let truth = lv();
    let about_apex = |scale: f64| {
        TriMesh::new(
            truth.positions.iter().map(|p| p * scale).collect(),
            truth.triangles.clone(),
        )
    };
    let spec = AcquisitionSpec::default();
    let alone = simulate(&truth, &spec).unwrap();
    let top = |a: &Acquisition| a.clip.origin.z;
    let sax = |a: &Acquisition, label: &str| contours_of(a, label, "sax");

    // 0.6 x the shape: its closed sections end ~30 mm under the planned base.
    let short = about_apex(0.6);
    let joint = simulate_surfaces(&[("LV", &truth), ("SHORT", &short)], &spec).unwrap();
    assert_eq!(joint.sax_planes, alone.sax_planes);
    assert_eq!(sax(&joint, "LV"), alone.sax_planes.len());
    // The base is at z = 80 (apex at 0).
    let short_top = 0.6 * 80.0;
    let own = joint.surface_clips[1].origin.z;
    assert!(
        own < short_top && own > short_top - 10.0 - spec.base_margin_mm,
        "{own}"
    );
    assert!(sax(&joint, "SHORT") >= 3 && sax(&joint, "SHORT") < sax(&joint, "LV"));
    assert_eq!(joint.surface_clips[0], joint.clip);
    // A counted stack likewise: all its slices on the planned surface, up to its base.
    let counted = AcquisitionSpec {
        sax: SaxStack::Count(8),
        ..AcquisitionSpec::default()
    };
    let alone8 = simulate(&truth, &counted).unwrap();
    let joint8 = simulate_surfaces(&[("LV", &truth), ("SHORT", &short)], &counted).unwrap();
    assert_eq!(joint8.clip, alone8.clip);
    assert_eq!(sax(&joint8, "LV"), 8);
    assert!(joint8.surface_clips[1].origin.z < short_top);

    // 0.93 x the shape: ~6 mm under the planned base, within a slice: it sets the stack's top.
    let near = about_apex(0.93);
    let shared = simulate_surfaces(&[("LV", &truth), ("NEAR", &near)], &spec).unwrap();
    assert!(
        top(&shared) < top(&alone) - 3.0,
        "{} vs {}",
        top(&shared),
        top(&alone)
    );
    assert_eq!(sax(&shared, "LV"), sax(&shared, "NEAR"));
    assert_eq!(shared.surface_clips, vec![shared.clip, shared.clip]);
}

/// A surface no short-axis plane cuts in one closed loop (an open patch standing along the axis)
/// beside the planned one: drawn on the long-axis images only, with a warning, instead of
/// refusing the whole acquisition; as the planned surface it is still refused.
#[test]
fn a_surface_without_closed_sections_gets_long_axis_curves_only() {
    let truth = lv();
    // A flat 10 x 60 mm strip in the plane y = 0 inside the cavity, along the axis.
    let strip = TriMesh::new(
        vec![
            Vec3::new(-5.0, 0.0, 10.0),
            Vec3::new(5.0, 0.0, 10.0),
            Vec3::new(5.0, 0.0, 70.0),
            Vec3::new(-5.0, 0.0, 70.0),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    );
    let spec = AcquisitionSpec::default();
    let alone = simulate(&truth, &spec).unwrap();
    let joint = simulate_surfaces(&[("LV", &truth), ("PATCH", &strip)], &spec).unwrap();
    assert_eq!(joint.sax_planes, alone.sax_planes);
    let of = |label: &str, kind: &str| contours_of(&joint, label, kind);
    assert_eq!(of("PATCH", "sax"), 0);
    assert!(of("PATCH", "lax") >= 1);
    assert!(joint
        .contours
        .warnings
        .iter()
        .any(|w| w.starts_with("PATCH: no short-axis slice")));
    assert!(simulate_surfaces(&[("PATCH", &strip), ("LV", &truth)], &spec).is_err());
}
