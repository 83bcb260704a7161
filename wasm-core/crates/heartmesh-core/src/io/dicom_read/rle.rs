//! DICOM's RLE Lossless pixel encoding (PS3.5 Annex G), as dcmjs (and so OHIF) writes every
//! segmentation by default and highdicom on request: each frame one fragment, a 64-byte header
//! (the number of byte segments and where each begins) then the segments, each PackBits-coded
//! (a byte n of 0-127 followed by n + 1 literal bytes; -1 to -127 followed by one byte repeated
//! 1 - n times; -128 nothing). A sample of k bytes is split into k segments, the most
//! significant first.

/// The transfer syntax.
pub const RLE_LOSSLESS: &str = "1.2.840.10008.1.2.5";

/// Most byte segments a frame may hold (the header has room for 15).
const MAX_SEGMENTS: usize = 15;
const HEADER: usize = 64;

/// The frame coded in `fragment`, as native little-endian pixel data: `segments` byte segments
/// (the bytes per sample) of `length` bytes each, interleaved least significant byte first.
/// Errors say what does not fit.
pub fn decode_frame(fragment: &[u8], segments: usize, length: usize) -> Result<Vec<u8>, String> {
    let word = |at: usize| {
        fragment
            .get(at..at + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
    };
    let count = word(0).ok_or("an RLE frame shorter than its 64-byte header")?;
    if fragment.len() < HEADER {
        return Err("an RLE frame shorter than its 64-byte header".into());
    }
    if count != segments || count == 0 || count > MAX_SEGMENTS {
        return Err(format!(
            "an RLE frame of {count} byte segments, {segments} expected"
        ));
    }
    let offsets: Vec<usize> = (0..count).filter_map(|i| word(4 + 4 * i)).collect();
    let mut out = vec![0u8; length * count];
    for (s, &start) in offsets.iter().enumerate() {
        let end = offsets.get(s + 1).copied().unwrap_or(fragment.len());
        if start < HEADER || start > end || end > fragment.len() {
            return Err(format!(
                "RLE segment {} lies at bytes {start} to {end} of a {}-byte frame",
                s + 1,
                fragment.len()
            ));
        }
        let bytes = unpack(&fragment[start..end], length);
        if bytes.len() < length {
            return Err(format!(
                "RLE segment {} decodes to {} bytes, {length} needed",
                s + 1,
                bytes.len()
            ));
        }
        // Segment 0 holds the most significant bytes: in little-endian order, the last.
        let place = count - 1 - s;
        for (p, b) in bytes.into_iter().enumerate() {
            out[p * count + place] = b;
        }
    }
    Ok(out)
}

/// PackBits-decodes `src`, stopping at `want` bytes (a damaged run cannot make more).
fn unpack(src: &[u8], want: usize) -> Vec<u8> {
    let mut out = Vec::with_capacity(want);
    let mut i = 0;
    while i < src.len() && out.len() < want {
        let n = src[i] as i8;
        i += 1;
        match n {
            0.. => {
                let end = (i + n as usize + 1).min(src.len());
                out.extend_from_slice(&src[i..end]);
                i = end;
            }
            -128 => {}
            _ => {
                if let Some(&b) = src.get(i) {
                    out.resize(out.len() + (1 - isize::from(n)) as usize, b);
                    i += 1;
                }
            }
        }
    }
    out.truncate(want);
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// PackBits as the tests write it: runs of 3 or more repeated, the rest literal.
    pub fn pack(data: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        let mut i = 0;
        while i < data.len() {
            let run = data[i..]
                .iter()
                .take(128)
                .take_while(|&&b| b == data[i])
                .count();
            if run >= 3 {
                out.push((1 - run as isize) as i8 as u8);
                out.push(data[i]);
                i += run;
            } else {
                let start = i;
                while i < data.len() && i - start < 128 {
                    let ahead = data[i..]
                        .iter()
                        .take(3)
                        .take_while(|&&b| b == data[i])
                        .count();
                    if ahead >= 3 {
                        break;
                    }
                    i += 1;
                }
                out.push((i - start - 1) as u8);
                out.extend_from_slice(&data[start..i]);
            }
        }
        out
    }

    /// A frame of `segments` (each already PackBits-coded) behind its header.
    pub fn frame(segments: &[Vec<u8>]) -> Vec<u8> {
        let mut out = vec![0u8; HEADER];
        out[..4].copy_from_slice(&(segments.len() as u32).to_le_bytes());
        let mut at = HEADER;
        for (i, s) in segments.iter().enumerate() {
            out[4 + 4 * i..8 + 4 * i].copy_from_slice(&(at as u32).to_le_bytes());
            at += s.len();
        }
        for s in segments {
            out.extend_from_slice(s);
        }
        out
    }

    #[test]
    fn packbits_as_apple_s_technical_note_gives_it() {
        // Apple's TN1023 example: its coded and decoded bytes.
        let coded = [
            0xFE, 0xAA, 0x02, 0x80, 0x00, 0x2A, 0xFD, 0xAA, 0x03, 0x80, 0x00, 0x2A, 0x22, 0xF7,
            0xAA,
        ];
        let plain = [
            0xAA, 0xAA, 0xAA, 0x80, 0x00, 0x2A, 0xAA, 0xAA, 0xAA, 0xAA, 0x80, 0x00, 0x2A, 0x22,
            0xAA, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA,
        ];
        assert_eq!(unpack(&coded, 1000), plain);
        assert_eq!(unpack(&pack(&plain), 1000), plain);
        // A no-op byte (-128) is skipped; the output stops at what is wanted.
        assert_eq!(unpack(&[0x80, 0x01, 7, 8], 10), [7, 8]);
        assert_eq!(unpack(&[0x81, 5], 10), [5; 10]);
    }

    #[test]
    fn a_16_bit_frame_interleaves_its_segments_least_significant_first() {
        let values: Vec<u16> = (0..300u16).map(|i| (i / 7) * 300 + 3).collect();
        let msb: Vec<u8> = values.iter().map(|v| (v >> 8) as u8).collect();
        let lsb: Vec<u8> = values.iter().map(|v| *v as u8).collect();
        let f = frame(&[pack(&msb), pack(&lsb)]);
        let native: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        assert_eq!(decode_frame(&f, 2, 300).unwrap(), native);
        // Wrong counts, short segments and offsets outside the frame are said, not panicked on.
        assert!(decode_frame(&f, 1, 300)
            .unwrap_err()
            .contains("2 byte segments, 1 expected"));
        assert!(decode_frame(&f, 2, 400)
            .unwrap_err()
            .contains("decodes to 300 bytes, 400 needed"));
        assert!(decode_frame(&f[..40], 2, 300)
            .unwrap_err()
            .contains("64-byte header"));
        let mut bad = f.clone();
        bad[8..12].copy_from_slice(&9999u32.to_le_bytes());
        assert!(decode_frame(&bad, 2, 300)
            .unwrap_err()
            .contains("RLE segment 1 lies at"));
    }
}
