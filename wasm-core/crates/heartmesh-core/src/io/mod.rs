//! Reading contours and meshes, writing meshes: the file formats people bring (see issue 4).
//!
//! Every reader takes bytes (the core never touches the file system, so it runs in the browser
//! worker unchanged) and returns [`CoreError::Parse`] with a 1-based line on bad input; none may
//! panic. Format detection looks at the content first and the file extension second.

mod builder;
pub mod csv;
pub mod obj;
mod text;

pub use builder::{polyline_from_run, MAX_POINTS};

use crate::contours::ContourSet;
use crate::error::{CoreError, Result};
use crate::mesh::TriMesh;

/// Largest vertex or triangle count accepted when reading a mesh.
pub const MAX_MESH_ELEMENTS: usize = 20_000_000;

/// A mesh read from a file, with the per-vertex scalar the file carried (if any).
#[derive(Debug, Clone, PartialEq)]
pub struct MeshData {
    pub mesh: TriMesh,
    /// (name, one value per vertex), e.g. ("distance", ...).
    pub point_data: Option<(String, Vec<f64>)>,
}

/// Contour file formats the core reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContourFormat {
    Csv,
}

/// Mesh file formats the core writes (and reads back).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshFormat {
    Obj,
    StlBinary,
    StlAscii,
    Ply,
    Vtk,
    Vtp,
}

impl MeshFormat {
    /// From a file name's extension (`.stl` means binary STL).
    pub fn from_path(path: &str) -> Option<MeshFormat> {
        Some(match extension(path).as_str() {
            "obj" => MeshFormat::Obj,
            "stl" => MeshFormat::StlBinary,
            "ply" => MeshFormat::Ply,
            "vtk" => MeshFormat::Vtk,
            "vtp" => MeshFormat::Vtp,
            _ => return None,
        })
    }

    /// Usual file extension.
    pub fn extension(self) -> &'static str {
        match self {
            MeshFormat::Obj => "obj",
            MeshFormat::StlBinary | MeshFormat::StlAscii => "stl",
            MeshFormat::Ply => "ply",
            MeshFormat::Vtk => "vtk",
            MeshFormat::Vtp => "vtp",
        }
    }
}

/// Lower-case extension of a file name ("" when there is none).
pub fn extension(path: &str) -> String {
    let name = path.rsplit(['/', '\\']).next().unwrap_or(path);
    match name.rsplit_once('.') {
        Some((stem, ext)) if !stem.is_empty() => ext.to_ascii_lowercase(),
        _ => String::new(),
    }
}

/// Guesses the contour format from the content, then from the extension.
pub fn detect_contour_format(_file_name: &str, _bytes: &[u8]) -> ContourFormat {
    ContourFormat::Csv
}

/// Reads contours from any supported format.
pub fn read_contours(file_name: &str, bytes: &[u8]) -> Result<ContourSet> {
    match detect_contour_format(file_name, bytes) {
        ContourFormat::Csv => csv::read_csv(bytes),
    }
}

/// Reads a triangle mesh (format from the content, then the extension).
pub fn read_mesh(file_name: &str, bytes: &[u8]) -> Result<MeshData> {
    match extension(file_name).as_str() {
        "obj" => obj::read_obj(bytes),
        other => Err(CoreError::parse(
            0,
            format!("unsupported mesh format {other:?} (expected obj, stl, ply, vtk or vtp)"),
        )),
    }
}

/// Serialises a mesh; `point_data` is one scalar per vertex (written where the format allows:
/// PLY, VTK, VTP); `header_comment` goes into the file's header or comment lines.
pub fn write_mesh(
    mesh: &TriMesh,
    format: MeshFormat,
    point_data: Option<(&str, &[f64])>,
    header_comment: &str,
) -> Result<Vec<u8>> {
    check_mesh(mesh, point_data)?;
    Ok(match format {
        MeshFormat::Obj => obj::write_obj(mesh, header_comment),
        _ => {
            return Err(CoreError::Io(format!(
                "{format:?} writer not available yet"
            )))
        }
    })
}

/// Refuses meshes that would produce broken files (dangling indices, wrong data length).
fn check_mesh(mesh: &TriMesh, point_data: Option<(&str, &[f64])>) -> Result<()> {
    let n = mesh.positions.len();
    if let Some(t) = mesh
        .triangles
        .iter()
        .find(|t| t.iter().any(|&i| i as usize >= n))
    {
        return Err(CoreError::InvalidMesh(format!(
            "triangle {t:?} refers to a vertex beyond the {n} vertices"
        )));
    }
    if let Some((name, values)) = point_data {
        if values.len() != n {
            return Err(CoreError::Io(format!(
                "point data {name:?} has {} values for {n} vertices",
                values.len()
            )));
        }
    }
    Ok(())
}

/// The header every writer puts first: `heartmesh <version>` and the caller's comment, one
/// entry per line of the comment (empty lines dropped).
pub(crate) fn header_lines(comment: &str) -> Vec<String> {
    let mut out = vec![format!("heartmesh {}", crate::VERSION)];
    out.extend(
        comment
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .map(str::to_string),
    );
    out
}

/// Shortest text that reads back to the same f64 (`{}` never uses exponents, which would make
/// tiny or huge values very long, so those use `{:e}`).
pub(crate) fn fmt_num(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || (1e-5..1e15).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Test data lives in `shared/data` next to the checkout (../../../../shared/data from a crate in
/// the main checkout, one level more from a worktree under wt/): the nearest ancestor that has it.
#[cfg(test)]
pub(crate) fn sample(rel: &str) -> Vec<u8> {
    let here = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = here
        .ancestors()
        .map(|a| a.join("shared/data"))
        .find(|d| d.join("README.md").is_file())
        .expect("shared/data not found above CARGO_MANIFEST_DIR");
    let path = dir.join(rel);
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extensions() {
        assert_eq!(MeshFormat::from_path("a/b.OBJ"), Some(MeshFormat::Obj));
        assert_eq!(MeshFormat::from_path("x.stl"), Some(MeshFormat::StlBinary));
        assert_eq!(MeshFormat::from_path(".vtp"), None);
        assert_eq!(MeshFormat::from_path("mesh"), None);
    }

    #[test]
    fn numbers_round_trip() {
        for v in [0.0, -1.5, 1e-12, 123.456789012345, 3e20, -0.1] {
            assert_eq!(fmt_num(v).parse::<f64>().unwrap(), v);
        }
    }
}
