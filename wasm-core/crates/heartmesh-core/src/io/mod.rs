//! Reading contours and meshes, writing meshes: the file formats people bring (see issue 4).
//!
//! Every reader takes bytes (the core never touches the file system, so it runs in the browser
//! worker unchanged) and returns [`CoreError::Parse`] with a 1-based line on bad input; none may
//! panic. Format detection looks at the content first and the file extension second.

mod buffers;
mod builder;
pub mod csv;
mod csv_columns;
pub mod cvi42;
pub mod dicom_image;
mod dicom_read;
mod frame_choice;
mod frames;
pub mod gpfile;
pub mod gzip;
pub mod markups;
pub mod mat;
pub mod nifti;
pub mod obj;
mod pixel_contours;
pub mod ply;
mod read_regions;
pub mod rtstruct;
pub mod segment;
pub mod session;
pub mod slicer_scene;
#[cfg(test)]
mod smoke;
mod space_tag;
pub mod stl;
pub mod sunnybrook;
#[cfg(test)]
mod test_images;
mod text;
pub mod vtk;
pub mod vtp;
pub mod xyz;
pub mod zip;

pub use buffers::mesh_from_buffers;
pub use builder::{polyline_from_run, MAX_POINTS};
pub use frame_choice::FrameChoice;
pub use frames::COMMAND_LINE_FRAME_ADVICE;
pub use read_regions::{MeshRegions, RegionFacts};

use crate::contours::{ContourSet, CoordinateSystem};
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::TriMesh;

/// Largest vertex or triangle count accepted when reading a mesh.
pub const MAX_MESH_ELEMENTS: usize = 20_000_000;

/// A mesh read from a file, with the per-vertex scalar the file carried (if any).
#[derive(Debug, Clone, PartialEq)]
pub struct MeshData {
    pub mesh: TriMesh,
    /// (name, one value per vertex), e.g. ("distance", ...).
    pub point_data: Option<(String, Vec<f64>)>,
    /// A label per triangle when the file carried one (see [`MeshRegions`]; never from STL).
    pub regions: Option<MeshRegions>,
    /// The patient frame the file states (`SPACE=LPS` / `SPACE=RAS`, see [`tagged_comment`]);
    /// None when it states none.
    pub coordinate_system: Option<CoordinateSystem>,
}

/// Contour file formats the core reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContourFormat {
    /// Canonical CSV (`contour,x,y,z[,surface]`).
    Csv,
    /// biv-me / Cardiac Atlas Project guide points (`GPFile_*.txt`).
    GpFile,
    /// Whitespace XYZ text, blank lines between contours.
    Xyz,
    /// VTK legacy POLYDATA with LINES.
    VtkLines,
    /// VTK XML PolyData with Lines.
    VtpLines,
    /// MATLAB v5 MAT-file with a cell array of Nx3 matrices (SurFCo).
    Mat,
    /// Segment (Medviso) study: a MAT-file with a `setstruct` of image stacks.
    Segment,
    /// heartmesh session JSON.
    Session,
    /// DICOM RT Structure Set (ROI names as surfaces).
    Rtstruct,
    /// NIfTI-1 label map (segmentation), outlined slice by slice.
    Nifti,
    /// NRRD label map (3D Slicer `.nrrd` / `.seg.nrrd` segmentation), read as a NIfTI is.
    Nrrd,
    /// Circle cvi42 workspace (`.cvi42wsx`), read with the DICOM images it was drawn on.
    Cvi42,
    /// DICOM Segmentation object (SEG), read as a label map is.
    DicomSeg,
    /// Sunnybrook Cardiac Data contour files (`IM-0001-0048-icontour-manual.txt`), read with the
    /// DICOM images they were drawn on.
    Sunnybrook,
    /// 3D Slicer markups (`.mrk.json`): closed curves and curves, one file or a folder of them.
    SlicerMarkups,
}

impl ContourFormat {
    /// The patient frame every file of the format is in (None: the file's own, or unknown).
    /// DICOM's objects and what is drawn on DICOM images are in DICOM's LPS; biv-me's GPFiles
    /// are the Cardiac Atlas Project's DICOM patient coordinates. Label maps say it per file
    /// (their readers set it); CSV, XYZ, VTK lines, MAT-files and sessions do not say.
    pub fn coordinate_system(self) -> Option<CoordinateSystem> {
        match self {
            ContourFormat::GpFile
            | ContourFormat::Segment
            | ContourFormat::Rtstruct
            | ContourFormat::Cvi42
            | ContourFormat::DicomSeg
            | ContourFormat::Sunnybrook => Some(CoordinateSystem::Lps),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            ContourFormat::Csv => "CSV",
            ContourFormat::GpFile => "biv-me GPFile",
            ContourFormat::Xyz => "XYZ text",
            ContourFormat::VtkLines => "VTK legacy lines",
            ContourFormat::VtpLines => "VTP lines",
            ContourFormat::Mat => "MATLAB MAT-file",
            ContourFormat::Segment => "Segment study",
            ContourFormat::Session => "heartmesh session",
            ContourFormat::Rtstruct => "DICOM RTSTRUCT",
            ContourFormat::Nifti => "NIfTI label map",
            ContourFormat::Nrrd => "NRRD label map",
            ContourFormat::Cvi42 => "cvi42 workspace",
            ContourFormat::DicomSeg => "DICOM SEG",
            ContourFormat::Sunnybrook => "Sunnybrook contours",
            ContourFormat::SlicerMarkups => "Slicer markups",
        }
    }
}

