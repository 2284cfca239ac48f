//! Triangles cut out by alpha masks (`alpha_mask.rs`): a hit where a
//! triangle's mask cuts it is left out where the blocks' hits are offered
//! (`offer_lanes`) and where they stop a shadow ray (`any_block`), so each
//! search (nearest, any, flat, in packets, in an instance's mesh) goes on
//! to the next hit as if the hole held nothing. A tree without masks never
//! reads them: one test of an empty field per block hit.

use super::Bvh;
use crate::alpha_mask::AlphaMask;
use glam::{Vec2, Vec4};
use std::sync::Arc;

impl Bvh {
    /// The same tree, its triangles cut out where `masks[m]` cuts them, m
    /// being each triangle's material (a scene material; a shared mesh's
    /// slot): a hit there is no hit, and every search goes on past it to
    /// the next. Spheres and planes are never cut.
    pub fn with_masks(mut self, masks: Vec<Option<Arc<AlphaMask>>>) -> Bvh {
        let any = masks.iter().any(Option::is_some);
        self.masks = any.then(|| masks.into_boxed_slice());
        self
    }

    /// The lanes of `hits` (a bit mask of triangle block `block`'s lanes,
    /// found at barycentrics `u`, `v`) whose surface is there: those a
    /// mask cuts out are left out.
    pub(super) fn uncut(&self, block: usize, mut hits: u32, [u, v]: [Vec4; 2]) -> u32 {
        let Some(masks) = &self.masks else {
            return hits;
        };
        let tris = &self.tris[block];
        let mut lanes = hits;
        while lanes != 0 {
            let lane = lanes.trailing_zeros() as usize;
            lanes &= lanes - 1;
            let Some(Some(mask)) = masks.get(tris.material(lane) as usize) else {
                continue;
            };
            let uv = self.map_uv(tris.id[lane], Vec2::new(u[lane], v[lane]));
            if mask.cuts(uv) {
                hits &= !(1 << lane);
            }
        }
        hits
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{soup, Rng};
    use super::super::PACKET;
    use super::*;
    use crate::geometry::{
        Instance, Object, Placement, Shape, SharedMesh, SurfaceHit, Triangle, UvMap,
    };
    use crate::ray::Ray;
    use crate::texture::{ColorTexture, ImageTexels, Wrap};
    use glam::Vec3;

    /// A 4 x 4 checkerboard of alpha 0 and 1 (grey colour), repeated.
    fn checker_mask() -> Arc<AlphaMask> {
        let colours = Arc::new(vec![[128u8; 3]; 16]);
        let alpha = (0..16).map(|k| if (k % 4 + k / 4) % 2 == 0 { 0 } else { 255 });
        let texels = ImageTexels::from_srgb8(4, 4, colours).with_alpha(Arc::new(alpha.collect()));
        let texture = ColorTexture::Image {
            texels: Arc::new(texels),
            scale: Vec2::ONE,
            wrap: Wrap::Repeat,
            place: None,
        };
        Arc::new(AlphaMask::new(Some(texture), 0.5).expect("a mask that cuts"))
    }

    /// The nearest hit the masks let through, by the loop over every
    /// object (each triangle hit once, tested on its own; an instance's
    /// mesh triangle by triangle, its slots' masks being `slot_masks`),
    /// ties to the object listed first; and whether any lies on the ray.
    fn expected(
        objects: &[Object],
        masks: &[Option<Arc<AlphaMask>>],
        slot_masks: &[Option<Arc<AlphaMask>>],
        ray: &Ray,
        t_max: f32,
    ) -> (Option<SurfaceHit>, bool) {
        let cut = |masks: &[Option<Arc<AlphaMask>>], h: &SurfaceHit| matches!(masks.get(h.material), Some(Some(m)) if m.cuts(h.uv));
        let (mut best, mut any): (Option<SurfaceHit>, bool) = (None, false);
        for (k, o) in objects.iter().enumerate() {
            let found = match &o.shape {
                Shape::Instance(i) => {
                    let local = i.object_ray(ray);
                    let mut nearest: Option<SurfaceHit> = None;
                    for (j, t) in i.mesh().objects().iter().enumerate() {
                        let limit = nearest.map_or(t_max, |h| h.t);
                        let hit = t.surface_hit(j, &local, 1e-4, limit);
                        if let Some(h) = hit.filter(|h| !cut(slot_masks, h)) {
                            nearest = Some(h);
                        }
                    }
                    nearest.map(|h| i.world_hit(ray, h, k))
                }
                _ => o
                    .surface_hit(k, ray, 1e-4, t_max)
                    .filter(|h| !matches!(o.shape, Shape::Triangle(_)) || !cut(masks, h)),
            };
            let Some(hit) = found else { continue };
            any = true;
            if best.is_none_or(|b| hit.t < b.t) {
                best = Some(hit);
            }
        }
        (best, any)
    }

    #[test]
    fn masked_triangles_are_passed_over_by_every_search() {
        let mut rng = Rng(0xA1FA);
        let mut objects = soup(&mut rng, 1500);
        // Mapped uv on some, so the mask is read where the hit's uv is.
        for o in objects.iter_mut().step_by(4) {
            o.uv = Some(Box::new(UvMap {
                origin: Vec2::new(0.3, 0.1),
                du: Vec2::new(2.0, 0.5),
                dv: Vec2::new(-0.5, 1.5),
            }));
        }
        let masks = vec![None, Some(checker_mask()), None];
        let bvh = Bvh::build(&objects).with_masks(masks.clone());
        let unmasked = Bvh::build(&objects);
        let (mut cut, mut hits, mut packets) = (0, 0, 0);
        for k in 0..3000 {
            // Rays from one origin, as a pixel's samples: each alone, and
            // as a packet (searched together when they agree in sign).
            let origin = rng.vec(if k % 2 == 0 { 8.0 } else { 4.0 });
            let aim = rng.vec(1.0);
            let rays: Vec<Ray> = (0..PACKET)
                .map(|_| Ray::new(origin, aim + rng.vec(0.05)))
                .collect();
            let t_max = if k % 3 == 0 { 2.0 } else { f32::INFINITY };
            let mut together = vec![None; PACKET];
            bvh.closest_hits(&rays, 1e-4, t_max, &mut together);
            let limits = vec![t_max; PACKET];
            let blocked = bvh.occluded_together(&rays, 1e-4, &limits);
            for (i, ray) in rays.iter().enumerate() {
                let (nearest, any) = expected(&objects, &masks, &[], ray, t_max);
                assert_eq!(bvh.closest_hit(ray, 1e-4, t_max), nearest, "ray {k}.{i}");
                assert_eq!(together[i], nearest, "ray {k}.{i} in a packet");
                assert_eq!(bvh.occluded(ray, 1e-4, t_max), any, "ray {k}.{i}");
                assert_eq!(blocked >> i & 1 == 1, any, "ray {k}.{i} in a packet");
                hits += nearest.is_some() as u32;
                cut += (unmasked.closest_hit(ray, 1e-4, t_max) != nearest) as u32;
            }
            packets += bvh.has_tree() as u32;
        }
        assert!(packets > 0, "no packet walked the tree");
        assert!(
            hits > 8000 && cut > 1000,
            "{hits} hits, {cut} through holes"
        );
    }

    #[test]
    fn an_instance_s_mesh_is_cut_by_the_masks_of_its_slots() {
        let mut rng = Rng(0x5107);
        let triangles: Vec<Object> = (0..200)
            .map(|i| {
                let c = rng.vec(1.0);
                let t = Triangle::new(c, c + rng.vec(0.5), c + rng.vec(0.5));
                Object::new(Shape::Triangle(t), i % 2)
            })
            .collect();
        let slot_masks = vec![Some(checker_mask()), None];
        let mesh = Arc::new(SharedMesh::new(triangles).with_masks(slot_masks.clone()));
        let mut objects = soup(&mut rng, 200);
        for _ in 0..12 {
            let placement =
                Placement::new(rng.vec(1.0).abs() + Vec3::ONE, rng.vec(90.0), rng.vec(4.0));
            let instance = Instance::new(Arc::clone(&mesh), placement, vec![5, 6]).unwrap();
            objects.push(Object::new(Shape::Instance(Arc::new(instance)), 5));
        }
        let bvh = Bvh::build(&objects);
        let (mut on_instances, mut through) = (0, 0);
        for k in 0..20_000 {
            let ray = Ray::new(rng.vec(if k % 2 == 0 { 9.0 } else { 4.0 }), rng.vec(1.0));
            let (nearest, any) = expected(&objects, &[], &slot_masks, &ray, f32::INFINITY);
            let found = bvh.closest_hit(&ray, 1e-4, f32::INFINITY);
            assert_eq!(
                found.map(|h| (h.object, h.material)),
                nearest.map(|h| (h.object, h.material)),
                "ray {k}"
            );
            assert_eq!(found.map(|h| h.t), nearest.map(|h| h.t), "ray {k}");
            assert_eq!(bvh.occluded(&ray, 1e-4, f32::INFINITY), any, "ray {k}");
            on_instances += nearest.is_some_and(|h| h.object >= 200) as u32;
            let unmasked =
                crate::accel::brute_force::closest_hit(&objects, &ray, 1e-4, f32::INFINITY);
            through += (unmasked.map(|h| h.t) != nearest.map(|h| h.t)) as u32;
        }
        assert!(
            on_instances > 1000 && through > 300,
            "{on_instances} on instances, {through} through holes"
        );
    }
}
