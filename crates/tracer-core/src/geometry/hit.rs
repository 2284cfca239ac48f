//! The record of a ray meeting a surface: what shading, textures and the
//! next features (glass, smooth normals) read of a hit.

use super::{Plane, Sphere, TriangleHit};
use crate::ray::Ray;
use glam::{Vec2, Vec3};

/// A ray's hit on an object's surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceHit {
    /// Distance along the ray (in units of its direction's length).
    pub t: f32,
    /// Index of the object in `Scene::objects()`.
    pub object: usize,
    /// Index of the object's material (`Scene::material(index)`).
    pub material: usize,
    /// The unit normal of the surface as the lab defines it: a triangle's
    /// from its vertex order, a sphere's outward; never flipped toward the ray.
    pub geometric_normal: Vec3,
    /// The unit normal shading uses: the geometric one, or on a smooth
    /// triangle its vertex normals interpolated (always on the geometric
    /// normal's side: the vertex normals are oriented so when prepared).
    pub shading_normal: Vec3,
    /// Surface coordinates: barycentric (u, v) on a triangle (v0 -> (0, 0),
    /// v1 -> (1, 0), v2 -> (0, 1)) unless its object maps them (a quad's or
    /// box face's half: (s, t) over the whole face); the lab's spherical
    /// mapping on a sphere; coordinates along the plane's axes on a plane.
    pub uv: Vec2,
    /// Whether the ray met the side the geometric normal points to.
    pub front_face: bool,
}

impl SurfaceHit {
    /// The hit on a sphere at distance `t` along `ray`.
    pub fn on_sphere(
        sphere: &Sphere,
        ray: &Ray,
        t: f32,
        object: usize,
        material: usize,
    ) -> SurfaceHit {
        let normal = sphere.normal(ray.at(t));
        SurfaceHit {
            t,
            object,
            material,
            geometric_normal: normal,
            shading_normal: normal,
            uv: Sphere::texture_uv(normal),
            front_face: ray.dir.dot(normal) < 0.0,
        }
    }

    /// The hit on a triangle with edges `e1 = v1 - v0`, `e2 = v2 - v0`, as
    /// Moller-Trumbore found it.
    pub fn on_triangle(
        e1: Vec3,
        e2: Vec3,
        ray: &Ray,
        hit: TriangleHit,
        object: usize,
        material: usize,
    ) -> SurfaceHit {
        // The same edges and operations as `Triangle::normal`.
        let normal = e1.cross(e2).normalize();
        SurfaceHit {
            t: hit.t,
            object,
            material,
            geometric_normal: normal,
            shading_normal: normal,
            uv: hit.uv,
            front_face: ray.dir.dot(normal) < 0.0,
        }
    }

    /// This hit on a triangle with unit vertex `normals`, at barycentric
    /// `b` (before any uv map): the shading normal interpolated from them.
    /// Where they cancel out (no direction left) the geometric one stays.
    pub fn with_vertex_normals(mut self, normals: &[Vec3; 3], b: Vec2) -> SurfaceHit {
        let n = (1.0 - b.x - b.y) * normals[0] + b.x * normals[1] + b.y * normals[2];
        if let Some(n) = n.try_normalize() {
            self.shading_normal = n;
        }
        self
    }

    /// The hit on a plane at distance `t` along `ray`.
    pub fn on_plane(
        plane: &Plane,
        ray: &Ray,
        t: f32,
        object: usize,
        material: usize,
    ) -> SurfaceHit {
        SurfaceHit {
            t,
            object,
            material,
            geometric_normal: plane.normal,
            shading_normal: plane.normal,
            uv: plane.uv(ray.at(t)),
            front_face: ray.dir.dot(plane.normal) < 0.0,
        }
    }
}
