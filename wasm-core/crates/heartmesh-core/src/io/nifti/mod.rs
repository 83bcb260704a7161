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

mod nrrd;
mod roles;
mod seg;
mod trace;
mod views;
mod volume;
mod write;

pub use nrrd::{is_nrrd, write_nrrd};
pub use volume::{LabelVolume, MAX_LABELS};
pub use write::write_nifti;

use crate::contours::{ContourSet, TimeFrames};
use crate::error::Result;
use crate::io::builder::ContourBuilder;
use crate::io::gzip::{inflate, inflate_head, is_gzip};
use crate::io::FrameChoice;
use roles::{find_roles, Roles};
use trace::{plan, trace, SlicePlan};
use volume::{err, magic, read_label_frame, Magic, Space};

/// Whether `bytes` is a NIfTI file (plain or gzip), of any version (the reader names what it
/// cannot read rather than the file falling through to the CSV reader).
pub fn is_nifti(bytes: &[u8]) -> bool {
    if is_gzip(bytes) {
        return magic(&inflate_head(bytes, 348)).is_some();
    }
    magic(bytes).is_some_and(|m| m != Magic::Pair || bytes.len() == 348)
}

/// Whether a reader warning is the label-map reader's account of what it read ("label map read
/// as ...", "long-axis view ... read as ..."): information, which the app shows apart from the
/// warnings.
pub fn is_reading_note(warning: &str) -> bool {
    warning.starts_with(NOTE_STACK)
        || (warning.starts_with(NOTE_VIEW) && warning.contains(" read as "))
}

const NOTE_STACK: &str = "label map read as ";
const NOTE_VIEW: &str = "long-axis view ";

/// Voxels along i, j, k and time frames of a label map of any format read (NIfTI-1 plain or gzip,
/// NRRD, DICOM SEG: its stack's) from its header alone; None when it is none. A study's files are
/// told apart by it: the short-axis stack, and the single-slice long-axis views read with it.
pub fn label_map_grid(bytes: &[u8]) -> Option<([usize; 3], usize)> {
    if is_gzip(bytes) {
        volume::grid(&inflate_head(bytes, 348))
    } else if is_nrrd(bytes) {
        nrrd::grid(bytes)
    } else if is_dicom_seg(bytes) {
        seg::grid(bytes)
    } else {
        volume::grid(bytes)
    }
}

/// Whether a file with a label map's header holds an image's intensities instead (a Slicer
/// scene keeps its scans beside its segmentations, in the same formats): told by reading it.
pub fn is_image(bytes: &[u8]) -> bool {
    read_label_maps(bytes, None).is_err_and(|e| e.to_string().contains(volume::IMAGE_NOT_LABELS))
}

/// The label maps of a file of any format read, at time frame `want`, in its own world
/// coordinates: one, or a SEG's stack and its planes of other orientations.
fn read_label_maps(bytes: &[u8], want: Option<&FrameChoice>) -> Result<Vec<LabelVolume>> {
    if is_nrrd(bytes) {
        nrrd::read_nrrd_volume(bytes, want).map(|(v, _)| vec![v])
    } else if is_dicom_seg(bytes) {
        seg::read_seg_volume(bytes, want)
            .map(|r| std::iter::once(r.volume).chain(r.views).collect())
    } else {
        read_label_frame(&inflate(bytes)?, want).map(|v| vec![v])
    }
}

/// Reads the contours of a NIfTI label map: one surface per structure, one curve per slice (a
/// second loop in a slice is a contour of its own, which the core's checks then judge).
pub fn read_nifti(bytes: &[u8], frame: Option<&FrameChoice>) -> Result<ContourSet> {
    read_nifti_study(bytes, &[], frame)
}

/// [`read_nifti`] of a short-axis stack with its long-axis views (`(file name, bytes)`, each a
/// single-slice label map in the same world): each view adds one curve per surface whose
/// structures it shows ([`views`]), so the apex and base are drawn rather than extrapolated.
pub fn read_nifti_study(
    bytes: &[u8],
    views: &[(&str, &[u8])],
    frame: Option<&FrameChoice>,
) -> Result<ContourSet> {
    let data = inflate(bytes)?;
    let volume = read_label_frame(&data, frame)?;
    read_volume_study(volume, &[], files_as_views(views), frame)
}

