#![no_main]
//! Fuzz target: read_mesh (must never panic, whatever the bytes).

use heartmesh_core::io;
use heartmesh_fuzz::check_mesh;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    for name in ["m.obj", "m.stl", "m.ply", "m.vtk", "m.vtp"] {
        check_mesh(io::read_mesh(name, data));
    }
});
