//! The shapes a ray can hit, and an object: a shape with its material.

use super::{Instance, Plane, Sphere, SurfaceHit, Triangle};
use crate::ray::Ray;
use glam::{Vec2, Vec3, Vec4};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// One primitive of the scene. A mesh is many triangles, each its own
/// shape; so are quads and boxes (two triangles per face, see `prepare`).
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    Sphere(Sphere),
    Triangle(Triangle),
    /// Infinite: it has no bounds, so the BVH tests it beside its tree.
    /// Boxed, as the sphere's texture frame: a mesh's million triangles
    /// would each pay the largest shape's size.
    Plane(Box<Plane>),
    /// A shared mesh placed by one object (`geometry::instance`): behind a
    /// pointer, as the plane, and shared with the BVH's leaves.
    Instance(Arc<Instance>),
}

/// What a triangle's barycentric (u, v) becomes as the hit's uv:
/// `origin + u * du + v * dv`. The identity for a plain triangle; a quad's
/// second half maps its barycentrics back onto the quad's (s, t).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct UvMap {
    pub origin: Vec2,
    pub du: Vec2,
    pub dv: Vec2,
}

impl UvMap {
    pub const IDENTITY: UvMap = UvMap {
        origin: Vec2::ZERO,
        du: Vec2::X,
        dv: Vec2::Y,
    };

    pub fn apply(&self, uv: Vec2) -> Vec2 {
        self.origin + uv.x * self.du + uv.y * self.dv
    }
}

impl Default for UvMap {
    fn default() -> Self {
        UvMap::IDENTITY
    }
}

/// A shape, the index of its material (`Scene::material(index)`), the
/// map of a triangle's barycentrics to its uv, and a triangle's unit vertex
/// normals for smooth shading (the last two ignored by other shapes).
#[derive(Debug, Clone, PartialEq)]
pub struct Object {
    pub shape: Shape,
    pub material: usize,
    /// None for the identity (most triangles): boxed, so that an object of
    /// a million-triangle mesh takes 72 bytes, not 96.
    pub uv: Option<Box<UvMap>>,
    /// Unit normals at `v0`, `v1`, `v2`, on the side of the triangle's own
    /// normal; None shades the triangle flat. Boxed: most objects have none.
    pub vertex_normals: Option<Box<[Vec3; 3]>>,
    /// Tangents at `v0`, `v1`, `v2` (`SurfaceHit::tangent`), for a normal
    /// texture; None for most triangles.
    pub tangents: Option<Box<[Vec4; 3]>>,
}

impl Shape {
    /// The nearest hit distance in (t_min, t_max), if any.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        match self {
            Shape::Sphere(s) => s.intersect(ray, t_min, t_max),
            Shape::Triangle(t) => t.intersect(ray, t_min, t_max).map(|hit| hit.t),
            Shape::Plane(p) => p.intersect(ray, t_min, t_max),
            Shape::Instance(i) => i.intersect(ray, t_min, t_max),
        }
    }

    /// The unit normal at surface point `p`, as the lab defines it; zero on
    /// an instance, which has many (its hits carry theirs).
    pub fn normal(&self, p: Vec3) -> Vec3 {
        match self {
            Shape::Sphere(s) => s.normal(p),
            Shape::Triangle(t) => t.normal(),
            Shape::Plane(plane) => plane.normal,
            Shape::Instance(_) => Vec3::ZERO,
        }
    }

    /// The smallest box holding the shape: (min, max); None for a plane;
    /// an instance's padded world box.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        match self {
            Shape::Sphere(s) => Some(s.bounds()),
            Shape::Triangle(t) => Some((t.v0.min(t.v1).min(t.v2), t.v0.max(t.v1).max(t.v2))),
            Shape::Plane(_) => None,
            Shape::Instance(i) => Some(i.bounds()),
        }
    }
}

impl Object {
    /// A shape with its material and the identity uv map.
    pub fn new(shape: Shape, material: usize) -> Object {
        Object {
            shape,
            material,
            uv: None,
            vertex_normals: None,
            tangents: None,
        }
    }

    /// The same object with the uv map `uv`.
    pub fn with_uv(self, uv: UvMap) -> Object {
        Object {
            uv: (uv != UvMap::IDENTITY).then(|| Box::new(uv)),
            ..self
        }
    }

    /// The map of a triangle's barycentrics to its uv.
    pub fn uv_map(&self) -> UvMap {
        self.uv.as_deref().copied().unwrap_or(UvMap::IDENTITY)
    }

    /// The nearest hit on this object in (t_min, t_max), as a full record;
    /// `index` is the object's place in the scene.
    pub fn surface_hit(
        &self,
        index: usize,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<SurfaceHit> {
        match &self.shape {
            Shape::Sphere(s) => {
                let t = s.intersect(ray, t_min, t_max)?;
                Some(SurfaceHit::on_sphere(
                    s,
                    ray,
                    t,
                    (index, self.material),
                    true,
                ))
            }
            Shape::Triangle(tri) => {
                let mut hit = tri.intersect(ray, t_min, t_max)?;
                let barycentric = hit.uv;
                hit.uv = self.uv_map().apply(hit.uv);
                let (e1, e2, _) = tri.edges();
                let surface = SurfaceHit::on_triangle(e1, e2, ray, hit, index, self.material);
                let surface = match &self.vertex_normals {
                    Some(normals) => {
                        surface.with_vertex_normals(ray, [tri.v0, e1, e2], normals, barycentric)
                    }
                    None => surface,
                };
                Some(match &self.tangents {
                    Some(tangents) => surface.with_tangents(tangents, barycentric),
                    None => surface,
                })
            }
            Shape::Plane(p) => {
                let t = p.intersect(ray, t_min, t_max)?;
                Some(SurfaceHit::on_plane(p, ray, t, index, self.material))
            }
            Shape::Instance(i) => i.surface_hit(index, ray, t_min, t_max),
        }
    }
}
