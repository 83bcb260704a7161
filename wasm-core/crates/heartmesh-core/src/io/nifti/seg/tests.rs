use super::super::volume::read_label_frame;
use super::super::{read_dicom_seg, read_nifti, write::write_nifti};
use super::*;
use crate::contours::ContourSet;
use crate::io::dicom_read::rle::{self, tests::frame as rle_frame, tests::pack as rle_pack};
use crate::io::gzip::inflate;
use dicom_core::value::{DataSetSequence, PixelFragmentSequence, Value as DValue};
use dicom_core::{DataElement, PrimitiveValue, Tag as DTag, VR};
use dicom_object::{FileMetaTableBuilder, InMemDicomObject};

/// The app's example segmentation (CardioMesh spasm: RV 1, myocardium 2, LV cavity 3).
fn sample() -> LabelVolume {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../public/samples/cardiomesh-spasm-seg.nii.gz"
    );
    let raw = std::fs::read(path).unwrap();
    let bytes = inflate(&raw).unwrap();
    read_label_frame(&bytes, None).unwrap()
}

/// `v` cut to `[i0, i0 + ni) x [j0, j0 + nj)` in plane, its origin moved with it: an odd size
/// makes the frames' bits run across byte boundaries.
fn crop(v: &LabelVolume, i0: usize, ni: usize, j0: usize, nj: usize) -> LabelVolume {
    let [di, dj, dk] = v.dims;
    let mut labels = Vec::with_capacity(ni * nj * dk);
    for k in 0..dk {
        for j in j0..j0 + nj {
            for i in i0..i0 + ni {
                labels.push(v.labels[i + di * (j + dj * k)]);
            }
        }
    }
    let origin = v.origin + v.axes[0] * i0 as f64 + v.axes[1] * j0 as f64;
    LabelVolume::new([ni, nj, dk], origin, v.axes, labels)
}

fn el(
    group: u16,
    element: u16,
    vr: VR,
    value: impl Into<PrimitiveValue>,
) -> DataElement<InMemDicomObject> {
    DataElement::new(DTag(group, element), vr, value.into())
}

fn seq(group: u16, element: u16, items: Vec<InMemDicomObject>) -> DataElement<InMemDicomObject> {
    DataElement::new(DTag(group, element), VR::SQ, DataSetSequence::from(items))
}

fn item(elements: Vec<DataElement<InMemDicomObject>>) -> InMemDicomObject {
    InMemDicomObject::from_element_iter(elements)
}

fn ds(values: &[f64]) -> String {
    let v: Vec<String> = values.iter().map(|x| format!("{x:.6}")).collect();
    v.join("\\")
}

/// How a test SEG is written.
struct Spec<'a> {
    /// 1 (binary), 8 (fractional, 255 = inside; a label map's bytes), 16 (a label map's).
    bits: u16,
    transfer_syntax: &'static str,
    /// SpacingBetweenSlices written (None: left out, as many writers do).
    spacing_between: Option<f64>,
    /// The first frames written lie in another orientation (their own PlaneOrientationSequence),
    /// upright through the stack's rows: how many.
    tilt_first: usize,
    /// LABELMAP (DICOM 2024c): one frame per slice holding every label, pixel = label.
    label_map: bool,
    /// A single-slice map on another plane (same pixel grid size and spacing), its frames added
    /// with their own PlaneOrientationSequence: a long-axis view segmented in the same object.
    plane: Option<&'a LabelVolume>,
}

const BINARY: Spec<'static> = Spec {
    bits: 1,
    transfer_syntax: "1.2.840.10008.1.2.1",
    spacing_between: None,
    tilt_first: 0,
    label_map: false,
    plane: None,
};

/// Row and column directions of a map's planes, as ImageOrientationPatient.
fn orientation(v: &LabelVolume) -> DataElement<InMemDicomObject> {
    let (row, col) = (v.axes[0].normalize(), v.axes[1].normalize());
    el(
        0x0020,
        0x0037,
        VR::DS,
        ds(&[row.x, row.y, row.z, col.x, col.y, col.z]),
    )
}

