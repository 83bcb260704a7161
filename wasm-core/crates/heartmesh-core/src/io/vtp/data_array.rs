//! Binary DataArrays of VTK XML files, as `vtkXMLWriter` writes them ("VTK File Formats", XML
//! section; `vtkXMLDataParser` reads them): the bytes an array holds once its header is read and
//! its zlib blocks inflated, then those bytes as numbers or strings.
//!
//! Every array starts with a header of unsigned words (`header_type`: UInt32, the default, or
//! UInt64; in the file's byte order):
//! - uncompressed: one word, the data's byte count, then the data;
//! - compressed: the block count, the uncompressed block size, the last block's uncompressed size
//!   (0 when it is a full block) and each block's compressed size, then the blocks.
//!
//! In base64 (inline `format="binary"`, or `<AppendedData encoding="base64">`) an uncompressed
//! array is one base64 run (header and data together), while a compressed one is two separately
//! padded runs: the header, then the blocks. [`Stream`] reads such runs from either encoding.
//!
//! Nothing here knows XML: the caller finds where an array starts and adds the line number to
//! the messages. Every size comes from the file, so every one is checked against the bytes that
//! are really there before anything is allocated, and inflating is capped by a budget.

use std::borrow::Cow;

use crate::io::gzip::DEFLATE_MAX_RATIO;

/// A message for the caller to put a line number on.
pub(super) type Fallible<T> = std::result::Result<T, String>;

/// How the file's arrays are stored, from the `<VTKFile>` attributes.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Layout {
    /// Bytes per header word: 4 (`header_type="UInt32"`, the default) or 8 (`UInt64`).
    pub word: usize,
    /// `byte_order="BigEndian"` (headers and data alike).
    pub big_endian: bool,
    pub compressor: Compressor,
}

/// The `compressor` attribute.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Compressor {
    None,
    Zlib,
    /// LZ4, LZMA or anything else, refused when a binary array needs it (an ascii file from VTK
    /// names a compressor it did not use).
    Unsupported(String),
}

impl Layout {
    pub fn new(
        header_type: Option<&str>,
        byte_order: Option<&str>,
        compressor: Option<&str>,
    ) -> Fallible<Layout> {
        let word = match header_type.map(str::trim) {
            None | Some("UInt32") => 4,
            Some("UInt64") => 8,
            Some(other) => {
                return Err(format!(
                    "header_type {other:?} is not supported (UInt32 or UInt64)"
                ))
            }
        };
        let compressor = match compressor.map(str::trim) {
            None | Some("") => Compressor::None,
            Some("vtkZLibDataCompressor") => Compressor::Zlib,
            Some(other) => Compressor::Unsupported(other.to_string()),
        };
        Ok(Layout {
            word,
            big_endian: byte_order.map(str::trim) == Some("BigEndian"),
            compressor,
        })
    }

    /// Header word `k` of `header` (which holds at least `k + 1` words) as a size.
    fn word_at(&self, header: &[u8], k: usize) -> Fallible<usize> {
        let w = self.word;
        let b = &header[k * w..(k + 1) * w];
        let mut buf = [0u8; 8];
        buf[..w].copy_from_slice(b);
        if self.big_endian {
            buf[..w].reverse();
        }
        usize::try_from(u64::from_le_bytes(buf))
            .map_err(|_| "a size in the array's header is too large".to_string())
    }
}

/// Where one array's data lies: raw bytes, or base64 text, from the array's start on (to the end
/// of the inline text or of the appended block: the header says how much belongs to it).
pub(super) struct Stream<'a> {
    data: &'a [u8],
    base64: bool,
    pos: usize,
}

impl<'a> Stream<'a> {
    pub fn raw(data: &'a [u8], start: usize) -> Self {
        Stream {
            data,
            base64: false,
            pos: start,
        }
    }

    /// Base64 text without whitespace inside (VTK writes none; inline text is stripped first).
    pub fn base64(text: &'a [u8], start: usize) -> Self {
        Stream {
            data: text,
            base64: true,
            pos: start,
        }
    }

