//! The lab's sphere (section 3): the quadratic, the outward normal, the
//! spherical texture mapping (section 4.5); and a sphere scaled unevenly,
//! an ellipsoid, solved as the same sphere in its own frame.

use crate::ray::Ray;
use crate::simd::{Mask, Real, V3};
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
    /// An ellipsoid: the map of world offsets from the centre to the
    /// sphere's own frame, where it is round with `radius` (the inverse of
    /// its transform's linear part); None: a round sphere.
    pub stretch: Option<Box<Mat3>>,
}

impl Sphere {
    pub fn new(center: Vec3, radius: f32) -> Self {
        Sphere {
            center,
            radius,
            texture_frame: None,
            stretch: None,
        }
    }

    /// The sphere of `radius` about the origin carried by the linear map
    /// `linear` (invertible) to `center`: an ellipsoid.
    pub fn ellipsoid(center: Vec3, radius: f32, linear: Mat3) -> Self {
        Sphere {
            stretch: Some(Box::new(linear.inverse())),
            ..Sphere::new(center, radius)
        }
    }

    /// The smallest box holding the sphere: (min, max). An ellipsoid's
    /// reach along axis i is `radius * |row i of its linear map|`, widened
    /// by a little for the rounding of the map's inverse.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let Some(stretch) = &self.stretch else {
            return (self.center - self.radius, self.center + self.radius);
        };
        let linear = stretch.inverse();
        let reach = Vec3::from_array([0, 1, 2].map(|i| linear.row(i).length()));
        let half = reach * self.radius * (1.0 + 1e-5);
        (self.center - half, self.center + half)
    }

    /// The ray's offset from the centre and its direction, in the frame
    /// where the sphere is round.
    fn own_frame(&self, ray: &Ray) -> (Vec3, Vec3) {
        let v = ray.origin() - self.center;
        match &self.stretch {
            None => (v, ray.dir()),
            Some(m) => (**m * v, **m * ray.dir()),
        }
    }

    /// The texture coordinates at surface point `p` with unit normal `n`:
    /// the lab's mapping, in the sphere's own frame when it was turned; an
    /// ellipsoid's from the direction of `p` in its round frame.
    pub fn uv(&self, p: Vec3, n: Vec3) -> Vec2 {
        if let Some(m) = &self.stretch {
            return Sphere::texture_uv((**m * (p - self.center)).normalize());
        }
        match &self.texture_frame {
            None => Sphere::texture_uv(n),
            Some(frame) => Sphere::texture_uv(**frame * n),
        }
    }

    /// The lab's quadratic (section 3): `A t^2 + B t + C = 0` with
    /// `v = origin - center`; the smallest root in (t_min, t_max).
    /// The direction need not be normalised: an ellipsoid's is not once
    /// mapped to its round frame, where the distance t stays the same.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let (v, dir) = self.own_frame(ray);
        let (v, dir) = (V3::from(v), V3::from(dir));
        let radius2 = self.radius * self.radius;
        let (hit, t) = sphere_roots(v, dir, dir.dot(dir), radius2, (t_min, t_max));
        hit.then_some(t)
    }

    /// The outward unit normal at surface point `p`; an ellipsoid's is its
    /// round frame's carried by the inverse transpose of its linear map.
    pub fn normal(&self, p: Vec3) -> Vec3 {
        match &self.stretch {
            None => (p - self.center).normalize(),
            Some(m) => (m.transpose() * (**m * (p - self.center))).normalize(),
        }
    }

    /// Spherical mapping of lab 4.5, from the unit normal.
    pub fn texture_uv(n: Vec3) -> Vec2 {
        let u = 0.5 + n.x.clamp(-1.0, 1.0).asin() / PI;
        let v = 0.5 - n.y.clamp(-1.0, 1.0).asin() / PI;
        Vec2::new(u, v)
    }
}

