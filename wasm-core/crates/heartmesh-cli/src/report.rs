//! The JSON report of `heartmesh reconstruct` (scripts rely on its keys) and the one-line summary.

use heartmesh_core::contours::{CoordinateSystem, TimeFrames};
use heartmesh_core::io;
use heartmesh_core::mesh::quality::quality;
use heartmesh_core::mesh::topology::validity;
use heartmesh_core::mesh::TriMesh;
use heartmesh_core::pipeline::Reconstruction;
use heartmesh_core::{LidMode, Params};
use serde_json::{json, Map, Value};

/// What the command knows besides the reconstruction itself.
pub struct Facts<'a> {
    pub input: &'a str,
    pub input_format: &'a str,
    pub output: &'a str,
    pub params: &'a Params,
    pub seconds: f64,
    pub warnings: &'a [String],
    /// The input's time frames and which were read (None: no time-frame column).
    pub time_frames: Option<&'a TimeFrames>,
    /// The patient frame of the input's coordinates, when its format fixes it.
    pub coordinate_system: Option<CoordinateSystem>,
}

/// Every parameter by its schema name, plus the modes, as the mesh file's header writes them; the
/// report adds `apex_floor` always ([`build`]).
pub fn parameters(params: &Params) -> Value {
    let mut m = Map::new();
    for s in Params::schema() {
        if let Some(v) = params.get(s.name) {
            m.insert(s.name.to_string(), json!(v));
        }
    }
    let lids = match params.lids {
        LidMode::Auto => "auto",
        LidMode::None => "none",
        LidMode::Explicit { .. } => "apex",
    };
    m.insert("lids".into(), json!(lids));
    m.insert("surface".into(), json!(params.surface));
    m.insert("end_caps".into(), json!(params.end_caps.name()));
    // The switches added since the header's format settled, only where they differ from the
    // default: every default file's header keeps its bytes (the apex floor, on by default since
    // session 14, is written as false when off).
    let default = Params::default();
    for (name, on, by_default) in [
        (
            "drop_second_loops",
            params.drop_second_loops,
            default.drop_second_loops,
        ),
        ("apex_floor", params.apex_floor, default.apex_floor),
        ("keep_specks", params.keep_specks, default.keep_specks),
    ] {
        if on != by_default {
            m.insert(name.into(), json!(on));
        }
    }
    if !params.leave_out.is_empty() {
        m.insert("leave_out".into(), json!(params.leave_out));
    }
    Value::Object(m)
}

/// A mesh's own facts (no contours needed): counts, size, topology and triangle quality, under the
/// report's keys; `heartmesh info MESH` prints the same.
pub fn mesh_facts(mesh: &TriMesh) -> Map<String, Value> {
    let v = validity(mesh);
    let q = quality(mesh);
    let facts = json!({
        "vertices": mesh.positions.len(),
        "triangles": mesh.triangles.len(),
        "volume_ml": mesh.volume_ml(),
        "area_mm2": mesh.area(),
        "watertight": v.closed && v.manifold && v.oriented,
        "manifold": v.manifold,
        "oriented": v.oriented,
        "boundary_edges": v.boundary_edges,
        "euler_characteristic": v.euler_characteristic,
        // Geometry, not topology: creases where neighbouring triangles turn more than 90 degrees
        // against each other (where contours that disagree pulled the surface two ways).
        "quality": {
            "folded_edges": q.folded_edges,
            "self_intersections": q.self_intersections,
            "max_dihedral_deg": q.max_dihedral_deg,
            "min_triangle_quality": q.min_triangle_quality,
            "median_triangle_quality": q.median_triangle_quality,
            "max_edge_mm": q.max_edge_mm,
            "mean_edge_mm": q.mean_edge_mm,
        },
    });
    match facts {
        Value::Object(m) => m,
        _ => Map::new(),
    }
}

