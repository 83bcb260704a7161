//! The patient frame a mesh file says it is in, read back from where 3D Slicer (and heartmesh's
//! own writers, [`super::tagged_comment`]) put it: a `SPACE=LPS` / `SPACE=RAS` token in the PLY
//! comments, the legacy VTK title, the STL header, OBJ comment lines, or the VTP field data string
//! array `SPACE`. Without it `convert` dropped the frame of a mesh it rewrote and `compare` could
//! not tell two meshes in mirrored frames apart.

use crate::contours::CoordinateSystem;

/// The frame a `SPACE=` token names (`SPACE=LPS`, `SPACE=RAS`, any case).
fn of_token(token: &str) -> Option<CoordinateSystem> {
    let value = token
        .get(..6)
        .filter(|k| k.eq_ignore_ascii_case("SPACE="))?;
    let name = &token[value.len()..];
    [CoordinateSystem::Lps, CoordinateSystem::Ras]
        .into_iter()
        .find(|s| name.eq_ignore_ascii_case(s.name()))
}

/// The first frame any token of `text` names (tokens split at whitespace and `|`).
fn in_text(text: &str) -> Option<CoordinateSystem> {
    text.split(|c: char| c.is_whitespace() || c == '|')
        .find_map(of_token)
}

/// The frame a text file's comment states (the comment's text without its `#`): a `SPACE=LPS`
/// token, as heartmesh's exports write it, or 3D Slicer's `CoordinateSystem = LPS` (its point
/// list CSV, `.fcsv`); None for any other comment.
pub fn of_comment(comment: &str) -> Option<CoordinateSystem> {
    if let Some(frame) = in_text(comment) {
        return Some(frame);
    }
    let compact: String = comment.chars().filter(|c| !c.is_whitespace()).collect();
    let value = compact
        .get(..17)
        .filter(|k| k.eq_ignore_ascii_case("CoordinateSystem="))
        .map(|k| &compact[k.len()..])?;
    [CoordinateSystem::Lps, CoordinateSystem::Ras]
        .into_iter()
        .find(|s| value.eq_ignore_ascii_case(s.name()))
}

/// The frame a mesh file's bytes state, None when they state none (or a value other than LPS and
/// RAS, which no reader here could honour).
pub fn of_mesh_file(bytes: &[u8]) -> Option<CoordinateSystem> {
    let head = &bytes[..bytes.len().min(1 << 16)];
    let text = String::from_utf8_lossy(head);
    let start = text.trim_start();
    if start.starts_with("ply") {
        let header = start.split("end_header").next().unwrap_or("");
        return header
            .lines()
            .filter_map(|l| l.trim().strip_prefix("comment"))
            .find_map(in_text);
    }
    if start.starts_with("# vtk DataFile") {
        return start.lines().nth(1).and_then(in_text);
    }
    if start.starts_with("<?xml") || start.starts_with("<VTKFile") {
        return vtp_field(start);
    }
    // STL (the 80-byte binary header, or an ASCII solid's name) and OBJ's leading comments.
    let stl_header = String::from_utf8_lossy(&head[..head.len().min(80)]);
    let first_line = stl_header.lines().next().unwrap_or("");
    in_text(first_line).or_else(|| {
        start
            .lines()
            .map(str::trim)
            .take_while(|l| l.is_empty() || l.starts_with('#'))
            .find_map(|l| in_text(l.trim_start_matches('#')))
    })
}

/// The VTP field data string array `SPACE` before the first piece: ASCII-format string arrays
/// hold character codes ending in 0 (`76 80 83 0`); plain text is taken as it stands.
fn vtp_field(xml: &str) -> Option<CoordinateSystem> {
    let before_piece = xml.split("<Piece").next().unwrap_or(xml);
    let at = before_piece.find("Name=\"SPACE\"")?;
    let rest = &before_piece[at..];
    let body = rest.get(rest.find('>')? + 1..)?;
    let body = body.split('<').next().unwrap_or("");
    let codes: Option<Vec<u8>> = body
        .split_whitespace()
        .map(|t| t.parse::<u8>().ok())
        .collect();
    let value = match codes {
        Some(c) if !c.is_empty() => String::from_utf8_lossy(&c)
            .trim_end_matches('\0')
            .to_string(),
        _ => body.trim().to_string(),
    };
    of_token(&format!("SPACE={value}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contours::CoordinateSystem::{Lps, Ras};

    #[test]
    fn tokens_name_one_of_two_frames() {
        assert_eq!(in_text("heartmesh 0.1 | SPACE=RAS | converted"), Some(Ras));
        assert_eq!(in_text("solid x space=lps"), Some(Lps));
        assert_eq!(in_text("SPACE=IJK"), None);
        assert_eq!(in_text("NOSPACE=LPS SPACE"), None);
        assert_eq!(in_text(""), None);
    }

    #[test]
    fn each_header_kind_is_read_where_slicer_writes_it() {
        let ply = b"ply\nformat ascii 1.0\ncomment SPACE=RAS\nelement vertex 0\nend_header\n";
        assert_eq!(of_mesh_file(ply), Some(Ras));
        // After end_header the token is data, not a statement.
        let late = b"ply\nformat ascii 1.0\nend_header\ncomment SPACE=RAS\n";
        assert_eq!(of_mesh_file(late), None);
        let vtk = b"# vtk DataFile Version 3.0\nheartmesh | SPACE=LPS\nASCII\n";
        assert_eq!(of_mesh_file(vtk), Some(Lps));
        let vtk_body = b"# vtk DataFile Version 3.0\nno frame\nASCII\nFIELD SPACE=RAS\n";
        assert_eq!(of_mesh_file(vtk_body), None);
        let obj = b"# heartmesh 0.1\n# SPACE=RAS\nv 0 0 0\n# SPACE=LPS\n";
        assert_eq!(of_mesh_file(obj), Some(Ras));
        let mut stl = vec![b' '; 84];
        let header = b"heartmesh 0.1 | SPACE=LPS | ";
        stl[..header.len()].copy_from_slice(header);
        assert_eq!(of_mesh_file(&stl), Some(Lps));
        let vtp = "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\">\n<PolyData>\n<FieldData>\n\
                   <Array type=\"String\" Name=\"SPACE\" NumberOfTuples=\"1\" format=\"ascii\">\n\
                   82 65 83 0\n</Array>\n</FieldData>\n<Piece NumberOfPoints=\"0\">";
        assert_eq!(of_mesh_file(vtp.as_bytes()), Some(Ras));
        let plain = "<VTKFile><FieldData><Array Name=\"SPACE\">LPS</Array></FieldData><Piece>";
        assert_eq!(of_mesh_file(plain.as_bytes()), Some(Lps));
    }
}
