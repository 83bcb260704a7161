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
    assert_eq!(
        set.get((0x7FE0, 0x0010)),
        Some(&Value::Fragments(vec![&[][..], &[0xAA; 6][..]]))
    );
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
