#![no_main]
//! Fuzz target: mesh_from_buffers (flat position/index arrays from the browser) and the mesh
//! measures the app runs on such a mesh (validity, volume, area). The bytes are split at a point
//! the first byte chooses: f32 positions, then u32 indices; a second pass folds the indices into
//! range so that arbitrary topology reaches the mesh code behind the checks.

use heartmesh_core::io;
use heartmesh_core::mesh::topology;
use libfuzzer_sys::fuzz_target;

fn floats(b: &[u8]) -> Vec<f32> {
    b.chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

fn ints(b: &[u8]) -> Vec<u32> {
    b.chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

fuzz_target!(|data: &[u8]| {
    let Some((&k, rest)) = data.split_first() else {
        return;
    };
    let cut = (rest.len() * k as usize / 255).min(rest.len());
    let positions = floats(&rest[..cut]);
    let indices = ints(&rest[cut..]);
    let mut runs = vec![indices.clone()];
    let n = (positions.len() / 3) as u32;
    if n > 0 {
        runs.push(indices.iter().map(|i| i % n).collect());
    }
    for idx in runs {
        if let Ok(m) = io::mesh_from_buffers(&positions, &idx) {
            assert!(m.triangles.iter().flatten().all(|&i| i < n));
            let v = topology::validity(&m);
            let _ = v.is_closed_manifold();
            let _ = v.describe();
            let _ = m.volume_ml();
            let _ = m.area();
            let _ = m.bounds();
            let _ = topology::compact(&m);
        }
    }
});
