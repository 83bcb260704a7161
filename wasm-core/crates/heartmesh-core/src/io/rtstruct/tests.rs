use super::*;
use crate::io::{read_contours, sample};

/// Committed sample: biv-me patient 1 at end-diastole (Apache-2.0 data), written by
/// [`write_rtstruct`]; regenerate with HEARTMESH_WRITE_SAMPLES=1.
const SAMPLE: &str = "tests/data/patient1-ED-rtstruct.dcm";

fn patient1() -> ContourSet {
    let rel = "contours/bivme-example-patient1/GPFile_000.txt";
    read_contours(rel, &sample(rel)).unwrap()
}

fn sorted_landmarks(set: &ContourSet) -> Vec<(String, [u64; 3])> {
    let mut l: Vec<_> = set
        .landmarks
        .iter()
        .map(|(n, p)| (n.clone(), [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]))
        .collect();
    l.sort();
    l
}

#[test]
fn patient1_round_trips_through_rtstruct() {
    let set = patient1();
    let bytes = write_rtstruct(&set, "patient1 ED").unwrap();
    assert!(is_dicom(&bytes));
    let back = read_contours("x.dcm", &bytes).unwrap();
    // One ROI per surface, in the order the surfaces first appear.
    assert_eq!(back.surfaces(), set.surfaces());
    assert_eq!(
        back.surfaces(),
        vec!["RV_ENDO", "RV_EPI", "LV_EPI", "LV_ENDO"]
    );
    assert_eq!(back.contours.len(), 40);
    assert_eq!(back.point_count(), 1791);
    assert_eq!(back.landmarks.len(), 23);
    assert_eq!(sorted_landmarks(&back), sorted_landmarks(&set));
    // Grouped by ROI: the contours of each surface in file order.
    let mut grouped: Vec<&crate::contours::Contour> = Vec::new();
    for surface in set.surfaces() {
        grouped.extend(
            set.contours
                .iter()
                .filter(|c| c.surface.as_ref() == Some(&surface)),
        );
    }
    for (a, b) in grouped.into_iter().zip(&back.contours) {
        assert_eq!(a.surface, b.surface, "{}", a.id);
        assert_eq!(a.pieces.len(), b.pieces.len(), "{}", a.id);
        for (pa, pb) in a.pieces.iter().zip(&b.pieces) {
            assert_eq!(pa.closed, pb.closed, "{}", a.id);
            // The biv-me values have at most 16 characters: the DS text is exact.
            assert_eq!(pa.points, pb.points, "{}", a.id);
        }
    }
    // The ROI name becomes the surface, the contour number the identifier.
    assert_eq!(
        back.contours[0].id,
        format!("{}:1", back.contours[0].surface.as_deref().unwrap())
    );
}

#[test]
fn committed_sample_is_what_the_writer_makes() {
    let bytes = write_rtstruct(&patient1(), "patient1 ED").unwrap();
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(SAMPLE);
    if std::env::var_os("HEARTMESH_WRITE_SAMPLES").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, &bytes).unwrap();
    }
    let committed = std::fs::read(&path).unwrap();
    assert_eq!(committed.len(), bytes.len());
    assert!(committed == bytes, "{SAMPLE} is stale: regenerate it");
    // Deterministic: same contours, same UIDs, same bytes.
    assert_eq!(write_rtstruct(&patient1(), "patient1 ED").unwrap(), bytes);
}

fn el(tag: dicom_core::Tag, vr: VR, v: &str) -> DataElement<InMemDicomObject> {
    DataElement::new(tag, vr, v)
}

fn contour(kind: &str, data: &str) -> InMemDicomObject {
    InMemDicomObject::from_element_iter([
        el(tags::CONTOUR_GEOMETRIC_TYPE, VR::CS, kind),
        el(tags::CONTOUR_DATA, VR::DS, data),
    ])
}

/// An RT structure set with the given ROIs (number, name) and ROI contours (referenced
/// number, contours), as a clinical tool would write it (with preamble and meta group).
fn rt_file(
    modality: &str,
    rois: &[(u32, &str)],
    roi_contours: Vec<(u32, Vec<InMemDicomObject>)>,
) -> Vec<u8> {
    let file = rt_object(modality, rois, roi_contours)
        .with_meta(FileMetaTableBuilder::new().transfer_syntax(uids::EXPLICIT_VR_LITTLE_ENDIAN))
        .unwrap();
    let mut out = Vec::new();
    file.write_all(&mut out).unwrap();
    out
}

