//! A bounding volume hierarchy over all the scene's shapes: built top-down
//! with the binned surface area heuristic (`build.rs`) into 8-wide nodes
//! (`wide.rs`) whose boxes a ray tests in SIMD lanes, free lanes going to
//! leaves a split within the node makes cheaper; leaves of triangles
//! in blocks of four tested at once (`tri4.rs`), or of spheres; traversed
//! nearest child first; shadow rays stop at the first hit. Planes are
//! infinite, so no box holds them: they are kept in a list tested beside
//! the tree, first (a floor's hit then prunes what lies beyond it).
//!
//! Instances (a mesh shared by several objects, each placing it with its
//! own transform) are the leaves of a tree of their own (`instances.rs`),
//! searched after the flattened tree; each instance's mesh has its own
//! `Bvh`, built once, searched in the mesh's space.
//!
//! It finds exactly the hits of the brute-force loop over all objects: the
//! same intersection arithmetic on the same (precomputed) numbers, box tests
//! padded against rounding, and ties in distance won by the lower object
//! index. (Not proved for every ray: of 3 M rays a fuzzer aimed at where
//! surfaces nearly meet, from 1e3 to 1e5 away or at sliver triangles,
//! about 65 were seen differently by the tree and by the loop.)

mod as_bytes;
pub mod brute_force;
mod build;
mod check;
mod flat;
mod instances;
mod leaves;
mod masked;
mod packet;
mod sphere4;
mod traverse;
mod tri4;
mod wide;

use crate::alpha_mask::AlphaMask;
use crate::geometry::{Object, Plane, Shape, Sphere, SurfaceHit, UvMap};
use crate::ray::Ray;
use build::{BuildPrim, PrimStore};
use glam::{Vec3, Vec4};
use instances::InstanceTree;
use leaves::{pack_leaves, SpherePrim};
use packet::ones;
pub use packet::PACKET;
use serde::{Deserialize, Serialize};
use sphere4::Sphere4;
use std::ops::Range;
use std::sync::Arc;
use traverse::{walk_any, walk_nearest, with_stack, Best, Entry, HitAt, RayData};
use tri4::{Ray4, Tri4};
use wide::{Node, SPHERE_LEAF};

/// The bounding volume hierarchy over a scene's objects. It copies what
/// the search needs of each object into its leaves, so it answers for the
/// object list it was built from: `Scene` keeps the two together.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Bvh {
    #[serde(with = "as_bytes")]
    nodes: Vec<Node>,
    #[serde(with = "as_bytes")]
    tris: Vec<Tri4>,
    spheres: Vec<SpherePrim>,
    /// The spheres four to a block, as their SIMD test reads them.
    #[serde(with = "as_bytes")]
    sphere4: Vec<Sphere4>,
    /// The unbounded objects, in list order.
    planes: Vec<PlanePrim>,
    /// The triangles whose barycentrics map to another uv (quads' and
    /// boxes' halves), by object index, sorted: looked up once per hit.
    uv_maps: Vec<(u32, UvMap)>,
    /// The smooth triangles' unit vertex normals, by object index, sorted:
    /// looked up once per closest hit, so the traversal never reads them.
    vertex_normals: Vec<(u32, [Vec3; 3])>,
    /// The vertex tangents of triangles with a normal texture, by object
    /// index, sorted; empty in most scenes.
    tangents: Vec<(u32, [glam::Vec4; 3])>,
    /// The objects' exact bounds (the nodes' boxes are padded).
    bounds: Option<(Vec3, Vec3)>,
    /// Where triangles are cut out, by the material index their blocks
    /// hold (`with_masks`); None in most scenes, whose search never looks.
    masks: Option<Box<[Option<Arc<AlphaMask>>]>>,
    /// Whether the spheres and triangles are few enough to be searched
    /// flat (`flat::few`).
    few: bool,
    /// The instances, in a tree of their own. Never serialized: a mesh
    /// shared by instances would be written once for each (the scene's
    /// serialization refuses a tree that has instances).
    #[serde(skip)]
    instances: InstanceTree,
}

/// A plane with its object index and material.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct PlanePrim {
    plane: Plane,
    id: u32,
    material: u32,
}

