//! `heartmesh convert IN OUT`: contours from any readable format to canonical CSV, meshes between
//! OBJ, STL, PLY, VTK and VTP (keeping a per-vertex scalar where both formats have one).

use heartmesh_core::io::{self, MeshFormat};

use crate::args::{parse, Spec};
use crate::contours;
use crate::error::CliError;
use crate::files;

pub const USAGE: &str = "heartmesh convert IN OUT [--frame N] [--ascii] [--quiet]
    contours (csv, GPFile txt, xyz txt, vtk/vtp lines, SurFCo .mat, session json)
      -> OUT.csv (canonical CSV) or OUT.json (heartmesh session)
    meshes (obj, stl, ply, vtk, vtp) -> OUT.obj|.stl|.ply|.vtk|.vtp  (--ascii: ASCII STL)";

pub fn run(args: &[String]) -> Result<(), CliError> {
    let p = parse(
        args,
        &Spec {
            with_value: &["frame"],
            switches: &["ascii", "quiet"],
            aliases: &[("-q", "quiet")],
        },
    )?;
    let [input, output] = p.positional.as_slice() else {
        return Err(CliError::usage(format!(
            "convert needs IN and OUT, got {} file names",
            p.positional.len()
        )));
    };
    let out_ext = io::extension(output);
    let comment = format!("converted from {}", file_name(input));
    if out_ext == "csv" || out_ext == "json" {
        let frame = contours::frame_flag(p.value("frame"))?;
        let loaded = contours::load(input, frame)?;
        let set = loaded.set;
        if !p.switch("quiet") {
            for w in &set.warnings {
                eprintln!("heartmesh: warning: {input}: {w}");
            }
        }
        let out = if out_ext == "csv" {
            io::csv::write_csv(&set, None)
        } else {
            let params = loaded.session_params.unwrap_or_default();
            io::session::write_session(&set, &params, heartmesh_core::VERSION)
        }
        .map_err(|e| CliError::Failed(format!("{output}: {e}")))?;
        files::write(output, &out)?;
        if !p.switch("quiet") {
            println!(
                "{output}: {} contours, {} points, {} landmarks",
                set.contours.len(),
                set.point_count(),
                set.landmarks.len()
            );
        }
        return Ok(());
    }
    let mut format = MeshFormat::from_path(output).ok_or_else(|| {
        CliError::usage(format!(
            "cannot tell the output format of {output} (use .csv for contours, .obj .stl .ply .vtk .vtp for meshes)"
        ))
    })?;
    if p.switch("ascii") && format == MeshFormat::StlBinary {
        format = MeshFormat::StlAscii;
    }
    let bytes = files::read(input)?;
    let data = io::read_mesh(input, &bytes).map_err(|e| CliError::input(input, e))?;
    let pd = data
        .point_data
        .as_ref()
        .map(|(n, v)| (n.as_str(), v.as_slice()));
    let out = io::write_mesh(&data.mesh, format, pd, &comment)
        .map_err(|e| CliError::Failed(format!("{output}: {e}")))?;
    files::write(output, &out)?;
    if !p.switch("quiet") {
        println!(
            "{output}: {} vertices, {} triangles",
            data.mesh.positions.len(),
            data.mesh.triangles.len()
        );
    }
    Ok(())
}

/// The last path component, for headers (full paths may be private).
pub fn file_name(path: &str) -> &str {
    path.rsplit(['/', '\\']).next().unwrap_or(path)
}
