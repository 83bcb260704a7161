#![no_main]
//! Fuzz target: gpfile (must never panic, whatever the bytes).

use heartmesh_core::io;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let _ = io::gpfile::read_gpfile(&text, None);
    let _ = io::gpfile::read_gpfile(&text, Some(&1.into()));
    let _ = io::gpfile::read_slice_info(&text);
});