impl Bvh {
    /// Builds the hierarchy over `objects`; uses the current rayon pool, and
    /// gives the same tree whatever its size.
    pub fn build(objects: &[Object]) -> Bvh {
        let mut bvh = Bvh::default();
        let mut prims = PrimStore::with_capacity(objects.len());
        let mut has_instances = false;
        // One pass over the objects (a mesh's take megabytes), on this
        // thread: rayon would collect in vectors of the worker threads,
        // whose freed memory stays in their glibc arenas (see `wide::Fork`).
        for (i, o) in objects.iter().enumerate() {
            let id = i as u32;
            match &o.shape {
                Shape::Plane(plane) => bvh.planes.push(PlanePrim {
                    plane: Plane::clone(plane),
                    id,
                    material: o.material as u32,
                }),
                // In a tree of their own (`InstanceTree`).
                Shape::Instance(_) => has_instances = true,
                shape => prims.extend(BuildPrim::new(shape, id)),
            }
            if let Some(uv) = o.uv.as_deref() {
                bvh.uv_maps.push((id, *uv));
            }
            if let Some(normals) = o.vertex_normals.as_deref() {
                bvh.vertex_normals.push((id, *normals));
            }
            if let Some(tangents) = o.tangents.as_deref() {
                bvh.tangents.push((id, *tangents));
            }
            if let Some((lo, hi)) = o.shape.bounds() {
                bvh.bounds = Some(bvh.bounds.map_or((lo, hi), |(l, h)| (l.min(lo), h.max(hi))));
            }
        }
        if has_instances {
            bvh.instances = InstanceTree::build(objects);
        }
        let (mut storage, count) = prims.finish();
        let items = &mut bytemuck::cast_slice_mut::<Tri4, BuildPrim>(&mut storage)[..count];
        if items.is_empty() {
            return bvh;
        }
        let spheres = items.iter().filter(|p| p.sphere()).count();
        bvh.few = flat::few(spheres, count - spheres);
        let mut nodes = wide::build(items);
        // The leaves need only the order of the objects: 4 bytes each, where
        // the build's primitives (written over by the blocks) took 32.
        let order: Vec<u32> = items.iter().map(BuildPrim::id).collect();
        storage.clear();
        (bvh.tris, bvh.spheres) = pack_leaves(&mut nodes, &order, objects, storage);
        bvh.sphere4 = Sphere4::blocks(&bvh.spheres);
        // The primitives' pages past the blocks (a scene of spheres has few
        // blocks) would stay resident for the tree's life. (A mesh's blocks
        // cover them: a block's 192 bytes hold four triangles, whose
        // primitives took 128. Shrinking those would copy them: Tri4's
        // alignment makes the allocator move, not trim.)
        let prims_bytes = count * std::mem::size_of::<BuildPrim>();
        if bvh.tris.len() * std::mem::size_of::<Tri4>() < prims_bytes {
            bvh.tris.shrink_to_fit();
        }
        bvh.nodes = nodes;
        bvh
    }

