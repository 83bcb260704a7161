//! Cardiac function from the volumes of one heart's surfaces over several phases (time frames of a
//! cine, or one file per phase): end-diastolic and end-systolic volumes, stroke volume, ejection
//! fraction and LV myocardial mass. These are why most users reconstruct a cavity at all, and
//! doing the arithmetic by hand over a dozen reports invites slips (ED taken from the wrong file).
//!
//! Conventions, as in cardiac MR reporting (SCMR post-processing recommendations): end-diastole is
//! the phase of largest cavity volume and end-systole that of smallest, each ventricle on its own;
//! myocardial mass is the volume between the epi- and endocardial surfaces times 1.05 g/ml.
//! Volumes are those of the closed reconstructed meshes (lid at the base), so they include what
//! the lids close, as model-based volumes do; an open mesh has no volume and is left out.

use crate::contours::ContourSet;
use crate::geometry::Vec3;
use crate::mesh::topology::validity;
use crate::mesh::TriMesh;
use crate::pipeline::Reconstruction;
use serde::Serialize;

/// Density of myocardium, g/ml (the value every CMR mass measurement uses).
pub const MYOCARDIAL_DENSITY_G_PER_ML: f64 = 1.05;

/// One surface's volume in one phase: None when it has none (open mesh, failed run, missing).
#[derive(Debug, Clone, PartialEq)]
pub struct PhaseVolume {
    pub phase: String,
    pub volume_ml: Option<f64>,
}

/// A cavity's function over the phases.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ventricle {
    pub surface: String,
    pub ed_phase: String,
    pub es_phase: String,
    pub edv_ml: f64,
    pub esv_ml: f64,
    pub sv_ml: f64,
    pub ef_percent: f64,
    /// Phases with a volume (the others were left out).
    pub phases_used: usize,
}

/// Whether a surface label is a cavity whose function is worth reporting: not an epicardium
/// (its volume holds the wall) and not an unidentified label of a segmentation.
pub fn is_cavity(surface: &str) -> bool {
    let s = surface.to_ascii_uppercase();
    !(s == "EPI" || s.ends_with("_EPI") || s.starts_with("LABEL_"))
}

/// End-diastolic (largest) and end-systolic (smallest) volumes of `surface` and what follows from
/// them; None with fewer than two phases holding a volume, or a largest volume that is not
/// positive. Ties go to the earlier phase.
pub fn ventricle(surface: &str, volumes: &[PhaseVolume]) -> Option<Ventricle> {
    let known: Vec<(&str, f64)> = volumes
        .iter()
        .filter_map(|p| Some((p.phase.as_str(), p.volume_ml.filter(|v| v.is_finite())?)))
        .collect();
    if known.len() < 2 {
        return None;
    }
    let mut ed = known[0];
    let mut es = known[0];
    for &(phase, v) in &known[1..] {
        if v > ed.1 {
            ed = (phase, v);
        }
        if v < es.1 {
            es = (phase, v);
        }
    }
    if ed.1 <= 0.0 {
        return None;
    }
    let sv = ed.1 - es.1;
    Some(Ventricle {
        surface: surface.to_string(),
        ed_phase: ed.0.to_string(),
        es_phase: es.0.to_string(),
        edv_ml: ed.1,
        esv_ml: es.1,
        sv_ml: sv,
        ef_percent: 100.0 * sv / ed.1,
        phases_used: known.len(),
    })
}

/// Myocardial mass in one phase, g: density times the volume between the surfaces. None where
/// either volume is missing or the epicardium does not hold more than the endocardium.
pub fn mass_g(endo_ml: Option<f64>, epi_ml: Option<f64>) -> Option<f64> {
    let wall = epi_ml? - endo_ml?;
    (wall.is_finite() && wall > 0.0).then_some(MYOCARDIAL_DENSITY_G_PER_ML * wall)
}

/// The column name of a file whose contours carry no surface label.
pub const UNLABELLED: &str = "surface";