/// A SEG of label maps on one grid, one per time frame (TemporalPositionIndex 1, 2, ...): a
/// frame per slice and label present, none for empty ones, listed last slice first (the reader
/// must not rely on their order); a label map's frames hold every label of their slice.
fn write_seg(times: &[&LabelVolume], spec: &Spec) -> Vec<u8> {
    let v = times[0];
    let [ni, nj, _] = v.dims;
    let spacing = [v.axes[1].norm(), v.axes[0].norm()];
    let mut per_frame = Vec::new();
    let mut values: Vec<u16> = Vec::new();
    let mut labels_seen = std::collections::BTreeSet::new();
    let sources = times
        .iter()
        .enumerate()
        .map(|(t, vol)| (t, *vol, false))
        .chain(spec.plane.map(|p| (0, p, true)));
    for (t, vol, own_plane) in sources {
        for k in (0..vol.dims[2]).rev() {
            let slice = &vol.labels[ni * nj * k..ni * nj * (k + 1)];
            let mut present: Vec<u16> = slice.iter().copied().filter(|&l| l != 0).collect();
            present.sort_unstable();
            present.dedup();
            labels_seen.extend(present.iter().copied());
            let frames: Vec<Option<u16>> = match (spec.label_map, present.is_empty()) {
                (_, true) => Vec::new(),
                (true, false) => vec![None],
                (false, false) => present.into_iter().map(Some).collect(),
            };
            for label in frames {
                let p = vol.origin + vol.axes[2] * k as f64;
                let mut groups = vec![
                    seq(
                        0x0020,
                        0x9111,
                        vec![item(vec![el(0x0020, 0x9128, VR::UL, (t + 1) as u32)])],
                    ),
                    seq(
                        0x0020,
                        0x9113,
                        vec![item(vec![el(0x0020, 0x0032, VR::DS, ds(&[p.x, p.y, p.z]))])],
                    ),
                ];
                if let Some(label) = label {
                    groups.push(seq(
                        0x0062,
                        0x000A,
                        vec![item(vec![el(0x0062, 0x000B, VR::US, label)])],
                    ));
                }
                if own_plane {
                    groups.push(seq(0x0020, 0x9116, vec![item(vec![orientation(vol)])]));
                }
                per_frame.push(item(groups));
                values.extend(slice.iter().map(|&l| match label {
                    None => l,
                    Some(label) => u16::from(l == label),
                }));
            }
        }
    }
    for frame in per_frame.iter_mut().take(spec.tilt_first) {
        let (row, col) = (v.axes[0].normalize(), v.axes[1].normalize());
        let n = row.cross(&col);
        frame.put(seq(
            0x0020,
            0x9116,
            vec![item(vec![el(
                0x0020,
                0x0037,
                VR::DS,
                ds(&[n.x, n.y, n.z, col.x, col.y, col.z]),
            )])],
        ));
    }
    // Native pixel data of `values`, bit after bit for a binary SEG.
    let native = |values: &[u16]| -> Vec<u8> {
        match spec.bits {
            1 => {
                let mut packed = vec![0u8; values.len().div_ceil(8)];
                for (n, _) in values.iter().enumerate().filter(|(_, &b)| b != 0) {
                    packed[n / 8] |= 1 << (n % 8);
                }
                packed
            }
            8 if spec.label_map => values.iter().map(|&l| l as u8).collect(),
            8 => values
                .iter()
                .map(|&b| if b != 0 { 255 } else { 0 })
                .collect(),
            _ => values.iter().flat_map(|l| l.to_le_bytes()).collect(),
        }
    };
    let pixel_data = if spec.transfer_syntax == rle::RLE_LOSSLESS {
        // One fragment per frame, each its own bytes (a binary frame starts on a byte).
        let fragments: Vec<Vec<u8>> = values
            .chunks(ni * nj)
            .map(|frame| {
                let bytes = native(frame);
                let segments = match spec.bits {
                    16 => vec![
                        rle_pack(&bytes.iter().skip(1).step_by(2).copied().collect::<Vec<_>>()),
                        rle_pack(&bytes.iter().step_by(2).copied().collect::<Vec<_>>()),
                    ],
                    _ => vec![rle_pack(&bytes)],
                };
                let mut f = rle_frame(&segments);
                if f.len() % 2 == 1 {
                    f.push(0);
                }
                f
            })
            .collect();
        let sequence = PixelFragmentSequence::new(Vec::<u32>::new(), fragments);
        DataElement::new(DTag(0x7FE0, 0x0010), VR::OB, DValue::from(sequence))
    } else {
        let mut pixels = native(&values);
        if pixels.len() % 2 == 1 {
            pixels.push(0);
        }
        el(0x7FE0, 0x0010, VR::OB, PrimitiveValue::U8(pixels.into()))
    };
    let segments: Vec<InMemDicomObject> = labels_seen
        .iter()
        .map(|&l| {
            item(vec![
                el(0x0062, 0x0004, VR::US, l),
                el(0x0062, 0x0005, VR::LO, format!("structure {l}")),
            ])
        })
        .collect();
    let (sop_class, kind) = match (spec.label_map, spec.bits) {
        (true, _) => (LABEL_MAP_SEGMENTATION_STORAGE, "LABELMAP"),
        (false, 1) => (SEGMENTATION_STORAGE, "BINARY"),
        (false, _) => (SEGMENTATION_STORAGE, "FRACTIONAL"),
    };
    let mut obj = InMemDicomObject::from_element_iter([
        el(0x0008, 0x0016, VR::UI, sop_class),
        el(0x0008, 0x0018, VR::UI, "1.2.826.0.1.3680043.10.1234.1"),
        el(0x0008, 0x0060, VR::CS, "SEG"),
        el(0x0028, 0x0002, VR::US, 1u16),
        el(0x0028, 0x0004, VR::CS, "MONOCHROME2"),
        el(0x0028, 0x0008, VR::IS, per_frame.len().to_string()),
        el(0x0028, 0x0010, VR::US, nj as u16),
        el(0x0028, 0x0011, VR::US, ni as u16),
        el(0x0028, 0x0100, VR::US, spec.bits),
        el(0x0028, 0x0101, VR::US, spec.bits),
        el(0x0028, 0x0102, VR::US, spec.bits - 1),
        el(0x0062, 0x0001, VR::CS, kind),
        seq(0x0062, 0x0002, segments),
        seq(
            0x5200,
            0x9229,
            vec![item(vec![
                seq(0x0020, 0x9116, vec![item(vec![orientation(v)])]),
                seq(
                    0x0028,
                    0x9110,
                    vec![item(
                        [
                            el(0x0028, 0x0030, VR::DS, ds(&spacing)),
                            el(0x0018, 0x0050, VR::DS, ds(&[v.axes[2].norm()])),
                        ]
                        .into_iter()
                        .chain(
                            spec.spacing_between
                                .map(|d| el(0x0018, 0x0088, VR::DS, ds(&[d]))),
                        )
                        .collect(),
                    )],
                ),
            ])],
        ),
        seq(0x5200, 0x9230, per_frame),
        pixel_data,
    ]);
    if spec.bits == 8 && !spec.label_map {
        obj.put(el(0x0062, 0x000E, VR::US, 255u16));
    }
    let file = obj
        .with_meta(
            FileMetaTableBuilder::new()
                .transfer_syntax(spec.transfer_syntax)
                .media_storage_sop_class_uid(sop_class)
                .media_storage_sop_instance_uid("1.2.826.0.1.3680043.10.1234.1"),
        )
        .unwrap();
    let mut out = Vec::new();
    file.write_all(&mut out).unwrap();
    out
}

