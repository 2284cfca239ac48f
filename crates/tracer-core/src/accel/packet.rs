//! Rays searched together. A pixel's samples share the camera's origin
//! and differ in direction by less than a pixel, and their shadow rays
//! start a pixel's width apart toward the same light, so they enter
//! nearly the same nodes. A packet walks the tree once, testing a node's
//! boxes against all its rays at once, and tests each leaf's primitives
//! against each ray (where a leaf is small beside the packet, against each
//! ray whose own slab test enters its box).
//!
//! Each ray finds what it finds alone. The packet's box test bounds every
//! ray's: float subtraction and multiplication are monotone in each
//! operand, so the slab distances worked out from the extreme origins and
//! inverse directions bound each ray's own, and the packet enters every box
//! that one of its rays would. A ray skips a leaf only where its own slab
//! test, with a limit no nearer than its best hit so far, misses the box:
//! as its own walk would skip it. Each ray is thus offered the primitives
//! of its own walk and perhaps more (each a hit or a miss of the same
//! arithmetic); the best-hit rule (nearest, then lowest object index) does
//! not depend on the order or the number of the offers, nor does "any hit".

use super::traverse::{
    slab_test, walk_any, walk_nearest, with_stack, Best, Enter, Entry, Reach, PAD,
};
use super::tri4::{Ray4, Tri4};
use super::wide::{Node, GROUPS, WIDTH};
use super::{leaf_run, Bvh};
use crate::geometry::OriginTerms;
use crate::geometry::SurfaceHit;
use crate::ray::Ray;
use glam::{Vec3A, Vec4};
use std::ops::Range;

/// Most rays in one packet: a pixel's 16 samples.
pub const PACKET: usize = 16;

/// A packet's rays as the box test needs them, per axis: the origin that
/// gives the least distance to the near planes and the one that gives the
/// greatest to the far planes (the same for rays of one origin), and the
/// least and greatest inverse direction (of one sign).
pub(super) struct PacketData {
    /// The rays' origin, when they share one (in every lane).
    common_origin: Option<[Vec4; 3]>,
    origin_near: [Vec4; 3],
    origin_far: [Vec4; 3],
    inv_lo: [Vec4; 3],
    inv_hi: [Vec4; 3],
    near_plane: [usize; 3],
    /// The largest difference of the rays' origins, and of their
    /// directions, on an axis: the packet's width at distance t is at most
    /// about `spread.0 + t * spread.1`.
    spread: (f32, f32),
}

impl PacketData {
    /// The packet of `rays`; None when the sign of their directions
    /// differs on some axis (the near plane would differ too), or a
    /// direction has a component below 1e-30 or above 1e30 in size (or not
    /// a number), or an origin is not finite.
    pub(super) fn new<'a>(rays: impl IntoIterator<Item = &'a Ray>) -> Option<PacketData> {
        let (mut d_lo, mut d_hi) = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);
        let (mut o_lo, mut o_hi) = (d_lo, d_hi);
        let (mut regular, mut empty) = (true, true);
        for ray in rays {
            let (d, o) = (Vec3A::from(ray.dir()), Vec3A::from(ray.origin()));
            // No component that `safe_inverse` replaces, nor one whose
            // inverse is subnormal.
            let size = d.abs();
            regular &= (size.cmpge(Vec3A::splat(1e-30)) & size.cmple(Vec3A::splat(1e30))).all()
                && o.is_finite();
            (d_lo, d_hi) = (d_lo.min(d), d_hi.max(d));
            (o_lo, o_hi) = (o_lo.min(o), o_hi.max(o));
            empty = false;
        }
        let (d_lo, d_hi) = (d_lo.to_array(), d_hi.to_array());
        let toward_minus = |axis: usize| d_lo[axis] < 0.0;
        if empty || !regular || (0..3).any(|axis| toward_minus(axis) != (d_hi[axis] < 0.0)) {
            return None;
        }
        // 1 / d falls as d grows on either side of 0, and division rounds
        // monotonically: the extreme directions give the extreme inverses
        // (each ray's own is `safe_inverse`'s 1 / d).
        let (lo, hi) = (
            [0, 1, 2].map(|a| 1.0 / d_hi[a]),
            [0, 1, 2].map(|a| 1.0 / d_lo[a]),
        );
        let (o_lo, o_hi) = (o_lo.to_array(), o_hi.to_array());
        // Toward +, the near plane's distance falls as the origin grows;
        // toward -, it grows with it (and the far plane's the other way).
        let pick = |minus: &[f32; 3], plus: &[f32; 3]| {
            [0, 1, 2].map(|axis| Vec4::splat(if toward_minus(axis) { minus } else { plus }[axis]))
        };
        Some(PacketData {
            common_origin: (o_lo == o_hi).then(|| o_lo.map(Vec4::splat)),
            origin_near: pick(&o_lo, &o_hi),
            origin_far: pick(&o_hi, &o_lo),
            inv_lo: lo.map(Vec4::splat),
            inv_hi: hi.map(Vec4::splat),
            near_plane: [0, 1, 2].map(|axis| if toward_minus(axis) { axis + 3 } else { axis }),
            spread: (
                (Vec3A::from_array(o_hi) - Vec3A::from_array(o_lo)).max_element(),
                (Vec3A::from_array(d_hi) - Vec3A::from_array(d_lo)).max_element(),
            ),
        })
    }
}

