//! DICOM RT Structure Set (RTSTRUCT) contours: read with our bounded reader (`dicom_read`, which
//! never allocates from a declared length), written with the dicom-rs crates.
//!
//! Reference: DICOM PS3.3 C.8.8.5 (Structure Set module: StructureSetROISequence with ROI number
//! and name) and C.8.8.6 (ROI Contour module: ROIContourSequence, each item pointing at an ROI
//! through ReferencedROINumber and holding a ContourSequence of ContourData triplets in patient
//! coordinates, mm). Clinical contouring tools export cardiac delineations this way, so every ROI
//! becomes a surface named after it.
//!
//! Geometric types: CLOSED_PLANAR (and CLOSED_PLANAR_XOR) are rings whatever their end points say,
//! OPEN_PLANAR / OPEN_NONPLANAR stay open, POINT contours become landmarks named after their ROI
//! (an apex marked as a point ROI can then serve as the lower lid). Contours that share a
//! ContourNumber within one ROI are pieces of one contour (the writer uses this for curves stored
//! in several pieces); without a ContourNumber every contour stands alone.
//!
//! Transfer syntaxes read: implicit and explicit VR little endian, explicit VR big endian and the
//! encapsulated (explicit little endian) ones — every RTSTRUCT in practice; deflated is refused.

use std::collections::HashMap;

use dicom_core::value::DataSetSequence;
use dicom_core::{DataElement, PrimitiveValue, VR};
use dicom_dictionary_std::{tags, uids};
use dicom_object::{FileMetaTableBuilder, InMemDicomObject};

mod iod;

use super::builder::ContourBuilder;
use super::dicom_read::{self, DataSet};
use crate::contours::ContourSet;
use crate::error::{CoreError, Result};
use crate::geometry::{v3, Vec3};

/// True when the bytes carry the DICOM magic, after the 128-byte preamble or at the start.
pub fn is_dicom(bytes: &[u8]) -> bool {
    bytes.get(128..132) == Some(b"DICM") || bytes.starts_with(b"DICM")
}

fn err(message: impl Into<String>) -> CoreError {
    CoreError::parse(0, message)
}

/// Tags read from a structure set (PS3.3 C.8.8.5, C.8.8.6, C.12.1).
mod tag {
    use super::dicom_read::Tag;
    pub const SOP_CLASS_UID: Tag = (0x0008, 0x0016);
    pub const MODALITY: Tag = (0x0008, 0x0060);
    pub const STRUCTURE_SET_ROI_SEQUENCE: Tag = (0x3006, 0x0020);
    pub const ROI_NUMBER: Tag = (0x3006, 0x0022);
    pub const ROI_NAME: Tag = (0x3006, 0x0026);
    pub const ROI_CONTOUR_SEQUENCE: Tag = (0x3006, 0x0039);
    pub const CONTOUR_SEQUENCE: Tag = (0x3006, 0x0040);
    pub const CONTOUR_GEOMETRIC_TYPE: Tag = (0x3006, 0x0042);
    pub const NUMBER_OF_CONTOUR_POINTS: Tag = (0x3006, 0x0046);
    pub const CONTOUR_NUMBER: Tag = (0x3006, 0x0048);
    pub const CONTOUR_DATA: Tag = (0x3006, 0x0050);
    pub const REFERENCED_ROI_NUMBER: Tag = (0x3006, 0x0084);
    /// The sequences read, which implicit VR files do not mark as such.
    pub const SEQUENCES: [Tag; 3] = [
        STRUCTURE_SET_ROI_SEQUENCE,
        ROI_CONTOUR_SEQUENCE,
        CONTOUR_SEQUENCE,
    ];
}

/// Parses the DICOM data set with the bounded reader (no allocation sized from a declared
/// length); files without the file meta group are read as implicit VR little endian.
fn parse(bytes: &[u8]) -> Result<DataSet<'_>> {
    if bytes.len() < 4 {
        return Err(err("truncated DICOM file (fewer than 4 bytes)"));
    }
    dicom_read::read_file(bytes, &tag::SEQUENCES)
}

/// The error with its chain of causes on one line (snafu errors keep the detail in sources).
fn flatten(e: &dyn std::error::Error) -> String {
    let mut out = e.to_string();
    let mut src = e.source();
    while let Some(s) = src {
        out.push_str(": ");
        out.push_str(&s.to_string());
        src = s.source();
    }
    out
}

fn int(obj: &DataSet, t: dicom_read::Tag) -> Option<i64> {
    obj.text(t)?.parse().ok()
}

/// How a contour of the file is to be used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Geometry {
    Ring,
    Open,
    Point,
}