/// Every surface of the phases' contour sets, in order of first appearance; `[None]` when none
/// carries a label (a single-surface file).
pub fn surfaces_of<'a>(sets: impl IntoIterator<Item = &'a ContourSet>) -> Vec<Option<String>> {
    let mut known: Vec<String> = Vec::new();
    for set in sets {
        for s in set.surfaces() {
            if !known.contains(&s) {
                known.push(s);
            }
        }
    }
    if known.is_empty() {
        vec![None]
    } else {
        known.into_iter().map(Some).collect()
    }
}

/// The name (without extension) of a phase's surface's file when a study's meshes are saved
/// (`volumes --meshes`, `--anatomical-meshes`, the app's archive): PHASE-SURFACE, characters a
/// file name cannot hold replaced by `_`.
pub fn file_stem(phase: &str, surface: &str) -> String {
    let safe = |s: &str| -> String {
        s.chars()
            .map(|c| {
                if c.is_alphanumeric() || "-_.".contains(c) {
                    c
                } else {
                    '_'
                }
            })
            .collect()
    };
    format!("{}-{}", safe(phase), safe(surface))
}

/// What one phase's surface came to in the function table.
#[derive(Debug, Clone, Default)]
pub struct Outcome {
    /// The closed mesh's volume; None when the mesh is open, the run failed or the phase lacks
    /// the surface.
    pub volume_ml: Option<f64>,
    pub watertight: bool,
    pub contour_to_mesh_mean: Option<f64>,
    pub mesh: Option<TriMesh>,
    /// Why there is no volume, in a word for the table: `open`, `failed` or `absent`.
    pub missing: Option<&'static str>,
}

impl Outcome {
    /// A finished reconstruction: its mesh, and a volume only if the mesh is closed (an open
    /// mesh's divergence sum is no volume).
    pub fn of(rec: &Reconstruction) -> Outcome {
        let mesh = rec.mesh().clone();
        let v = validity(&mesh);
        let watertight = v.closed && v.manifold && v.oriented;
        Outcome {
            volume_ml: watertight.then(|| mesh.volume_ml()),
            watertight,
            contour_to_mesh_mean: Some(rec.contour_distances().overall.mean),
            missing: (!watertight).then_some("open"),
            mesh: Some(mesh),
        }
    }

    /// No mesh, for the reason `missing` (`failed`, `absent`).
    pub fn none(missing: &'static str) -> Outcome {
        Outcome {
            missing: Some(missing),
            ..Outcome::default()
        }
    }

    pub fn measured(&self) -> Measured<'_> {
        Measured {
            volume_ml: self.volume_ml,
            mesh: self.mesh.as_ref(),
        }
    }
}

/// One surface's outcome in one phase, as [`summarise`] reads it.
#[derive(Debug, Clone, Copy, Default)]
pub struct Measured<'a> {
    /// The closed mesh's volume; None when the mesh is open, the run failed or the phase lacks
    /// the surface.
    pub volume_ml: Option<f64>,
    /// The mesh, when there is one (the biventricular check of the LV mass reads it).
    pub mesh: Option<&'a TriMesh>,
}

/// A cavity with fewer than two volumes: no ejection fraction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SingleVolume {
    pub surface: String,
    /// Its one volume, if any phase gave a closed mesh.
    pub volume_ml: Option<f64>,
}

/// The LV mass of one phase, or why there is none.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PhaseMass {
    pub phase: String,
    pub grams: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub why_none: Option<&'static str>,
}

/// LV myocardial mass over the phases.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LvMass {
    pub density_g_per_ml: f64,
    pub per_phase: Vec<PhaseMass>,
    /// At the LV's end-diastole and end-systole (None without an LV ejection fraction).
    pub ed_g: Option<f64>,
    pub es_g: Option<f64>,
}

/// Cardiac function of a study: each cavity's volumes over the phases and the LV mass.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Function {
    pub ventricles: Vec<Ventricle>,
    pub single: Vec<SingleVolume>,
    /// None unless both LV_ENDO and LV_EPI were measured.
    pub lv_mass: Option<LvMass>,
}

/// Share of the RV cavity's vertices inside an "LV epicardium" above which it is taken for a
/// biventricular epicardium (it holds the RV cavity, not just touches it).
const BIVENTRICULAR_SHARE: f64 = 0.5;