fn rt_object(
    modality: &str,
    rois: &[(u32, &str)],
    roi_contours: Vec<(u32, Vec<InMemDicomObject>)>,
) -> InMemDicomObject {
    let ss: Vec<InMemDicomObject> = rois
        .iter()
        .map(|(n, name)| {
            InMemDicomObject::from_element_iter([
                el(tags::ROI_NUMBER, VR::IS, &n.to_string()),
                el(tags::ROI_NAME, VR::LO, name),
            ])
        })
        .collect();
    let rc: Vec<InMemDicomObject> = roi_contours
        .into_iter()
        .map(|(n, cs)| {
            InMemDicomObject::from_element_iter([
                el(tags::REFERENCED_ROI_NUMBER, VR::IS, &n.to_string()),
                DataElement::new(tags::CONTOUR_SEQUENCE, VR::SQ, DataSetSequence::from(cs)),
            ])
        })
        .collect();
    let class = if modality == "RTSTRUCT" {
        uids::RT_STRUCTURE_SET_STORAGE
    } else {
        uids::MR_IMAGE_STORAGE
    };
    let mut elements = vec![
        el(tags::SOP_CLASS_UID, VR::UI, class),
        el(tags::SOP_INSTANCE_UID, VR::UI, "2.25.1234"),
        el(tags::MODALITY, VR::CS, modality),
    ];
    if !ss.is_empty() {
        elements.push(DataElement::new(
            tags::STRUCTURE_SET_ROI_SEQUENCE,
            VR::SQ,
            DataSetSequence::from(ss),
        ));
    }
    if !rc.is_empty() {
        elements.push(DataElement::new(
            tags::ROI_CONTOUR_SEQUENCE,
            VR::SQ,
            DataSetSequence::from(rc),
        ));
    }
    InMemDicomObject::from_element_iter(elements)
}

fn hand_made() -> Vec<u8> {
    let file = hand_made_object()
        .with_meta(FileMetaTableBuilder::new().transfer_syntax(uids::EXPLICIT_VR_LITTLE_ENDIAN))
        .unwrap();
    let mut out = Vec::new();
    file.write_all(&mut out).unwrap();
    out
}

fn hand_made_object() -> InMemDicomObject {
    rt_object(
        "RTSTRUCT",
        &[(7, "LV Endo"), (9, "Apex")],
        vec![
            (
                7,
                vec![
                    // A ring that repeats its first point, and one that does not.
                    contour(
                        "CLOSED_PLANAR",
                        "0\\0\\10\\10\\0\\10\\10\\10\\10\\0\\10\\10\\0\\0\\10",
                    ),
                    contour("CLOSED_PLANAR", "0\\0\\20\\10\\0\\20\\10\\10\\20"),
                    // A U-shaped long-axis curve whose ends are close: open all the same.
                    contour("OPEN_PLANAR", "0\\5\\0\\0\\5\\30\\1\\5\\30\\1\\5\\0.5"),
                ],
            ),
            (9, vec![contour("POINT", "5\\5\\-3.25")]),
            (
                4,
                vec![contour("CLOSED_PLANAR", "1\\2\\3\\4\\5\\6\\7\\8\\9.5")],
            ),
        ],
    )
}

#[test]
fn hand_made_structure_set() {
    let set = read_rtstruct(&hand_made()).unwrap();
    assert_eq!(set.surfaces(), vec!["LV Endo", "ROI 4"]);
    let ids: Vec<&str> = set.contours.iter().map(|c| c.id.as_str()).collect();
    assert_eq!(ids, ["LV Endo:#1", "LV Endo:#2", "LV Endo:#3", "ROI 4:#1"]);
    let counts: Vec<usize> = set.contours.iter().map(|c| c.point_count()).collect();
    assert_eq!(counts, [4, 3, 4, 3]);
    let closed: Vec<bool> = set.contours.iter().map(|c| c.pieces[0].closed).collect();
    assert_eq!(closed, [true, true, false, true]);
    assert_eq!(set.contours[2].pieces[0].points[3], v3(1.0, 5.0, 0.5));
    assert_eq!(set.contours[3].pieces[0].points[2], v3(7.0, 8.0, 9.5));
    assert_eq!(
        set.landmarks,
        vec![("Apex".to_string(), v3(5.0, 5.0, -3.25))]
    );
    assert_eq!(set.point_count(), 14);
}