pub fn build(rec: &Reconstruction, f: &Facts) -> Value {
    let mesh = rec.mesh();
    let d = rec.contour_distances();
    let per_contour: Vec<Value> = d
        .per_contour
        .iter()
        .map(|c| {
            let mut row = json!({
                "id": c.id,
                "kind": c.kind,
                "mean": c.stats.mean,
                "median": c.stats.median,
                "p95": c.stats.p95,
                "max": c.stats.max,
                "points": c.stats.count,
            });
            // Points left out of it as damaged values (only when there are any).
            if let Some(fields) = row.as_object_mut() {
                fields.extend(rec.damage_of(&c.id));
            }
            row
        })
        .collect();
    let o = d.overall;
    // The surface actually reconstructed (the only one of the file when none was asked for).
    let surface = rec
        .contours()
        .iter()
        .find_map(|c| c.surface.clone())
        .or_else(|| f.params.surface.clone());
    let t = rec.total_timings();
    let mut rep = json!({
        "version": heartmesh_core::VERSION,
        "input": f.input,
        "input_format": f.input_format,
        "output": f.output,
        "surface": surface,
        "frame": frame_read(f.time_frames),
        // The mesh is in the input's coordinates: DICOM's LPS, NIfTI's RAS, or null (unknown).
        "coordinate_system": f.coordinate_system.map(CoordinateSystem::name),
        "iterations": rec.iteration(),
        // The method's stop rule can end a run before --iterations (SurFCo: 244 of 250): said
        // here, as the app's result panel says "converged", so a short count is not a mystery.
        "converged": rec.iteration() < rec.total_iterations(),
        "seconds": f.seconds,
        // Where no curve closes an end, the mesh runs on past the data there (extrapolated).
        "past_data": rec.past_data(),
        // Which ends no curve closes got synthetic lid points (not data: in no distance).
        "end_caps": rec.end_caps(),
        // Long-axis curves closed across the valve, fitted opened there (`valve_chord_note`).
        "valve_chords": rec.valve_chords(),
        // Remeshes skipped because each would have wrecked the surface (empty on sound data).
        "skipped_remeshes": rec.skipped_remeshes(),
        "contours": rec.contours().len(),
        "contour_to_mesh": {
            "mean": o.mean,
            "median": o.median,
            "p95": o.p95,
            "max": o.max,
            "points": o.count,
        },
        "per_contour": per_contour,
        // With --align-slices: the shifts found; contour_to_mesh is then to the shifted contours
        // the mesh follows, and this to the file's contours as given.
        "alignment": rec.alignment(),
        // Always (null when no curves of one surface cross): how far apart the file's images
        // are where their planes cross, before any alignment.
        "crossing_residual_mm": rec.crossing_residual_mm(),
        "alignment_suggested": rec.alignment_suggested(),
        "contour_to_mesh_as_given": rec.contour_distances_as_given().map(|d| json!({
            "mean": d.overall.mean,
            "median": d.overall.median,
            "p95": d.overall.p95,
            "max": d.overall.max,
            "points": d.overall.count,
        })),
        "timings_ms": {
            "attractors": t.attractors_ms,
            "closest": t.closest_ms,
            "solve": t.solve_ms,
            "apply": t.apply_ms,
            "remesh": t.remesh_ms,
            "total": t.total_ms,
        },
        "parameters": report_parameters(f.params),
        "warnings": f.warnings,
    });
    if let Some(m) = rep.as_object_mut() {
        m.extend(mesh_facts(mesh));
    }
    // Only when some contour was left out (strays, specks, the user's): default reports keep
    // their bytes. Each with how far the mesh passes from it (mean, median, max in mm).
    if let (false, Some(m)) = (rec.set_aside().is_empty(), rep.as_object_mut()) {
        m.insert("set_aside".into(), json!(rec.set_aside_distances()));
    }
    rep
}

/// The report's `frame`: which time frame the contours were read from, as the file writes it
/// (`"ES"`, `"9"`: the one asked for with `--frame`, or the one every contour starts in); the
/// list of frames (`["0", "1"]`) when the contours start in different frames and none was asked
/// for (each contour's first was read: biv-me's example has one slice labelled `1.0` in a frame-0
/// file); null when the file has no time-frame column. Scripts comparing phases read it to know
/// which phase a mesh is.
pub fn frame_read(time_frames: Option<&TimeFrames>) -> Value {
    match time_frames.map(|t| t.read.as_slice()) {
        None | Some([]) => Value::Null,
        Some([one]) => json!(one),
        Some(several) => json!(several),
    }
}

/// The report's `parameters`: the header's ([`parameters`]) with `apex_floor` whatever its value.
/// Its default changed (session 14), so an absent key would mean off in older reports and on in
/// newer ones; a report says what ran without knowing the version's defaults.
pub fn report_parameters(params: &Params) -> Value {
    let mut p = parameters(params);
    if let Some(m) = p.as_object_mut() {
        m.insert("apex_floor".into(), json!(params.apex_floor));
    }
    p
}