/// Long-axis view files, to read with a stack.
fn files_as_views<'a>(views: &[(&'a str, &'a [u8])]) -> Vec<View<'a>> {
    views
        .iter()
        .map(|&(name, bytes)| View::File(name, bytes))
        .collect()
}

/// Reads the contours of a NRRD label map (3D Slicer's `.nrrd` / `.seg.nrrd`, [`nrrd`]), as
/// [`read_nifti`] reads a NIfTI; a `.seg.nrrd`'s segment names are listed in its note.
pub fn read_nrrd(bytes: &[u8], frame: Option<&FrameChoice>) -> Result<ContourSet> {
    read_nrrd_study(bytes, &[], frame)
}

/// [`read_nrrd`] of a short-axis stack with its long-axis views, as [`read_nifti_study`].
pub fn read_nrrd_study(
    bytes: &[u8],
    views: &[(&str, &[u8])],
    frame: Option<&FrameChoice>,
) -> Result<ContourSet> {
    let (volume, names) = nrrd::read_nrrd_volume(bytes, frame)?;
    read_volume_study(volume, &names, files_as_views(views), frame)
}

/// Whether `bytes` is a DICOM Segmentation object ([`seg`]).
pub fn is_dicom_seg(bytes: &[u8]) -> bool {
    seg::is_seg(bytes)
}

/// Reads the contours of a DICOM Segmentation object ([`seg`]: OHIF's, 3D Slicer's DICOM export,
/// highdicom's), as [`read_nifti`] reads a NIfTI; its segment labels are listed in its note.
pub fn read_dicom_seg(bytes: &[u8], frame: Option<&FrameChoice>) -> Result<ContourSet> {
    read_dicom_seg_study(bytes, &[], frame)
}

/// [`read_dicom_seg`] of a short-axis stack with its long-axis views, as [`read_nifti_study`]:
/// views in other files, and single planes of another orientation in the SEG itself.
pub fn read_dicom_seg_study(
    bytes: &[u8],
    views: &[(&str, &[u8])],
    frame: Option<&FrameChoice>,
) -> Result<ContourSet> {
    let read = seg::read_seg_volume(bytes, frame)?;
    let planes = read
        .views
        .into_iter()
        .enumerate()
        .map(|(n, v)| View::Plane(n + 1, Box::new(v)));
    let views: Vec<View> = planes.chain(files_as_views(views)).collect();
    let mut set = read_volume_study(read.volume, &read.names, views, frame)?;
    if read.aside > 0 {
        set.warnings.push(format!(
            "{} of the DICOM SEG in another orientation or pixel spacing than the stack, and on \
             no single plane of their own, set aside: the stack is the orientation most frames \
             share",
            if read.aside == 1 {
                "1 frame".to_string()
            } else {
                format!("{} frames", read.aside)
            }
        ));
    }
    if read.overlaps > 0 {
        set.warnings.push(format!(
            "{} pixels belong to two segments: each kept in the first one's",
            read.overlaps
        ));
    }
    Ok(set)
}

/// The contours of a label map's volume (frame already chosen) with its long-axis views; `names`:
/// segment names by label, when the file gives them.
fn read_volume_study(
    volume: LabelVolume,
    names: &[(u16, String)],
    views: Vec<View>,
    frame: Option<&FrameChoice>,
) -> Result<ContourSet> {
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
    let surfaces = surfaces(&roles);
    let mut b = ContourBuilder::new();
    let mut specks = 0;
    for (surface, labels) in &surfaces {
        let (loops, left) = trace(&volume, labels, &plan);
        specks += left;
        push_loops(&mut b, surface, loops, |l| format!("slice {}", l.slice))?;
    }
    let mut reading = describe(&volume, &roles, &plan);
    if !names.is_empty() {
        let listed: Vec<String> = names
            .iter()
            .filter(|(l, _)| volume.labels.contains(l))
            .map(|(l, n)| format!("{l} {n}"))
            .collect();
        reading += &format!("; segments {}", listed.join(", "));
    }
    b.warn(reading);
    let mut view_notes = Vec::new();
    let empty = views.is_empty();
    let files: Vec<&str> = views
        .iter()
        .filter_map(|v| match v {
            View::File(name, _) => Some(*name),
            View::Plane(..) => None,
        })
        .collect();
    for (n, view) in in_reading_order(views) {
        let maps = match view {
            View::Plane(k, map) => {
                vec![(format!("{k} of the DICOM SEG"), format!("view {k}"), *map)]
            }
            View::File(name, bytes) => {
                let shown = name.rsplit(['/', '\\']).next().unwrap_or(name).to_string();
                let id = view_id(name, n, &files);
                let maps = view_file(&volume, name, bytes)?;
                // A SEG of several long-axis planes (a view per orientation): each a view.
                let many = maps.len() > 1;
                (maps.into_iter().enumerate())
                    .map(|(k, map)| match many {
                        true => (
                            format!("{shown} plane {}", k + 1),
                            format!("{id} plane {}", k + 1),
                            map,
                        ),
                        false => (shown.clone(), id.clone(), map),
                    })
                    .collect()
            }
        };
        for (shown, id, map) in maps {
            let (notes, left) = add_view(&mut b, &volume, &roles, &surfaces, &shown, &id, map)?;
            specks += left;
            view_notes.extend(notes);
        }
    }
    for note in view_notes {
        b.warn(note);
    }
    if empty && volume.dims[plan.axis] == 1 {
        b.warn(
            "the label map is a single slice (a long-axis view?): a surface needs a short-axis \
             stack; open the view together with its stack",
        );
    }
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
            end_diastole: None,
            end_systole: None,
        });
    }
    set.coordinate_system = volume.space.and_then(Space::coordinate_system);
    Ok(set)
}

