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
    /// Skipped content of undefined length that is not a data set (encapsulated pixel data).
    Fragments,
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
    let mut r = Reader {
        data: bytes,
        pos: 0,
        sequences,
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
                _ => {
                    self.fragments(end, enc)?;
                    Value::Fragments
                }
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

    /// Skips encapsulated pixel data: items of raw fragments up to the sequence delimiter.
    fn fragments(&mut self, end: usize, enc: Encoding) -> Result<()> {
        loop {
            let at = self.pos;
            let tag = self.tag(end, enc)?;
            let len = self.u32(end, enc)?;
            match tag {
                ITEM if len != UNDEFINED => {
                    let len = self.fits(tag, len, end)?;
                    self.pos += len;
                }
                SEQUENCE_END if len == 0 => return Ok(()),
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
mod tests {
    use super::*;

    /// Explicit VR little endian element (short or long header by VR).
    fn ex(tag: Tag, vr: &[u8; 2], value: &[u8]) -> Vec<u8> {
        let mut b = Vec::new();
        b.extend(tag.0.to_le_bytes());
        b.extend(tag.1.to_le_bytes());
        b.extend(vr);
        if SHORT_VRS.contains(&vr) {
            b.extend((value.len() as u16).to_le_bytes());
        } else {
            b.extend([0, 0]);
            b.extend((value.len() as u32).to_le_bytes());
        }
        b.extend(value);
        b
    }

    fn header(tag: Tag, len: u32) -> Vec<u8> {
        let mut b = Vec::new();
        b.extend(tag.0.to_le_bytes());
        b.extend(tag.1.to_le_bytes());
        b.extend(len.to_le_bytes());
        b
    }

    fn item(content: &[u8]) -> Vec<u8> {
        let mut b = header(ITEM, content.len() as u32);
        b.extend(content);
        b
    }

    /// An undefined-length item and sequence in explicit VR little endian.
    fn undefined_sq(tag: Tag, items: &[Vec<u8>]) -> Vec<u8> {
        let mut b = ex(tag, b"SQ", &[]);
        let n = b.len();
        b[n - 4..].copy_from_slice(&UNDEFINED.to_le_bytes());
        for i in items {
            b.extend(header(ITEM, UNDEFINED));
            b.extend(i);
            b.extend(header(ITEM_END, 0));
        }
        b.extend(header(SEQUENCE_END, 0));
        b
    }

    fn with_meta(syntax: &str, body: &[u8]) -> Vec<u8> {
        let mut f = vec![0u8; 128];
        f.extend(b"DICM");
        f.extend(ex((2, 1), b"OB", &[0, 1]));
        f.extend(ex(TRANSFER_SYNTAX, b"UI", syntax.as_bytes()));
        f.extend(body);
        f
    }

    const EXPLICIT: &str = "1.2.840.10008.1.2.1\0";

    /// Nested sequences of defined and undefined length, pixel data fragments and an UN
    /// sequence of undefined length: the values come back where they were.
    fn nested() -> Vec<u8> {
        let inner = [
            ex((0x3006, 0x0050), b"DS", b"1\\2\\3 "),
            ex((0x3006, 0x0048), b"IS", b"7 "),
        ];
        let defined = ex(
            (0x3006, 0x0040),
            b"SQ",
            &[item(&inner.concat()), item(&[])].concat(),
        );
        let mut body = ex((0x0008, 0x0060), b"CS", b"RTSTRUCT");
        body.extend(undefined_sq((0x3006, 0x0039), &[defined]));
        // UN of undefined length: implicit VR little endian inside.
        let mut un = ex((0x0009, 0x1010), b"UN", &[]);
        let n = un.len();
        un[n - 4..].copy_from_slice(&UNDEFINED.to_le_bytes());
        un.extend(item(
            &[header((0x0010, 0x0010), 4), b"Doe ".to_vec()].concat(),
        ));
        un.extend(header(SEQUENCE_END, 0));
        body.extend(un);
        let mut pixels = ex((0x7FE0, 0x0010), b"OB", &[]);
        let n = pixels.len();
        pixels[n - 4..].copy_from_slice(&UNDEFINED.to_le_bytes());
        pixels.extend(item(&[]));
        pixels.extend(item(&[0xAA; 6]));
        pixels.extend(header(SEQUENCE_END, 0));
        body.extend(pixels);
        body.extend(ex((0x0020, 0x0013), b"IS", b"42"));
        with_meta(EXPLICIT, &body)
    }

    #[test]
    fn nested_sequences_fragments_and_un_are_read() {
        let f = nested();
        let set = read_file(&f, &[]).unwrap();
        assert_eq!(
            set.text(TRANSFER_SYNTAX).as_deref(),
            Some("1.2.840.10008.1.2.1")
        );
        assert_eq!(set.text((0x0008, 0x0060)).as_deref(), Some("RTSTRUCT"));
        let rois = set.items((0x3006, 0x0039));
        assert_eq!(rois.len(), 1);
        let contours = rois[0].items((0x3006, 0x0040));
        assert_eq!(contours.len(), 2);
        assert_eq!(
            contours[0].text((0x3006, 0x0050)).as_deref(),
            Some("1\\2\\3")
        );
        assert_eq!(contours[0].text((0x3006, 0x0048)).as_deref(), Some("7"));
        assert!(contours[1].elements.is_empty());
        let un = set.items((0x0009, 0x1010));
        assert_eq!(un[0].text((0x0010, 0x0010)).as_deref(), Some("Doe"));
        assert_eq!(set.get((0x7FE0, 0x0010)), Some(&Value::Fragments));
        // The element after the pixel data is found: every byte was accounted for.
        assert_eq!(set.text((0x0020, 0x0013)).as_deref(), Some("42"));
        // Without the preamble, and as a bare data set starting at "DICM".
        assert_eq!(read_file(&f[128..], &[]).unwrap(), set);
    }

    #[test]
    fn implicit_vr_sequences_are_the_listed_tags() {
        let inner = [header((0x3006, 0x0026), 2), b"LV".to_vec()].concat();
        let items = item(&inner);
        let mut body = header((0x3006, 0x0020), items.len() as u32);
        body.extend(&items);
        body.extend(header((0x0008, 0x0060), 8));
        body.extend(b"RTSTRUCT");
        let set = read_file(&body, &[(0x3006, 0x0020)]).unwrap();
        assert_eq!(
            set.items((0x3006, 0x0020))[0]
                .text((0x3006, 0x0026))
                .as_deref(),
            Some("LV")
        );
        // Not listed: the sequence stays raw bytes.
        let raw = read_file(&body, &[]).unwrap();
        assert_eq!(
            raw.bytes((0x3006, 0x0020)).map(<[u8]>::len),
            Some(items.len())
        );
        assert_eq!(raw.text((0x0008, 0x0060)).as_deref(), Some("RTSTRUCT"));
    }

    #[test]
    fn un_sequences_and_a_missing_transfer_syntax() {
        // A listed sequence written as explicit UN of defined length: implicit VR items inside.
        let inner = [header((0x3006, 0x0026), 2), b"LV".to_vec()].concat();
        let mut f = vec![0u8; 128];
        f.extend(b"DICM");
        f.extend(ex((2, 1), b"OB", &[0, 1]));
        f.extend(ex((0x3006, 0x0020), b"UN", &item(&inner)));
        let set = read_file(&f, &[(0x3006, 0x0020)]).unwrap();
        let name = set.items((0x3006, 0x0020))[0].text((0x3006, 0x0026));
        assert_eq!(name.as_deref(), Some("LV"));
        // Not listed: raw bytes.
        assert!(read_file(&f, &[])
            .unwrap()
            .bytes((0x3006, 0x0020))
            .is_some());
        // A meta group without a transfer syntax, then an implicit VR data set.
        let mut f = vec![0u8; 128];
        f.extend(b"DICM");
        f.extend(ex((2, 1), b"OB", &[0, 1]));
        f.extend(header((0x0008, 0x0060), 8));
        f.extend(b"RTSTRUCT");
        let set = read_file(&f, &[]).unwrap();
        assert_eq!(set.text((0x0008, 0x0060)).as_deref(), Some("RTSTRUCT"));
    }

    fn message(bytes: &[u8]) -> String {
        read_file(bytes, &[]).unwrap_err().to_string()
    }

    #[test]
    fn lengths_past_their_container_are_refused_with_the_offset() {
        // Implicit VR: (0008,0005) with a length of "garb" (about 1.6 GB).
        let m = message(b"\x08\x00\x05\x00garbage that is no DICOM");
        assert!(
            m.contains("(0008,0005) declares 1651663207 bytes but only 20 remain in its file"),
            "{m}"
        );
        assert!(m.contains("at byte 8"), "{m}");
        // Explicit VR long form in the meta group.
        let mut f = b"DICM\x02\x00\x01\x00OB\x00\x00\xff\xff\xff\x7f".to_vec();
        f.extend([0; 10]);
        assert!(message(&f).contains("declares 2147483647 bytes but only 10 remain"));
        // An element longer than its defined-length item, though shorter than the file.
        let long = ex((0x3006, 0x0050), b"DS", &[b'1'; 40]);
        let mut it = header(ITEM, 20);
        it.extend(&long);
        let mut sq = ex((0x3006, 0x0040), b"SQ", &[]);
        let n = sq.len();
        sq[n - 4..].copy_from_slice(&(it.len() as u32).to_le_bytes());
        sq.extend(it);
        let m = message(&with_meta(EXPLICIT, &sq));
        assert!(m.contains("remain in its enclosing item"), "{m}");
        // An undefined-length item inside a defined-length sequence cannot run past the sequence.
        let body = [
            ex(
                (0x3006, 0x0040),
                b"SQ",
                &[header(ITEM, UNDEFINED), ex((8, 0x60), b"CS", b"RT")].concat(),
            ),
            header(ITEM_END, 0),
        ]
        .concat();
        let m = message(&with_meta(EXPLICIT, &body));
        assert!(m.contains("without its delimiter"), "{m}");
    }

    #[test]
    fn malformed_structure_is_refused() {
        let m = message(&with_meta(EXPLICIT, &header(ITEM, 0)));
        assert!(m.contains("(FFFE,E000) outside a sequence"), "{m}");
        let mut sq = undefined_sq((0x3006, 0x0039), &[]);
        let n = sq.len();
        sq[n - 4..].copy_from_slice(&0xFA00_0000u32.to_le_bytes());
        assert!(message(&with_meta(EXPLICIT, &sq)).contains("sequence delimiter with length"));
        let bad_vr = [8u8, 0, 0x60, 0, 0, 0, 2, 0, b'R', b'T'];
        assert!(message(&with_meta(EXPLICIT, &bad_vr)).contains("no valid VR"));
        let deflated = with_meta("1.2.840.10008.1.2.1.99", &[]);
        assert!(message(&deflated).contains("deflated"));
        // Deep nesting stops at MAX_DEPTH instead of exhausting the stack.
        let mut deep = Vec::new();
        for _ in 0..10_000 {
            deep.extend(&ex((0x3006, 0x0039), b"SQ", &[])[..8]);
            deep.extend(UNDEFINED.to_le_bytes());
            deep.extend(header(ITEM, UNDEFINED));
        }
        assert!(message(&with_meta(EXPLICIT, &deep)).contains("nested more than 64 deep"));
    }

    /// Every file the rtstruct fuzz target found out of memory with dicom-rs (fuzz/regressions):
    /// each is refused at the offending header, nothing is allocated from its length.
    #[test]
    fn fuzz_regressions_are_refused() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fuzz/regressions");
        let expect = [
            // A UL of length 1, which dicom-rs read as nothing and so found a header with length
            // 0xFFFFFF02 one byte early; here the value is that one byte, and the file ends
            // inside the next header.
            (
                "rtstruct-oom-29fa52ac.dcm",
                "truncated: 4 bytes needed, 0 left (at byte 29)",
            ),
            // Sequence delimiters with non-zero lengths.
            (
                "rtstruct-oom-fd873c90.dcm",
                "sequence delimiter with length",
            ),
            // An item of length 0xFFDFFFFF after a sequence's delimiter; the stray item delimiter
            // before it is already refused.
            (
                "rtstruct-oom-c00fae35.dcm",
                "(FFFE,E00D) outside a sequence (at byte 604)",
            ),
            // An item header (length 13) where the third ROI item's delimiter belongs, inside
            // that item's data set.
            (
                "rtstruct-oom-9a278e58.dcm",
                "(FFFE,E000) outside a sequence (at byte 648)",
            ),
        ];
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(
            names.len(),
            expect.len(),
            "a regression file without a test: {names:?}"
        );
        for (name, text) in expect {
            let bytes = std::fs::read(format!("{dir}/{name}")).unwrap();
            let m = message(&bytes);
            assert!(m.contains(text), "{name}: {m}");
            assert!(m.contains("at byte"), "{name}: {m}");
        }
    }

    /// Any four bytes of a real file overwritten with a huge length, or the file cut anywhere:
    /// an error naming an offset, or a data set, never a panic.
    #[test]
    fn corrupted_lengths_and_cuts_never_panic() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/data/patient1-ED-rtstruct.dcm"
        );
        let real = std::fs::read(path).unwrap();
        let sets = [(nested(), 1), (real.clone(), 61)];
        let mut refused = 0;
        for (f, step) in &sets {
            read_file(f, &[]).unwrap();
            for at in (0..f.len() - 4).step_by(*step) {
                for huge in [0xFFFF_FFF0u32, 0x7FFF_FFFF, 0xFFFF] {
                    let mut g = f.clone();
                    g[at..at + 4].copy_from_slice(&huge.to_le_bytes());
                    if let Err(e) = read_file(&g, &[]) {
                        assert!(e.to_string().contains("at byte"), "{e}");
                        refused += 1;
                    }
                }
            }
            for cut in (0..f.len()).step_by(*step) {
                if let Err(e) = read_file(&f[..cut], &[]) {
                    assert!(e.to_string().contains("at byte"), "{e}");
                }
            }
        }
        assert!(refused > 500, "{refused}");
    }
}
