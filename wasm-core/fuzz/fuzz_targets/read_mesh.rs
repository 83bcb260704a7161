#![no_main]
//! Fuzz target: read_mesh (must never panic, whatever the bytes).

use heartmesh_core::io;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    for name in ["m.obj", "m.stl", "m.ply", "m.vtk", "m.vtp"] {
        check_mesh(io::read_mesh(name, data));
    }
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
