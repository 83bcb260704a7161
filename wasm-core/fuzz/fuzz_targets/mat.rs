#![no_main]
//! Fuzz target: mat (must never panic, whatever the bytes).

use heartmesh_core::io;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = io::mat::read_mat(data);
});