    /// The next `n` bytes written as one piece (in base64: one padded run), and where the piece
    /// ends. The piece must be there in full, so a size from a hostile header allocates nothing.
    fn piece(&self, n: usize) -> Fallible<(Cow<'a, [u8]>, usize)> {
        let len = if self.base64 {
            n.div_ceil(3).checked_mul(4)
        } else {
            Some(n)
        };
        let data = self.data;
        let end = len
            .and_then(|l| self.pos.checked_add(l))
            .filter(|&e| e <= data.len())
            .ok_or_else(|| {
                format!(
                    "the array's data ends early: {n} bytes wanted at {}, past the end of the data \
                     (truncated or damaged file?)",
                    self.pos
                )
            })?;
        let run = &data[self.pos..end];
        if !self.base64 {
            return Ok((Cow::Borrowed(run), end));
        }
        let mut bytes = super::base64::decode(run).ok_or("invalid base64 data")?;
        if bytes.len() < n {
            return Err("the array's base64 data ends early (damaged file?)".into());
        }
        bytes.truncate(n);
        Ok((Cow::Owned(bytes), end))
    }

    fn peek(&self, n: usize) -> Fallible<Cow<'a, [u8]>> {
        self.piece(n).map(|(b, _)| b)
    }

    fn take(&mut self, n: usize) -> Fallible<Cow<'a, [u8]>> {
        let (b, end) = self.piece(n)?;
        self.pos = end;
        Ok(b)
    }
}

/// The data bytes of the array that starts `stream`: its header read, its blocks inflated.
/// `budget` is what may still be inflated in this file; it shrinks by what this array inflates.
pub(super) fn array_bytes(
    layout: &Layout,
    mut stream: Stream,
    budget: &mut usize,
) -> Fallible<Vec<u8>> {
    let w = layout.word;
    match &layout.compressor {
        Compressor::None => {
            let n = layout.word_at(&stream.peek(w)?, 0)?;
            let all = stream.take(w.checked_add(n).ok_or("array size overflows")?)?;
            Ok(all[w..].to_vec())
        }
        Compressor::Unsupported(name) => Err(format!(
            "compressor {name} is not supported: save the file uncompressed or with zlib \
             (vtkZLibDataCompressor)"
        )),
        Compressor::Zlib => inflate_blocks(layout, stream, budget),
    }
}

fn inflate_blocks(layout: &Layout, mut stream: Stream, budget: &mut usize) -> Fallible<Vec<u8>> {
    let w = layout.word;
    let head = stream.peek(3 * w)?;
    let blocks = layout.word_at(&head, 0)?;
    let block_size = layout.word_at(&head, 1)?;
    let last = layout.word_at(&head, 2)?;
    // The whole header must be in the file before its block count is believed.
    let header_bytes = blocks
        .checked_add(3)
        .and_then(|k| k.checked_mul(w))
        .ok_or("the block count overflows")?;
    let head = stream.take(header_bytes)?;
    if blocks == 0 {
        return Ok(Vec::new());
    }
    if last > block_size {
        return Err(format!(
            "the last block's size {last} exceeds the block size {block_size} (damaged file?)"
        ));
    }
    let sizes = (0..blocks)
        .map(|k| layout.word_at(&head, 3 + k))
        .collect::<Fallible<Vec<usize>>>()?;
    let compressed = sizes
        .iter()
        .try_fold(0usize, |a, &s| a.checked_add(s))
        .ok_or("the compressed sizes overflow")?;
    let full_blocks = if last == 0 { blocks } else { blocks - 1 };
    let total = full_blocks
        .checked_mul(block_size)
        .and_then(|t| t.checked_add(last))
        .ok_or("the uncompressed size overflows")?;
    let data = stream.take(compressed)?;
    if total > *budget {
        return Err(format!(
            "the file is larger than {} MB once decompressed: the limit",
            crate::io::gzip::MAX_INFLATED_BYTES >> 20
        ));
    }
    *budget -= total;
    // Deflate cannot compress more than ~1032:1, so a lying header reserves no more than that.
    let mut out = Vec::with_capacity(total.min(compressed.saturating_mul(DEFLATE_MAX_RATIO)));
    let mut at = 0;
    for (k, &size) in sizes.iter().enumerate() {
        let want = if k + 1 == blocks && last != 0 {
            last
        } else {
            block_size
        };
        // In bounds: the sizes sum to `data.len()`.
        let block = &data[at..at + size];
        at += size;
        let inflated = miniz_oxide::inflate::decompress_to_vec_zlib_with_limit(block, want)
            .map_err(|e| {
                format!(
                    "compressed block {} of {blocks} is damaged or larger than its header says \
                     ({:?})",
                    k + 1,
                    e.status
                )
            })?;
        if inflated.len() != want {
            return Err(format!(
                "compressed block {} of {blocks} holds {} bytes; its header says {want}",
                k + 1,
                inflated.len()
            ));
        }
        out.extend_from_slice(&inflated);
    }
    Ok(out)
}

