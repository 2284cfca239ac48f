//! A bounding volume hierarchy over all the scene's shapes: built top-down
//! with the binned surface area heuristic (`build.rs`) into 8-wide nodes
//! (`wide.rs`) whose boxes a ray tests in SIMD lanes; traversed nearest
//! child first; shadow rays stop at the first hit.
//!
//! It finds exactly the hits of the brute-force loop over all objects: the
//! same intersection code on the same (precomputed) numbers, box tests padded
//! against rounding, and ties in distance won by the lower object index.

mod build;
mod wide;

use crate::ray::Ray;
use crate::scene::{Hit, Object};
use crate::shapes::{moller_trumbore, Shape, Sphere};
use build::{BuildPrim, MAX_DEPTH};
use glam::{Vec3, Vec4};
use rayon::prelude::*;
use std::cell::RefCell;
use wide::{node_halves, Node, GROUPS, INNER, WIDTH};

/// Widens box intervals by a few ulps against the rounding of the slab test
/// (pbrt's `1 + 2 gamma(3)`, with margin). Rays that Moller-Trumbore rounds
/// into a hit just outside an edge are met by the padding of triangle boxes
/// (`build.rs`); neither is a proof for every angle, so the tests compare
/// with brute force.
const PAD: f32 = 1.0 + 4.0 * f32::EPSILON;

/// Room on the traversal stack: each level pops one entry and pushes at
/// most `WIDTH`.
const STACK: usize = (WIDTH - 1) * MAX_DEPTH + 1;

thread_local! {
    /// Each thread's traversal stack, allocated once: zeroing a fresh one
    /// for every ray cost more than a ray that misses the scene.
    static STACKS: RefCell<Vec<Entry>> = const { RefCell::new(Vec::new()) };
}

/// Runs `f` with this thread's traversal stack.
#[inline(always)]
fn with_stack<R>(f: impl FnOnce(&mut [Entry]) -> R) -> R {
    STACKS.with_borrow_mut(|stack| {
        if stack.is_empty() {
            stack.resize(STACK, Entry::ROOT);
        }
        f(stack)
    })
}

/// A primitive with the numbers its test needs, its object index and its
/// material, in leaf order: one 52-byte record, so neither a leaf test nor
/// the shading of its hit touches another array.
#[derive(Debug, Clone, PartialEq)]
struct Prim {
    geometry: Geometry,
    id: u32,
    material: u32,
}

#[derive(Debug, Clone, PartialEq)]
enum Geometry {
    Triangle {
        v0: Vec3,
        e1: Vec3,
        e2: Vec3,
        edge_scale: f32,
    },
    Sphere(Sphere),
}

impl Geometry {
    fn new(shape: &Shape) -> Geometry {
        match shape {
            Shape::Triangle(t) => {
                let (e1, e2) = (t.v1 - t.v0, t.v2 - t.v0);
                Geometry::Triangle {
                    v0: t.v0,
                    e1,
                    e2,
                    edge_scale: f32::EPSILON * e1.length() * e2.length(),
                }
            }
            Shape::Sphere(s) => Geometry::Sphere(s.clone()),
        }
    }

    #[inline(always)]
    fn intersect(&self, ray: &RayData, t_min: f32, t_max: f32) -> Option<f32> {
        match self {
            Geometry::Triangle {
                v0,
                e1,
                e2,
                edge_scale,
            } => moller_trumbore(
                *v0,
                *e1,
                *e2,
                *edge_scale,
                &ray.ray,
                ray.dir_len,
                t_min,
                t_max,
            ),
            Geometry::Sphere(s) => s.intersect(&ray.ray, t_min, t_max),
        }
    }
}

impl Prim {
    /// The hit at distance `t`, as `Hit::on` gives it for the object.
    fn hit(&self, ray: &Ray, t: f32) -> Hit {
        let normal = match &self.geometry {
            // e1 and e2 are Triangle::normal's edges, computed the same way.
            Geometry::Triangle { e1, e2, .. } => e1.cross(*e2).normalize(),
            Geometry::Sphere(s) => s.normal(ray.at(t)),
        };
        Hit {
            t,
            object: self.id as usize,
            normal,
            material: self.material as usize,
        }
    }
}

/// What the traversal precomputes once per ray: origin and inverse
/// direction in every lane, and which plane of each axis the ray meets
/// first (min if it runs toward +, max if toward -).
struct RayData {
    ray: Ray,
    origin: [Vec4; 3],
    inv_dir: [Vec4; 3],
    near_plane: [usize; 3],
    dir_len: f32,
}