/// Function from `cells[phase][surface]` (the volumes of `surfaces` in each of `phases`).
/// Surfaces are matched by label: `LV_ENDO`, `LV_EPI` and `RV_ENDO` for the mass.
pub fn summarise(phases: &[String], surfaces: &[String], cells: &[Vec<Measured>]) -> Function {
    let column = |name: &str| surfaces.iter().position(|s| s == name);
    let mut ventricles = Vec::new();
    let mut single = Vec::new();
    for (j, name) in surfaces.iter().enumerate() {
        if !is_cavity(name) {
            continue;
        }
        let volumes: Vec<PhaseVolume> = phases
            .iter()
            .zip(cells)
            .map(|(phase, row)| PhaseVolume {
                phase: phase.clone(),
                volume_ml: row.get(j).and_then(|c| c.volume_ml),
            })
            .collect();
        match ventricle(name, &volumes) {
            Some(v) => ventricles.push(v),
            None => single.push(SingleVolume {
                surface: name.clone(),
                volume_ml: volumes.iter().find_map(|p| p.volume_ml),
            }),
        }
    }
    let lv_mass = match (column("LV_ENDO"), column("LV_EPI")) {
        (Some(endo), Some(epi)) => {
            let rv = column("RV_ENDO");
            let per_phase: Vec<PhaseMass> = phases
                .iter()
                .zip(cells)
                .map(|(phase, row)| {
                    let at = |j: usize| row.get(j).copied().unwrap_or_default();
                    let m = lv_mass(at(endo), at(epi), rv.map(at));
                    PhaseMass {
                        phase: phase.clone(),
                        grams: m.ok(),
                        why_none: m.err(),
                    }
                })
                .collect();
            let lv = ventricles.iter().find(|v| v.surface == "LV_ENDO");
            let at = |phase: Option<&str>| {
                per_phase
                    .iter()
                    .find(|m| Some(m.phase.as_str()) == phase)
                    .and_then(|m| m.grams)
            };
            Some(LvMass {
                density_g_per_ml: MYOCARDIAL_DENSITY_G_PER_ML,
                ed_g: at(lv.map(|v| v.ed_phase.as_str())),
                es_g: at(lv.map(|v| v.es_phase.as_str())),
                per_phase,
            })
        }
        _ => None,
    };
    Function {
        ventricles,
        single,
        lv_mass,
    }
}

/// The LV mass of one phase, or why there is none: an "LV epicardium" that holds the RV cavity is
/// a biventricular epicardium (label maps painted from biventricular models), whose volume minus
/// the LV cavity's would count the RV cavity as muscle.
pub fn lv_mass(
    endo: Measured,
    epi: Measured,
    rv: Option<Measured>,
) -> std::result::Result<f64, &'static str> {
    if let (Some(e), Some(r), Some(_)) = (epi.mesh, rv.and_then(|c| c.mesh), epi.volume_ml) {
        if share_inside(e, r) > BIVENTRICULAR_SHARE {
            return Err("LV_EPI encloses the RV cavity: a biventricular epicardium");
        }
    }
    match (endo.volume_ml, epi.volume_ml) {
        (Some(_), Some(_)) => {
            mass_g(endo.volume_ml, epi.volume_ml).ok_or("LV_EPI holds no more than LV_ENDO")
        }
        _ => Err("LV_ENDO or LV_EPI has no closed mesh"),
    }
}

/// Generalised winding number of a closed, outward-oriented mesh about `p`: 1 inside, 0 outside
/// (the sum of the triangles' signed solid angles over 4 pi, Van Oosterom & Strackee 1983). Robust
/// to small gaps and needs no acceleration structure for the one-off checks it serves.
pub fn winding_number(mesh: &TriMesh, p: &Vec3) -> f64 {
    let mut total = 0.0;
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.corners(t).map(|q| q - p);
        let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
        let num = a.dot(&b.cross(&c));
        let den = la * lb * lc + a.dot(&b) * lc + b.dot(&c) * la + c.dot(&a) * lb;
        total += 2.0 * num.atan2(den);
    }
    total / (4.0 * std::f64::consts::PI)
}

