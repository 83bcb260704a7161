//! The header of a contour CSV: which column holds what, as other tools name them.
//!
//! Spreadsheets and scripts write `X`, `x (mm)`, `x[mm]`, `X_mm` or `Points:0` where the canonical
//! file has `x`, number slices in a `slice` column instead of naming contours, add an unnamed
//! index column (pandas) or a time-frame column. A column's unit, when the header states one, is
//! applied (cm and m to mm) or refused with the reason (pixels), instead of "missing column x".

use crate::error::{CoreError, Result};

/// Where the contour identifier of a row comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IdSource {
    /// A `contour` (or `id`) column: its text is the identifier.
    Contour(usize),
    /// A `slice` column: the slice number names the contour (`slice 3`).
    Slice(usize),
    /// No identifier: blank lines separate the contours `c1`, `c2`, ... (XYZ-like).
    BlankLines,
}

/// Column positions found in the header.
#[derive(Debug, Clone)]
pub struct Columns {
    pub id: IdSource,
    pub x: usize,
    pub y: usize,
    pub z: usize,
    pub surface: Option<usize>,
    /// A time-frame column (`frame`, `time frame`, `phase`, ...): files holding a cine sequence.
    pub frame: Option<usize>,
    /// Number of columns the header declares.
    pub width: usize,
    /// Millimetres per unit of x, y and z (1 unless the header states another unit).
    pub mm_per_unit: [f64; 3],
    /// A note for the user when the header's units were converted.
    pub unit_note: Option<String>,
}

impl Columns {
    /// Index of the last column a data row must have.
    pub fn last_needed(&self) -> usize {
        let id = match self.id {
            IdSource::Contour(i) | IdSource::Slice(i) => i,
            IdSource::BlankLines => 0,
        };
        self.x.max(self.y).max(self.z).max(id)
    }
}

const X: &[&str] = &["x", "points:0", "points_0", "point_x", "pos_x"];
const Y: &[&str] = &["y", "points:1", "points_1", "point_y", "pos_y"];
const Z: &[&str] = &["z", "points:2", "points_2", "point_z", "pos_z"];
/// Names that say the column names the contour (in this order of preference).
const CONTOUR: &[&str] = &[
    "contour",
    "contour_id",
    "contour id",
    "contourid",
    "contour_name",
    "contour name",
    "curve",
    "name",
];
/// A bare `id` names the contour only when nothing else does: exports from databases and
/// dataframes write `id` for the point's own index (`id,contour,x,y,z`, `id,slice,x,y,z`).
const ID: &[&str] = &["id"];
const SLICE: &[&str] = &[
    "slice",
    "slice_id",
    "slice id",
    "sliceid",
    "slice_index",
    "slice_number",
    "slice_no",
];
const SURFACE: &[&str] = &["surface", "structure"];
const FRAME: &[&str] = &[
    "frame",
    "time frame",
    "time_frame",
    "timeframe",
    "frame_id",
    "frame_index",
    "phase",
    "cardiac_phase",
];

/// Reads the header row (already split into `fields`).
pub fn parse_header(fields: &[&str], line: usize) -> Result<Columns> {
    let named: Vec<(String, Option<String>)> = fields.iter().map(|f| column_name(f)).collect();
    let names: Vec<String> = named.iter().map(|(n, _)| n.clone()).collect();
    if !names.is_empty() && names.iter().all(|n| n.parse::<f64>().is_ok()) {
        return Err(CoreError::parse(
            line,
            "header missing: the first line must name the columns, e.g. contour,x,y,z,surface",
        ));
    }
    let find = |wanted: &[&str]| super::text::find_column(&names, wanted);
    let need = |wanted: &[&str]| super::text::need_column(&names, wanted, line);
    let (x, y, z) = (need(X)?, need(Y)?, need(Z)?);
    let mut mm_per_unit = [1.0; 3];
    let mut converted = Vec::new();
    for (k, &col) in [x, y, z].iter().enumerate() {
        let Some(unit) = named[col].1.as_deref() else {
            continue;
        };
        match mm_per(unit) {
            Some(Ok(f)) => {
                mm_per_unit[k] = f;
                if f != 1.0 && !converted.contains(&unit) {
                    converted.push(unit);
                }
            }
            Some(Err(what)) => {
                return Err(CoreError::parse(
                    line,
                    format!(
                        "column {:?} is in {what}; heartmesh works in millimetres: convert \
                         {what} with the image's pixel spacing first",
                        fields[col].trim()
                    ),
                ))
            }
            // An annotation that is no unit ("x (world)"): the column is still x, in mm.
            None => {}
        }
    }
    let id = match (find(CONTOUR), find(SLICE), find(ID)) {
        (Some(i), _, _) => IdSource::Contour(i),
        (None, Some(i), _) => IdSource::Slice(i),
        (None, None, Some(i)) => IdSource::Contour(i),
        (None, None, None) => IdSource::BlankLines,
    };
    Ok(Columns {
        id,
        x,
        y,
        z,
        surface: find(SURFACE),
        frame: find(FRAME),
        width: names.len(),
        mm_per_unit,
        unit_note: (!converted.is_empty()).then(|| {
            format!(
                "coordinates in {} (as the header says) converted to mm",
                converted.join(" and ")
            )
        }),
    })
}

