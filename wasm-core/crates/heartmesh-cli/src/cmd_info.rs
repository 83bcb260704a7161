//! `heartmesh info CONTOURS`: what a contour file holds and what a reconstruction would make of
//! it, without running one. Before a batch of reconstructions a user wants to know which surfaces
//! a file has, how its slices are spaced, which curves would be left out and whether its images
//! need aligning; the core's set-up (`Reconstruction::new`: classification, long axis, set-aside
//! contours, end caps, the images' crossing gap) answers all of it in milliseconds per surface.

use std::collections::BTreeMap;

use heartmesh_core::contours::{set_aside, ContourKind};
use heartmesh_core::geometry::Vec3;
use heartmesh_core::io::{self, ContourFormat, FrameChoice};
use heartmesh_core::mesh::quality::folded_edges_within;
use heartmesh_core::{ContourSet, Params, Reconstruction};
use serde_json::{json, Value};

use crate::args::{parse, Spec};
use crate::cmd_convert::file_name;
use crate::contours;
use crate::error::CliError;
use crate::{files, report};

pub const USAGE: &str = "heartmesh info CONTOURS [VIEWS...] [--frame N|LABEL] [--json]
    or: heartmesh info MESH.obj|.stl|.ply|.vtk|.vtp [--json]
    or: heartmesh info FILE FILE... [--json]  (each in turn; --json: an array)
  What the file holds and what reconstruct would make of it, without running it: format, time
  frames, points, landmarks, coordinate range (mm, the file's own frame), and per surface the
  short- and long-axis contours (their ids, as reconstruct's --leave-out takes them), the
  slices' spacing, the long axis, the contours a run leaves
  out and why, the ends that get lid points, and how far the images disagree where their planes
  cross (with the advice to --align-slices when they do). A surface that cannot be
  reconstructed says why (exit status 0: the file was read). A mesh file: vertices, triangles,
  closed / manifold / oriented, volume (closed meshes) and area, range, edge lengths, triangle
  quality, folded edges, self-intersections, its point data and its triangles' region labels
  (name, triangles, area each: `myocardium` writes epicardium / endocardium / base), under the
  keys of reconstruct's report. A volume mesh (a VTK unstructured grid: myocardium --hex-mesh,
  gmsh, TetGen): points, cells by type, volume, the smallest scaled Jacobian and inverted cells
  (tetrahedra, hexahedra, wedges, pyramids), and its point and cell data arrays (name,
  components, range). --json prints the same as JSON.";

pub fn run(args: &[String]) -> Result<(), CliError> {
    let p = parse(
        args,
        &Spec {
            with_value: &["frame"],
            switches: &["json"],
            aliases: &[],
        },
    )?;
    if p.positional.is_empty() {
        return Err(CliError::usage("info needs a contour file"));
    }
    let frame = contours::frame_flag(p.value("frame"))?;
    let json = p.switch("json");
    let files = p.positional.as_slice();
    if files.len() == 1 || is_study(&files[0]) || contours::is_workspace_study(files) {
        let (info, words) = describe_files(files, frame)?;
        return print(&info, json, words);
    }
    // Several files that are no segmented study (`heartmesh info exports/*`): each in turn, a
    // file that cannot be read named on stderr without stopping the others; the last such error
    // is the command's (status 2), as `reconstruct --surface all` does with its surfaces.
    let mut infos = Vec::new();
    let mut failed: Option<CliError> = None;
    for file in files {
        match describe_files(std::slice::from_ref(file), frame.clone()) {
            Ok((info, words)) if !json => outln!("{}\n", words(&info)),
            Ok((info, _)) => infos.push(info),
            Err(e) => {
                if let Some(earlier) = failed.replace(e) {
                    eprintln!("heartmesh: {}", earlier.message());
                }
            }
        }
    }
    if json {
        print(&Value::Array(infos), true, text)?;
    }
    failed.map_or(Ok(()), Err)
}

type Words = fn(&Value) -> String;

/// One file's facts (a mesh's, or a contour file's; several files: one segmented study) and how
/// to word them.
fn describe_files(
    files: &[String],
    frame: Option<FrameChoice>,
) -> Result<(Value, Words), CliError> {
    if let [one] = files {
        if let Some(described) = mesh_file(one)? {
            return Ok(described);
        }
    }
    let (input, loaded) = contours::load_all(files, frame)?;
    let base = loaded.session_params.unwrap_or_default();
    let info = describe(file_name(input), loaded.format.name(), &loaded.set, &base);
    Ok((info, text))
}

/// Whether `path` is a label map, whose companions on the command line are its long-axis views.
fn is_study(path: &str) -> bool {
    files::read(path).is_ok_and(|bytes| {
        matches!(
            io::detect_contour_format(path, &bytes),
            ContourFormat::Nifti
                | ContourFormat::Nrrd
                | ContourFormat::DicomSeg
                | ContourFormat::Cvi42
                | ContourFormat::Sunnybrook
        )
    })
}

fn print(info: &Value, json: bool, words: Words) -> Result<(), CliError> {
    if json {
        let text =
            serde_json::to_string_pretty(info).map_err(|e| CliError::Failed(e.to_string()))?;
        outln!("{text}");
    } else {
        outln!("{}", words(info));
    }
    Ok(())
}

/// A surface file's facts (`mesh_facts`, as a reconstruction's report gives them, plus its range
/// and point data), a volume mesh's (`info_volume`), or None when `path` holds contours: .vtk
/// and .vtp hold either.
fn mesh_file(path: &str) -> Result<Option<(Value, Words)>, CliError> {
    let ext = io::extension(path);
    if !matches!(ext.as_str(), "obj" | "stl" | "ply" | "vtk" | "vtp") {
        return Ok(None);
    }
    let bytes = files::read(path)?;
    if ext == "vtk" && io::vtk::is_unstructured_grid(&bytes) {
        return Ok(Some((
            crate::info_volume::facts(path, &bytes)?,
            crate::info_volume::text,
        )));
    }
    let data = match io::read_mesh(path, &bytes) {
        Ok(data) => data,
        Err(_) if matches!(ext.as_str(), "vtk" | "vtp") => return Ok(None),
        Err(e) => return Err(CliError::input(path, e)),
    };
    let mut facts = report::mesh_facts(&data.mesh);
    facts.insert("input".into(), json!(file_name(path)));
    facts.insert("format".into(), json!(ext.to_ascii_uppercase()));
    facts.insert("bounds_mm".into(), bounds(data.mesh.positions.iter()));
    // The patient frame the file states (SPACE=LPS / SPACE=RAS), null when it states none.
    facts.insert(
        "coordinate_system".into(),
        json!(data.coordinate_system.map(|c| c.name())),
    );
    let point_data = data.point_data.as_ref().map(|(name, v)| {
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        json!({ "name": name, "min": lo, "max": hi })
    });
    facts.insert("point_data".into(), json!(point_data));
    facts.insert("regions".into(), regions_json(&data));
    Ok(Some((Value::Object(facts), mesh_text)))
}

/// The triangle labels the file carried (a wall's epicardium / endocardium / base): each
/// region's label, name, triangles and area, and the folded edges within regions, since where
/// two regions meet (the wall's rim) the crease is by design; null without labels.
fn regions_json(data: &io::MeshData) -> Value {
    let Some(r) = &data.regions else {
        return Value::Null;
    };
    let list: Vec<Value> = r
        .facts(&data.mesh)
        .into_iter()
        .map(|f| {
            json!({ "label": f.label, "name": f.name, "triangles": f.triangles,
                    "area_mm2": f.area_mm2 })
        })
        .collect();
    json!({
        "array": r.array,
        "list": list,
        "folded_edges_within": folded_edges_within(&data.mesh, &r.labels),
    })
}

/// The lines `info MESH` prints.
fn mesh_text(m: &Value) -> String {
    let n = |k: &str| m.get(k).and_then(Value::as_u64).unwrap_or(0);
    let f = |p: &str| m.pointer(p).and_then(Value::as_f64).unwrap_or(0.0);
    let yes = |k: &str| m[k].as_bool() == Some(true);
    let mut out = format!(
        "{}: {} mesh, {} vertices, {} triangles",
        m["input"].as_str().unwrap_or(""),
        m["format"].as_str().unwrap_or(""),
        n("vertices"),
        n("triangles")
    );
    out += &if yes("watertight") {
        format!(
            "\n  closed, manifold, consistently oriented{} (Euler characteristic {})",
            if f("/volume_ml") > 0.0 {
                ", outward"
            } else {
                ", inward (negative volume)"
            },
            m["euler_characteristic"]
        )
    } else {
        format!(
            "\n  not closed: {} boundary edges; manifold {}, oriented {}",
            n("boundary_edges"),
            yes("manifold"),
            yes("oriented")
        )
    };
    let volume = f("/volume_ml");
    out += &if !yes("watertight") {
        format!(
            "\n  area {:.0} mm2 (open: no enclosed volume)",
            f("/area_mm2")
        )
    } else if volume.abs() < 1.0 {
        format!(
            "\n  volume {:.1} mm3, area {:.1} mm2",
            volume * 1000.0,
            f("/area_mm2")
        )
    } else {
        format!("\n  volume {volume:.2} ml, area {:.0} mm2", f("/area_mm2"))
    };
    out += &range_text(m);
    out +=
        &format!(
        "\n  edges {:.2} mm mean, {:.2} max; triangle quality {:.2} min, {:.2} median; {} folded \
         edges; {} pairs of triangles crossing",
        f("/quality/mean_edge_mm"),
        f("/quality/max_edge_mm"),
        f("/quality/min_triangle_quality"),
        f("/quality/median_triangle_quality"),
        m.pointer("/quality/folded_edges").and_then(Value::as_u64).unwrap_or(0),
        m.pointer("/quality/self_intersections").and_then(Value::as_u64).unwrap_or(0)
    );
    if let Some(name) = m.pointer("/point_data/name").and_then(Value::as_str) {
        out += &format!(
            "\n  point data {name}: {:.3} to {:.3}",
            f("/point_data/min"),
            f("/point_data/max")
        );
    }
    if let Some(list) = m.pointer("/regions/list").and_then(Value::as_array) {
        out += &format!(
            "\n  regions ({}): {}; {} folded edges within them",
            m.pointer("/regions/array")
                .and_then(Value::as_str)
                .unwrap_or(""),
            list.iter()
                .map(|r| format!(
                    "{} {} ({}, {:.0} mm2)",
                    r["label"],
                    r["name"].as_str().unwrap_or(""),
                    plural(r["triangles"].as_u64().unwrap_or(0), "triangle"),
                    r["area_mm2"].as_f64().unwrap_or(0.0)
                ))
                .collect::<Vec<_>>()
                .join(", "),
            m.pointer("/regions/folded_edges_within")
                .and_then(Value::as_u64)
                .unwrap_or(0)
        );
    }
    out
}

/// The file's facts and one entry per surface (JSON; [`text`] words it).
fn describe(input: &str, format: &str, set: &ContourSet, base: &Params) -> Value {
    let mut landmarks: BTreeMap<&str, usize> = BTreeMap::new();
    for (name, _) in &set.landmarks {
        *landmarks.entry(name.as_str()).or_default() += 1;
    }
    let labels: Vec<Option<String>> = match set.surfaces() {
        l if l.is_empty() => vec![None],
        l => l.into_iter().map(Some).collect(),
    };
    let surfaces: Vec<Value> = labels
        .iter()
        .map(|s| surface(set, base, s.as_deref()))
        .collect();
    let frames = set.time_frames.as_ref().map(|t| {
        json!({
            "count": t.count,
            "listed": t.frames,
            "read": report::frame_read(Some(t)),
            "sequence": t.sequence,
            "chosen": t.chosen,
            "end_diastole": t.end_diastole,
            "end_systole": t.end_systole,
        })
    });
    json!({
        "input": input,
        "format": format,
        "contours": set.contours.len(),
        "points": set.point_count(),
        "landmarks": landmarks,
        "bounds_mm": bounds(set.contours.iter().flat_map(|c| c.points())),
        // The patient frame the format fixes (LPS, RAS), null when it does not say.
        "coordinate_system": set.coordinate_system.map(|c| c.name()),
        "time_frames": frames,
        // The file's own warnings; those about one surface's contours go with that surface.
        "warnings": set
            .warnings
            .iter()
            .filter(|w| !set.surface_warnings.iter().any(|(_, t)| t == *w))
            .collect::<Vec<_>>(),
        "surfaces": surfaces,
    })
}

/// One surface as `reconstruct --surface` would set it up.
fn surface(set: &ContourSet, base: &Params, label: Option<&str>) -> Value {
    let own: Vec<&String> = set
        .surface_warnings
        .iter()
        .filter(|(s, _)| Some(s.as_str()) == label)
        .map(|(_, w)| w)
        .collect();
    let params = Params {
        surface: label.map(str::to_string),
        ..base.clone()
    };
    // Step 0 builds the initial tube and decides the end caps; nothing is deformed yet.
    let rec = Reconstruction::new(set, params).and_then(|mut rec| rec.step().map(|_| rec));
    let rec = match rec {
        Ok(rec) => rec,
        Err(e) => {
            let given = set
                .contours
                .iter()
                .filter(|c| c.surface.as_deref() == label)
                .count();
            return json!({ "surface": label, "contours": given, "warnings": own, "error": e.to_string() });
        }
    };
    // As reconstruct says them: the load-time warnings, then any left-out contour they did not name.
    let said: Vec<String> = own.iter().map(|w| w.to_string()).collect();
    let mut warnings = said.clone();
    warnings.extend(set_aside::unannounced(rec.set_aside(), &said));
    let kinds = rec.kinds();
    let count = |k: ContourKind| kinds.iter().filter(|&&x| x == k).count();
    let used = rec.contours();
    let open = used
        .iter()
        .filter(|c| c.pieces.iter().any(|p| !p.closed))
        .count();
    let heights = rec.slice_heights();
    let mut gaps: Vec<f64> = heights.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    gaps.sort_by(f64::total_cmp);
    let spacing = (!gaps.is_empty()).then(
        || json!({ "min": gaps[0], "median": gaps[gaps.len() / 2], "max": gaps[gaps.len() - 1] }),
    );
    let a = rec.long_axis();
    // The ids, as `--leave-out` takes them (a file's names are often all a user has to go by).
    let ids = |k: ContourKind| -> Vec<&str> {
        used.iter()
            .zip(kinds)
            .filter(|(_, &x)| x == k)
            .map(|(c, _)| c.id.as_str())
            .collect()
    };
    json!({
        "surface": label,
        "contours": used.len(),
        "ids": { "sax": ids(ContourKind::Sax), "lax": ids(ContourKind::Lax) },
        "sax": count(ContourKind::Sax),
        "lax": count(ContourKind::Lax),
        "open_curves": open,
        "points": used.iter().map(|c| c.point_count()).sum::<usize>(),
        "slices": heights.len(),
        "slice_spacing_mm": spacing,
        "stack_height_mm": heights.last().zip(heights.first()).map(|(t, b)| (t - b).abs()),
        "long_axis": [a.x, a.y, a.z],
        "set_aside": rec.set_aside(),
        "end_caps": rec.end_caps(),
        "crossing_residual_mm": rec.crossing_residual_mm(),
        "alignment_suggested": rec.alignment_suggested(),
        "warnings": warnings,
    })
}

/// The lines `info` prints.
fn text(info: &Value) -> String {
    let n = |v: &Value, k: &str| v.get(k).and_then(Value::as_u64).unwrap_or(0);
    let mut out = format!(
        "{}: {}, {} contours, {} points",
        info["input"].as_str().unwrap_or(""),
        info["format"].as_str().unwrap_or(""),
        n(info, "contours"),
        n(info, "points")
    );
    // A frame column whose slices merely carry their own numbers (each slice's first frame read)
    // is no sequence: not worth a line.
    let sequence = |t: &&Value| {
        t["sequence"] == true || t["chosen"] == true || (n(t, "count") > 1 && t["read"].is_string())
    };
    if let Some(t) = info.get("time_frames").filter(sequence) {
        let words = |v: &Value| match v {
            Value::String(s) => s.clone(),
            Value::Array(a) => a
                .iter()
                .filter_map(Value::as_str)
                .collect::<Vec<_>>()
                .join(", "),
            _ => String::new(),
        };
        out += &format!(
            "\n  time frames: {} ({}); read: {} (--frame picks one)",
            n(t, "count"),
            words(&t["listed"]),
            words(&t["read"])
        );
        if let (Some(ed), Some(es)) = (t["end_diastole"].as_str(), t["end_systole"].as_str()) {
            out += &format!("; the file's end-diastole {ed}, end-systole {es}");
        }
    }
    out += &range_text(info);
    if let Some(marks) = info["landmarks"].as_object().filter(|m| !m.is_empty()) {
        let list: Vec<String> = marks.iter().map(|(k, v)| format!("{k} {v}")).collect();
        out += &format!("\n  landmarks: {}", list.join(", "));
    }
    for w in info["warnings"].as_array().into_iter().flatten() {
        let w = w.as_str().unwrap_or("");
        let kind = if io::is_reading_note(w) {
            "note"
        } else {
            "warning"
        };
        out += &format!("\n  {kind}: {w}");
    }
    // The images' crossing gap is the file's (every surface's curves are aligned together): said
    // once when every surface gives the same.
    let surfaces: Vec<&Value> = info["surfaces"].as_array().into_iter().flatten().collect();
    let gaps: Vec<Option<String>> = surfaces.iter().map(|s| crossing_text(s)).collect();
    let known: Vec<&String> = gaps.iter().flatten().collect();
    let shared = known.len() > 1 && known.windows(2).all(|w| w[0] == w[1]);
    if let (true, Some(line)) = (shared, known.first()) {
        out += &format!("\n  {line}");
    }
    for (s, gap) in surfaces.iter().zip(gaps) {
        out += &format!("\n{}", surface_text(s, if shared { None } else { gap }));
    }
    out
}

/// How far apart the images are where their planes cross, with the advice to align them.
fn crossing_text(s: &Value) -> Option<String> {
    let r = s["crossing_residual_mm"].as_f64()?;
    Some(if s["alignment_suggested"].as_bool() == Some(true) {
        format!(
            "the images disagree by {r:.2} mm (mean) where their planes cross, as breath-hold \
             offsets do: --align-slices shifts them into agreement first"
        )
    } else {
        format!("where their planes cross the images are {r:.2} mm apart (mean)")
    })
}

fn surface_text(s: &Value, crossing: Option<String>) -> String {
    let n = |k: &str| s.get(k).and_then(Value::as_u64).unwrap_or(0);
    let name = s["surface"].as_str().unwrap_or("(unlabelled)");
    if let Some(e) = s["error"].as_str() {
        return format!(
            "{name}: {}; cannot be reconstructed: {e}",
            plural(n("contours"), "contour")
        );
    }
    let mut out = format!(
        "{name}: {} ({} short-axis, {} long-axis{}), {} points",
        plural(n("contours"), "contour"),
        n("sax"),
        n("lax"),
        match n("open_curves") {
            0 => String::new(),
            k => format!("; {k} open"),
        },
        n("points")
    );
    let names = |k: &str| -> Vec<&str> {
        s["ids"][k]
            .as_array()
            .into_iter()
            .flatten()
            .filter_map(Value::as_str)
            .collect()
    };
    for (kind, k) in [("short-axis", "sax"), ("long-axis", "lax")] {
        let list = names(k);
        if !list.is_empty() {
            out += &format!("\n  {kind}: {}", list.join(", "));
        }
    }
    let num = |p: &str| s.pointer(p).and_then(Value::as_f64).unwrap_or(0.0);
    if s["slice_spacing_mm"].is_object() {
        out += &format!(
            "\n  {} slices {:.1} mm apart (median; {:.1} to {:.1}), {:.1} mm from apex to base",
            n("slices"),
            num("/slice_spacing_mm/median"),
            num("/slice_spacing_mm/min"),
            num("/slice_spacing_mm/max"),
            num("/stack_height_mm")
        );
    }
    out += &format!(
        "\n  long axis (apex to base): ({:.3}, {:.3}, {:.3})",
        num("/long_axis/0"),
        num("/long_axis/1"),
        num("/long_axis/2")
    );
    let caps = &s["end_caps"];
    let on = |k: &str| caps[k].as_bool() == Some(true);
    let mut ends: Vec<&str> = Vec::new();
    if on("base") {
        ends.push(if on("base_ceiling") {
            "base, a ceiling one slice spacing past the basal slice"
        } else {
            "base"
        });
    } else if on("base_too_narrow") {
        ends.push(
            "the base left open (its outline has no room for them at this attractor spacing; \
             should it run on over 5 mm past the data, the run lays them nearer its rim)",
        );
    }
    if on("apex") {
        ends.push(if on("apex_floor") {
            "apex, one point at the tip the apical slices' taper predicts (the apex floor)"
        } else {
            "apex"
        });
    }
    if !ends.is_empty() {
        out += &format!(
            "\n  lid points where no long-axis curve closes the cavity (--end-caps off: none): {}",
            ends.join("; ")
        );
    }
    if let Some(line) = crossing {
        out += &format!("\n  {line}");
    }
    for w in s["warnings"].as_array().into_iter().flatten() {
        out += &format!("\n  warning: {}", w.as_str().unwrap_or(""));
    }
    out
}

pub(crate) fn plural(n: u64, word: &str) -> String {
    format!("{n} {word}{}", if n == 1 { "" } else { "s" })
}

/// The smallest box around `points` (mm, the file's own frame), or null for none.
pub(crate) fn bounds<'a>(points: impl Iterator<Item = &'a Vec3>) -> Value {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if lo[0] <= hi[0] {
        json!({ "min": lo, "max": hi })
    } else {
        Value::Null
    }
}

