//! 3D Slicer's legacy point list file (`.fcsv`, "Markups fiducial file"): what Slicer wrote before
//! its JSON markups (4.11) and still writes on request. Before curves existed, a contour drawn in
//! Slicer was a point list clicked along it, one list (one file) per contour; curves saved in this
//! format are their control points too. The file says neither which, nor whether a curve closes.
//!
//! A file becomes the markup Slicer itself makes of it when it loads one and saves it as
//! `.mrk.json`: a point list (`Fiducial`) named by the file, with each row's label and position
//! in the file's frame. The markups reader then decides, as for any point list, whether its points
//! are landmarks or a contour ([`super::point_list_is_contour`]).
//!
//! Layout (Slicer 4.4-5.x):
//! ```text
//! # Markups fiducial file version = 4.11
//! # CoordinateSystem = LPS            (4.11 on: LPS or RAS; before: 0 = RAS, 1 = LPS)
//! # columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID
//! 1,-13.22,2.25,-34.68,0,0,0,1,1,1,0,LV_ENDO_3-1,,vtkMRMLScalarVolumeNode1
//! ```
//! Columns come from the `# columns` line when there is one (the positions above otherwise); a
//! description holding commas is double-quoted; Slicer 5 adds two unnamed fields at the end of
//! each row, passed over. A file without a `CoordinateSystem` line is RAS, the only frame the
//! versions that wrote none used.

use serde_json::Value;

use crate::error::{CoreError, Result};
use crate::io::csv::{split_fields, unquote};
use crate::io::text::{decode, head, lines, parse_coord, quote};

/// How many of a file's first lines are looked into for its header.
const HEADER_LINES: usize = 8;

/// Where the columns are when the file has no `# columns` line (Slicer's own order).
const DEFAULT_COLUMNS: [&str; 14] = [
    "id",
    "x",
    "y",
    "z",
    "ow",
    "ox",
    "oy",
    "oz",
    "vis",
    "sel",
    "lock",
    "label",
    "desc",
    "associatednodeid",
];

/// A header comment's value when its key (compared without spaces and case) is `key`.
fn value_of<'a>(comment: &'a str, key: &str) -> Option<&'a str> {
    let (k, v) = comment.split_once('=')?;
    let k: String = k.chars().filter(|c| !c.is_whitespace()).collect();
    k.eq_ignore_ascii_case(key).then_some(v.trim())
}

/// Whether a file's start is a Slicer point list file: a comment line naming it ("Markups
/// fiducial file version") or a `# columns` line of Slicer's (`id` first, x, y and z among the
/// others) among its first lines.
pub fn is_fcsv(bytes: &[u8]) -> bool {
    let text = head(bytes, 4096);
    let found = lines(&text)
        .take(HEADER_LINES)
        .filter_map(|(_, l)| l.trim_start().strip_prefix('#'))
        .any(|c| {
            c.to_ascii_lowercase().contains("markups fiducial file")
                || value_of(c, "columns").is_some_and(|v| {
                    let names: Vec<String> = v
                        .split(',')
                        .map(|n| n.trim().to_ascii_lowercase())
                        .collect();
                    names.first().is_some_and(|n| n == "id")
                        && ["x", "y", "z"].iter().all(|w| names.iter().any(|n| n == w))
                })
        });
    found
}

/// The frame a `CoordinateSystem` value names: the words, or the numbers Slicer wrote before 4.11.
fn frame_of(value: &str, line: usize) -> Result<&'static str> {
    match value.to_ascii_uppercase().as_str() {
        "RAS" | "0" => Ok("RAS"),
        "LPS" | "1" => Ok("LPS"),
        other => Err(CoreError::parse(
            line,
            format!(
                "coordinate system {} (expected LPS, RAS, 0 for RAS or 1 for LPS)",
                quote(other)
            ),
        )),
    }
}

/// The file as a markups JSON point list named `name`: the markup Slicer writes for it.
pub fn to_markup(name: &str, bytes: &[u8]) -> Result<Value> {
    let text = decode(bytes)?;
    let mut frame = "RAS";
    let mut columns: Vec<String> = DEFAULT_COLUMNS.iter().map(|c| c.to_string()).collect();
    let mut rows = super::PointListRows::new(name);
    let mut fields = Vec::new();
    for (line, row) in lines(&text) {
        let t = row.trim();
        if let Some(comment) = t.strip_prefix('#') {
            if let Some(v) = value_of(comment, "CoordinateSystem") {
                frame = frame_of(v, line)?;
            } else if let Some(v) = value_of(comment, "columns") {
                columns = v
                    .split(',')
                    .map(|n| n.trim().to_ascii_lowercase())
                    .collect();
            }
            continue;
        }
        if t.is_empty() {
            continue;
        }
        let at = |name: &str| columns.iter().position(|c| c == name);
        let (Some(x), Some(y), Some(z)) = (at("x"), at("y"), at("z")) else {
            return Err(CoreError::parse(
                line,
                format!(
                    "the columns line names no x, y and z (found: {})",
                    quote(&columns.join(","))
                ),
            ));
        };
        split_fields(row, ',', &mut fields);
        let needed = x.max(y).max(z) + 1;
        if fields.len() < needed {
            return Err(CoreError::parse(
                line,
                format!(
                    "{} field(s), but the coordinates are fields {}, {} and {} of {}",
                    fields.len(),
                    x + 1,
                    y + 1,
                    z + 1,
                    columns.join(",")
                ),
            ));
        }
        let position = [
            parse_coord(fields[x], line, "x")?,
            parse_coord(fields[y], line, "y")?,
            parse_coord(fields[z], line, "z")?,
        ];
        let label = at("label").and_then(|k| fields.get(k)).map(|f| unquote(f));
        rows.push(label, position, line)?;
    }
    Ok(rows.finish(frame))
}

