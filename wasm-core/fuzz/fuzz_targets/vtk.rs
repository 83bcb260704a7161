#![no_main]
//! Fuzz target: vtk (must never panic, whatever the bytes).

use heartmesh_core::io;
use heartmesh_fuzz::check_mesh;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = io::vtk::read_vtk_contours(data);
    check_mesh(io::vtk::read_vtk_mesh(data));
});
