#![no_main]
//! The PLY reader on any bytes: a mesh or an error, never a panic, and a
//! mesh's lists agree with each other.

use scene_format::{ply, Budget};

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    // A small budget keeps each input's memory small; the counting is the
    // same as with the scene's.
    let mut budget = Budget::of(1 << 16);
    if let Ok(mesh) = ply::read_ply_bytes(data, &mut budget) {
        let n = mesh.triangles.len();
        assert!(n > 0);
        assert_eq!(mesh.indices.len(), n);
        assert!(mesh.normals.is_empty() || mesh.normals.len() == n);
        assert!(mesh.uvs.is_empty() || mesh.uvs.len() == n);
        assert!(mesh.triangles.iter().flatten().flatten().all(|x| x.is_finite()));
    }
});