impl PacketData {
    /// Whether a leaf's box of `planes`, entered at distance `t`, is small
    /// beside the packet there (each side under `NARROW` times the packet's
    /// width): then some of the packet's rays likely miss it, and testing
    /// it ray by ray (`RayLanes`) costs less than its primitives for those
    /// rays. Where a leaf is much wider than the packet, as are most of a
    /// pixel's 16 samples' leaves, the test would cost more than it saves.
    /// (Shadow rays' stack entries carry no distance: `t` is 0 there, and
    /// the width the origins' spread.)
    #[inline(always)]
    fn small_beside(&self, planes: &[f32; 6], t: f32) -> bool {
        let side = (planes[3] - planes[0])
            .max(planes[4] - planes[1])
            .max(planes[5] - planes[2]);
        side < NARROW * (self.spread.0 + t.max(0.0) * self.spread.1)
    }
}

impl Enter for PacketData {
    /// The boxes one of the rays may enter, and the least of their entry
    /// distances: of the distances from the extreme origin and with the
    /// least and greatest inverse direction, the smaller for the near
    /// plane, the larger for the far.
    #[inline(always)]
    fn enter(&self, node: &Node, halves: usize, t_min: f32, t_max: f32) -> (u32, [Vec4; GROUPS]) {
        slab_test(
            node,
            halves,
            (t_min, t_max),
            &self.near_plane,
            |axis, near, far| {
                let (lo, hi) = (self.inv_lo[axis], self.inv_hi[axis]);
                let near = near - self.origin_near[axis];
                let far = far - self.origin_far[axis];
                ((near * lo).min(near * hi), (far * lo).max(far * hi))
            },
        )
    }
}

/// See `PacketData::small_beside`. A box several times wider than the
/// packet is still missed by some of its rays where the packet meets it
/// near an edge. 3, 5, 10 and 1,000 took the 1.1M bunny's render the same
/// time (8 lies between them), 1,000 cost 16 samples a pixel 5 %, and 1
/// lost most of the gain.
const NARROW: f32 = 8.0;

/// Groups of four rays of a packet, one ray a SIMD lane.
const RAY_GROUPS: usize = PACKET / 4;

/// A packet's rays one to a SIMD lane, in groups of four, for the slab
/// test of a leaf's box ray by ray: each lane's arithmetic is the one
/// `RayData::enter` does for that ray, so with its best hit so far as the
/// limit a ray is offered every leaf that may hold its answer, as its own
/// walk would be. At 1.1M triangles a leaf is smaller than a 4 x 4
/// packet's footprint.
struct RayLanes {
    origin: [[Vec4; 3]; RAY_GROUPS],
    inv_dir: [[Vec4; 3]; RAY_GROUPS],
    /// How many rays.
    len: usize,
    common_origin: bool,
}

impl RayLanes {
    /// The lanes of `rays` (one to `PACKET`); those past the last ray
    /// repeat it.
    fn new(rays: &[Ray]) -> RayLanes {
        let mut origin = [[Vec4::ZERO; 3]; RAY_GROUPS];
        let mut dir = [[Vec4::ONE; 3]; RAY_GROUPS];
        for i in 0..PACKET {
            let ray = &rays[i.min(rays.len() - 1)];
            let (o, d) = (ray.origin(), ray.dir());
            for axis in 0..3 {
                origin[i / 4][axis][i % 4] = o[axis];
                dir[i / 4][axis][i % 4] = d[axis];
            }
        }
        RayLanes {
            origin,
            // `safe_inverse`'s: a packet's directions have no component
            // it replaces (`PacketData::new`). (Shadow rays already
            // blocked beside the tree are left out of the packet, but not
            // of these lanes; their bits are never asked for.)
            inv_dir: dir.map(|d| d.map(|d| Vec4::ONE / d)),
            len: rays.len(),
            common_origin: rays.iter().all(|r| r.origin() == rays[0].origin()),
        }
    }