/// The contours of `v` read as a NIfTI: what a SEG of the same map must give.
fn as_nifti(v: &LabelVolume) -> ContourSet {
    read_nifti(&write_nifti(v, false), None).unwrap()
}

/// Each surface's points: two readings of one label map agree point for point, to the 1e-6 of
/// the DS strings the test writes.
fn points_by_surface(set: &ContourSet) -> Vec<(String, Vec<Vec3>)> {
    let mut out: Vec<(String, Vec<Vec3>)> = set
        .surfaces()
        .into_iter()
        .map(|s| {
            let p: Vec<Vec3> = set
                .contours
                .iter()
                .filter(|c| c.surface.as_deref() == Some(s.as_str()))
                .flat_map(|c| c.points().copied().collect::<Vec<_>>())
                .collect();
            (s, p)
        })
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

/// The same surfaces with the same point counts, every point within 1e-3 mm of one of the other's.
fn assert_same_points(a: &ContourSet, b: &ContourSet) {
    let (a, b) = (points_by_surface(a), points_by_surface(b));
    assert_eq!(a.len(), b.len());
    for ((sa, pa), (sb, pb)) in a.iter().zip(&b) {
        assert_eq!(sa, sb);
        assert_eq!(pa.len(), pb.len(), "{sa}");
        let worst = pa
            .iter()
            .map(|p| {
                pb.iter()
                    .map(|q| (p - q).norm())
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max);
        assert!(worst < 1e-3, "{sa}: {worst} mm");
    }
}

#[test]
fn a_seg_reads_as_the_label_map_it_was_written_from() {
    // 91 x 87 pixels: frames of 7917 bits, so each starts inside a byte.
    let v = crop(&sample(), 5, 91, 3, 87);
    let nifti = as_nifti(&v);
    for spec in [
        BINARY,
        Spec {
            bits: 8,
            transfer_syntax: "1.2.840.10008.1.2.1",
            spacing_between: Some(10.0),
            tilt_first: 0,
            ..BINARY
        },
        Spec {
            bits: 1,
            transfer_syntax: "1.2.840.10008.1.2",
            spacing_between: None,
            tilt_first: 0,
            ..BINARY
        },
        // The slice thickness written where the spacing belongs (8 mm; the planes are 10 apart):
        // the planes' own gaps win.
        Spec {
            bits: 1,
            transfer_syntax: "1.2.840.10008.1.2.1",
            spacing_between: Some(8.0),
            tilt_first: 0,
            ..BINARY
        },
    ] {
        let bytes = write_seg(&[&v], &spec);
        assert!(is_seg(&bytes));
        let seg = read_dicom_seg(&bytes, None).unwrap();
        assert_eq!(seg.surfaces().len(), 3);
        assert_same_points(&seg, &nifti);
        let note = &seg.warnings[0];
        assert!(note.contains("frame positions (DICOM SEG, LPS)"), "{note}");
        assert!(
            note.contains("segments 1 structure 1, 2 structure 2, 3 structure 3"),
            "{note}"
        );
    }
}

#[test]
fn time_frames_are_read_one_at_a_time() {
    let v = crop(&sample(), 0, 90, 0, 90);
    // The second frame: the LV cavity (3) grown into the myocardium (2) everywhere.
    let mut grown = v.clone();
    for l in grown.labels.iter_mut().filter(|l| **l == 2) {
        *l = 3;
    }
    let bytes = write_seg(&[&v, &grown], &BINARY);
    let first = read_dicom_seg(&bytes, None).unwrap();
    let tf = first.time_frames.as_ref().unwrap();
    assert_eq!(tf.count, 2);
    let second = read_dicom_seg(&bytes, FrameChoice::new("1").as_ref()).unwrap();
    assert_same_points(&first, &as_nifti(&v));
    assert_same_points(&second, &as_nifti(&grown));
    let e = read_dicom_seg(&bytes, FrameChoice::new("5").as_ref())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("no frame 5 in the DICOM SEG (its time frames: 0 to 1)"),
        "{e}"
    );
}

#[test]
fn segs_that_are_no_stack_or_are_cut_are_refused_with_the_reason() {
    let v = crop(&sample(), 0, 64, 0, 64);
    let good = write_seg(&[&v], &BINARY);
    let reason = |b: &[u8]| read_dicom_seg(b, None).unwrap_err().to_string();
    // Cut inside the pixel data.
    let e = reason(&good[..good.len() - 200]);
    assert!(e.contains("truncated") || e.contains("DICOM"), "{e}");
    // A compressed transfer syntax other than RLE (the header says so; JPEG is not decoded).
    let rle = write_seg(
        &[&v],
        &Spec {
            bits: 1,
            transfer_syntax: "1.2.840.10008.1.2.4.50",
            spacing_between: None,
            tilt_first: 0,
            ..BINARY
        },
    );
    assert!(
        reason(&rle).contains("export it uncompressed"),
        "{}",
        reason(&rle)
    );
    // One frame's plane 3.7 mm off the 10 mm grid (its ImagePositionPatient rewritten in place).
    let mut shifted = good.clone();
    let at = find(&shifted, b"\x20\x00\x32\x00DS").unwrap();
    let len = u16::from_le_bytes([shifted[at + 6], shifted[at + 7]]) as usize;
    let value = String::from_utf8_lossy(&shifted[at + 8..at + 8 + len]).to_string();
    let mut parts: Vec<f64> = value
        .trim()
        .split('\\')
        .map(|x| x.trim().parse().unwrap())
        .collect();
    parts[2] += 3.7;
    let mut moved = ds(&parts);
    if moved.len() > len {
        moved = format!("{:.2}\\{:.2}\\{:.2}", parts[0], parts[1], parts[2]);
    }
    assert!(moved.len() <= len, "{moved}");
    let padded = format!("{moved:<len$}");
    shifted[at + 8..at + 8 + len].copy_from_slice(padded.as_bytes());
    let e = reason(&shifted);
    assert!(
        e.contains("not evenly spaced") || e.contains("across its plane"),
        "{e}"
    );
    // Not a SEG: an image goes to the structure-set reader, which says what it is.
    assert!(!is_seg(
        &crate::io::rtstruct::write_rtstruct(&ContourSet::default(), "x").unwrap_or_default()
    ));
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

#[test]
fn mutated_segs_never_panic() {
    let v = crop(&sample(), 10, 37, 10, 29);
    // Binary, a 16-bit label map, one with a plane of another orientation (a view), and an RLE
    // label map.
    let view = upright_view(&v, 14, 10.0);
    let seeds = [
        write_seg(&[&v], &BINARY),
        write_seg(
            &[&v],
            &Spec {
                bits: 16,
                label_map: true,
                transfer_syntax: rle::RLE_LOSSLESS,
                ..BINARY
            },
        ),
        write_seg(
            &[&v],
            &Spec {
                bits: 16,
                label_map: true,
                ..BINARY
            },
        ),
        write_seg(
            &[&v],
            &Spec {
                plane: Some(&view),
                ..BINARY
            },
        ),
    ];
    let mut rng = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        rng
    };
    for n in 0..800 {
        let mut b = seeds[n % seeds.len()].clone();
        match (n / seeds.len()) % 3 {
            0 => {
                for _ in 0..4 {
                    let at = (next() as usize) % b.len();
                    b[at] = next() as u8;
                }
            }
            1 => b.truncate((next() as usize) % b.len()),
            _ => {
                let at = (next() as usize) % b.len();
                let bytes = (next() as u32).to_le_bytes();
                b.splice(at..at, bytes);
            }
        }
        let _ = read_dicom_seg(&b, None);
        let _ = read_dicom_seg(&b, FrameChoice::new("1").as_ref());
        let _ = super::grid(&b);
    }
}

#[test]
fn a_lone_plane_of_another_orientation_is_a_view_frames_on_no_one_plane_are_set_aside() {
    let v = crop(&sample(), 0, 90, 0, 90);
    let tilted = |n: usize| {
        write_seg(
            &[&v],
            &Spec {
                tilt_first: n,
                ..BINARY
            },
        )
    };
    // The first frame written (the top slice's lowest label) turned upright: a plane of its own.
    let read = read_seg_volume(&tilted(1), None).unwrap();
    assert_eq!((read.views.len(), read.aside), (1, 0));
    assert_eq!(read.views[0].dims, [90, 90, 1]);
    assert_eq!(read.views[0].space, Some(Space::LPS));
    // The first 4 (the top slice's labels and the next slice's): upright planes through two
    // slices' positions, which lie in one upright plane, offset in it: no grid, set aside.
    let read = read_seg_volume(&tilted(4), None).unwrap();
    assert_eq!((read.views.len(), read.aside), (0, 4));
    let set = read_dicom_seg(&tilted(4), None).unwrap();
    assert!(
        set.warnings.iter().any(|w| w.starts_with(
            "4 frames of the DICOM SEG in another orientation or pixel spacing than the stack, \
             and on no single plane of their own, set aside"
        )),
        "{:?}",
        set.warnings
    );
}

#[test]
fn the_stack_is_read_without_the_frames_of_another_orientation() {
    let v = crop(&sample(), 0, 90, 0, 90);
    let bytes = write_seg(
        &[&v],
        &Spec {
            tilt_first: 1,
            ..BINARY
        },
    );
    let mut set = read_dicom_seg(&bytes, None).unwrap();
    assert!(
        set.warnings
            .iter()
            .any(|w| w.starts_with("long-axis view 1 of the DICOM SEG")),
        "{:?}",
        set.warnings
    );
    set.contours.retain(|c| !c.id.starts_with("view"));
    // The frame read as a view is the first written: the top slice's lowest label. Without it,
    // the stack is the label map with that slice's label cleared.
    let [ni, nj, nk] = v.dims;
    let top = (0..nk)
        .rev()
        .find(|&k| {
            v.labels[ni * nj * k..ni * nj * (k + 1)]
                .iter()
                .any(|&l| l != 0)
        })
        .unwrap();
    let slice = ni * nj * top..ni * nj * (top + 1);
    let lowest = v.labels[slice.clone()]
        .iter()
        .copied()
        .filter(|&l| l != 0)
        .min()
        .unwrap();
    let mut without = v.clone();
    for l in without.labels[slice].iter_mut().filter(|l| **l == lowest) {
        *l = 0;
    }
    assert_same_points(&set, &as_nifti(&without));
}

#[test]
fn label_map_segs_read_as_the_map_they_hold() {
    // DICOM 2024c's LABELMAP: one frame per slice, each pixel its segment's number.
    let v = crop(&sample(), 5, 91, 3, 87);
    let nifti = as_nifti(&v);
    for bits in [8, 16] {
        let bytes = write_seg(
            &[&v],
            &Spec {
                bits,
                label_map: true,
                ..BINARY
            },
        );
        assert!(is_seg(&bytes));
        let seg = read_dicom_seg(&bytes, None).unwrap();
        assert_same_points(&seg, &nifti);
        assert!(
            seg.warnings[0].contains("segments 1 structure 1"),
            "{:?}",
            seg.warnings
        );
    }
    // The pixel padding value is background: label 2 written as padding reads as absent.
    let mut bytes = write_seg(
        &[&v],
        &Spec {
            bits: 8,
            label_map: true,
            ..BINARY
        },
    );
    // (0028,0120) US 2, after (0028,0102) HighBit.
    let at = find(&bytes, b"\x28\x00\x02\x01US").unwrap() + 10;
    let padding = [0x28, 0x00, 0x20, 0x01, b'U', b'S', 2, 0, 2, 0];
    bytes.splice(at..at, padding);
    let mut without = v.clone();
    for l in without.labels.iter_mut().filter(|l| **l == 2) {
        *l = 0;
    }
    let seg = read_seg_volume(&bytes, None).unwrap();
    let differ: Vec<(u16, u16)> = seg
        .volume
        .labels
        .iter()
        .zip(&without.labels)
        .filter(|(a, b)| a != b)
        .map(|(a, b)| (*a, *b))
        .take(5)
        .collect();
    assert!(differ.is_empty(), "{differ:?}");
    assert!(without.labels.contains(&3));
    // Other depths are refused with the reason.
    let mut wide = write_seg(
        &[&v],
        &Spec {
            bits: 16,
            label_map: true,
            ..BINARY
        },
    );
    let at = find(&wide, b"\x28\x00\x00\x01US").unwrap();
    wide[at + 8] = 32;
    let e = read_dicom_seg(&wide, None).unwrap_err().to_string();
    assert!(e.contains("label map SEG with 32 bits per pixel"), "{e}");
}

/// A single-slice map on the upright plane through `v`'s row `j` (the stack's rows and its
/// long axis, the same pixel spacing, starting `below` mm under the lowest slice): each pixel
/// the label of the stack voxel it lies in, as a long-axis view segmented on the same heart.
fn upright_view(v: &LabelVolume, j: usize, below: f64) -> LabelVolume {
    upright_view_along(v, 0, j, below)
}

/// [`upright_view`] along the stack's rows (`along` 0) or columns (1), through row or column
/// `at` of the other; the stack must be square in plane.
fn upright_view_along(v: &LabelVolume, along: usize, at: usize, below: f64) -> LabelVolume {
    let [ni, nj, nk] = v.dims;
    let across = 1 - along;
    let up = v.axes[2].normalize();
    let axes = [
        v.axes[along],
        up * v.axes[across].norm(),
        -v.axes[across].normalize(),
    ];
    let origin = v.origin + v.axes[across] * at as f64 - up * below;
    let inverse = nalgebra::Matrix3::from_columns(&v.axes)
        .try_inverse()
        .unwrap();
    let mut labels = vec![0u16; ni * nj];
    for r in 0..nj {
        for c in 0..ni {
            let p = origin + axes[0] * c as f64 + axes[1] * r as f64;
            let ijk = inverse * (p - v.origin);
            let at = ijk.map(f64::round);
            if (0..3).all(|a| at[a] >= 0.0 && at[a] < [ni, nj, nk][a] as f64) {
                let (i, j, k) = (at[0] as usize, at[1] as usize, at[2] as usize);
                labels[c + ni * r] = v.labels[i + ni * (j + nj * k)];
            }
        }
    }
    LabelVolume::new([ni, nj, 1], origin, axes, labels)
}

/// The sample cropped, and the row through the most LV cavity (3).
fn stack_and_row() -> (LabelVolume, usize) {
    let v = crop(&sample(), 0, 90, 0, 90);
    let [ni, nj, _] = v.dims;
    let row = (0..nj)
        .max_by_key(|&j| {
            v.labels
                .iter()
                .enumerate()
                .filter(|(n, &l)| l == 3 && (n / ni) % nj == j)
                .count()
        })
        .unwrap();
    (v, row)
}

/// `v` said to be NIfTI's RAS and turned into DICOM's LPS (x and y negated).
fn as_lps(v: &LabelVolume) -> LabelVolume {
    v.clone().in_space(Space::RAS).turned_into(Some(Space::LPS))
}

#[test]
fn a_plane_of_another_orientation_in_the_seg_is_read_as_a_long_axis_view() {
    let (v, row) = stack_and_row();
    let view = upright_view(&v, row, 10.0);
    let bytes = write_seg(
        &[&v],
        &Spec {
            plane: Some(&view),
            ..BINARY
        },
    );
    let mut set = read_dicom_seg(&bytes, None).unwrap();
    let note = set
        .warnings
        .iter()
        .find(|w| w.starts_with("long-axis view 1 of the DICOM SEG read as "))
        .unwrap_or_else(|| panic!("{:?}", set.warnings));
    // The view's labels lie on the stack's own: each matched to itself, 2 curves at least (LV
    // cavity, and cavity with myocardium).
    assert!(
        note.contains("3 LV cavity (") && note.contains("2 myocardium ("),
        "{note}"
    );
    let normal = view.axes[2].normalize();
    let on_view: Vec<_> = set
        .contours
        .iter()
        .filter(|c| c.id.starts_with("view 1"))
        .collect();
    let ids: Vec<&str> = set.contours.iter().map(|c| c.id.as_str()).collect();
    assert!(on_view.len() >= 2, "{note} {ids:?}");
    for c in &on_view {
        for p in c.points() {
            assert!((p - view.origin).dot(&normal).abs() < 1e-3, "{}", c.id);
        }
    }
    // Without them, the stack is the map's own.
    set.contours.retain(|c| !c.id.starts_with("view 1"));
    assert_same_points(&set, &as_nifti(&v));
}

#[test]
fn views_and_stacks_of_different_formats_meet_in_the_stack_s_coordinates() {
    use crate::io::{read_study, ContourOptions};
    let (v, row) = stack_and_row();
    let view = upright_view(&v, row, 10.0);
    // NIfTI (RAS) files of both, and DICOM SEGs (LPS) of both: the same anatomy.
    let nifti_stack = write_nifti(&v, false);
    let nifti_view = write_nifti(&view, true);
    let seg_stack = write_seg(&[&as_lps(&v)], &BINARY);
    let seg_view = write_seg(&[&as_lps(&view)], &BINARY);
    let study = |files: &[(&str, &[u8])]| {
        let (stack, set) = read_study(files, &ContourOptions::default()).unwrap();
        assert!(files[stack].0.starts_with("sa"));
        set
    };
    let all_nifti = study(&[("la.nii.gz", &nifti_view), ("sa.nii", &nifti_stack)]);
    let views = |s: &ContourSet| {
        s.contours
            .iter()
            .filter(|c| c.id.starts_with("la "))
            .count()
    };
    let ids: Vec<&str> = all_nifti.contours.iter().map(|c| c.id.as_str()).collect();
    assert!(views(&all_nifti) >= 2, "{ids:?}");
    // In LPS: the NIfTI study's points with x and y negated.
    let mut in_lps = all_nifti.clone();
    for p in in_lps
        .contours
        .iter_mut()
        .flat_map(|c| &mut c.pieces)
        .flat_map(|p| &mut p.points)
    {
        *p = Vec3::new(-p.x, -p.y, p.z);
    }
    for (files, lps) in [
        (
            vec![("sa.dcm", &seg_stack[..]), ("la.dcm", &seg_view[..])],
            true,
        ),
        (
            vec![("la.nii.gz", &nifti_view[..]), ("sa.dcm", &seg_stack[..])],
            true,
        ),
        (
            vec![("sa.nii", &nifti_stack[..]), ("la.dcm", &seg_view[..])],
            false,
        ),
    ] {
        let set = study(&files);
        assert_eq!(
            views(&set),
            views(&all_nifti),
            "{files:?}: {:?}",
            set.warnings
        );
        assert_same_points(&set, if lps { &in_lps } else { &all_nifti });
    }
}

#[test]
fn a_seg_of_long_axis_planes_only_gives_a_view_per_plane() {
    use crate::io::{read_study, ContourOptions};
    let (v, row) = stack_and_row();
    // The column through the most LV cavity too.
    let [ni, _, _] = v.dims;
    let column = (0..ni)
        .max_by_key(|&i| {
            (v.labels.iter().enumerate())
                .filter(|(n, &l)| l == 3 && n % ni == i)
                .count()
        })
        .unwrap();
    let (a, b) = (
        upright_view_along(&v, 0, row, 10.0),
        upright_view_along(&v, 1, column, 10.0),
    );
    // One SEG holding both planes, no short-axis frame (as a service segmenting the long-axis
    // series writes them), against the two as NIfTI views.
    let views_seg = write_seg(
        &[&as_lps(&a)],
        &Spec {
            plane: Some(&as_lps(&b)),
            ..BINARY
        },
    );
    assert_eq!(super::grid(&views_seg).map(|g| g.0[2]), Some(1));
    let stack = write_nifti(&v, false);
    let (na, nb) = (write_nifti(&a, false), write_nifti(&b, false));
    let read = |files: &[(&str, &[u8])]| read_study(files, &ContourOptions::default()).unwrap().1;
    let from_seg = read(&[("la.dcm", &views_seg), ("sa.nii", &stack)]);
    let from_nifti = read(&[("sa.nii", &stack), ("a.nii", &na), ("b.nii", &nb)]);
    for plane in ["la plane 1", "la plane 2"] {
        let curves = from_seg
            .contours
            .iter()
            .filter(|c| c.id.starts_with(plane))
            .count();
        assert!(curves >= 2, "{plane}: {:?}", from_seg.warnings);
    }
    assert!(
        from_seg
            .warnings
            .iter()
            .any(|w| w.starts_with("long-axis view la.dcm plane 2 read as ")),
        "{:?}",
        from_seg.warnings
    );
    assert_same_points(&from_seg, &from_nifti);
}

#[test]
fn rle_segs_read_as_the_map_they_hold() {
    // RLE Lossless, as dcmjs (OHIF) writes every SEG by default: binary frames each starting on
    // a byte of their own (91 x 87 pixels: not a whole number of bytes), fractional ones, and
    // label maps of 8 and 16 bits (two byte segments per frame).
    let v = crop(&sample(), 5, 91, 3, 87);
    let nifti = as_nifti(&v);
    for (bits, label_map) in [(1, false), (8, false), (8, true), (16, true)] {
        let bytes = write_seg(
            &[&v],
            &Spec {
                bits,
                label_map,
                transfer_syntax: rle::RLE_LOSSLESS,
                ..BINARY
            },
        );
        let seg = read_dicom_seg(&bytes, None).unwrap_or_else(|e| panic!("{bits} bits: {e}"));
        assert_same_points(&seg, &nifti);
        // The header alone gives the grid, as for an uncompressed SEG.
        assert_eq!(super::grid(&bytes).map(|g| g.0), Some([91, 87, 8]));
    }
    // A frame whose fragment is cut: refused, naming the frame.
    let bytes = write_seg(
        &[&v],
        &Spec {
            transfer_syntax: rle::RLE_LOSSLESS,
            ..BINARY
        },
    );
    let set = crate::io::dicom_read::read_file(&bytes, &[]).unwrap();
    let Some(Value::Fragments(items)) = set.get(tag::PIXEL_DATA) else {
        panic!("no fragments")
    };
    assert_eq!(items.len(), 1 + 21);
    let first = items[1];
    let at = find(&bytes, first).unwrap();
    let mut cut = bytes.clone();
    // Its first segment's offset pointed past the fragment's end.
    cut[at + 4..at + 8].copy_from_slice(&60_000u32.to_le_bytes());
    let e = read_dicom_seg(&cut, None).unwrap_err().to_string();
    assert!(
        e.contains("frame 1 of the DICOM SEG: RLE segment 1 lies at"),
        "{e}"
    );
}
