//! What the RT Structure Set IOD (DICOM PS3.3 A.19.3) requires beside the contours: the Patient,
//! General Study and RT Series modules' Type 2 attributes, the Structure Set's date and time and
//! each ROI's frame of reference (Type 1), and the RT ROI Observations module (mandatory).
//! Without them pydicom still reads the file, but an IOD validator (dciodvfy) rejects it and
//! importers that go through the frame of reference or the observations (treatment planning
//! systems, SlicerRT) have nothing to follow. heartmesh knows no patient, study, date or observer:
//! Type 2 attributes are present and empty (PS3.5 7.4: "unknown"), so the same contours still
//! give the same bytes.

use dicom_core::value::DataSetSequence;
use dicom_core::{DataElement, PrimitiveValue, VR};
use dicom_dictionary_std::tags;
use dicom_object::InMemDicomObject;

type Element = DataElement<InMemDicomObject>;

/// Type 2 attributes with no value to give: Patient (C.7.1.1), General Study (C.7.2.1), RT Series
/// (C.8.8.1), Structure Set (C.8.8.5).
pub(super) fn empty_type2() -> Vec<Element> {
    [
        (tags::STUDY_DATE, VR::DA),
        (tags::STUDY_TIME, VR::TM),
        (tags::ACCESSION_NUMBER, VR::SH),
        (tags::REFERRING_PHYSICIAN_NAME, VR::PN),
        (tags::OPERATORS_NAME, VR::PN),
        (tags::PATIENT_BIRTH_DATE, VR::DA),
        (tags::PATIENT_SEX, VR::CS),
        (tags::STUDY_ID, VR::SH),
        (tags::SERIES_NUMBER, VR::IS),
        (tags::STRUCTURE_SET_DATE, VR::DA),
        (tags::STRUCTURE_SET_TIME, VR::TM),
    ]
    .into_iter()
    .map(|(tag, vr)| DataElement::new(tag, vr, PrimitiveValue::Empty))
    .collect()
}

/// The frame of reference every ROI's coordinates are in (the input's patient coordinates):
/// listed once in ReferencedFrameOfReferenceSequence, named by each ROI (Type 1).
pub(super) fn frames_of_reference(frame_uid: &str) -> Element {
    DataElement::new(
        tags::REFERENCED_FRAME_OF_REFERENCE_SEQUENCE,
        VR::SQ,
        DataSetSequence::from(vec![InMemDicomObject::from_element_iter([
            DataElement::new(tags::FRAME_OF_REFERENCE_UID, VR::UI, frame_uid),
        ])]),
    )
}

/// RT ROI Observations (C.8.8.8): one observation per ROI, numbered as the ROIs. The interpreted
/// type is MARKER for landmark ROIs (POINT contours only) and left empty (Type 2) for surfaces,
/// which no RT type (ORGAN, CAVITY, ...) names exactly; no interpreter is known.
pub(super) fn observations(markers: &[bool]) -> Element {
    let items: Vec<InMemDicomObject> = markers
        .iter()
        .enumerate()
        .map(|(i, &marker)| {
            let number = (i + 1).to_string();
            InMemDicomObject::from_element_iter([
                DataElement::new(tags::OBSERVATION_NUMBER, VR::IS, number.as_str()),
                DataElement::new(tags::REFERENCED_ROI_NUMBER, VR::IS, number.as_str()),
                DataElement::new(
                    tags::RTROI_INTERPRETED_TYPE,
                    VR::CS,
                    if marker { "MARKER" } else { "" },
                ),
                DataElement::new(tags::ROI_INTERPRETER, VR::PN, ""),
            ])
        })
        .collect();
    DataElement::new(
        tags::RTROI_OBSERVATIONS_SEQUENCE,
        VR::SQ,
        DataSetSequence::from(items),
    )
}

/// SpecificCharacterSet (Type 1C): needed once any text leaves ASCII (an ROI name such as
/// "VENTRÍCULO"); UTF-8 (ISO_IR 192) holds every name a contour file can carry, where the
/// default repertoire held none of them (Latin-1 names were written as bare 8-bit bytes, others
/// made the write fail).
pub(super) fn character_set<'a>(texts: impl IntoIterator<Item = &'a str>) -> Option<Element> {
    let wide = texts.into_iter().any(|t| !t.is_ascii());
    wide.then(|| DataElement::new(tags::SPECIFIC_CHARACTER_SET, VR::CS, "ISO_IR 192"))
}
