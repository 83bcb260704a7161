#![no_main]
//! Fuzz target: rtstruct (DICOM RT structure sets; must never panic, whatever the bytes, and never
//! allocate beyond the input's size: io/dicom_read/ bounds every declared length).

use heartmesh_core::io;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(set) = io::rtstruct::read_rtstruct(data) {
        // Whatever is accepted can be written again and reads back with the same points.
        let again = io::rtstruct::write_rtstruct(&set, "fuzz").expect("re-encode");
        let back = io::rtstruct::read_rtstruct(&again).expect("re-read");
        assert_eq!(back.point_count(), set.point_count());
    }
});
