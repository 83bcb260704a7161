//! The study's simulated cases: misaligned acquisitions whose per-image motions are redrawn
//! exactly as `sim` draws them, so each image's correction is known.
use heartmesh_core::contours::{Contour, ContourSet, Polyline};
use heartmesh_core::geometry::Vec3;
use heartmesh_core::io;
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::sim::planes::draw_motion;
use heartmesh_core::sim::prng::SplitMix64;
use heartmesh_core::sim::repair::{orient_consistently, weld};
use heartmesh_core::sim::slice::{join_chains, polyline_length, resample};
use heartmesh_core::sim::{simulate, slice_mesh, AcquisitionSpec, Misalignment, Plane};
use nalgebra::Rotation3;
use std::collections::HashMap;

pub fn truth(dir: &str, name: &str) -> TriMesh {
    let path = format!("{dir}/meshes/{name}");
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let m = io::read_mesh(name, &bytes)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .mesh;
    orient_consistently(&weld(&m, 1e-6).0).0
}

/// The acquisitions' misalignment: every image shifted up to 2 mm and tilted up to 2 degrees.
const TWO_MM_TWO_DEG: Misalignment = Misalignment {
    shift_mm: 2.0,
    tilt_deg: 2.0,
};

/// One simulated case: the contours, each contour id's true in-plane correction (the image's
/// shift, projected into its nominal plane) and plane normal, and the long axis.
pub struct Case {
    pub name: String,
    pub set: ContourSet,
    pub truth: HashMap<String, (Vec3, Vec3, f64)>,
    pub axis: Vec3,
    /// Mean shift of the short-axis images along the axis (through their planes; mm).
    pub sax_through: f64,
    /// The truths (surface label, mesh) and the basal clip plane, for mesh-to-truth.
    pub truths: Vec<(Option<String>, TriMesh)>,
    pub clip: Plane,
}

/// `sim::simulate` with 2 mm / 2 degree misalignment; the motions redrawn to know the shifts.
pub fn lv_case(name: &str, mesh: &TriMesh, base: &AcquisitionSpec, seed: u64) -> Option<Case> {
    let spec = AcquisitionSpec {
        misalignment: Some(TWO_MM_TWO_DEG),
        seed,
        ..base.clone()
    };
    let acq = simulate(mesh, &spec).ok()?;
    let mut rng = SplitMix64::new(seed);
    let mut truth = HashMap::new();
    let mut through = Vec::new();
    let named = acq
        .sax_planes
        .iter()
        .enumerate()
        .map(|(k, p)| (format!("sax{:02}", k + 1), p))
        .chain(
            acq.lax_planes
                .iter()
                .enumerate()
                .map(|(k, p)| (format!("lax{:02}", k + 1), p)),
        );
    for (id, plane) in named {
        let m = draw_motion(&mut rng, plane, TWO_MM_TWO_DEG);
        let n = plane.normal;
        if id.starts_with("sax") {
            through.push(m.shift.dot(&n));
        }
        truth.insert(id, (m.shift - n * m.shift.dot(&n), n, m.shift.dot(&n)));
    }
    Some(Case {
        name: format!("{name} s{seed}"),
        set: acq.contours,
        truth,
        axis: acq.axis.direction,
        sax_through: through.iter().sum::<f64>() / through.len().max(1) as f64,
        truths: vec![(None, mesh.clone())],
        clip: acq.clip,
    })
}

/// A clean acquisition (no misalignment): nothing to correct.
pub fn clean_case(name: &str, mesh: &TriMesh, base: &AcquisitionSpec) -> Option<Case> {
    let acq = simulate(mesh, base).ok()?;
    let truth = acq
        .contours
        .contours
        .iter()
        .map(|c| (c.id.clone(), (Vec3::zeros(), acq.axis.direction, 0.0)))
        .collect();
    Some(Case {
        name: format!("{name} clean"),
        set: acq.contours,
        truth,
        axis: acq.axis.direction,
        sax_through: 0.0,
        truths: vec![(None, mesh.clone())],
        clip: acq.clip,
    })
}

/// Which parts of each image's motion an acquisition keeps.
#[derive(Clone, Copy)]
pub struct Parts {
    /// The 2-degree tilts.
    pub tilt: bool,
    /// The shifts' components through the images' own planes: short-axis, long-axis images.
    pub through_sax: bool,
    pub through_lax: bool,
}

pub const ALL_PARTS: Parts = Parts {
    tilt: true,
    through_sax: true,
    through_lax: true,
};

/// LV and RV cut by the same misaligned images (as tests/alignment.rs `biventricular`).
pub fn biv_case(name: &str, lv: &TriMesh, rv: &TriMesh, seed: u64) -> Option<Case> {
    let base = AcquisitionSpec::default();
    own_case(
        name,
        &[("LV_ENDO", lv), ("RV_ENDO", rv)],
        &base,
        seed,
        ALL_PARTS,
    )
}

/// Surfaces cut by the same misaligned images planned on the first (motions drawn as `sim` draws
/// them), keeping only `parts` of each motion.
pub fn own_case(
    name: &str,
    surfaces: &[(&str, &TriMesh)],
    base: &AcquisitionSpec,
    seed: u64,
    parts: Parts,
) -> Option<Case> {
    let nominal = simulate(surfaces.first()?.1, base).ok()?;
    let planes = nominal
        .sax_planes
        .iter()
        .map(|p| ("sax", *p))
        .chain(nominal.lax_planes.iter().map(|p| ("lax", *p)));
    let mut rng = SplitMix64::new(seed);
    let mut set = ContourSet::default();
    let mut truth = HashMap::new();
    let mut through = Vec::new();
    for (k, (kind, plane)) in planes.enumerate() {
        let mut m = draw_motion(&mut rng, &plane, TWO_MM_TWO_DEG);
        if !parts.tilt {
            m.rotation = Rotation3::identity();
        }
        if !(if kind == "sax" {
            parts.through_sax
        } else {
            parts.through_lax
        }) {
            m.shift -= plane.normal * m.shift.dot(&plane.normal);
        }
        let imaged = m.apply_to_plane(&plane);
        let n = plane.normal;
        if kind == "sax" {
            through.push(m.shift.dot(&n));
        }
        for &(surf, mesh) in surfaces {
            let mut pieces = join_chains(slice_mesh(mesh, &imaged), 3.0, &imaged);
            pieces.sort_by(|a, b| polyline_length(b).total_cmp(&polyline_length(a)));
            let Some(first) = pieces.first() else {
                continue;
            };
            let piece = resample(first, 1.0);
            if piece.points.len() < 5 {
                continue;
            }
            let points = piece.points.iter().map(|p| m.inverse_apply(p)).collect();
            let id = format!("{kind}{k:02}_{surf}");
            truth.insert(
                id.clone(),
                (m.shift - n * m.shift.dot(&n), n, m.shift.dot(&n)),
            );
            set.contours.push(Contour {
                id,
                surface: Some(surf.into()),
                pieces: vec![Polyline {
                    points,
                    closed: kind == "sax",
                }],
                first_line: 0,
            });
        }
    }
    Some(Case {
        name: format!("{name} s{seed}"),
        set,
        truth,
        axis: nominal.axis.direction,
        sax_through: through.iter().sum::<f64>() / through.len().max(1) as f64,
        truths: surfaces
            .iter()
            .map(|(s, m)| (Some(s.to_string()), (*m).clone()))
            .collect(),
        clip: nominal.clip,
    })
}
