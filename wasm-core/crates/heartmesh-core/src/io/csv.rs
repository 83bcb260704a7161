//! The canonical CSV of ../shared/data/README.md: a header naming `contour,x,y,z` and
//! optionally `surface` (any order, other names and units as `csv_columns` reads them, extra
//! columns ignored), one row per point, `#` comments, comma, semicolon or tab separated, any
//! encoding and line ends `text` decodes. A header with `x,y,z` but no `contour` column is read
//! like XYZ text: blank lines separate the contours `c1`, `c2`, ... A `slice` column names the
//! contours by slice; a time-frame column keeps one frame (`frames`). A file without a header
//! whose rows read `name,x,y,z[,surface]` (or `x,y,z`, blank lines between the contours) is read
//! with those columns and a warning: scripts often write no header, and the layout is unambiguous.

use super::builder::ContourBuilder;
use super::csv_columns::{parse_header, Columns, IdSource};
use super::frame_choice::FrameChoice;
use super::frames::FrameFilter;
use super::space_tag;
use super::text::{decode, lines, parse_coord};
use crate::contours::ContourSet;
use crate::error::{CoreError, Result};
use crate::geometry::v3;

/// Reads canonical CSV contours (each contour's first time frame, see [`read_csv_frame`]).
pub fn read_csv(bytes: &[u8]) -> Result<ContourSet> {
    read_csv_frame(bytes, None)
}

/// Reads canonical CSV contours; `frame` keeps only the rows of that time frame (by its label:
/// `9`, `ES`) when the file has a frame column (None: each contour's first frame).
pub fn read_csv_frame(bytes: &[u8], frame: Option<&FrameChoice>) -> Result<ContourSet> {
    let text = decode(bytes)?;
    let mut rows = lines(&text);
    let mut header = None;
    // The patient frame a comment states (heartmesh's `# SPACE=LPS`, before the header or after).
    let mut space = None;
    for (line, row) in rows.by_ref() {
        let t = row.trim_start();
        if let Some(c) = t.strip_prefix('#') {
            space = space.or_else(|| space_tag::of_comment(c));
        } else if !t.is_empty() {
            header = Some((line, row));
            break;
        }
    }
    let (header_line, header) =
        header.ok_or_else(|| CoreError::parse(0, "empty file (only comments)"))?;
    let sep = detect_separator(header);
    let mut fields: Vec<&str> = Vec::new();
    split_fields(header, sep, &mut fields);
    let headerless = headerless_columns(&fields, sep, header_line);
    let cols = match &headerless {
        Some(cols) => cols.clone(),
        None => parse_header(&fields, header_line)?,
    };
    let mut b = ContourBuilder::new();
    if let Some(note) = &cols.unit_note {
        b.warn(note.clone());
    }
    if headerless.is_some() {
        let names = ["contour", "x", "y", "z", "surface"];
        let (names, how) = match cols.id {
            IdSource::BlankLines => (&names[1..4], ", blank lines between the contours"),
            _ => (&names[..cols.width], ""),
        };
        b.warn(format!(
            "no header line: columns read as {} (mm){how}; name them in a first line \
             (contour,x,y,z,surface) to say otherwise",
            names.join(", ")
        ));
    }
    // Without a header the first line is a data row.
    let first = headerless.is_some().then_some((header_line, header));
    let mut frames = FrameFilter::new(frame);
    // Numbering of contours in files without a contour column.
    let mut unnamed = 1;
    let mut in_unnamed = false;
    let mut id = String::new();
    for (line, row) in first.into_iter().chain(rows) {
        let t = row.trim_start();
        if t.is_empty() {
            if in_unnamed {
                unnamed += 1;
                in_unnamed = false;
            }
            continue;
        }
        if let Some(c) = t.strip_prefix('#') {
            space = space.or_else(|| space_tag::of_comment(c));
            read_comment(c.trim(), &mut b, line)?;
            continue;
        }
        split_fields(row, sep, &mut fields);
        check_width(&fields, &cols, sep, line)?;
        id.clear();
        match cols.id {
            IdSource::Contour(i) => id.push_str(unquote(fields[i])),
            IdSource::Slice(i) => {
                let slice = unquote(fields[i]);
                if !slice.is_empty() {
                    id.push_str("slice ");
                    id.push_str(slice);
                }
            }
            IdSource::BlankLines => {
                in_unnamed = true;
                id.push_str(&format!("c{unnamed}"));
            }
        }
        if id.is_empty() {
            let name = match cols.id {
                IdSource::Slice(_) => "slice",
                _ => "contour",
            };
            return Err(CoreError::parse(line, format!("column {name:?} is empty")));
        }
        if let Some(i) = cols.frame {
            if !frames.keep(&id, fields.get(i).map_or("", |f| unquote(f))) {
                continue;
            }
        }
        let [sx, sy, sz] = cols.mm_per_unit;
        let x = sx * parse_number(fields[cols.x], sep, line, "x")?;
        let y = sy * parse_number(fields[cols.y], sep, line, "y")?;
        let z = sz * parse_number(fields[cols.z], sep, line, "z")?;
        let surface = cols
            .surface
            .and_then(|i| fields.get(i))
            .map(|s| unquote(s))
            .filter(|s| !s.is_empty());
        b.push(&id, surface, v3(x, y, z), line)?;
    }
    if let Some(e) = frames.nothing_in_wanted() {
        return Err(e);
    }
    for w in frames.warnings("contour") {
        b.warn(w);
    }
    if let (Some(want), None) = (frame, cols.frame) {
        b.warn(format!(
            "the file has no time-frame column, so frame {want} was not applied: all its rows read"
        ));
    }
    if b.total() == 0 {
        return Err(CoreError::parse(
            header_line,
            "no data rows after the header",
        ));
    }
    let mut set = b.finish()?;
    set.time_frames = frames.time_frames();
    set.coordinate_system = space;
    Ok(set)
}

