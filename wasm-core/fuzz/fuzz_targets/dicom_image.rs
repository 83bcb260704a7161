#![no_main]
//! Fuzz target: DICOM images and segmentations (must never panic, whatever the bytes): the
//! geometry a cvi42 workspace's contours are placed by, through the header reader under it
//! (which stops at the pixel data and takes a file's first bytes), and the DICOM SEG reader
//! (multi-frame functional groups, bit-packed or RLE frames laid on a grid, planes of other
//! orientations read as views; seeds: the core's fixture, RLE label map and view SEGs) and its
//! header-only grid.

use heartmesh_core::io::{
    dicom_image::image_geometry,
    nifti::{label_map_grid, read_dicom_seg},
};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(g) = image_geometry(data) {
        // Whatever it accepts places pixels at finite millimetres.
        let p = g.to_patient(10.0, 20.0);
        assert!(p.iter().all(|v| v.is_finite()), "{p:?}");
    }
    let _ = read_dicom_seg(data, None);
    let _ = label_map_grid(data);
});
