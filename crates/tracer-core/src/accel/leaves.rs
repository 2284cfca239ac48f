//! The leaves' records: triangles packed into blocks of four, spheres in
//! runs, each with its object index and material, so shading reads the hit
//! from the record just tested.

use super::tri4::{Tri4, TriRecord};
use super::wide::{is_leaf, node_halves, Node, SPHERE_LEAF, WIDTH};
use crate::geometry::{Object, Shape, Sphere, SurfaceHit};
use crate::ray::Ray;
use serde::{Deserialize, Serialize};

/// A sphere, with its object index and material. Leaves hold spheres or
/// triangles, never both.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(super) struct SpherePrim {
    pub(super) sphere: Sphere,
    pub(super) id: u32,
    material: u32,
    /// Whether its hits carry uv (`Bvh::with_uv_read_by`).
    pub(super) with_uv: bool,
}

impl SpherePrim {
    pub(super) fn material(&self) -> u32 {
        self.material
    }

    /// The hit at distance `t`, as `Object::surface_hit` gives it.
    pub(super) fn hit(&self, ray: &Ray, t: f32) -> SurfaceHit {
        let (id, material) = (self.id as usize, self.material as usize);
        SurfaceHit::on_sphere(&self.sphere, ray, t, (id, material), self.with_uv)
    }
}

/// Turns the leaf lanes' runs of primitives (indices into `objects`, in the
/// build's order) into blocks of up to four triangles or runs of spheres,
/// stored in leaf order (the blocks appended to `tris`), and points the
/// lanes at them.
pub(super) fn pack_leaves(
    nodes: &mut [Node],
    order: &[u32],
    objects: &[Object],
    mut tris: Vec<Tri4>,
) -> (Vec<Tri4>, Vec<SpherePrim>) {
    let leaves = leaf_lanes(nodes);
    let mut spheres = Vec::new();
    for (first, n, lane) in leaves {
        let (_, count) = nodes[n].child(lane);
        let run = &order[first as usize..][..count as usize];
        // A leaf holds spheres or triangles (`build.rs` splits the two).
        let records = || run.iter().map(|&id| (&objects[id as usize], id));
        if matches!(objects[run[0] as usize].shape, Shape::Sphere(_)) {
            let start = spheres.len();
            spheres.extend(records().filter_map(|(o, id)| sphere_prim(o, id)));
            let count = (spheres.len() - start) as u32;
            nodes[n].set(lane, start as u32, SPHERE_LEAF | count);
        } else {
            let start = tris.len();
            let mut records = records().filter_map(|(o, id)| tri_record(o, id)).peekable();
            // Each block filled where it is stored, four records at a time.
            while records.peek().is_some() {
                tris.push(Tri4::EMPTY);
                let block = tris.last_mut().expect("just pushed");
                for (lane, t) in records.by_ref().take(4).enumerate() {
                    block.set(lane, &t);
                }
            }
            nodes[n].set(lane, start as u32, (tris.len() - start) as u32);
        }
    }
    (tris, spheres)
}

/// Every leaf lane as (its first primitive, node, lane), in the order of
/// their primitives: a node's lanes hold its primitives in lane order, so
/// a depth-first walk in lane order meets the leaves in that order.
pub(super) fn leaf_lanes(nodes: &[Node]) -> Vec<(u32, usize, usize)> {
    let mut leaves = Vec::new();
    if !nodes.is_empty() {
        walk(nodes, 0, &mut leaves);
    }
    leaves
}

/// Appends the leaf lanes under node `n`, lane by lane.
fn walk(nodes: &[Node], n: usize, leaves: &mut Vec<(u32, usize, usize)>) {
    for lane in 0..WIDTH {
        let (child, count) = nodes[n].child(lane);
        if is_leaf(count) {
            leaves.push((child, n, lane));
        } else if node_halves(count).is_some() {
            walk(nodes, child as usize, leaves);
        }
    }
}

fn tri_record(object: &Object, id: u32) -> Option<TriRecord> {
    let Shape::Triangle(t) = &object.shape else {
        return None;
    };
    let (e1, e2, edge_scale) = t.edges();
    Some(TriRecord {
        v0: t.v0,
        e1,
        e2,
        edge_scale,
        id,
        material: object.material as u32,
    })
}

fn sphere_prim(object: &Object, id: u32) -> Option<SpherePrim> {
    let Shape::Sphere(sphere) = &object.shape else {
        return None;
    };
    Some(SpherePrim {
        sphere: sphere.clone(),
        id,
        material: object.material as u32,
        with_uv: true,
    })
}
