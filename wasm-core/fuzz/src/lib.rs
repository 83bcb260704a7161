//! Invariants shared by the fuzz targets: what a reader accepts must be usable downstream.

use heartmesh_core::{error::Result, io::MeshData};

/// Whatever a mesh reader accepts must be consistent: indices in range, one value per vertex.
/// A violation panics, which is what makes libFuzzer report the input.
pub fn check_mesh(r: Result<MeshData>) {
    if let Ok(d) = r {
        let n = d.mesh.positions.len();
        assert!(d.mesh.triangles.iter().flatten().all(|&i| (i as usize) < n));
        if let Some((_, v)) = &d.point_data {
            assert_eq!(v.len(), n);
        }
    }
}