/// The lab's quadratic (section 3), `A t^2 + B t + C = 0`, lane by lane:
/// rays whose offsets from the centre are `v` and directions `dir` (`a =
/// dir . dir`, the direction need not be unit) against spheres of squared
/// radius `radius2`. Which lanes meet one, and the smaller root in
/// (t_min, t_max) (else the larger). The one sphere test of every form.
#[inline(always)]
pub fn sphere_roots<N: Real>(
    v: V3<N>,
    dir: V3<N>,
    a: N,
    radius2: N,
    (t_min, t_max): (N, N),
) -> (N::Mask, N) {
    let b = N::splat(2.0) * v.dot(dir);
    let c = v.dot(v) - radius2;
    let discriminant = b * b - N::splat(4.0) * a * c;
    let real = !discriminant.lt(N::zero());
    if real.none() {
        return (real, N::zero());
    }
    let root = discriminant.sqrt();
    let near = (-b - root) / (N::splat(2.0) * a);
    let far = (-b + root) / (N::splat(2.0) * a);
    let near_in = near.gt(t_min) & near.lt(t_max);
    let far_in = far.gt(t_min) & far.lt(t_max);
    (real & (near_in | far_in), N::select(near_in, near, far))
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

    /// Semi-axes 3, 1, 2 along x, y, z, then turned 30 degrees about z.
    fn ellipsoid() -> (Sphere, Mat3) {
        let linear = Mat3::from_rotation_z(30f32.to_radians())
            * Mat3::from_diagonal(Vec3::new(3.0, 1.0, 2.0));
        (
            Sphere::ellipsoid(Vec3::new(1.0, 2.0, 3.0), 1.0, linear),
            linear,
        )
    }

    #[test]
    fn an_ellipsoid_s_hits_lie_on_it_with_the_gradient_as_normal() {
        let (e, linear) = ellipsoid();
        let inverse = linear.inverse();
        // The implicit f(p) = |A^-1 (p - c)|^2 - 1; its gradient is normal.
        let f = |p: Vec3| (inverse * (p - e.center)).length_squared() - 1.0;
        let mut hits = 0;
        for k in 0..400 {
            let a = k as f32 * 0.37;
            let origin = e.center + Vec3::new(8.0 * a.cos(), 8.0 * a.sin(), 5.0 * (a * 0.3).sin());
            let target =
                e.center + Vec3::new((a * 1.7).sin(), (a * 2.3).cos(), (a * 0.9).sin()) * 2.0;
            let ray = Ray::new(origin, target - origin);
            let Some(t) = e.intersect(&ray, 0.0, f32::INFINITY) else {
                continue;
            };
            hits += 1;
            let p = ray.at(t);
            assert!(f(p).abs() < 1e-4, "f = {}", f(p));
            let h = 1e-3;
            let gradient = Vec3::new(
                f(p + Vec3::X * h) - f(p - Vec3::X * h),
                f(p + Vec3::Y * h) - f(p - Vec3::Y * h),
                f(p + Vec3::Z * h) - f(p - Vec3::Z * h),
            )
            .normalize();
            assert!(
                e.normal(p).dot(gradient) > 0.9999,
                "{} vs {gradient}",
                e.normal(p)
            );
            // uv: the lab's mapping of the round frame's direction.
            let round = (inverse * (p - e.center)).normalize();
            assert_eq!(e.uv(p, e.normal(p)), Sphere::texture_uv(round));
        }
        assert!(hits > 200, "{hits} hits");
    }

    #[test]
    fn an_ellipsoid_s_box_is_tight() {
        let (e, linear) = ellipsoid();
        let (lo, hi) = e.bounds();
        let (mut seen_lo, mut seen_hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for i in 0..200 {
            for j in 0..400 {
                let (theta, phi) = (PI * i as f32 / 199.0, 2.0 * PI * j as f32 / 400.0);
                let q = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                let p = e.center + linear * q;
                assert!(
                    p.cmpge(lo).all() && p.cmple(hi).all(),
                    "{p} outside {lo}..{hi}"
                );
                (seen_lo, seen_hi) = (seen_lo.min(p), seen_hi.max(p));
            }
        }
        assert!((seen_lo - lo).abs().max_element() < 1e-3);
        assert!((seen_hi - hi).abs().max_element() < 1e-3);
    }
}
