//! `heartmesh segment --lv-endo A.obj [--lv-epi B.obj] [--rv C.obj] -o SEG.nii.gz`: paint reference
//! surfaces on a short-axis stack as a segmentation network would deliver them (a NIfTI label map,
//! ACDC numbering), to test the label-map path (`heartmesh reconstruct SEG.nii.gz`) against a
//! known truth.

use heartmesh_core::io::nifti;
use heartmesh_core::metrics::function;
use heartmesh_core::sim::cavity::rv_cavity;
use heartmesh_core::sim::experiment_design::RV_JOIN_GAP_MM;
use heartmesh_core::sim::planes::anatomical_axis;
use heartmesh_core::sim::planes::{simulate, AcquisitionSpec, PAPER_LAX_ANGLES_DEG};
use heartmesh_core::sim::segmentation::{segment, segment_view, SegmentationSpec, Structure};

use crate::args::{parse, Spec};
use crate::cmd_convert::file_name;
use crate::cmd_simulate::read_surface;
use crate::error::CliError;
use crate::files;

pub const USAGE: &str = "heartmesh segment --lv-endo LV_ENDO.obj [--lv-epi LV_EPI.obj]
    [--rv RV.obj | --rv-free-wall RV_FREE_WALL.obj] -o SEG.nii.gz [--pixel MM] [--slice-spacing MM]
    [--join-gap MM] [--lax N] [--quiet]
  Writes a NIfTI-1 label map (.nii, or gzip-compressed .nii.gz; or NRRD, .nrrd / .seg.nrrd as
  3D Slicer saves segmentations, gzip-encoded, space LPS, segments named) of the surfaces on a short-axis
  stack planned on the LV endocardium's long axis: 3 LV cavity, 2 myocardium (inside LV_EPI, outside
  the cavity), 1 RV cavity (ACDC / M&Ms numbering), 0 background. Pixels 1.25 mm and slices 10 mm
  apart by default, world coordinates in mm as the surfaces give them (the sform). Sections whose
  pieces end within --join-gap (3 mm) are joined. --rv-free-wall takes an RV given as its free wall
  only (open, as CardioMesh models are) and closes it against --lv-epi's septum (pieces joined
  across 6 mm unless --join-gap says otherwise). --lax N (1-3) also writes N long-axis views
  through the apex, each a single-slice label map (same numbering, 1.25 mm pixels, 8 mm thick)
  beside SEG in its format: SEG_lax1.nii.gz ... (read them with the stack: heartmesh reconstruct
  SEG.nii.gz SEG_lax1.nii.gz ...).";

/// Thickness of a written long-axis view (mm): a typical cine long-axis slice.
const VIEW_THICKNESS_MM: f64 = 8.0;

/// How far from the free wall the septum is looked for when closing an RV cavity (mm), as the
/// accuracy tests build the spasm subject's.
const RV_CAVITY_RAY_MM: f64 = 40.0;

