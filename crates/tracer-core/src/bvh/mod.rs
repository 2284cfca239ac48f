//! A bounding volume hierarchy over all the scene's shapes: built top-down
//! with the binned surface area heuristic (`build.rs`) into 8-wide nodes
//! (`wide.rs`) whose boxes a ray tests in SIMD lanes; leaves of triangles
//! in blocks of four tested at once (`tri4.rs`), or of spheres; traversed
//! nearest child first; shadow rays stop at the first hit.
//!
//! It finds exactly the hits of the brute-force loop over all objects: the
//! same intersection arithmetic on the same (precomputed) numbers, box tests
//! padded against rounding, and ties in distance won by the lower object
//! index.

mod build;
mod tri4;
mod wide;

use crate::ray::Ray;
use crate::scene::{Hit, Object};
use crate::shapes::{Shape, Sphere};
use build::{BuildPrim, MAX_DEPTH};
use glam::Vec4;
use rayon::prelude::*;
use std::cell::RefCell;
use tri4::{Ray4, Tri4, TriRecord};
use wide::{is_leaf, node_halves, Node, GROUPS, INNER, WIDTH};

/// Widens box intervals by a few ulps against the rounding of the slab test
/// (pbrt's `1 + 2 gamma(3)`, with margin). Rays that Moller-Trumbore rounds
/// into a hit just outside an edge are met by the padding of triangle boxes
/// (`build.rs`); neither is a proof for every angle, so the tests compare
/// with brute force.
const PAD: f32 = 1.0 + 4.0 * f32::EPSILON;

/// Room on the traversal stack: each level pops one entry and pushes at
/// most `WIDTH`; a split of spheres from triangles may go one below
/// `MAX_DEPTH`.
const STACK: usize = (WIDTH - 1) * (MAX_DEPTH + 1) + 1;

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

/// A sphere, with its object index and material. Leaves hold spheres or
/// triangles, never both.
#[derive(Debug, Clone, PartialEq)]
struct SpherePrim {
    sphere: Sphere,
    id: u32,
    material: u32,
}

/// Marks a leaf lane's `count` as a run of spheres; without it, the count
/// is of triangle blocks.
const SPHERE_LEAF: u32 = 1 << 30;

/// The best hit so far of a nearest-hit search, and where it is.
struct Best {
    t: f32,
    id: u32,
    at: HitAt,
}

#[derive(Clone, Copy)]
enum HitAt {
    Triangle { block: usize, lane: usize },
    Sphere(usize),
}

impl Best {
    /// Whether `t` (within t_min and the limit the test was given) and
    /// `id` make a better hit, as the brute-force loop would take it: once
    /// something is hit, up to and including best_t, an equal distance
    /// winning if its object comes first.
    #[inline(always)]
    fn offer(&mut self, t: f32, id: u32, t_max: f32, at: HitAt) {
        if t < self.limit(t_max) && (t < self.t || id < self.id) {
            (self.t, self.id, self.at) = (t, id, at);
        }
    }

    #[inline(always)]
    fn limit(&self, t_max: f32) -> f32 {
        if self.id == u32::MAX {
            t_max
        } else {
            next_up(self.t)
        }
    }
}

/// What the traversal precomputes once per ray: origin and inverse
/// direction in every lane, and which plane of each axis the ray meets
/// first (min if it runs toward +, max if toward -).
struct RayData {
    ray: Ray,
    ray4: Ray4,
    origin: [Vec4; 3],
    inv_dir: [Vec4; 3],
    near_plane: [usize; 3],
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
        let dir_len = ray.dir.length();
        RayData {
            ray: *ray,
            ray4: Ray4::new(ray, dir_len),
            origin: ray.origin.to_array().map(Vec4::splat),
            inv_dir: inv.map(Vec4::splat),
            near_plane: [0, 1, 2].map(|axis| if inv[axis] < 0.0 { axis + 3 } else { axis }),
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
    tris: Vec<Tri4>,
    spheres: Vec<SpherePrim>,
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
        let mut nodes = wide::build(&mut items);
        let (tris, spheres) = pack_leaves(&mut nodes, &items, objects);
        Bvh {
            nodes,
            tris,
            spheres,
        }
    }

