//! Text decoding shared by the text readers: UTF-8 with an optional BOM, UTF-16 (Excel's "Unicode
//! text", Notepad's "Unicode"), Windows-1252 bytes (a Windows "ANSI" export with an accented
//! name), CRLF, LF or classic-Mac CR line ends, and a clear error (with the line) when the bytes
//! are not text at all.

use std::borrow::Cow;

use crate::error::{CoreError, Result};

/// Decodes `bytes` as text without a leading byte-order mark.
///
/// UTF-16 is recognised by its BOM or, without one, by the NUL byte beside each of the first two
/// ASCII characters (plain text never holds NULs, so the two cannot be confused). Bytes that are
/// not UTF-8 but hold no control characters are a single-byte Windows export and are read as
/// Windows-1252: refusing them would leave a user with an accented patient name in an id no way
/// in. Binary input (NUL or control bytes) is refused with the 1-based line where it starts, so
/// that a user who dropped the wrong file learns what happened instead of seeing a number error.
pub fn decode(bytes: &[u8]) -> Result<Cow<'_, str>> {
    if let Some(kind) = recognised_binary(bytes) {
        // A signature alone is not enough ("BM" starts text too): the head must be binary.
        let head = &bytes[..bytes.len().min(1024)];
        let binary = head.contains(&0)
            || matches!(std::str::from_utf8(head), Err(e) if e.error_len().is_some());
        if binary {
            return Err(CoreError::parse(
                1,
                format!("binary data at byte 0: this is {kind}, not contours"),
            ));
        }
    }
    if let Some(text) = utf16(bytes)? {
        return checked(Cow::Owned(text));
    }
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        return Err(CoreError::parse(0, "empty file"));
    }
    let text = match std::str::from_utf8(bytes) {
        Ok(t) => Cow::Borrowed(t),
        Err(_) if is_single_byte_text(bytes) => Cow::Owned(windows_1252(bytes)),
        Err(e) => {
            let at = e.valid_up_to();
            return Err(CoreError::parse(
                line_of(bytes, at),
                format!("binary data at byte {at}: not a UTF-8 text file"),
            ));
        }
    };
    checked(text)
}

/// What a binary file opened by mistake is, from its signature: a screenshot or exported slice
/// of the images, a PDF report, a zipped folder. "Not a UTF-8 text file" alone leaves the user
/// guessing; the kind says what happened.
fn recognised_binary(bytes: &[u8]) -> Option<&'static str> {
    const SIGNATURES: &[(&[u8], &str)] = &[
        (b"\x89PNG\r\n\x1a\n", "a PNG picture"),
        (b"\xFF\xD8\xFF", "a JPEG picture"),
        (b"GIF87a", "a GIF picture"),
        (b"GIF89a", "a GIF picture"),
        (b"II*\0", "a TIFF picture"),
        (b"MM\0*", "a TIFF picture"),
        (b"BM", "a BMP picture"),
        (b"%PDF-", "a PDF document"),
        (
            b"PK\x03\x04",
            "a ZIP archive (unpack it and open the files in it)",
        ),
    ];
    if bytes.len() >= 12 && bytes.starts_with(b"RIFF") && &bytes[8..12] == b"WEBP" {
        return Some("a WebP picture");
    }
    SIGNATURES
        .iter()
        .find(|(magic, _)| bytes.starts_with(magic))
        .map(|(_, kind)| *kind)
}

/// The first `max` bytes of `bytes` as text, for format detection: decoded as [`decode`] would,
/// but lossy and never an error (a cut character or a binary tail only shortens the head).
pub fn head(bytes: &[u8], max: usize) -> Cow<'_, str> {
    let cut = &bytes[..bytes.len().min(max)];
    match utf16_order(cut) {
        Some((big_endian, skip)) => {
            let even = (cut.len() - skip) & !1;
            Cow::Owned(decode_utf16_lossy(&cut[skip..skip + even], big_endian))
        }
        None => {
            let cut = cut.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(cut);
            match std::str::from_utf8(cut) {
                Ok(t) => Cow::Borrowed(t),
                // A multi-byte character cut by `max`: the valid part.
                Err(e) if e.error_len().is_none() => {
                    Cow::Borrowed(std::str::from_utf8(&cut[..e.valid_up_to()]).unwrap_or(""))
                }
                Err(_) if is_single_byte_text(cut) => Cow::Owned(windows_1252(cut)),
                Err(e) => Cow::Borrowed(std::str::from_utf8(&cut[..e.valid_up_to()]).unwrap_or("")),
            }
        }
    }
}

