//! Text decoding shared by the text readers: UTF-8 with an optional BOM, CRLF or LF line ends, and
//! a clear error (with the line) when the bytes are not text at all.

use crate::error::{CoreError, Result};

/// Decodes `bytes` as UTF-8 text without a leading byte-order mark.
///
/// Binary input (NUL bytes or invalid UTF-8) is refused with the 1-based line where it starts, so
/// that a user who dropped the wrong file learns what happened instead of seeing a number error.
pub fn decode(bytes: &[u8]) -> Result<&str> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        return Err(CoreError::parse(0, "empty file"));
    }
    let text = match std::str::from_utf8(bytes) {
        Ok(t) => t,
        Err(e) => {
            let at = e.valid_up_to();
            return Err(CoreError::parse(
                line_of(bytes, at),
                format!("binary data at byte {at}: not a UTF-8 text file"),
            ));
        }
    };
    if let Some(at) = text.find('\0') {
        return Err(CoreError::parse(
            line_of(bytes, at),
            format!("binary data (NUL byte) at byte {at}: not a text file"),
        ));
    }
    Ok(text)
}

/// 1-based line number of byte offset `at`.
pub fn line_of(bytes: &[u8], at: usize) -> usize {
    let end = at.min(bytes.len());
    1 + bytes[..end].iter().filter(|&&b| b == b'\n').count()
}

/// Lines with their 1-based numbers, trailing `\r` removed.
pub fn lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.split('\n')
        .enumerate()
        .map(|(i, l)| (i + 1, l.strip_suffix('\r').unwrap_or(l)))
}

/// Lines that carry data: not blank and not `#` comments.
pub fn data_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    lines(text).filter(|(_, l)| {
        let t = l.trim_start();
        !t.is_empty() && !t.starts_with('#')
    })
}

/// Parses one coordinate, refusing NaN and infinities (Rust's parser accepts them).
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
    fn bom_and_crlf() {
        let t = decode(b"\xEF\xBB\xBFa\r\nb\r\n").unwrap();
        let ls: Vec<_> = lines(t).collect();
        assert_eq!(ls[0], (1, "a"));
        assert_eq!(ls[1], (2, "b"));
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
    }
}