#[test]
fn without_preamble_and_without_meta_group() {
    let bytes = hand_made();
    let whole = read_rtstruct(&bytes).unwrap();
    // "DICM" first: the 128-byte preamble left out.
    let no_preamble = read_contours("x", &bytes[128..]).unwrap();
    assert_eq!(no_preamble, whole);
    // A bare data set in implicit VR little endian, found by its extension.
    let obj = hand_made_object();
    let mut bare = Vec::new();
    let ts = dicom_transfer_syntax_registry::entries::IMPLICIT_VR_LITTLE_ENDIAN.erased();
    obj.write_dataset_with_ts(&mut bare, &ts).unwrap();
    assert!(!is_dicom(&bare));
    let set = read_contours("rs.dcm", &bare).unwrap();
    assert_eq!(set, whole);
    // Implicit VR and explicit VR big endian with a file meta group.
    for ts in [uids::IMPLICIT_VR_LITTLE_ENDIAN, "1.2.840.10008.1.2.2"] {
        let file = hand_made_object()
            .with_meta(FileMetaTableBuilder::new().transfer_syntax(ts))
            .unwrap();
        let mut out = Vec::new();
        file.write_all(&mut out).unwrap();
        assert_eq!(read_rtstruct(&out).unwrap(), whole, "{ts}");
    }
}

fn message(bytes: &[u8]) -> String {
    match read_contours("x.dcm", bytes) {
        Err(CoreError::Parse { message, .. }) => message,
        other => panic!("expected a parse error, got {other:?}"),
    }
}

#[test]
fn malformed_files_give_clear_errors() {
    let good = hand_made();
    // Truncated anywhere after the header: never a panic, always a parse error.
    for cut in [132, 200, good.len() / 2, good.len() - 7] {
        let m = message(&good[..cut]);
        assert!(!m.is_empty(), "cut {cut}");
    }
    assert!(message(&good[..good.len() / 2]).contains("DICOM"));
    assert!(message(b"DI").contains("truncated"));
    let mr = rt_file("MR", &[], vec![]);
    let m = message(&mr);
    assert!(
        m.contains("not an RT structure set") && m.contains("modality MR"),
        "{m}"
    );
    let empty = rt_file("RTSTRUCT", &[(1, "LV")], vec![]);
    assert!(message(&empty).contains("ROIContourSequence"));
    let missing = rt_file(
        "RTSTRUCT",
        &[(1, "LV")],
        vec![(
            1,
            vec![InMemDicomObject::from_element_iter([el(
                tags::CONTOUR_GEOMETRIC_TYPE,
                VR::CS,
                "CLOSED_PLANAR",
            )])],
        )],
    );
    assert_eq!(
        message(&missing),
        "ROI \"LV\", contour 1: ContourData is missing"
    );
    let odd = rt_file(
        "RTSTRUCT",
        &[(1, "LV")],
        vec![(1, vec![contour("CLOSED_PLANAR", "1\\2\\3\\4")])],
    );
    assert_eq!(
        message(&odd),
        "ROI \"LV\", contour 1: ContourData has 4 values, not x\\y\\z triplets"
    );
    let text = rt_file(
        "RTSTRUCT",
        &[(1, "LV")],
        vec![(1, vec![contour("CLOSED_PLANAR", "1\\2\\abc")])],
    );
    assert!(message(&text).contains("not a list of numbers"));
    let only_points = rt_file(
        "RTSTRUCT",
        &[(1, "Apex")],
        vec![(1, vec![contour("POINT", "1\\2\\3")])],
    );
    assert!(message(&only_points).contains("without contour points"));
    assert!(message(b"\x08\x00\x05\x00garbage that is no DICOM").contains("DICOM"));
}

