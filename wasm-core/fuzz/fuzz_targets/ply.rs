#![no_main]
//! Fuzz target: ply (must never panic, whatever the bytes).

use heartmesh_core::io;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    check_mesh(io::ply::read_ply(data));
});

/// Whatever a mesh reader accepts must be consistent: indices in range, one value per vertex.
fn check_mesh(r: heartmesh_core::error::Result<io::MeshData>) {
    if let Ok(d) = r {
        let n = d.mesh.positions.len();
        assert!(d.mesh.triangles.iter().flatten().all(|&i| (i as usize) < n));
        if let Some((_, v)) = &d.point_data {
            assert_eq!(v.len(), n);
        }
    }
}