/// Bytes per value of a DataArray `type`, None for types that are no numbers.
fn value_size(ty: &str) -> Option<usize> {
    Some(match ty {
        "Int8" | "UInt8" | "Char" | "UChar" => 1,
        "Int16" | "UInt16" => 2,
        "Int32" | "UInt32" | "Float32" => 4,
        "Int64" | "UInt64" | "Float64" | "vtkIdType" => 8,
        _ => return None,
    })
}

/// The array's bytes as numbers of its `type` (64-bit integers beyond 2^53 round, as in any
/// f64), at most `max_values` of them.
pub(super) fn numbers(
    bytes: &[u8],
    ty: &str,
    big_endian: bool,
    max_values: usize,
) -> Fallible<Vec<f64>> {
    let size = value_size(ty).ok_or_else(|| format!("unknown DataArray type {ty:?}"))?;
    if !bytes.len().is_multiple_of(size) {
        return Err(format!(
            "{} bytes of data are not a whole number of {ty} values",
            bytes.len()
        ));
    }
    if bytes.len() / size > max_values {
        return Err("data array exceeds the size limit".into());
    }
    let mut out = Vec::with_capacity(bytes.len() / size);
    for c in bytes.chunks_exact(size) {
        let mut b = [0u8; 8];
        b[..size].copy_from_slice(c);
        if big_endian {
            b[..size].reverse();
        }
        let u = u64::from_le_bytes(b);
        out.push(match ty {
            "Int8" | "Char" => u as u8 as i8 as f64,
            "Int16" => u as u16 as i16 as f64,
            "Int32" => u as u32 as i32 as f64,
            "Int64" | "vtkIdType" => u as i64 as f64,
            "Float32" => f32::from_bits(u as u32) as f64,
            "Float64" => f64::from_bits(u),
            _ => u as f64,
        });
    }
    Ok(out)
}