/// Refuses text holding a NUL (a binary file that happens to be valid UTF-8) and removes a BOM
/// left at its start (UTF-16 files carry theirs as U+FEFF).
fn checked(text: Cow<'_, str>) -> Result<Cow<'_, str>> {
    if let Some(at) = text.find('\0') {
        return Err(CoreError::parse(
            line_of_text(&text, at),
            format!("binary data (NUL byte) at byte {at}: not a text file"),
        ));
    }
    if text.trim().trim_start_matches('\u{feff}').trim().is_empty() {
        return Err(CoreError::parse(0, "empty file"));
    }
    Ok(match text {
        Cow::Borrowed(t) => Cow::Borrowed(t.strip_prefix('\u{feff}').unwrap_or(t)),
        Cow::Owned(t) => match t.strip_prefix('\u{feff}') {
            Some(rest) => Cow::Owned(rest.to_string()),
            None => Cow::Owned(t),
        },
    })
}

/// (big endian, bytes to skip) when `bytes` look like UTF-16: a BOM, or the first two
/// characters ASCII with a NUL byte beside each.
fn utf16_order(bytes: &[u8]) -> Option<(bool, usize)> {
    match bytes {
        [0xFF, 0xFE, ..] => Some((false, 2)),
        [0xFE, 0xFF, ..] => Some((true, 2)),
        [a, 0, b, 0, ..] if a.is_ascii() && b.is_ascii() && *a != 0 && *b != 0 => Some((false, 0)),
        [0, a, 0, b, ..] if a.is_ascii() && b.is_ascii() && *a != 0 && *b != 0 => Some((true, 0)),
        _ => None,
    }
}

/// The text of a UTF-16 file (None when `bytes` are not UTF-16). A lone odd byte at the end (a
/// file cut short) is ignored; an unpaired surrogate is refused with its line.
fn utf16(bytes: &[u8]) -> Result<Option<String>> {
    let Some((big_endian, skip)) = utf16_order(bytes) else {
        return Ok(None);
    };
    let body = &bytes[skip..];
    let units = body.chunks_exact(2).map(|u| unit(u, big_endian));
    let mut out = String::with_capacity(body.len() / 2);
    for ch in char::decode_utf16(units) {
        match ch {
            Ok(c) => out.push(c),
            Err(e) => {
                return Err(CoreError::parse(
                    line_of_text(&out, out.len()),
                    format!(
                        "UTF-16 text with an unpaired surrogate 0x{:04X}: the file is damaged",
                        e.unpaired_surrogate()
                    ),
                ))
            }
        }
    }
    Ok(Some(out))
}

fn unit(pair: &[u8], big_endian: bool) -> u16 {
    let (a, b) = (
        u16::from(pair[0]),
        u16::from(pair.get(1).copied().unwrap_or(0)),
    );
    if big_endian {
        a << 8 | b
    } else {
        b << 8 | a
    }
}

fn decode_utf16_lossy(body: &[u8], big_endian: bool) -> String {
    char::decode_utf16(body.chunks_exact(2).map(|u| unit(u, big_endian)))
        .map(|c| c.unwrap_or(char::REPLACEMENT_CHARACTER))
        .collect()
}

/// True when no byte is a control character other than tab, line feed, form feed and carriage
/// return: binary data (and UTF-16 without a BOM) always has some.
fn is_single_byte_text(bytes: &[u8]) -> bool {
    !bytes
        .iter()
        .any(|&b| (b < 0x20 && !matches!(b, b'\t' | b'\n' | b'\r' | 0x0C)) || b == 0x7F)
}

/// Windows-1252, the single-byte encoding of Windows "ANSI" text (ISO-8859-1 with printable
/// characters in 0x80-0x9F; its five unassigned bytes map to the C1 code points, as browsers do).
fn windows_1252(bytes: &[u8]) -> String {
    const HIGH: [char; 32] = [
        '€', '\u{81}', '‚', 'ƒ', '„', '…', '†', '‡', 'ˆ', '‰', 'Š', '‹', 'Œ', '\u{8D}', 'Ž',
        '\u{8F}', '\u{90}', '‘', '’', '“', '”', '•', '–', '—', '˜', '™', 'š', '›', 'œ', '\u{9D}',
        'ž', 'Ÿ',
    ];
    bytes
        .iter()
        .map(|&b| match b {
            0x80..=0x9F => HIGH[usize::from(b - 0x80)],
            _ => char::from(b),
        })
        .collect()
}

/// 1-based line number of byte offset `at`, counting line ends as [`lines`] does.
pub fn line_of(bytes: &[u8], at: usize) -> usize {
    let end = at.min(bytes.len());
    let eol = if bytes.contains(&b'\n') { b'\n' } else { b'\r' };
    1 + bytes[..end].iter().filter(|&&b| b == eol).count()
}

/// 1-based line number of byte offset `at` of decoded text.
fn line_of_text(text: &str, at: usize) -> usize {
    line_of(text.as_bytes(), at)
}

/// Lines with their 1-based numbers, line-end characters removed. A text with line feeds splits
/// at them (LF, CRLF, and the CR CR LF of a file converted twice); a text without any is a
/// classic-Mac one (Excel for Mac's "CSV (Macintosh)" still writes it) and splits at its CRs.
pub fn lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let eol = if text.contains('\n') { '\n' } else { '\r' };
    text.split(eol)
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_end_matches('\r')))
}

