//! Header-only DICOM MR images for the tests of the readers that place pixel contours on them
//! (cvi42 workspaces, Sunnybrook contour files).

/// One explicit VR little endian element.
pub fn element(tag: (u16, u16), vr: &[u8; 2], value: &[u8]) -> Vec<u8> {
    let mut v = value.to_vec();
    if v.len() % 2 == 1 {
        v.push(if vr == b"UI" { 0 } else { b' ' });
    }
    let mut out = Vec::new();
    out.extend_from_slice(&tag.0.to_le_bytes());
    out.extend_from_slice(&tag.1.to_le_bytes());
    out.extend_from_slice(vr);
    if matches!(vr, b"OB" | b"OW") {
        out.extend_from_slice(&[0, 0]);
        out.extend_from_slice(&(v.len() as u32).to_le_bytes());
    } else {
        out.extend_from_slice(&(v.len() as u16).to_le_bytes());
    }
    out.extend_from_slice(&v);
    out
}

pub fn ds(values: &[f64]) -> Vec<u8> {
    values
        .iter()
        .map(|v| format!("{v}"))
        .collect::<Vec<_>>()
        .join("\\")
        .into_bytes()
}

pub struct Image {
    pub uid: &'static str,
    pub position: [f64; 3],
    pub orientation: [f64; 6],
    pub spacing: [f64; 2],
    pub series: i64,
    pub trigger: f64,
    /// Instance Number (0020,0013), written when given.
    pub instance: Option<i64>,
}

/// A header-only MR image (with a few pixels, as a real file has).
pub fn dicom(im: &Image) -> Vec<u8> {
    let mut out = vec![0u8; 128];
    out.extend_from_slice(b"DICM");
    out.extend(element((2, 0x10), b"UI", b"1.2.840.10008.1.2.1"));
    out.extend(element((8, 0x18), b"UI", im.uid.as_bytes()));
    out.extend(element((0x18, 0x1060), b"DS", &ds(&[im.trigger])));
    out.extend(element(
        (0x20, 0x11),
        b"IS",
        im.series.to_string().as_bytes(),
    ));
    if let Some(n) = im.instance {
        out.extend(element((0x20, 0x13), b"IS", n.to_string().as_bytes()));
    }
    out.extend(element((0x20, 0x32), b"DS", &ds(&im.position)));
    out.extend(element((0x20, 0x37), b"DS", &ds(&im.orientation)));
    out.extend(element((0x28, 0x30), b"DS", &ds(&im.spacing)));
    out.extend(element((0x7FE0, 0x10), b"OW", &[7u8; 4096]));
    out
}

/// An oblique plane: rows along (1,1,0)/sqrt2, columns along z, 0.8 mm rows and 1.25 mm columns.
pub const S2: f64 = std::f64::consts::FRAC_1_SQRT_2;
pub fn oblique(uid: &'static str, trigger: f64) -> Image {
    Image {
        uid,
        position: [10.0, -20.0, 30.0],
        orientation: [S2, S2, 0.0, 0.0, 0.0, 1.0],
        spacing: [0.8, 1.25],
        series: 5,
        trigger,
        instance: None,
    }
}