    /// The rays (a bit mask) whose slab test enters the box `planes`
    /// within (t_min, far], `far` by ray in lanes, for a packet whose rays
    /// meet the near planes `near_plane`.
    #[inline(always)]
    fn entering(
        &self,
        planes: &[f32; 6],
        near_plane: &[usize; 3],
        t_min: f32,
        far: &[Vec4; RAY_GROUPS],
    ) -> u32 {
        // Each axis's near and far plane (the near one the min when the
        // rays run toward +), with indices the compiler sees are in range.
        let mut bounds = [(0.0, 0.0); 3];
        for (axis, bound) in bounds.iter_mut().enumerate() {
            let (min, max) = (planes[axis], planes[axis + 3]);
            *bound = if near_plane[axis] == axis {
                (min, max)
            } else {
                (max, min)
            };
        }
        // The planes' offsets from the origin, by axis; worked out once
        // when the rays share their origin.
        let offsets = |g: usize| {
            let mut offsets = [(Vec4::ZERO, Vec4::ZERO); 3];
            for (axis, &(near, far)) in bounds.iter().enumerate() {
                let o = self.origin[g][axis];
                offsets[axis] = (Vec4::splat(near) - o, Vec4::splat(far) - o);
            }
            offsets
        };
        let shared = offsets(0);
        let mut mask = 0;
        for g in 0..self.len.div_ceil(4).min(RAY_GROUPS) {
            let offsets = if self.common_origin {
                shared
            } else {
                offsets(g)
            };
            let inv = &self.inv_dir[g];
            let mut t_near = Vec4::splat(t_min);
            let mut t_far = far[g];
            for (axis, (near, far)) in offsets.into_iter().enumerate() {
                t_near = t_near.max(near * inv[axis]);
                t_far = t_far.min(far * inv[axis]);
            }
            mask |= t_near.cmple(t_far * PAD).bitmask() << (4 * g);
        }
        mask & all(self.len)
    }
}

/// Which of a packet's rays test a leaf: all, or where the leaf is small
/// beside the packet, those whose own slab test enters its box (the lanes
/// made at the first such leaf).
struct LeafFilter<'a> {
    rays: &'a [Ray],
    packet: &'a PacketData,
    lanes: Option<RayLanes>,
}

impl<'a> LeafFilter<'a> {
    fn new(rays: &'a [Ray], packet: &'a PacketData) -> Self {
        LeafFilter {
            rays,
            packet,
            lanes: None,
        }
    }

    /// The rays (a bit mask) that test the leaf `entry` of `nodes` (its box
    /// read from the node lane that pushed it), each within (t_min, its
    /// lane of `far`].
    #[inline(always)]
    fn rays_entering(
        &mut self,
        nodes: &[Node],
        entry: Entry,
        t_min: f32,
        far: impl FnOnce() -> [Vec4; RAY_GROUPS],
    ) -> u32 {
        let from = entry.from as usize;
        let planes = nodes[from / WIDTH].lane_planes(from % WIDTH);
        if !self.packet.small_beside(&planes, entry.t) {
            return all(self.rays.len());
        }
        let lanes = self.lanes.get_or_insert_with(|| RayLanes::new(self.rays));
        lanes.entering(&planes, &self.packet.near_plane, t_min, &far())
    }
}

/// `value(i)` for each ray i of a packet, one to a lane.
#[inline(always)]
fn by_lane(value: impl Fn(usize) -> f32) -> [Vec4; RAY_GROUPS] {
    let mut lanes = [Vec4::ZERO; RAY_GROUPS];
    for i in 0..PACKET {
        lanes[i / 4][i % 4] = value(i);
    }
    lanes
}

/// The best hits so far of a packet's rays, and the farthest of them.
pub(super) struct Bests {
    of: [Best; PACKET],
    len: usize,
    reach: f32,
}

impl Bests {
    fn new(len: usize, t_max: f32) -> Bests {
        Bests {
            of: [Best::none(t_max); PACKET],
            len,
            reach: t_max,
        }
    }

    fn update_reach(&mut self) {
        self.reach = self.of[..self.len]
            .iter()
            .fold(f32::NEG_INFINITY, |reach, best| reach.max(best.t));
    }

    /// Each ray's reach (`Best::reach`), one to a lane (see `RayLanes`).
    #[inline(always)]
    fn far(&self) -> [Vec4; RAY_GROUPS] {
        by_lane(|i| self.of[i].t)
    }
}

impl Reach for Bests {
    #[inline(always)]
    fn reach(&self) -> f32 {
        self.reach
    }
}

impl Bvh {
    /// Whether the primitives are searched through a tree (not flat, as a
    /// small scene's): what packets walk together.
    pub fn has_tree(&self) -> bool {
        !self.is_flat() && !self.nodes.is_empty()
    }

    /// The nearest hits of `rays` (at most `PACKET`) in (t_min, t_max),
    /// into `hits`: each the one `closest_hit` finds for it. Rays from one
    /// origin are searched together.
    pub fn closest_hits(
        &self,
        rays: &[Ray],
        t_min: f32,
        t_max: f32,
        hits: &mut [Option<SurfaceHit>],
    ) {
        assert!(rays.len() <= PACKET && hits.len() == rays.len());
        let tree = rays.len() > 1 && self.has_tree();
        let Some(packet) = tree.then(|| PacketData::new(rays)).flatten() else {
            for (ray, hit) in rays.iter().zip(hits) {
                *hit = self.closest_hit(ray, t_min, t_max);
            }
            return;
        };
        let mut bests = Bests::new(rays.len(), t_max);
        for (ray, best) in rays.iter().zip(&mut bests.of) {
            self.offer_planes(ray, t_min, t_max, best);
        }
        self.nearest_of_packet(rays, &packet, (t_min, t_max), &mut bests);
        for ((ray, best), hit) in rays.iter().zip(&mut bests.of).zip(hits) {
            if !self.instances.is_empty() {
                self.instances.nearest(ray, t_min, t_max, best);
            }
            *hit = self.surface_hit(best, ray);
        }
    }