/// Share of `inner`'s vertices that lie inside the closed mesh `outer` (winding number over 1/2),
/// from at most [`SHARE_SAMPLES`] of them evenly taken (the winding number visits every triangle
/// of `outer` for each). An "LV epicardium" that holds most of the RV cavity is a biventricular
/// epicardium, whose volume minus the LV cavity's is no LV mass.
pub fn share_inside(outer: &TriMesh, inner: &TriMesh) -> f64 {
    let n = inner.positions.len();
    if n == 0 {
        return 0.0;
    }
    let step = n.div_ceil(SHARE_SAMPLES);
    let sampled: Vec<&Vec3> = inner.positions.iter().step_by(step).collect();
    let inside = sampled
        .iter()
        .filter(|p| winding_number(outer, p) > 0.5)
        .count();
    inside as f64 / sampled.len() as f64
}

/// Vertices of the inner mesh [`share_inside`] looks at, at most.
pub const SHARE_SAMPLES: usize = 500;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;
    use crate::mesh::shapes;

    /// A closed mesh as measured.
    fn m(mesh: &TriMesh) -> Measured<'_> {
        Measured {
            volume_ml: Some(mesh.volume_ml()),
            mesh: Some(mesh),
        }
    }

    fn phases(v: &[Option<f64>]) -> Vec<PhaseVolume> {
        v.iter()
            .enumerate()
            .map(|(i, &volume_ml)| PhaseVolume {
                phase: format!("f{i}"),
                volume_ml,
            })
            .collect()
    }

    #[test]
    fn ed_is_the_largest_and_es_the_smallest_volume() {
        let v = ventricle(
            "LV_ENDO",
            &phases(&[Some(150.0), Some(60.0), None, Some(120.0)]),
        )
        .unwrap();
        assert_eq!((v.ed_phase.as_str(), v.es_phase.as_str()), ("f0", "f1"));
        assert_eq!((v.edv_ml, v.esv_ml, v.sv_ml), (150.0, 60.0, 90.0));
        assert!((v.ef_percent - 60.0).abs() < 1e-12);
        assert_eq!(v.phases_used, 3);
        // Systole first in the file: the phases' order does not matter.
        let v = ventricle("RV_ENDO", &phases(&[Some(70.0), Some(180.0)])).unwrap();
        assert_eq!((v.ed_phase.as_str(), v.es_phase.as_str()), ("f1", "f0"));
        assert!((v.ef_percent - 100.0 * 110.0 / 180.0).abs() < 1e-12);
    }

    #[test]
    fn too_few_volumes_give_no_function() {
        assert!(ventricle("LV_ENDO", &phases(&[Some(150.0)])).is_none());
        assert!(ventricle("LV_ENDO", &phases(&[Some(150.0), None, Some(f64::NAN)])).is_none());
        assert!(ventricle("LV_ENDO", &phases(&[Some(-1.0), Some(-2.0)])).is_none());
        // Two equal volumes: a still heart, EF 0, not an error.
        let v = ventricle("LV_ENDO", &phases(&[Some(100.0), Some(100.0)])).unwrap();
        assert_eq!((v.ef_percent, v.ed_phase.as_str()), (0.0, "f0"));
    }

    #[test]
    fn mass_is_the_wall_volume_times_the_density() {
        let m = mass_g(Some(170.0), Some(300.0)).unwrap();
        assert!((m - 136.5).abs() < 1e-9, "{m}");
        assert_eq!(mass_g(None, Some(300.0)), None);
        assert_eq!(mass_g(Some(170.0), None), None);
        assert_eq!(mass_g(Some(300.0), Some(170.0)), None);
    }

    #[test]
    fn cavities_are_not_epicardia_or_unknown_labels() {
        for s in ["LV_ENDO", "RV_ENDO", "LV", "lv_endo"] {
            assert!(is_cavity(s), "{s}");
        }
        for s in ["LV_EPI", "RV_EPI", "BIV_EPI", "epi", "LABEL_4"] {
            assert!(!is_cavity(s), "{s}");
        }
    }

    #[test]
    fn summarise_reports_cavities_and_the_lv_mass() {
        let endo = [shapes::icosphere(20.0, 3), shapes::icosphere(16.0, 3)];
        let epi = [shapes::icosphere(26.0, 3), shapes::icosphere(23.0, 3)];
        let phases = vec!["ES".to_string(), "ED".to_string()];
        let surfaces: Vec<String> = ["LV_ENDO", "LV_EPI", "LABEL_7"].map(String::from).to_vec();
        // ES listed first, with the smaller meshes.
        let cells = vec![
            vec![m(&endo[1]), m(&epi[1]), Measured::default()],
            vec![m(&endo[0]), m(&epi[0]), m(&endo[0])],
        ];
        let f = summarise(&phases, &surfaces, &cells);
        assert_eq!(f.ventricles.len(), 1, "LABEL_7 gets no EF");
        let lv = &f.ventricles[0];
        assert_eq!((lv.ed_phase.as_str(), lv.es_phase.as_str()), ("ED", "ES"));
        let mass = f.lv_mass.unwrap();
        let ed = 1.05 * (epi[0].volume_ml() - endo[0].volume_ml());
        assert!((mass.ed_g.unwrap() - ed).abs() < 1e-9);
        assert_eq!(mass.per_phase[1].grams, mass.ed_g);
        assert!(mass.per_phase.iter().all(|p| p.why_none.is_none()));
        let json = serde_json::to_value(&mass).unwrap();
        assert!(json["per_phase"][0].get("why_none").is_none(), "{json}");
        // One phase: no EF, the volume kept; no LV_EPI: no mass.
        let f = summarise(&phases[..1], &surfaces[..1], &cells[..1]);
        assert!(f.ventricles.is_empty() && f.lv_mass.is_none());
        assert_eq!(f.single[0].volume_ml, Some(endo[1].volume_ml()));
    }

    #[test]
    fn a_biventricular_epicardium_gives_no_lv_mass() {
        let shifted = |m: TriMesh, dx: f64| TriMesh {
            positions: m.positions.iter().map(|p| p + v3(dx, 0.0, 0.0)).collect(),
            ..m
        };
        let (endo, epi) = (shapes::icosphere(20.0, 3), shapes::icosphere(30.0, 3));
        let rv = shifted(shapes::icosphere(15.0, 2), 50.0);
        let biv = shapes::icosphere(80.0, 3);
        let g = lv_mass(m(&endo), m(&epi), Some(m(&rv))).unwrap();
        assert!((g - 1.05 * (epi.volume_ml() - endo.volume_ml())).abs() < 1e-9);
        let e = lv_mass(m(&endo), m(&biv), Some(m(&rv))).unwrap_err();
        assert!(e.contains("biventricular"), "{e}");
        assert!(lv_mass(m(&endo), m(&epi), None).is_ok());
        assert!(lv_mass(m(&endo), Measured::default(), None).is_err());
        assert!(lv_mass(m(&epi), m(&endo), None).is_err());
    }

    #[test]
    fn winding_number_is_one_inside_and_zero_outside() {
        let sphere = shapes::icosphere(10.0, 3);
        for (p, want) in [
            (v3(0.0, 0.0, 0.0), 1.0),
            (v3(9.0, 0.0, 0.0), 1.0),
            (v3(0.0, 0.0, -9.5), 1.0),
            (v3(11.0, 0.0, 0.0), 0.0),
            (v3(30.0, -40.0, 5.0), 0.0),
        ] {
            let w = winding_number(&sphere, &p);
            assert!((w - want).abs() < 1e-6, "{p:?}: {w}");
        }
        let small = TriMesh {
            positions: shapes::icosphere(3.0, 2)
                .positions
                .iter()
                .map(|q| q + v3(2.0, 0.0, 0.0))
                .collect(),
            ..shapes::icosphere(3.0, 2)
        };
        assert_eq!(share_inside(&sphere, &small), 1.0);
        let beside = TriMesh {
            positions: small
                .positions
                .iter()
                .map(|q| q + v3(8.0, 0.0, 0.0))
                .collect(),
            ..small.clone()
        };
        // Centred at x 10 on the big sphere's surface: about half inside.
        let s = share_inside(&sphere, &beside);
        assert!((0.3..0.7).contains(&s), "{s}");
    }
}