/// Extra inputs some formats use.
#[derive(Debug, Clone, Default)]
pub struct ContourOptions<'a> {
    /// Time frame to read from a GPFile or a CSV with a frame column, by its label (`9`, `ES`;
    /// default: each slice's or contour's first frame); the set's `time_frames` lists the others.
    pub frame: Option<FrameChoice>,
    /// Bytes of the `SliceInfoFile.txt` that accompanies a GPFile (adds off-plane warnings);
    /// decoded as the contour files are (UTF-16, Windows-1252, any line ends).
    pub slice_info: Option<&'a [u8]>,
    /// Long-axis label maps (`(file name, bytes)`) read with a NIfTI short-axis stack
    /// ([`nifti::read_nifti_study`]), or the DICOM images a cvi42 workspace was drawn on
    /// ([`cvi42::read_cvi42`]; headers are enough); refused beside any other format.
    pub views: &'a [(&'a str, &'a [u8])],
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

/// Whether a reader warning is its account of what it read (a label map's "label map read as
/// ...", a workspace's "workspace read with ..."): information, which the app shows apart from
/// the warnings and the command line prints as a note.
pub fn is_reading_note(warning: &str) -> bool {
    nifti::is_reading_note(warning)
        || warning.starts_with(cvi42::NOTE)
        || warning.starts_with(sunnybrook::NOTE)
        || warning.starts_with(segment::NOTE)
        || warning.starts_with(segment::PHASES)
        || warning.starts_with(segment::MATCHED)
        || warning.starts_with(markups::POINT_CONTOURS)
}

/// Guesses the contour format from the content, then from the extension.
pub fn detect_contour_format(file_name: &str, bytes: &[u8]) -> ContourFormat {
    let ext = extension(file_name);
    let head = &bytes[..bytes.len().min(4096)];
    let head = head.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(head);
    let starts = |magic: &[u8]| head.trim_ascii_start().starts_with(magic);
    if nifti::is_nifti(bytes) {
        return ContourFormat::Nifti;
    }
    if nifti::is_nrrd(bytes) {
        return ContourFormat::Nrrd;
    }
    if mat::is_mat(bytes) {
        if mat::has_variable(bytes, "setstruct") {
            return ContourFormat::Segment;
        }
        return ContourFormat::Mat;
    }
    if nifti::is_dicom_seg(bytes) {
        return ContourFormat::DicomSeg;
    }
    if rtstruct::is_dicom(bytes) {
        return ContourFormat::Rtstruct;
    }
    if cvi42::is_cvi42(head) {
        return ContourFormat::Cvi42;
    }
    if starts(b"# vtk DataFile") {
        return ContourFormat::VtkLines;
    }
    if starts(b"<?xml") || starts(b"<VTKFile") {
        return ContourFormat::VtpLines;
    }
    if markups::is_markups(head) {
        return ContourFormat::SlicerMarkups;
    }
    if session::looks_like_session(head) || (starts(b"{") && ext == "json") {
        return ContourFormat::Session;
    }
    // Sunnybrook's `x y` files say what they are by their names only.
    if sunnybrook::is_contour_file(file_name, bytes) {
        return ContourFormat::Sunnybrook;
    }
    // Text formats: judge by the first lines, decoded as the readers will (UTF-16 too).
    let text = text::head(bytes, 4096);
    if gpfile::looks_like_gpfile(&text) {
        return ContourFormat::GpFile;
    }
    if xyz::looks_like_xyz(&text) {
        return ContourFormat::Xyz;
    }
    match ext.as_str() {
        "mat" => ContourFormat::Mat,
        "vtk" => ContourFormat::VtkLines,
        "vtp" => ContourFormat::VtpLines,
        "json" => ContourFormat::Session,
        "xyz" => ContourFormat::Xyz,
        "dcm" | "dicom" => ContourFormat::Rtstruct,
        "nii" | "gz" => ContourFormat::Nifti,
        "nrrd" | "nhdr" => ContourFormat::Nrrd,
        "cvi42wsx" => ContourFormat::Cvi42,
        // CSV also reports the clearest errors for unknown text (header missing, ...).
        _ => ContourFormat::Csv,
    }
}

fn looks_like_mesh(file_name: &str, bytes: &[u8]) -> bool {
    let head = bytes.trim_ascii_start();
    matches!(extension(file_name).as_str(), "obj" | "stl" | "ply")
        || head.starts_with(b"ply\n")
        || head.starts_with(b"solid ")
        || head.starts_with(b"v ")
        || head.starts_with(b"o ")
        || head.starts_with(b"mtllib ")
}

fn looks_like_slice_info(bytes: &[u8]) -> bool {
    let head = text::head(bytes, 1024);
    head.contains("ImagePositionPatient") && head.contains("ImageOrientationPatient")
}

/// Reads contours from any supported format (detected from content and extension).
pub fn read_contours(file_name: &str, bytes: &[u8]) -> Result<ContourSet> {
    read_contours_with(file_name, bytes, &ContourOptions::default())
}