/// Refuses a row shorter than the columns it needs, or carrying values beyond the header's
/// columns: those are not data the header names, and with a comma separator they are usually
/// decimal commas (`-32,8` read as two fields), which would otherwise shift every coordinate.
/// Empty fields past the header (a separator at the end of every row) are fine.
fn check_width(fields: &[&str], cols: &Columns, sep: char, line: usize) -> Result<()> {
    if fields.len() <= cols.last_needed() {
        return Err(CoreError::parse(
            line,
            format!(
                "row has {} fields but the header has {} columns ({})",
                fields.len(),
                cols.width,
                missing_name(cols, fields.len())
            ),
        ));
    }
    let surplus = fields.get(cols.width..).unwrap_or(&[]);
    if surplus.iter().any(|f| !unquote(f).is_empty()) {
        // Decimal commas split every number in two whole ones: "-32,83557" -> "-32", "83557".
        let id = match cols.id {
            IdSource::Contour(i) | IdSource::Slice(i) => Some(i),
            IdSource::BlankLines => None,
        };
        let whole = |f: &str| {
            let f = unquote(f);
            let digits = f.strip_prefix(['-', '+']).unwrap_or(f);
            !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit())
        };
        let split_numbers = fields
            .iter()
            .enumerate()
            .filter(|(k, _)| Some(*k) != id && cols.surface != Some(*k))
            .all(|(_, f)| unquote(f).is_empty() || whole(f));
        let hint = if sep == ',' && split_numbers {
            "; decimal commas with \",\" between the fields? Then separate the fields with \";\""
        } else {
            "; name every column in the header, or remove the values past it"
        };
        return Err(CoreError::parse(
            line,
            format!(
                "row has {} fields but the header names {} columns{hint}",
                fields.len(),
                cols.width
            ),
        ));
    }
    Ok(())
}

/// The two comments heartmesh writes itself: `# piece ...` starts a new piece of the next contour
/// (so that pieces survive a round trip), `# landmark NAME x y z` is a named point.
fn read_comment(c: &str, b: &mut ContourBuilder, line: usize) -> Result<()> {
    if c.starts_with("piece") {
        b.break_run();
    } else if let Some(rest) = c.strip_prefix("landmark ") {
        let f: Vec<&str> = rest.split_whitespace().collect();
        if f.len() == 4 {
            let x = parse_coord(f[1], line, "landmark x")?;
            let y = parse_coord(f[2], line, "landmark y")?;
            let z = parse_coord(f[3], line, "landmark z")?;
            b.landmark(f[0], v3(x, y, z), line)?;
        }
    }
    Ok(())
}

