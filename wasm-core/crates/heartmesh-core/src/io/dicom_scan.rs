//! A length check of DICOM element headers before the real parser sees the bytes.
//!
//! Reference: DICOM PS3.5 section 7 (data element structure: tag, VR, 16- or 32-bit length;
//! items and delimiters of sequences, 7.5). dicom-rs allocates each value from its declared length
//! before reading it, so a hostile four-byte length could make it reserve (and zero) up to 4 GiB.
//! Walking the headers first and refusing any length that runs past the end of the file keeps
//! every allocation below the size of the input, in the browser and in the CLI.

use dicom_core::dictionary::{DataDictionary, DataDictionaryEntry, VirtualVr};
use dicom_core::{Tag, VR};
use dicom_dictionary_std::StandardDataDictionary;

use crate::error::{CoreError, Result};

/// Value representations with a 16-bit length in explicit VR (PS3.5 table 7.1-2); every other
/// VR, and any unknown one (which dicom-rs reads as UN), has a 2-byte reserved field and a
/// 32-bit length.
const SHORT_VRS: [&[u8; 2]; 21] = [
    b"AE", b"AS", b"AT", b"CS", b"DA", b"DS", b"DT", b"FL", b"FD", b"IS", b"LO", b"LT", b"PN",
    b"SH", b"SL", b"SS", b"ST", b"TM", b"UI", b"UL", b"US",
];