    /// The smallest box holding every bounded object (planes are left out),
    /// or None for a scene without one.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        self.bounds
    }

    /// The uv of a hit on triangle `id` at barycentric `uv`.
    fn map_uv(&self, id: u32, uv: glam::Vec2) -> glam::Vec2 {
        match self.uv_maps.binary_search_by_key(&id, |&(i, _)| i) {
            Ok(k) => self.uv_maps[k].1.apply(uv),
            Err(_) => uv,
        }
    }

    /// The vertex normals of triangle `id`, if it is smooth.
    fn vertex_normals(&self, id: u32) -> Option<&[Vec3; 3]> {
        let k = self
            .vertex_normals
            .binary_search_by_key(&id, |&(i, _)| i)
            .ok()?;
        Some(&self.vertex_normals[k].1)
    }

    /// The tree whose spheres' hits carry uv only where `reads_uv` says
    /// their material reads them (`Material::reads_uv`).
    pub fn with_uv_read_by(mut self, reads_uv: impl Fn(usize) -> bool) -> Bvh {
        for s in &mut self.spheres {
            s.with_uv = reads_uv(s.material() as usize);
        }
        self
    }

    /// The sphere of object `id`, if it is one whose hits leave their uv
    /// out (a search of the list: for `explain`, not for renders).
    pub fn sphere_without_uv(&self, id: usize) -> Option<&Sphere> {
        let prim = self.spheres.iter().find(|s| s.id as usize == id)?;
        (!prim.with_uv).then_some(&prim.sphere)
    }

    /// Whether some objects are instances of a shared mesh.
    pub fn has_instances(&self) -> bool {
        !self.instances.is_empty()
    }

    /// How many 8-wide nodes the tree has.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The tree's cost by the surface area heuristic, in primitive tests
    /// per ray: each node's visit and each leaf's tests weighted by the
    /// chance that a ray through the root's box enters theirs. It compares
    /// builds without the noise of timing renders.
    pub fn sah_cost(&self) -> f64 {
        wide::sah_cost(&self.nodes)
    }

    /// The nearest hit in (t_min, t_max); of hits at the same distance, the
    /// one of the lowest object index (as the brute-force loop finds it).
    pub fn closest_hit(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<SurfaceHit> {
        let mut best = Best::none(t_max);
        self.offer_planes(ray, t_min, t_max, &mut best);
        if self.is_flat() {
            self.nearest_flat(ray, t_min, t_max, &mut best);
        } else if !self.nodes.is_empty() {
            self.nearest_in_tree(ray, t_min, t_max, &mut best);
        }
        if !self.instances.is_empty() {
            self.instances.nearest(ray, t_min, t_max, &mut best);
        }
        self.surface_hit(&best, ray)
    }

    /// Offers `best` the hits on the planes.
    #[inline(always)]
    fn offer_planes(&self, ray: &Ray, t_min: f32, t_max: f32, best: &mut Best) {
        for (k, p) in self.planes.iter().enumerate() {
            if let Some(t) = p.plane.intersect(ray, t_min, best.limit(t_max)) {
                best.offer(t, p.id, t_max, HitAt::Plane(k));
            }
        }
    }

    /// The hit record of `ray`'s best hit, if it found one.
    #[inline(always)]
    fn surface_hit(&self, best: &Best, ray: &Ray) -> Option<SurfaceHit> {
        best.found().then(|| match best.at {
            HitAt::Triangle { block, lane, uv } => self.triangle_hit(block, lane, ray, best.t, uv),
            HitAt::Sphere(k) => self.spheres[k].hit(ray, best.t),
            HitAt::Plane(k) => {
                let p = &self.planes[k];
                let (id, material) = (p.id as usize, p.material as usize);
                SurfaceHit::on_plane(&p.plane, ray, best.t, id, material)
            }
            HitAt::Instance { k, block, lane, uv } => {
                self.instances.hit(k, block, lane, ray, best.t, uv)
            }
        })
    }

    /// The hit on lane `lane` of triangle block `block` at distance `t`
    /// and barycentric `uv`.
    #[inline(always)]
    fn triangle_hit(
        &self,
        block: usize,
        lane: usize,
        ray: &Ray,
        t: f32,
        uv: glam::Vec2,
    ) -> SurfaceHit {
        let tris = &self.tris[block];
        let id = tris.id[lane];
        let hit = tris.hit(lane, ray, t, self.map_uv(id, uv));
        let hit = match self.vertex_normals(id) {
            Some(normals) => hit.with_vertex_normals(ray, tris.corners(lane), normals, uv),
            None => hit,
        };
        if self.tangents.is_empty() {
            return hit;
        }
        match self.tangents.binary_search_by_key(&id, |&(i, _)| i) {
            Ok(k) => hit.with_tangents(&self.tangents[k].1, uv),
            Err(_) => hit,
        }
    }

    /// The nearest hit of the tree (planes and instances left out: a
    /// shared mesh's tree has neither) in (t_min, t_max), not yet made a
    /// `SurfaceHit`.
    fn nearest(&self, ray: &Ray, t_min: f32, t_max: f32) -> Best {
        let mut best = Best::none(t_max);
        if !self.nodes.is_empty() {
            self.nearest_in_tree(ray, t_min, t_max, &mut best);
        }
        best
    }

    /// Offers `best` the nearest hits of the tree.
    fn nearest_in_tree(&self, ray: &Ray, t_min: f32, t_max: f32, best: &mut Best) {
        let r = RayData::new(ray);
        with_stack(|stack| {
            walk_nearest(&self.nodes, &r, t_min, best, stack, |entry, best| {
                self.nearest_in_leaf(&r.ray, &r.ray4, entry, (t_min, t_max), best)
            })
        });
    }

    /// Offers `best` every hit in the leaf `entry`.
    #[inline(always)]
    fn nearest_in_leaf(
        &self,
        ray: &Ray,
        ray4: &Ray4,
        entry: Entry,
        (t_min, t_max): (f32, f32),
        best: &mut Best,
    ) {
        match leaf_run(entry) {
            (true, run) => self.offer_spheres(run, ray, t_min, t_max, best),
            (false, run) => self.offer_blocks(run, ray4, t_min, t_max, best),
        }
    }

    /// Offers `best` the hits on spheres `run`.
    #[inline(always)]
    fn offer_spheres(&self, run: Range<usize>, ray: &Ray, t_min: f32, t_max: f32, best: &mut Best) {
        for block in sphere4::blocks_of(&run) {
            let (four, lanes) = (&self.sphere4[block], sphere4::lanes_in(block, &run));
            let (hits, t) = four.intersect(ray, t_min, best.limit(t_max));
            for lane in ones(hits & lanes) {
                let k = block * 4 + lane;
                best.offer(t[lane], self.spheres[k].id, t_max, HitAt::Sphere(k));
            }
            for k in ones(four.stretched() & lanes).map(|lane| block * 4 + lane) {
                let s = &self.spheres[k];
                if let Some(t) = s.sphere.intersect(ray, t_min, best.limit(t_max)) {
                    best.offer(t, s.id, t_max, HitAt::Sphere(k));
                }
            }
        }
    }

    /// Offers `best` the hits on triangle blocks `run`.
    #[inline(always)]
    fn offer_blocks(
        &self,
        run: Range<usize>,
        ray4: &Ray4,
        t_min: f32,
        t_max: f32,
        best: &mut Best,
    ) {
        for block in run {
            let found = self.tris[block].intersect(ray4, t_min, best.limit(t_max));
            self.offer_lanes(block, found, t_max, best);
        }
    }

    /// Offers `best` the hits `found` on triangle block `block` (a lane
    /// mask, distances, barycentrics), in lane order, as the scalar loop
    /// would meet them.
    #[inline(always)]
    fn offer_lanes(
        &self,
        block: usize,
        found: (u32, Vec4, [Vec4; 2]),
        t_max: f32,
        best: &mut Best,
    ) {
        let (mut mask, t, [u, v]) = found;
        if self.masks.is_some() {
            mask = self.uncut(block, mask, [u, v]);
        }
        while mask != 0 {
            let lane = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            let uv = glam::Vec2::new(u[lane], v[lane]);
            let at = HitAt::Triangle { block, lane, uv };
            best.offer(t[lane], self.tris[block].id[lane], t_max, at);
        }
    }

    /// Whether any primitive lies on the ray in (t_min, t_max).
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        self.occluded_beside_tree(ray, t_min, t_max) || self.occluded_in_tree(ray, t_min, t_max)
    }

    /// Whether a plane, an instance or (in a small scene searched flat) a
    /// sphere or triangle lies on the ray in (t_min, t_max).
    #[inline(always)]
    fn occluded_beside_tree(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        let on_plane = |p: &PlanePrim| p.plane.intersect(ray, t_min, t_max).is_some();
        if self.planes.iter().any(on_plane) {
            return true;
        }
        if !self.instances.is_empty() && self.instances.occluded(ray, t_min, t_max) {
            return true;
        }
        self.is_flat() && self.any_flat(ray, t_min, t_max)
    }

    /// Whether a primitive of the tree (unless searched flat) lies on the
    /// ray in (t_min, t_max).
    #[inline(always)]
    fn occluded_in_tree(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        if !self.has_tree() {
            return false;
        }
        let r = RayData::new(ray);
        with_stack(|stack| {
            walk_any(&self.nodes, &r, (t_min, t_max), stack, |entry| {
                self.any_in_leaf(&r.ray, &r.ray4, entry, (t_min, t_max))
            })
        })
    }
}

