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

use super::build::{Aabb, BuildPrim};
use super::leaves::leaf_lanes;
use super::traverse::{
    safe_inverse, walk_any, walk_nearest, with_instance_stack, Best, HitAt, RayData, PAD,
};
use super::wide::{self, Node, INNER, INNER_HALF, WIDTH};
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
        let inv = Vec3::from(safe_inverse(ray.dir()));
        with_instance_stack(|stack| {
            walk_nearest(&self.nodes, &r, t_min, best, stack, |entry, best| {
                let run = entry.child as usize..(entry.child + entry.count) as usize;
                for k in run {
                    self.nearest_in(k, ray, inv, t_min, t_max, best);
                }
            })
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
        let inv = Vec3::from(safe_inverse(ray.dir()));
        with_instance_stack(|stack| {
            walk_any(&self.nodes, &r, (t_min, t_max), stack, |entry| {
                let run = &self.prims[entry.child as usize..][..entry.count as usize];
                run.iter().any(|p| p.occludes(ray, inv, t_min, t_max))
            })
        })
    }

    /// The hit of `ray` at distance `t` on triangle `lane` of block `block`
    /// of instance `k`'s mesh, at barycentric `uv`, in world terms.
    pub(super) fn hit(
        &self,
        k: u32,
        block: u32,
        lane: u32,
        ray: &Ray,
        t: f32,
        uv: Vec2,
    ) -> SurfaceHit {
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
        let (a, b) = (
            (self.lo - ray.origin()) * inv,
            (self.hi - ray.origin()) * inv,
        );
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
/// pointed at them. A run of several becomes a node of its own, each lane
/// one instance (two when there are more than eight): the build sizes
/// leaves for blocks of triangles (up to 16 primitives, 1.5 tests per four),
/// but an instance costs a search of its mesh, so its box is better tested
/// with the others' in SIMD lanes, and the nearest visited first.
fn pack(nodes: &mut Vec<Node>, items: &[BuildPrim], objects: &[Object]) -> Vec<InstancePrim> {
    let leaves = leaf_lanes(nodes);
    let mut prims = Vec::with_capacity(items.len());
    for (first, n, lane) in leaves {
        let (_, count) = nodes[n].child(lane);
        let start = prims.len();
        let run = &items[first as usize..][..count as usize];
        prims.extend(run.iter().filter_map(|item| prim(item.id(), objects)));
        let placed = &prims[start..];
        if placed.len() <= 1 {
            nodes[n].set(lane, start as u32, placed.len() as u32);
            continue;
        }
        let (child, child_count) = leaf_node(placed, start);
        let index = nodes.len() as u32;
        nodes[n].set(lane, index, child_count);
        nodes.push(child);
    }
    prims
}

/// The node whose lanes hold `placed` (at most 16 instances, the first
/// being `prims[start]`), one or two to a lane, with the `count` its
/// parent's lane marks it with.
fn leaf_node(placed: &[InstancePrim], start: usize) -> (Node, u32) {
    let per_lane = placed.len().div_ceil(WIDTH);
    let mut node = Node::EMPTY;
    let mut lanes = 0;
    for (lane, group) in placed.chunks(per_lane).enumerate() {
        let mut bounds = Aabb::EMPTY;
        for p in group {
            bounds.grow(&Aabb {
                min: p.lo.into(),
                max: p.hi.into(),
            });
        }
        node.set_bounds(lane, &bounds);
        node.set(lane, (start + lane * per_lane) as u32, group.len() as u32);
        lanes += 1;
    }
    let count = if lanes > 4 { INNER } else { INNER_HALF };
    (node, count)
}

/// Object `id` as the instance tree keeps it, if it is an instance.
fn prim(id: u32, objects: &[Object]) -> Option<InstancePrim> {
    let Shape::Instance(instance) = &objects[id as usize].shape else {
        return None;
    };
    let (lo, hi) = instance.bounds();
    Some(InstancePrim {
        lo,
        hi,
        id,
        instance: Arc::clone(instance),
    })
}

#[cfg(test)]
mod tests {
    use super::super::tests::Rng;
    use super::super::{brute_force, Bvh};
    use crate::geometry::{
        Instance, Object, Placement, Plane, Shape, SharedMesh, Sphere, Triangle, UvMap,
    };
    use crate::ray::Ray;
    use glam::{Vec2, Vec3};
    use std::sync::Arc;

    /// Small triangles in a mesh's own space, in material slots 0 to 2,
    /// every third smooth, every fifth with its uv mapped.
    fn mesh(rng: &mut Rng, n: usize) -> Arc<SharedMesh> {
        let objects = (0..n)
            .map(|i| {
                let c = rng.vec(1.0);
                let t = Triangle::new(c, c + rng.vec(0.3), c + rng.vec(0.3));
                let mut o = Object::new(Shape::Triangle(t), i % 3);
                if i % 3 == 0 {
                    let n = [0; 3].map(|_| (rng.vec(1.0) + Vec3::Z).normalize());
                    o.vertex_normals = Some(Box::new(n));
                }
                if i % 5 == 0 {
                    o = o.with_uv(UvMap {
                        origin: Vec2::ONE,
                        du: -Vec2::X,
                        dv: -Vec2::Y,
                    });
                }
                o
            })
            .collect();
        Arc::new(SharedMesh::new(objects))
    }

    /// Scales of either sign (a third of the placements mirror), turns
    /// about all three axes, moves within the scene.
    fn placement(rng: &mut Rng) -> Placement {
        let factor = |rng: &mut Rng| {
            let s = 0.3 + 1.5 * rng.next().abs();
            if rng.next() < -0.6 {
                -s
            } else {
                s
            }
        };
        let scale = Vec3::new(factor(rng), factor(rng), factor(rng));
        Placement::new(scale, rng.vec(180.0), rng.vec(4.0))
    }

    fn instance(mesh: &Arc<SharedMesh>, placement: Placement, materials: Vec<usize>) -> Object {
        let instance = Instance::new(Arc::clone(mesh), placement, materials).expect("invertible");
        Object::new(Shape::Instance(Arc::new(instance)), 0)
    }

    /// Instances of three meshes among triangles, spheres and a plane,
    /// each instance with materials of its own; one instance listed twice.
    /// Returns the objects and the indices of the instances.
    fn scene(rng: &mut Rng) -> (Vec<Object>, Vec<usize>) {
        let meshes = [mesh(rng, 300), mesh(rng, 50), mesh(rng, 1)];
        let mut objects = Vec::new();
        for i in 0..120 {
            objects.push(match i % 4 {
                0 => {
                    let s = Sphere::new(rng.vec(5.0), 0.1 + 0.3 * rng.next().abs());
                    Object::new(Shape::Sphere(s), 1)
                }
                1 => {
                    let c = rng.vec(5.0);
                    let t = Triangle::new(c, c + rng.vec(0.6), c + rng.vec(0.6));
                    Object::new(Shape::Triangle(t), 2)
                }
                _ => instance(&meshes[i % 3], placement(rng), vec![i % 7, 7 + i % 5, 12]),
            });
        }
        let plane = Plane::new(Vec3::new(0.0, -5.0, 0.0), Vec3::new(0.1, 1.0, 0.0));
        objects.insert(17, Object::new(Shape::Plane(Box::new(plane)), 1));
        let copy = objects[40].clone();
        objects.push(copy);
        let instances = objects
            .iter()
            .enumerate()
            .filter(|(_, o)| matches!(o.shape, Shape::Instance(_)))
            .map(|(i, _)| i)
            .collect();
        (objects, instances)
    }

    #[test]
    fn instances_find_exactly_the_brute_force_hits() {
        let mut rng = Rng(0x1234_5678_9ABC_DEF1);
        let (objects, instances) = scene(&mut rng);
        let bvh = Bvh::build(&objects);
        let (mut hits, mut backs, mut smooth) = (0, 0, 0);
        for k in 0..20_000 {
            let origin = rng.vec(if k % 2 == 0 { 9.0 } else { 4.0 });
            // Directions of many lengths: `t` is never renormalised.
            let ray = Ray::new(origin, rng.vec(1.0) * (0.2 + 3.0 * rng.next().abs()));
            let t_max = if k % 3 == 0 { 2.0 } else { f32::INFINITY };
            let expected = brute_force::closest_hit(&objects, &ray, 1e-4, t_max);
            assert_eq!(bvh.closest_hit(&ray, 1e-4, t_max), expected, "ray {k}");
            let any = brute_force::occluded(&objects, &ray, 1e-4, t_max);
            assert_eq!(bvh.occluded(&ray, 1e-4, t_max), any, "ray {k}");
            if let Some(h) = expected.filter(|h| instances.contains(&h.object)) {
                hits += 1;
                backs += !h.front_face as u32;
                smooth += (h.shading_normal != h.geometric_normal) as u32;
            }
        }
        assert!(hits > 3000, "only {hits} instance hits");
        assert!(
            backs > 500 && smooth > 500,
            "{backs} back faces, {smooth} smooth"
        );
    }

    #[test]
    fn each_instance_is_in_one_leaf_inside_its_lane_box() {
        let mut rng = Rng(5);
        let (objects, instances) = scene(&mut rng);
        let tree = super::InstanceTree::build(&objects);
        let mut ids = Vec::new();
        for node in &tree.nodes {
            for lane in 0..super::WIDTH {
                let (first, count) = node.child(lane);
                if !super::super::wide::is_leaf(count) {
                    continue;
                }
                let (min, max) = node.bounds(lane);
                for p in &tree.prims[first as usize..][..count as usize] {
                    let inside = (0..3).all(|a| min[a] <= p.lo[a] && p.hi[a] <= max[a]);
                    assert!(inside, "instance {} outside its lane's box", p.id);
                    ids.push(p.id as usize);
                }
            }
        }
        ids.sort_unstable();
        assert_eq!(ids, instances);
        // Runs of several instances became nodes of their own.
        assert!(tree.nodes.iter().all(|n| (0..super::WIDTH)
            .all(|k| n.child(k).1 <= 2 || !super::super::wide::is_leaf(n.child(k).1))));
    }

    #[test]
    fn a_triangle_and_its_instance_at_the_same_distance_tie_to_the_one_listed_first() {
        // Placed by the identity, the instance's triangle is the flat one
        // to the bit, and so are their distances.
        let t = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
        let mesh = Arc::new(SharedMesh::new(vec![Object::new(
            Shape::Triangle(t.clone()),
            0,
        )]));
        let flat = Object::new(Shape::Triangle(t), 1);
        let placed = instance(&mesh, Placement::IDENTITY, vec![2]);
        let ray = Ray::new(Vec3::new(0.2, 0.2, 5.0), -Vec3::Z);
        for (objects, material) in [
            (vec![placed.clone(), flat.clone()], 2),
            (vec![flat.clone(), placed.clone()], 1),
            (vec![placed.clone(), placed], 2),
        ] {
            let hit = Bvh::build(&objects).closest_hit(&ray, 1e-4, f32::INFINITY);
            assert_eq!(
                hit.map(|h| (h.t, h.object, h.material)),
                Some((5.0, 0, material))
            );
            assert_eq!(
                hit,
                brute_force::closest_hit(&objects, &ray, 1e-4, f32::INFINITY)
            );
        }
    }
}