/// A derived file's entry under `key` (its figures and `file`: `anatomical_mesh`, `hex_mesh`),
/// or, when it could not be built, null and `KEY_note` saying why.
pub fn add_built(rep: &mut Value, key: &str, path: &str, built: Result<Value, &String>) {
    let Some(m) = rep.as_object_mut() else {
        return;
    };
    match built {
        Ok(mut v) => {
            if let Some(o) = v.as_object_mut() {
                o.insert("file".into(), json!(crate::cmd_convert::file_name(path)));
            }
            m.insert(key.into(), v);
        }
        Err(why) => {
            m.insert(key.into(), Value::Null);
            m.insert(format!("{key}_note"), json!(why));
        }
    }
}

/// Per-vertex distance to the nearest contour point (mm): the colour on the mesh.
pub fn vertex_distances(rec: &Reconstruction) -> Vec<f64> {
    rec.vertex_distances()
}

/// The comment written into the mesh file's header.
pub fn header_comment(f: &Facts) -> String {
    let p = parameters(f.params);
    let aligned = if f.params.align_slices {
        "; slices aligned (breath-hold shifts, see the report)"
    } else {
        ""
    };
    // A mesh of one phase of a cine file is only comparable with its frame known (ED vs ES).
    let frame = f
        .time_frames
        .and_then(|t| t.named())
        .map(|n| format!(" (frame {n})"))
        .unwrap_or_default();
    let comment = format!(
        "reconstructed from {}{frame}; parameters {p}{aligned}",
        f.input
    );
    io::tagged_comment(f.coordinate_system, &comment)
}

/// When the report says the alignment is worth a try (`Reconstruction::alignment_suggested`): a
/// note saying how far apart the images cross and what to do about it.
pub fn alignment_note(rep: &Value) -> Option<String> {
    let r = rep.get("crossing_residual_mm")?.as_f64()?;
    (rep.get("alignment_suggested")?.as_bool() == Some(true)).then(|| {
        format!(
            "the images disagree by {r:.2} mm (mean) where their planes cross, as breath-hold \
             offsets do; --align-slices shifts them into agreement first"
        )
    })
}

/// When triangles of the mesh pass through each other (`quality.self_intersections`): a warning,
/// since the file is still written but a volume mesher or a slicer would refuse or misread it.
/// On every real file and simulated acquisition measured (docs/VALIDATION.md, "Session 13: mesh
/// self-intersections") the count is 0; inputs the load-time checks warn about can cause it.
pub fn self_intersection_warning(rep: &Value) -> Option<String> {
    let n = rep.get("quality")?.get("self_intersections")?.as_u64()?;
    (n > 0).then(|| {
        format!(
            "the mesh passes through itself ({n} pairs of triangles cross): volume meshers and \
             3D-printing slicers will refuse it; check the warnings about the contours"
        )
    })
}

/// One line for stdout.
pub fn summary(output: &str, rep: &Value) -> String {
    let num = |k: &str| rep.get(k).and_then(Value::as_f64).unwrap_or(f64::NAN);
    let mut s = format!(
        "{output}: {} vertices, {} triangles, {:.1} ml, {:.0} mm2",
        num("vertices"),
        num("triangles"),
        num("volume_ml"),
        num("area_mm2")
    );
    if let Some(c) = rep.get("contour_to_mesh") {
        let g = |k: &str| c.get(k).and_then(Value::as_f64).unwrap_or(f64::NAN);
        s.push_str(&format!(
            ", contour-to-mesh mean {:.3} mm, max {:.3} mm",
            g("mean"),
            g("max")
        ));
    }
    if let Some(groups) = rep
        .get("alignment")
        .and_then(|a| a.get("groups"))
        .and_then(Value::as_array)
    {
        let largest = groups
            .iter()
            .filter_map(|g| g.get("shift_mm").and_then(Value::as_array))
            .map(|v| {
                v.iter()
                    .filter_map(Value::as_f64)
                    .map(|c| c * c)
                    .sum::<f64>()
                    .sqrt()
            })
            .fold(0.0, f64::max);
        s.push_str(&format!(
            ", {} slices/views aligned (largest shift {largest:.2} mm)",
            groups.len()
        ));
    }
    s.push_str(&format!(" ({:.2} s)", num("seconds")));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_frame_read_is_a_label_a_list_or_null() {
        let mut t = TimeFrames {
            frames: vec!["ED".into(), "ES".into()],
            count: 2,
            read: vec!["ES".into()],
            firsts: vec!["ED".into()],
            chosen: true,
            left_out: 1204,
            sequence: true,
            ..TimeFrames::default()
        };
        assert_eq!(frame_read(Some(&t)), json!("ES"));
        t.read = vec!["0".into(), "1".into()];
        assert_eq!(frame_read(Some(&t)), json!(["0", "1"]));
        assert_eq!(frame_read(None), Value::Null);
    }
}