/// Tab if the header has one, else semicolon if it has one, else comma.
fn detect_separator(header: &str) -> char {
    if header.contains('\t') {
        '\t'
    } else if header.contains(';') {
        ';'
    } else {
        ','
    }
}

/// The columns of a file whose first line is already data, when its layout leaves no doubt:
/// `name,x,y,z` or `name,x,y,z,surface` (a name that is no number, then three numbers, then a name),
/// or `x,y,z` (three numbers). Anything else (four numbers: a slice index or a frame?) needs a
/// header, and [`parse_header`] says so.
fn headerless_columns(fields: &[&str], sep: char, line: usize) -> Option<Columns> {
    let number = |f: &str| parse_number(f, sep, line, "x").is_ok();
    let name = |f: &str| !unquote(f).is_empty() && !number(f);
    let (id, x) = match fields.len() {
        3 if fields.iter().all(|f| number(f)) => (IdSource::BlankLines, 0),
        4 | 5 if name(fields[0]) && fields[1..4].iter().all(|f| number(f)) => {
            if fields.len() == 5 && !name(fields[4]) {
                return None;
            }
            (IdSource::Contour(0), 1)
        }
        _ => return None,
    };
    Some(Columns {
        id,
        x,
        y: x + 1,
        z: x + 2,
        surface: (fields.len() == 5).then_some(4),
        frame: None,
        width: fields.len(),
        mm_per_unit: [1.0; 3],
        unit_note: None,
    })
}

/// Name of the first required column a short row lacks, for the message.
fn missing_name(cols: &Columns, have: usize) -> String {
    let id = match cols.id {
        IdSource::Contour(i) => (i, "contour"),
        IdSource::Slice(i) => (i, "slice"),
        IdSource::BlankLines => (usize::MAX, "contour"),
    };
    let mut named = [id, (cols.x, "x"), (cols.y, "y"), (cols.z, "z")];
    named.sort();
    named
        .iter()
        .find(|(i, _)| *i >= have)
        .map(|(i, n)| format!("column {n:?} would be field {}", i + 1))
        .unwrap_or_default()
}

/// A coordinate; with `;` or tab separators a decimal comma (`1,5`) is accepted too.
fn parse_number(field: &str, sep: char, line: usize, column: &str) -> Result<f64> {
    let what = format!("column {column:?}");
    let f = unquote(field);
    if sep != ',' && f.matches(',').count() == 1 && !f.contains('.') {
        if let Ok(v) = parse_coord(&f.replace(',', "."), line, &what) {
            return Ok(v);
        }
    }
    parse_coord(f, line, &what)
}

/// Splits a row; double-quoted fields may contain the separator (`""` is a literal quote).
pub(crate) fn split_fields<'a>(row: &'a str, sep: char, out: &mut Vec<&'a str>) {
    out.clear();
    let mut start = 0;
    let mut in_quotes = false;
    for (i, ch) in row.char_indices() {
        if ch == '"' {
            in_quotes = !in_quotes;
        } else if ch == sep && !in_quotes {
            out.push(&row[start..i]);
            start = i + ch.len_utf8();
        }
    }
    out.push(&row[start..]);
}

/// Trims spaces and surrounding quotes.
pub(crate) fn unquote(field: &str) -> &str {
    let f = field.trim();
    f.strip_prefix('"')
        .and_then(|s| s.strip_suffix('"'))
        .unwrap_or(f)
        .trim()
}