/// [`read_contours`] with format-specific options (GPFile frame and slice info).
pub fn read_contours_with(
    file_name: &str,
    bytes: &[u8],
    options: &ContourOptions,
) -> Result<ContourSet> {
    if slicer_scene::is_mrml(bytes) {
        return Err(slicer_scene::scene_file_alone());
    }
    if gzip::is_gzip(bytes) && !nifti::is_nifti(bytes) {
        // A compressed contour file (`contours.csv.gz`): read what it holds, once.
        let inner = gzip::inflate(bytes)?;
        if gzip::is_gzip(&inner) {
            return Err(CoreError::parse(
                0,
                "gzip inside gzip: decompress the file first",
            ));
        }
        let name = strip_gz(file_name);
        return read_contours_with(name, &inner, options);
    }
    let format = detect_contour_format(file_name, bytes);
    let takes_views = matches!(
        format,
        ContourFormat::Nifti
            | ContourFormat::Nrrd
            | ContourFormat::DicomSeg
            | ContourFormat::Cvi42
            | ContourFormat::Sunnybrook
            | ContourFormat::SlicerMarkups
    );
    // A GPFile's companion is its SliceInfoFile (the app sends it as the views are sent).
    let slice_info_view = match (format, options.views) {
        (ContourFormat::GpFile, []) => None,
        (ContourFormat::GpFile, [view]) if looks_like_slice_info(view.1) => Some(*view),
        (ContourFormat::GpFile, _) => {
            return Err(CoreError::parse(
                0,
                "a GPFile is read with one SliceInfoFile (its image planes) and no other file",
            ))
        }
        _ => None,
    };
    if !takes_views && slice_info_view.is_none() && !options.views.is_empty() {
        return Err(CoreError::parse(
            0,
            "long-axis label maps are read with a short-axis label map (NIfTI, NRRD or DICOM \
             SEG), not with contours of another format",
        ));
    }
    let mut set = match format {
        ContourFormat::Csv if looks_like_slice_info(bytes) => Err(CoreError::parse(
            1,
            "this is a biv-me SliceInfoFile (image planes), not contours; read the GPFile_*.txt beside it",
        )),
        ContourFormat::Csv if looks_like_mesh(file_name, bytes) => Err(CoreError::parse(
            0,
            "this is a mesh file (OBJ, STL or PLY), not contours",
        )),
        ContourFormat::Csv => csv::read_csv_frame(bytes, options.frame.as_ref()),
        ContourFormat::GpFile => {
            let mut set = gpfile::read_gpfile(&text::decode(bytes)?, options.frame.as_ref())?;
            let info = match (options.slice_info, slice_info_view) {
                (Some(info), _) => Some(("slice info file", info)),
                (None, view) => view,
            };
            if let Some((name, info)) = info {
                // Only a check of the contours (they carry their own coordinates): a damaged
                // companion is said, and the GPFile read without it.
                match text::decode(info).and_then(|t| gpfile::read_slice_info(&t)) {
                    Ok(slices) => gpfile::check_slices(&mut set, &slices),
                    Err(e) => set.warnings.push(format!(
                        "{name} not read ({}): the contours are not checked against their \
                         image planes",
                        e.to_string().trim_end_matches('.')
                    )),
                }
            }
            Ok(set)
        }
        ContourFormat::Xyz => xyz::read_xyz(bytes),
        ContourFormat::VtkLines => vtk::read_vtk_contours(bytes),
        ContourFormat::VtpLines => vtp::read_vtp_contours(bytes),
        ContourFormat::Mat | ContourFormat::Segment => {
            mat::read_mat_frame(bytes, options.frame.as_ref())
        }
        ContourFormat::Session => session::read_session(bytes).map(|s| s.contours),
        ContourFormat::Rtstruct => rtstruct::read_rtstruct(bytes),
        ContourFormat::Nifti => {
            nifti::read_nifti_study(bytes, options.views, options.frame.as_ref())
        }
        ContourFormat::Nrrd => {
            nifti::read_nrrd_study(bytes, options.views, options.frame.as_ref())
        }
        ContourFormat::DicomSeg => {
            nifti::read_dicom_seg_study(bytes, options.views, options.frame.as_ref())
        }
        ContourFormat::Cvi42 => cvi42::read_cvi42(bytes, options.views, options.frame.as_ref()),
        ContourFormat::Sunnybrook => sunnybrook::read_sunnybrook(
            file_name,
            bytes,
            options.views,
            options.frame.as_ref(),
        ),
        ContourFormat::SlicerMarkups => markups::read_markups(file_name, bytes, options.views),
    }?;
    if set.coordinate_system.is_none() {
        set.coordinate_system = format.coordinate_system();
    }
    Ok(set)
}

