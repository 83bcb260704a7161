//! The myocardium as one closed solid in the app: the command line's `heartmesh myocardium`
//! (heartmesh-cli `cmd_myocardium.rs`) made of the finished meshes the app holds (their last runs,
//! at the current parameters) instead of fresh reconstructions. The LV wall ([`Session::wall`]) is
//! LV_ENDO and LV_EPI; the biventricular one ([`Session::biventricular_wall`], the command line's
//! `--biventricular`) is BIV_EPI less the LV_ENDO and RV_ENDO cavities.
//!
//! The base plane comes from the file's contours at the same parameters
//! (`common_basal_plane_of` / `common_basal_plane_all`, the planes the command line uses), the
//! solid from the core's `mesh::wall::build_wall` / `build_biventricular`, the file from
//! `Wall::write` with the same regions, point data and header comment as the command line's:
//! given the same meshes, the same bytes (an app header, when given, follows the command line's
//! comment). Everything is checked before the core sees it, so a bad call is an error thrown as
//! JSON (`errors.rs`), never a panic: the worker goes on.

use heartmesh_core::geometry::Vec3;
use heartmesh_core::io::{tagged_comment, MeshFormat};
use heartmesh_core::mesh::wall::{self, Wall, BIV_REGION_NAMES, REGION_NAMES};
use heartmesh_core::metrics::compare::{common_basal_plane_all, common_basal_plane_of, ClipPlane};
use heartmesh_core::metrics::function::MYOCARDIAL_DENSITY_G_PER_ML;
use heartmesh_core::metrics::{bullseye, segments};
use heartmesh_core::pipeline::Reconstruction;
use heartmesh_core::{ContourSet, CoreError, Params, TriMesh};
use serde_json::{json, Value};
use wasm_bindgen::prelude::*;

use crate::{convert, errors, Session};

/// The largest minimum wall thickness accepted (mm), as the command line's `--min-thickness`.
pub const MAX_MIN_THICKNESS_MM: f64 = 10.0;
/// The minimum wall thickness the app's walls use (its `WALL_MIN_THICKNESS_MM`, the command
/// line's default `--min-thickness 1`): the hexahedra keep their wall as thick.
pub const DEFAULT_MIN_THICKNESS_MM: f64 = 1.0;

/// One surface's finished mesh as the app holds it: xyz per vertex (mm) and three vertex indices
/// per triangle, outward.
#[derive(Debug, Clone, Copy)]
pub struct SurfaceMesh<'a> {
    pub name: &'a str,
    pub positions: &'a [f64],
    pub indices: &'a [u32],
}

impl<'a> SurfaceMesh<'a> {
    pub fn new(name: &'a str, positions: &'a [f64], indices: &'a [u32]) -> Self {
        SurfaceMesh {
            name,
            positions,
            indices,
        }
    }
}

/// A built wall: the summary the app shows and the file in the format asked for.
#[derive(Debug, Clone)]
pub struct WallExport {
    pub summary: Value,
    pub bytes: Vec<u8>,
}

#[wasm_bindgen]
impl Session {
    /// The LV myocardium wall of a loaded file, as `heartmesh myocardium` builds it, from the two
    /// finished meshes of its endocardium (`endo_surface`, e.g. "LV_ENDO") and epicardium
    /// (`epi_surface`), both run with `params_json` and `lids` (as [`Session::start`] takes them):
    /// cut at the base plane of the contours at those parameters and joined by a flat ring.
    /// `min_thickness_mm` (0 to 10; undefined: off) moves endocardial vertices that far under the
    /// epicardium first (the command line's default is 1). `format` is a mesh extension (`obj`,
    /// `stl`, `ply`, `vtk`, `vtp`); `header`: lines the app adds after the command line's comment.
    /// Returns `{summary, bytes}`: the summary JSON (the report's figures: `wall_volume_ml`,
    /// `myocardial_mass_g`, `cavity_volume_ml`, `thickness_mm`, `regions`, `endocardium_moved`,
    /// ..., the AHA `segments` with their bullseye as SVG text, `bullseye_svg`, or
    /// `segments: null` and `segments_note` saying why) and the file.
    #[allow(clippy::too_many_arguments)]
    #[wasm_bindgen(unchecked_return_type = "{ summary: string; bytes: Uint8Array }")]
    pub fn wall(
        &self,
        file_name: &str,
        params_json: &str,
        lids: &str,
        endo_surface: &str,
        endo_positions: &[f64],
        endo_indices: &[u32],
        epi_surface: &str,
        epi_positions: &[f64],
        epi_indices: &[u32],
        min_thickness_mm: Option<f64>,
        format: &str,
        header: &str,
    ) -> Result<js_sys::Object, JsValue> {
        let set = self.file(file_name)?;
        let params =
            convert::params_from_json(params_json, lids, None).map_err(|e| errors::to_js(&e))?;
        let endo = SurfaceMesh::new(endo_surface, endo_positions, endo_indices);
        let epi = SurfaceMesh::new(epi_surface, epi_positions, epi_indices);
        let format = mesh_format(format).map_err(|e| errors::to_js(&e))?;
        let built = build(
            set,
            file_name,
            &params,
            endo,
            epi,
            min_thickness_mm,
            format,
            header,
        )
        .map_err(|e| wall_error(&e, LV_WALL))?;
        export_object(&built)
    }