/// Adds the loops of one surface, named `name(loop)`, a second loop of the same slice or view
/// with " (2)" and so on.
fn push_loops(
    b: &mut ContourBuilder,
    surface: &str,
    loops: Vec<trace::Loop>,
    name: impl Fn(&trace::Loop) -> String,
) -> Result<()> {
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
            1 => name(&l),
            n => format!("{} ({n})", name(&l)),
        };
        b.push_piece(&id, Some(surface), l.points, Some(true), 0)?;
    }
    Ok(())
}

/// A long-axis view to read with a stack.
enum View<'a> {
    /// A file: a single-slice label map of any format read ([`read_label_maps`]), `(name, bytes)`.
    File(&'a str, &'a [u8]),
    /// Plane `n` (from 1) of another orientation in the stack's own DICOM SEG, already read.
    Plane(usize, Box<LabelVolume>),
}

/// Views in the order they are read, each file with its index among the files: a SEG's own
/// planes in the file's order, then the files in name order (file names, not folders), so that
/// the same files give the same contours, and the same mesh, however they were listed.
fn in_reading_order(views: Vec<View>) -> Vec<(usize, View)> {
    let base = |name: &str| name.rsplit(['/', '\\']).next().unwrap_or(name).to_string();
    let mut files = 0;
    let mut out: Vec<(usize, View)> = views
        .into_iter()
        .map(|v| match v {
            View::File(..) => {
                files += 1;
                (files - 1, v)
            }
            plane => (0, plane),
        })
        .collect();
    out.sort_by_key(|(n, v)| match v {
        View::Plane(k, _) => (0, String::new(), *k),
        View::File(name, _) => (1, base(name), *n),
    });
    out
}

/// A long-axis view file's label maps (one; a SEG's: one per plane) at the stack's time frame (a
/// view of one frame goes with any frame of the stack), in the stack's world convention; errors
/// name the file.
fn view_file(stack: &LabelVolume, name: &str, bytes: &[u8]) -> Result<Vec<LabelVolume>> {
    let named = |e: crate::error::CoreError| match e {
        crate::error::CoreError::Parse { line, message } => {
            crate::error::CoreError::parse(line, format!("{name}: {message}"))
        }
        other => other,
    };
    let want = match label_map_grid(bytes) {
        Some((_, frames)) if frames > 1 => FrameChoice::new(&stack.frame.to_string()),
        _ => None,
    };
    let maps = read_label_maps(bytes, want.as_ref()).map_err(named)?;
    maps.into_iter()
        .map(|view| {
            views::single_slice_axis(&view, name)?;
            Ok(view.turned_into(stack.space))
        })
        .collect()
}

