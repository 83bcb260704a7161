//! A bounded reader of DICOM data sets: every value is a slice of the input, never a buffer sized
//! from a declared length.
//!
//! Reference: DICOM PS3.5 sections 7.1 (data element encoding: tag, VR, 16- or 32-bit length),
//! 7.5 (nesting of data sets: items and delimiters, defined and undefined lengths), 6.2.2 (UN of
//! undefined length holds implicit VR little endian), A.4 (encapsulated pixel data fragments);
//! PS3.10 section 7.1 (preamble, "DICM" and the explicit VR little endian file meta group).
//!
//! Why our own: dicom-rs allocates each value from its declared length before reading it, so a
//! hostile four-byte length made it reserve (and zero) up to 4 GiB, and a second walk that
//! mirrored its parsing to refuse such lengths kept missing cases (fuzz/regressions). Here the
//! parser that checks the lengths is the parser that reads the values: a length is accepted only
//! when it fits in what is left of its enclosing item, sequence or file, at every nesting level,
//! so memory stays proportional to the input whatever the bytes say.

pub mod rle;

use crate::error::{CoreError, Result};

/// (group, element).
pub type Tag = (u16, u16);

/// Nesting deeper than this is refused (real files nest a few levels; a hostile one could nest
/// thousands and exhaust the stack).
const MAX_DEPTH: usize = 64;

const UNDEFINED: u32 = u32::MAX;
const ITEM: Tag = (0xFFFE, 0xE000);
const ITEM_END: Tag = (0xFFFE, 0xE00D);
const SEQUENCE_END: Tag = (0xFFFE, 0xE0DD);
const TRANSFER_SYNTAX: Tag = (0x0002, 0x0010);

const DEFLATED: &str =
    "deflated transfer syntax is not supported; export the structure set uncompressed";

/// Value representations with a 16-bit length in explicit VR (PS3.5 table 7.1-2); every other VR
/// has two reserved bytes and a 32-bit length.
const SHORT_VRS: [&[u8; 2]; 21] = [
    b"AE", b"AS", b"AT", b"CS", b"DA", b"DS", b"DT", b"FL", b"FD", b"IS", b"LO", b"LT", b"PN",
    b"SH", b"SL", b"SS", b"ST", b"TM", b"UI", b"UL", b"US",
];

/// An element's value.
#[derive(Debug, Clone, PartialEq)]
pub enum Value<'a> {
    /// The raw value bytes (strings are not decoded until asked for).
    Bytes(&'a [u8]),
    /// A sequence of items, each a data set.
    Items(Vec<DataSet<'a>>),
    /// Content of undefined length that is not a data set: encapsulated pixel data, its items'
    /// bytes in order (the first the basic offset table, possibly empty; then the fragments).
    Fragments(Vec<&'a [u8]>),
}

/// The elements of one data set, in file order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DataSet<'a> {
    pub elements: Vec<(Tag, Value<'a>)>,
}

impl<'a> DataSet<'a> {
    pub fn get(&self, tag: Tag) -> Option<&Value<'a>> {
        self.elements
            .iter()
            .find(|(t, _)| *t == tag)
            .map(|(_, v)| v)
    }

    pub fn bytes(&self, tag: Tag) -> Option<&'a [u8]> {
        match self.get(tag)? {
            Value::Bytes(b) => Some(b),
            _ => None,
        }
    }

    /// A string value without its padding (spaces, NULs); None when missing or empty. Bytes
    /// that are not UTF-8 are read as ISO 8859-1, the usual single-byte character set.
    pub fn text(&self, tag: Tag) -> Option<String> {
        let s = decode(self.bytes(tag)?);
        let s = s.trim_matches(|c: char| c.is_whitespace() || c == '\0');
        (!s.is_empty()).then(|| s.to_string())
    }

    /// A multi-valued decimal or integer string (DS, IS: `1.5\-2\3`) as numbers; None when
    /// missing, or when any value is not a finite number.
    pub fn numbers(&self, tag: Tag) -> Option<Vec<f64>> {
        self.text(tag)?
            .split('\\')
            .map(|v| v.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
            .collect()
    }

    /// The items of a sequence (none when missing or not a sequence).
    pub fn items(&self, tag: Tag) -> &[DataSet<'a>] {
        match self.get(tag) {
            Some(Value::Items(items)) => items,
            _ => &[],
        }
    }
}

/// UTF-8 when valid, else ISO 8859-1 (each byte one character).
pub fn decode(b: &[u8]) -> String {
    match std::str::from_utf8(b) {
        Ok(s) => s.to_string(),
        Err(_) => b.iter().map(|&c| char::from(c)).collect(),
    }
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Encoding {
    ExplicitLittle,
    ImplicitLittle,
    ExplicitBig,
}

impl Encoding {
    fn explicit(self) -> bool {
        self != Encoding::ImplicitLittle
    }
}

fn fail(at: usize, message: impl std::fmt::Display) -> CoreError {
    CoreError::parse(0, format!("DICOM: {message} (at byte {at})"))
}

fn tag_name(t: Tag) -> String {
    format!("({:04X},{:04X})", t.0, t.1)
}

/// Reads a DICOM file: 128-byte preamble and "DICM" optional; without "DICM", a bare data set in
/// implicit VR little endian (the DICOM default, which some exporters write). In implicit VR the
/// bytes do not say which elements are sequences: the `sequences` listed are read as such (undefined-
/// length elements always are), every other defined-length value stays raw bytes.
pub fn read_file<'a>(bytes: &'a [u8], sequences: &[Tag]) -> Result<DataSet<'a>> {
    read(bytes, sequences, None)
}