#[test]
fn decimal_strings_fit_sixteen_characters() {
    for v in [
        0.0,
        -42.0947,
        1.0 / 3.0,
        -1234.567890123,
        1e-300,
        -6.02e23,
        123456789012.5,
    ] {
        let s = ds(v);
        assert!(s.len() <= 16, "{s}");
        let back: f64 = s.parse().unwrap();
        assert!((back - v).abs() <= 1e-9 * v.abs().max(1.0), "{v} -> {s}");
    }
}

/// The modules PS3.3 A.19.3 makes mandatory are there (pydicom reads a file without them, an IOD
/// validator and importers that follow the frame of reference do not): Type 2 attributes present
/// (empty), one frame of reference named by every ROI, one observation per ROI (MARKER for the
/// landmark ROIs), and UTF-8 declared once a name leaves ASCII.
#[test]
fn written_structure_set_has_the_iods_required_attributes() {
    let bytes = write_rtstruct(&patient1(), "patient1 ED").unwrap();
    const FRAMES: dicom_read::Tag = (0x3006, 0x0010);
    const OBSERVATIONS: dicom_read::Tag = (0x3006, 0x0080);
    let obj = dicom_read::read_file(&bytes, &[FRAMES, OBSERVATIONS]).unwrap();
    let type2 = [
        (0x0008, 0x0020), // StudyDate
        (0x0008, 0x0030), // StudyTime
        (0x0008, 0x0050), // AccessionNumber
        (0x0008, 0x0090), // ReferringPhysicianName
        (0x0008, 0x1070), // OperatorsName
        (0x0010, 0x0030), // PatientBirthDate
        (0x0010, 0x0040), // PatientSex
        (0x0020, 0x0010), // StudyID
        (0x0020, 0x0011), // SeriesNumber
        (0x3006, 0x0008), // StructureSetDate
        (0x3006, 0x0009), // StructureSetTime
    ];
    let missing: Vec<_> = type2.iter().filter(|t| obj.get(**t).is_none()).collect();
    assert!(missing.is_empty(), "missing {missing:04X?}");
    let frames = obj.items(FRAMES);
    assert_eq!(frames.len(), 1);
    let frame = frames[0].text((0x0020, 0x0052)).unwrap();
    assert!(frame.starts_with("2.25.") && frame.len() <= 64, "{frame}");
    let rois = obj.items(tag::STRUCTURE_SET_ROI_SEQUENCE);
    assert_eq!(rois.len(), 10); // 4 surfaces + 6 landmark names
    for roi in rois {
        assert_eq!(roi.text((0x3006, 0x0024)).as_deref(), Some(frame.as_str()));
    }
    let observations: Vec<(i64, i64, Option<String>)> = obj
        .items(OBSERVATIONS)
        .iter()
        .map(|o| {
            let n = |t| o.text(t).unwrap().parse::<i64>().unwrap();
            (
                n((0x3006, 0x0082)),
                n((0x3006, 0x0084)),
                o.text((0x3006, 0x00A4)),
            )
        })
        .collect();
    assert_eq!(observations.len(), 10);
    for (i, (number, roi, kind)) in observations.iter().enumerate() {
        assert_eq!((*number, *roi), (i as i64 + 1, i as i64 + 1));
        let marker = i >= 4;
        assert_eq!(kind.as_deref(), marker.then_some("MARKER"), "ROI {roi}");
    }
    assert!(
        obj.get((0x0008, 0x0005)).is_none(),
        "ASCII names need no character set"
    );
    // A name outside ASCII (Latin-1 and beyond): declared UTF-8, read back the same.
    let mut set = patient1();
    set.contours
        .retain(|c| c.surface.as_deref() == Some("LV_ENDO"));
    for c in &mut set.contours {
        c.surface = Some("左心室 VENTRÍCULO".into());
    }
    let bytes = write_rtstruct(&set, "patient1 ED").unwrap();
    let obj = dicom_read::read_file(&bytes, &[]).unwrap();
    assert_eq!(obj.text((0x0008, 0x0005)).as_deref(), Some("ISO_IR 192"));
    let back = read_contours("x.dcm", &bytes).unwrap();
    assert_eq!(back.surfaces(), vec!["左心室 VENTRÍCULO"]);
    assert_eq!(back.point_count(), set.point_count());
}
