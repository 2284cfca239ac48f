//! A mesh placed by several objects: its triangles prepared once, in the
//! mesh file's own coordinates, with a BVH of their own; each object naming
//! it is an `Instance`, the shared triangles with its own transform and
//! materials. A ray meets an instance by moving into the mesh's space (its
//! direction not renormalised, so a distance along it is the same `t` as
//! along the world ray), and its hit comes back by the transform.

use super::{Object, Placement, Shape, SurfaceHit};
use crate::accel::{brute_force, Bvh};
use crate::alpha_mask::AlphaMask;
use crate::ray::Ray;
use glam::{Mat3, Vec3};
use std::sync::Arc;

/// The triangles of a mesh shared by several objects, in the mesh's own
/// coordinates, and the BVH over them. Their `material` is a slot of each
/// instance's table (`Instance::new`), not a scene material, so objects
/// naming the mesh with other materials share it too.
#[derive(Debug, PartialEq)]
pub struct SharedMesh {
    objects: Vec<Object>,
    bvh: Bvh,
}

impl SharedMesh {
    /// The mesh of `objects`, its BVH built on the current rayon pool.
    /// Only triangles are kept: a mesh is made of them, and the instance
    /// tree's search (`accel/instances.rs`) reads its hits as triangles'.
    pub fn new(mut objects: Vec<Object>) -> SharedMesh {
        objects.retain(|o| matches!(o.shape, Shape::Triangle(_)));
        let bvh = Bvh::build(&objects);
        SharedMesh { objects, bvh }
    }

    /// The same mesh, its triangles cut out where `masks[slot]` cuts them
    /// (`Bvh::with_masks`): the masks of the materials its instances give
    /// the slots, the same for all of them (`prepare` makes a mesh apart
    /// for instances whose masks differ). The brute-force reference
    /// (`Instance::intersect`) knows no masks.
    pub fn with_masks(self, masks: Vec<Option<Arc<AlphaMask>>>) -> SharedMesh {
        SharedMesh {
            bvh: self.bvh.with_masks(masks),
            ..self
        }
    }

    /// The primitives, in the mesh's coordinates.
    pub fn objects(&self) -> &[Object] {
        &self.objects
    }

    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// The smallest box holding the primitives, None for no primitive:
    /// each instance places it.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        self.bvh.bounds()
    }
}

/// One object's placement of a shared mesh.
#[derive(Debug, PartialEq)]
pub struct Instance {
    mesh: Arc<SharedMesh>,
    to_world: Placement,
    to_object: Placement,
    /// Takes the mesh's normals to the world's: the inverse transpose of
    /// the linear part, which keeps them perpendicular to the surface and
    /// on the side they pointed to, a mirroring placement included.
    normal_matrix: Mat3,
    /// The scene material of each of the mesh's material slots.
    materials: Box<[usize]>,
    /// The world box: the mesh box's corners placed, padded.
    bounds: (Vec3, Vec3),
}

/// How much an instance's world box is widened, relative to its
/// coordinates: its corners are placed in f32, and a world ray must enter
/// it wherever the ray moved into the mesh's space meets a triangle.
const INSTANCE_PAD: f32 = 256.0 * f32::EPSILON;

impl Instance {
    /// `mesh` placed by `placement`, its material slot `k` drawing scene
    /// material `materials[k]`; None when the mesh is empty, the placement
    /// cannot be undone in f32, or no material is given.
    pub fn new(
        mesh: Arc<SharedMesh>,
        placement: Placement,
        materials: Vec<usize>,
    ) -> Option<Instance> {
        let to_object = placement.inverse()?;
        let (lo, hi) = mesh.bounds()?;
        if materials.is_empty() {
            return None;
        }
        let (min, max) = placement.apply_box(lo, hi);
        let size = min.abs().max(max.abs()).max_element() + (max - min).max_element();
        let pad = Vec3::splat(size * INSTANCE_PAD);
        Some(Instance {
            mesh,
            to_world: placement,
            normal_matrix: to_object.linear().transpose(),
            to_object,
            materials: materials.into_boxed_slice(),
            bounds: (min - pad, max + pad),
        })
    }

    pub fn mesh(&self) -> &Arc<SharedMesh> {
        &self.mesh
    }

    /// The scene material of each material slot of the mesh.
    pub fn materials(&self) -> &[usize] {
        &self.materials
    }

    /// The world box, padded.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.bounds
    }

    /// The corners of the mesh's triangle `t` placed in the world, in an
    /// order whose normal (`(v1 - v0) x (v2 - v0)`) faces as this
    /// instance's hits on it do: a mirroring placement turns the vertex
    /// order, not the normals (`world_hit`).
    pub fn world_triangle(&self, t: &super::Triangle) -> [Vec3; 3] {
        let [a, b, c] = [t.v0, t.v1, t.v2].map(|v| self.to_world.apply(v));
        if self.to_world.mirrors() {
            [a, c, b]
        } else {
            [a, b, c]
        }
    }

    /// Whether the placement mirrors, so that `world_triangle` gives a
    /// triangle's corners in the order (v0, v2, v1).
    pub fn mirrors(&self) -> bool {
        self.to_world.mirrors()
    }

    /// `ray` in the mesh's coordinates; its direction keeps the scale the
    /// placement gives it, so distances `t` along both are the same.
    #[inline(always)]
    pub fn object_ray(&self, ray: &Ray) -> Ray {
        Ray::new(
            self.to_object.apply(ray.origin()),
            self.to_object.apply_vector(ray.dir()),
        )
    }

    /// The world hit of `ray` for `local`, the hit of `object_ray(ray)` on
    /// the mesh: normals placed and renormalised, the shadow offset placed
    /// (a displacement), the material slot made the scene's, `object` the
    /// instance's index; distance and uv as they are.
    pub fn world_hit(&self, ray: &Ray, local: SurfaceHit, object: usize) -> SurfaceHit {
        let placed = |n: Vec3| (self.normal_matrix * n).normalize();
        let geometric_normal = placed(local.geometric_normal);
        let shading_normal = if local.shading_normal == local.geometric_normal {
            geometric_normal
        } else {
            placed(local.shading_normal)
        };
        let material = self.materials.get(local.material);
        SurfaceHit {
            t: local.t,
            object,
            material: *material.unwrap_or(&self.materials[0]),
            geometric_normal,
            shading_normal,
            uv: local.uv,
            front_face: ray.dir().dot(geometric_normal) < 0.0,
            shadow_offset: self.to_world.apply_vector(local.shadow_offset),
            // Along the surface: placed as a direction, its handedness
            // turned by a mirroring placement.
            tangent: if local.tangent == glam::Vec4::ZERO {
                local.tangent
            } else {
                let sign = if self.to_world.mirrors() { -1.0 } else { 1.0 };
                let t = self.to_world.apply_vector(local.tangent.truncate());
                t.normalize_or_zero().extend(local.tangent.w * sign)
            },
        }
    }

    /// The nearest hit distance in (t_min, t_max), testing every triangle:
    /// the brute-force reference.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let local = self.object_ray(ray);
        brute_force::closest_hit(&self.mesh.objects, &local, t_min, t_max).map(|h| h.t)
    }

    /// The nearest hit in (t_min, t_max) as a full record, testing every
    /// triangle (ties to the mesh's first); `index` is the instance's
    /// place in the scene.
    pub fn surface_hit(
        &self,
        index: usize,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<SurfaceHit> {
        let local = self.object_ray(ray);
        let hit = brute_force::closest_hit(&self.mesh.objects, &local, t_min, t_max)?;
        Some(self.world_hit(ray, hit, index))
    }
}