impl RayData {
    fn new(ray: &Ray) -> RayData {
        // A zero component would give 0 * inf = NaN in the slab test.
        let safe = |d: f32| {
            if d.abs() < 1e-30 {
                1e-30f32.copysign(d)
            } else {
                d
            }
        };
        let inv = ray.dir.to_array().map(|d| 1.0 / safe(d));
        RayData {
            ray: *ray,
            origin: ray.origin.to_array().map(Vec4::splat),
            inv_dir: inv.map(Vec4::splat),
            near_plane: [0, 1, 2].map(|axis| if inv[axis] < 0.0 { axis + 3 } else { axis }),
            dir_len: ray.dir.length(),
        }
    }

    /// Which boxes of the node's first `halves` halves the ray meets within
    /// (t_min, t_max], padded against rounding, as a bit mask; and the
    /// entry distances.
    #[inline(always)]
    fn enter(&self, node: &Node, halves: usize, t_min: f32, t_max: f32) -> (u32, [Vec4; GROUPS]) {
        let mut mask = 0;
        let mut entries = [Vec4::ZERO; GROUPS];
        for (g, entry) in entries.iter_mut().enumerate().take(halves) {
            let planes = &node.halves[g].planes;
            let mut near = Vec4::splat(t_min);
            let mut far = Vec4::splat(t_max);
            for axis in 0..3 {
                let (n, f) = (self.near_plane[axis], (self.near_plane[axis] + 3) % 6);
                near = near.max((planes[n] - self.origin[axis]) * self.inv_dir[axis]);
                far = far.min((planes[f] - self.origin[axis]) * self.inv_dir[axis]);
            }
            mask |= near.cmple(far * PAD).bitmask() << (4 * g);
            *entry = near;
        }
        (mask, entries)
    }
}

/// A node or leaf waiting on the traversal stack, as its parent's lane
/// refers to it, with the distance at which the ray enters its box.
#[derive(Clone, Copy)]
struct Entry {
    child: u32,
    count: u32,
    t: f32,
}

impl Entry {
    /// The root, read whole.
    const ROOT: Entry = Entry {
        child: 0,
        count: INNER,
        t: 0.0,
    };
}

#[derive(Debug, Clone, Default, PartialEq)]
pub struct Bvh {
    nodes: Vec<Node>,
    prims: Vec<Prim>,
}

impl Bvh {
    /// Builds the hierarchy over `objects`; uses the current rayon pool, and
    /// gives the same tree whatever its size.
    pub fn build(objects: &[Object]) -> Bvh {
        let mut items: Vec<BuildPrim> = objects
            .par_iter()
            .enumerate()
            .map(|(i, o)| BuildPrim::new(&o.shape, i as u32))
            .collect();
        if items.is_empty() {
            return Bvh::default();
        }
        let nodes = wide::build(&mut items);
        let prims = items
            .par_iter()
            .map(|p| {
                let object = &objects[p.id as usize];
                Prim {
                    geometry: Geometry::new(&object.shape),
                    id: p.id,
                    material: object.material as u32,
                }
            })
            .collect();
        Bvh { nodes, prims }
    }

    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The nearest hit in (t_min, t_max); of hits at the same distance, the
    /// one of the lowest object index (as the brute-force loop finds it).
    pub fn closest_hit(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        if self.nodes.is_empty() {
            return None;
        }
        let r = RayData::new(ray);
        let mut best_t = t_max;
        let mut best_id = u32::MAX;
        let mut best_prim = 0;
        with_stack(|stack| {
            stack[0] = Entry::ROOT;
            let mut sp = 1;
            while sp > 0 {
                sp -= 1;
                let entry = stack[sp];
                if entry.t > best_t * PAD {
                    continue;
                }
                let Some(halves) = node_halves(entry.count) else {
                    let start = entry.child as usize;
                    for k in start..start + entry.count as usize {
                        let prim = &self.prims[k];
                        // Once something is hit, up to and including best_t: an
                        // equal distance wins if its object comes first.
                        let limit = if best_id == u32::MAX {
                            t_max
                        } else {
                            next_up(best_t)
                        };
                        if let Some(t) = prim.geometry.intersect(&r, t_min, limit) {
                            if t < best_t || prim.id < best_id {
                                (best_t, best_id, best_prim) = (t, prim.id, k);
                            }
                        }
                    }
                    continue;
                };
                let node = &self.nodes[entry.child as usize];
                let (mask, near) = r.enter(node, halves, t_min, best_t);
                sp = push_nearest_last(stack, sp, node, mask, near);
            }
        });
        (best_id != u32::MAX).then(|| self.prims[best_prim].hit(ray, best_t))
    }