/// The elements before the pixel data, from a whole file or from its first bytes only: reading
/// stops at the first top-level element of group 7FE0 (pixel data), and a top-level element cut
/// by the end of `bytes` (or unreadable) ends the set instead of failing it. Why: a cine study is
/// hundreds of images of which only the headers matter (position, orientation, spacing), so a
/// browser reads a slice of each file, never the pixels.
pub fn read_header<'a>(bytes: &'a [u8], sequences: &[Tag]) -> Result<DataSet<'a>> {
    read(bytes, sequences, Some(PIXEL_GROUP))
}

/// Group of the pixel data and its companions, which follow every header element (PS3.5 7.1:
/// elements come in ascending tag order).
const PIXEL_GROUP: u16 = 0x7FE0;

fn read<'a>(bytes: &'a [u8], sequences: &[Tag], header_only: Option<u16>) -> Result<DataSet<'a>> {
    let mut r = Reader {
        data: bytes,
        pos: 0,
        sequences,
        stop_group: header_only,
    };
    let end = bytes.len();
    if bytes.get(128..132) == Some(b"DICM") {
        r.pos = 132;
    } else if bytes.starts_with(b"DICM") {
        r.pos = 4;
    } else {
        return r.dataset(end, Encoding::ImplicitLittle, 0, false);
    }
    // The file meta group: explicit VR little endian, group 0002, up to the first other group.
    let mut meta = DataSet::default();
    while r.pos + 2 <= end && bytes[r.pos..r.pos + 2] == [0x02, 0x00] {
        meta.elements
            .push(r.element(end, Encoding::ExplicitLittle, 0)?);
    }
    let syntax = meta.text(TRANSFER_SYNTAX);
    let enc = match syntax.as_deref() {
        Some("1.2.840.10008.1.2") => Encoding::ImplicitLittle,
        Some("1.2.840.10008.1.2.2") => Encoding::ExplicitBig,
        Some("1.2.840.10008.1.2.1.99") => return Err(fail(r.pos, DEFLATED)),
        // Explicit VR little endian, and every encapsulated (compressed pixel data) syntax.
        Some(_) => Encoding::ExplicitLittle,
        // No transfer syntax named: a VR after the first tag tells explicit from implicit.
        None => match bytes.get(r.pos + 4..r.pos + 6) {
            Some(vr) if !vr.iter().all(u8::is_ascii_uppercase) => Encoding::ImplicitLittle,
            _ => Encoding::ExplicitLittle,
        },
    };
    let mut set = r.dataset(end, enc, 0, false)?;
    let mut all = meta.elements;
    all.append(&mut set.elements);
    Ok(DataSet { elements: all })
}