    /// The biventricular myocardium of a loaded file, as `heartmesh myocardium --biventricular`
    /// builds it, from the three finished meshes of its LV cavity (`lv_endo_surface`, e.g.
    /// "LV_ENDO"), its RV cavity (`rv_endo_surface`, "RV_ENDO") and the biventricular epicardium
    /// (`biv_epi_surface`, "BIV_EPI": the file's LV_EPI and RV_EPI curves joined), all run with
    /// `params_json` and `lids`: the epicardium less both cavities, cut at the most basal
    /// short-axis slice all three were drawn on. `min_thickness_mm`, `format` and `header` as
    /// [`Session::wall`] takes them (the cavities are also kept that far apart: the septum).
    /// Returns `{summary, bytes}`: the summary adds `cavities` (the LV's and the RV's volume
    /// below the base) and `crossings` by pair of regions; regions 1 epicardium,
    /// 2 lv_endocardium, 3 rv_endocardium, 4 base. Errors start "the biventricular wall: ".
    #[allow(clippy::too_many_arguments)]
    #[wasm_bindgen(unchecked_return_type = "{ summary: string; bytes: Uint8Array }")]
    pub fn biventricular_wall(
        &self,
        file_name: &str,
        params_json: &str,
        lids: &str,
        lv_endo_surface: &str,
        lv_endo_positions: &[f64],
        lv_endo_indices: &[u32],
        rv_endo_surface: &str,
        rv_endo_positions: &[f64],
        rv_endo_indices: &[u32],
        biv_epi_surface: &str,
        biv_epi_positions: &[f64],
        biv_epi_indices: &[u32],
        min_thickness_mm: Option<f64>,
        format: &str,
        header: &str,
    ) -> Result<js_sys::Object, JsValue> {
        let fail = |e: &CoreError| wall_error(e, BIV_WALL);
        let set = self.file(file_name)?;
        let params = convert::params_from_json(params_json, lids, None).map_err(|e| fail(&e))?;
        let meshes = Biventricular {
            lv_endo: SurfaceMesh::new(lv_endo_surface, lv_endo_positions, lv_endo_indices),
            rv_endo: SurfaceMesh::new(rv_endo_surface, rv_endo_positions, rv_endo_indices),
            biv_epi: SurfaceMesh::new(biv_epi_surface, biv_epi_positions, biv_epi_indices),
        };
        let format = mesh_format(format).map_err(|e| fail(&e))?;
        let built = build_biventricular(
            set,
            file_name,
            &params,
            meshes,
            min_thickness_mm,
            format,
            header,
        )
        .map_err(|e| fail(&e))?;
        export_object(&built)
    }
}

/// `{summary, bytes}` as the worker reads it: the summary as JSON text, the file's bytes.
pub fn export_object(built: &WallExport) -> Result<js_sys::Object, JsValue> {
    let out = js_sys::Object::new();
    js_sys::Reflect::set(&out, &"summary".into(), &built.summary.to_string().into())?;
    let bytes = js_sys::Uint8Array::from(built.bytes.as_slice());
    js_sys::Reflect::set(&out, &"bytes".into(), &bytes)?;
    Ok(out)
}

/// How the LV wall's failures begin (the command line's "the myocardium wall: ").
pub const LV_WALL: &str = "the LV wall";
/// How the biventricular wall's failures begin.
pub const BIV_WALL: &str = "the biventricular wall";

/// A failure to build a wall as the app shows it: the core's code, its message after `what`
/// ("the LV wall: ...", "the biventricular wall: ...").
pub fn wall_error_json(e: &CoreError, what: &str) -> Value {
    let mut v = errors::error_json(e);
    let message = v["message"].as_str().unwrap_or_default().to_string();
    v["message"] = json!(format!("{what}: {message}"));
    v
}

fn wall_error(e: &CoreError, what: &str) -> JsValue {
    JsValue::from_str(&wall_error_json(e, what).to_string())
}

/// The format of a mesh extension (`stl` is binary STL).
pub fn mesh_format(extension: &str) -> heartmesh_core::error::Result<MeshFormat> {
    MeshFormat::from_path(&format!("wall.{}", extension.trim_start_matches('.'))).ok_or_else(|| {
        CoreError::ParamInvalid {
            name: "format".into(),
            message: format!("{extension:?} is no mesh format (use obj, stl, ply, vtk or vtp)"),
        }
    })
}

/// The three meshes of a biventricular wall.
#[derive(Debug, Clone, Copy)]
pub struct Biventricular<'a> {
    pub lv_endo: SurfaceMesh<'a>,
    pub rv_endo: SurfaceMesh<'a>,
    pub biv_epi: SurfaceMesh<'a>,
}

