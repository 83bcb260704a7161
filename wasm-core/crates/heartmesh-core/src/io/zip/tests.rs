use super::*;
use miniz_oxide::deflate::compress_to_vec;

/// (name, contents, deflated?) packed into an archive; `descriptor`: sizes left out of the local
/// headers (flag bit 3), as streaming packers write them.
fn archive(files: &[(&str, &[u8], bool)], descriptor: bool) -> Vec<u8> {
    let mut out = Vec::new();
    let mut dir = Vec::new();
    for (name, data, deflate) in files {
        let packed = if *deflate {
            compress_to_vec(data, 6)
        } else {
            data.to_vec()
        };
        let method: u16 = if *deflate { 8 } else { 0 };
        let flags: u16 = if descriptor { 8 } else { 0 };
        let at = out.len() as u32;
        let (local_packed, local_size) = if descriptor {
            (0, 0)
        } else {
            (packed.len() as u32, data.len() as u32)
        };
        out.extend_from_slice(&LOCAL.to_le_bytes());
        out.extend_from_slice(&20u16.to_le_bytes());
        out.extend_from_slice(&flags.to_le_bytes());
        out.extend_from_slice(&method.to_le_bytes());
        out.extend_from_slice(&[0; 8]); // time, date, crc
        out.extend_from_slice(&local_packed.to_le_bytes());
        out.extend_from_slice(&local_size.to_le_bytes());
        out.extend_from_slice(&(name.len() as u16).to_le_bytes());
        out.extend_from_slice(&0u16.to_le_bytes());
        out.extend_from_slice(name.as_bytes());
        out.extend_from_slice(&packed);
        dir.extend_from_slice(&CENTRAL.to_le_bytes());
        dir.extend_from_slice(&[20, 0, 20, 0]);
        dir.extend_from_slice(&flags.to_le_bytes());
        dir.extend_from_slice(&method.to_le_bytes());
        dir.extend_from_slice(&[0; 8]);
        dir.extend_from_slice(&(packed.len() as u32).to_le_bytes());
        dir.extend_from_slice(&(data.len() as u32).to_le_bytes());
        dir.extend_from_slice(&(name.len() as u16).to_le_bytes());
        dir.extend_from_slice(&[0; 12]); // extra, comment, disk, attributes
        dir.extend_from_slice(&at.to_le_bytes());
        dir.extend_from_slice(name.as_bytes());
    }
    let dir_at = out.len() as u32;
    out.extend_from_slice(&dir);
    out.extend_from_slice(&END.to_le_bytes());
    out.extend_from_slice(&[0; 4]);
    out.extend_from_slice(&(files.len() as u16).to_le_bytes());
    out.extend_from_slice(&(files.len() as u16).to_le_bytes());
    out.extend_from_slice(&(dir.len() as u32).to_le_bytes());
    out.extend_from_slice(&dir_at.to_le_bytes());
    out.extend_from_slice(&0u16.to_le_bytes());
    out
}

#[test]
fn stored_and_deflated_members_come_out_as_packed() {
    let big: Vec<u8> = (0..50_000u32)
        .flat_map(|i| (i % 251).to_le_bytes())
        .collect();
    for descriptor in [false, true] {
        let zip = archive(
            &[
                ("study/Contours.cvi42wsx", b"<xml/>", false),
                ("study/dicom/", b"", false),
                ("study/dicom/IM_1.dcm", &big, true),
                ("__MACOSX/study/._IM_1.dcm", b"fork", false),
                ("study/.DS_Store", b"junk", false),
            ],
            descriptor,
        );
        assert!(is_zip(&zip));
        let m = members(&zip).unwrap();
        let names: Vec<&str> = m.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["study/Contours.cvi42wsx", "study/dicom/IM_1.dcm"]);
        assert_eq!(m[0].bytes, b"<xml/>");
        assert_eq!(m[1].bytes, big);
    }
}

#[test]
fn bombs_encryption_other_methods_and_damage_are_refused() {
    let zeros = vec![0u8; 2_000_000];
    let bomb = archive(&[("a.bin", &zeros, true)], false);
    assert!(bomb.len() < 10_000);
    let e = members_within(&bomb, 1_000_000).unwrap_err().to_string();
    assert!(
        e.contains("a.bin: unpacks to more than the 1000000 bytes"),
        "{e}"
    );
    assert_eq!(
        members_within(&bomb, 2_000_000).unwrap()[0].bytes.len(),
        2_000_000
    );

    let mut locked = archive(&[("a.txt", b"secret", false)], false);
    let dir = locked.len() - 22 - 46 - 5;
    locked[dir + 8] = 1;
    let e = members(&locked).unwrap_err().to_string();
    assert!(e.contains("a.txt is encrypted"), "{e}");

    let mut other = archive(&[("a.txt", b"text", false)], false);
    let dir = other.len() - 22 - 46 - 5;
    other[dir + 10] = 12;
    let e = members(&other).unwrap_err().to_string();
    assert!(e.contains("method 12"), "{e}");

    let good = archive(&[("a.txt", b"some text here", true)], false);
    let e = members(&good[..good.len() - 30]).unwrap_err().to_string();
    assert!(e.contains("no end of central directory"), "{e}");
    // Every byte changed in turn, and every cut: errors or members, never a panic.
    for at in 0..good.len() {
        for v in [0u8, 0x7F, 0xFF] {
            let mut bad = good.clone();
            bad[at] = v;
            let _ = members(&bad);
        }
        let _ = members(&good[..at]);
    }
}