    /// Whether any primitive lies on the ray in (t_min, t_max).
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let r = RayData::new(ray);
        with_stack(|stack| {
            stack[0] = Entry::ROOT;
            let mut sp = 1;
            while sp > 0 {
                sp -= 1;
                let entry = stack[sp];
                let Some(halves) = node_halves(entry.count) else {
                    let start = entry.child as usize;
                    let prims = &self.prims[start..start + entry.count as usize];
                    if prims
                        .iter()
                        .any(|p| p.geometry.intersect(&r, t_min, t_max).is_some())
                    {
                        return true;
                    }
                    continue;
                };
                // Nearer children on top: an occluder near the ray's start is
                // found before the far side of the scene is searched.
                let node = &self.nodes[entry.child as usize];
                let (mask, near) = r.enter(node, halves, t_min, t_max);
                sp = push_nearest_last(stack, sp, node, mask, near);
            }
            false
        })
    }
}

/// Pushes the children of `node` that the ray enters (`mask`), farthest
/// first, so the nearest is popped next; returns the new stack size.
#[inline(always)]
fn push_nearest_last(
    stack: &mut [Entry],
    mut sp: usize,
    node: &Node,
    mut mask: u32,
    near: [Vec4; GROUPS],
) -> usize {
    let first = sp;
    while mask != 0 {
        let lane = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        let (child, count) = node.child(lane);
        let entry = Entry {
            child,
            count,
            t: near[lane / 4][lane % 4],
        };
        // Insertion into the pushed run, kept in decreasing distance.
        let mut k = sp;
        while k > first && stack[k - 1].t < entry.t {
            stack[k] = stack[k - 1];
            k -= 1;
        }
        stack[k] = entry;
        sp += 1;
    }
    sp
}