/// Several files read as one study: a short-axis label map (NIfTI, NRRD or DICOM SEG) and its
/// long-axis views (single-slice label maps of any of those formats), or a cvi42 workspace and the DICOM images it was drawn on, in any
/// order. Returns which file is the stack (the workspace), and the contours of all. One file is
/// read as [`read_contours_with`] reads it.
pub fn read_study(
    files: &[(&str, &[u8])],
    options: &ContourOptions,
) -> Result<(usize, ContourSet)> {
    let refuse = |m: String| CoreError::parse(0, m);
    match files {
        [] => return Err(refuse("no file given".into())),
        [(name, bytes)] => return read_contours_with(name, bytes, options).map(|s| (0, s)),
        _ => {}
    }
    let workspaces: Vec<usize> = (0..files.len())
        .filter(|&n| cvi42::is_cvi42(files[n].1))
        .collect();
    // Sunnybrook contour files: the first by name reads the others and the images.
    let sunnybrook = (0..files.len())
        .filter(|&n| sunnybrook::is_contour_file(files[n].0, files[n].1))
        .min_by_key(|&n| files[n].0);
    match (&workspaces[..], sunnybrook) {
        ([], Some(first)) => return read_with_companions(files, first, options),
        ([one], _) => return read_with_companions(files, *one, options),
        _ => {}
    }
    // A Slicer scene (its folder or .mrb bundle), or markups among other files: its markups or its
    // segmentations, the rest set aside and named.
    if let Some(scene) = slicer_scene::select(files)? {
        let chosen: Vec<(&str, &[u8])> = scene.read.iter().map(|&n| files[n]).collect();
        let (main, mut set) = read_study(&chosen, options)?;
        set.warnings.extend(scene.warning(files));
        return Ok((scene.read[main], set));
    }
    // A folder of Slicer markups (one node per file, as Slicer saves them): one set. An error
    // names its file itself, or is about the set (its folders), so none is put before it.
    if files
        .iter()
        .all(|(_, bytes)| markups::is_markups(&bytes[..bytes.len().min(4096)]))
    {
        let (first, rest) = (files[0], &files[1..]);
        return markups::read_markups(first.0, first.1, rest).map(|set| (0, set));
    }
    match workspaces[..] {
        [] | [_] => {}
        [a, b, ..] => {
            return Err(refuse(format!(
                "{} and {} are both cvi42 workspaces: open one at a time, with its images",
                files[a].0, files[b].0
            )))
        }
    }
    let mut stacks = Vec::new();
    for (n, (name, bytes)) in files.iter().enumerate() {
        let grid = nifti::label_map_grid(bytes).ok_or_else(|| {
            refuse(format!(
                "{name} is not a label map (NIfTI-1, NRRD or DICOM SEG): several files are read \
                 together only as one segmented study (a short-axis label map and its long-axis \
                 views), as a cvi42 workspace with its DICOM images or as Slicer markups files"
            ))
        })?;
        if grid.0.iter().all(|&d| d > 1) {
            stacks.push(n);
        }
    }
    let stack = match stacks[..] {
        [one] => one,
        [] => {
            return Err(refuse(
                "every file is a single slice: a segmented study needs its short-axis stack".into(),
            ))
        }
        [a, b, ..] => {
            return Err(refuse(format!(
                "{} and {} are both stacks: open one short-axis stack at a time, with its \
                 long-axis views",
                files[a].0, files[b].0
            )))
        }
    };
    read_with_companions(files, stack, options)
}

/// Reads `files[main]` with every other file as its companions ([`ContourOptions::views`]: a
/// label map's long-axis views, a workspace's images). An error that does not name a file
/// already gets the main file's name.
fn read_with_companions(
    files: &[(&str, &[u8])],
    main: usize,
    options: &ContourOptions,
) -> Result<(usize, ContourSet)> {
    let views: Vec<(&str, &[u8])> = files
        .iter()
        .enumerate()
        .filter(|(n, _)| *n != main)
        .map(|(_, f)| *f)
        .collect();
    let options = ContourOptions {
        views: &views,
        ..options.clone()
    };
    let (name, bytes) = files[main];
    read_contours_with(name, bytes, &options)
        .map(|s| (main, s))
        .map_err(|e| match e {
            CoreError::Parse { line, message }
                if !files.iter().any(|(f, _)| message.starts_with(f)) =>
            {
                CoreError::parse(line, format!("{name}: {message}"))
            }
            other => other,
        })
}

/// `name` without a final `.gz` (in any case).
fn strip_gz(name: &str) -> &str {
    let cut = name.len().saturating_sub(3);
    match name.get(cut..) {
        Some(ext) if ext.eq_ignore_ascii_case(".gz") => &name[..cut],
        _ => name,
    }
}

/// Reads a triangle mesh (format from the content, then the extension).
pub fn read_mesh(file_name: &str, bytes: &[u8]) -> Result<MeshData> {
    Ok(MeshData {
        coordinate_system: space_tag::of_mesh_file(bytes),
        ..read_mesh_data(file_name, bytes)?
    })
}

