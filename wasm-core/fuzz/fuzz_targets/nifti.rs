#![no_main]
//! Fuzz target: label maps (must never panic, whatever the bytes): NIfTI, plain or gzip, read
//! alone, as a long-axis view of a valid stack (the corpus's first file), and the study reader's
//! header probe; the same bytes as a NRRD (3D Slicer's format, seeds in the corpus).

use heartmesh_core::io;
use libfuzzer_sys::fuzz_target;

static STACK: &[u8] = include_bytes!("../corpus/nifti/spasm-lv.nii.gz");

fuzz_target!(|data: &[u8]| {
    let _ = io::nifti::read_nifti(data, None);
    let _ = io::nifti::label_map_grid(data);
    let _ = io::nifti::read_nifti_study(STACK, &[("view.nii", data)], None);
    let _ = io::nifti::read_nrrd(data, None);
});
