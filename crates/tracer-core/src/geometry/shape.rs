//! The shapes a ray can hit, and an object: a shape with its material.

use super::{Sphere, SurfaceHit, Triangle};
use crate::ray::Ray;
use glam::Vec3;

/// One primitive of the scene. A mesh is many triangles, each its own shape.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    Sphere(Sphere),
    Triangle(Triangle),
}

/// A shape and the index of its material (`Scene::material(index)`).
#[derive(Debug, Clone, PartialEq)]
pub struct Object {
    pub shape: Shape,
    pub material: usize,
}

impl Shape {
    /// The nearest hit distance in (t_min, t_max), if any.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        match self {
            Shape::Sphere(s) => s.intersect(ray, t_min, t_max),
            Shape::Triangle(t) => t.intersect(ray, t_min, t_max).map(|hit| hit.t),
        }
    }

    /// The unit normal at surface point `p`, as the lab defines it.
    pub fn normal(&self, p: Vec3) -> Vec3 {
        match self {
            Shape::Sphere(s) => s.normal(p),
            Shape::Triangle(t) => t.normal(),
        }
    }

    /// The smallest box holding the shape: (min, max).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        match self {
            Shape::Sphere(s) => (s.center - s.radius, s.center + s.radius),
            Shape::Triangle(t) => (t.v0.min(t.v1).min(t.v2), t.v0.max(t.v1).max(t.v2)),
        }
    }
}

impl Object {
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
                Some(SurfaceHit::on_sphere(s, ray, t, index, self.material))
            }
            Shape::Triangle(tri) => {
                let hit = tri.intersect(ray, t_min, t_max)?;
                let (e1, e2, _) = tri.edges();
                Some(SurfaceHit::on_triangle(
                    e1,
                    e2,
                    ray,
                    hit,
                    index,
                    self.material,
                ))
            }
        }
    }
}
