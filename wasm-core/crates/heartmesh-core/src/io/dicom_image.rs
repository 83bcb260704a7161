//! Where a DICOM image lies in patient coordinates: what contours drawn on it in pixel
//! coordinates (a cvi42 workspace) need to become millimetres.
//!
//! Reference: DICOM PS3.3 C.7.6.2 (Image Plane module: ImagePositionPatient is the centre of the
//! first transmitted pixel, ImageOrientationPatient the directions of its rows and columns,
//! PixelSpacing the distance between rows, then between columns), C.7.6.1 (SOP Instance UID,
//! Instance Number), C.7.3.1 (Series Number), C.7.6.16 / C.8.3.1 (Trigger Time of a cine frame).
//! Only the header is read ([`dicom_read::read_header`]): a slice of each file is enough.

use super::dicom_read::{self, DataSet, Tag};
use crate::error::Result;
use crate::geometry::{v3, Vec3};

mod tag {
    use super::Tag;
    pub const SOP_INSTANCE_UID: Tag = (0x0008, 0x0018);
    pub const SERIES_DESCRIPTION: Tag = (0x0008, 0x103E);
    pub const TRIGGER_TIME: Tag = (0x0018, 0x1060);
    pub const SERIES_NUMBER: Tag = (0x0020, 0x0011);
    pub const INSTANCE_NUMBER: Tag = (0x0020, 0x0013);
    pub const IMAGE_POSITION: Tag = (0x0020, 0x0032);
    pub const IMAGE_ORIENTATION: Tag = (0x0020, 0x0037);
    pub const PIXEL_SPACING: Tag = (0x0028, 0x0030);
}

/// One image's plane and its place in the acquisition.
#[derive(Debug, Clone, PartialEq)]
pub struct ImageGeometry {
    pub uid: String,
    /// Centre of the first pixel (mm).
    pub position: Vec3,
    /// Unit directions of a row (increasing column index) and of a column (increasing row index).
    pub row_dir: Vec3,
    pub col_dir: Vec3,
    /// Distance between the centres of adjacent rows, then of adjacent columns (mm).
    pub pixel_spacing: [f64; 2],
    pub series: Option<i64>,
    pub series_description: Option<String>,
    pub instance: Option<i64>,
    /// Time after the R wave (ms): orders a cine slice's frames.
    pub trigger_ms: Option<f64>,
}

impl ImageGeometry {
    /// The patient-coordinate point of pixel (`column`, `row`), fractional, 0 at the first
    /// pixel's centre.
    pub fn to_patient(&self, column: f64, row: f64) -> Vec3 {
        self.position
            + self.row_dir * (column * self.pixel_spacing[1])
            + self.col_dir * (row * self.pixel_spacing[0])
    }

    /// Unit normal of the image plane.
    pub fn normal(&self) -> Vec3 {
        self.row_dir.cross(&self.col_dir).normalize()
    }
}

/// What stops a file from placing its image.
#[derive(Debug, Clone, PartialEq)]
pub enum NoGeometry {
    /// Not a DICOM file at all.
    NotDicom,
    /// A DICOM file without an image plane (a DICOMDIR, a report, a structure set), naming the
    /// first element missing; `uid` when the file had one.
    Missing {
        uid: Option<String>,
        element: &'static str,
    },
    /// An element is there but unusable (wrong count of numbers, a degenerate orientation).
    Invalid { uid: String, why: String },
}

fn int(set: &DataSet, t: Tag) -> Option<i64> {
    set.text(t)?.trim().parse().ok()
}

/// Reads the image plane from a DICOM file, or from its first bytes (headers only).
pub fn image_geometry(bytes: &[u8]) -> std::result::Result<ImageGeometry, NoGeometry> {
    if !super::rtstruct::is_dicom(bytes) {
        return Err(NoGeometry::NotDicom);
    }
    let set: Result<DataSet> = dicom_read::read_header(bytes, &[]);
    let Ok(set) = set else {
        return Err(NoGeometry::NotDicom);
    };
    let uid = set.text(tag::SOP_INSTANCE_UID);
    let missing = |element| NoGeometry::Missing {
        uid: uid.clone(),
        element,
    };
    let Some(id) = uid.clone() else {
        return Err(missing("SOPInstanceUID (0008,0018)"));
    };
    let invalid = |why: &str| NoGeometry::Invalid {
        uid: id.clone(),
        why: why.to_string(),
    };
    let position = set
        .numbers(tag::IMAGE_POSITION)
        .ok_or_else(|| missing("ImagePositionPatient (0020,0032)"))?;
    let orientation = set
        .numbers(tag::IMAGE_ORIENTATION)
        .ok_or_else(|| missing("ImageOrientationPatient (0020,0037)"))?;
    let spacing = set
        .numbers(tag::PIXEL_SPACING)
        .ok_or_else(|| missing("PixelSpacing (0028,0030)"))?;
    let [x, y, z]: [f64; 3] = position[..]
        .try_into()
        .map_err(|_| invalid("ImagePositionPatient needs 3 numbers"))?;
    let [r1, r2, r3, c1, c2, c3]: [f64; 6] = orientation[..]
        .try_into()
        .map_err(|_| invalid("ImageOrientationPatient needs 6 numbers"))?;
    let [dr, dc]: [f64; 2] = spacing[..]
        .try_into()
        .map_err(|_| invalid("PixelSpacing needs 2 numbers"))?;
    let (row, col) = (v3(r1, r2, r3), v3(c1, c2, c3));
    if row.norm() < 1e-6
        || col.norm() < 1e-6
        || row.normalize().cross(&col.normalize()).norm() < 0.5
    {
        return Err(invalid(
            "ImageOrientationPatient's directions are degenerate",
        ));
    }
    if !(dr > 0.0 && dc > 0.0) {
        return Err(invalid("PixelSpacing is not positive"));
    }
    Ok(ImageGeometry {
        uid: id,
        position: v3(x, y, z),
        row_dir: row.normalize(),
        col_dir: col.normalize(),
        pixel_spacing: [dr, dc],
        series: int(&set, tag::SERIES_NUMBER),
        series_description: set.text(tag::SERIES_DESCRIPTION),
        instance: int(&set, tag::INSTANCE_NUMBER),
        trigger_ms: set
            .numbers(tag::TRIGGER_TIME)
            .and_then(|v| v.first().copied()),
    })
}