/// Writes contours as canonical CSV (`contour,x,y,z[,surface][,distance]`); every piece after the
/// first is preceded by a comment so that pieces stay apart when read back (an id that reappears
/// after another id is a new piece, so consecutive pieces are separated by a `# piece` marker and a
/// repeated id is not enough on its own); landmarks become `# landmark` comments, and the patient
/// frame, when the set has one, a first `# SPACE=LPS` (or `RAS`) line that the reader takes back.
///
/// `distances` holds one value per point in contour, piece, point order (as
/// `Reconstruction::contour_distances().per_point`).
pub fn write_csv(set: &ContourSet, distances: Option<&[f64]>) -> Result<Vec<u8>> {
    use super::{fmt_num, fmt_point};
    if let Some(d) = distances {
        if d.len() != set.point_count() {
            return Err(CoreError::Io(format!(
                "{} distances for {} contour points",
                d.len(),
                set.point_count()
            )));
        }
    }
    let with_surface = set.contours.iter().any(|c| c.surface.is_some());
    // The patient frame, where the reader (and 3D Slicer's exports) put it: a comment first.
    let mut out = set
        .coordinate_system
        .map_or(String::new(), |s| format!("# SPACE={}\n", s.name()));
    out.push_str("contour,x,y,z");
    if with_surface {
        out.push_str(",surface");
    }
    if distances.is_some() {
        out.push_str(",distance");
    }
    out.push('\n');
    let mut k = 0;
    for c in &set.contours {
        let id = csv_field(&c.id);
        for (pi, piece) in c.pieces.iter().enumerate() {
            if pi > 0 {
                out.push_str(&format!(
                    "# piece {} of {}\n",
                    pi + 1,
                    c.id.replace('\n', " ")
                ));
            }
            let mut pts: Vec<_> = piece.points.clone();
            // A closed ring is written with its first point repeated, so that the closed-ring
            // heuristic of the reader recognises it again whatever the spacing.
            if piece.closed && pts.len() >= 3 {
                pts.push(pts[0]);
            }
            for (j, p) in pts.iter().enumerate() {
                out.push_str(&format!("{id},{}", fmt_point(p, ",")));
                if with_surface {
                    out.push(',');
                    out.push_str(&csv_field(c.surface.as_deref().unwrap_or("")));
                }
                if let Some(d) = distances {
                    // The repeated closing point has the first point's distance.
                    let idx = if j < piece.points.len() { k + j } else { k };
                    out.push(',');
                    out.push_str(&fmt_num(d[idx]));
                }
                out.push('\n');
            }
            k += piece.points.len();
        }
    }
    for (name, p) in &set.landmarks {
        out.push_str(&format!(
            "# landmark {} {}
",
            name.replace(char::is_whitespace, "_"),
            fmt_point(p, " ")
        ));
    }
    Ok(out.into_bytes())
}