    /// How many 8-wide nodes the tree has.
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
        let mut best = Best {
            t: t_max,
            id: u32::MAX,
            at: HitAt::Sphere(0),
        };
        with_stack(|stack| {
            stack[0] = Entry::ROOT;
            let mut sp = 1;
            while sp > 0 {
                sp -= 1;
                let entry = stack[sp];
                if entry.t > best.t * PAD {
                    continue;
                }
                let Some(halves) = node_halves(entry.count) else {
                    self.nearest_in_leaf(&r, entry, t_min, t_max, &mut best);
                    continue;
                };
                let node = &self.nodes[entry.child as usize];
                let (mask, near) = r.enter(node, halves, t_min, best.t);
                sp = push_nearest_last(stack, sp, node, mask, near);
            }
        });
        (best.id != u32::MAX).then(|| match best.at {
            HitAt::Triangle { block, lane } => self.tris[block].hit(lane, best.t),
            HitAt::Sphere(k) => self.spheres[k].hit(ray, best.t),
        })
    }

    /// Offers `best` every hit in the leaf `entry`.
    #[inline(always)]
    fn nearest_in_leaf(&self, r: &RayData, entry: Entry, t_min: f32, t_max: f32, best: &mut Best) {
        let start = entry.child as usize;
        if entry.count & SPHERE_LEAF != 0 {
            let count = (entry.count & !SPHERE_LEAF) as usize;
            for k in start..start + count {
                let s = &self.spheres[k];
                if let Some(t) = s.sphere.intersect(&r.ray, t_min, best.limit(t_max)) {
                    best.offer(t, s.id, t_max, HitAt::Sphere(k));
                }
            }
            return;
        }
        for block in start..start + entry.count as usize {
            let tris = &self.tris[block];
            let (mut mask, t) = tris.intersect(&r.ray4, t_min, best.limit(t_max));
            // In lane order, as the scalar loop would meet them.
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                best.offer(
                    t[lane],
                    tris.id[lane],
                    t_max,
                    HitAt::Triangle { block, lane },
                );
            }
        }
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
                    if self.any_in_leaf(&r, entry, t_min, t_max) {
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

impl Bvh {
    /// Whether anything in the leaf `entry` lies on the ray in (t_min, t_max).
    #[inline(always)]
    fn any_in_leaf(&self, r: &RayData, entry: Entry, t_min: f32, t_max: f32) -> bool {
        let start = entry.child as usize;
        if entry.count & SPHERE_LEAF != 0 {
            let count = (entry.count & !SPHERE_LEAF) as usize;
            return self.spheres[start..start + count]
                .iter()
                .any(|s| s.sphere.intersect(&r.ray, t_min, t_max).is_some());
        }
        self.tris[start..start + entry.count as usize]
            .iter()
            .any(|tris| tris.intersect(&r.ray4, t_min, t_max).0 != 0)
    }
}

impl SpherePrim {
    /// The hit at distance `t`, as `Hit::on` gives it for the object.
    fn hit(&self, ray: &Ray, t: f32) -> Hit {
        Hit {
            t,
            object: self.id as usize,
            normal: self.sphere.normal(ray.at(t)),
            material: self.material as usize,
        }
    }
}

/// Turns the leaf lanes' runs of primitives into blocks of up to four
/// triangles or runs of spheres, stored in leaf order, and points the lanes
/// at them.
fn pack_leaves(
    nodes: &mut [Node],
    items: &[BuildPrim],
    objects: &[Object],
) -> (Vec<Tri4>, Vec<SpherePrim>) {
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
    let (mut tris, mut spheres) = (Vec::with_capacity(items.len() / 3), Vec::new());
    for (first, n, lane) in leaves {
        let (_, count) = nodes[n].child(lane);
        let run = &items[first as usize..][..count as usize];
        // A leaf holds spheres or triangles (`build.rs` splits the two).
        let records = || run.iter().map(|p| (&objects[p.id as usize], p.id));
        if run[0].sphere {
            let start = spheres.len();
            spheres.extend(records().filter_map(|(o, id)| sphere_prim(o, id)));
            let count = (spheres.len() - start) as u32;
            nodes[n].set(lane, start as u32, SPHERE_LEAF | count);
        } else {
            let triangles: Vec<TriRecord> =
                records().filter_map(|(o, id)| tri_record(o, id)).collect();
            nodes[n].set(lane, tris.len() as u32, triangles.len().div_ceil(4) as u32);
            tris.extend(triangles.chunks(4).map(Tri4::new));
        }
    }
    (tris, spheres)
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
    })
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
    use glam::Vec3;

    /// xorshift: reproducible numbers in [-1, 1) without a dependency.
    pub(super) struct Rng(pub(super) u64);
    impl Rng {
        pub(super) fn next(&mut self) -> f32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 40) as f32 / (1u64 << 23) as f32 - 1.0
        }
        pub(super) fn vec(&mut self, scale: f32) -> Vec3 {
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
        let triangles = bvh
            .tris
            .iter()
            .flat_map(|b| b.id)
            .filter(|&id| id != u32::MAX);
        let mut ids: Vec<u32> = triangles.chain(bvh.spheres.iter().map(|s| s.id)).collect();
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
        assert_eq!(std::mem::size_of::<Tri4>(), 192);
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