/// The work of [`Session::wall`] (native, so tests reach it).
#[allow(clippy::too_many_arguments)]
pub fn build(
    set: &ContourSet,
    file_name: &str,
    params: &Params,
    endo: SurfaceMesh,
    epi: SurfaceMesh,
    min_thickness_mm: Option<f64>,
    format: MeshFormat,
    header: &str,
) -> heartmesh_core::error::Result<WallExport> {
    check_min_thickness(min_thickness_mm)?;
    check_distinct(&[("endocardium", endo), ("epicardium", epi)])?;
    let endo_mesh = mesh_of(endo)?;
    let epi_mesh = mesh_of(epi)?;
    let base = common_basal_plane_of(set, params, endo.name, epi.name)?;
    let wall = wall::build_wall(&endo_mesh, &epi_mesh, &base, min_thickness_mm)?;
    let comment = header_comment(file_name, endo.name, epi.name, header);
    let bytes = wall.write(format, &tagged_comment(set.coordinate_system, &comment))?;
    let surfaces = json!({ "endo": endo.name, "epi": epi.name });
    let mut summary = summary(&wall, surfaces, min_thickness_mm, format, LV_WALL)?;
    if let Value::Object(map) = &mut summary {
        // The AHA segments and their bullseye, as `heartmesh myocardium` gives them.
        match segments::of_file(set, &wall) {
            Ok(s) => {
                let title = format!("{file_name} ({} + {})", endo.name, epi.name);
                map.insert("bullseye_svg".into(), json!(bullseye::svg(&s, &title)));
                map.insert("segments".into(), json!(s));
            }
            Err(why) => {
                map.insert("segments".into(), Value::Null);
                map.insert("segments_note".into(), json!(why));
            }
        }
    }
    Ok(WallExport { summary, bytes })
}

/// The work of [`Session::biventricular_wall`] (native, so tests reach it): as
/// `heartmesh myocardium --biventricular`, the base plane the lowest of the three surfaces' most
/// basal short-axis planes along the LV cavity's long axis (the command line's order: LV_ENDO,
/// BIV_EPI, RV_ENDO).
pub fn build_biventricular(
    set: &ContourSet,
    file_name: &str,
    params: &Params,
    meshes: Biventricular,
    min_thickness_mm: Option<f64>,
    format: MeshFormat,
    header: &str,
) -> heartmesh_core::error::Result<WallExport> {
    let Biventricular {
        lv_endo,
        rv_endo,
        biv_epi,
    } = meshes;
    check_min_thickness(min_thickness_mm)?;
    check_distinct(&[
        ("LV endocardium", lv_endo),
        ("RV endocardium", rv_endo),
        ("biventricular epicardium", biv_epi),
    ])?;
    let lv_mesh = mesh_of(lv_endo)?;
    let rv_mesh = mesh_of(rv_endo)?;
    let epi_mesh = mesh_of(biv_epi)?;
    let order = [lv_endo.name, biv_epi.name, rv_endo.name];
    let base = basal_plane_of_all(set, params, &order)?;
    let wall = wall::build_biventricular(&lv_mesh, &rv_mesh, &epi_mesh, &base, min_thickness_mm)?;
    let comment = comment_of(
        "biventricular myocardium",
        file_name,
        &order,
        &BIV_REGION_NAMES,
        header,
    );
    let bytes = wall.write(format, &tagged_comment(set.coordinate_system, &comment))?;
    let surfaces = json!({ "endo": lv_endo.name, "epi": biv_epi.name, "rv_endo": rv_endo.name });
    Ok(WallExport {
        summary: summary(&wall, surfaces, min_thickness_mm, format, BIV_WALL)?,
        bytes,
    })
}

/// A minimum thickness from 0 to [`MAX_MIN_THICKNESS_MM`] mm, or none.
fn check_min_thickness(min_thickness_mm: Option<f64>) -> heartmesh_core::error::Result<()> {
    match min_thickness_mm {
        Some(mm) if !(mm.is_finite() && (0.0..=MAX_MIN_THICKNESS_MM).contains(&mm)) => {
            Err(CoreError::ParamInvalid {
                name: "min_thickness_mm".into(),
                message: format!(
                    "{mm}: give a thickness in mm from 0 to {MAX_MIN_THICKNESS_MM}, or none"
                ),
            })
        }
        _ => Ok(()),
    }
}

/// Refuses two roles of a wall given the same surface (names compared whatever their case, as
/// the file's are).
fn check_distinct(roles: &[(&str, SurfaceMesh)]) -> heartmesh_core::error::Result<()> {
    for (i, (role, s)) in roles.iter().enumerate() {
        if let Some((other, _)) = roles[..i]
            .iter()
            .find(|(_, o)| o.name.eq_ignore_ascii_case(s.name))
        {
            return Err(CoreError::ParamInvalid {
                name: "surfaces".into(),
                message: format!(
                    "the {other} and the {role} are the same surface ({})",
                    s.name
                ),
            });
        }
    }
    Ok(())
}

/// [`common_basal_plane_all`] of surfaces of a contour file, from the contours alone (each
/// surface set up, not run: the slices and the long axis are fixed then), as
/// `common_basal_plane_of` does for two.
fn basal_plane_of_all(
    set: &ContourSet,
    params: &Params,
    surfaces: &[&str],
) -> heartmesh_core::error::Result<ClipPlane> {
    let setups = surfaces
        .iter()
        .map(|s| {
            Reconstruction::new(
                set,
                Params {
                    surface: Some(s.to_string()),
                    ..params.clone()
                },
            )
        })
        .collect::<heartmesh_core::error::Result<Vec<_>>>()?;
    let refs: Vec<&Reconstruction> = setups.iter().collect();
    common_basal_plane_all(&refs)
}

