//! A bounding volume hierarchy over all the scene's shapes: built with the
//! binned surface area heuristic, flattened depth-first into 32-byte nodes,
//! traversed nearest child first; shadow rays stop at the first hit.
//!
//! It finds exactly the hits of the brute-force loop over all objects: the
//! same intersection code on the same (precomputed) numbers, box tests padded
//! against rounding, and ties in distance won by the lower object index.

use crate::ray::Ray;
use crate::scene::{Hit, Object};
use crate::shapes::{moller_trumbore, Shape, Sphere};
use glam::{UVec3, Vec3, Vec3A, Vec4};

/// Bins per axis of the SAH sweep.
const BINS: usize = 16;
/// Largest leaf the SAH may choose; larger nodes are always split.
const MAX_LEAF: usize = 8;
/// Cost of visiting a node, relative to one primitive test.
const TRAVERSAL_COST: f32 = 1.0;
/// Deeper nodes become leaves, so the traversal stack cannot overflow.
const MAX_DEPTH: usize = 60;
/// Nodes with more primitives than this build their children in parallel.
const PARALLEL_BUILD: usize = 4096;
/// Widens box intervals by a few ulps against the rounding of the slab test
/// (pbrt's `1 + 2 gamma(3)`, with margin). Rays that Moller-Trumbore rounds
/// into a hit just outside an edge are met by `TRIANGLE_PAD`; neither is a
/// proof for every angle, so the tests compare with brute force.
const PAD: f32 = 1.0 + 4.0 * f32::EPSILON;
/// How much a triangle's box is widened, relative to its coordinates.
const TRIANGLE_PAD: f32 = 64.0 * f32::EPSILON;

/// A node, 32 bytes: a box, with two integers in the spare lanes so that
/// each corner loads as one SIMD register. A leaf (`count > 0`) holds
/// `prims[offset..offset + count]`; an inner node's children are the next
/// node and node `offset`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Node {
    /// min.w: `offset` as bits.
    min: Vec4,
    /// max.w: `count` as bits.
    max: Vec4,
}

impl Node {
    fn new(bounds: &Aabb, offset: u32, count: u32) -> Node {
        Node {
            min: bounds.min.extend(f32::from_bits(offset)),
            max: bounds.max.extend(f32::from_bits(count)),
        }
    }

    #[inline(always)]
    fn offset(&self) -> u32 {
        self.min.w.to_bits()
    }

    #[inline(always)]
    fn count(&self) -> u32 {
        self.max.w.to_bits()
    }

    fn set_offset(&mut self, offset: u32) {
        self.min.w = f32::from_bits(offset);
    }
}

/// A primitive with the numbers its test needs and its object index, in
/// leaf order: one 48-byte record, so a leaf test touches no other array.
#[derive(Debug, Clone, PartialEq)]
struct Prim {
    geometry: Geometry,
    id: u32,
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

/// What the traversal precomputes once per ray.
struct RayData {
    ray: Ray,
    origin: Vec3A,
    inv_dir: Vec3A,
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
        RayData {
            ray: *ray,
            origin: ray.origin.into(),
            inv_dir: Vec3A::ONE / Vec3A::new(safe(ray.dir.x), safe(ray.dir.y), safe(ray.dir.z)),
            dir_len: ray.dir.length(),
        }
    }