pub fn run(args: &[String]) -> Result<(), CliError> {
    let p = parse(
        args,
        &Spec {
            with_value: &[
                "output",
                "lv-endo",
                "lv-epi",
                "rv",
                "rv-free-wall",
                "pixel",
                "slice-spacing",
                "join-gap",
                "lax",
            ],
            switches: &["quiet"],
            aliases: &[("-o", "output"), ("-q", "quiet")],
        },
    )?;
    if let Some(extra) = p.positional.first() {
        return Err(CliError::usage(format!(
            "segment takes its surfaces as --lv-endo/--lv-epi/--rv, not {extra:?}"
        )));
    }
    let output = p
        .value("output")
        .ok_or_else(|| CliError::usage("segment needs -o SEG.nii.gz"))?;
    let lower = output.to_ascii_lowercase();
    let nrrd = lower.ends_with(".nrrd");
    let gzip = lower.ends_with(".gz");
    if !gzip && !nrrd && !lower.ends_with(".nii") {
        return Err(CliError::usage(format!(
            "segment writes NIfTI or NRRD: {output:?} should end in .nii, .nii.gz, .nrrd or \
             .seg.nrrd"
        )));
    }
    let endo_path = p
        .value("lv-endo")
        .ok_or_else(|| CliError::usage("segment needs --lv-endo (it plans the stack)"))?;
    files::check_output(output)?;
    let inputs: Vec<&str> = ["lv-endo", "lv-epi", "rv", "rv-free-wall"]
        .iter()
        .filter_map(|o| p.value(o))
        .collect();
    let lax_views = p.whole("lax")?.unwrap_or(0).min(3);
    let views_named: Vec<String> = (1..=lax_views as usize)
        .map(|n| view_path(output, n))
        .collect();
    let mut outputs = vec![("-o", output)];
    outputs.extend(views_named.iter().map(|v| ("--lax", v.as_str())));
    files::check_distinct(&inputs, &outputs)?;
    let mut spec = SegmentationSpec::default();
    if let Some(v) = p.number("pixel")? {
        spec.pixel_mm = v;
    }
    if let Some(v) = p.number("slice-spacing")? {
        spec.slice_mm = v;
    }
    let join_gap = p.number("join-gap")?;
    let join_gap_mm = join_gap.unwrap_or(3.0);
    let endo = read_surface(endo_path)?;
    let epi = p.value("lv-epi").map(read_surface).transpose()?;
    let rv = match (p.value("rv"), p.value("rv-free-wall"), &epi) {
        (Some(_), Some(_), _) => {
            return Err(CliError::usage(
                "give either --rv or --rv-free-wall, not both",
            ))
        }
        (Some(path), None, _) => Some(read_surface(path)?),
        (None, Some(path), Some(epi)) => Some(
            rv_cavity(&read_surface(path)?, epi, RV_CAVITY_RAY_MM)
                .map_err(|e| CliError::input(path, e))?,
        ),
        (None, Some(_), None) => {
            return Err(CliError::usage(
                "--rv-free-wall needs --lv-epi (the septum that closes the cavity)",
            ))
        }
        (None, None, _) => None,
    };
    let axis = anatomical_axis(&endo, join_gap_mm).map_err(|e| CliError::input(endo_path, e))?;
    // The first structure painted keeps a pixel. The LV cavity goes first, its wall (inside
    // LV_EPI) next, so the RV's outline, closed along the LV epicardium, keeps off the wall; but
    // a biventricular epicardium holds the RV cavity, which would then all be painted as wall:
    // there the RV goes before it.
    let rv_in_epi = match (&epi, &rv) {
        (Some(e), Some(r)) => function::share_inside(e, r) > 0.5,
        _ => false,
    };
    let mut structures = vec![Structure::new(3, &endo)];
    let wall = epi.as_ref().map(|m| Structure::new(2, m));
    // A cavity closed from a free wall and the septum meets it across wider gaps.
    let composite = p.value("rv-free-wall").is_some();
    let cavity = rv.as_ref().map(|m| Structure {
        join_gap_mm: match (join_gap, composite) {
            (None, true) => RV_JOIN_GAP_MM,
            _ => join_gap_mm,
        },
        ..Structure::new(1, m)
    });
    if rv_in_epi {
        structures.extend(cavity);
        structures.extend(wall);
    } else {
        structures.extend(wall);
        structures.extend(cavity);
    }
    for s in structures.iter_mut().filter(|s| s.label != 1) {
        s.join_gap_mm = join_gap_mm;
    }
    let volume = segment(&structures, &axis, &spec).map_err(CliError::param)?;
    let lax = p.whole("lax")?.unwrap_or(0) as usize;
    if lax > PAPER_LAX_ANGLES_DEG.len() {
        return Err(CliError::usage(format!(
            "--lax {lax}: at most {} long-axis views",
            PAPER_LAX_ANGLES_DEG.len()
        )));
    }
    let mut views = Vec::new();
    if lax > 0 {
        let planes = simulate(
            &endo,
            &AcquisitionSpec {
                axis: Some(axis),
                lax_count: lax,
                ..AcquisitionSpec::default()
            },
        )
        .map_err(|e| CliError::input(endo_path, e))?
        .lax_planes;
        let view_spec = SegmentationSpec {
            slice_mm: VIEW_THICKNESS_MM,
            ..spec
        };
        for (n, plane) in planes.iter().enumerate() {
            let view = segment_view(
                &structures,
                plane.origin,
                plane.normal,
                axis.direction,
                &view_spec,
            )
            .map_err(CliError::param)?;
            views.push((view_path(output, n + 1), view));
        }
    }
    // The views in the stack's format: a NRRD's world is LPS and a NIfTI's RAS, and the same
    // coordinates are written to both, so a view must say what its stack says.
    let encode = |map: &nifti::LabelVolume| {
        if nrrd {
            // 3D Slicer's segment names; its world is LPS, which the coordinates are taken to be.
            let names: Vec<(u16, String)> = [(3, "LV"), (2, "Myocardium"), (1, "RV")]
                .into_iter()
                .filter(|(l, _)| map.labels.contains(l))
                .map(|(l, n)| (l, n.to_string()))
                .collect();
            nifti::write_nrrd(map, true, "left-posterior-superior", &names)
        } else {
            nifti::write_nifti(map, gzip)
        }
    };
    files::write(output, &encode(&volume))?;
    for (path, view) in &views {
        files::write(path, &encode(view))?;
    }
    if !p.switch("quiet") {
        let count = |l: u16| volume.labels.iter().filter(|&&x| x == l).count();
        outln!(
            "{output}: {} x {} x {} voxels ({:.2} x {:.2} mm pixels, {:.1} mm slices) from {}; \
             labelled voxels: LV {} myocardium {} RV {}",
            volume.dims[0],
            volume.dims[1],
            volume.dims[2],
            spec.pixel_mm,
            spec.pixel_mm,
            spec.slice_mm,
            file_name(endo_path),
            count(3),
            count(2),
            count(1)
        );
    }
    for (path, view) in &views {
        if !p.switch("quiet") {
            outln!(
                "{path}: long-axis view, {} x {} pixels",
                view.dims[0],
                view.dims[1]
            );
        }
    }
    Ok(())
}

/// `SEG.nii.gz` -> `SEG_lax1.nii.gz` (`.nii`, `.seg.nrrd`, `.nrrd` likewise).
fn view_path(output: &str, n: usize) -> String {
    let lower = output.to_ascii_lowercase();
    let cut = [".nii.gz", ".seg.nrrd", ".nrrd", ".nii"]
        .into_iter()
        .find(|e| lower.ends_with(e))
        .map_or(0, str::len);
    let (stem, ext) = output.split_at(output.len() - cut);
    format!("{stem}_lax{n}{ext}")
}
