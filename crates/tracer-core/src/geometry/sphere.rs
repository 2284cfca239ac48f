//! The lab's sphere (section 3): the quadratic, the outward normal, the
//! spherical texture mapping (section 4.5).

use crate::ray::Ray;
use glam::{Mat3, Vec2, Vec3};
use serde::{Deserialize, Serialize};
use std::f32::consts::PI;

/// A sphere: centre and radius, and the turn its texture was given.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
    /// From world directions to the texture's own (a rotated sphere's
    /// texture turns with it); None: the lab's, world axes.
    pub texture_frame: Option<Box<Mat3>>,
}

impl Sphere {
    pub fn new(center: Vec3, radius: f32) -> Self {
        Sphere {
            center,
            radius,
            texture_frame: None,
        }
    }

    /// The texture coordinates at unit normal `n`: the lab's mapping, in
    /// the sphere's own frame when it was turned.
    pub fn uv(&self, n: Vec3) -> Vec2 {
        match &self.texture_frame {
            None => Sphere::texture_uv(n),
            Some(frame) => Sphere::texture_uv(**frame * n),
        }
    }

    /// The lab's quadratic (section 3): `A t^2 + B t + C = 0` with
    /// `v = origin - center`; the smallest root in (t_min, t_max).
    /// The direction need not be normalised.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let v = ray.origin() - self.center;
        let a = ray.dir().dot(ray.dir());
        let b = 2.0 * v.dot(ray.dir());
        let c = v.dot(v) - self.radius * self.radius;
        let discriminant = b * b - 4.0 * a * c;
        if discriminant < 0.0 {
            return None;
        }
        let root = discriminant.sqrt();
        [(-b - root) / (2.0 * a), (-b + root) / (2.0 * a)]
            .into_iter()
            .find(|&t| t > t_min && t < t_max)
    }

    pub fn normal(&self, p: Vec3) -> Vec3 {
        (p - self.center).normalize()
    }

    /// Spherical mapping of lab 4.5, from the unit normal.
    pub fn texture_uv(n: Vec3) -> Vec2 {
        let u = 0.5 + n.x.clamp(-1.0, 1.0).asin() / PI;
        let v = 0.5 - n.y.clamp(-1.0, 1.0).asin() / PI;
        Vec2::new(u, v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lab_check_t_is_5_6() {
        let sphere = Sphere::new(Vec3::ZERO, 5.0);
        let ray = Ray::new(Vec3::new(0.0, 0.0, 10.0), Vec3::new(0.3, 0.3, -1.0));
        let t = sphere.intersect(&ray, 0.0, f32::INFINITY).expect("a hit");
        assert!((t - 5.6).abs() <= 0.05, "t = {t}");
    }

    #[test]
    fn from_inside_the_far_root_is_taken() {
        let sphere = Sphere::new(Vec3::ZERO, 2.0);
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        assert_eq!(sphere.intersect(&ray, 0.0, f32::INFINITY), Some(2.0));
    }

    #[test]
    fn behind_and_beside_are_misses() {
        let sphere = Sphere::new(Vec3::ZERO, 1.0);
        let behind = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::Z);
        let beside = Ray::new(Vec3::new(3.0, 0.0, 5.0), -Vec3::Z);
        assert_eq!(sphere.intersect(&behind, 0.0, f32::INFINITY), None);
        assert_eq!(sphere.intersect(&beside, 0.0, f32::INFINITY), None);
    }

    #[test]
    fn texture_uv_at_the_poles_and_front() {
        assert_eq!(Sphere::texture_uv(Vec3::Z), Vec2::new(0.5, 0.5));
        assert!((Sphere::texture_uv(Vec3::Y).y - 0.0).abs() < 1e-6);
        assert!((Sphere::texture_uv(-Vec3::Y).y - 1.0).abs() < 1e-6);
        assert!((Sphere::texture_uv(Vec3::X).x - 1.0).abs() < 1e-6);
    }
}