impl Bvh {
    /// Whether anything in the leaf `entry` lies on the ray in (t_min, t_max).
    #[inline(always)]
    fn any_in_leaf(
        &self,
        ray: &Ray,
        ray4: &Ray4,
        entry: Entry,
        (t_min, t_max): (f32, f32),
    ) -> bool {
        match leaf_run(entry) {
            (true, run) => self.any_sphere(run, ray, t_min, t_max),
            (false, run) => self.any_block(run, ray4, t_min, t_max),
        }
    }

    /// Whether one of spheres `run` lies on the ray in (t_min, t_max).
    #[inline(always)]
    fn any_sphere(&self, run: Range<usize>, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        sphere4::blocks_of(&run).any(|block| {
            let (four, lanes) = (&self.sphere4[block], sphere4::lanes_in(block, &run));
            let alone = |lane: usize| {
                let sphere = &self.spheres[block * 4 + lane].sphere;
                sphere.intersect(ray, t_min, t_max).is_some()
            };
            four.intersect(ray, t_min, t_max).0 & lanes != 0
                || ones(four.stretched() & lanes).any(alone)
        })
    }

    /// Whether one of triangle blocks `run` lies on the ray in (t_min, t_max).
    #[inline(always)]
    fn any_block(&self, run: Range<usize>, ray4: &Ray4, t_min: f32, t_max: f32) -> bool {
        if self.masks.is_some() {
            return run.into_iter().any(|block| {
                let (hits, _, uv) = self.tris[block].intersect(ray4, t_min, t_max);
                hits != 0 && self.uncut(block, hits, uv) != 0
            });
        }
        self.tris[run]
            .iter()
            .any(|tris| tris.intersect(ray4, t_min, t_max).0 != 0)
    }
}