    /// Offers each of `bests` the nearest hits of its ray in the tree.
    fn nearest_of_packet(
        &self,
        rays: &[Ray],
        packet: &PacketData,
        (t_min, t_max): (f32, f32),
        bests: &mut Bests,
    ) {
        let ray4 = rays4(rays);
        let mut filter = LeafFilter::new(rays, packet);
        bests.update_reach();
        with_stack(|stack| {
            walk_nearest(&self.nodes, packet, t_min, bests, stack, |entry, bests| {
                let entering = filter.rays_entering(&self.nodes, entry, t_min, || bests.far());
                match (leaf_run(entry), &packet.common_origin) {
                    ((false, run), Some(origin)) => {
                        let (ray4, of) = (&ray4, &mut bests.of);
                        self.offer_blocks_together(run, origin, entering, ray4, (t_min, t_max), of);
                    }
                    _ => {
                        for i in ones(entering) {
                            let best = &mut bests.of[i];
                            self.nearest_in_leaf(&rays[i], &ray4[i], entry, (t_min, t_max), best);
                        }
                    }
                }
                bests.update_reach();
            })
        });
    }

    /// Offers each of `bests` the hits of its ray (`ray4`, from `origin`
    /// as all) on triangle blocks `run`: what the test shares among rays
    /// of one origin worked out once a block.
    #[inline(always)]
    fn offer_blocks_together(
        &self,
        run: Range<usize>,
        origin: &[Vec4; 3],
        rays: u32,
        ray4: &[Ray4; PACKET],
        (t_min, t_max): (f32, f32),
        bests: &mut [Best; PACKET],
    ) {
        if rays == 0 {
            return;
        }
        let test =
            |block: usize, tris: &Tri4, terms: &OriginTerms<Vec4>, i: usize, best: &mut Best| {
                let found = tris.intersect_with(terms, &ray4[i], t_min, best.limit(t_max));
                self.offer_lanes(block, found, t_max, best);
            };
        for block in run {
            let tris = &self.tris[block];
            let terms = tris.origin_terms(origin);
            // The first n rays, as all of a pixel's samples mostly are: a
            // plain loop (16 samples' primary rays 3 % faster than by mask).
            if rays & (rays + 1) == 0 {
                let n = rays.count_ones() as usize;
                for (i, best) in bests[..n].iter_mut().enumerate() {
                    test(block, tris, &terms, i, best);
                }
            } else {
                for i in ones(rays) {
                    test(block, tris, &terms, i, &mut bests[i]);
                }
            }
        }
    }

    /// Which of `rays` (at most `PACKET`) something lies on within
    /// (t_min, t_max[i]), as a bit mask (bit i for ray i): each as
    /// `occluded` finds it. Shadow rays toward one light point, from a
    /// pixel's hits, are searched together.
    pub fn occluded_together(&self, rays: &[Ray], t_min: f32, t_max: &[f32]) -> u32 {
        assert!(rays.len() <= PACKET && t_max.len() == rays.len());
        let mut blocked = 0;
        for (i, (ray, &t_max)) in rays.iter().zip(t_max).enumerate() {
            blocked |= (self.occluded_beside_tree(ray, t_min, t_max) as u32) << i;
        }
        let left = ((1u32 << rays.len()) - 1) & !blocked;
        let in_left = |i: &usize| left & (1 << i) != 0;
        let packet = (left.count_ones() > 1 && self.has_tree())
            .then(|| PacketData::new((0..rays.len()).filter(in_left).map(|i| &rays[i])))
            .flatten();
        let Some(packet) = packet else {
            for i in (0..rays.len()).filter(in_left) {
                blocked |= (self.occluded_in_tree(&rays[i], t_min, t_max[i]) as u32) << i;
            }
            return blocked;
        };
        blocked | self.occluded_in_packet(rays, &packet, t_min, t_max, left)
    }

    /// Which of the rays of `left` (a bit mask) a primitive of the tree
    /// lies on within (t_min, t_max[i]), as a bit mask.
    fn occluded_in_packet(
        &self,
        rays: &[Ray],
        packet: &PacketData,
        t_min: f32,
        t_max: &[f32],
        left: u32,
    ) -> u32 {
        let ray4 = rays4(rays);
        let mut filter = LeafFilter::new(rays, packet);
        let far = by_lane(|i| t_max[i.min(rays.len() - 1)]);
        let reach = (0..rays.len())
            .filter(|&i| left & (1 << i) != 0)
            .fold(f32::NEG_INFINITY, |reach, i| reach.max(t_max[i]));
        let mut open = left;
        with_stack(|stack| {
            walk_any(&self.nodes, packet, (t_min, reach), stack, |entry| {
                let entering = filter.rays_entering(&self.nodes, entry, t_min, || far);
                for i in ones(open & entering) {
                    if self.any_in_leaf(&rays[i], &ray4[i], entry, (t_min, t_max[i])) {
                        open &= !(1 << i);
                    }
                }
                open == 0
            })
        });
        left & !open
    }
}

