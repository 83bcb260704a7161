//! 3D Slicer's control points table (a plain CSV): what Slicer's Markups module writes when a
//! markup's control points are exported to a table and saved, or by
//! `ExportControlPointsToCSV` (LPS unless asked otherwise). One file per markup, named by the
//! user; the header says the frame by its coordinate columns:
//! ```text
//! label,l,p,s,defined,selected,visible,locked,description
//! LV_ENDO_3-1,-13.22,2.25,-34.68,1,1,1,0,
//! ```
//! (`r,a,s` for RAS). Like a legacy point list file ([`super::fcsv`]) it does not say the markup's
//! type, so it becomes a point list named by the file, and the markups reader tells landmarks from
//! a contour ([`super::point_list_is_contour`]). Rows whose `defined` is false are points not
//! placed, skipped as a JSON markup's are.

use serde_json::Value;

use crate::error::{CoreError, Result};
use crate::io::csv::{split_fields, unquote};
use crate::io::text::{data_lines, decode, head, parse_coord, quote};

/// The header's lowercased column names when the first data line is a control points table's
/// header: `label` first, and the three coordinates of one frame; with that frame.
fn header_of(line: &str) -> Option<(Vec<String>, &'static str, [usize; 3])> {
    let mut fields = Vec::new();
    split_fields(line, ',', &mut fields);
    let names: Vec<String> = fields
        .iter()
        .map(|f| unquote(f).to_ascii_lowercase())
        .collect();
    if names.first().map(String::as_str) != Some("label") {
        return None;
    }
    let at = |c: &str| names.iter().position(|n| n == c);
    for (frame, axes) in [("LPS", ["l", "p", "s"]), ("RAS", ["r", "a", "s"])] {
        if let (Some(a), Some(b), Some(c)) = (at(axes[0]), at(axes[1]), at(axes[2])) {
            return Some((names, frame, [a, b, c]));
        }
    }
    None
}

/// Whether a file's start is a Slicer control points table.
pub fn is_points_table(bytes: &[u8]) -> bool {
    let text = head(bytes, 4096);
    let first = data_lines(&text).next().map(|(_, l)| l.to_string());
    first.is_some_and(|l| header_of(&l).is_some())
}

/// Whether a `defined` (or other flag) cell says no: Slicer writes 0/1, a spreadsheet may write
/// false/true.
fn is_false(cell: &str) -> bool {
    matches!(
        unquote(cell).to_ascii_lowercase().as_str(),
        "0" | "false" | "no"
    )
}

/// The table as a markups JSON point list named `name`: the markup Slicer imports from it.
pub fn to_markup(name: &str, bytes: &[u8]) -> Result<Value> {
    let text = decode(bytes)?;
    let mut rows = data_lines(&text);
    let Some((names, frame, xyz)) = rows.next().and_then(|(_, l)| header_of(l)) else {
        return Err(CoreError::parse(
            1,
            "not a Slicer control points table: the header is label and l,p,s or r,a,s",
        ));
    };
    let label = names.iter().position(|n| n == "label");
    let defined = names.iter().position(|n| n == "defined");
    let axes = [&names[xyz[0]], &names[xyz[1]], &names[xyz[2]]];
    let mut list = super::PointListRows::new(name);
    let mut fields = Vec::new();
    for (line, row) in rows {
        split_fields(row, ',', &mut fields);
        if defined
            .and_then(|k| fields.get(k))
            .is_some_and(|c| is_false(c))
        {
            continue;
        }
        let mut position = [0.0; 3];
        for (p, (&k, axis)) in position.iter_mut().zip(xyz.iter().zip(axes)) {
            let cell = fields.get(k).ok_or_else(|| {
                CoreError::parse(
                    line,
                    format!(
                        "{} field(s), but column {} is field {}",
                        fields.len(),
                        quote(axis),
                        k + 1
                    ),
                )
            })?;
            *p = parse_coord(cell, line, axis)?;
        }
        let label = label.and_then(|k| fields.get(k)).map(|f| unquote(f));
        list.push(label, position, line)?;
    }
    Ok(list.finish(frame))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn rows_give_placed_points_in_the_frame_the_columns_say() {
        let lps = "label,l,p,s,defined,selected,visible,locked,description\n\
                   A-1,1.5,2,3,1,1,1,0,\"a, note\"\nA-2,4,5,6,0,1,1,0,\n,7,8,9,true,1,1,0,\n";
        assert!(is_points_table(lps.as_bytes()));
        let m = to_markup("LV_ENDO_3", lps.as_bytes()).unwrap();
        assert_eq!(m["coordinateSystem"], "LPS");
        let points = m["controlPoints"].as_array().unwrap();
        // The second point is not placed (defined 0); the third has no label.
        assert_eq!(points.len(), 2);
        assert_eq!(points[0]["position"], json!([1.5, 2.0, 3.0]));
        assert_eq!(points[1]["label"], "LV_ENDO_3-2");
        let ras = "label,r,a,s,defined,selected,visible,locked,description\nB,1,2,3,1,1,1,0,\n";
        assert_eq!(
            to_markup("B", ras.as_bytes()).unwrap()["coordinateSystem"],
            "RAS"
        );
        // The canonical CSV, point text and a table of other columns are not this.
        assert!(!is_points_table(b"contour,x,y,z\nc1,1,2,3\n"));
        assert!(!is_points_table(b"label,x,y,z\nc1,1,2,3\n"));
        assert!(!is_points_table(b"1 2 3\n"));
    }

    #[test]
    fn damaged_rows_are_refused_with_their_line() {
        for (text, want_line, want) in [
            (
                "label,l,p,s,defined\nA,1,2,3,1\nB,1,2\n",
                3,
                "column \"s\" is field 4",
            ),
            (
                "label,l,p,s,defined\nA,1,x,3,1\n",
                2,
                "p: \"x\" is not a number",
            ),
        ] {
            match to_markup("F", text.as_bytes()) {
                Err(CoreError::Parse { line, message }) => {
                    assert_eq!(line, want_line, "{text}: {message}");
                    assert!(message.contains(want), "{text}: {message}");
                }
                other => panic!("{text}: {other:?}"),
            }
        }
    }
}
