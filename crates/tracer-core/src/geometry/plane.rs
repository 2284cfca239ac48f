//! An infinite plane: a point and a unit normal, with uv measured along two
//! axes in the plane (unit scale), so textures tile it.

use super::Placement;
use crate::ray::Ray;
use crate::simd::{Real, V3};
use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

/// A plane through `point` with unit normal `normal`; a point's uv is its
/// offset from `point` dotted with `u_axis` and `v_axis`. Those are unit
/// vectors in the plane with `u_axis x v_axis = normal`, unless the plane
/// was placed by a transform: then they are what keeps each point's uv.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Plane {
    pub point: Vec3,
    pub normal: Vec3,
    pub u_axis: Vec3,
    pub v_axis: Vec3,
}

impl Plane {
    /// The plane through `point` facing `normal` (any non-zero length).
    /// u runs along world x projected into the plane (along y when the
    /// plane is nearly perpendicular to x), v = normal x u: a floor
    /// (normal +y) gets u = +x, v = -z; a wall facing +z gets u = +x, v = +y.
    pub fn new(point: Vec3, normal: Vec3) -> Plane {
        let normal = normal.normalize();
        let reference = if normal.x.abs() < 0.9 {
            Vec3::X
        } else {
            Vec3::Y
        };
        let u_axis = (reference - normal * normal.dot(reference)).normalize();
        let v_axis = normal.cross(u_axis);
        Plane {
            point,
            normal,
            u_axis,
            v_axis,
        }
    }

    /// The plane carried by `placement`, its uv carried along: a placed
    /// point has the uv it had (textures stretch and turn with the plane).
    pub fn placed(&self, placement: &Placement) -> Plane {
        let u = placement.apply_vector(self.u_axis);
        let v = placement.apply_vector(self.v_axis);
        // The dual basis of (u, v) in the placed plane: u* . u = 1,
        // u* . v = 0 and the other way round.
        let n = u.cross(v);
        let n2 = n.length_squared();
        Plane {
            point: placement.apply(self.point),
            normal: placement.apply_normal(self.normal),
            u_axis: v.cross(n) / n2,
            v_axis: n.cross(u) / n2,
        }
    }

    /// The distance in (t_min, t_max) where the ray crosses the plane; a
    /// ray in the plane or parallel to it misses (as a triangle's edge-on
    /// ray does).
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let (origin, dir) = (ray.origin().into(), ray.dir().into());
        let at = (self.point.into(), self.normal.into());
        let (hit, t) = plane_distance(at, origin, dir, ray.dir().length(), (t_min, t_max));
        hit.then_some(t)
    }

    /// Coordinates of `p` (a point on the plane) along `u_axis` and `v_axis`
    /// from `point`.
    pub fn uv(&self, p: Vec3) -> Vec2 {
        let d = p - self.point;
        Vec2::new(d.dot(self.u_axis), d.dot(self.v_axis))
    }
}

/// Where rays from `origin` along `dir` (of lengths `dir_len`) cross the
/// planes through `point` with unit `normal`, lane by lane: which cross
/// within (t_min, t_max), and where. A ray in the plane or parallel to it
/// misses (as a triangle's edge-on ray does). The one plane test of every
/// form.
#[inline(always)]
pub fn plane_distance<N: Real>(
    (point, normal): (V3<N>, V3<N>),
    origin: V3<N>,
    dir: V3<N>,
    dir_len: N,
    (t_min, t_max): (N, N),
) -> (N::Mask, N) {
    let denom = normal.dot(dir);
    let crossing = !denom.abs().le(N::splat(f32::EPSILON) * dir_len);
    let t = normal.dot(point - origin) / denom;
    (crossing & t.gt(t_min) & t.lt(t_max), t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_floor_is_hit_at_the_analytic_distance_and_uv() {
        let floor = Plane::new(Vec3::new(0.0, -1.0, 0.0), Vec3::new(0.0, 3.0, 0.0));
        assert_eq!(floor.normal, Vec3::Y);
        // From (2, 3, 5) toward (0, -1, 0) direction (-1, -2, -2.5): y falls by
        // 4 at t = 2, the point (0, -1, 0).
        let ray = Ray::new(Vec3::new(2.0, 3.0, 5.0), Vec3::new(-1.0, -2.0, -2.5));
        let t = floor.intersect(&ray, 0.0, f32::INFINITY).expect("a hit");
        assert!((t - 2.0).abs() < 1e-6, "{t}");
        // u = +x, v = -z from the plane's point.
        let p = Vec3::new(1.5, -1.0, -0.25);
        assert!((floor.uv(p) - Vec2::new(1.5, 0.25)).length() < 1e-6);
        assert_eq!(floor.u_axis.cross(floor.v_axis), floor.normal);
    }

    #[test]
    fn a_placed_plane_keeps_each_points_uv() {
        let floor = Plane::new(Vec3::ZERO, Vec3::Y);
        // Stretched along x, sheared by a turn about z, moved.
        let stretch = Placement::new(Vec3::new(3.0, 1.0, 0.5), Vec3::ZERO, Vec3::ZERO);
        let turn = Placement::new(
            Vec3::ONE,
            Vec3::new(10.0, 0.0, 30.0),
            Vec3::new(1.0, 2.0, 3.0),
        );
        let placement = turn.compose(&stretch);
        let placed = floor.placed(&placement);
        for p in [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(-2.0, 0.0, 0.7),
            Vec3::ZERO,
        ] {
            let q = placement.apply(p);
            let ray = Ray::new(q + placed.normal * 2.0, -placed.normal);
            let t = placed.intersect(&ray, 0.0, f32::INFINITY).expect("a hit");
            assert!((t - 2.0).abs() < 1e-5, "{t}");
            assert!((placed.uv(q) - floor.uv(p)).length() < 1e-5, "{p}");
        }
    }

    #[test]
    fn parallel_and_behind_are_misses() {
        let wall = Plane::new(Vec3::ZERO, Vec3::Z);
        let along = Ray::new(Vec3::new(0.0, 0.0, 1.0), Vec3::X);
        let away = Ray::new(Vec3::new(0.0, 0.0, 1.0), Vec3::Z);
        assert_eq!(wall.intersect(&along, 0.0, f32::INFINITY), None);
        assert_eq!(wall.intersect(&away, 0.0, f32::INFINITY), None);
        let toward = Ray::new(Vec3::new(0.0, 0.0, 1.0), -Vec3::Z);
        assert_eq!(wall.intersect(&toward, 0.0, 0.5), None);
        assert_eq!(wall.intersect(&toward, 0.0, 2.0), Some(1.0));
    }

    #[test]
    fn axes_are_orthonormal_for_any_normal() {
        for n in [
            Vec3::X,
            -Vec3::X,
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(0.95, 0.1, 0.0),
        ] {
            let p = Plane::new(Vec3::ZERO, n);
            assert!(p.u_axis.dot(p.normal).abs() < 1e-6);
            assert!((p.u_axis.length() - 1.0).abs() < 1e-6);
            assert!((p.u_axis.cross(p.v_axis) - p.normal).length() < 1e-6);
        }
    }
}
