//! Rays searched together: a pixel's samples share the camera's origin and
//! differ in direction by less than a pixel, so they enter nearly the same
//! nodes. A packet walks the tree once, testing a node's boxes against all
//! its rays at once, and tests each leaf's primitives against each ray.
//!
//! Each ray finds the hit it finds alone. The packet's box test bounds
//! every ray's: float products are monotone in each factor, so the
//! products with the least and the greatest inverse direction of an axis
//! bound each ray's own, and the packet enters every box that one of its
//! rays would. Each ray is thus offered the primitives of its own walk and
//! perhaps more (all of them real hits or misses of the same arithmetic),
//! and the best-hit rule (nearest, then lowest object index) does not
//! depend on the order or the number of the offers.

use super::traverse::{safe_inverse, slab_test, walk_nearest, with_stack, Best, Enter, Reach};
use super::tri4::Ray4;
use super::wide::{Node, GROUPS};
use super::Bvh;
use crate::geometry::SurfaceHit;
use crate::ray::Ray;
use glam::Vec4;

/// Most rays in one packet: a pixel's 16 samples.
pub const PACKET: usize = 16;

/// A packet's rays as the box test needs them: their common origin in
/// every lane and, per axis, the least and greatest inverse direction (of
/// one sign).
pub(super) struct PacketData {
    origin: [Vec4; 3],
    inv_lo: [Vec4; 3],
    inv_hi: [Vec4; 3],
    near_plane: [usize; 3],
}

impl PacketData {
    /// The packet of `rays`; None when they do not share an origin, or the
    /// sign of their direction differs on some axis (the near plane would
    /// differ too), or a direction is not finite and non-zero.
    pub(super) fn new(rays: &[Ray]) -> Option<PacketData> {
        let origin = rays.first()?.origin;
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for ray in rays {
            let inv = safe_inverse(ray.dir);
            if ray.origin != origin || inv.iter().any(|&i| !i.is_normal()) {
                return None;
            }
            for axis in 0..3 {
                lo[axis] = lo[axis].min(inv[axis]);
                hi[axis] = hi[axis].max(inv[axis]);
            }
        }
        if (0..3).any(|axis| (lo[axis] < 0.0) != (hi[axis] < 0.0)) {
            return None;
        }
        Some(PacketData {
            origin: origin.to_array().map(Vec4::splat),
            inv_lo: lo.map(Vec4::splat),
            inv_hi: hi.map(Vec4::splat),
            near_plane: [0, 1, 2].map(|axis| if lo[axis] < 0.0 { axis + 3 } else { axis }),
        })
    }
}

impl Enter for PacketData {
    /// The boxes one of the rays may enter, and the least of their entry
    /// distances: the slab distances of the least and greatest inverse
    /// direction, the smaller for the near plane, the larger for the far.
    #[inline(always)]
    fn enter(&self, node: &Node, halves: usize, t_min: f32, t_max: f32) -> (u32, [Vec4; GROUPS]) {
        slab_test(
            node,
            halves,
            (t_min, t_max),
            &self.near_plane,
            |axis, near, far| {
                let (lo, hi) = (self.inv_lo[axis], self.inv_hi[axis]);
                let (near, far) = (near - self.origin[axis], far - self.origin[axis]);
                ((near * lo).min(near * hi), (far * lo).max(far * hi))
            },
        )
    }
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
}

impl Reach for Bests {
    #[inline(always)]
    fn reach(&self) -> f32 {
        self.reach
    }
}

impl Bvh {
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
        let tree = rays.len() > 1 && !self.is_flat() && !self.nodes.is_empty();
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
        let ray4: [Ray4; PACKET] = std::array::from_fn(|i| {
            let ray = &rays[i.min(rays.len() - 1)];
            Ray4::new(ray, ray.dir.length())
        });
        bests.update_reach();
        with_stack(|stack| {
            walk_nearest(&self.nodes, packet, t_min, bests, stack, |entry, bests| {
                for (i, best) in bests.of[..bests.len].iter_mut().enumerate() {
                    self.nearest_in_leaf(&rays[i], &ray4[i], entry, (t_min, t_max), best);
                }
                bests.update_reach();
            })
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::brute_force;
    use crate::accel::tests::{soup, Rng};
    use crate::accel::traverse::RayData;
    use crate::geometry::{Object, Plane, Shape};
    use glam::Vec3;

    /// Up to 16 rays from one origin around one direction: a pixel's
    /// samples (spread 0.002), or wider (0.3); some with a zero component,
    /// some from another origin, so that the packet is refused.
    fn packet(rng: &mut Rng, k: usize) -> Vec<Ray> {
        let origin = rng.vec(if k.is_multiple_of(2) { 8.0 } else { 4.0 });
        let aim = rng.vec(1.0);
        let spread = if k.is_multiple_of(3) { 0.3 } else { 0.002 };
        let n = 1 + k % PACKET;
        let mut rays: Vec<Ray> = (0..n)
            .map(|_| Ray::new(origin, aim + rng.vec(spread)))
            .collect();
        if k.is_multiple_of(11) {
            rays[n - 1].dir.y = 0.0;
        }
        if k.is_multiple_of(13) {
            rays[0].origin.x += 1e-3;
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
        let (mut searched_together, mut hits) = (0, 0);
        for k in 0..3000 {
            let rays = packet(&mut rng, k);
            let t_max = if k.is_multiple_of(4) {
                3.0
            } else {
                f32::INFINITY
            };
            let mut found = vec![None; rays.len()];
            bvh.closest_hits(&rays, 1e-4, t_max, &mut found);
            for (i, ray) in rays.iter().enumerate() {
                let expected = brute_force::closest_hit(&objects, ray, 1e-4, t_max);
                assert_eq!(found[i], expected, "packet {k}, ray {i}");
                hits += expected.is_some() as u32;
            }
            searched_together += (rays.len() > 1 && PacketData::new(&rays).is_some()) as u32;
        }
        assert!(searched_together > 2000, "{searched_together} packets");
        assert!(
            hits > 10_000,
            "only {hits} hits: the test would prove little"
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

    fn objects_prims(objects: &[Object]) -> Vec<super::super::build::BuildPrim> {
        let ids = 0u32..;
        objects
            .iter()
            .zip(ids)
            .flat_map(|(o, id)| super::super::build::BuildPrim::new(&o.shape, id))
            .collect()
    }
}