/// The command line's header comment (`cmd_myocardium.rs`), then the app's `extra` lines.
pub fn header_comment(file_name: &str, endo: &str, epi: &str, extra: &str) -> String {
    comment_of(
        "LV myocardium wall",
        file_name,
        &[endo, epi],
        &REGION_NAMES,
        extra,
    )
}

/// "`kind` of `file` (A + B ...); units mm, the contour file's coordinates; region 1 ..." as
/// `heartmesh myocardium` writes it (the surfaces in its order), then the app's `extra` lines.
fn comment_of(
    kind: &str,
    file_name: &str,
    surfaces: &[&str],
    regions: &[&str],
    extra: &str,
) -> String {
    let name = file_name.rsplit(['/', '\\']).next().unwrap_or(file_name);
    let labels: Vec<String> = regions
        .iter()
        .enumerate()
        .map(|(k, n)| format!("{} {n}", k + 1))
        .collect();
    let mut comment = format!(
        "{kind} of {name} ({}); units mm, the contour file's coordinates; region {}",
        surfaces.join(" + "),
        labels.join(", ")
    );
    append_lines(&mut comment, extra);
    comment
}

/// The app's `extra` header lines after the command line's comment (blank ones dropped).
pub fn append_lines(comment: &mut String, extra: &str) {
    for line in extra.lines().map(str::trim).filter(|l| !l.is_empty()) {
        comment.push('\n');
        comment.push_str(line);
    }
}

/// A surface's mesh from the app's flat arrays, refused (naming the surface) unless every
/// coordinate is finite, there are whole triangles, at least four of them, and each names three
/// different vertices that exist.
pub fn mesh_of(s: SurfaceMesh) -> heartmesh_core::error::Result<TriMesh> {
    let bad = |what: String| CoreError::InvalidMesh(format!("the {} mesh: {what}", s.name));
    if !s.positions.len().is_multiple_of(3) || !s.indices.len().is_multiple_of(3) {
        return Err(bad(format!(
            "{} coordinates and {} indices are not whole vertices and triangles",
            s.positions.len(),
            s.indices.len()
        )));
    }
    if let Some(i) = s.positions.iter().position(|x| !x.is_finite()) {
        return Err(bad(format!("vertex {} is not a finite point", i / 3)));
    }
    let vertices = s.positions.len() / 3;
    if s.indices.len() / 3 < 4 {
        return Err(bad(format!(
            "{} triangles: no closed surface",
            s.indices.len() / 3
        )));
    }
    let mut triangles = Vec::with_capacity(s.indices.len() / 3);
    for (t, tri) in s.indices.chunks_exact(3).enumerate() {
        let [a, b, c] = [tri[0], tri[1], tri[2]];
        if let Some(&v) = tri.iter().find(|&&v| v as usize >= vertices) {
            return Err(bad(format!("triangle {t} names vertex {v} of {vertices}")));
        }
        if a == b || b == c || a == c {
            return Err(bad(format!("triangle {t} names a vertex twice")));
        }
        triangles.push([a, b, c]);
    }
    let positions = s
        .positions
        .chunks_exact(3)
        .map(|p| Vec3::new(p[0], p[1], p[2]))
        .collect();
    Ok(TriMesh::new(positions, triangles))
}

/// What the app shows and tests read: the core's `Wall::summary` (the command line report's
/// figures, under its names), with the surfaces it is made of, the solid's size, the rim-less
/// folds, the density and what was asked for. `what` names the wall in errors.
fn summary(
    wall: &Wall,
    surfaces: Value,
    min_thickness_mm: Option<f64>,
    format: MeshFormat,
    what: &str,
) -> heartmesh_core::error::Result<Value> {
    let mut value = serde_json::to_value(wall.summary(min_thickness_mm))
        .map_err(|e| CoreError::Io(format!("{what}'s summary: {e}")))?;
    let Value::Object(map) = &mut value else {
        return Err(CoreError::Io(format!("{what}'s summary is not an object")));
    };
    for (key, v) in [
        ("surfaces", surfaces),
        ("format", json!(format.extension())),
        ("vertices", json!(wall.mesh.positions.len())),
        ("triangles", json!(wall.mesh.triangles.len())),
        ("density_g_per_ml", json!(MYOCARDIAL_DENSITY_G_PER_ML)),
        ("folded_edges", json!(wall.folded_edges_off_rim())),
    ] {
        map.insert(key.to_string(), v);
    }
    Ok(value)
}

#[cfg(test)]
mod tests {
    use super::*;
    use heartmesh_core::io;
    use heartmesh_core::pipeline::Reconstruction;

    /// Rings of an ellipsoidal cavity (`test_data::cavity_rows`), ids prefixed by the surface.
    fn cavity_rows(surface: &str, a: f64, c: f64) -> String {
        crate::test_data::cavity_rows(surface, &format!("{surface}_"), a, c, |_| 0.0)
    }

    /// An LV of two nested ellipsoids: the cavity (25 x 60 mm) and the epicardium 8 mm out.
    fn lv_csv() -> String {
        format!(
            "contour,x,y,z,surface\n{}{}",
            cavity_rows("LV_ENDO", 25.0, 60.0),
            cavity_rows("LV_EPI", 33.0, 68.0)
        )
    }