#[cfg(test)]
mod tests {
    use super::*;

    const SLICER_5: &str = "# Markups fiducial file version = 5.6\n\
        # CoordinateSystem = LPS\n\
        # columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n\
        1,-13.5,2.25,-34.75,0,0,0,1,1,1,0,LV-1,\"a, quoted note\",vtkMRMLScalarVolumeNode1,2,0\n\
        2,-12,3,-34.75,0,0,0,1,1,1,0,,,,2,0\n";

    fn position(m: &Value, k: usize) -> Vec<f64> {
        m["controlPoints"][k]["position"]
            .as_array()
            .map(|a| a.iter().filter_map(Value::as_f64).collect())
            .unwrap_or_default()
    }

    #[test]
    fn rows_give_labelled_points_in_the_stated_frame() {
        assert!(is_fcsv(SLICER_5.as_bytes()));
        let m = to_markup("LV_ENDO_3", SLICER_5.as_bytes()).unwrap();
        assert_eq!(m["type"], "Fiducial");
        assert_eq!(m["name"], "LV_ENDO_3");
        assert_eq!(m["coordinateSystem"], "LPS");
        assert_eq!(position(&m, 0), vec![-13.5, 2.25, -34.75]);
        assert_eq!(position(&m, 1), vec![-12.0, 3.0, -34.75]);
        // A quoted description's comma does not shift the label; an empty label is numbered.
        assert_eq!(m["controlPoints"][0]["label"], "LV-1");
        assert_eq!(m["controlPoints"][1]["label"], "LV_ENDO_3-2");
    }

    #[test]
    fn older_files_state_the_frame_by_number_or_not_at_all() {
        let old = "# Markups fiducial file version = 4.6\n# CoordinateSystem = 1\n\
                   vtkMRMLMarkupsFiducialNode_0,1,2,3,0,0,0,1,1,1,0,F-1,,\n";
        let m = to_markup("F", old.as_bytes()).unwrap();
        assert_eq!(m["coordinateSystem"], "LPS");
        assert_eq!(position(&m, 0), vec![1.0, 2.0, 3.0]);
        let none = "# Markups fiducial file version = 4.4\n1,4,5,6\n";
        let m = to_markup("F", none.as_bytes()).unwrap();
        assert_eq!(m["coordinateSystem"], "RAS");
        assert_eq!(position(&m, 0), vec![4.0, 5.0, 6.0]);
        // Columns in another order (a script's file) are found by name.
        let moved = "# columns = id,label,z,y,x\n1,A,3,2,1\n";
        assert!(is_fcsv(moved.as_bytes()));
        let m = to_markup("F", moved.as_bytes()).unwrap();
        assert_eq!(position(&m, 0), vec![1.0, 2.0, 3.0]);
        assert_eq!(m["controlPoints"][0]["label"], "A");
    }

    #[test]
    fn damaged_rows_are_refused_with_their_line() {
        let cases = [
            (
                "# Markups fiducial file version = 4.11\n# CoordinateSystem = IJK\n1,1,2,3\n",
                2,
                "coordinate system \"IJK\"",
            ),
            (
                "# Markups fiducial file version = 4.11\n1,1,2,3\n2,1,2\n",
                3,
                "3 field(s)",
            ),
            (
                "# Markups fiducial file version = 4.11\n1,1,2,3\n2,1,nan,3\n",
                3,
                "not a finite number",
            ),
            ("# columns = id,a,b,c\n1,1,2,3\n", 2, "names no x, y and z"),
        ];
        for (text, want_line, want) in cases {
            match to_markup("F", text.as_bytes()) {
                Err(CoreError::Parse { line, message }) => {
                    assert_eq!(line, want_line, "{text}: {message}");
                    assert!(message.contains(want), "{text}: {message}");
                }
                other => panic!("{text}: {other:?}"),
            }
        }
        // Plain CSV and point text are no point list files.
        assert!(!is_fcsv(b"contour,x,y,z\nc1,1,2,3\n"));
        assert!(!is_fcsv(b"1 2 3\n4 5 6\n"));
        assert!(!is_fcsv(b"# a comment\n# columns = contour,x,y\n"));
    }
}