/// The next larger float, for a positive `t` (infinity stays).
fn next_up(t: f32) -> f32 {
    if t.is_finite() {
        f32::from_bits(t.to_bits() + 1)
    } else {
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::Triangle;

    /// xorshift: reproducible numbers in [-1, 1) without a dependency.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 40) as f32 / (1u64 << 23) as f32 - 1.0
        }
        fn vec(&mut self, scale: f32) -> Vec3 {
            Vec3::new(self.next(), self.next(), self.next()) * scale
        }
    }

    fn object(shape: Shape) -> Object {
        Object { shape, material: 0 }
    }

    /// Small triangles and spheres scattered in a cube, some coinciding.
    fn soup(rng: &mut Rng, n: usize) -> Vec<Object> {
        let mut objects = Vec::new();
        for i in 0..n {
            let c = rng.vec(5.0);
            let shape = if i % 10 == 0 {
                Shape::Sphere(Sphere::new(c, 0.05 + 0.3 * rng.next().abs()))
            } else {
                Shape::Triangle(Triangle::new(c, c + rng.vec(0.6), c + rng.vec(0.6)))
            };
            // Materials vary, so a hit's material is checked too.
            objects.push(Object {
                shape,
                material: i % 3,
            });
        }
        // Exact duplicates: the lower index must win the tie.
        let copies: Vec<Object> = objects.iter().step_by(7).cloned().collect();
        objects.extend(copies);
        objects
    }

    fn brute_closest(objects: &[Object], ray: &Ray, t_max: f32) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        for (i, o) in objects.iter().enumerate() {
            if let Some(t) = o.shape.intersect(ray, 1e-4, best.map_or(t_max, |h| h.t)) {
                best = Some(Hit::on(objects, i, ray, t));
            }
        }
        best
    }

    #[test]
    fn finds_exactly_the_brute_force_hits_of_random_rays() {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        let objects = soup(&mut rng, 3000);
        let bvh = Bvh::build(&objects);
        let mut hits = 0;
        for k in 0..20_000 {
            // Rays from outside and from among the objects, some axis-parallel.
            let origin = rng.vec(if k % 2 == 0 { 8.0 } else { 4.0 });
            let mut dir = rng.vec(1.0);
            if k % 5 == 0 {
                dir = Vec3::new(0.0, 0.0, dir.z.signum());
            }
            let ray = Ray::new(origin, dir);
            let t_max = if k % 3 == 0 { 2.0 } else { f32::INFINITY };
            let expected = brute_closest(&objects, &ray, t_max);
            assert_eq!(bvh.closest_hit(&ray, 1e-4, t_max), expected, "ray {k}");
            let any = objects
                .iter()
                .any(|o| o.shape.intersect(&ray, 1e-4, t_max).is_some());
            assert_eq!(bvh.occluded(&ray, 1e-4, t_max), any, "ray {k}");
            hits += expected.is_some() as u32;
        }
        assert!(hits > 2000, "only {hits} hits: the test would prove little");
    }

    #[test]
    fn a_tie_goes_to_the_object_listed_first() {
        let t = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
        let mut objects: Vec<Object> = (0..20)
            .map(|i| {
                let offset = Vec3::new(0.0, 0.0, -(i as f32));
                let far = Triangle::new(t.v0 + offset, t.v1 + offset, t.v2 + offset);
                object(Shape::Triangle(far))
            })
            .collect();
        objects.push(object(Shape::Triangle(t.clone())));
        objects.insert(3, object(Shape::Triangle(t)));
        let bvh = Bvh::build(&objects);
        let ray = Ray::new(Vec3::new(0.2, 0.2, 5.0), -Vec3::Z);
        let hit = bvh.closest_hit(&ray, 1e-4, f32::INFINITY).expect("a hit");
        // Object 0 (z = 0) and the copy at index 3 are at the same distance.
        assert_eq!((hit.t, hit.object), (5.0, 0));
    }

    #[test]
    fn leaves_hold_every_object_once_and_boxes_nest() {
        let mut rng = Rng(42);
        let objects = soup(&mut rng, 1000);
        let bvh = Bvh::build(&objects);
        let mut ids: Vec<u32> = bvh.prims.iter().map(|p| p.id).collect();
        ids.sort_unstable();
        assert_eq!(ids, (0..objects.len() as u32).collect::<Vec<_>>());
        check_node(&bvh, 0, ([f32::MIN; 3], [f32::MAX; 3]), GROUPS);
    }

    /// Every used lane's box lies inside the box its parent gave it, and
    /// within the halves the parent says the traversal reads.
    fn check_node(bvh: &Bvh, index: usize, parent: ([f32; 3], [f32; 3]), halves: usize) {
        let node = &bvh.nodes[index];
        for lane in 0..WIDTH {
            let (min, max) = node.bounds(lane);
            if min[0] > max[0] {
                continue; // an unused lane
            }
            assert!(
                lane < 4 * halves,
                "lane {lane} of node {index} is never read"
            );
            assert!(
                (0..3).all(|a| min[a] >= parent.0[a] && max[a] <= parent.1[a]),
                "lane {lane} of node {index} outside its parent's box"
            );
            let (child, count) = node.child(lane);
            if let Some(halves) = node_halves(count) {
                check_node(bvh, child as usize, (min, max), halves);
            }
        }
    }

    #[test]
    fn the_tree_does_not_depend_on_the_thread_count() {
        let mut rng = Rng(7);
        let objects = soup(&mut rng, 20_000);
        let pool = |n| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
        };
        let one = pool(1).install(|| Bvh::build(&objects));
        let three = pool(3).install(|| Bvh::build(&objects));
        assert!(one == three);
    }

    #[test]
    fn records_are_compact() {
        assert_eq!(std::mem::size_of::<Node>(), 32 * WIDTH);
        assert_eq!(std::mem::size_of::<Prim>(), 52);
    }

    #[test]
    fn a_single_object_is_found() {
        let objects = [Object {
            shape: Shape::Sphere(Sphere::new(Vec3::new(0.0, 0.0, -5.0), 1.0)),
            material: 2,
        }];
        let bvh = Bvh::build(&objects);
        let ray = Ray::new(Vec3::ZERO, -Vec3::Z);
        let expected = brute_closest(&objects, &ray, f32::INFINITY);
        assert_eq!(expected.map(|h| (h.t, h.material)), Some((4.0, 2)));
        assert_eq!(bvh.closest_hit(&ray, 1e-4, f32::INFINITY), expected);
        assert!(bvh.occluded(&ray, 1e-4, 10.0));
        assert!(!bvh.occluded(&ray, 1e-4, 3.0));
        let away = Ray::new(Vec3::ZERO, Vec3::Z);
        assert_eq!(bvh.closest_hit(&away, 1e-4, f32::INFINITY), None);
    }

    #[test]
    fn an_empty_scene_has_no_hits() {
        let bvh = Bvh::build(&[]);
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        assert_eq!(bvh.closest_hit(&ray, 0.0, f32::INFINITY), None);
        assert!(!bvh.occluded(&ray, 0.0, f32::INFINITY));
    }
}
