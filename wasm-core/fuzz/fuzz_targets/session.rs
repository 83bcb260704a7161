#![no_main]
//! Fuzz target: session (must never panic, whatever the bytes).

use heartmesh_core::io;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(s) = io::session::read_session(data) {
        let _ = s.params();
    }
});