/// (name, unit) of a header field: lower case, quotes and spaces trimmed, and a unit in brackets
/// (`x (mm)`, `x[mm]`) or after `_`, ` ` or `/` (`x_mm`, `x mm`, `x/mm`) split off. A suffix
/// after `_`, ` ` or `/` counts as a unit only when it is one ([`mm_per`]), so that `contour id`
/// and `time_frame` keep their names.
fn column_name(field: &str) -> (String, Option<String>) {
    let f = field.trim();
    let f = f
        .strip_prefix('"')
        .and_then(|s| s.strip_suffix('"'))
        .unwrap_or(f)
        .trim()
        .to_lowercase();
    for (open, close) in [('(', ')'), ('[', ']'), ('{', '}')] {
        if let Some(inner) = f.strip_suffix(close) {
            if let Some(at) = inner.rfind(open) {
                let name = inner[..at].trim().trim_end_matches(['_', ' ', '/']);
                if !name.is_empty() {
                    return (name.to_string(), Some(inner[at + 1..].trim().to_string()));
                }
            }
        }
    }
    if let Some(at) = f.rfind(['_', ' ', '/']) {
        let (name, unit) = (f[..at].trim(), f[at + 1..].trim());
        if !name.is_empty() && mm_per(unit).is_some() {
            return (name.to_string(), Some(unit.to_string()));
        }
    }
    (f, None)
}

/// Millimetres per `unit`: Some(Ok) for a length unit, Some(Err(name)) for image units that need
/// the pixel spacing, None for anything else.
fn mm_per(unit: &str) -> Option<std::result::Result<f64, &'static str>> {
    Some(Ok(match unit {
        "mm" | "millimetre" | "millimetres" | "millimeter" | "millimeters" => 1.0,
        "cm" | "centimetre" | "centimetres" | "centimeter" | "centimeters" => 10.0,
        "m" | "metre" | "metres" | "meter" | "meters" => 1000.0,
        "um" | "µm" | "μm" | "micron" | "microns" => 0.001,
        "px" | "pixel" | "pixels" => return Some(Err("pixels")),
        "vox" | "voxel" | "voxels" => return Some(Err("voxels")),
        _ => return None,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(s: &str) -> Result<Columns> {
        let fields: Vec<&str> = s.split(',').collect();
        parse_header(&fields, 1)
    }

    #[test]
    fn units_in_brackets_and_suffixes_are_split_off() {
        for h in [
            "contour,x (mm),y (mm),z (mm)",
            "contour,X[mm],Y[mm],Z[mm]",
            "contour,X_mm,Y_mm,Z_mm",
            "Contour,X mm,Y mm,Z mm",
            "\"contour\",\"x/mm\",\"y/mm\",\"z/mm\"",
        ] {
            let c = header(h).unwrap_or_else(|e| panic!("{h}: {e}"));
            assert_eq!(
                (c.x, c.y, c.z, c.id),
                (1, 2, 3, IdSource::Contour(0)),
                "{h}"
            );
            assert_eq!(c.mm_per_unit, [1.0; 3], "{h}");
            assert_eq!(c.unit_note, None, "{h}");
        }
    }

    #[test]
    fn other_length_units_scale_and_pixels_are_refused() {
        let c = header("contour,x (cm),y (cm),z (cm)").unwrap();
        assert_eq!(c.mm_per_unit, [10.0; 3]);
        assert_eq!(
            c.unit_note.as_deref(),
            Some("coordinates in cm (as the header says) converted to mm")
        );
        assert_eq!(header("id,x_m,y_m,z_m").unwrap().mm_per_unit, [1000.0; 3]);
        let e = header("contour,x [px],y [px],z [px]").unwrap_err();
        assert_eq!(e.line(), Some(1));
        assert!(e.to_string().contains("\"x [px]\" is in pixels"), "{e}");
        // Not a unit: the name stays whole, and "x (world)" is still x.
        let c = header("contour id,x (world),y,z,time_frame").unwrap();
        assert_eq!((c.id, c.x, c.frame), (IdSource::Contour(0), 1, Some(4)));
    }

    #[test]
    fn slice_index_and_frame_columns() {
        let c = header(",slice,x,y,z,frame").unwrap();
        assert_eq!(
            (c.id, c.x, c.frame, c.width),
            (IdSource::Slice(1), 2, Some(5), 6)
        );
        let c = header("Points:0,Points:1,Points:2").unwrap();
        assert_eq!((c.id, c.x, c.z), (IdSource::BlankLines, 0, 2));
        let c = header("slice,contour,x,y,z").unwrap();
        assert_eq!(
            c.id,
            IdSource::Contour(1),
            "a contour column wins over a slice column"
        );
    }

    #[test]
    fn a_point_index_named_id_gives_way_to_the_contour_or_slice_column() {
        for (h, id) in [
            ("id,contour,x,y,z", IdSource::Contour(1)),
            ("contour,id,x,y,z", IdSource::Contour(0)),
            ("id,slice,x,y,z", IdSource::Slice(1)),
            ("id,x,y,z", IdSource::Contour(0)),
            ("name,x,y,z,surface", IdSource::Contour(0)),
            ("ID,Contour Name,X,Y,Z", IdSource::Contour(1)),
        ] {
            assert_eq!(header(h).unwrap().id, id, "{h}");
        }
    }
}