    struct Run {
        positions: Vec<f64>,
        indices: Vec<u32>,
    }

    fn run(set: &ContourSet, params: &Params, surface: &str) -> Run {
        let mut p = params.clone();
        p.surface = Some(surface.to_string());
        let mut rec = Reconstruction::new(set, p).unwrap();
        rec.run().unwrap();
        let mesh = rec.mesh();
        Run {
            positions: mesh
                .positions
                .iter()
                .flat_map(|v| [v.x, v.y, v.z])
                .collect(),
            indices: mesh.indices_u32(),
        }
    }

    /// `r` without its last `n` indices: no longer whole triangles.
    fn cut(r: &Run, n: usize) -> Run {
        Run {
            positions: r.positions.clone(),
            indices: r.indices[..r.indices.len() - n].to_vec(),
        }
    }

    /// `r` moved `mm` along z: far enough, out of reach of the base plane.
    fn lifted(r: &Run, mm: f64) -> Run {
        Run {
            positions: r
                .positions
                .iter()
                .enumerate()
                .map(|(i, &x)| if i % 3 == 2 { x + mm } else { x })
                .collect(),
            indices: r.indices.clone(),
        }
    }

    fn surface<'a>(name: &'a str, r: &'a Run) -> SurfaceMesh<'a> {
        SurfaceMesh {
            name,
            positions: &r.positions,
            indices: &r.indices,
        }
    }

