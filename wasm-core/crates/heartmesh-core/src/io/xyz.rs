//! Plain point text: three numbers per line (spaces, tabs, commas or semicolons between them),
//! a blank line between contours, `#` comments. Contours are named `c1`, `c2`, ...

use super::builder::ContourBuilder;
use super::text::{decode, lines, parse_coord};
use crate::contours::ContourSet;
use crate::error::{CoreError, Result};
use crate::geometry::v3;

fn fields(row: &str) -> impl Iterator<Item = &str> {
    row.split(|c: char| c.is_whitespace() || c == ',' || c == ';')
        .filter(|f| !f.is_empty())
}

/// True when the first data line is three (or more) numbers.
pub fn looks_like_xyz(text: &str) -> bool {
    let first = lines(text).find(|(_, l)| {
        let t = l.trim_start();
        !t.is_empty() && !t.starts_with('#')
    });
    first.is_some_and(|(_, l)| {
        let f: Vec<&str> = fields(l).collect();
        f.len() >= 3 && f[..3].iter().all(|v| v.parse::<f64>().is_ok())
    })
}

pub fn read_xyz(bytes: &[u8]) -> Result<ContourSet> {
    let text = decode(bytes)?;
    let mut b = ContourBuilder::new();
    let mut k = 1;
    let mut in_contour = false;
    for (line, row) in lines(&text) {
        let t = row.trim_start();
        if t.starts_with('#') {
            continue;
        }
        if t.is_empty() {
            if in_contour {
                k += 1;
                in_contour = false;
            }
            continue;
        }
        let f: Vec<&str> = fields(row).take(4).collect();
        if f.len() < 3 {
            return Err(CoreError::parse(
                line,
                format!("expected 3 coordinates (x y z), found {}", f.len()),
            ));
        }
        let x = parse_coord(f[0], line, "x")?;
        let y = parse_coord(f[1], line, "y")?;
        let z = parse_coord(f[2], line, "z")?;
        b.push(&format!("c{k}"), None, v3(x, y, z), line)?;
        in_contour = true;
    }
    let mut set = b.finish()?;
    // Without a blank line every point is one curve: the run then fails as "too few contours",
    // which does not say why, so the reason travels with the set (the CLI joins the first warning
    // to its error line; the app shows it).
    if let [only] = set.contours.as_slice() {
        let n = only.point_count();
        // First: it explains the other warnings (a path far longer than wide) and the failure.
        set.warnings.insert(
            0,
            format!(
                "no blank line separates contours, so all {n} points were read as one contour \
             (put a blank line between contours, or use CSV with a contour column)"
            ),
        );
    }
    Ok(set)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blank_lines_separate_contours() {
        let s = "# two curves\r\n0 0 0\r\n1,0,0\r\n1\t1\t0\r\n\r\n\r\n0 0 5\r\n1 0 5\r\n";
        assert!(looks_like_xyz(s));
        let set = read_xyz(s.as_bytes()).unwrap();
        assert_eq!(set.contours.len(), 2);
        assert_eq!(set.contours[1].id, "c2");
        assert_eq!(set.contours[1].first_line, 7);
        assert_eq!(set.point_count(), 5);
        assert!(
            !set.warnings.iter().any(|w| w.contains("blank line")),
            "{:?}",
            set.warnings
        );
        let e = read_xyz(b"0 0 0\n1 2\n").unwrap_err();
        assert_eq!(e.line(), Some(2));
        let e = read_xyz(b"0 0 0\n1 2 inf\n").unwrap_err();
        assert!(e.to_string().contains("finite"), "{e}");
    }

    #[test]
    fn one_block_of_points_says_that_blank_lines_separate_contours() {
        let set = read_xyz(b"0 0 0\n1 0 0\n1 1 0\n0 0 5\n1 0 5\n").unwrap();
        assert_eq!(set.contours.len(), 1);
        assert!(
            set.warnings[0].starts_with("no blank line separates contours, so all 5 points"),
            "{:?}",
            set.warnings
        );
    }
}
