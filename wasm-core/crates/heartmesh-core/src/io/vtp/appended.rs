//! The `<AppendedData>` block of a VTK XML file, cut off before the XML is parsed.
//!
//! VTK and ParaView write appended *raw* data by default: after `<AppendedData encoding="raw">`,
//! an underscore, then the arrays' bytes as they are in memory, then `</AppendedData>`. Those
//! bytes are neither XML nor UTF-8, so the document is parsed without them (the tag is kept,
//! emptied, so that its `encoding` can still be read) and each DataArray's `offset` attribute
//! counts from the byte after the underscore. Base64-encoded appended data is cut off the same
//! way: it is text, but parsing megabytes of it as XML character data buys nothing.

use std::borrow::Cow;

use crate::error::{CoreError, Result};

const OPEN: &[u8] = b"<AppendedData";
const CLOSE: &[u8] = b"</AppendedData";

/// A file cut in two by [`split`].
#[derive(Debug)]
pub(super) struct Split<'a> {
    /// The XML without the appended data.
    pub xml: Cow<'a, [u8]>,
    /// The appended data, from the byte after the `_` marker to the closing tag, if any.
    pub data: Option<&'a [u8]>,
}

/// The XML and the appended data. Without `<AppendedData` the bytes are returned untouched, so
/// that files without it read exactly as before.
pub(super) fn split(bytes: &[u8]) -> Result<Split<'_>> {
    let Some(open) = find(bytes, OPEN) else {
        return Ok(Split {
            xml: Cow::Borrowed(bytes),
            data: None,
        });
    };
    let line = 1 + bytes[..open].iter().filter(|&&b| b == b'\n').count();
    let tag_end = bytes[open..]
        .iter()
        .position(|&b| b == b'>')
        .map(|k| open + k + 1)
        .ok_or_else(|| CoreError::parse(line, "the <AppendedData> tag is not closed"))?;
    // Self-closing (`<AppendedData/>`): an empty block, still valid XML as it stands.
    if bytes[..tag_end].ends_with(b"/>") {
        return Ok(Split {
            xml: Cow::Borrowed(bytes),
            data: Some(&[]),
        });
    }
    let marker = bytes[tag_end..]
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .map(|k| tag_end + k)
        .filter(|&at| bytes[at] == b'_')
        .ok_or_else(|| {
            CoreError::parse(
                line,
                "<AppendedData> must start with the \"_\" marker (damaged file?)",
            )
        })?;
    // The last closing tag: raw data may happen to hold the same bytes.
    let close = rfind(&bytes[marker..], CLOSE)
        .map(|k| marker + k)
        .ok_or_else(|| {
            CoreError::parse(
                line,
                "the appended data has no closing </AppendedData> tag (truncated file?)",
            )
        })?;
    let mut xml = Vec::with_capacity(marker + (bytes.len() - close));
    xml.extend_from_slice(&bytes[..marker]);
    xml.extend_from_slice(&bytes[close..]);
    Ok(Split {
        xml: Cow::Owned(xml),
        data: Some(&bytes[marker + 1..close]),
    })
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

fn rfind(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).rposition(|w| w == needle)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn raw_bytes_are_cut_out() {
        let file = b"<VTKFile>\n<AppendedData encoding=\"raw\">\n  _\xff\x00</AppendedData\x01\n</AppendedData>\n</VTKFile>";
        let Split { xml, data } = split(file).unwrap();
        assert_eq!(
            &*xml,
            b"<VTKFile>\n<AppendedData encoding=\"raw\">\n  </AppendedData>\n</VTKFile>"
        );
        assert_eq!(data.unwrap(), b"\xff\x00</AppendedData\x01\n");
        let Split { xml, data } = split(b"<VTKFile/>").unwrap();
        assert_eq!((&*xml, data), (&b"<VTKFile/>"[..], None));
        let e = split(b"<VTKFile>\n<AppendedData encoding=\"raw\">\n_\xff\x00").unwrap_err();
        assert_eq!(e.line(), Some(2), "{e}");
        assert!(e.to_string().contains("truncated"), "{e}");
        assert!(split(b"<AppendedData>x_</AppendedData>").is_err());
        assert!(split(b"<AppendedData").is_err());
    }
}