/// Bits 0 to `n - 1`.
fn all(n: usize) -> u32 {
    (1u32 << n) - 1
}

/// The bits set in `mask`, lowest first.
#[inline(always)]
pub(super) fn ones(mut mask: u32) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (mask != 0).then(|| {
            let i = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            i
        })
    })
}

/// Each ray of `rays` in every lane, for the triangle blocks' test; the
/// lanes past the last ray repeat it.
fn rays4(rays: &[Ray]) -> [Ray4; PACKET] {
    std::array::from_fn(|i| {
        let ray = &rays[i.min(rays.len() - 1)];
        Ray4::new(ray)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::brute_force;
    use crate::accel::tests::{soup, Rng};
    use crate::accel::traverse::RayData;
    use crate::geometry::{Object, Plane, Shape, Sphere, Triangle};
    use glam::Vec3;

    /// Up to 16 rays around one direction: a pixel's samples from one
    /// origin (spread 0.002), or wider (0.3); or shadow rays, from points
    /// up to 0.05 apart toward one point; some with a zero component, so
    /// that the packet is refused.
    fn packet(rng: &mut Rng, k: usize) -> Vec<Ray> {
        let origin = rng.vec(if k.is_multiple_of(2) { 8.0 } else { 4.0 });
        let aim = rng.vec(1.0);
        let spread = if k.is_multiple_of(3) { 0.3 } else { 0.002 };
        let n = 1 + k % PACKET;
        let mut rays: Vec<Ray> = (0..n)
            .map(|_| Ray::new(origin, aim + rng.vec(spread)))
            .collect();
        if k % 5 == 1 {
            let light = origin + 6.0 * aim;
            for ray in &mut rays {
                let origin = ray.origin() + rng.vec(0.05);
                *ray = Ray::new(origin, (light - origin).normalize());
            }
        }
        if k.is_multiple_of(11) {
            let (origin, dir) = (rays[n - 1].origin(), rays[n - 1].dir());
            rays[n - 1] = Ray::new(origin, Vec3::new(dir.x, 0.0, dir.z));
        }
        rays
    }

    #[test]
    fn packets_find_exactly_the_brute_force_hits() {
        let mut rng = Rng(0xC0FF_EE00_1234_5678);
        let mut objects = soup(&mut rng, 3000);
        objects.insert(
            400,
            Object::new(
                Shape::Plane(Box::new(Plane::new(-4.0 * Vec3::Y, Vec3::Y))),
                1,
            ),
        );
        let bvh = Bvh::build(&objects);
        let (mut searched_together, mut hits, mut blocked) = (0, 0, 0);
        for k in 0..3000 {
            let rays = packet(&mut rng, k);
            let t_max = if k.is_multiple_of(4) {
                3.0
            } else {
                f32::INFINITY
            };
            let mut found = vec![None; rays.len()];
            bvh.closest_hits(&rays, 1e-4, t_max, &mut found);
            // Shadow rays' lengths differ ray by ray.
            let lengths: Vec<f32> = (0..rays.len()).map(|i| 1.0 + i as f32 * 0.4).collect();
            let occluded = bvh.occluded_together(&rays, 1e-4, &lengths);
            for (i, ray) in rays.iter().enumerate() {
                let expected = brute_force::closest_hit(&objects, ray, 1e-4, t_max);
                assert_eq!(found[i], expected, "packet {k}, ray {i}");
                hits += expected.is_some() as u32;
                let any = brute_force::occluded(&objects, ray, 1e-4, lengths[i]);
                assert_eq!(occluded & (1 << i) != 0, any, "packet {k}, shadow ray {i}");
                blocked += any as u32;
            }
            searched_together += (rays.len() > 1 && PacketData::new(&rays).is_some()) as u32;
        }
        assert!(searched_together > 2000, "{searched_together} packets");
        assert!(
            hits > 10_000,
            "only {hits} hits: the test would prove little"
        );
        assert!(
            blocked > 5_000,
            "only {blocked} blocked: the test would prove little"
        );
    }

    #[test]
    fn a_packet_enters_every_box_one_of_its_rays_enters() {
        let mut rng = Rng(0xB0B5);
        let objects = soup(&mut rng, 500);
        let nodes = super::super::wide::build(&mut objects_prims(&objects));
        let (mut entered, mut tested) = (0, 0);
        for k in 0..2000 {
            let rays = packet(&mut rng, k);
            let Some(p) = PacketData::new(&rays) else {
                continue;
            };
            let t_max = if k.is_multiple_of(2) {
                4.0
            } else {
                f32::INFINITY
            };
            for node in &nodes {
                let (mask, near) = p.enter(node, GROUPS, 1e-4, t_max);
                for ray in &rays {
                    let (own, own_near) = RayData::new(ray).enter(node, GROUPS, 1e-4, t_max);
                    assert_eq!(own & !mask, 0, "packet {k}: a box of a ray left out");
                    for lane in 0..8 {
                        if own & (1 << lane) != 0 {
                            assert!(near[lane / 4][lane % 4] <= own_near[lane / 4][lane % 4]);
                        }
                    }
                    entered += own.count_ones();
                }
                tested += 1;
            }
        }
        assert!(
            tested > 1000 && entered > 1000,
            "{tested} nodes, {entered} boxes"
        );
    }

    #[test]
    fn a_leaf_is_offered_to_exactly_the_rays_whose_own_slab_test_enters_it() {
        let mut rng = Rng(0x5EED_1EAF);
        let objects = soup(&mut rng, 500);
        let nodes = super::super::wide::build(&mut objects_prims(&objects));
        let (mut entered, mut missed) = (0, 0);
        for k in 0..1500 {
            let rays = packet(&mut rng, k);
            let Some(p) = PacketData::new(&rays) else {
                continue;
            };
            let lanes = RayLanes::new(&rays);
            // Each ray's own limit: its best hit so far, or none.
            let limits: Vec<f32> = (0..PACKET)
                .map(|i| match (k + i) % 3 {
                    0 => f32::INFINITY,
                    _ => 1.0 + 6.0 * rng.next().abs(),
                })
                .collect();
            let far: [Vec4; RAY_GROUPS] =
                std::array::from_fn(|g| Vec4::from_slice(&limits[4 * g..4 * g + 4]));
            for node in &nodes {
                for lane in 0..WIDTH {
                    let planes = node.lane_planes(lane);
                    let mask = lanes.entering(&planes, &p.near_plane, 1e-4, &far);
                    for (i, ray) in rays.iter().enumerate() {
                        let (own, _) = RayData::new(ray).enter(node, GROUPS, 1e-4, limits[i]);
                        let own = own & (1 << lane) != 0;
                        assert_eq!(
                            mask & (1 << i) != 0,
                            own,
                            "packet {k}, ray {i}, lane {lane}"
                        );
                        (entered, missed) = (entered + own as u32, missed + !own as u32);
                    }
                    assert_eq!(mask >> rays.len(), 0, "packet {k}: a lane past its rays");
                }
            }
        }
        assert!(
            entered > 10_000 && missed > 10_000,
            "{entered} entered, {missed} missed"
        );
    }

    /// A ray's leaf test at the edge of its limit: the limit at the box's
    /// entry distance, just below it, and where only the padding of the
    /// slab test lets the ray in; directions with components down to the
    /// least a packet takes; origins on the box's planes; flat boxes.
    #[test]
    fn a_leaf_is_offered_as_the_rays_own_slab_test_decides_at_the_edges() {
        let mut rng = Rng(0xFEED_BEEF);
        let index = |rng: &mut Rng, n: usize| ((rng.next() + 1.0) * 0.5 * n as f32) as usize % n;
        let (mut checked, mut by_padding) = (0, 0);
        let sizes = [1e-30f32, 1.5e-30, 1e-7, 0.3, 1.0, 7.0, 1e30];
        let coordinates = [0.0f32, -0.0, 1.0, -1.0, 0.5, 3.0, 1e-20];
        for k in 0..20_000 {
            let signs = [0, 1, 2].map(|_| if rng.next() < 0.0 { -1.0 } else { 1.0 });
            let lo = [0, 1, 2].map(|_| coordinates[index(&mut rng, 7)] + rng.next().max(0.0));
            let hi: [f32; 3] = std::array::from_fn(|a| {
                let flat = k % 3 == 0 && a == k % 9 / 3;
                lo[a] + if flat { 0.0 } else { 2.0 * rng.next().abs() }
            });
            let n = 1 + index(&mut rng, PACKET);
            let rays: Vec<Ray> = (0..n)
                .map(|_| {
                    let dir: [f32; 3] = std::array::from_fn(|a| {
                        let size = match rng.next() < -0.4 {
                            true => sizes[index(&mut rng, sizes.len())],
                            false => 0.01 + rng.next().abs(),
                        };
                        signs[a] * size
                    });
                    let origin: [f32; 3] = std::array::from_fn(|a| match index(&mut rng, 4) {
                        0 => lo[a],
                        1 => hi[a],
                        2 => coordinates[index(&mut rng, 7)],
                        _ => 4.0 * rng.next(),
                    });
                    Ray::new(Vec3::from_array(origin), Vec3::from_array(dir))
                })
                .collect();
            let Some(p) = PacketData::new(&rays) else {
                continue;
            };
            let lane = index(&mut rng, WIDTH);
            let mut node = Node::EMPTY;
            node.set_bounds(lane, &bounds(lo, hi));
            let t_min = [0.0, 1e-4, -1.0, 0.5][k % 4];
            let limits: [f32; PACKET] = std::array::from_fn(|i| {
                let own = RayData::new(&rays[i.min(n - 1)]);
                let entry = own.enter(&node, GROUPS, t_min, f32::INFINITY).1[lane / 4][lane % 4];
                let below = |t: f32| f32::from_bits(t.to_bits().wrapping_sub(1));
                [
                    f32::INFINITY,
                    entry,
                    below(entry),
                    entry / PAD,
                    below(entry / PAD),
                    entry / PAD / PAD,
                    f32::NAN,
                    10.0 * rng.next().abs(),
                ][index(&mut rng, 8)]
            });
            let far: [Vec4; RAY_GROUPS] =
                std::array::from_fn(|g| Vec4::from_slice(&limits[4 * g..4 * g + 4]));
            let lanes = RayLanes::new(&rays);
            let mask = lanes.entering(&node.lane_planes(lane), &p.near_plane, t_min, &far);
            assert_eq!(mask >> n, 0, "packet {k}: a lane past its rays");
            for (i, ray) in rays.iter().enumerate() {
                let (own, near) = RayData::new(ray).enter(&node, GROUPS, t_min, limits[i]);
                let own = own & (1 << lane) != 0;
                assert_eq!(mask & (1 << i) != 0, own, "packet {k}, ray {i}");
                by_padding += (own && near[lane / 4][lane % 4] > limits[i]) as u32;
                checked += 1;
            }
        }
        assert!(checked > 50_000, "{checked} rays");
        assert!(
            by_padding > 100,
            "{by_padding} rays let in by the padding alone"
        );
    }

    fn bounds(lo: [f32; 3], hi: [f32; 3]) -> super::super::build::Aabb {
        super::super::build::Aabb {
            min: glam::Vec3A::from_array(lo),
            max: glam::Vec3A::from_array(hi),
        }
    }

    /// A flat grid of 28,800 small triangles with shared edges, a sphere
    /// of 4,096, copies of some of them (ties), and 200 small spheres; and
    /// the grid's and the sphere's vertices and edge midpoints, to aim at.
    fn fine_scene() -> (Vec<Object>, [Vec<Vec3>; 2]) {
        let mut objects = Vec::new();
        let mut targets = [Vec::new(), Vec::new()];
        let triangle =
            |a, b, c, material| Object::new(Shape::Triangle(Triangle::new(a, b, c)), material);
        let n = 120;
        let grid = |i: usize, j: usize| {
            let at = |k: usize| -2.0 + 4.0 * k as f32 / n as f32;
            Vec3::new(at(i), at(j), 0.0)
        };
        for i in 0..n {
            for j in 0..n {
                let [a, b, c, d] = [
                    grid(i, j),
                    grid(i + 1, j),
                    grid(i + 1, j + 1),
                    grid(i, j + 1),
                ];
                let (first, second, diagonal) = match (i + j) % 2 {
                    0 => ((a, b, c), (a, c, d), 0.5 * (a + c)),
                    _ => ((a, b, d), (b, c, d), 0.5 * (b + d)),
                };
                objects.push(triangle(first.0, first.1, first.2, 0));
                objects.push(triangle(second.0, second.1, second.2, 1));
                targets[0].extend([a, 0.5 * (a + b), diagonal]);
            }
        }
        let (center, radius, around, down) = (Vec3::new(0.3, -0.2, 1.0), 0.7, 64, 32);
        let sphere = |i: usize, j: usize| {
            let phi = std::f32::consts::TAU * (i % around) as f32 / around as f32;
            let theta = std::f32::consts::PI * j as f32 / down as f32;
            let (sin, cos) = (theta.sin(), theta.cos());
            center + radius * Vec3::new(sin * phi.cos(), sin * phi.sin(), cos)
        };
        let first = objects.len();
        for i in 0..around {
            for j in 0..down {
                let [a, b, c, d] = [
                    sphere(i, j),
                    sphere(i + 1, j),
                    sphere(i + 1, j + 1),
                    sphere(i, j + 1),
                ];
                objects.push(triangle(a, b, c, 2));
                objects.push(triangle(a, c, d, 0));
                targets[1].extend([a, 0.5 * (a + c), 0.5 * (a + b)]);
            }
        }
        let copies: Vec<Object> = objects[first..].iter().step_by(5).cloned().collect();
        objects.extend(copies);
        let mut rng = Rng(0xABCD_1234);
        for _ in 0..200 {
            let c = rng.vec(2.0) * Vec3::new(1.0, 1.0, 0.0) + Vec3::new(0.0, 0.0, 0.05);
            objects.push(Object::new(Shape::Sphere(Sphere::new(c, 0.02)), 1));
        }
        (objects, targets)
    }

    /// Two unit vectors square to `d` and to each other.
    fn across(d: Vec3) -> (Vec3, Vec3) {
        let u = d
            .cross(if d.x.abs() < 0.9 { Vec3::X } else { Vec3::Y })
            .normalize();
        (u, d.normalize().cross(u))
    }

    /// Packets on a fine mesh, whose leaves are small beside them: 4 x 4
    /// packets from one origin with one ray aimed at a vertex or an edge,
    /// packets from many origins toward one point, some with tiny
    /// components; limits and shadow lengths at a ray's own hit distance
    /// and one ulp past it. (A limit a ten-thousandth short of each ray's
    /// own, in either walk, fails it.)
    #[test]
    fn packets_on_a_fine_mesh_find_exactly_the_brute_force_hits() {
        let (objects, targets) = fine_scene();
        let bvh = Bvh::build(&objects);
        let mut rng = Rng(0x1234_5678_9ABC_DEF1);
        let pick = |rng: &mut Rng, v: &[Vec3]| {
            v[((rng.next() + 1.0) * 0.5 * v.len() as f32) as usize % v.len()]
        };
        let nearest = |ray: &Ray| brute_force::closest_hit(&objects, ray, 1e-4, f32::INFINITY);
        let next_up = |t: f32| f32::from_bits(t.to_bits() + 1);
        let (mut hits, mut blocked, mut together) = (0, 0, 0);
        for k in 0..800 {
            let mut rays: Vec<Ray> = Vec::new();
            match k % 5 {
                0 | 1 => {
                    let target = pick(&mut rng, &targets[k % 2]);
                    let origin = Vec3::new(
                        3.0 * rng.next(),
                        3.0 * rng.next(),
                        3.0 + 3.0 * rng.next().abs(),
                    );
                    let aim = target - origin;
                    let (u, v) = across(aim);
                    let step = [1e-4, 1e-3, 4e-3, 2e-2][(k / 4) % 4] * aim.length();
                    for (a, b) in (0..16).map(|i| ((i % 4) as f32 - 1.0, (i / 4) as f32 - 1.0)) {
                        rays.push(Ray::new(origin, aim + (a * u + b * v) * step));
                    }
                }
                2 => {
                    // Straight down at the grid, x and y tiny or zero.
                    let target = pick(&mut rng, &targets[0]);
                    let origin = Vec3::new(target.x, target.y, 1.0 + 4.0 * rng.next().abs());
                    let spread = [0.0, 1e-5, 1e-3][(k / 4) % 3];
                    let tiny = [1e-20, 1e-29, 1e-7][(k / 12) % 3];
                    for (a, b) in (0..16).map(|i| ((i % 4) as f32, (i / 4) as f32)) {
                        rays.push(Ray::new(
                            origin,
                            Vec3::new(tiny + a * spread, tiny + b * spread, -1.0),
                        ));
                    }
                }
                3 => {
                    // Rays from many origins above the grid toward one
                    // point below it: they meet its flat leaves where
                    // their boxes begin.
                    let target = pick(&mut rng, &targets[0]);
                    let spacing = [0.002, 0.02, 0.1][(k / 5) % 3];
                    let below = target - Vec3::new(0.1 * rng.next(), 0.1 * rng.next(), 0.5);
                    let top = target + (target - below) * (1.0 + rng.next().abs());
                    for i in 0..16 {
                        let origin = top + Vec3::new((i % 4) as f32, (i / 4) as f32, 0.0) * spacing;
                        rays.push(Ray::new(origin, below - origin));
                    }
                }
                _ => {
                    // Shadow rays from the grid toward a light placed so
                    // that the first passes through a vertex of the sphere.
                    let (vertex, base) = (pick(&mut rng, &targets[1]), pick(&mut rng, &targets[0]));
                    let spacing = [0.002, 0.02, 0.1][(k / 4) % 3];
                    let light = vertex + (vertex - base) * (0.5 + rng.next().abs());
                    for i in 0..16 {
                        let origin =
                            base + Vec3::new((i % 4) as f32, (i / 4) as f32, 0.0) * spacing;
                        rays.push(Ray::new(origin, (light - origin).normalize()));
                    }
                }
            }
            rays.truncate(if k % 7 == 3 { 1 + (k / 7) % 16 } else { 16 });
            let first = nearest(&rays[0]);
            let t_max = match k % 3 {
                0 => first.map_or(f32::INFINITY, |h| h.t),
                1 => first.map_or(f32::INFINITY, |h| next_up(h.t)),
                _ => f32::INFINITY,
            };
            let mut found = vec![None; rays.len()];
            bvh.closest_hits(&rays, 1e-4, t_max, &mut found);
            let lengths: Vec<f32> = rays
                .iter()
                .enumerate()
                .map(|(i, ray)| match (nearest(ray), i % 3) {
                    (Some(h), 0) => h.t,
                    (Some(h), 1) => next_up(h.t),
                    _ => 2.0 + i as f32 * 0.3,
                })
                .collect();
            let occluded = bvh.occluded_together(&rays, 1e-4, &lengths);
            for (i, ray) in rays.iter().enumerate() {
                let expected = brute_force::closest_hit(&objects, ray, 1e-4, t_max);
                assert_eq!(found[i], expected, "packet {k}, ray {i}");
                let any = brute_force::occluded(&objects, ray, 1e-4, lengths[i]);
                assert_eq!(occluded & (1 << i) != 0, any, "packet {k}, shadow ray {i}");
                (hits, blocked) = (hits + expected.is_some() as u32, blocked + any as u32);
            }
            together += (rays.len() > 1 && PacketData::new(&rays).is_some()) as u32;
        }
        assert!(together > 600, "{together} packets searched together");
        assert!(
            hits > 5_000 && blocked > 3_000,
            "{hits} hits, {blocked} blocked"
        );
    }

    fn objects_prims(objects: &[Object]) -> Vec<super::super::build::BuildPrim> {
        let ids = 0u32..;
        objects
            .iter()
            .zip(ids)
            .flat_map(|(o, id)| super::super::build::BuildPrim::new(&o.shape, id))
            .collect()
    }
}
