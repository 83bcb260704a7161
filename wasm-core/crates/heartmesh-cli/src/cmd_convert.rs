//! `heartmesh convert IN OUT`: contours from any readable format to canonical CSV, meshes between
//! OBJ, STL, PLY, VTK and VTP (keeping a per-vertex scalar where both formats have one).

use heartmesh_core::io::{self, MeshFormat};

use crate::args::{parse, Spec};
use crate::contours;
use crate::error::CliError;
use crate::files;

pub const USAGE: &str = "heartmesh convert IN [VIEWS...] OUT [--frame N|LABEL] [--ascii] [--quiet]
    contours (csv, GPFile txt, xyz txt, vtk/vtp lines, SurFCo or Segment .mat, session json,
      DICOM RTSTRUCT, NIfTI label maps: a short-axis stack, with its long-axis views if any)
      -> OUT.csv (canonical CSV), OUT.json (heartmesh session), OUT.vtk|.vtp (polylines),
         OUT.dcm (DICOM RT structure set, one ROI per surface)
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
    let [inputs @ .., output] = p.positional.as_slice() else {
        return Err(CliError::usage(
            "convert needs IN and OUT, got no file names",
        ));
    };
    if inputs.is_empty() {
        return Err(CliError::usage(format!(
            "convert needs IN and OUT, got 1 file name ({output})"
        )));
    }
    let input = &inputs[0];
    files::check_output(output)?;
    let paths: Vec<&str> = inputs.iter().map(String::as_str).collect();
    files::check_distinct(&paths, &[("OUT", output)])?;
    let out_ext = io::extension(output);
    let comment = format!("converted from {}", file_name(input));
    let format = MeshFormat::from_path(output);
    let contour_out = matches!(out_ext.as_str(), "csv" | "json" | "dcm");
    if format.is_none() && !contour_out {
        return Err(CliError::usage(format!(
            "cannot tell the output format of {output} (contours: .csv .json .vtk .vtp .dcm; meshes: .obj .stl .ply .vtk .vtp)"
        )));
    }
    // .vtk and .vtp hold either: a mesh when the input is one, else contour polylines.
    let lines_ok = matches!(out_ext.as_str(), "vtk" | "vtp");
    let in_ext = io::extension(input);
    let mesh_in = matches!(in_ext.as_str(), "obj" | "stl" | "ply" | "vtk" | "vtp");
    if let (Some(mut format), true) = (format, mesh_in) {
        let bytes = files::read(input)?;
        match io::read_mesh(input, &bytes) {
            Ok(data) => {
                if p.switch("ascii") && format == MeshFormat::StlBinary {
                    format = MeshFormat::StlAscii;
                }
                // The frame the input states goes on, where the output format has room for it.
                let comment = io::tagged_comment(data.coordinate_system, &comment);
                return write_mesh(&data, format, output, &comment, p.switch("quiet"));
            }
            // A .vtk/.vtp of polylines is contours, not a mesh: fall through.
            Err(e) if !(lines_ok && matches!(in_ext.as_str(), "vtk" | "vtp")) => {
                return Err(CliError::input(input, e))
            }
            Err(_) => {}
        }
    } else if format.is_some() && !lines_ok {
        return Err(CliError::usage(format!(
            "{input} is not a mesh file (obj, stl, ply, vtk, vtp); contours convert to .csv .json .vtk .vtp .dcm"
        )));
    }
    let frame = contours::frame_flag(p.value("frame"))?;
    let (input, loaded) = contours::load_all(inputs, frame)?;
    let set = loaded.set;
    if !p.switch("quiet") {
        for w in &set.warnings {
            eprintln!("{}", contours::warning_line(input, w));
        }
    }
    let out = match out_ext.as_str() {
        "csv" => io::csv::write_csv(&set, None),
        "json" => {
            let params = loaded.session_params.unwrap_or_default();
            io::session::write_session(&set, &params, heartmesh_core::VERSION)
        }
        "dcm" => io::rtstruct::write_rtstruct(&set, stem(input)),
        ext => Ok(io::write_contour_lines(
            &set,
            ext == "vtp",
            &io::tagged_comment(set.coordinate_system, &comment),
        )),
    }
    .map_err(|e| CliError::Failed(format!("{output}: {e}")))?;
    files::write(output, &out)?;
    if !p.switch("quiet") {
        outln!(
            "{output}: {} contours, {} points, {} landmarks",
            set.contours.len(),
            set.point_count(),
            set.landmarks.len()
        );
    }
    Ok(())
}

fn write_mesh(
    data: &io::MeshData,
    format: MeshFormat,
    output: &str,
    comment: &str,
    quiet: bool,
) -> Result<(), CliError> {
    let pd = data
        .point_data
        .as_ref()
        .map(|(n, v)| (n.as_str(), v.as_slice()));
    // Region labels (a wall's epicardium / endocardium / base) go wherever the format has room.
    let labels = data.regions.as_ref().map(|r| (r, r.for_writing()));
    let names: Vec<&str> = labels
        .as_ref()
        .map(|(_, (_, n))| n.iter().map(String::as_str).collect())
        .unwrap_or_default();
    let regions = labels.as_ref().map(|(r, (ids, _))| io::Regions {
        array: &r.array,
        ids,
        names: &names,
    });
    let stl = matches!(format, MeshFormat::StlBinary | MeshFormat::StlAscii);
    let out = io::write_mesh_with(
        &data.mesh,
        format,
        pd,
        regions.as_ref().filter(|_| !stl),
        comment,
    )
    .map_err(|e| CliError::Failed(format!("{output}: {e}")))?;
    files::write(output, &out)?;
    if stl && !names.is_empty() && !quiet {
        eprintln!(
            "heartmesh: warning: {output}: STL has no place for region labels; the input's {} \
             regions ({}) are left out (PLY, VTK, VTP and OBJ keep them)",
            names.len(),
            names.join(", ")
        );
    }
    if !quiet {
        let regions = match names.len() {
            0 => String::new(),
            _ if stl => String::new(),
            n => format!(", {n} regions ({})", names.join(", ")),
        };
        outln!(
            "{output}: {} vertices, {} triangles{regions}",
            data.mesh.positions.len(),
            data.mesh.triangles.len()
        );
    }
    Ok(())
}

/// File name without its extension (the RT structure set label).
fn stem(path: &str) -> &str {
    let name = file_name(path);
    name.rsplit_once('.').map_or(name, |(s, _)| s)
}

/// The last path component, for headers (full paths may be private).
pub fn file_name(path: &str) -> &str {
    path.rsplit(['/', '\\']).next().unwrap_or(path)
}