    /// The entry distance into the box if the ray meets it within
    /// (t_min, t_max], padded against rounding.
    #[inline(always)]
    fn enter(&self, node: &Node, t_min: f32, t_max: f32) -> Option<f32> {
        let t0 = (Vec3A::from_vec4(node.min) - self.origin) * self.inv_dir;
        let t1 = (Vec3A::from_vec4(node.max) - self.origin) * self.inv_dir;
        let near = t0.min(t1).max_element().max(t_min);
        let far = (t0.max(t1).min_element() * PAD).min(t_max * PAD);
        (near <= far).then_some(near)
    }
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
            .iter()
            .enumerate()
            .map(|(i, o)| BuildPrim::new(&o.shape, i as u32))
            .collect();
        if items.is_empty() {
            return Bvh::default();
        }
        let tree = build_node(&mut items, 0);
        let mut nodes = Vec::with_capacity(tree.size());
        flatten(&tree, 0, &mut nodes);
        let prims = items
            .iter()
            .map(|p| Prim {
                geometry: Geometry::new(&objects[p.id as usize].shape),
                id: p.id,
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
        let r = RayData::new(ray);
        let mut best_t = t_max;
        let mut best_id = u32::MAX;
        let mut stack = [(0u32, 0f32); MAX_DEPTH + 2];
        let mut sp = 0;
        let root = self.nodes.first()?;
        if let Some(t) = r.enter(root, t_min, t_max) {
            stack[0] = (0, t);
            sp = 1;
        }
        while sp > 0 {
            sp -= 1;
            let (index, entry) = stack[sp];
            if entry > best_t * PAD {
                continue;
            }
            let node = &self.nodes[index as usize];
            if node.count() > 0 {
                let start = node.offset() as usize;
                for k in start..start + node.count() as usize {
                    // Once something is hit, up to and including best_t: an
                    // equal distance wins if its object comes first.
                    let limit = if best_id == u32::MAX {
                        t_max
                    } else {
                        next_up(best_t)
                    };
                    let prim = &self.prims[k];
                    if let Some(t) = prim.geometry.intersect(&r, t_min, limit) {
                        let id = prim.id;
                        if t < best_t || id < best_id {
                            (best_t, best_id) = (t, id);
                        }
                    }
                }
                continue;
            }
            let (left, right) = (index + 1, node.offset());
            let hit_left = r.enter(&self.nodes[left as usize], t_min, best_t);
            let hit_right = r.enter(&self.nodes[right as usize], t_min, best_t);
            match (hit_left, hit_right) {
                (Some(tl), Some(tr)) => {
                    let (near, far) = if tl <= tr {
                        ((left, tl), (right, tr))
                    } else {
                        ((right, tr), (left, tl))
                    };
                    stack[sp] = far;
                    stack[sp + 1] = near;
                    sp += 2;
                }
                (Some(tl), None) => {
                    stack[sp] = (left, tl);
                    sp += 1;
                }
                (None, Some(tr)) => {
                    stack[sp] = (right, tr);
                    sp += 1;
                }
                (None, None) => {}
            }
        }
        (best_id != u32::MAX).then_some(Hit {
            t: best_t,
            object: best_id as usize,
        })
    }

    /// Whether any primitive lies on the ray in (t_min, t_max).
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        let r = RayData::new(ray);
        let mut stack = [0u32; MAX_DEPTH + 2];
        let mut sp = 0;
        let Some(root) = self.nodes.first() else {
            return false;
        };
        if r.enter(root, t_min, t_max).is_some() {
            sp = 1;
        }
        while sp > 0 {
            sp -= 1;
            let index = stack[sp];
            let node = &self.nodes[index as usize];
            if node.count() > 0 {
                let start = node.offset() as usize;
                let prims = &self.prims[start..start + node.count() as usize];
                if prims
                    .iter()
                    .any(|p| p.geometry.intersect(&r, t_min, t_max).is_some())
                {
                    return true;
                }
                continue;
            }
            // Nearer child on top: an occluder near the ray's start is
            // found before the far side of the scene is searched.
            let (left, right) = (index + 1, node.offset());
            let hit_left = r.enter(&self.nodes[left as usize], t_min, t_max);
            let hit_right = r.enter(&self.nodes[right as usize], t_min, t_max);
            match (hit_left, hit_right) {
                (Some(tl), Some(tr)) => {
                    let (near, far) = if tl <= tr {
                        (left, right)
                    } else {
                        (right, left)
                    };
                    stack[sp] = far;
                    stack[sp + 1] = near;
                    sp += 2;
                }
                (Some(_), None) => {
                    stack[sp] = left;
                    sp += 1;
                }
                (None, Some(_)) => {
                    stack[sp] = right;
                    sp += 1;
                }
                (None, None) => {}
            }
        }
        false
    }
}

/// The next larger float, for a positive `t` (infinity stays).
fn next_up(t: f32) -> f32 {
    if t.is_finite() {
        f32::from_bits(t.to_bits() + 1)
    } else {
        t
    }
}