fn geometry(kind: Option<&str>) -> Option<Geometry> {
    match kind? {
        "CLOSED_PLANAR" | "CLOSED_PLANAR_XOR" => Some(Geometry::Ring),
        "OPEN_PLANAR" | "OPEN_NONPLANAR" => Some(Geometry::Open),
        "POINT" => Some(Geometry::Point),
        _ => None,
    }
}

/// Reads the contours of an RT Structure Set; ROI names become surfaces.
pub fn read_rtstruct(bytes: &[u8]) -> Result<ContourSet> {
    let obj = parse(bytes)?;
    let modality = obj.text(tag::MODALITY);
    let sop_class = obj.text(tag::SOP_CLASS_UID);
    let roi_contours = obj.items(tag::ROI_CONTOUR_SEQUENCE);
    let is_rt = modality.as_deref() == Some("RTSTRUCT")
        || sop_class.as_deref() == Some(uids::RT_STRUCTURE_SET_STORAGE);
    if !is_rt && roi_contours.is_empty() && super::dicom_image::image_geometry(bytes).is_ok() {
        return Err(err(format!(
            "this is a DICOM image (modality {}), not contours: open the contours drawn on it \
             (an RT structure set, or a cvi42 workspace together with its images)",
            modality.as_deref().unwrap_or("missing"),
        )));
    }
    if !is_rt && roi_contours.is_empty() {
        return Err(err(format!(
            "this DICOM file is not an RT structure set (modality {}, SOP class {}); \
             export the contours as RTSTRUCT",
            modality.as_deref().unwrap_or("missing"),
            sop_class.as_deref().unwrap_or("missing"),
        )));
    }
    if roi_contours.is_empty() {
        return Err(err(
            "RT structure set without contours (ROIContourSequence is missing or empty)",
        ));
    }
    let mut names: HashMap<i64, String> = HashMap::new();
    for roi in obj.items(tag::STRUCTURE_SET_ROI_SEQUENCE) {
        if let (Some(n), Some(name)) = (int(roi, tag::ROI_NUMBER), roi.text(tag::ROI_NAME)) {
            names.insert(n, name);
        }
    }

    let mut b = ContourBuilder::new();
    for (r, roi) in roi_contours.iter().enumerate() {
        let number = int(roi, tag::REFERENCED_ROI_NUMBER);
        let name = match number {
            Some(n) => names.get(&n).cloned().unwrap_or_else(|| format!("ROI {n}")),
            None => format!("ROI item {}", r + 1),
        };
        let contours = roi.items(tag::CONTOUR_SEQUENCE);
        if contours.is_empty() {
            b.warn(format!("ROI {name:?} has no contours"));
        }
        for (k, c) in contours.iter().enumerate() {
            let what = format!("ROI {name:?}, contour {}", k + 1);
            let kind = c.text(tag::CONTOUR_GEOMETRIC_TYPE);
            let points = contour_points(c, &what)?;
            let geom = match geometry(kind.as_deref()) {
                Some(g) => g,
                None if points.len() == 1 => Geometry::Point,
                None => {
                    b.warn(format!(
                        "{what}: geometric type {} not understood; ring or open curve decided \
                         from its ends",
                        kind.as_deref().unwrap_or("missing")
                    ));
                    Geometry::Open
                }
            };
            if let Some(n) = int(c, tag::NUMBER_OF_CONTOUR_POINTS) {
                if n != points.len() as i64 {
                    b.warn(format!(
                        "{what}: NumberOfContourPoints says {n} but ContourData has {} points",
                        points.len()
                    ));
                }
            }
            if geom == Geometry::Point {
                for p in points {
                    b.landmark(&name, p, 0)?;
                }
                continue;
            }
            let id = match int(c, tag::CONTOUR_NUMBER) {
                Some(n) => format!("{name}:{n}"),
                None => format!("{name}:#{}", k + 1),
            };
            let ring = match geometry(kind.as_deref()) {
                Some(Geometry::Ring) => Some(true),
                Some(Geometry::Open) => Some(false),
                _ => None,
            };
            b.push_piece(&id, Some(&name), points, ring, 0)?;
        }
    }
    let mut set = b.finish().map_err(|e| match e {
        CoreError::Parse { line: 0, message } if message == "no contour points found" => {
            err("RT structure set without contour points (only empty ROIs or POINT contours)")
        }
        other => other,
    })?;
    // DICOM's patient coordinates, whichever way the file is read.
    set.coordinate_system = Some(crate::contours::CoordinateSystem::Lps);
    Ok(set)
}