struct Reader<'a, 's> {
    data: &'a [u8],
    pos: usize,
    sequences: &'s [Tag],
    /// Header-only reading ([`read_header`]): the top-level group to stop at.
    stop_group: Option<u16>,
}

impl<'a> Reader<'a, '_> {
    /// The next `n` bytes, which must lie before `end`.
    fn take(&mut self, n: usize, end: usize) -> Result<&'a [u8]> {
        if end.saturating_sub(self.pos) < n {
            return Err(fail(
                self.pos,
                format!(
                    "truncated: {n} bytes needed, {} left",
                    end.saturating_sub(self.pos)
                ),
            ));
        }
        let b = &self.data[self.pos..self.pos + n];
        self.pos += n;
        Ok(b)
    }

    fn u16(&mut self, end: usize, enc: Encoding) -> Result<u16> {
        let b = self.take(2, end)?;
        let b = [b[0], b[1]];
        Ok(match enc {
            Encoding::ExplicitBig => u16::from_be_bytes(b),
            _ => u16::from_le_bytes(b),
        })
    }

    fn u32(&mut self, end: usize, enc: Encoding) -> Result<u32> {
        let b = self.take(4, end)?;
        let b = [b[0], b[1], b[2], b[3]];
        Ok(match enc {
            Encoding::ExplicitBig => u32::from_be_bytes(b),
            _ => u32::from_le_bytes(b),
        })
    }

    fn tag(&mut self, end: usize, enc: Encoding) -> Result<Tag> {
        Ok((self.u16(end, enc)?, self.u16(end, enc)?))
    }

    /// Checks a declared length against what is left before `end`.
    fn fits(&self, tag: Tag, len: u32, end: usize) -> Result<usize> {
        let left = end.saturating_sub(self.pos);
        let len = len as usize;
        if len > left {
            return Err(fail(
                self.pos,
                format!(
                    "element {} declares {len} bytes but only {left} remain in its {}: \
                     truncated or corrupt file",
                    tag_name(tag),
                    if end == self.data.len() {
                        "file"
                    } else {
                        "enclosing item"
                    }
                ),
            ));
        }
        Ok(len)
    }

    /// Data set elements up to `end` (a defined-length item or the file) or, with `delimited`,
    /// up to the item delimiter (which must come before `end`).
    fn dataset(
        &mut self,
        end: usize,
        enc: Encoding,
        depth: usize,
        delimited: bool,
    ) -> Result<DataSet<'a>> {
        if depth > MAX_DEPTH {
            return Err(fail(
                self.pos,
                format!("sequences nested more than {MAX_DEPTH} deep"),
            ));
        }
        let mut set = DataSet::default();
        loop {
            if self.pos >= end {
                if delimited {
                    return Err(fail(
                        self.pos,
                        "item of undefined length without its delimiter (FFFE,E00D)",
                    ));
                }
                return Ok(set);
            }
            if delimited {
                let at = self.pos;
                if self.tag(end, enc)? == ITEM_END {
                    let len = self.u32(end, enc)?;
                    if len != 0 {
                        return Err(fail(at, format!("item delimiter with length {len}")));
                    }
                    return Ok(set);
                }
                self.pos = at;
            }
            if depth == 0 {
                if let Some(stop) = self.stop_group {
                    let at = self.pos;
                    match self.tag(end, enc) {
                        Ok((group, _)) if group < stop => self.pos = at,
                        _ => return Ok(set),
                    }
                    match self.element(end, enc, depth) {
                        Ok(e) => set.elements.push(e),
                        Err(_) => return Ok(set),
                    }
                    continue;
                }
            }
            set.elements.push(self.element(end, enc, depth)?);
        }
    }

    /// One data element (header and value), bounded by `end`.
    fn element(&mut self, end: usize, enc: Encoding, depth: usize) -> Result<(Tag, Value<'a>)> {
        let at = self.pos;
        let tag = self.tag(end, enc)?;
        if tag.0 == 0xFFFE {
            return Err(fail(
                at,
                format!("item or delimiter {} outside a sequence", tag_name(tag)),
            ));
        }
        let (vr, len) = if enc.explicit() {
            let b = self.take(2, end)?;
            let vr = [b[0], b[1]];
            if !vr.iter().all(u8::is_ascii_uppercase) {
                return Err(fail(
                    at + 4,
                    format!("element {} has no valid VR", tag_name(tag)),
                ));
            }
            if SHORT_VRS.contains(&&vr) {
                (vr, u32::from(self.u16(end, enc)?))
            } else {
                self.take(2, end)?;
                (vr, self.u32(end, enc)?)
            }
        } else {
            (*b"??", self.u32(end, enc)?)
        };
        if len == UNDEFINED {
            let value = match (&vr, enc.explicit()) {
                // Implicit VR: only sequences have undefined length.
                (b"SQ", _) | (_, false) => Value::Items(self.items(end, None, enc, depth + 1)?),
                (b"UN", true) => {
                    Value::Items(self.items(end, None, Encoding::ImplicitLittle, depth + 1)?)
                }
                _ => Value::Fragments(self.fragments(end, enc)?),
            };
            return Ok((tag, value));
        }
        let len = self.fits(tag, len, end)?;
        let value_end = self.pos + len;
        let listed = self.sequences.contains(&tag);
        // A listed sequence written as UN (by a tool that did not know it) holds implicit VR
        // little endian items (PS3.5 6.2.2).
        let inner = match (&vr, enc.explicit()) {
            (b"SQ", true) => Some(enc),
            (b"UN", true) if listed => Some(Encoding::ImplicitLittle),
            (_, false) if listed => Some(enc),
            _ => None,
        };
        if let Some(inner) = inner {
            let items = self.items(value_end, Some(value_end), inner, depth + 1)?;
            return Ok((tag, Value::Items(items)));
        }
        let value = &self.data[self.pos..value_end];
        self.pos = value_end;
        Ok((tag, Value::Bytes(value)))
    }

    /// Items of a sequence: up to `defined` (its end) or the sequence delimiter.
    fn items(
        &mut self,
        end: usize,
        defined: Option<usize>,
        enc: Encoding,
        depth: usize,
    ) -> Result<Vec<DataSet<'a>>> {
        let mut items = Vec::new();
        loop {
            if defined.is_some_and(|d| self.pos >= d) {
                return Ok(items);
            }
            let at = self.pos;
            let tag = self.tag(end, enc)?;
            let len = self.u32(end, enc)?;
            match tag {
                ITEM if len == UNDEFINED => items.push(self.dataset(end, enc, depth, true)?),
                ITEM => {
                    let len = self.fits(tag, len, end)?;
                    let item_end = self.pos + len;
                    items.push(self.dataset(item_end, enc, depth, false)?);
                    self.pos = item_end;
                }
                SEQUENCE_END if defined.is_none() => {
                    if len != 0 {
                        return Err(fail(at, format!("sequence delimiter with length {len}")));
                    }
                    return Ok(items);
                }
                _ => {
                    return Err(fail(
                        at,
                        format!("expected an item (FFFE,E000), found {}", tag_name(tag)),
                    ))
                }
            }
        }
    }

    /// Encapsulated pixel data: items of raw fragments up to the sequence delimiter.
    fn fragments(&mut self, end: usize, enc: Encoding) -> Result<Vec<&'a [u8]>> {
        let mut items = Vec::new();
        loop {
            let at = self.pos;
            let tag = self.tag(end, enc)?;
            let len = self.u32(end, enc)?;
            match tag {
                ITEM if len != UNDEFINED => {
                    let len = self.fits(tag, len, end)?;
                    items.push(self.take(len, end)?);
                }
                SEQUENCE_END if len == 0 => return Ok(items),
                _ => {
                    return Err(fail(
                        at,
                        format!(
                            "expected a pixel data fragment, found {} of length {len}",
                            tag_name(tag)
                        ),
                    ))
                }
            }
        }
    }
}

#[cfg(test)]
mod tests;
