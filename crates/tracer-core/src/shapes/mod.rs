//! The shapes a ray can hit.

pub mod mesh;
mod sphere;
mod triangle;

pub use sphere::Sphere;
pub use triangle::Triangle;

use crate::ray::Ray;
use glam::{Vec2, Vec3};

#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    Sphere(Sphere),
    Triangle(Triangle),
}

impl Shape {
    /// The nearest hit distance in (t_min, t_max), if any.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        match self {
            Shape::Sphere(s) => s.intersect(ray, t_min, t_max),
            Shape::Triangle(t) => t.intersect(ray, t_min, t_max),
        }
    }

    /// The unit normal at surface point `p`, as the lab defines it.
    pub fn normal(&self, p: Vec3) -> Vec3 {
        match self {
            Shape::Sphere(s) => s.normal(p),
            Shape::Triangle(t) => t.normal(),
        }
    }

    /// Texture coordinates of surface point `p` with unit normal `n`.
    pub fn texture_uv(&self, p: Vec3, n: Vec3) -> Vec2 {
        match self {
            Shape::Sphere(_) => Sphere::texture_uv(n),
            Shape::Triangle(t) => t.texture_uv(p),
        }
    }
}