/// [`read_mesh`] without the frame.
fn read_mesh_data(file_name: &str, bytes: &[u8]) -> Result<MeshData> {
    let head = &bytes[..bytes.len().min(256)];
    let starts = |magic: &[u8]| head.trim_ascii_start().starts_with(magic);
    if head.starts_with(b"ply") {
        return ply::read_ply(bytes);
    }
    if starts(b"# vtk DataFile") {
        return vtk::read_vtk_mesh(bytes);
    }
    if starts(b"<?xml") || starts(b"<VTKFile") {
        return vtp::read_vtp_mesh(bytes);
    }
    match extension(file_name).as_str() {
        "stl" => stl::read_stl(bytes),
        "obj" => obj::read_obj(bytes),
        _ if starts(b"solid") || (bytes.len() >= 84 && bytes.len() % 50 == 34) => {
            stl::read_stl(bytes)
        }
        _ if starts(b"v ") || starts(b"#") || starts(b"o ") || starts(b"mtllib") => {
            obj::read_obj(bytes)
        }
        other => Err(CoreError::parse(
            0,
            format!("unrecognised mesh format {other:?} (expected obj, stl, ply, vtk or vtp)"),
        )),
    }
}

/// Named triangle groups of a mesh: `ids[t]` is triangle t's region, an index into `names`
/// (written as the integer `ids[t] + 1`, so 0 never names a region in files).
///
/// Simulation tools take boundary conditions from such labels (which triangles are the
/// endocardium, the epicardium, the base) and viewers colour by them. How each format carries
/// them is told at [`write_mesh_with`].
#[derive(Debug, Clone, Copy)]
pub struct Regions<'a> {
    /// Name of the cell-data array in PLY/VTK/VTP (e.g. "region").
    pub array: &'a str,
    /// One region per triangle, in the mesh's triangle order.
    pub ids: &'a [u32],
    /// One name per region, e.g. ["epicardium", "endocardium", "base"].
    pub names: &'a [&'a str],
}

impl Regions<'_> {
    /// The number written for triangle `t`: its id + 1. [`check_regions`] has made every id
    /// smaller than the number of names, itself below `i32::MAX`, so the sum fits an `i32` (the
    /// `int` of PLY and VTK); a triangle beyond `ids` (never, once checked) gets 0, "no region".
    pub(crate) fn value(&self, t: usize) -> i32 {
        self.ids
            .get(t)
            .and_then(|&id| i32::try_from(id).ok())
            .map_or(0, |id| id.saturating_add(1))
    }

    /// The name of triangle `t`'s region ("" beyond the checked range, which never happens).
    pub(crate) fn name_of(&self, t: usize) -> &str {
        self.ids
            .get(t)
            .and_then(|&id| self.names.get(id as usize))
            .copied()
            .unwrap_or("")
    }

    /// The name of the per-triangle string array that spells each triangle's region out
    /// (`region_name` for the array `region`), for VTK-based viewers.
    pub(crate) fn names_array(&self) -> String {
        format!("{}_name", self.array)
    }
}

/// Serialises a mesh; `point_data` is one scalar per vertex (written where the format allows:
/// PLY, VTK, VTP); `header_comment` goes into the file's header or comment lines. The same as
/// [`write_mesh_with`] without regions, byte for byte.
pub fn write_mesh(
    mesh: &TriMesh,
    format: MeshFormat,
    point_data: Option<(&str, &[f64])>,
    header_comment: &str,
) -> Result<Vec<u8>> {
    write_mesh_with(mesh, format, point_data, None, header_comment)
}

/// [`write_mesh`] with a region label per triangle, written as `id + 1` (see [`Regions`]):
///
/// - OBJ: a `g NAME` line before each run of consecutive triangles of one region (the triangle
///   order is kept, so a region may come back in several runs).
/// - PLY: a face property `int ARRAY` after `vertex_indices`, and one `comment ARRAY K NAME` line
///   per region in the header.
/// - VTK legacy: after the POINT_DATA block, `CELL_DATA` with `SCALARS ARRAY int 1` and a FIELD
///   string array `ARRAY_name` holding each triangle's region name.
/// - VTP: `<CellData Scalars="ARRAY">` (after `<PointData>`, as the VTK XML schema orders them)
///   with an Int32 array and the String array `ARRAY_name`.
/// - STL: the regions are dropped; the format has no place for them.
///
/// Errors ([`CoreError::Io`]) when `ids` is not one per triangle, an id names no region, or the
/// array or a region name is empty or holds whitespace or control characters (they would break
/// OBJ `g` lines and PLY/VTK tokens).
pub fn write_mesh_with(
    mesh: &TriMesh,
    format: MeshFormat,
    point_data: Option<(&str, &[f64])>,
    regions: Option<&Regions>,
    header_comment: &str,
) -> Result<Vec<u8>> {
    check_mesh(mesh, point_data)?;
    if let Some(r) = regions {
        check_regions(mesh, r)?;
    }
    Ok(match format {
        MeshFormat::Obj => obj::write_obj_with(mesh, regions, header_comment),
        MeshFormat::StlBinary => stl::write_stl_binary(mesh, header_comment),
        MeshFormat::StlAscii => stl::write_stl_ascii(mesh, header_comment),
        MeshFormat::Ply => ply::write_ply_with(mesh, point_data, regions, header_comment),
        MeshFormat::Vtk => vtk::write_vtk_with(mesh, point_data, regions, header_comment),
        MeshFormat::Vtp => vtp::write_vtp_with(mesh, point_data, regions, header_comment),
    })
}