/// Quotes a field when it holds a separator, a quote or surrounding spaces.
fn csv_field(s: &str) -> String {
    if s.contains([',', ';', '\t', '"', '\n', '\r']) || s.trim() != s {
        format!("\"{}\"", s.replace('"', "\"\"").replace(['\n', '\r'], " "))
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(s: &str) -> Result<ContourSet> {
        read_csv(s.as_bytes())
    }

    #[test]
    fn columns_in_any_order_with_surface() {
        let set = read(
            "# made by hand\nsurface,z,contour,y,x,extra\nLV_ENDO,1,a,2,3,foo\nLV_ENDO,1,a,2,4,foo\n",
        )
        .unwrap();
        assert_eq!(set.contours.len(), 1);
        let c = &set.contours[0];
        assert_eq!(c.surface.as_deref(), Some("LV_ENDO"));
        assert_eq!(c.first_line, 3);
        assert_eq!(c.pieces[0].points[1], v3(4.0, 2.0, 1.0));
    }

    /// A contour with blank frame cells (drawn once for the sequence) is read with every frame,
    /// the frames listed are the others (none called ""), and a note says so; `-0` is frame 0.
    #[test]
    fn blank_frame_cells_are_in_every_frame() {
        let csv = "contour,x,y,z,frame\na,0,0,0,-0\na,1,0,0,0\na,0,0,5,5\na,1,0,5,5\n\
                   lid,0,0,9,\nlid,1,0,9,\n";
        for frame in [None, Some(FrameChoice::from(5))] {
            let set = read_csv_frame(csv.as_bytes(), frame.as_ref()).unwrap();
            let ids: Vec<&str> = set.contours.iter().map(|c| c.id.as_str()).collect();
            assert_eq!(ids, ["a", "lid"]);
            assert_eq!(set.time_frames.unwrap().frames, ["0", "5"]);
            assert!(
                set.warnings
                    .iter()
                    .any(|w| w.starts_with("2 points have no time frame")),
                "{:?}",
                set.warnings
            );
        }
    }

    /// A frame column: the set lists the frames and which was read; a file without one has no
    /// frames to list (no picker), and its set is as before.
    #[test]
    fn frame_columns_list_their_frames() {
        let two = "contour,x,y,z,frame\na,0,0,0,0\na,1,0,0,0\na,0,0,5,5\na,1,0,5,5\n";
        let set = read(two).unwrap();
        let t = set.time_frames.unwrap();
        assert_eq!(
            (t.frames.as_slice(), t.read.as_slice()),
            (
                &["0".to_string(), "5".to_string()][..],
                &["0".to_string()][..]
            )
        );
        assert!(t.sequence && !t.chosen && t.left_out == 2);
        let five = read_csv_frame(two.as_bytes(), Some(&5.into())).unwrap();
        assert_eq!(five.contours[0].pieces[0].points[0], v3(0.0, 0.0, 5.0));
        assert_eq!(five.time_frames.unwrap().read, ["5"]);
        assert_eq!(
            read("contour,x,y,z\na,0,0,0\na,1,0,0\n")
                .unwrap()
                .time_frames,
            None
        );
    }

    /// Patient 1's ED and ES CSVs in one file with a `phase` column of text labels: ED is read
    /// by default, and ES (asked for in any case) reads exactly the ES file's contours.
    #[test]
    fn a_phase_column_of_text_reads_either_phase() {
        let dir = "contours/bivme-example-patient1/";
        let text =
            |name: &str| String::from_utf8(super::super::sample(&format!("{dir}{name}"))).unwrap();
        let (ed, es) = (text("patient1-ED.csv"), text("patient1-ES.csv"));
        let mut both = String::from("contour,x,y,z,surface,phase\n");
        for (rows, label) in [(&ed, "ED"), (&es, "ES")] {
            for row in rows.lines().skip(1).filter(|r| !r.is_empty()) {
                both.push_str(&format!("{row},{label}\n"));
            }
        }
        let first = read(&both).unwrap();
        let t = first.time_frames.clone().unwrap();
        assert_eq!(t.frames, ["ED", "ES"]);
        assert_eq!(
            (t.read.as_slice(), t.sequence),
            (&["ED".to_string()][..], true)
        );
        assert_eq!(t.left_out, es.lines().count() - 1);
        let curves = |s: &ContourSet| -> Vec<(String, usize)> {
            s.contours
                .iter()
                .map(|c| (c.id.clone(), c.point_count()))
                .collect()
        };
        assert_eq!(curves(&first), curves(&read(&ed).unwrap()));
        // The same curves, point for point (their lines in the file differ).
        let unlined = |s: ContourSet| -> Vec<crate::contours::Contour> {
            s.contours
                .into_iter()
                .map(|c| crate::contours::Contour { first_line: 0, ..c })
                .collect()
        };
        let alone = unlined(read(&es).unwrap());
        assert_eq!(alone.len(), 35);
        for asked in ["ES", "es", " Es "] {
            let want = FrameChoice::new(asked);
            let got = read_csv_frame(both.as_bytes(), want.as_ref()).unwrap();
            assert!(!got.warnings.iter().any(|w| w.contains("time frames")));
            let t = got.time_frames.clone().unwrap();
            assert_eq!(
                (t.read.as_slice(), t.chosen),
                (&["ES".to_string()][..], true)
            );
            assert!(unlined(got) == alone, "{asked:?}");
        }
        let e = read_csv_frame(both.as_bytes(), FrameChoice::new("9").as_ref()).unwrap_err();
        assert_eq!(
            e.to_string(),
            "no contour points in frame 9 (frames in the file: ED, ES)"
        );
    }

    #[test]
    fn no_contour_column_uses_blank_lines() {
        let set = read("x,y,z\n0,0,0\n1,0,0\n\n\n0,0,5\n1,0,5\n1,1,5\n").unwrap();
        assert_eq!(set.contours.len(), 2);
        assert_eq!(set.contours[1].id, "c2");
        assert_eq!(set.contours[1].point_count(), 3);
        assert_eq!(set.contours[1].first_line, 6);
    }

    #[test]
    fn separators_bom_crlf_blank_lines() {
        let s = "\u{feff}contour;x;y;z\r\n\r\na;1,5;2;3\r\na;1;2;3\r\n";
        let set = read(s).unwrap();
        assert_eq!(set.point_count(), 2);
        assert_eq!(set.contours[0].pieces[0].points[0].x, 1.5);
        let set = read("contour\tx\ty\tz\nb\t1\t2\t3\n").unwrap();
        assert_eq!(set.contours[0].id, "b");
        assert_eq!(set.contours[0].surface, None);
    }

    #[test]
    fn values_past_the_header_are_refused_with_the_likely_cause() {
        let e = read("contour,x,y,z\na,-32,8,27,4,35,0\n").unwrap_err();
        assert_eq!(e.line(), Some(2));
        assert!(e.to_string().ends_with("row has 7 fields but the header names 4 columns; decimal commas with \",\" between the fields? Then separate the fields with \";\""), "{e}");
        let e = read("contour,x,y,z\na,1.5,2,3,LV_ENDO\n").unwrap_err();
        assert!(e.to_string().ends_with("row has 5 fields but the header names 4 columns; name every column in the header, or remove the values past it"), "{e}");
        // Empty fields past the header (a separator closing every row) are fine.
        assert_eq!(read("contour,x,y,z\na,1,2,3,,\n").unwrap().point_count(), 1);
    }

    #[test]
    fn a_file_without_header_is_read_when_its_layout_is_unambiguous() {
        // name,x,y,z: the first line is data (line 1), and a warning says how it was read.
        let set = read("a,1,2,3\na,4,5,6\nb,7,8,9.5\n").unwrap();
        assert_eq!(set.contours.len(), 2);
        assert_eq!(set.contours[0].first_line, 1);
        assert_eq!(set.contours[0].point_count(), 2);
        assert_eq!(set.contours[1].points().next().unwrap().z, 9.5);
        assert!(
            set.warnings
                .iter()
                .any(|w| w.starts_with("no header line: columns read as contour, x, y, z (mm)")),
            "{:?}",
            set.warnings
        );
        // name,x,y,z,surface, semicolons and decimal commas (a European spreadsheet).
        let set = read("a;1,5;2;3;LV_ENDO\nb;4;5;6,25;RV_ENDO\n").unwrap();
        assert_eq!(set.contours[0].surface.as_deref(), Some("LV_ENDO"));
        assert_eq!(set.contours[0].points().next().unwrap().x, 1.5);
        assert_eq!(set.contours[1].points().next().unwrap().z, 6.25);
        // x,y,z: blank lines separate the contours.
        let set = read("1,2,3\n4,5,6\n\n7,8,9\n").unwrap();
        assert_eq!(set.contours.len(), 2);
        // A bad row is still named by its line.
        let e = read("a,1,2,3\na,1,x,3\n").unwrap_err();
        assert_eq!(e.line(), Some(2));
        // Four numbers (a slice index? a frame?) or a name too few still need a header.
        assert!(read("1,2,3,4\n")
            .unwrap_err()
            .to_string()
            .contains("header missing"));
        assert!(read("a,1,2\n").is_err());
        assert!(read("a,1,2,3,4\n").is_err());
    }

    #[test]
    fn errors_name_line_and_column() {
        let e = read("contour,x,y,z\na,1,2,3\na,1,oops,3\n").unwrap_err();
        assert_eq!(e.line(), Some(3));
        assert!(e.to_string().contains("column \"y\""), "{e}");
        assert!(e.to_string().contains("oops"), "{e}");
        let e = read("contour,x,y,z\na,1,2,NaN\n").unwrap_err();
        assert_eq!(e.line(), Some(2));
        assert!(e.to_string().contains("column \"z\""), "{e}");
        let e = read("contour,x,z\na,1,2\n").unwrap_err();
        assert!(e.to_string().contains("missing column \"y\""), "{e}");
        let e = read("1,2,3,4\n").unwrap_err();
        assert!(e.to_string().contains("header missing"), "{e}");
        let e = read("contour,x,y,z\na,1,2\n").unwrap_err();
        assert!(e.to_string().contains("column \"z\""), "{e}");
        assert_eq!(read("").unwrap_err().code(), "parse");
        assert!(read("contour,x,y,z\n# nothing\n").is_err());
    }

    #[test]
    fn writer_round_trips_pieces_rings_landmarks_distances() {
        let bytes = super::super::sample("contours/bivme-example-patient1/patient1-ED.csv");
        let mut set = read_csv(&bytes).unwrap();
        set.landmarks.push(("APEX_POINT".into(), v3(1.0, 2.0, 3.5)));
        let d: Vec<f64> = (0..set.point_count()).map(|i| i as f64 * 0.01).collect();
        let out = write_csv(&set, Some(&d)).unwrap();
        let back = read_csv(&out).unwrap();
        assert_eq!(back.contours.len(), set.contours.len());
        for (a, b) in back.contours.iter().zip(&set.contours) {
            assert_eq!((&a.id, &a.surface), (&b.id, &b.surface));
            assert!(a.pieces == b.pieces, "pieces of {} differ", a.id);
        }
        assert_eq!(back.landmarks, set.landmarks);
        let text = String::from_utf8(out).unwrap();
        assert!(text.starts_with("contour,x,y,z,surface,distance\n"));
        assert!(write_csv(&set, Some(&d[1..])).is_err());
    }

    #[test]
    fn the_patient_frame_goes_round_in_a_comment() {
        use crate::contours::CoordinateSystem::{Lps, Ras};
        let bytes = super::super::sample("contours/bivme-example-patient1/patient1-ED.csv");
        let mut set = read_csv(&bytes).unwrap();
        assert_eq!(
            set.coordinate_system, None,
            "a CSV without the comment says nothing"
        );
        assert!(!String::from_utf8(write_csv(&set, None).unwrap())
            .unwrap()
            .contains("SPACE"));
        set.coordinate_system = Some(Lps);
        let out = write_csv(&set, None).unwrap();
        assert!(String::from_utf8_lossy(&out).starts_with("# SPACE=LPS\ncontour,x,y,z,surface\n"));
        let back = read_csv(&out).unwrap();
        assert_eq!(back.coordinate_system, Some(Lps));
        // The same contours (a line further down the file).
        assert_eq!(back.contours.len(), set.contours.len());
        for (a, b) in back.contours.iter().zip(&set.contours) {
            assert!(a.id == b.id && a.pieces == b.pieces, "{} differs", a.id);
        }
        // The app's distances CSV (comments before the header), after it, and Slicer's wording.
        for (text, frame) in [
            (
                "# heartmesh 0.1.0 | x.csv\n# SPACE=RAS\ncontour,x,y,z\nc,0,0,0\nc,1,0,0\n",
                Some(Ras),
            ),
            ("contour,x,y,z\n# SPACE=lps\nc,0,0,0\nc,1,0,0\n", Some(Lps)),
            (
                "# CoordinateSystem = RAS\ncontour,x,y,z\nc,0,0,0\nc,1,0,0\n",
                Some(Ras),
            ),
            (
                "# CoordinateSystem = 0\ncontour,x,y,z\nc,0,0,0\nc,1,0,0\n",
                None,
            ),
            ("# SPACE=XYZ\ncontour,x,y,z\nc,0,0,0\nc,1,0,0\n", None),
        ] {
            assert_eq!(
                read_csv(text.as_bytes()).unwrap().coordinate_system,
                frame,
                "{text}"
            );
        }
    }

    #[test]
    fn surfco_sample() {
        let bytes = super::super::sample("contours/surfco-example.csv");
        let set = read_csv(&bytes).unwrap();
        assert_eq!(set.contours.len(), 8);
        // 3014 rows; the six SAX rings repeat their first point at the end, which is dropped.
        assert_eq!(set.point_count(), 3008);
        let closed = set.contours.iter().filter(|c| c.pieces[0].closed).count();
        assert_eq!(closed, 6, "6 SAX rings closed, 2 LAX curves open");
        assert!(set.warnings.is_empty(), "{:?}", set.warnings);
    }

    #[test]
    fn bivme_sample_two_pieces() {
        let bytes = super::super::sample("contours/bivme-example-patient1/patient1-ED.csv");
        let set = read_csv(&bytes).unwrap();
        assert_eq!(set.contours.len(), 40);
        assert_eq!(set.point_count(), 1791);
        let two: Vec<_> = set
            .contours
            .iter()
            .filter(|c| c.pieces.len() == 2)
            .map(|c| c.id.as_str())
            .collect();
        assert_eq!(two.len(), 2, "{two:?}");
        assert_eq!(set.surfaces().len(), 4);
    }
}
