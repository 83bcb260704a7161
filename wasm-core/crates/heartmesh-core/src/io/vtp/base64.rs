//! Standard base64, as VTK's `vtkBase64OutputStream` writes it: the "binary" DataArrays and the
//! `<AppendedData encoding="base64">` of VTK XML files.

/// Decodes standard base64 (whitespace ignored, padding optional); None on a bad character.
///
/// VTK pads each separately written piece (a compression header, then the compressed blocks):
/// the caller cuts the text at piece boundaries, since decoding across a `=` would shift the
/// bits of everything after it.
pub(super) fn decode(text: &[u8]) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(text.len() / 4 * 3 + 3);
    let mut acc = 0u32;
    let mut bits = 0;
    for &c in text {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            b'=' => continue,
            c if c.is_ascii_whitespace() => continue,
            _ => return None,
        };
        acc = (acc << 6) | v as u32;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decodes() {
        assert_eq!(decode(b"aGVhcnQ=").unwrap(), b"heart");
        assert_eq!(decode(b"aGVh\n  cnQ").unwrap(), b"heart");
        assert!(decode(b"a$").is_none());
    }
}
