//! `heartmesh info MESH.vtk` for a volume mesh (a VTK UNSTRUCTURED_GRID: `myocardium
//! --hex-mesh`'s hexahedra, or tetrahedra from gmsh or TetGen): what a simulation user checks
//! before a run (cell counts by type, total volume, the smallest scaled Jacobian, inverted
//! cells) and which arrays the points and cells carry (fibres, segments). Refusing the file, as
//! `info` did, left the user to open it elsewhere to learn whether it was sound.

use heartmesh_core::io::vtk::read_unstructured;
use heartmesh_core::mesh::cells::{self, CellQuality};
use serde_json::{json, Value};

use crate::cmd_convert::file_name;
use crate::cmd_info::{bounds, plural, range_text};
use crate::error::CliError;

/// The facts of the volume mesh in `bytes` (read from `path`).
pub fn facts(path: &str, bytes: &[u8]) -> Result<Value, CliError> {
    let g = read_unstructured(bytes).map_err(|e| CliError::input(path, e))?;
    let mut counts: Vec<(u8, usize)> = Vec::new();
    for &t in &g.types {
        match counts.iter_mut().find(|(k, _)| *k == t) {
            Some((_, n)) => *n += 1,
            None => counts.push((t, 1)),
        }
    }
    let types: Vec<Value> = counts
        .iter()
        .map(|&(t, n)| json!({ "type": t, "name": cells::type_name(t), "cells": n }))
        .collect();
    let q: CellQuality = cells::quality(
        &g.points,
        g.types
            .iter()
            .zip(&g.cells)
            .map(|(&t, c)| (t, c.as_slice())),
    );
    let measured = q.measured > 0;
    Ok(json!({
        "input": file_name(path),
        "format": "VTK unstructured grid",
        "points": g.points.len(),
        "cells": g.cells.len(),
        "cell_types": types,
        "measured_cells": q.measured,
        "volume_ml": measured.then_some(q.volume / 1000.0),
        "min_scaled_jacobian": measured.then_some(q.min_scaled_jacobian),
        "inverted_cells": measured.then_some(q.inverted),
        "bounds_mm": bounds(g.points.iter()),
        "point_data": g.point_arrays,
        "cell_data": g.cell_arrays,
    }))
}

/// The lines `info` prints for a volume mesh.
pub fn text(m: &Value) -> String {
    let n = |k: &str| m.get(k).and_then(Value::as_u64).unwrap_or(0);
    let types: Vec<String> = m["cell_types"]
        .as_array()
        .into_iter()
        .flatten()
        .map(|t| {
            let name = t["name"].as_str().unwrap_or("");
            let count = t["cells"].as_u64().unwrap_or(0);
            match name {
                "hexahedron" => format!("{count} hexahedr{}", if count == 1 { "on" } else { "a" }),
                _ => plural(count, name),
            }
        })
        .collect();
    let mut out = format!(
        "{}: VTK unstructured grid (a volume mesh), {}, {}: {}",
        m["input"].as_str().unwrap_or(""),
        plural(n("points"), "point"),
        plural(n("cells"), "cell"),
        types.join(", ")
    );
    out += &match m["volume_ml"].as_f64() {
        Some(v) => {
            let inverted = n("inverted_cells");
            let unmeasured = n("cells") - n("measured_cells");
            format!(
                "\n  volume {v:.2} ml; smallest scaled Jacobian {:.3}; {}{}",
                m["min_scaled_jacobian"].as_f64().unwrap_or(0.0),
                if inverted == 0 {
                    "no inverted cell".to_string()
                } else {
                    format!(
                        "{} inverted (a corner at or below 0)",
                        plural(inverted, "cell")
                    )
                },
                if unmeasured > 0 {
                    format!(
                        " ({} of other types not measured)",
                        plural(unmeasured, "cell")
                    )
                } else {
                    String::new()
                }
            )
        }
        None => "\n  no tetrahedra, hexahedra, wedges or pyramids to measure".to_string(),
    };
    out += &range_text(m);
    for (key, what) in [("point_data", "point data"), ("cell_data", "cell data")] {
        let list: Vec<String> = m[key]
            .as_array()
            .into_iter()
            .flatten()
            .map(array_text)
            .collect();
        if !list.is_empty() {
            out += &format!("\n  {what}: {}", list.join("; "));
        }
    }
    out
}

/// One array as `info` words it: name, components, range (of the lengths for vectors).
fn array_text(a: &Value) -> String {
    let components = a["components"].as_u64().unwrap_or(1);
    let range = match (a["min"].as_f64(), a["max"].as_f64()) {
        (Some(lo), Some(hi)) if components == 3 => format!(" length {lo:.3} to {hi:.3}"),
        (Some(lo), Some(hi)) => format!(" {lo:.3} to {hi:.3}"),
        _ => String::new(),
    };
    let comps = if components == 1 {
        String::new()
    } else {
        format!(" ({components} components)")
    };
    format!("{}{comps}{range}", a["name"].as_str().unwrap_or(""))
}
