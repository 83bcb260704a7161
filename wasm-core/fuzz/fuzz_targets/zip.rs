#![no_main]
//! Fuzz target: the ZIP archive reader (must never panic, whatever the bytes); what it accepts
//! stays within its unpacked-size cap.

use heartmesh_core::io::zip;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = zip::is_zip(data);
    if let Ok(members) = zip::members(data) {
        let total: usize = members.iter().map(|m| m.bytes.len()).sum();
        assert!(total <= 1 << 30, "{total} bytes unpacked");
    }
});
