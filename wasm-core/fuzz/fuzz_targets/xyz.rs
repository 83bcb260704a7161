#![no_main]
//! Fuzz target: xyz (must never panic, whatever the bytes).

use heartmesh_core::io;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = io::xyz::read_xyz(data);
});
