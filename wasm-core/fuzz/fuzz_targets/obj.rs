#![no_main]
//! Fuzz target: obj (must never panic, whatever the bytes).

use heartmesh_core::io;
use heartmesh_fuzz::check_mesh;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    check_mesh(io::obj::read_obj(data));
});
