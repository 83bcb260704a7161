//! The files inside a ZIP archive, as studies are handed out: UK Biobank delivers each subject's
//! cvi42 workspace and each DICOM series as a `.zip`.
//!
//! Reference: PKWARE APPNOTE 6.3.x, sections 4.3.7 (local file header), 4.3.12 (central directory
//! file header) and 4.3.16 (end of central directory record). Members are found through the
//! central directory (local headers may leave sizes to a trailing data descriptor), stored
//! (method 0) or deflated (method 8). Why our own: the `zip` crate needs a random source and a
//! zlib port of its own in WebAssembly; this reader is bounded like `dicom_read`: every offset and
//! size is checked against the archive, and inflating stops at a budget whatever the archive
//! declares (a zip bomb ends in a clear error, not an out-of-memory tab).

use miniz_oxide::inflate::{decompress_to_vec_with_limit, TINFLStatus};

use crate::error::{CoreError, Result};

/// Largest total of unpacked bytes: far above a cine study's headers and contours, low enough
/// for a browser tab.
pub const MAX_UNPACKED: usize = 1 << 30;

const LOCAL: u32 = 0x0403_4b50;
const CENTRAL: u32 = 0x0201_4b50;
const END: u32 = 0x0605_4b50;

/// True when the bytes start like a ZIP archive (a local file header, or an empty archive).
pub fn is_zip(bytes: &[u8]) -> bool {
    bytes.starts_with(b"PK\x03\x04") || bytes.starts_with(b"PK\x05\x06")
}

/// One file of an archive: its path inside it, and its bytes.
#[derive(Debug, Clone, PartialEq)]
pub struct Member {
    pub name: String,
    pub bytes: Vec<u8>,
}

fn fail(message: impl std::fmt::Display) -> CoreError {
    CoreError::parse(0, format!("ZIP archive: {message}"))
}

fn u16_at(b: &[u8], at: usize) -> Result<u16> {
    b.get(at..at + 2)
        .map(|s| u16::from_le_bytes([s[0], s[1]]))
        .ok_or_else(|| fail(format!("truncated at byte {at}")))
}

fn u32_at(b: &[u8], at: usize) -> Result<u32> {
    b.get(at..at + 4)
        .map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
        .ok_or_else(|| fail(format!("truncated at byte {at}")))
}

fn slice(b: &[u8], at: usize, len: usize) -> Result<&[u8]> {
    at.checked_add(len)
        .and_then(|end| b.get(at..end))
        .ok_or_else(|| fail(format!("{len} bytes at byte {at} run past the end")))
}

/// The end of central directory record: searched back from the end over the longest comment.
fn end_record(b: &[u8]) -> Result<usize> {
    let lowest = b.len().saturating_sub(22 + usize::from(u16::MAX));
    (lowest..=b.len().saturating_sub(22))
        .rev()
        .find(|&at| u32_at(b, at).ok() == Some(END))
        .ok_or_else(|| fail("no end of central directory: truncated or not an archive"))
}

/// Metadata and junk a packer adds beside the files (macOS resource forks, hidden files).
fn is_clutter(name: &str) -> bool {
    name.ends_with('/')
        || name.starts_with("__MACOSX/")
        || name
            .rsplit('/')
            .next()
            .is_some_and(|base| base.starts_with('.'))
}

/// Every file of the archive, in central directory order (folders, `__MACOSX/` and hidden
/// files left out), unpacked up to [`MAX_UNPACKED`] bytes in all.
pub fn members(b: &[u8]) -> Result<Vec<Member>> {
    members_within(b, MAX_UNPACKED)
}

fn members_within(b: &[u8], limit: usize) -> Result<Vec<Member>> {
    let end = end_record(b)?;
    let count = u16_at(b, end + 10)?;
    let dir_size = u32_at(b, end + 12)?;
    let dir_at = u32_at(b, end + 16)?;
    if count == u16::MAX || dir_size == u32::MAX || dir_at == u32::MAX {
        return Err(fail(
            "a ZIP64 archive (over 4 GB or 65535 files): unpack it first",
        ));
    }
    let dir = slice(b, dir_at as usize, dir_size as usize)?;
    let mut out = Vec::new();
    let mut budget = limit;
    let mut at = 0usize;
    for _ in 0..count {
        if u32_at(dir, at)? != CENTRAL {
            return Err(fail(format!(
                "central directory entry expected at byte {}",
                dir_at as usize + at
            )));
        }
        let flags = u16_at(dir, at + 8)?;
        let method = u16_at(dir, at + 10)?;
        let packed = u32_at(dir, at + 20)? as usize;
        let name_len = usize::from(u16_at(dir, at + 28)?);
        let extra_len = usize::from(u16_at(dir, at + 30)?);
        let comment_len = usize::from(u16_at(dir, at + 32)?);
        let local = u32_at(dir, at + 42)? as usize;
        let name = String::from_utf8_lossy(slice(dir, at + 46, name_len)?).into_owned();
        at += 46 + name_len + extra_len + comment_len;
        if is_clutter(&name) {
            continue;
        }
        if flags & 1 == 1 {
            return Err(fail(format!("{name} is encrypted: unpack it first")));
        }
        if u32_at(b, local)? != LOCAL {
            return Err(fail(format!("{name}: no local header at byte {local}")));
        }
        let header = 30 + usize::from(u16_at(b, local + 26)?) + usize::from(u16_at(b, local + 28)?);
        let data_at = local
            .checked_add(header)
            .ok_or_else(|| fail(format!("{name}: local header past the end")))?;
        let data = slice(b, data_at, packed)?;
        let bytes = match method {
            0 if data.len() <= budget => data.to_vec(),
            8 => decompress_to_vec_with_limit(data, budget).map_err(|e| {
                if e.status == TINFLStatus::HasMoreOutput {
                    fail(format!(
                        "{name}: unpacks to more than the {limit} bytes read from one archive"
                    ))
                } else {
                    fail(format!("{name}: corrupt deflate data"))
                }
            })?,
            0 => {
                return Err(fail(format!(
                    "more than the {limit} bytes read from one archive"
                )))
            }
            m => {
                return Err(fail(format!(
                    "{name} is packed with method {m}; only stored and deflated files are read"
                )))
            }
        };
        budget -= bytes.len();
        out.push(Member { name, bytes });
    }
    Ok(out)
}

#[cfg(test)]
mod tests;