/// A view's contour name: its file name without `.nii`/`.nii.gz`/`.nrrd`/`.dcm` (and folders),
/// numbered when two views share one.
fn view_id(name: &str, n: usize, files: &[&str]) -> String {
    let stem = |name: &str| {
        let base = name.rsplit(['/', '\\']).next().unwrap_or(name);
        let lower = base.to_ascii_lowercase();
        let cut = [".nii.gz", ".nii", ".gz", ".seg.nrrd", ".nrrd", ".dcm"]
            .into_iter()
            .find(|e| lower.ends_with(e))
            .map_or(0, str::len);
        let s = &base[..base.len() - cut];
        if s.is_empty() {
            "view".to_string()
        } else {
            s.to_string()
        }
    };
    let own = stem(name);
    let same = files.iter().filter(|v| stem(v) == own).count();
    if same > 1 {
        format!("{own} #{}", n + 1)
    } else {
        own
    }
}

/// Traces one long-axis view into the surfaces of the stack whose structures it shows: a
/// surface gets the view's curve only when every stack label of it has a match (an LV_EPI curve
/// needs the cavity and the myocardium). Returns the note that says what matched (and a warning
/// when a still view is read with one frame of a cine stack), and specks.
fn add_view(
    b: &mut ContourBuilder,
    stack: &LabelVolume,
    roles: &Roles,
    surfaces: &[(String, Vec<u16>)],
    shown: &str,
    id: &str,
    view: LabelVolume,
) -> Result<(Vec<String>, usize)> {
    let axis = views::single_slice_axis(&view, shown)?;
    if !view.labelled.contains(&view.frame) {
        return Ok((
            vec![format!(
                "long-axis view {shown}: frame {} holds no labels; not used",
                view.frame
            )],
            0,
        ));
    }
    let matches = views::match_labels(stack, &view);
    let plan = SlicePlan {
        axis,
        step: 1,
        spacing_mm: view.spacing()[axis],
    };
    let mut specks = 0;
    let mut used = 0;
    for (surface, stack_labels) in surfaces {
        let mine: Vec<u16> = stack_labels
            .iter()
            .filter_map(|s| {
                matches
                    .iter()
                    .find(|m| m.stack_label == Some(*s))
                    .map(|m| m.view_label)
            })
            .collect();
        if mine.len() < stack_labels.len() {
            continue;
        }
        let (loops, left) = trace(&view, &mine, &plan);
        specks += left;
        used += usize::from(!loops.is_empty());
        push_loops(b, surface, loops, |_| id.to_string())?;
    }
    let role = |s: u16| match (roles.lv, roles.myo, roles.rv) {
        (Some(l), _, _) if l == s => "LV cavity".to_string(),
        (_, Some(m), _) if m == s => "myocardium".to_string(),
        (_, _, Some(r)) if r == s => "RV cavity".to_string(),
        _ => format!("LABEL_{s}"),
    };
    let found: Vec<String> = matches
        .iter()
        .filter_map(|m| {
            m.stack_label
                .map(|s| format!("{} {} ({:.0} %)", m.view_label, role(s), 100.0 * m.share))
        })
        .collect();
    let unmatched: Vec<String> = matches
        .iter()
        .filter(|m| m.stack_label.is_none())
        .map(|m| m.view_label.to_string())
        .collect();
    let mut note = if found.is_empty() {
        format!(
            "long-axis view {shown}: none of its labels lies on the stack's structures (is it of \
             this patient and time frame?); not used"
        )
    } else {
        format!(
            "{NOTE_VIEW}{shown} read as {} by where its pixels lie in the stack; {used} curve{} added",
            found.join(", "),
            if used == 1 { "" } else { "s" }
        )
    };
    if !found.is_empty() && !unmatched.is_empty() {
        note += &format!(
            "; label{} {} on none of the stack's structures (atria, vessels), left out",
            if unmatched.len() == 1 { "" } else { "s" },
            unmatched.join(", ")
        );
    }
    let mut said = vec![note];
    if used > 0 && view.frames == 1 && stack.labelled.len() > 1 {
        said.push(format!(
            "{shown} holds one time frame, read with frame {} of the cine stack: make sure it \
             shows the same phase",
            stack.frame
        ));
    }
    Ok((said, specks))
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
    match (roles.lv, roles.myo) {
        (Some(lv), Some(myo)) if roles.biventricular => parts.push(format!(
            "{lv} LV cavity (LV_ENDO), {myo} myocardium of both ventricles (LV_EPI around \
             cavities and myocardium: the biventricular epicardium)"
        )),
        (Some(lv), Some(myo)) => parts.push(format!(
            "{lv} LV cavity (LV_ENDO), {myo} myocardium (LV_EPI around both)"
        )),
        _ => {}
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
        "{NOTE_STACK}{}; traced across the {axis} axis{every}, {:.1} mm apart, \
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

    /// A vertical long-axis view (x-z plane) through the middle of [`stack`]: UK Biobank
    /// numbering (1 LV, 2 myocardium, 3 RV) against the stack's ACDC, an atrium (4) above it,
    /// 1.5 x 1 mm pixels, 8 mm thick; frames holding labels as `labelled` says.
    fn view(frames: u16, labelled: &[u16], lift_mm: f32) -> Vec<u8> {
        let slice = heart_slice(40, 3, 2, 1);
        let (nx, nz) = (40usize, 70usize);
        let mut one = vec![0u8; nx * nz];
        for z in 0..nz {
            let height = z as f64 - 5.0;
            for x in 0..nx {
                let own = if (-5.0..55.0).contains(&height) {
                    slice[x + 40 * 20]
                } else {
                    0
                };
                one[x + nx * z] = match own {
                    3 => 1,
                    2 => 2,
                    1 => 3,
                    _ if height > 55.0 && (10..30).contains(&x) => 4,
                    _ => 0,
                };
            }
        }
        let voxels: Vec<u8> = (0..frames)
            .flat_map(|t| {
                let keep = labelled.contains(&t);
                one.iter().map(move |&l| if keep { l } else { 0 })
            })
            .collect();
        let rows = [
            [1.5, 0.0, 0.0, 0.0],
            [0.0, 0.0, 8.0, 30.0],
            [0.0, 1.0, 0.0, -5.0 + lift_mm],
        ];
        let dims: Vec<u16> = if frames > 1 {
            vec![nx as u16, nz as u16, 1, frames]
        } else {
            vec![nx as u16, nz as u16, 1]
        };
        nifti_bytes(&dims, Some(rows), &voxels)
    }

    fn curves(set: &ContourSet, surface: &str, prefix: &str) -> usize {
        set.contours
            .iter()
            .filter(|c| c.surface.as_deref() == Some(surface) && c.id.starts_with(prefix))
            .count()
    }

    #[test]
    fn a_stack_with_a_long_axis_view() {
        let stack = stack(6, 1);
        let v = view(1, &[0], 0.0);
        let set = read_nifti_study(&stack, &[("dir/la_4ch.nii", &v)], None).unwrap();
        for surface in ["LV_ENDO", "LV_EPI", "RV_ENDO"] {
            assert_eq!(curves(&set, surface, "slice"), 6, "{surface}");
            assert_eq!(curves(&set, surface, "la_4ch"), 1, "{surface}");
        }
        // The LV cavity's curve runs from the apex slice's level to the top slice's, in the view's
        // plane (y = 30 mm).
        let c = set
            .contours
            .iter()
            .find(|c| c.surface.as_deref() == Some("LV_ENDO") && c.id.starts_with("la_4ch"))
            .unwrap();
        let zs: Vec<f64> = c.points().map(|p| p.z).collect();
        let (lo, hi) = (
            zs.iter().cloned().fold(f64::MAX, f64::min),
            zs.iter().cloned().fold(f64::MIN, f64::max),
        );
        assert!(
            (lo + 5.0).abs() < 1.0 && (hi - 55.0).abs() < 1.0,
            "{lo} {hi}"
        );
        assert!(c.points().all(|p| (p.y - 30.0).abs() < 1e-6));
        let note = set
            .warnings
            .iter()
            .find(|w| w.starts_with("long-axis view la_4ch.nii read as"))
            .unwrap();
        assert!(
            note.contains("1 LV cavity (100 %)")
                && note.contains("3 RV cavity")
                && note.contains("label 4 on none"),
            "{note}"
        );
        assert!(is_reading_note(note) && is_reading_note(&set.warnings[0]));
        assert!(!set.warnings.iter().any(|w| w.contains("single slice")));
        // Listed in any order, views are read in name order: the same contours.
        let ids = |views: &[(&str, &[u8])]| -> Vec<String> {
            let set = read_nifti_study(&stack, views, None).unwrap();
            set.contours.iter().map(|c| c.id.clone()).collect()
        };
        let other = view(1, &[0], 2.0);
        assert_eq!(
            ids(&[("dir/la_b.nii", &v), ("la_a.nii", &other)]),
            ids(&[("la_a.nii", &other), ("la_b.nii", &v)])
        );
        // Alone, a view is one slice: said so.
        let alone = read_nifti(&v, None).unwrap();
        assert!(alone.warnings.iter().any(|w| w.contains("a single slice")));
        // From another patient or acquisition: nothing lies on the stack; said, not used.
        let far = view(1, &[0], 400.0);
        let set = read_nifti_study(&stack, &[("far.nii", &far)], None).unwrap();
        assert_eq!(curves(&set, "LV_ENDO", "far"), 0);
        assert!(set
            .warnings
            .iter()
            .any(|w| w.contains("far.nii: none of its labels") && !is_reading_note(w)));
        // A second stack as a view, and a damaged view, are refused naming the file.
        let e = read_nifti_study(&stack, &[("sa2.nii", &stack)], None).unwrap_err();
        assert!(
            e.to_string()
                .contains("sa2.nii: 40 x 40 x 6 voxels is a stack"),
            "{e}"
        );
        let e = read_nifti_study(&stack, &[("cut.nii", &v[..400])], None).unwrap_err();
        assert!(
            e.to_string().contains("cut.nii: the file is truncated"),
            "{e}"
        );
    }

    #[test]
    fn cine_views_follow_the_stacks_frame() {
        let stack = stack(6, 3);
        // The view's frame 1 was left unlabelled.
        let v = view(3, &[0, 2], 0.0);
        let views: [(&str, &[u8]); 1] = [("la.nii", &v)];
        let at = |f: &str| read_nifti_study(&stack, &views, FrameChoice::new(f).as_ref()).unwrap();
        assert_eq!(curves(&at("2"), "LV_ENDO", "la"), 1);
        let one = at("1");
        assert_eq!(curves(&one, "LV_ENDO", "la"), 0);
        assert!(
            one.warnings
                .iter()
                .any(|w| w == "long-axis view la.nii: frame 1 holds no labels; not used"),
            "{:?}",
            one.warnings
        );
        // A view of one frame goes with every frame of the stack.
        let still = view(1, &[0], 0.0);
        let set = read_nifti_study(
            &stack,
            &[("la.nii", &still)],
            FrameChoice::new("1").as_ref(),
        )
        .unwrap();
        assert_eq!(curves(&set, "LV_EPI", "la"), 1);
        assert!(
            set.warnings.iter().any(|w| w
                == "la.nii holds one time frame, read with frame 1 of the cine stack: make sure \
                    it shows the same phase"),
            "{:?}",
            set.warnings
        );
        // With a cine view, no such warning.
        assert!(!at("2")
            .warnings
            .iter()
            .any(|w| w.contains("one time frame")));
    }

    #[test]
    fn studies_of_several_files() {
        use crate::io::{read_study, ContourOptions};
        let stack = stack(6, 1);
        let v = view(1, &[0], 0.0);
        let o = ContourOptions::default();
        let (at, set) = read_study(&[("la.nii", &v), ("sa.nii", &stack)], &o).unwrap();
        assert_eq!((at, curves(&set, "LV_ENDO", "la")), (1, 1));
        let text = |files: &[(&str, &[u8])]| read_study(files, &o).unwrap_err().to_string();
        assert!(text(&[("sa.nii", &stack), ("b.nii", &stack)])
            .contains("sa.nii and b.nii are both stacks"));
        assert!(text(&[("la.nii", &v), ("lb.nii", &v)]).contains("every file is a single slice"));
        assert!(text(&[("sa.nii", &stack), ("c.csv", b"contour,x,y,z\n")])
            .contains("c.csv is not a label map (NIfTI-1, NRRD or DICOM SEG)"));
        // A stack's own damage is named too.
        let e = text(&[("sa.nii", &stack[..1000]), ("la.nii", &v)]);
        assert!(e.contains("sa.nii: the file is truncated"), "{e}");
        // Views beside another format, through the options.
        let views: [(&str, &[u8]); 1] = [("la.nii", &v)];
        let with = ContourOptions {
            views: &views,
            ..ContourOptions::default()
        };
        let e =
            crate::io::read_contours_with("c.csv", b"contour,x,y,z\n1,0,0,0\n", &with).unwrap_err();
        assert!(
            e.to_string()
                .contains("long-axis label maps are read with a short-axis label map"),
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