/// ContourData as points, refusing what cannot be a contour.
fn contour_points(c: &DataSet, what: &str) -> Result<Vec<Vec3>> {
    let data = match c.get(tag::CONTOUR_DATA) {
        Some(dicom_read::Value::Bytes(b)) => b,
        Some(_) => return Err(err(format!("{what}: ContourData is not a list of numbers"))),
        None => return Err(err(format!("{what}: ContourData is missing"))),
    };
    let text = dicom_read::decode(data);
    let text = text.trim_matches(|c: char| c.is_whitespace() || c == '\0');
    let mut values = Vec::new();
    if !text.is_empty() {
        for (i, v) in text.split('\\').enumerate() {
            let v = v.trim_matches(|c: char| c.is_whitespace() || c == '\0');
            let x: f64 = v.parse().map_err(|_| {
                err(format!(
                    "{what}: ContourData is not a list of numbers (value {} is {v:?})",
                    i + 1
                ))
            })?;
            values.push(x);
        }
    }
    if values.is_empty() {
        return Err(err(format!("{what}: ContourData is empty")));
    }
    if !values.len().is_multiple_of(3) {
        return Err(err(format!(
            "{what}: ContourData has {} values, not x\\y\\z triplets",
            values.len()
        )));
    }
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(err(format!(
            "{what}: ContourData value {} is not a finite number",
            i + 1
        )));
    }
    Ok(values
        .chunks_exact(3)
        .map(|p| v3(p[0], p[1], p[2]))
        .collect())
}

/// Decimal String value: at most 16 characters (DICOM PS3.5 6.2), shortest form that fits.
fn ds(v: f64) -> String {
    let plain = super::fmt_num(v);
    if plain.len() <= 16 {
        return plain;
    }
    for digits in (1..=10).rev() {
        let s = format!("{v:.digits$}");
        if s.len() <= 16 {
            return s;
        }
        let s = format!("{v:.digits$e}");
        if s.len() <= 16 {
            return s;
        }
    }
    format!("{v:.0e}")
}

fn ds_values(points: &[Vec3]) -> PrimitiveValue {
    PrimitiveValue::Strs(
        points
            .iter()
            .flat_map(|p| [p.x, p.y, p.z])
            .map(ds)
            .collect(),
    )
}

/// A UID under the 2.25 (UUID-derived) root from a hash of the content: the same contours give
/// the same file, which keeps generated test samples reproducible.
fn uid(seed: &[u8], salt: u8) -> String {
    // FNV-1a, 128 bits folded from two 64-bit lanes; uniqueness, not security, is the point.
    let mut a: u64 = 0xcbf2_9ce4_8422_2325;
    let mut c: u64 = 0x8422_2325_cbf2_9ce4 ^ u64::from(salt);
    for &x in seed {
        a = (a ^ u64::from(x)).wrapping_mul(0x0000_0100_0000_01b3);
        c = (c ^ u64::from(x.rotate_left(3))).wrapping_mul(0x0000_0100_0000_01b3);
    }
    let n = (u128::from(a) << 64 | u128::from(c)) >> 1;
    format!("2.25.{n}")
}

