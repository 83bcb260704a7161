//! NIfTI-1 label maps (`.nii`, `.nii.gz`): segmentations of a short-axis stack, the form most
//! cardiac contours take today (ACDC, M&Ms, UK Biobank, nnU-Net and every network trained on
//! them write them), read as contours.
//!
//! Each structure is outlined slice by slice ([`trace`]) and placed in millimetres with the
//! header's sform (else its qform, else the spacings alone): NIfTI's world coordinates, RAS+ (+x
//! towards the patient's right, +y anterior, +z superior; DICOM and biv-me files are LPS+, their x
//! and y negated). Coordinates are kept as the file gives them, so a mesh made from a label map
//! lies on it in the same world (a viewer that reads mesh files as LPS shows it mirrored).
//!
//! Surfaces: the LV cavity's outline is `LV_ENDO`, the outline of cavity and myocardium together
//! `LV_EPI`, the RV cavity's `RV_ENDO` (roles found from how the labels touch, [`roles`]); any
//! other label `LABEL_<n>`. A 4D file is a cine sequence: each time frame holding labels is a
//! frame of the file, read one at a time as the other readers do.

mod roles;
mod trace;
mod volume;
mod write;

pub use volume::{LabelVolume, MAX_LABELS};
pub use write::write_nifti;

use crate::contours::{ContourSet, TimeFrames};
use crate::error::Result;
use crate::io::builder::ContourBuilder;
use crate::io::gzip::{inflate, inflate_head, is_gzip};
use crate::io::FrameChoice;
use roles::{find_roles, Roles};
use trace::{plan, trace, SlicePlan};
use volume::{err, magic, read_label_frame, Magic};

/// Whether `bytes` is a NIfTI file (plain or gzip), of any version (the reader names what it
/// cannot read rather than the file falling through to the CSV reader).
pub fn is_nifti(bytes: &[u8]) -> bool {
    if is_gzip(bytes) {
        return magic(&inflate_head(bytes, 348)).is_some();
    }
    magic(bytes).is_some_and(|m| m != Magic::Pair || bytes.len() == 348)
}

/// Reads the contours of a NIfTI label map: one surface per structure, one curve per slice (a
/// second loop in a slice is a contour of its own, which the core's checks then judge).
pub fn read_nifti(bytes: &[u8], frame: Option<&FrameChoice>) -> Result<ContourSet> {
    let data = inflate(bytes)?;
    let volume = read_label_frame(&data, frame)?;
    let labelled = &volume.labelled;
    if labelled.is_empty() {
        return Err(err("the label map is empty: every voxel is 0 (background)"));
    }
    let t = volume.frame;
    let first = labelled[0];
    if !labelled.contains(&t) {
        return Err(err(format!(
            "frame {t} of the label map holds no labels (frames with labels: {})",
            list(labelled)
        )));
    }
    let plan = plan(&volume);
    let roles = find_roles(&volume.labels, volume.dims, plan.axis);
    let mut b = ContourBuilder::new();
    let mut specks = 0;
    for (surface, labels) in surfaces(&roles) {
        let (loops, left) = trace(&volume, &labels, &plan);
        specks += left;
        let mut seen_slice = None;
        let mut nth = 0;
        for l in loops {
            nth = if seen_slice == Some(l.slice) {
                nth + 1
            } else {
                1
            };
            seen_slice = Some(l.slice);
            let id = match nth {
                1 => format!("slice {}", l.slice),
                n => format!("slice {} ({n})", l.slice),
            };
            b.push_piece(&id, Some(&surface), l.points, Some(true), 0)?;
        }
    }
    b.warn(describe(&volume, &roles, &plan));
    if specks > 0 {
        let (n, what) = match specks {
            1 => ("1 speck".to_string(), "a stray voxel or two"),
            n => (format!("{n} specks"), "stray voxels"),
        };
        b.warn(format!(
            "{n} of fewer than {} pixels ({what} of a label) left out",
            trace::MIN_LOOP_PIXELS
        ));
    }
    if labelled.len() > 1 && frame.is_none() {
        b.warn(format!(
            "the label map holds {} labelled time frames ({}): frame {t} read; {} (e.g. --frame {})",
            labelled.len(),
            list(labelled),
            crate::io::COMMAND_LINE_FRAME_ADVICE,
            labelled.get(1).copied().unwrap_or(t)
        ));
    }
    let mut set = b
        .finish()
        .map_err(|_| err(format!("no structure in frame {t} outlines as a curve")))?;
    if volume.frames > 1 {
        let names: Vec<String> = labelled.iter().map(usize::to_string).collect();
        set.time_frames = Some(TimeFrames {
            count: names.len(),
            frames: names,
            read: vec![t.to_string()],
            firsts: vec![first.to_string()],
            chosen: frame.is_some(),
            left_out: 0,
            sequence: labelled.len() > 1,
        });
    }
    Ok(set)
}

/// Surfaces to trace and the labels inside each.
fn surfaces(roles: &Roles) -> Vec<(String, Vec<u16>)> {
    let mut out = Vec::new();
    if let Some(lv) = roles.lv {
        out.push(("LV_ENDO".to_string(), vec![lv]));
        if let Some(myo) = roles.myo {
            out.push(("LV_EPI".to_string(), vec![lv, myo]));
        }
    }
    if let Some(rv) = roles.rv {
        out.push(("RV_ENDO".to_string(), vec![rv]));
    }
    out.extend(
        roles
            .others
            .iter()
            .map(|&l| (format!("LABEL_{l}"), vec![l])),
    );
    out
}

