//! Faces a mesh file repeats: the same three corners as an earlier face,
//! in the same order. Every ray through such a face tests each copy (a
//! bounding volume cannot part faces that lie on one another), so a file
//! of one face written two million times rendered 1700 times slower than
//! as many distinct faces; the copies add nothing to the image (the first
//! wins every tie). They are left out, and counted, as faces of zero area
//! are. A face written from another corner is kept: its tests round
//! otherwise, so it may win some ties (files give such copies other
//! materials), and each face has only three such turns.

use crate::model::{MeshData, Vec3};
use std::collections::HashSet;

/// A face's corners as bits, in order.
fn key(t: &[Vec3; 3]) -> [u32; 9] {
    let mut out = [0; 9];
    for (j, v) in t.iter().enumerate() {
        out[3 * j..3 * j + 3].copy_from_slice(&v.map(f32::to_bits));
    }
    out
}

/// A 64-bit hash of a key (FNV-1a over its words, then mixed).
fn hash(key: &[u32; 9]) -> u64 {
    let h = key.iter().fold(0xCBF2_9CE4_8422_2325_u64, |h, &x| {
        (h ^ u64::from(x)).wrapping_mul(0x0000_0100_0000_01B3)
    });
    (h ^ (h >> 31)).wrapping_mul(0x94D0_49BB_1331_11EB)
}

/// Leaves out of `data` every face that repeats an earlier one, with its
/// normals, uvs and material; returns how many. Faces are first told
/// apart by hash (8 bytes a face for the sort); only those whose hash
/// another shares are compared whole.
pub fn drop_repeated(data: &mut MeshData) -> usize {
    let mut hashes: Vec<u64> = data.triangles.iter().map(|t| hash(&key(t))).collect();
    hashes.sort_unstable();
    let shared: HashSet<u64> = hashes
        .windows(2)
        .filter(|w| w[0] == w[1])
        .map(|w| w[0])
        .collect();
    drop(hashes);
    if shared.is_empty() {
        return 0;
    }
    let mut seen = HashSet::new();
    let keep: Vec<bool> = data
        .triangles
        .iter()
        .map(|t| {
            let key = key(t);
            !shared.contains(&hash(&key)) || seen.insert(key)
        })
        .collect();
    let dropped = keep.iter().filter(|k| !**k).count();
    retain(&mut data.triangles, &keep);
    retain(&mut data.indices, &keep);
    retain(&mut data.normals, &keep);
    retain(&mut data.uvs, &keep);
    retain(&mut data.triangle_materials, &keep);
    dropped
}

/// Keeps the items of a list parallel to the faces (or empty) whose face
/// is kept.
fn retain<T>(items: &mut Vec<T>, keep: &[bool]) {
    if items.len() == keep.len() {
        let mut kept = keep.iter();
        items.retain(|_| kept.next().copied().unwrap_or(true));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn face(a: Vec3, b: Vec3, c: Vec3) -> [Vec3; 3] {
        [a, b, c]
    }

    #[test]
    fn a_face_repeated_in_order_is_left_out_and_its_other_turns_kept() {
        let (a, b, c, d) = ([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]);
        let triangles = vec![
            face(a, b, c),
            face(a, b, c), // the first again
            face(b, c, a), // the first, from another corner
            face(b, d, c),
            face(a, b, c), // the first again
        ];
        let mut data = MeshData {
            indices: (0..5).map(|k| [k, k, k]).collect(),
            triangle_materials: (0..5).map(Some).collect(),
            triangles,
            ..MeshData::default()
        };
        assert_eq!(drop_repeated(&mut data), 2);
        assert_eq!(data.triangles.len(), 3);
        assert_eq!(data.triangle_materials, [Some(0), Some(2), Some(3)]);
        assert_eq!(data.indices[1], [2, 2, 2]);
        assert!(data.normals.is_empty());
        // Nothing repeated: nothing changes.
        assert_eq!(drop_repeated(&mut data), 0);
        assert_eq!(data.triangles.len(), 3);
    }
}