/// Contours as polylines (one line cell per piece; rings repeat their first point so that they
/// read back closed) for VTK-based viewers: legacy VTK (`vtp == false`) or VTP. Each cell carries
/// its contour's identifier and surface as cell data, so that our readers give back the same
/// contours (pieces joined again by identifier). Landmarks are one-point vertex cells, their
/// points after the contours' and their cells first (VTK's cell data order is verts, lines),
/// labelled with their name and the surface [`vtk::LANDMARK_SURFACE`]: without them a converted
/// file would lose the apex and valves (`--lids apex`, the app's markers).
pub fn write_contour_lines(set: &ContourSet, vtp: bool, header_comment: &str) -> Vec<u8> {
    let mut points = Vec::with_capacity(set.point_count() + set.landmarks.len());
    let mut cells: Vec<Vec<u32>> = Vec::new();
    let mut labels: Vec<(&str, &str)> = set
        .landmarks
        .iter()
        .map(|(name, _)| (name.as_str(), vtk::LANDMARK_SURFACE))
        .collect();
    for (c, piece) in set
        .contours
        .iter()
        .flat_map(|c| c.pieces.iter().map(move |p| (c, p)))
    {
        labels.push((c.id.as_str(), c.surface.as_deref().unwrap_or("")));
        let start = points.len() as u32;
        points.extend_from_slice(&piece.points);
        let mut cell: Vec<u32> = (start..points.len() as u32).collect();
        if piece.closed && cell.len() >= 3 {
            cell.push(start);
        }
        cells.push(cell);
    }
    let first = points.len() as u32;
    let verts: Vec<u32> = (first..first + set.landmarks.len() as u32).collect();
    points.extend(set.landmarks.iter().map(|(_, p)| *p));
    if vtp {
        vtp::write_lines(&points, &verts, &cells, &labels, header_comment)
    } else {
        vtk::write_lines(&points, &verts, &cells, &labels, header_comment)
    }
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

/// Refuses regions that would make a broken or misleading file: not one id per triangle, an id
/// with no name, or a name that would split into several tokens (OBJ `g` lines, PLY comments
/// and VTK keywords are whitespace-separated).
fn check_regions(mesh: &TriMesh, regions: &Regions) -> Result<()> {
    let (ids, names) = (regions.ids, regions.names);
    if ids.len() != mesh.triangles.len() {
        return Err(CoreError::Io(format!(
            "regions {:?}: {} ids for {} triangles",
            regions.array,
            ids.len(),
            mesh.triangles.len()
        )));
    }
    if names.is_empty() || names.len() >= i32::MAX as usize {
        return Err(CoreError::Io(format!(
            "regions {:?}: {} names; between 1 and {} needed",
            regions.array,
            names.len(),
            i32::MAX - 1
        )));
    }
    if let Some((t, id)) = ids
        .iter()
        .enumerate()
        .find(|(_, &id)| id as usize >= names.len())
    {
        return Err(CoreError::Io(format!(
            "regions {:?}: triangle {t} has region {id}, but only {} names are given",
            regions.array,
            names.len()
        )));
    }
    check_token("region array name", regions.array)?;
    for name in names {
        check_token("region name", name)?;
    }
    Ok(())
}

/// A name written as one token: not empty, no whitespace or control characters.
fn check_token(what: &str, name: &str) -> Result<()> {
    if name.is_empty() || name.chars().any(|c| c.is_whitespace() || c.is_control()) {
        return Err(CoreError::Io(format!(
            "{what} {name:?} must be non-empty, without whitespace or control characters"
        )));
    }
    Ok(())
}

/// A header comment that starts with the patient frame's `SPACE=` line when it is known: every
/// writer puts its first lines where 3D Slicer reads the frame (the VTK title, the STL header,
/// PLY and OBJ comments; VTP field data, [`space_of_line`]).
pub fn tagged_comment(system: Option<CoordinateSystem>, comment: &str) -> String {
    match system {
        Some(s) => format!("{}\n{comment}", s.tag()),
        None => comment.to_string(),
    }
}

/// `LPS` or `RAS` of a header line that is a [`tagged_comment`]'s `SPACE=` line.
pub(crate) fn space_of_line(line: &str) -> Option<&'static str> {
    [CoordinateSystem::Lps, CoordinateSystem::Ras]
        .into_iter()
        .find(|s| line.trim() == s.tag())
        .map(CoordinateSystem::name)
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

/// A point's coordinates as `fmt_num` text joined by `sep`: one spelling of a point for every
/// text writer, so a mesh read back from any of them has the same bits.
pub(crate) fn fmt_point(p: &Vec3, sep: &str) -> String {
    format!("{}{sep}{}{sep}{}", fmt_num(p.x), fmt_num(p.y), fmt_num(p.z))
}

/// Points one per line, their coordinates separated by spaces: the ascii point block of both
/// VTK writers (legacy `POINTS`, XML `<Points>`), contours and meshes alike, so every VTK file
/// spells a point as the others do.
pub(crate) fn push_point_lines(out: &mut String, points: &[Vec3]) {
    for p in points {
        out.push_str(&format!("{}\n", fmt_point(p, " ")));
    }
}

/// Numbers one per line: the ascii point data of both VTK writers (as [`push_point_lines`]).
pub(crate) fn push_number_lines(out: &mut String, values: &[f64]) {
    for v in values {
        out.push_str(&fmt_num(*v));
        out.push('\n');
    }
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

/// Shortest text that reads back to the same f32 (STL and PLY-style single precision).
pub(crate) fn fmt_f32(v: f64) -> String {
    let f = v as f32;
    let a = f.abs();
    if a == 0.0 || (1e-5..1e15).contains(&a) {
        format!("{f}")
    } else {
        format!("{f:e}")
    }
}

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

/// Text safe inside an XML element or a quoted attribute (VTP files, SVG drawings).
pub(crate) fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compressed_contour_files_are_read_as_what_they_hold() {
        use std::io::Write;
        let csv = sample("contours/surfco-example.csv");
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        gz.write_all(&csv).unwrap();
        let gz = gz.finish().unwrap();
        let plain = read_contours("surfco.csv", &csv).unwrap();
        assert_eq!(read_contours("surfco.csv.gz", &gz).unwrap(), plain);
        assert_eq!(read_contours("SURFCO.CSV.GZ", &gz).unwrap(), plain);
        let mut twice = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        twice.write_all(&gz).unwrap();
        let e = read_contours("x.gz.gz", &twice.finish().unwrap()).unwrap_err();
        assert!(e.to_string().contains("gzip inside gzip"), "{e}");
    }

    #[test]
    fn extensions() {
        assert_eq!(MeshFormat::from_path("a/b.OBJ"), Some(MeshFormat::Obj));
        assert_eq!(MeshFormat::from_path("x.stl"), Some(MeshFormat::StlBinary));
        assert_eq!(MeshFormat::from_path(".vtp"), None);
        assert_eq!(MeshFormat::from_path("mesh"), None);
    }

    /// A closed octahedron with awkward coordinates (not exactly representable in f32).
    fn sample_mesh() -> TriMesh {
        crate::mesh::shapes::octahedron(37.123456789, crate::geometry::v3(-101.3, 0.1, 0.0))
    }

    /// Corner coordinates of every triangle, in f32: what survives any format.
    fn corners_f32(m: &TriMesh) -> Vec<[[f32; 3]; 3]> {
        (0..m.triangles.len())
            .map(|t| m.corners(t).map(|c| [c.x as f32, c.y as f32, c.z as f32]))
            .collect()
    }

    #[test]
    fn every_writer_round_trips() {
        let m = sample_mesh();
        assert!(m.signed_volume() > 0.0);
        let dist: Vec<f64> = (0..6).map(|i| 0.25 * i as f64).collect();
        let cases = [
            (MeshFormat::Obj, "m.obj", false),
            (MeshFormat::StlBinary, "m.stl", false),
            (MeshFormat::StlAscii, "m.stl", false),
            (MeshFormat::Ply, "m.ply", true),
            (MeshFormat::Vtk, "m.vtk", true),
            (MeshFormat::Vtp, "m.vtp", true),
        ];
        for (fmt, name, has_data) in cases {
            let bytes =
                write_mesh(&m, fmt, Some(("distance", &dist)), "test run\nsecond line").unwrap();
            let back = read_mesh(name, &bytes).unwrap_or_else(|e| panic!("{fmt:?}: {e}"));
            assert_eq!(back.mesh.positions.len(), 6, "{fmt:?}");
            assert_eq!(back.mesh.triangles.len(), 8, "{fmt:?}");
            assert_eq!(corners_f32(&back.mesh), corners_f32(&m), "{fmt:?}");
            let vol = back.mesh.signed_volume();
            assert!((vol - m.signed_volume()).abs() < 1e-3, "{fmt:?}: {vol}");
            if has_data {
                let (n, v) = back.point_data.clone().unwrap();
                assert_eq!(n, "distance", "{fmt:?}");
                assert_eq!(v, dist, "{fmt:?}");
            }
            // The writers that keep vertex order give back the very same vertex list.
            if !matches!(fmt, MeshFormat::StlBinary | MeshFormat::StlAscii) {
                assert_eq!(back.mesh.triangles, m.triangles, "{fmt:?}");
            }
        }
    }

    #[test]
    fn headers_carry_version_and_comment() {
        let m = sample_mesh();
        let obj = write_mesh(&m, MeshFormat::Obj, None, "from x.csv").unwrap();
        let text = String::from_utf8(obj).unwrap();
        assert!(text.starts_with(&format!("# heartmesh {}\n# from x.csv\n", crate::VERSION)));
        let stl = write_mesh(&m, MeshFormat::StlBinary, None, "from x.csv").unwrap();
        assert_eq!(stl.len(), 84 + 50 * 8);
        assert!(stl.starts_with(b"heartmesh "));
        assert!(write_mesh(&m, MeshFormat::Ply, Some(("d", &[1.0])), "").is_err());
    }

    #[test]
    fn contour_lines_round_trip() {
        let rel = "contours/bivme-example-patient1/patient1-ED.csv";
        let set = read_contours(rel, &sample(rel)).unwrap();
        let pieces: Vec<_> = set.contours.iter().flat_map(|c| c.pieces.iter()).collect();
        assert!(
            pieces.len() > set.contours.len(),
            "some contours have several pieces"
        );
        for (vtp, name) in [(false, "c.vtk"), (true, "c.vtp")] {
            let bytes = write_contour_lines(&set, vtp, "patient1 ED");
            let back = read_contours(name, &bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
            // Lossless: same identifiers, surfaces, pieces, points and ring/open status.
            assert_eq!(back.contours.len(), 40, "{name}");
            assert_eq!(back.surfaces(), set.surfaces(), "{name}");
            for (b, c) in back.contours.iter().zip(&set.contours) {
                assert_eq!(b.id, c.id, "{name}");
                assert_eq!(b.surface, c.surface, "{name} {}", c.id);
                assert_eq!(b.pieces, c.pieces, "{name} {}", c.id);
            }
            // Without the labels (files from other tools) every cell is a contour of its own.
            let text = String::from_utf8(bytes).unwrap();
            let cut = text
                .find(if vtp { "<CellData>" } else { "CELL_DATA" })
                .unwrap();
            let bare = if vtp {
                format!("{}</Piece>\n</PolyData>\n</VTKFile>\n", &text[..cut])
            } else {
                text[..cut].to_string()
            };
            let back = read_contours(name, bare.as_bytes()).unwrap();
            assert_eq!(back.contours.len(), pieces.len(), "{name}");
            assert_eq!(back.contours[0].id, "line1");
            for (c, p) in back.contours.iter().zip(&pieces) {
                assert_eq!(c.pieces.len(), 1);
                assert_eq!(c.pieces[0].closed, p.closed, "{name} {}", c.id);
                assert_eq!(c.pieces[0].points, p.points, "{name} {}", c.id);
            }
        }
        // Awkward identifiers survive: spaces, percent signs, non-ASCII, no surface.
        let mut odd = set.clone();
        odd.contours[0].id = "slice 3 % endo µ".into();
        odd.contours[1].surface = None;
        for (vtp, name) in [(false, "c.vtk"), (true, "c.vtp")] {
            let back = read_contours(name, &write_contour_lines(&odd, vtp, "")).unwrap();
            assert_eq!(back.contours[0].id, "slice 3 % endo µ", "{name}");
            assert_eq!(back.contours[1].surface, None, "{name}");
            assert_eq!(back.contours[2].surface, odd.contours[2].surface, "{name}");
        }
    }

    #[test]
    fn detection_by_content_then_extension() {
        let d = |name: &str, bytes: &[u8]| detect_contour_format(name, bytes);
        assert_eq!(d("a.txt", b"contour,x,y,z\n"), ContourFormat::Csv);
        assert_eq!(d("a", b"\xEF\xBB\xBFcontour;x;y;z\n"), ContourFormat::Csv);
        assert_eq!(
            d("GPFile_000.txt", b"x\ty\tz\tcontour type\n"),
            ContourFormat::GpFile
        );
        assert_eq!(
            d("a.csv", b"1 2 3 SAX_LV_EPICARDIAL 1 1.0 0\n"),
            ContourFormat::GpFile
        );
        assert_eq!(d("pts.txt", b"# c\n1 2 3\n"), ContourFormat::Xyz);
        assert_eq!(
            d("l.vtk", b"# vtk DataFile Version 3.0\n"),
            ContourFormat::VtkLines
        );
        assert_eq!(d("l", b"<?xml version=\"1.0\"?>"), ContourFormat::VtpLines);
        assert_eq!(
            d("s", b" {\"heartmesh_session\": 1}"),
            ContourFormat::Session
        );
        assert_eq!(d("x.mat", b"MATLAB 5.0 MAT-file"), ContourFormat::Mat);
        assert_eq!(d("x.bin", b"\x00\x01garbage"), ContourFormat::Csv);
        let e = read_contours("m.obj", b"v 1 2 3\n").unwrap_err();
        assert!(e.to_string().contains("mesh file"), "{e}");
    }

    /// Every sample in shared/data/contours through the detecting entry point. Expected points:
    /// the CSV data rows minus one for each ring that repeats its first point at the end (0 in
    /// patient1, 17 in each patient2 file, 6 in SurFCo), as counted independently with a script.
    #[test]
    fn samples_through_read_contours() {
        let cases = [
            ("contours/surfco-example.csv", 8, 3008),
            ("contours/surfco-example.mat", 8, 3008),
            ("contours/bivme-example-patient1/GPFile_000.txt", 40, 1791),
            ("contours/bivme-example-patient1/GPFile_009.txt", 35, 1204),
            ("contours/bivme-example-patient1/patient1-ED.csv", 40, 1791),
            ("contours/bivme-example-patient1/patient1-ES.csv", 35, 1204),
            ("contours/bivme-test-patient2/GPFile_000.txt", 28, 7466),
            ("contours/bivme-test-patient2/GPFile_012.txt", 24, 5562),
            ("contours/bivme-test-patient2/patient2-ED.csv", 28, 7466),
            ("contours/bivme-test-patient2/patient2-ES.csv", 24, 5562),
        ];
        for (rel, contours, points) in cases {
            let set = read_contours(rel, &sample(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"));
            assert_eq!(
                (set.contours.len(), set.point_count()),
                (contours, points),
                "{rel}"
            );
        }
    }

    #[test]
    fn numbers_round_trip() {
        for v in [0.0, -1.5, 1e-12, 123.456789012345, 3e20, -0.1] {
            assert_eq!(fmt_num(v).parse::<f64>().unwrap(), v);
        }
    }
}
