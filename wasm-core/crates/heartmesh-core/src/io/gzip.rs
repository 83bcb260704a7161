//! gzip-compressed input (`.nii.gz`, `contours.csv.gz`): inflated in memory with a bound, since a
//! few kilobytes of gzip can inflate to gigabytes.

use std::borrow::Cow;
use std::io::Read;

use crate::error::{CoreError, Result};

/// Largest inflated size accepted (bytes): a cine label map of 256 x 256 x 20 slices x 50 frames
/// is 66 MB in 8 bits (UK Biobank's and M&Ms' are 25-50 MB); nothing a contour reader takes comes
/// near it, and a browser worker must hold it whole.
pub const MAX_INFLATED_BYTES: usize = 128 << 20;

/// Deflate's largest compression ratio (a run of one byte: 258 bytes per 2-bit code, ~1032:1).
pub(crate) const DEFLATE_MAX_RATIO: usize = 1032;

/// Whether `bytes` is gzip data.
pub fn is_gzip(bytes: &[u8]) -> bool {
    bytes.starts_with(&[0x1f, 0x8b])
}

/// The bytes, inflated when they are gzip (every member of a multi-member file), refused past
/// [`MAX_INFLATED_BYTES`].
pub fn inflate(bytes: &[u8]) -> Result<Cow<'_, [u8]>> {
    if !is_gzip(bytes) {
        return Ok(Cow::Borrowed(bytes));
    }
    // The trailer's size (modulo 4 GiB, of the last member) saves the doublings of a growing
    // buffer, which would briefly need twice the memory. It is only a hint, and believed no
    // further than deflate can compress (at most ~1032:1), so a lying trailer cannot reserve more.
    let hint = bytes
        .len()
        .checked_sub(4)
        .and_then(|at| bytes.get(at..))
        .map_or(0, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize);
    let mut out = Vec::with_capacity(
        hint.min(bytes.len().saturating_mul(DEFLATE_MAX_RATIO))
            .min(MAX_INFLATED_BYTES + 1),
    );
    flate2::read::MultiGzDecoder::new(bytes)
        .take(MAX_INFLATED_BYTES as u64 + 1)
        .read_to_end(&mut out)
        .map_err(|e| CoreError::parse(0, format!("the gzip data is damaged ({e})")))?;
    if out.len() > MAX_INFLATED_BYTES {
        return Err(CoreError::parse(
            0,
            format!(
                "the file is larger than {} MB once decompressed: the limit",
                MAX_INFLATED_BYTES >> 20
            ),
        ));
    }
    Ok(Cow::Owned(out))
}

/// The first `n` bytes of a gzip stream, inflated (for format detection without inflating it
/// all); whatever inflates before an error.
pub fn inflate_head(bytes: &[u8], n: usize) -> Vec<u8> {
    let mut out = Vec::new();
    let _ = flate2::read::MultiGzDecoder::new(bytes)
        .take(n as u64)
        .read_to_end(&mut out);
    out
}

/// `data` gzip-compressed (what the label-map writers save as `.gz` / `encoding: gzip`).
pub fn deflate(data: &[u8]) -> Vec<u8> {
    use std::io::Write;
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    // Writing into a Vec cannot fail.
    let _ = gz.write_all(data);
    gz.finish().unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn gzip(data: &[u8], level: flate2::Compression) -> Vec<u8> {
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), level);
        gz.write_all(data).unwrap();
        gz.finish().unwrap()
    }

    #[test]
    fn gzip_is_inflated_and_bounded() {
        let raw = b"contour,x,y,z\n".repeat(100);
        let gz = gzip(&raw, flate2::Compression::default());
        assert!(is_gzip(&gz) && !is_gzip(&raw));
        assert_eq!(&*inflate(&gz).unwrap(), &raw[..]);
        assert_eq!(inflate_head(&gz, 8), &raw[..8]);
        assert!(inflate(&gz[..gz.len() / 2]).is_err());
        let bomb = gzip(
            &vec![0u8; MAX_INFLATED_BYTES + (1 << 20)],
            flate2::Compression::best(),
        );
        assert!(bomb.len() < 1 << 20);
        assert!(inflate(&bomb).unwrap_err().to_string().contains("limit"));
    }
}