#[derive(Debug, Clone, Copy)]
struct Aabb {
    min: Vec3A,
    max: Vec3A,
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        min: Vec3A::INFINITY,
        max: Vec3A::NEG_INFINITY,
    };

    fn grow(&mut self, other: &Aabb) {
        self.min = self.min.min(other.min);
        self.max = self.max.max(other.max);
    }

    fn grow_point(&mut self, p: Vec3A) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    fn half_area(&self) -> f32 {
        let d = (self.max - self.min).max(Vec3A::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }
}

/// A primitive's box and object index, partitioned in place during the build.
#[derive(Debug, Clone, Copy)]
struct BuildPrim {
    bounds: Aabb,
    id: u32,
}

impl BuildPrim {
    fn new(shape: &Shape, id: u32) -> BuildPrim {
        let bounds = match shape {
            Shape::Triangle(t) => {
                let (a, b, c) = (Vec3A::from(t.v0), Vec3A::from(t.v1), Vec3A::from(t.v2));
                let (min, max) = (a.min(b).min(c), a.max(b).max(c));
                // Moller-Trumbore may round a ray that passes just outside an
                // edge into a hit; the box is widened so such a ray still
                // enters it, in proportion to the coordinates' size.
                let size = min.abs().max(max.abs()).max_element() + (max - min).max_element();
                let pad = Vec3A::splat(size * TRIANGLE_PAD);
                Aabb {
                    min: min - pad,
                    max: max + pad,
                }
            }
            Shape::Sphere(s) => {
                let (c, r) = (Vec3A::from(s.center), Vec3A::splat(s.radius));
                Aabb {
                    min: c - r,
                    max: c + r,
                }
            }
        };
        BuildPrim { bounds, id }
    }

    /// Twice the box centre: only compared, never used as a point.
    fn centroid2(&self) -> Vec3A {
        self.bounds.min + self.bounds.max
    }
}

enum BuildNode {
    Leaf {
        bounds: Aabb,
        count: usize,
    },
    Inner {
        bounds: Aabb,
        count: usize,
        left: Box<BuildNode>,
        right: Box<BuildNode>,
    },
}

impl BuildNode {
    fn size(&self) -> usize {
        match self {
            BuildNode::Leaf { .. } => 1,
            BuildNode::Inner { left, right, .. } => 1 + left.size() + right.size(),
        }
    }
}

/// One SAH split candidate: axis, first bin of the right side, cost.
#[derive(Clone, Copy)]
struct Split {
    axis: usize,
    bin: usize,
    cost: f32,
}

fn build_node(items: &mut [BuildPrim], depth: usize) -> BuildNode {
    let mut bounds = Aabb::EMPTY;
    let mut centroids = Aabb::EMPTY;
    for p in items.iter() {
        bounds.grow(&p.bounds);
        centroids.grow_point(p.centroid2());
    }
    let count = items.len();
    if count == 1 || depth >= MAX_DEPTH {
        return BuildNode::Leaf { bounds, count };
    }
    let split = best_split(items, &bounds, &centroids);
    let mid = match split {
        Some(s) if count > MAX_LEAF || s.cost < count as f32 => {
            partition(items, &centroids, s.axis, s.bin)
        }
        // Every centroid in one place: halve by count if too many.
        None if count > MAX_LEAF => count / 2,
        _ => return BuildNode::Leaf { bounds, count },
    };
    let (lo, hi) = items.split_at_mut(mid);
    let (left, right) = if count > PARALLEL_BUILD {
        rayon::join(|| build_node(lo, depth + 1), || build_node(hi, depth + 1))
    } else {
        (build_node(lo, depth + 1), build_node(hi, depth + 1))
    };
    BuildNode::Inner {
        bounds,
        count,
        left: Box::new(left),
        right: Box::new(right),
    }
}

/// Bins per unit of each axis of the centroid box; 0 on a flat axis.
fn bin_scale(centroids: &Aabb) -> Vec3A {
    let extent = centroids.max - centroids.min;
    let scale = Vec3A::splat(BINS as f32) / extent;
    Vec3A::select(extent.cmpgt(Vec3A::ZERO), scale, Vec3A::ZERO)
}

/// The bin of a primitive on each axis.
#[inline(always)]
fn bins_of(p: &BuildPrim, centroids: &Aabb, scale: Vec3A) -> UVec3 {
    ((p.centroid2() - centroids.min) * scale)
        .as_uvec3()
        .min(UVec3::splat(BINS as u32 - 1))
}

