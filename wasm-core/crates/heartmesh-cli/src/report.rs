//! The JSON report of `heartmesh reconstruct` (scripts rely on its keys) and the one-line summary.

use std::collections::HashMap;

use heartmesh_core::pipeline::Reconstruction;
use heartmesh_core::{LidMode, Params, TriMesh};
use serde_json::{json, Map, Value};

/// What the command knows besides the reconstruction itself.
pub struct Facts<'a> {
    pub input: &'a str,
    pub output: &'a str,
    pub params: &'a Params,
    pub iterations: usize,
    pub seconds: f64,
    pub warnings: &'a [String],
}

/// Every parameter by its schema name, plus the modes.
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
        LidMode::Explicit { .. } => "explicit",
    };
    m.insert("lids".into(), json!(lids));
    m.insert("surface".into(), json!(params.surface));
    Value::Object(m)
}

pub fn build(rec: &Reconstruction, f: &Facts) -> Value {
    let mesh = rec.mesh();
    let (watertight, manifold) = mesh_checks(mesh);
    json!({
        "version": heartmesh_core::VERSION,
        "input": f.input,
        "output": f.output,
        "surface": f.params.surface,
        "iterations": f.iterations,
        "seconds": f.seconds,
        "vertices": mesh.positions.len(),
        "triangles": mesh.triangles.len(),
        "volume_ml": mesh.volume_ml(),
        "area_mm2": mesh.area(),
        "watertight": watertight,
        "manifold": manifold,
        "parameters": parameters(f.params),
        "warnings": f.warnings,
    })
}

/// Per-vertex distance to the nearest contour point (mm), when the pipeline provides it.
pub fn vertex_distances(_rec: &Reconstruction) -> Option<Vec<f64>> {
    None
}

/// The comment written into the mesh file's header.
pub fn header_comment(f: &Facts) -> String {
    let p = parameters(f.params);
    format!(
        "reconstructed from {} ({} iterations); parameters {p}",
        f.input, f.iterations
    )
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
    s.push_str(&format!(" ({:.2} s)", num("seconds")));
    s
}

/// (watertight, manifold): every edge shared by exactly two triangles traversing it in opposite
/// directions; no edge shared by more than two triangles.
pub fn mesh_checks(mesh: &TriMesh) -> (bool, bool) {
    let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            *directed.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    let mut manifold = !mesh.triangles.is_empty();
    let mut watertight = manifold;
    for (&(a, b), &n) in &directed {
        let back = directed.get(&(b, a)).copied().unwrap_or(0);
        if n + back > 2 {
            manifold = false;
        }
        if n != 1 || back != 1 {
            watertight = false;
        }
    }
    (watertight, manifold)
}

#[cfg(test)]
mod tests {
    use super::*;
    use heartmesh_core::geometry::v3;

    #[test]
    fn checks_tetra_and_open() {
        let mut m = TriMesh::new(
            vec![
                v3(0., 0., 0.),
                v3(1., 0., 0.),
                v3(0., 1., 0.),
                v3(0., 0., 1.),
            ],
            vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        );
        assert_eq!(mesh_checks(&m), (true, true));
        m.triangles.pop();
        assert_eq!(mesh_checks(&m), (false, true));
        m.triangles.push([1, 3, 2]);
        m.triangles.push([1, 2, 3]);
        assert_eq!(mesh_checks(&m), (false, false));
    }
}