/// The `coordinates (mm)` line of a `bounds_mm` (`(mm, LPS)` when the frame is known), or nothing.
pub(crate) fn range_text(info: &Value) -> String {
    let (Some(lo), Some(hi)) = (
        info.pointer("/bounds_mm/min").and_then(Value::as_array),
        info.pointer("/bounds_mm/max").and_then(Value::as_array),
    ) else {
        return String::new();
    };
    let axes: Vec<String> = ["x", "y", "z"]
        .iter()
        .zip(lo.iter().zip(hi))
        .map(|(a, (l, h))| {
            let (l, h) = (l.as_f64().unwrap_or(0.0), h.as_f64().unwrap_or(0.0));
            format!("{a} {l:.1} to {h:.1}")
        })
        .collect();
    let frame = info
        .get("coordinate_system")
        .and_then(Value::as_str)
        .map(|s| format!(", {s}"))
        .unwrap_or_default();
    format!("\n  coordinates (mm{frame}): {}", axes.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lid line names a base left open for want of room (not silence, which reads as "no
    /// lid needed"), and a lidded base as before.
    #[test]
    fn a_base_too_narrow_for_a_lid_is_named() {
        let surface = |caps: Value| json!({"surface": "RV_ENDO", "contours": 3, "end_caps": caps});
        let open = surface_text(
            &surface(
                json!({"mode": "auto", "base": false, "apex": false, "points": 0,
                            "base_too_narrow": true}),
            ),
            None,
        );
        assert!(
            open.contains("(--end-caps off: none): the base left open (its outline has no room"),
            "{open}"
        );
        let lidded = surface_text(
            &surface(json!({"mode": "auto", "base": true, "apex": false, "points": 11})),
            None,
        );
        assert!(lidded.ends_with("(--end-caps off: none): base"), "{lidded}");
    }
}
