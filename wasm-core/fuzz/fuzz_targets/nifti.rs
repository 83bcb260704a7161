#![no_main]
//! Fuzz target: NIfTI label maps, plain or gzip (must never panic, whatever the bytes).

use heartmesh_core::io;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = io::nifti::read_nifti(data, None);
});