/// The reading, in one line: which label became which surface, how the slices were taken.
fn describe(volume: &LabelVolume, roles: &Roles, plan: &SlicePlan) -> String {
    let mut parts = Vec::new();
    if let (Some(lv), Some(myo)) = (roles.lv, roles.myo) {
        parts.push(format!(
            "{lv} LV cavity (LV_ENDO), {myo} myocardium (LV_EPI around both)"
        ));
    }
    if let Some(rv) = roles.rv {
        parts.push(format!("{rv} RV cavity (RV_ENDO)"));
    }
    if !roles.others.is_empty() {
        let names: Vec<String> = roles.others.iter().map(|l| format!("LABEL_{l}")).collect();
        let why = if roles.lv.is_none() {
            " (no label is ringed by another as an LV cavity by its myocardium)"
        } else {
            ""
        };
        parts.push(format!("{}{why}", names.join(", ")));
    }
    let s = volume.spacing();
    let axis = ["i", "j", "k"][plan.axis];
    let every = match plan.step {
        1 => String::new(),
        n => format!(", every {n}th slice"),
    };
    format!(
        "label map read as {}; traced across the {axis} axis{every}, {:.1} mm apart, \
         {:.2} x {:.2} mm pixels; coordinates from the header's {}",
        parts.join(", "),
        plan.spacing_mm,
        s[(plan.axis + 1) % 3],
        s[(plan.axis + 2) % 3],
        volume.placement
    )
}

fn list(values: &[usize]) -> String {
    let shown: Vec<String> = values.iter().take(8).map(usize::to_string).collect();
    let more = if values.len() > 8 { ", ..." } else { "" };
    format!("{}{more}", shown.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;
    use roles::tests::heart_slice;
    use volume::tests::nifti_bytes;

    /// A stack of `slices` identical heart slices (40 x 40 pixels of 1.5 mm, 10 mm apart), ACDC
    /// numbering.
    fn stack(slices: u16, frames: u16) -> Vec<u8> {
        let slice: Vec<u8> = heart_slice(40, 3, 2, 1).iter().map(|&l| l as u8).collect();
        let voxels = slice.repeat(usize::from(slices * frames));
        let dims: Vec<u16> = if frames > 1 {
            vec![40, 40, slices, frames]
        } else {
            vec![40, 40, slices]
        };
        nifti_bytes(&dims, None, &voxels)
    }

    #[test]
    fn a_segmented_stack_gives_three_surfaces() {
        let set = read_nifti(&stack(6, 1), None).unwrap();
        assert_eq!(set.surfaces(), ["LV_ENDO", "LV_EPI", "RV_ENDO"]);
        assert_eq!(set.contours.len(), 18);
        assert!(set.time_frames.is_none());
        assert!(
            set.warnings[0].contains("3 LV cavity"),
            "{:?}",
            set.warnings
        );
        // LV_ENDO of slice 2: a circle of radius 0.3 * 20 pixels * 1.5 mm = 9 mm about the
        // image centre, 20 mm up.
        let c = set
            .contours
            .iter()
            .find(|c| c.surface.as_deref() == Some("LV_ENDO") && c.id.starts_with("slice 2"))
            .unwrap();
        let centre = c
            .points()
            .fold(crate::geometry::Vec3::zeros(), |a, p| a + p)
            / c.point_count() as f64;
        for p in c.points() {
            let r = ((p.x - centre.x).powi(2) + (p.y - centre.y).powi(2)).sqrt();
            assert!((r - 9.0).abs() < 1.0, "radius {r}");
            assert!((p.z - 20.0).abs() < 1e-9);
        }
        assert!(c.pieces[0].closed);
    }

    #[test]
    fn frames_of_a_cine_label_map() {
        let bytes = stack(4, 3);
        let set = read_nifti(&bytes, None).unwrap();
        let t = set.time_frames.clone().unwrap();
        assert_eq!(
            (t.frames.len(), t.read.clone(), t.sequence),
            (3, vec!["0".to_string()], true)
        );
        assert!(set.warnings.iter().any(|w| w.contains("--frame 1")));
        let two = read_nifti(&bytes, FrameChoice::new("2").as_ref()).unwrap();
        assert_eq!(two.time_frames.unwrap().read, ["2"]);
        let e = read_nifti(&bytes, FrameChoice::new("7").as_ref()).unwrap_err();
        assert!(e.to_string().contains("no frame 7"), "{e}");
        // A cine whose frame 0 a network left empty.
        let mut gap = bytes.clone();
        let frame = 40 * 40 * 4;
        gap[352..352 + frame].fill(0);
        let set = read_nifti(&gap, None).unwrap();
        assert_eq!(set.time_frames.unwrap().frames, ["1", "2"]);
        let e = read_nifti(&gap, FrameChoice::new("0").as_ref()).unwrap_err();
        assert!(
            e.to_string()
                .contains("frame 0 of the label map holds no labels (frames with labels: 1, 2)"),
            "{e}"
        );
    }

    #[test]
    fn empty_and_foreign_files() {
        let empty = nifti_bytes(&[4, 4, 2], None, &[0; 32]);
        assert!(read_nifti(&empty, None)
            .unwrap_err()
            .to_string()
            .contains("empty"));
        assert!(is_nifti(&empty));
        assert!(!is_nifti(b"contour,x,y,z\n"));
        assert!(!is_nifti(&[0x1f, 0x8b, 0, 0]));
        let mut pair = empty.clone();
        pair[344..348].copy_from_slice(b"ni1\0");
        assert!(
            !is_nifti(&pair),
            "a .hdr carries no voxels after its header"
        );
        assert!(is_nifti(&pair[..348]));
    }
}