/// A String array's bytes: each string's UTF-8 bytes followed by a 0 (as VTK writes them in
/// every format; the ascii form lists the same bytes as numbers). A last string without its 0
/// is kept.
pub(super) fn strings(bytes: &[u8]) -> Vec<String> {
    let bytes = bytes.strip_suffix(&[0]).unwrap_or(bytes);
    if bytes.is_empty() {
        return Vec::new();
    }
    bytes
        .split(|&b| b == 0)
        .map(|s| String::from_utf8_lossy(s).into_owned())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout(word: usize, big_endian: bool, compressor: Compressor) -> Layout {
        Layout {
            word,
            big_endian,
            compressor,
        }
    }

    fn words(values: &[u64], word: usize, big: bool) -> Vec<u8> {
        let mut out = Vec::new();
        for &v in values {
            let b = v.to_le_bytes();
            let mut w = b[..word].to_vec();
            if big {
                w.reverse();
            }
            out.extend(w);
        }
        out
    }

    fn b64(bytes: &[u8]) -> Vec<u8> {
        const T: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut out = Vec::new();
        for c in bytes.chunks(3) {
            let n = (c[0] as u32) << 16
                | (*c.get(1).unwrap_or(&0) as u32) << 8
                | *c.get(2).unwrap_or(&0) as u32;
            for k in 0..4 {
                out.push(if k <= c.len() {
                    T[(n >> (18 - 6 * k) & 63) as usize]
                } else {
                    b'='
                });
            }
        }
        out
    }

    /// `data` as VTK writes a zlib-compressed array: blocks of `block` bytes, header first.
    fn compressed(data: &[u8], block: usize, word: usize, big: bool) -> (Vec<u8>, Vec<u8>) {
        let blocks: Vec<Vec<u8>> = data
            .chunks(block)
            .map(|c| miniz_oxide::deflate::compress_to_vec_zlib(c, 6))
            .collect();
        let last = data.len() % block;
        let mut head = vec![blocks.len() as u64, block as u64, last as u64];
        head.extend(blocks.iter().map(|b| b.len() as u64));
        (words(&head, word, big), blocks.concat())
    }

    #[test]
    fn uncompressed_raw_and_base64() {
        let data: Vec<u8> = (0..40u8).collect();
        for word in [4, 8] {
            for big in [false, true] {
                let l = layout(word, big, Compressor::None);
                let mut file = b"junk".to_vec();
                file.extend(words(&[40], word, big));
                file.extend(&data);
                file.extend(b"next array");
                let mut budget = 0;
                let got = array_bytes(&l, Stream::raw(&file, 4), &mut budget).unwrap();
                assert_eq!(got, data);
                let text = b64(&file[4..]);
                let got = array_bytes(&l, Stream::base64(&text, 0), &mut budget).unwrap();
                assert_eq!(got, data);
                // Cut short: an error, never a panic.
                for cut in [0, 3, word + 39] {
                    assert!(array_bytes(&l, Stream::raw(&file[..4 + cut], 4), &mut 0).is_err());
                }
            }
        }
    }

    #[test]
    fn zlib_blocks_raw_and_base64() {
        let data: Vec<u8> = (0..1000u32).flat_map(|k| (k * k).to_le_bytes()).collect();
        for (block, word, big) in [(1024, 4, false), (4000, 8, true), (32768, 4, false)] {
            let l = layout(word, big, Compressor::Zlib);
            let (head, blocks) = compressed(&data, block, word, big);
            let raw = [head.clone(), blocks.clone()].concat();
            let mut budget = 1 << 20;
            assert_eq!(
                array_bytes(&l, Stream::raw(&raw, 0), &mut budget).unwrap(),
                data
            );
            assert_eq!(budget, (1 << 20) - data.len());
            // Two separately padded base64 runs.
            let text = [b64(&head), b64(&blocks)].concat();
            let got = array_bytes(&l, Stream::base64(&text, 0), &mut budget).unwrap();
            assert_eq!(got, data);
            // The budget caps what inflates.
            let e = array_bytes(&l, Stream::raw(&raw, 0), &mut 100).unwrap_err();
            assert!(e.contains("limit"), "{e}");
        }
        // An empty array: no blocks.
        let l = layout(4, false, Compressor::Zlib);
        let empty = words(&[0, 32768, 0], 4, false);
        assert!(array_bytes(&l, Stream::raw(&empty, 0), &mut 0)
            .unwrap()
            .is_empty());
    }

    #[test]
    fn hostile_headers_are_errors() {
        let data = vec![7u8; 5000];
        let l = layout(4, false, Compressor::Zlib);
        let (head, blocks) = compressed(&data, 4096, 4, false);
        let file = |head: &[u64]| [words(head, 4, false), blocks.clone()].concat();
        let sizes: Vec<u64> = head
            .chunks(4)
            .map(|c| u32::from_le_bytes(c.try_into().unwrap()) as u64)
            .collect();
        let run = |f: &[u8]| array_bytes(&l, Stream::raw(f, 0), &mut (1 << 27));
        assert_eq!(run(&file(&sizes)).unwrap(), data);
        let cases: Vec<(&str, Vec<u64>)> = vec![
            (
                "2^32-1 blocks",
                vec![u32::MAX as u64, 4096, 904, sizes[3], sizes[4]],
            ),
            (
                "huge block",
                vec![2, u32::MAX as u64, 904, sizes[3], sizes[4]],
            ),
            (
                "compressed size past the end",
                vec![2, 4096, 904, sizes[3], 1 << 30],
            ),
            ("last > block", vec![2, 4096, 5000, sizes[3], sizes[4]]),
            (
                "block bigger than said",
                vec![2, 1000, 904, sizes[3], sizes[4]],
            ),
            (
                "block smaller than said",
                vec![2, 4096, 1000, sizes[3], sizes[4]],
            ),
            ("sizes swapped", vec![2, 4096, 904, sizes[4], sizes[3]]),
        ];
        for (what, head) in cases {
            assert!(run(&file(&head)).is_err(), "{what}");
        }
        let whole = file(&sizes);
        for cut in [0, 5, 12, 19, whole.len() - 1] {
            assert!(run(&whole[..cut]).is_err(), "cut at {cut}");
        }
        let none = layout(8, false, Compressor::None);
        let lie = words(&[u64::MAX], 8, false);
        assert!(array_bytes(&none, Stream::raw(&lie, 0), &mut 0).is_err());
        assert!(array_bytes(&none, Stream::raw(&lie, 100), &mut 0).is_err());
        assert!(array_bytes(&none, Stream::base64(b"AA$AAAAA", 0), &mut 0).is_err());
    }

    #[test]
    fn unsupported_compressors_are_named() {
        let l = Layout::new(None, None, Some("vtkLZ4DataCompressor")).unwrap();
        let e = array_bytes(&l, Stream::raw(&[0; 16], 0), &mut 0).unwrap_err();
        assert!(
            e.contains("vtkLZ4DataCompressor") && e.contains("zlib"),
            "{e}"
        );
        assert!(Layout::new(Some("UInt16"), None, None).is_err());
        assert_eq!(Layout::new(Some("UInt64"), None, None).unwrap().word, 8);
    }

    #[test]
    fn every_numeric_type() {
        let le = |v: &[i64], size: usize| -> Vec<u8> {
            v.iter()
                .flat_map(|x| x.to_le_bytes()[..size].to_vec())
                .collect()
        };
        let v = [-3i64, 0, 5, 100];
        for (ty, size) in [("Int8", 1), ("Int16", 2), ("Int32", 4), ("Int64", 8)] {
            assert_eq!(
                numbers(&le(&v, size), ty, false, 10).unwrap(),
                [-3.0, 0.0, 5.0, 100.0],
                "{ty}"
            );
        }
        for (ty, size, max) in [
            ("UInt8", 1, 255.0),
            ("UInt16", 2, 65535.0),
            ("UInt32", 4, 4294967295.0),
            ("UInt64", 8, 18446744073709551615.0),
        ] {
            assert_eq!(
                numbers(&le(&[-1, 7], size), ty, false, 10).unwrap(),
                [max, 7.0],
                "{ty}"
            );
        }
        let f: Vec<u8> = [0.1f32, -2.5]
            .iter()
            .flat_map(|x| x.to_be_bytes())
            .collect();
        assert_eq!(
            numbers(&f, "Float32", true, 10).unwrap(),
            [0.1f32 as f64, -2.5]
        );
        let d: Vec<u8> = [0.1f64, 1e300]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        assert_eq!(numbers(&d, "Float64", false, 10).unwrap(), [0.1, 1e300]);
        assert!(numbers(&d[..15], "Float64", false, 10).is_err());
        assert!(numbers(&d, "Float64", false, 1).is_err());
        assert!(numbers(&d, "String", false, 10).is_err());
    }

    #[test]
    fn string_arrays() {
        assert_eq!(
            strings(b"endo 1\0epi \xc2\xb5\0\0"),
            ["endo 1", "epi µ", ""]
        );
        assert_eq!(strings(b"a\0b"), ["a", "b"]);
        assert!(strings(b"").is_empty());
    }
}
