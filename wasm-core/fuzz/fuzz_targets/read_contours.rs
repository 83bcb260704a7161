#![no_main]
//! Fuzz target: read_contours (must never panic, whatever the bytes).

use heartmesh_core::io;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    for name in ["in.csv", "in.txt", "in.mat", "in.vtk", "in.vtp", "in.json"] {
        let _ = io::read_contours(name, data);
    }
});
