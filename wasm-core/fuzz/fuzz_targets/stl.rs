#![no_main]
//! Fuzz target: stl (must never panic, whatever the bytes).

use heartmesh_core::io;
use heartmesh_fuzz::check_mesh;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    check_mesh(io::stl::read_stl(data));
});
