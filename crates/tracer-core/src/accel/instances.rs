//! The top level of the two-level BVH: a tree of its own over the scene's
//! instances (a shared mesh placed by one object), beside the tree of the
//! flattened primitives. Each leaf holds a run of instances; at each, the
//! ray moves into the mesh's space and searches the mesh's own tree, up to
//! the best distance so far. A tree apart rather than instances among the
//! triangles' leaves: the flattened scene's tree and its traversal stay
//! exactly as they are (a scene without instances pays one emptiness
//! test), and the build never has to keep three kinds of leaf apart.
//!
//! Ties keep the rule of the whole BVH: the lower object index wins, the
//! instance's within its mesh the lower triangle index (the mesh tree's own
//! rule), as the brute-force loop meets them.

use super::build::BuildPrim;
use super::traverse::{
    push_nearest_last, safe_inverse, with_instance_stack, Best, Entry, HitAt, RayData, PAD,
};
use super::wide::{self, is_leaf, node_halves, Node, WIDTH};
use crate::geometry::{Instance, Object, Shape, SurfaceHit};
use crate::ray::Ray;
use glam::{Vec2, Vec3};
use std::sync::Arc;

/// An instance with its object index and world box (tested before the
/// ray is moved into the mesh's space).
#[derive(Debug, Clone, PartialEq)]
struct InstancePrim {
    lo: Vec3,
    hi: Vec3,
    id: u32,
    instance: Arc<Instance>,
}

/// The instance tree: nodes as the flattened tree's, leaves runs of
/// `prims`.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct InstanceTree {
    nodes: Vec<Node>,
    prims: Vec<InstancePrim>,
}

impl InstanceTree {
    /// The tree over the instances among `objects`.
    pub(super) fn build(objects: &[Object]) -> InstanceTree {
        let mut items: Vec<BuildPrim> = objects
            .iter()
            .enumerate()
            .filter_map(|(i, o)| match &o.shape {
                Shape::Instance(instance) => {
                    let (lo, hi) = instance.bounds();
                    Some(BuildPrim::boxed(lo, hi, i as u32))
                }
                _ => None,
            })
            .collect();
        if items.is_empty() {
            return InstanceTree::default();
        }
        let mut nodes = wide::build(&mut items);
        let prims = pack(&mut nodes, &items, objects);
        InstanceTree { nodes, prims }
    }

    pub(super) fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Offers `best` the nearest hits on the instances.
    pub(super) fn nearest(&self, ray: &Ray, t_min: f32, t_max: f32, best: &mut Best) {
        let r = RayData::new(ray);
        let inv = Vec3::from(safe_inverse(ray.dir));
        with_instance_stack(|stack| {
            stack[0] = Entry::ROOT;
            let mut sp = 1;
            while sp > 0 {
                sp -= 1;
                let entry = stack[sp];
                if entry.t > best.t * PAD {
                    continue;
                }
                let Some(halves) = node_halves(entry.count) else {
                    let run = entry.child as usize..(entry.child + entry.count) as usize;
                    for k in run {
                        self.nearest_in(k, ray, inv, t_min, t_max, best);
                    }
                    continue;
                };
                let node = &self.nodes[entry.child as usize];
                let (mask, near) = r.enter(node, halves, t_min, best.t);
                sp = push_nearest_last(stack, sp, node, mask, near);
            }
        });
    }

    /// Offers `best` the nearest hit on instance `k`.
    #[inline(always)]
    fn nearest_in(&self, k: usize, ray: &Ray, inv: Vec3, t_min: f32, t_max: f32, best: &mut Best) {
        let p = &self.prims[k];
        let limit = best.limit(t_max);
        if !p.entered(ray, inv, t_min, limit) {
            return;
        }
        let local = p.instance.object_ray(ray);
        let inner = p.instance.mesh().bvh().nearest(&local, t_min, limit);
        if let HitAt::Triangle { block, lane, uv } = inner.at {
            if inner.found() {
                let at = HitAt::Instance {
                    k: k as u32,
                    block: block as u32,
                    lane: lane as u32,
                    uv,
                };
                best.offer(inner.t, p.id, t_max, at);
            }
        }
    }

