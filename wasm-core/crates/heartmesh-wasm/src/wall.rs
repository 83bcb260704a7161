//! The LV myocardium as one closed solid in the app: the command line's `heartmesh myocardium`
//! (heartmesh-cli `cmd_myocardium.rs`) made of the two finished meshes the app holds (its last
//! LV_ENDO and LV_EPI runs, at the current parameters) instead of two fresh reconstructions.
//!
//! The base plane comes from the file's contours at the same parameters
//! (`common_basal_plane_of`, the plane the command line uses), the solid from the core's
//! `mesh::wall::build_wall`, the file from `Wall::write` with the same regions, point data
//! and header comment as the command line's: given the same meshes, the same bytes (an app header,
//! when given, follows the command line's comment). Everything is checked before the core sees it,
//! so a bad call is an error thrown as JSON (`errors.rs`), never a panic.

use heartmesh_core::geometry::Vec3;
use heartmesh_core::io::MeshFormat;
use heartmesh_core::mesh::wall::{self, Wall};
use heartmesh_core::metrics::compare::common_basal_plane_of;
use heartmesh_core::metrics::function::MYOCARDIAL_DENSITY_G_PER_ML;
use heartmesh_core::{ContourSet, CoreError, Params, TriMesh};
use serde_json::{json, Value};
use wasm_bindgen::prelude::*;

use crate::{convert, errors, Session};

/// The largest minimum wall thickness accepted (mm), as the command line's `--min-thickness`.
pub const MAX_MIN_THICKNESS_MM: f64 = 10.0;

/// One surface's finished mesh as the app holds it: xyz per vertex (mm) and three vertex indices
/// per triangle, outward.
#[derive(Debug, Clone, Copy)]
pub struct SurfaceMesh<'a> {
    pub name: &'a str,
    pub positions: &'a [f64],
    pub indices: &'a [u32],
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
    /// ...) and the file.
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
        let endo = SurfaceMesh {
            name: endo_surface,
            positions: endo_positions,
            indices: endo_indices,
        };
        let epi = SurfaceMesh {
            name: epi_surface,
            positions: epi_positions,
            indices: epi_indices,
        };
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
        .map_err(|e| wall_error(&e))?;
        let out = js_sys::Object::new();
        js_sys::Reflect::set(&out, &"summary".into(), &built.summary.to_string().into())?;
        let bytes = js_sys::Uint8Array::from(built.bytes.as_slice());
        js_sys::Reflect::set(&out, &"bytes".into(), &bytes)?;
        Ok(out)
    }
}

/// A failure to build the wall as the app shows it: the core's code, its message after "the LV
/// wall: " (the command line's "the myocardium wall: ").
fn wall_error(e: &CoreError) -> JsValue {
    let mut v = errors::error_json(e);
    let message = v["message"].as_str().unwrap_or_default().to_string();
    v["message"] = json!(format!("the LV wall: {message}"));
    JsValue::from_str(&v.to_string())
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
    if let Some(mm) = min_thickness_mm {
        if !(mm.is_finite() && (0.0..=MAX_MIN_THICKNESS_MM).contains(&mm)) {
            return Err(CoreError::ParamInvalid {
                name: "min_thickness_mm".into(),
                message: format!(
                    "{mm}: give a thickness in mm from 0 to {MAX_MIN_THICKNESS_MM}, or none"
                ),
            });
        }
    }
    if endo.name.eq_ignore_ascii_case(epi.name) {
        return Err(CoreError::ParamInvalid {
            name: "surfaces".into(),
            message: format!(
                "the endocardium and the epicardium are the same surface ({})",
                endo.name
            ),
        });
    }
    let endo_mesh = mesh_of(endo)?;
    let epi_mesh = mesh_of(epi)?;
    let base = common_basal_plane_of(set, params, endo.name, epi.name)?;
    let wall = wall::build_wall(&endo_mesh, &epi_mesh, &base, min_thickness_mm)?;
    let comment = header_comment(file_name, endo.name, epi.name, header);
    let bytes = wall.write(format, &comment)?;
    Ok(WallExport {
        summary: summary(&wall, endo.name, epi.name, min_thickness_mm, format)?,
        bytes,
    })
}

/// The command line's header comment (`cmd_myocardium.rs`), then the app's `extra` lines.
pub fn header_comment(file_name: &str, endo: &str, epi: &str, extra: &str) -> String {
    let name = file_name.rsplit(['/', '\\']).next().unwrap_or(file_name);
    let mut comment = format!(
        "LV myocardium wall of {name} ({endo} + {epi}); units mm, the contour file's \
         coordinates; region 1 epicardium, 2 endocardium, 3 base"
    );
    for line in extra.lines().map(str::trim).filter(|l| !l.is_empty()) {
        comment.push('\n');
        comment.push_str(line);
    }
    comment
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
/// figures, under its names), with the solid's size, the rim-less folds, the density and what was
/// asked for.
fn summary(
    wall: &Wall,
    endo: &str,
    epi: &str,
    min_thickness_mm: Option<f64>,
    format: MeshFormat,
) -> heartmesh_core::error::Result<Value> {
    let mut value = serde_json::to_value(wall.summary(min_thickness_mm))
        .map_err(|e| CoreError::Io(format!("the LV wall's summary: {e}")))?;
    let Value::Object(map) = &mut value else {
        return Err(CoreError::Io(
            "the LV wall's summary is not an object".into(),
        ));
    };
    for (key, v) in [
        ("surfaces", json!({ "endo": endo, "epi": epi })),
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

    /// Rings of an ellipsoidal cavity of semi-axes `a` (around) and `c` (along z), centred at
    /// z = 0, cut every 8 mm from -48 to 0, as contour CSV rows of `surface`; two long-axis curves
    /// close the apex.
    fn cavity_rows(surface: &str, a: f64, c: f64) -> String {
        let mut csv = String::new();
        for (k, z) in [-48.0f64, -40.0, -32.0, -24.0, -16.0, -8.0, 0.0]
            .iter()
            .enumerate()
        {
            let r = a * (1.0 - (z / c) * (z / c)).sqrt();
            for i in 0..60 {
                let t = i as f64 / 60.0 * std::f64::consts::TAU;
                csv.push_str(&format!(
                    "{surface}_s{k},{},{},{z},{surface}\n",
                    r * t.cos(),
                    r * t.sin()
                ));
            }
        }
        for (k, phi) in [0.3f64, 1.9].iter().enumerate() {
            for i in 0..=80 {
                let t = std::f64::consts::PI * (0.5 + i as f64 / 80.0);
                let (u, z) = (a * t.sin(), c * t.cos());
                if z > 4.0 {
                    continue;
                }
                csv.push_str(&format!(
                    "{surface}_l{k},{},{},{z},{surface}\n",
                    u * phi.cos(),
                    u * phi.sin()
                ));
            }
        }
        csv
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
        let cut = Run {
            positions: epi.positions.clone(),
            indices: epi.indices[..epi.indices.len() - 1].to_vec(),
        };
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
        let lifted = Run {
            positions: epi
                .positions
                .iter()
                .enumerate()
                .map(|(i, &x)| if i % 3 == 2 { x + 200.0 } else { x })
                .collect(),
            indices: epi.indices.clone(),
        };
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