/// Writes contours as an RT Structure Set (explicit VR little endian): one ROI per surface
/// (contours without a surface go to ROI "CONTOURS"), closed pieces as CLOSED_PLANAR, open
/// pieces as OPEN_PLANAR, landmarks as POINT ROIs. The pieces of one contour share a
/// ContourNumber so that [`read_rtstruct`] joins them again.
pub fn write_rtstruct(set: &ContourSet, label: &str) -> Result<Vec<u8>> {
    let mut rois: Vec<(String, Vec<InMemDicomObject>)> = Vec::new();
    let mut seed: Vec<u8> = label.as_bytes().to_vec();
    for (k, c) in set.contours.iter().enumerate() {
        let name = c.surface.as_deref().unwrap_or("CONTOURS");
        let i = slot(&mut rois, name);
        for piece in &c.pieces {
            if piece.points.is_empty() {
                continue;
            }
            let kind = if piece.closed {
                "CLOSED_PLANAR"
            } else {
                "OPEN_PLANAR"
            };
            let data = ds_values(&piece.points);
            if let PrimitiveValue::Strs(s) = &data {
                seed.extend(s.iter().take(6).flat_map(|v| v.bytes()));
            }
            rois[i].1.push(InMemDicomObject::from_element_iter([
                DataElement::new(tags::CONTOUR_GEOMETRIC_TYPE, VR::CS, kind),
                DataElement::new(
                    tags::NUMBER_OF_CONTOUR_POINTS,
                    VR::IS,
                    piece.points.len().to_string(),
                ),
                DataElement::new(tags::CONTOUR_NUMBER, VR::IS, (k + 1).to_string()),
                DataElement::new(tags::CONTOUR_DATA, VR::DS, data),
            ]));
        }
    }
    for (name, p) in &set.landmarks {
        let i = slot(&mut rois, name);
        rois[i].1.push(InMemDicomObject::from_element_iter([
            DataElement::new(tags::CONTOUR_GEOMETRIC_TYPE, VR::CS, "POINT"),
            DataElement::new(tags::NUMBER_OF_CONTOUR_POINTS, VR::IS, "1"),
            DataElement::new(tags::CONTOUR_DATA, VR::DS, ds_values(&[*p])),
        ]));
    }
    if rois.is_empty() {
        return Err(CoreError::Io("no contours to write".into()));
    }
    let frame = uid(&seed, 4);
    let structure_set_rois: Vec<InMemDicomObject> = rois
        .iter()
        .enumerate()
        .map(|(i, (name, _))| {
            InMemDicomObject::from_element_iter([
                DataElement::new(tags::ROI_NUMBER, VR::IS, (i + 1).to_string()),
                DataElement::new(
                    tags::REFERENCED_FRAME_OF_REFERENCE_UID,
                    VR::UI,
                    frame.as_str(),
                ),
                DataElement::new(tags::ROI_NAME, VR::LO, name.as_str()),
                DataElement::new(tags::ROI_GENERATION_ALGORITHM, VR::CS, "MANUAL"),
            ])
        })
        .collect();
    // Landmark ROIs hold POINT contours only: a surface's name never becomes a marker.
    let markers: Vec<bool> = rois
        .iter()
        .map(|(name, _)| {
            !set.contours
                .iter()
                .any(|c| c.surface.as_deref().unwrap_or("CONTOURS") == name)
        })
        .collect();
    let charset = iod::character_set(
        rois.iter()
            .map(|(name, _)| name.as_str())
            .chain([short(label).as_str()]),
    );
    let roi_contours: Vec<InMemDicomObject> = rois
        .into_iter()
        .enumerate()
        .map(|(i, (_, contours))| {
            InMemDicomObject::from_element_iter([
                DataElement::new(tags::REFERENCED_ROI_NUMBER, VR::IS, (i + 1).to_string()),
                DataElement::new(
                    tags::CONTOUR_SEQUENCE,
                    VR::SQ,
                    DataSetSequence::from(contours),
                ),
            ])
        })
        .collect();
    let instance = uid(&seed, 1);
    let mut obj = InMemDicomObject::from_element_iter([
        DataElement::new(tags::SOP_CLASS_UID, VR::UI, uids::RT_STRUCTURE_SET_STORAGE),
        DataElement::new(tags::SOP_INSTANCE_UID, VR::UI, instance.as_str()),
        DataElement::new(tags::MODALITY, VR::CS, "RTSTRUCT"),
        DataElement::new(tags::MANUFACTURER, VR::LO, "heartmesh"),
        DataElement::new(tags::PATIENT_NAME, VR::PN, ""),
        DataElement::new(tags::PATIENT_ID, VR::LO, ""),
        DataElement::new(tags::STUDY_INSTANCE_UID, VR::UI, uid(&seed, 2).as_str()),
        DataElement::new(tags::SERIES_INSTANCE_UID, VR::UI, uid(&seed, 3).as_str()),
        DataElement::new(tags::STRUCTURE_SET_LABEL, VR::SH, short(label)),
        DataElement::new(
            tags::STRUCTURE_SET_ROI_SEQUENCE,
            VR::SQ,
            DataSetSequence::from(structure_set_rois),
        ),
        DataElement::new(
            tags::ROI_CONTOUR_SEQUENCE,
            VR::SQ,
            DataSetSequence::from(roi_contours),
        ),
        iod::frames_of_reference(&frame),
        iod::observations(&markers),
    ]);
    obj.extend(iod::empty_type2().into_iter().chain(charset));
    let file = obj
        .with_meta(
            FileMetaTableBuilder::new()
                .transfer_syntax(uids::EXPLICIT_VR_LITTLE_ENDIAN)
                .implementation_class_uid(uid(b"heartmesh", 0))
                .implementation_version_name(short(&format!("HEARTMESH_{}", crate::VERSION))),
        )
        .map_err(|e| CoreError::Io(format!("DICOM meta group: {}", flatten(&e))))?;
    let mut out = Vec::new();
    file.write_all(&mut out)
        .map_err(|e| CoreError::Io(format!("DICOM encoding: {}", flatten(&e))))?;
    Ok(out)
}

/// Index of the ROI called `name`, added at the end when new.
fn slot(rois: &mut Vec<(String, Vec<InMemDicomObject>)>, name: &str) -> usize {
    match rois.iter().position(|(n, _)| n == name) {
        Some(i) => i,
        None => {
            rois.push((name.to_string(), Vec::new()));
            rois.len() - 1
        }
    }
}

/// Structure Set Label is a Short String (16 characters at most).
fn short(label: &str) -> String {
    let s: String = label
        .chars()
        .filter(|c| !c.is_control() && *c != '\\')
        .take(16)
        .collect();
    if s.is_empty() {
        "heartmesh".into()
    } else {
        s
    }
}

#[cfg(test)]
mod tests;