/// Whether the leaf `entry` holds spheres, and the run of its spheres or
/// triangle blocks.
#[inline(always)]
fn leaf_run(entry: Entry) -> (bool, Range<usize>) {
    let start = entry.child as usize;
    let spheres = entry.count & SPHERE_LEAF != 0;
    let count = (entry.count & !SPHERE_LEAF) as usize;
    (spheres, start..start + count)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Sphere, Triangle};
    use wide::{node_halves, GROUPS, WIDTH};

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
        Object::new(shape, 0)
    }

    #[test]
    fn a_tree_of_spheres_keeps_no_room_for_triangle_blocks() {
        // The build's primitives are written where the triangle blocks go:
        // with no triangles, none of that room may stay held.
        let mut rng = Rng(7);
        let objects: Vec<Object> = (0..3000)
            .map(|_| object(Shape::Sphere(Sphere::new(rng.vec(5.0), 0.1))))
            .collect();
        let bvh = Bvh::build(&objects);
        assert_eq!(bvh.spheres.len(), 3000);
        assert_eq!((bvh.tris.len(), bvh.tris.capacity()), (0, 0));
    }

    /// Small triangles and spheres scattered in a cube, some coinciding.
    pub(super) fn soup(rng: &mut Rng, n: usize) -> Vec<Object> {
        let mut objects = Vec::new();
        for i in 0..n {
            let c = rng.vec(5.0);
            let shape = if i % 20 == 10 {
                // An ellipsoid, stretched and turned.
                let axes = Vec3::new(1.0, 0.2, 0.5) + rng.vec(1.0).abs();
                let turn = glam::Mat3::from_axis_angle(rng.vec(1.0).normalize(), rng.next() * 3.0);
                let linear = turn * glam::Mat3::from_diagonal(axes);
                Shape::Sphere(Sphere::ellipsoid(c, 0.05 + 0.2 * rng.next().abs(), linear))
            } else if i % 10 == 0 {
                Shape::Sphere(Sphere::new(c, 0.05 + 0.3 * rng.next().abs()))
            } else {
                Shape::Triangle(Triangle::new(c, c + rng.vec(0.6), c + rng.vec(0.6)))
            };
            // Materials vary, so a hit's material is checked too.
            objects.push(Object::new(shape, i % 3));
        }
        // Exact duplicates: the lower index must win the tie.
        let copies: Vec<Object> = objects.iter().step_by(7).cloned().collect();
        objects.extend(copies);
        objects
    }

    fn brute_closest(objects: &[Object], ray: &Ray, t_max: f32) -> Option<SurfaceHit> {
        brute_force::closest_hit(objects, ray, 1e-4, t_max)
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
    fn planes_beside_the_tree_find_exactly_the_brute_force_hits() {
        let mut rng = Rng(0x5EED);
        let mut objects = soup(&mut rng, 1500);
        // Planes cutting through the soup and bounding it, among the other
        // objects; and mapped uv (a quad's second half) on some triangles.
        let planes = [
            (0, Vec3::new(0.0, -4.0, 0.0), Vec3::Y),
            (200, Vec3::new(0.5, 0.0, 0.0), Vec3::new(1.0, 0.3, -0.2)),
            (901, Vec3::new(0.0, 0.0, 6.0), -Vec3::Z),
        ];
        for (at, point, normal) in planes {
            objects.insert(
                at,
                Object::new(Shape::Plane(Box::new(Plane::new(point, normal))), 1),
            );
        }
        for o in objects.iter_mut().step_by(5) {
            o.uv = Some(Box::new(UvMap {
                origin: glam::Vec2::ONE,
                du: -glam::Vec2::X,
                dv: -glam::Vec2::Y,
            }));
        }
        // Vertex normals on every third triangle (some with mapped uv too):
        // the shading normal and the shadow offset must be the same.
        for o in objects.iter_mut().step_by(3) {
            if matches!(o.shape, Shape::Triangle(_)) {
                let n = [0; 3].map(|_| (rng.vec(1.0) + Vec3::Z).normalize());
                o.vertex_normals = Some(Box::new(n));
            }
        }
        let bvh = Bvh::build(&objects);
        let (mut plane_hits, mut smooth_hits) = (0, 0);
        for k in 0..20_000 {
            let origin = rng.vec(if k % 2 == 0 { 8.0 } else { 4.0 });
            let ray = Ray::new(origin, rng.vec(1.0));
            let t_max = if k % 3 == 0 { 2.0 } else { f32::INFINITY };
            let expected = brute_closest(&objects, &ray, t_max);
            assert_eq!(bvh.closest_hit(&ray, 1e-4, t_max), expected, "ray {k}");
            let any = brute_force::occluded(&objects, &ray, 1e-4, t_max);
            assert_eq!(bvh.occluded(&ray, 1e-4, t_max), any, "ray {k}");
            plane_hits += expected.is_some_and(|h| [0, 200, 901].contains(&h.object)) as u32;
            smooth_hits += expected.is_some_and(|h| h.shading_normal != h.geometric_normal) as u32;
        }
        assert!(plane_hits > 2000, "only {plane_hits} plane hits");
        assert!(smooth_hits > 500, "only {smooth_hits} smooth hits");
    }

    #[test]
    fn the_walls_of_a_room_get_a_leaf_each() {
        // Five walls of the cube [-1, 1]^3, two triangles each: as one
        // leaf (the SAH's choice, a node's visit dearer than three blocks),
        // its box the room's, every ray inside tested all ten triangles.
        let corners = [-1.0f32, 1.0];
        let mut objects = Vec::new();
        for (axis, side) in [(0, 0), (0, 1), (1, 0), (1, 1), (2, 0)] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let point = |a: f32, b: f32| {
                let mut p = [0.0; 3];
                (p[axis], p[u], p[v]) = (corners[side], a, b);
                Vec3::from(p)
            };
            let (p00, p10) = (point(-1.0, -1.0), point(1.0, -1.0));
            let (p01, p11) = (point(-1.0, 1.0), point(1.0, 1.0));
            objects.push(object(Shape::Triangle(Triangle::new(p00, p10, p11))));
            objects.push(object(Shape::Triangle(Triangle::new(p00, p11, p01))));
        }
        let bvh = Bvh::build(&objects);
        assert_eq!(bvh.node_count(), 1);
        let root = &bvh.nodes[0];
        let leaves: Vec<_> = (0..WIDTH)
            .filter(|&lane| wide::is_leaf(root.child(lane).1))
            .collect();
        assert_eq!(leaves.len(), 5);
        for lane in leaves {
            let (lo, hi) = root.bounds(lane);
            let thinnest = (0..3).map(|a| hi[a] - lo[a]).fold(f32::INFINITY, f32::min);
            assert!(
                thinnest < 1e-3,
                "lane {lane}: {lo:?} to {hi:?}, not one wall"
            );
        }
        // And the hits are the brute-force loop's.
        let mut rng = Rng(7);
        for _ in 0..2000 {
            let ray = Ray::new(rng.vec(0.9), rng.vec(1.0));
            let found = bvh.closest_hit(&ray, 1e-4, f32::INFINITY);
            assert_eq!(found, brute_closest(&objects, &ray, f32::INFINITY));
        }
    }

    #[test]
    fn a_plane_and_a_triangle_at_the_same_distance_tie_to_the_one_listed_first() {
        let t = object(Shape::Triangle(Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y)));
        let plane = object(Shape::Plane(Box::new(Plane::new(Vec3::ZERO, Vec3::Z))));
        let ray = Ray::new(Vec3::new(0.2, 0.2, 5.0), -Vec3::Z);
        for (objects, winner) in [
            (vec![plane.clone(), t.clone()], 0),
            (vec![t.clone(), plane.clone()], 0),
            (vec![t.clone(), plane.clone(), t], 0),
            (vec![plane.clone(), plane], 0),
        ] {
            let hit = Bvh::build(&objects).closest_hit(&ray, 1e-4, f32::INFINITY);
            assert_eq!(hit.map(|h| (h.t, h.object)), Some((5.0, winner)));
            assert_eq!(hit, brute_closest(&objects, &ray, f32::INFINITY));
        }
        // Only planes: no tree at all, still hit and still in shadow.
        let only = [object(Shape::Plane(Box::new(Plane::new(
            Vec3::ZERO,
            Vec3::Z,
        ))))];
        let bvh = Bvh::build(&only);
        assert_eq!(bvh.node_count(), 0);
        assert!(bvh.occluded(&ray, 1e-4, 6.0));
        assert!(!bvh.occluded(&ray, 1e-4, 4.0));
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
        // One of these a mesh triangle, while the tree is built (72: the
        // boxed tangents of a normal texture took the last 8 bytes).
        assert_eq!(std::mem::size_of::<Object>(), 72);
        assert_eq!(std::mem::size_of::<Tri4>(), 192);
    }

    #[test]
    fn a_ray_along_an_axis_grazing_a_sphere_finds_what_brute_force_finds() {
        // Spheres each grazed on its top, along x and along z: the
        // quadratic's root is double. In a tree (20 spheres), the ray runs
        // in its box's top face, where 0 times the inverse of the
        // direction's 0 must not shut it out; searched flat (12), four
        // spheres at a time.
        for (n, flat) in [(20, false), (12, true)] {
            let objects: Vec<Object> = (0..n)
                .map(|k| {
                    let c = Vec3::new(3.0 * (k % 4) as f32, -1.0, 3.0 * (k / 4) as f32);
                    Object::new(Shape::Sphere(Sphere::new(c, 1.0)), 0)
                })
                .collect();
            let bvh = Bvh::build(&objects);
            assert_eq!(bvh.is_flat(), flat);
            for k in 0..n {
                let (x, z) = (3.0 * (k % 4) as f32, 3.0 * (k / 4) as f32);
                for ray in [
                    Ray::new(Vec3::new(-5.0, 0.0, z), Vec3::X),
                    Ray::new(Vec3::new(x, 0.0, -5.0), Vec3::Z),
                ] {
                    let expected = brute_force::closest_hit(&objects, &ray, 1e-4, f32::INFINITY);
                    assert!(expected.is_some(), "{ray:?}");
                    assert_eq!(
                        bvh.closest_hit(&ray, 1e-4, f32::INFINITY),
                        expected,
                        "{ray:?}"
                    );
                    assert!(bvh.occluded(&ray, 1e-4, f32::INFINITY), "{ray:?}");
                }
            }
        }
    }

    #[test]
    fn a_single_object_is_found() {
        let objects = [Object::new(
            Shape::Sphere(Sphere::new(Vec3::new(0.0, 0.0, -5.0), 1.0)),
            2,
        )];
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
    fn the_sah_cost_of_one_leaf_is_a_node_visit_and_one_block() {
        let sphere = |x: f32| {
            let shape = Shape::Sphere(Sphere::new(Vec3::new(x, 0.0, 0.0), 1.0));
            Object::new(shape, 0)
        };
        // The root node, then the leaf, whose box is the root's: 2 + 1.5.
        let near = |a: f64, b: f64| (a - b).abs() < 1e-4 * b;
        assert!(near(Bvh::build(&[sphere(0.0)]).sah_cost(), 3.5));
        // Two spheres 200 apart: a split into a node of its own would cost
        // 2 + (12 * 1.5 + 12 * 1.5) / 812 against one block's 1.5, but
        // split within the root, whose lanes are free, only the boxes'
        // share: a lane each.
        let apart = Bvh::build(&[sphere(-100.0), sphere(100.0)]).sah_cost();
        // (The boxes are widened by a few ulps: `build.rs`'s `widened`.)
        assert!(near(apart, 2.0 + (12.0 * 1.5 + 12.0 * 1.5) / 812.0));
        assert_eq!(Bvh::build(&[]).sah_cost(), 0.0);
    }

    #[test]
    fn an_empty_scene_has_no_hits() {
        let bvh = Bvh::build(&[]);
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        assert_eq!(bvh.closest_hit(&ray, 0.0, f32::INFINITY), None);
        assert!(!bvh.occluded(&ray, 0.0, f32::INFINITY));
    }
}