    fn setup() -> (ContourSet, Params, Run, Run) {
        let set = io::read_contours("lv.csv", lv_csv().as_bytes()).unwrap();
        let params = convert::params_from_json(r#"{"iterations": 40}"#, "auto", None).unwrap();
        let endo = run(&set, &params, "LV_ENDO");
        let epi = run(&set, &params, "LV_EPI");
        (set, params, endo, epi)
    }

    /// The wall of two nested ellipsoids: a closed solid of three regions whose volume is the
    /// shell's between them below the base (z = 0), the cavity the half ellipsoid's, a mean
    /// thickness near the 8 mm between them; the OBJ has the three groups and the command line's
    /// comment, the summary what the file holds.
    #[test]
    fn nested_ellipsoids_make_a_wall_of_the_shells_volume() {
        let (set, params, endo, epi) = setup();
        let out = build(
            &set,
            "lv.csv",
            &params,
            surface("LV_ENDO", &endo),
            surface("LV_EPI", &epi),
            Some(1.0),
            MeshFormat::Obj,
            "heartmesh 9.9.9 (app)\n\n  lids: auto  ",
        )
        .unwrap();
        let s = &out.summary;
        let half = |a: f64, c: f64| 2.0 / 3.0 * std::f64::consts::PI * a * a * c / 1000.0;
        let cavity = s["cavity_volume_ml"].as_f64().unwrap();
        assert!(
            (cavity / half(25.0, 60.0) - 1.0).abs() < 0.05,
            "{cavity} ml vs {}",
            half(25.0, 60.0)
        );
        let shell = half(33.0, 68.0) - half(25.0, 60.0);
        let wall_ml = s["wall_volume_ml"].as_f64().unwrap();
        assert!((wall_ml / shell - 1.0).abs() < 0.08, "{wall_ml} vs {shell}");
        assert!(
            (s["myocardial_mass_g"].as_f64().unwrap() - 1.05 * wall_ml).abs() < 1e-12 * wall_ml
        );
        let mean = s["thickness_mm"]["mean"].as_f64().unwrap();
        assert!((6.0..10.0).contains(&mean), "{mean}");
        assert_eq!(s["endo_epi_crossings"], 0);
        assert_eq!(s["endocardium_moved"]["vertices"], 0);
        assert_eq!(s["endocardium_moved"]["min_thickness_mm"], 1.0);
        assert_eq!(s["epicardium_moved"]["vertices"], 0);
        assert_eq!(s["thickness_mm"]["count"], s["vertices"]);
        let regions = s["regions"].as_array().unwrap();
        let per: Vec<u64> = regions
            .iter()
            .map(|r| r["triangles"].as_u64().unwrap())
            .collect();
        assert!(per.iter().all(|&n| n > 20), "{per:?}");
        assert_eq!(
            per.iter().sum::<u64>(),
            s["triangles"].as_u64().unwrap(),
            "every triangle in one region"
        );
        // The base plane is z = 0 (the top slice of both), its normal along the long axis.
        let normal = &s["base_plane"]["normal"];
        assert!(normal[2].as_f64().unwrap().abs() > 0.99, "{normal}");

        let text = String::from_utf8(out.bytes).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], format!("# heartmesh {}", heartmesh_core::VERSION));
        assert_eq!(
            lines[1],
            "# LV myocardium wall of lv.csv (LV_ENDO + LV_EPI); units mm, the contour file's \
             coordinates; region 1 epicardium, 2 endocardium, 3 base"
        );
        assert_eq!(lines[2], "# heartmesh 9.9.9 (app)");
        assert_eq!(lines[3], "# lids: auto");
        let groups: Vec<&str> = lines
            .iter()
            .filter(|l| l.starts_with("g "))
            .copied()
            .collect();
        assert_eq!(groups, ["g epicardium", "g endocardium", "g base"]);
        let v = lines.iter().filter(|l| l.starts_with("v ")).count();
        let f = lines.iter().filter(|l| l.starts_with("f ")).count();
        assert_eq!(
            (v as u64, f as u64),
            (
                s["vertices"].as_u64().unwrap(),
                s["triangles"].as_u64().unwrap()
            )
        );
        // Closed: every edge in exactly two faces.
        let mut edges = std::collections::HashMap::new();
        for l in lines.iter().filter(|l| l.starts_with("f ")) {
            let ids: Vec<u32> = l[2..].split(' ').map(|x| x.parse().unwrap()).collect();
            for k in 0..3 {
                let (a, b) = (ids[k], ids[(k + 1) % 3]);
                *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        assert!(edges.values().all(|&n| n == 2));
    }

    /// The same meshes in every format: the same summary; STL carries no regions, VTK one
    /// `region` value per triangle and the thickness per vertex.
    #[test]
    fn every_format_holds_the_same_wall() {
        let (set, params, endo, epi) = setup();
        let make = |format| {
            build(
                &set,
                "lv.csv",
                &params,
                surface("LV_ENDO", &endo),
                surface("LV_EPI", &epi),
                Some(1.0),
                format,
                "",
            )
            .unwrap()
        };
        let obj = make(MeshFormat::Obj);
        let stl = make(MeshFormat::StlBinary);
        let vtk = make(MeshFormat::Vtk);
        let ply = make(MeshFormat::Ply);
        for other in [&stl, &vtk, &ply] {
            let mut a = obj.summary.clone();
            let mut b = other.summary.clone();
            a["format"] = Value::Null;
            b["format"] = Value::Null;
            assert_eq!(a, b);
        }
        assert_eq!(stl.summary["format"], "stl");
        let triangles = obj.summary["triangles"].as_u64().unwrap() as usize;
        assert_eq!(stl.bytes.len(), 84 + 50 * triangles);
        let text = String::from_utf8(vtk.bytes).unwrap();
        assert!(
            text.contains(&format!("CELL_DATA {triangles}")),
            "VTK cells"
        );
        assert!(text.contains("SCALARS region int 1"));
        assert!(text.contains("thickness"));
        let ply_head = String::from_utf8_lossy(&ply.bytes[..600]).to_string();
        assert!(ply_head.contains("comment region 3 base"), "{ply_head}");
        // The wall read back is the summary's.
        let back = io::read_mesh("wall.obj", &obj.bytes).unwrap();
        let ml = back.mesh.volume_ml();
        let said = obj.summary["wall_volume_ml"].as_f64().unwrap();
        assert!((ml / said - 1.0).abs() < 1e-12, "{ml} vs {said}");
    }

    /// What the app may send wrongly is refused with a message naming the surface or setting,
    /// never a panic; a plane that misses the epicardium is the core's degenerate error.
    #[test]
    fn bad_inputs_are_errors_not_panics() {
        let (set, params, endo, epi) = setup();
        let try_with = |e: SurfaceMesh, p: SurfaceMesh, min: Option<f64>| {
            build(&set, "lv.csv", &params, e, p, min, MeshFormat::Obj, "").unwrap_err()
        };
        let cut = cut(&epi, 1);
        let e = try_with(surface("LV_ENDO", &endo), surface("LV_EPI", &cut), None);
        assert_eq!(e.code(), "invalid_mesh");
        assert!(e.to_string().contains("the LV_EPI mesh"), "{e}");
        let mut beyond = epi.indices.clone();
        beyond[4] = 999_999;
        let far = Run {
            positions: epi.positions.clone(),
            indices: beyond,
        };
        let e = try_with(surface("LV_ENDO", &endo), surface("LV_EPI", &far), None);
        assert!(
            e.to_string().contains("triangle 1 names vertex 999999"),
            "{e}"
        );
        let mut nan = endo.positions.clone();
        nan[7] = f64::NAN;
        let nan = Run {
            positions: nan,
            indices: endo.indices.clone(),
        };
        let e = try_with(surface("LV_ENDO", &nan), surface("LV_EPI", &epi), None);
        assert!(
            e.to_string().contains("vertex 2 is not a finite point"),
            "{e}"
        );
        let e = try_with(
            surface("LV_ENDO", &endo),
            surface("LV_EPI", &epi),
            Some(11.0),
        );
        assert_eq!(e.code(), "param_invalid");
        let e = try_with(surface("LV_ENDO", &endo), surface("LV_ENDO", &endo), None);
        assert!(e.to_string().contains("same surface"), "{e}");
        // The epicardium 200 mm up: the base plane does not cut it.
        let lifted = lifted(&epi, 200.0);
        let e = try_with(surface("LV_ENDO", &endo), surface("LV_EPI", &lifted), None);
        assert_eq!(e.code(), "degenerate");
        assert!(e.to_string().contains("does not cut the epicardium"), "{e}");
        let v = errors::error_json(&e);
        assert_eq!(v["code"], "degenerate");
        // An unknown surface name is the core's error from the contours.
        let e = try_with(surface("LV_ENDO", &endo), surface("RV_EPI", &epi), None);
        assert_eq!(e.code(), "unknown_surface");
        assert_eq!(mesh_format(".vtp").unwrap(), MeshFormat::Vtp);
        assert_eq!(mesh_format("gltf").unwrap_err().code(), "param_invalid");
    }

    use crate::test_data::data;

    /// The biv-me example patient 1 at end-diastole (the app's "Patient 1 · ED") with its
    /// LV_ENDO, RV_ENDO and BIV_EPI run at the app's default settings, as the app keeps them.
    fn patient1_biv() -> (ContourSet, Params, Run, Run, Run) {
        let path = data("contours/bivme-example-patient1/patient1-ED.csv");
        let set = io::read_contours("patient1-ED.csv", &std::fs::read(path).unwrap()).unwrap();
        let params = convert::params_from_json("{}", "auto", None).unwrap();
        let lv = run(&set, &params, "LV_ENDO");
        let rv = run(&set, &params, "RV_ENDO");
        let epi = run(&set, &params, "BIV_EPI");
        (set, params, lv, rv, epi)
    }

    fn biv<'a>(lv: &'a Run, rv: &'a Run, epi: &'a Run) -> Biventricular<'a> {
        Biventricular {
            lv_endo: surface("LV_ENDO", lv),
            rv_endo: surface("RV_ENDO", rv),
            biv_epi: surface("BIV_EPI", epi),
        }
    }

    /// `heartmesh myocardium patient1-ED.csv --biventricular --report`: 2167 vertices, 4330
    /// triangles, wall 133.579 ml (mass 140.258 g), LV cavity 135.005 ml, RV cavity 127.093 ml,
    /// regions 1280 / 1495 / 1317 / 238, 23 endocardial and 3 epicardial vertices moved.
    const CLI_BIV: (usize, usize, f64, f64, f64, f64) = (
        2167,
        4330,
        133.5789290808014,
        140.25787553484147,
        135.00492042807693,
        127.09252539737463,
    );

    /// The biventricular wall of a real file is the command line's: the same size, volumes,
    /// regions and header comment; a closed solid (every edge in two faces) whose enclosed
    /// volume read back is the summary's; the OBJ has the four region groups; the VTK one region
    /// per triangle in 1..4, as many of each as the summary counts.
    #[test]
    fn patient1_biventricular_wall_is_the_command_lines() {
        let (set, params, lv, rv, epi) = patient1_biv();
        let make = |format, header| {
            build_biventricular(
                &set,
                "patient1-ED.csv",
                &params,
                biv(&lv, &rv, &epi),
                Some(1.0),
                format,
                header,
            )
            .unwrap()
        };
        let obj = make(MeshFormat::Obj, "heartmesh 9.9.9 (app)");
        let s = &obj.summary;
        let (vertices, triangles, wall_ml, mass_g, lv_ml, rv_ml) = CLI_BIV;
        assert_eq!(s["vertices"], vertices);
        assert_eq!(s["triangles"], triangles);
        let close = |key: &Value, want: f64| {
            let got = key.as_f64().unwrap();
            assert!((got / want - 1.0).abs() < 1e-9, "{got} vs the CLI's {want}");
        };
        close(&s["wall_volume_ml"], wall_ml);
        close(&s["myocardial_mass_g"], mass_g);
        close(&s["cavity_volume_ml"], lv_ml);
        assert_eq!(s["cavities"][0]["region"], "lv_endocardium");
        close(&s["cavities"][0]["volume_ml"], lv_ml);
        assert_eq!(s["cavities"][1]["region"], "rv_endocardium");
        close(&s["cavities"][1]["volume_ml"], rv_ml);
        assert_eq!(s["endo_epi_crossings"], 0);
        assert_eq!(s["crossings"], json!([]));
        assert_eq!(s["endocardium_moved"]["vertices"], 23);
        assert_eq!(s["epicardium_moved"]["vertices"], 3);
        assert_eq!(
            s["surfaces"],
            json!({ "endo": "LV_ENDO", "epi": "BIV_EPI", "rv_endo": "RV_ENDO" })
        );
        let regions: Vec<(u64, &str, u64)> = s["regions"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| {
                (
                    r["id"].as_u64().unwrap(),
                    r["name"].as_str().unwrap(),
                    r["triangles"].as_u64().unwrap(),
                )
            })
            .collect();
        assert_eq!(
            regions,
            [
                (1, "epicardium", 1280),
                (2, "lv_endocardium", 1495),
                (3, "rv_endocardium", 1317),
                (4, "base", 238)
            ]
        );

        let text = String::from_utf8(obj.bytes.clone()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[1],
            "# biventricular myocardium of patient1-ED.csv (LV_ENDO + BIV_EPI + RV_ENDO); units \
             mm, the contour file's coordinates; region 1 epicardium, 2 lv_endocardium, \
             3 rv_endocardium, 4 base"
        );
        assert_eq!(lines[2], "# heartmesh 9.9.9 (app)");
        let groups: Vec<&str> = lines
            .iter()
            .filter(|l| l.starts_with("g "))
            .copied()
            .collect();
        assert_eq!(
            groups,
            [
                "g epicardium",
                "g lv_endocardium",
                "g rv_endocardium",
                "g base"
            ]
        );
        let mut edges = std::collections::HashMap::new();
        for l in lines.iter().filter(|l| l.starts_with("f ")) {
            let ids: Vec<u32> = l[2..].split(' ').map(|x| x.parse().unwrap()).collect();
            for k in 0..3 {
                let (a, b) = (ids[k], ids[(k + 1) % 3]);
                *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        assert_eq!(edges.values().filter(|&&n| n != 2).count(), 0, "closed");
        let back = io::read_mesh("biv.obj", &obj.bytes).unwrap();
        close(&json!(back.mesh.volume_ml()), wall_ml);

        // Byte for byte the command line's file: what `cmd_myocardium.rs` does with its own
        // finished reconstructions (LV_ENDO, BIV_EPI, RV_ENDO), written with its comment.
        let recs: Vec<Reconstruction> = ["LV_ENDO", "BIV_EPI", "RV_ENDO"]
            .iter()
            .map(|name| {
                let mut p = params.clone();
                p.surface = Some(name.to_string());
                let mut rec = Reconstruction::new(&set, p).unwrap();
                rec.run().unwrap();
                rec
            })
            .collect();
        let refs: Vec<&Reconstruction> = recs.iter().collect();
        let base = common_basal_plane_all(&refs).unwrap();
        let cli = wall::build_biventricular(
            recs[0].mesh(),
            recs[2].mesh(),
            recs[1].mesh(),
            &base,
            Some(1.0),
        )
        .unwrap();
        let comment = "biventricular myocardium of patient1-ED.csv (LV_ENDO + BIV_EPI + RV_ENDO); \
                       units mm, the contour file's coordinates; region 1 epicardium, \
                       2 lv_endocardium, 3 rv_endocardium, 4 base";
        let cli_obj = cli.write(MeshFormat::Obj, comment).unwrap();
        assert!(make(MeshFormat::Obj, "").bytes == cli_obj, "the CLI's OBJ");

        let vtk = String::from_utf8(make(MeshFormat::Vtk, "").bytes).unwrap();
        let vtk_lines: Vec<&str> = vtk.lines().collect();
        let at = vtk_lines
            .iter()
            .position(|l| *l == "SCALARS region int 1")
            .unwrap();
        let ids: Vec<u32> = vtk_lines[at + 1..]
            .iter()
            .skip_while(|l| l.starts_with("LOOKUP_TABLE"))
            .take_while(|l| !l.starts_with(|c: char| c.is_ascii_alphabetic()))
            .flat_map(|l| l.split_whitespace().map(|x| x.parse::<u32>().unwrap()))
            .collect();
        assert_eq!(ids.len(), triangles);
        let per: Vec<usize> = (1..=4)
            .map(|r| ids.iter().filter(|&&x| x == r).count())
            .collect();
        assert_eq!(per, [1280, 1495, 1317, 238]);
    }

    /// Bad biventricular calls are errors naming what is wrong, never panics; the binding's
    /// message starts "the biventricular wall: ".
    #[test]
    fn bad_biventricular_inputs_are_errors_not_panics() {
        let (set, params, lv, rv, epi) = patient1_biv();
        let try_with = |m: Biventricular, min: Option<f64>| {
            build_biventricular(&set, "p.csv", &params, m, min, MeshFormat::Obj, "").unwrap_err()
        };
        let all = biv(&lv, &rv, &epi);
        let with_rv_endo = |rv_endo| Biventricular { rv_endo, ..all };
        let with_biv_epi = |biv_epi| Biventricular { biv_epi, ..all };
        let e = try_with(with_rv_endo(surface("lv_endo", &rv)), None);
        assert_eq!(e.code(), "param_invalid");
        assert!(
            e.to_string().contains(
                "the LV endocardium and the RV endocardium are the same surface (lv_endo)"
            ),
            "{e}"
        );
        let cut = cut(&rv, 2);
        let e = try_with(with_rv_endo(surface("RV_ENDO", &cut)), None);
        assert_eq!(e.code(), "invalid_mesh");
        assert!(e.to_string().contains("the RV_ENDO mesh"), "{e}");
        assert_eq!(try_with(all, Some(-1.0)).code(), "param_invalid");
        // The epicardium 300 mm up: the base plane does not cut it.
        let lifted = lifted(&epi, 300.0);
        let e = try_with(with_biv_epi(surface("BIV_EPI", &lifted)), None);
        assert_eq!(e.code(), "degenerate");
        let v = wall_error_json(&e, BIV_WALL);
        assert_eq!(v["code"], "degenerate");
        let message = v["message"].as_str().unwrap();
        assert!(
            message.starts_with("the biventricular wall: degenerate input: the base plane does not cut the epicardium"),
            "{message}"
        );
        // A file without the surface named: the core's error from its contours.
        let e = try_with(with_biv_epi(surface("LV_EPI_X", &epi)), None);
        assert_eq!(e.code(), "unknown_surface");
    }

    /// The app's header lines follow the command line's comment; blank ones are dropped and a
    /// path is cut to the file's name.
    #[test]
    fn the_header_is_the_command_lines_then_the_apps() {
        let c = header_comment("dir/p1.csv", "LV_ENDO", "LV_EPI", "a\n \nb");
        let lines: Vec<&str> = c.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(lines[0].starts_with("LV myocardium wall of p1.csv (LV_ENDO + LV_EPI)"));
        assert_eq!(&lines[1..], ["a", "b"]);
    }
}