    /// Whether an instance lies on the ray in (t_min, t_max).
    pub(super) fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        let r = RayData::new(ray);
        let inv = Vec3::from(safe_inverse(ray.dir));
        with_instance_stack(|stack| {
            stack[0] = Entry::ROOT;
            let mut sp = 1;
            while sp > 0 {
                sp -= 1;
                let entry = stack[sp];
                let Some(halves) = node_halves(entry.count) else {
                    let run = &self.prims[entry.child as usize..][..entry.count as usize];
                    if run.iter().any(|p| p.occludes(ray, inv, t_min, t_max)) {
                        return true;
                    }
                    continue;
                };
                let node = &self.nodes[entry.child as usize];
                let (mut mask, _) = r.enter(node, halves, t_min, t_max);
                while mask != 0 {
                    let lane = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    let (child, count) = node.child(lane);
                    stack[sp] = Entry {
                        child,
                        count,
                        t: 0.0,
                    };
                    sp += 1;
                }
            }
            false
        })
    }

    /// The hit of `ray` at distance `t` on triangle `lane` of block `block`
    /// of instance `k`'s mesh, at barycentric `uv`, in world terms.
    pub(super) fn hit(&self, k: u32, block: u32, lane: u32, ray: &Ray, t: f32, uv: Vec2) -> SurfaceHit {
        let p = &self.prims[k as usize];
        let local_ray = p.instance.object_ray(ray);
        let mesh = p.instance.mesh().bvh();
        let local = mesh.triangle_hit(block as usize, lane as usize, &local_ray, t, uv);
        p.instance.world_hit(ray, local, p.id as usize)
    }
}

impl InstancePrim {
    /// Whether the ray meets the world box within (t_min, t_max], padded
    /// as the nodes' boxes are.
    #[inline(always)]
    fn entered(&self, ray: &Ray, inv: Vec3, t_min: f32, t_max: f32) -> bool {
        let (a, b) = ((self.lo - ray.origin) * inv, (self.hi - ray.origin) * inv);
        let near = a.min(b).max_element().max(t_min);
        let far = a.max(b).min_element().min(t_max);
        near <= far * PAD
    }

    fn occludes(&self, ray: &Ray, inv: Vec3, t_min: f32, t_max: f32) -> bool {
        if !self.entered(ray, inv, t_min, t_max) {
            return false;
        }
        let local = self.instance.object_ray(ray);
        self.instance.mesh().bvh().occluded(&local, t_min, t_max)
    }
}

/// The instances of each leaf lane's run, stored in leaf order, the lanes
/// pointed at them (count: how many instances).
fn pack(nodes: &mut [Node], items: &[BuildPrim], objects: &[Object]) -> Vec<InstancePrim> {
    let mut leaves: Vec<(u32, usize, usize)> = Vec::new();
    for (n, node) in nodes.iter().enumerate() {
        for lane in 0..WIDTH {
            let (first, count) = node.child(lane);
            if is_leaf(count) {
                leaves.push((first, n, lane));
            }
        }
    }
    leaves.sort_unstable();
    let mut prims = Vec::with_capacity(items.len());
    for (first, n, lane) in leaves {
        let (_, count) = nodes[n].child(lane);
        let start = prims.len() as u32;
        for item in &items[first as usize..][..count as usize] {
            let Shape::Instance(instance) = &objects[item.id() as usize].shape else {
                continue;
            };
            let (lo, hi) = instance.bounds();
            prims.push(InstancePrim {
                lo,
                hi,
                id: item.id(),
                instance: Arc::clone(instance),
            });
        }
        nodes[n].set(lane, start, prims.len() as u32 - start);
    }
    prims
}
