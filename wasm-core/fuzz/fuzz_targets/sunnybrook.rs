#![no_main]
//! Fuzz target: Sunnybrook contour files (must never panic, whatever the bytes). The input is
//! read as a contour file with two of the fixture's contour files and three of its images, as
//! one of the images beside them, and through the study detection (`read_study`) with a frame
//! asked for.

use heartmesh_core::io::{self, sunnybrook::read_sunnybrook, ContourOptions, FrameChoice};
use libfuzzer_sys::fuzz_target;

static ENDO_1: &[u8] = include_bytes!(
    "../../crates/heartmesh-core/tests/data/sunnybrook-patient1/contours-manual/IRCCI-expert/IM-0001-0001-icontour-manual.txt"
);
static ENDO_21: &[u8] = include_bytes!(
    "../../crates/heartmesh-core/tests/data/sunnybrook-patient1/contours-manual/IRCCI-expert/IM-0001-0021-icontour-manual.txt"
);
static IMAGE_1: &[u8] = include_bytes!(
    "../../crates/heartmesh-core/tests/data/sunnybrook-patient1/CINESAX_300/IM-0003-0001.dcm"
);
static IMAGE_10: &[u8] = include_bytes!(
    "../../crates/heartmesh-core/tests/data/sunnybrook-patient1/CINESAX_300/IM-0003-0010.dcm"
);
static IMAGE_21: &[u8] = include_bytes!(
    "../../crates/heartmesh-core/tests/data/sunnybrook-patient1/CINESAX_300/IM-0003-0021.dcm"
);

fuzz_target!(|data: &[u8]| {
    let others = [
        ("IM-0001-0021-icontour-manual.txt", ENDO_21),
        ("IM-0003-0001.dcm", IMAGE_1),
        ("IM-0003-0010.dcm", IMAGE_10),
        ("IM-0003-0021.dcm", IMAGE_21),
    ];
    let _ = read_sunnybrook("IM-0001-0010-icontour-manual.txt", data, &others, None);
    let mut with_image = others.to_vec();
    with_image[2] = ("IM-0003-0010.dcm", data);
    let _ = read_sunnybrook(
        "IM-0001-0001-icontour-manual.txt",
        ENDO_1,
        &with_image,
        None,
    );
    let mut files = vec![
        ("IM-0001-0010-ocontour-manual.txt", data),
        ("IM-0001-0001-icontour-manual.txt", ENDO_1),
    ];
    files.extend(others);
    let options = ContourOptions {
        frame: FrameChoice::new("9"),
        ..ContourOptions::default()
    };
    let _ = io::read_study(&files, &options);
});
