#![no_main]
//! Fuzz target: cvi42 workspaces (must never panic, whatever the bytes). The input is read as a
//! workspace with two of the fixture's images (frame 0, then a frame asked for), as one of the
//! images of the corpus's workspace, and through the study detection (`read_study`) beside both.

use heartmesh_core::io::{self, cvi42::read_cvi42, ContourOptions, FrameChoice};
use libfuzzer_sys::fuzz_target;

static WORKSPACE: &[u8] = include_bytes!("../corpus/cvi42/two-slices.cvi42wsx");
static IMAGE_3: &[u8] =
    include_bytes!("../../crates/heartmesh-core/tests/data/cvi42-patient1/dicom/IM_03_00.dcm");
static IMAGE_4: &[u8] =
    include_bytes!("../../crates/heartmesh-core/tests/data/cvi42-patient1/dicom/IM_04_00.dcm");

fuzz_target!(|data: &[u8]| {
    let images = [("IM_03_00.dcm", IMAGE_3), ("IM_04_00.dcm", IMAGE_4)];
    let _ = read_cvi42(data, &images, None);
    let _ = read_cvi42(data, &images, FrameChoice::new("1").as_ref());
    let _ = read_cvi42(WORKSPACE, &[images[0], ("x.dcm", data)], None);
    let files = [
        ("w.cvi42wsx", data),
        images[0],
        ("Contours.cvi42wsx", WORKSPACE),
    ];
    let _ = io::read_study(&files, &ContourOptions::default());
});