/// Bytes dicom-rs actually consumes for a value of `len` bytes: binary numbers are read whole
/// (a UL of length 1 reads nothing), so the walk must step as far as the parser does or the two
/// would read different headers from then on.
fn consumed(vr: [u8; 2], len: usize) -> usize {
    let unit = match &vr {
        b"US" | b"SS" | b"OW" => 2,
        b"UL" | b"SL" | b"FL" | b"AT" | b"OF" | b"OL" => 4,
        b"FD" | b"OD" | b"SV" | b"UV" | b"OV" => 8,
        _ => 1,
    };
    len - len % unit
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Encoding {
    ExplicitLittle,
    ImplicitLittle,
    ExplicitBig,
}

/// Checks `bytes` (a whole file: preamble optional, or a bare implicit VR data set).
pub fn check_lengths(bytes: &[u8]) -> Result<()> {
    let body = if bytes.get(128..132) == Some(b"DICM") {
        &bytes[132..]
    } else if let Some(rest) = bytes.strip_prefix(b"DICM") {
        rest
    } else {
        return walk(bytes, Encoding::ImplicitLittle, None).map(|_| ());
    };
    // The file meta group is always explicit VR little endian; it names the data set's encoding.
    let (meta_end, syntax) = walk(body, Encoding::ExplicitLittle, Some(0x0002))?;
    let rest = &body[meta_end..];
    let enc = match syntax.as_deref() {
        Some("1.2.840.10008.1.2") => Encoding::ImplicitLittle,
        Some("1.2.840.10008.1.2.2") => Encoding::ExplicitBig,
        // Deflated data sets are not walkable (dicom-rs without its deflate feature refuses them).
        Some("1.2.840.10008.1.2.1.99") => return Ok(()),
        _ => Encoding::ExplicitLittle,
    };
    walk(rest, enc, None).map(|_| ())
}

fn too_long(tag: Tag, len: usize, left: usize) -> CoreError {
    CoreError::parse(
        0,
        format!(
            "DICOM element ({:04X},{:04X}) declares {len} bytes but only {left} remain: \
             truncated or corrupt file",
            tag.0, tag.1
        ),
    )
}

/// What the bytes inside an undefined-length element are.
#[derive(Clone, Copy)]
enum Inside {
    /// Items holding data sets, in the given encoding (restored at the sequence delimiter).
    Items(Encoding),
    /// Encapsulated pixel data: items are raw byte fragments.
    Fragments(Encoding),
}

/// Walks element headers from the start of `data`, stepping into sequences and items and over
/// values. With `only_group`, stops at the first element of another group (the end of the meta
/// group) and returns its offset and the Transfer Syntax UID found on the way.
fn walk(data: &[u8], enc: Encoding, only_group: Option<u16>) -> Result<(usize, Option<String>)> {
    let mut enc = enc;
    let mut stack: Vec<Inside> = Vec::new();
    let mut pos = 0usize;
    let mut syntax = None;
    // A partial header at the very end is left to the parser, which reports it.
    loop {
        let big = enc == Encoding::ExplicitBig;
        let u16_at = |at: usize| -> Option<u16> {
            let b: [u8; 2] = data.get(at..at + 2)?.try_into().ok()?;
            Some(if big {
                u16::from_be_bytes(b)
            } else {
                u16::from_le_bytes(b)
            })
        };
        let u32_at = |at: usize| -> Option<u32> {
            let b: [u8; 4] = data.get(at..at + 4)?.try_into().ok()?;
            Some(if big {
                u32::from_be_bytes(b)
            } else {
                u32::from_le_bytes(b)
            })
        };
        let (Some(group), Some(element)) = (u16_at(pos), u16_at(pos + 2)) else {
            break;
        };
        let tag = Tag(group, element);
        if only_group.is_some_and(|g| g != group) {
            break;
        }
        if group == 0xFFFE {
            // Item or delimiter: tag and a 32-bit length, never a VR.
            let Some(len) = u32_at(pos + 4) else { break };
            pos += 8;
            // Delimiters have length 0 (PS3.5 7.5); dicom-rs reads a value for one that does not,
            // so such a file is refused here.
            if matches!(element, 0xE00D | 0xE0DD) && len != 0 {
                return Err(CoreError::parse(
                    0,
                    format!("DICOM delimiter (FFFE,{element:04X}) with length {len}: corrupt file"),
                ));
            }
            match (element, stack.last().copied()) {
                (0xE0DD, Some(inside)) => {
                    stack.pop();
                    enc = match inside {
                        Inside::Items(e) | Inside::Fragments(e) => e,
                    };
                }
                (0xE000, Some(Inside::Fragments(_))) if len != u32::MAX => {
                    let left = data.len().saturating_sub(pos);
                    if len as usize > left {
                        return Err(too_long(tag, len as usize, left));
                    }
                    pos += len as usize;
                }
                // An item of defined length can never run past the end of the file; outside a
                // sequence dicom-rs would read it as one value of that length.
                (0xE000, _) if len != u32::MAX && len as usize > data.len().saturating_sub(pos) => {
                    return Err(too_long(tag, len as usize, data.len().saturating_sub(pos)));
                }
                // Items holding data sets are stepped into.
                (0xE000 | 0xE00D | 0xE0DD, _) => {}
                // Any other element of group FFFE is read as a plain value by dicom-rs.
                _ if len != u32::MAX => {
                    let left = data.len().saturating_sub(pos);
                    if len as usize > left {
                        return Err(too_long(tag, len as usize, left));
                    }
                    pos += len as usize;
                }
                _ => {}
            }
            continue;
        }
        let explicit = enc != Encoding::ImplicitLittle;
        let (len, header, vr) = if explicit {
            let Some(vr) = data.get(pos + 4..pos + 6) else {
                break;
            };
            let vr: [u8; 2] = [vr[0], vr[1]];
            if SHORT_VRS.iter().any(|v| **v == vr) {
                let Some(len) = u16_at(pos + 6) else { break };
                (u32::from(len), 8, vr)
            } else {
                let Some(len) = u32_at(pos + 8) else { break };
                (len, 12, vr)
            }
        } else {
            let Some(len) = u32_at(pos + 4) else { break };
            // The dictionary's VR, as dicom-rs uses it for implicit VR data sets.
            let vr = match StandardDataDictionary.by_tag(tag).map(|e| e.vr()) {
                Some(VirtualVr::Exact(vr)) => vr,
                _ => VR::UN,
            };
            let code = match vr.to_string().as_bytes() {
                [a, b, ..] => [*a, *b],
                _ => *b"UN",
            };
            (len, 8, code)
        };
        pos += header;
        if len == u32::MAX {
            // Undefined length: a sequence whose items follow, UN holding an implicit VR little
            // endian sequence, or encapsulated pixel data.
            match &vr {
                b"SQ" => stack.push(Inside::Items(enc)),
                // Implicit VR has no encapsulated pixel data: a data set sequence.
                _ if !explicit => stack.push(Inside::Items(enc)),
                b"UN" => {
                    stack.push(Inside::Items(enc));
                    enc = Encoding::ImplicitLittle;
                }
                _ => stack.push(Inside::Fragments(enc)),
            }
            continue;
        }
        let len = len as usize;
        let left = data.len().saturating_sub(pos);
        if len > left {
            return Err(too_long(tag, len, left));
        }
        if &vr == b"SQ" {
            // A defined-length sequence: its items are walked like the rest.
            continue;
        }
        if tag == Tag(0x0002, 0x0010) {
            let v = String::from_utf8_lossy(&data[pos..pos + len]);
            syntax = Some(v.trim_end_matches(['\0', ' ']).to_string());
        }
        pos += consumed(vr, len);
    }
    Ok((pos, syntax))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn huge_declared_lengths_are_refused_before_parsing() {
        // Implicit VR: (0008,0005) with a length of "garb" (about 1.6 GB).
        let e = check_lengths(b"\x08\x00\x05\x00garbage that is no DICOM").unwrap_err();
        assert!(
            e.to_string()
                .contains("(0008,0005) declares 1651663207 bytes"),
            "{e}"
        );
        // Explicit VR long form in the meta group.
        let mut f = b"DICM\x02\x00\x01\x00OB\x00\x00\xff\xff\xff\x7f".to_vec();
        f.extend_from_slice(&[0; 10]);
        let e = check_lengths(&f).unwrap_err();
        assert!(
            e.to_string()
                .contains("declares 2147483647 bytes but only 10 remain"),
            "{e}"
        );
    }

    /// Found by the rtstruct fuzz target: (000F,0000) is a group length (UL) of declared length 1,
    /// which dicom-rs reads as zero values, so the next header starts one byte earlier than the
    /// declared length says; there it finds a length of 0xFFFFFF02.
    #[test]
    fn walk_follows_the_parser_through_short_numbers() {
        let b = [
            0u8, 0, 0, 0, 0, 0, 0, 0, 15, 0, 0, 0, 1, 0, 0, 0, 39, 0, 0, 0, 2, 255, 255, 255, 255,
            0, 0, 39, 0,
        ];
        let e = check_lengths(&b).unwrap_err();
        assert!(
            e.to_string()
                .contains("(0027,0000) declares 4294967042 bytes"),
            "{e}"
        );
    }

    /// Second fuzz find: sequence delimiters with non-zero lengths (one of 0xFA000000), which
    /// dicom-rs reads as values.
    #[test]
    fn delimiters_with_a_length_are_refused() {
        let b = std::fs::read(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../fuzz/regressions/rtstruct-oom-fd873c90.dcm"
        ))
        .unwrap();
        let e = check_lengths(&b).unwrap_err();
        assert!(
            e.to_string().contains("delimiter (FFFE,E0DD) with length"),
            "{e}"
        );
    }

    #[test]
    fn items_longer_than_the_file_are_refused() {
        // Found by the rtstruct fuzz target (third run): an item of length 0xFFDFFFFF after a
        // sequence's delimiter made dicom-rs allocate 4 GiB.
        let b = std::fs::read(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../fuzz/regressions/rtstruct-oom-c00fae35.dcm"
        ))
        .unwrap();
        let e = check_lengths(&b).unwrap_err();
        assert!(e.to_string().contains("FFFE,E000"), "{e}");
    }

    #[test]
    fn real_files_pass() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/patient1-ED-rtstruct.dcm");
        let bytes = std::fs::read(path).unwrap();
        check_lengths(&bytes).unwrap();
        check_lengths(&bytes[128..]).unwrap();
        // Any cut still passes the length walk or names the element that runs past the end.
        for cut in (140..bytes.len()).step_by(997) {
            if let Err(e) = check_lengths(&bytes[..cut]) {
                assert!(e.to_string().contains("remain"), "{e}");
            }
        }
    }
}
