#![no_main]
//! Fuzz target: mat (must never panic, whatever the bytes): SurFCo matrices and Segment studies
//! (read at their end-diastole and at a frame asked for), and the variable-name look-up the
//! format detection runs.

use heartmesh_core::io::{self, FrameChoice};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = io::mat::read_mat(data);
    let _ = io::mat::has_variable(data, "setstruct");
    let _ = io::mat::read_mat_frame(data, FrameChoice::new("2").as_ref());
});
