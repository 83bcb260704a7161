#![no_main]
//! Fuzz target: vtp (must never panic, whatever the bytes).

use heartmesh_core::io;
use heartmesh_fuzz::check_mesh;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = io::vtp::read_vtp_contours(data);
    check_mesh(io::vtp::read_vtp_mesh(data));
});