/// The cheapest binned SAH split over the three axes, with its cost in
/// units of one primitive test; None if the centroids do not spread.
fn best_split(items: &[BuildPrim], bounds: &Aabb, centroids: &Aabb) -> Option<Split> {
    let scale = bin_scale(centroids);
    let mut boxes = [[Aabb::EMPTY; BINS]; 3];
    let mut counts = [[0u32; BINS]; 3];
    for p in items {
        let b = bins_of(p, centroids, scale);
        for axis in 0..3 {
            let bin = b[axis] as usize;
            boxes[axis][bin].grow(&p.bounds);
            counts[axis][bin] += 1;
        }
    }
    let parent_area = bounds.half_area();
    let mut best: Option<Split> = None;
    for axis in 0..3 {
        if scale[axis] == 0.0 {
            continue;
        }
        let (boxes, counts) = (&boxes[axis], &counts[axis]);
        // Right-side area * count for each first-right bin, swept from the end.
        let mut right_cost = [0f32; BINS];
        let (mut acc, mut n) = (Aabb::EMPTY, 0u32);
        for b in (1..BINS).rev() {
            acc.grow(&boxes[b]);
            n += counts[b];
            right_cost[b] = acc.half_area() * n as f32;
        }
        let (mut acc, mut n) = (Aabb::EMPTY, 0u32);
        for b in 1..BINS {
            acc.grow(&boxes[b - 1]);
            n += counts[b - 1];
            if n == 0 || n as usize == items.len() {
                continue;
            }
            let cost = TRAVERSAL_COST + (acc.half_area() * n as f32 + right_cost[b]) / parent_area;
            if best.is_none_or(|s| cost < s.cost) {
                best = Some(Split { axis, bin: b, cost });
            }
        }
    }
    best
}

/// Puts the primitives of bins below `bin` first; returns how many.
fn partition(items: &mut [BuildPrim], centroids: &Aabb, axis: usize, bin: usize) -> usize {
    let scale = bin_scale(centroids);
    let mut mid = 0;
    for i in 0..items.len() {
        if (bins_of(&items[i], centroids, scale)[axis] as usize) < bin {
            items.swap(i, mid);
            mid += 1;
        }
    }
    mid
}

/// Writes `node` depth-first; `first` is the index of its first primitive.
fn flatten(node: &BuildNode, first: usize, nodes: &mut Vec<Node>) {
    let index = nodes.len();
    let (bounds, count) = match node {
        BuildNode::Leaf { bounds, count } => (bounds, *count),
        BuildNode::Inner { bounds, .. } => (bounds, 0),
    };
    nodes.push(Node::new(bounds, first as u32, count as u32));
    if let BuildNode::Inner { left, right, .. } = node {
        flatten(left, first, nodes);
        let right_index = nodes.len() as u32;
        nodes[index].set_offset(right_index);
        flatten(right, first + prim_count(left), nodes);
    }
}

fn prim_count(node: &BuildNode) -> usize {
    match node {
        BuildNode::Leaf { count, .. } => *count,
        BuildNode::Inner { count, .. } => *count,
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
            objects.push(object(shape));
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
                best = Some(Hit { t, object: i });
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
        check_node(&bvh, 0);
    }

    fn check_node(bvh: &Bvh, index: usize) {
        let n = bvh.nodes[index];
        let inside = |m: &Node| (0..3).all(|a| m.min[a] >= n.min[a] && m.max[a] <= n.max[a]);
        if n.count() > 0 {
            return;
        }
        for child in [index + 1, n.offset() as usize] {
            assert!(inside(&bvh.nodes[child]), "node {child} outside {index}");
            check_node(bvh, child);
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
        assert_eq!(std::mem::size_of::<Node>(), 32);
        assert_eq!(std::mem::size_of::<Prim>(), 48);
    }

    #[test]
    fn an_empty_scene_has_no_hits() {
        let bvh = Bvh::build(&[]);
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        assert_eq!(bvh.closest_hit(&ray, 0.0, f32::INFINITY), None);
        assert!(!bvh.occluded(&ray, 0.0, f32::INFINITY));
    }
}