/// Lines that carry data: not blank and not `#` comments.
pub fn data_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    lines(text).filter(|(_, l)| {
        let t = l.trim_start();
        !t.is_empty() && !t.starts_with('#')
    })
}

/// Parses one coordinate, refusing NaN and infinities (Rust's parser accepts them). The minus
/// sign U+2212 (what a number copied from a formatted document or a typeset table carries) reads
/// as `-`.
///
/// `what` names the column or field in the message.
pub fn parse_coord(field: &str, line: usize, what: &str) -> Result<f64> {
    let f = field.trim();
    let f = f
        .strip_prefix('"')
        .and_then(|s| s.strip_suffix('"'))
        .unwrap_or(f)
        .trim();
    if f.is_empty() {
        return Err(CoreError::parse(line, format!("{what} is empty")));
    }
    let minus;
    let f = if f.contains('\u{2212}') {
        minus = f.replace('\u{2212}', "-");
        minus.as_str()
    } else {
        f
    };
    match f.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(CoreError::parse(
            line,
            format!(
                "{what}: {} is not a finite number (NaN or infinity)",
                quote(f)
            ),
        )),
        Err(_) => Err(CoreError::parse(
            line,
            format!("{what}: {} is not a number", quote(f)),
        )),
    }
}

/// End of the run of non-whitespace bytes that starts at `from` (`from` itself if there is none):
/// the token scanners of the text mesh formats share it.
pub fn word_end(bytes: &[u8], from: usize) -> usize {
    from + bytes.get(from..).map_or(0, |rest| {
        rest.iter().take_while(|c| !c.is_ascii_whitespace()).count()
    })
}

/// At most `max` characters of `s`, with an ellipsis when cut.
pub fn shorten(s: &str, max: usize) -> String {
    let mut out: String = s.chars().take(max).collect();
    if s.chars().nth(max).is_some() {
        out.push('…');
    }
    out
}

/// The header's column named by one of `wanted` (lowercased names, in order of preference).
pub fn find_column(names: &[String], wanted: &[&str]) -> Option<usize> {
    // `wanted` is in order of preference: `x` before `points:0`, whatever the file's order.
    wanted
        .iter()
        .find_map(|w| names.iter().position(|n| n == w))
}

/// [`find_column`], or the parse error at `line` naming the column (`wanted[0]`) and what the
/// header has instead: the CSV and GPFile readers say it the same way.
pub fn need_column(names: &[String], wanted: &[&str], line: usize) -> Result<usize> {
    find_column(names, wanted).ok_or_else(|| {
        CoreError::parse(
            line,
            format!(
                "missing column {:?} in the header (found: {})",
                wanted[0],
                shorten(&names.join(", "), 80)
            ),
        )
    })
}

/// Quotes a field for a message, shortened so that garbage cannot flood the terminal.
pub fn quote(field: &str) -> String {
    const MAX: usize = 40;
    let mut s: String = field.chars().take(MAX).collect();
    if field.chars().nth(MAX).is_some() {
        s.push('…');
    }
    format!("{s:?}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pictures_and_archives_opened_by_mistake_are_named() {
        let png = b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR";
        let e = decode(png).unwrap_err();
        assert_eq!(
            e.to_string(),
            "line 1: binary data at byte 0: this is a PNG picture, not contours"
        );
        let jpeg = decode(b"\xFF\xD8\xFF\xE0\0\x10JFIF").unwrap_err();
        assert!(jpeg
            .to_string()
            .ends_with("this is a JPEG picture, not contours"));
        let zip = decode(b"PK\x03\x04\x14\0\0\0\x08\0").unwrap_err();
        assert!(
            zip.to_string().contains("a ZIP archive (unpack it"),
            "{zip}"
        );
        // Text that starts like a signature is text; other binary data keeps the plain message.
        assert!(decode(b"BMI,x,y,z\n").is_ok());
        let other = decode(b"ab\xFF\xFE\0\x01").unwrap_err();
        assert!(
            other.to_string().ends_with("not a UTF-8 text file"),
            "{other}"
        );
    }

    #[test]
    fn bom_and_crlf() {
        let t = decode(b"\xEF\xBB\xBFa\r\nb\r\n").unwrap();
        let ls: Vec<_> = lines(&t).collect();
        assert_eq!(ls[0], (1, "a"));
        assert_eq!(ls[1], (2, "b"));
    }

    #[test]
    fn utf16_with_and_without_bom_and_windows_1252_decode() {
        let text = "contour\tx\r\nµ-ring\t1,5\r\n";
        let le: Vec<u8> = text.encode_utf16().flat_map(u16::to_le_bytes).collect();
        let be: Vec<u8> = text.encode_utf16().flat_map(u16::to_be_bytes).collect();
        for (name, bytes) in [
            ("LE + BOM", [&[0xFF, 0xFE][..], &le].concat()),
            ("BE + BOM", [&[0xFE, 0xFF][..], &be].concat()),
            ("LE", le.clone()),
            ("BE", be.clone()),
            ("LE cut", [&[0xFF, 0xFE][..], &le, &[b'x'][..]].concat()),
        ] {
            assert_eq!(decode(&bytes).unwrap(), text, "{name}");
            assert!(text.starts_with(&*head(&bytes, 12)), "{name}: head");
            assert!(head(&bytes, 12).len() >= 5, "{name}: head");
        }
        // Excel's "CSV" on Windows: Windows-1252 (0xB5 micro, 0x96 en dash, 0xE9 e acute).
        let ansi = b"contour,x\nr\xE9gion \x96 \xB5,1\n";
        assert_eq!(decode(ansi).unwrap(), "contour,x\nrégion – µ,1\n");
        // An unpaired surrogate names its line.
        let bad: Vec<u8> = [0xFF, 0xFE, b'a', 0, b'\n', 0, 0x00, 0xD8, b'b', 0].to_vec();
        let e = decode(&bad).unwrap_err();
        assert_eq!(e.line(), Some(2));
        assert!(e.to_string().contains("unpaired surrogate 0xD800"), "{e}");
    }

    #[test]
    fn cr_only_files_split_at_cr_and_others_at_lf() {
        let ls: Vec<_> = lines("a\rb\rc").collect();
        assert_eq!(ls, [(1, "a"), (2, "b"), (3, "c")]);
        // With line feeds, a CR is only ever part of a line end (CRLF, or CR CR LF from a file
        // converted twice), never a line break of its own.
        let ls: Vec<_> = lines("a\r\nb\nc\r\r\nd,\re").collect();
        assert_eq!(ls, [(1, "a"), (2, "b"), (3, "c"), (4, "d,\re")]);
        assert_eq!(line_of(b"a\rb\rc", 4), 3);
        assert_eq!(line_of(b"a\r\nb\r\nc", 6), 3);
        assert_eq!(lines("").count(), 1);
    }

    #[test]
    fn binary_is_refused_with_line() {
        let e = decode(b"abc\ndef\n\xff\xfe\x00").unwrap_err();
        assert_eq!(e.line(), Some(3));
        assert!(e.to_string().contains("binary"), "{e}");
        assert_eq!(decode(b"  \n\n").unwrap_err().to_string(), "empty file");
    }

    #[test]
    fn coords_refuse_nan() {
        assert!(parse_coord("nan", 4, "column \"x\"").is_err());
        assert!(parse_coord("inf", 4, "x")
            .unwrap_err()
            .to_string()
            .contains("finite"));
        assert_eq!(parse_coord(" 1.5e1 ", 1, "x").unwrap(), 15.0);
        assert_eq!(parse_coord("\u{2212}3.5", 1, "x").unwrap(), -3.5);
        assert_eq!(parse_coord("2e\u{2212}1", 1, "x").unwrap(), 0.2);
        for ok in ["+3", ".5", "5.", "1.5E+01", "\u{a0}7\u{a0}"] {
            assert!(parse_coord(ok, 1, "x").is_ok(), "{ok}");
        }
    }
}
