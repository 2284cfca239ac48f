//! The lab's triangle (section 3): Moller-Trumbore, hit from both sides,
//! normal from the vertex order.

use crate::ray::Ray;
use glam::{Vec2, Vec3};

/// Three vertices, in the lab's clockwise order.
#[derive(Debug, Clone, PartialEq)]
pub struct Triangle {
    pub v0: Vec3,
    pub v1: Vec3,
    pub v2: Vec3,
}

impl Triangle {
    pub fn new(v0: Vec3, v1: Vec3, v2: Vec3) -> Self {
        Triangle { v0, v1, v2 }
    }

    /// Moller-Trumbore, two-sided: a triangle seen from behind is still
    /// hit (and still casts its shadow), unlike GLM's front-face-only test.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<TriangleHit> {
        let (e1, e2, edge_scale) = self.edges();
        moller_trumbore(
            self.v0,
            e1,
            e2,
            edge_scale,
            ray,
            ray.dir().length(),
            t_min,
            t_max,
        )
    }

    /// The edges from `v0` and the scale of the parallel test,
    /// `EPSILON * |e1| * |e2|`: what `intersect` computes, and what the BVH
    /// precomputes to find the same distances.
    pub(crate) fn edges(&self) -> (Vec3, Vec3, f32) {
        let (e1, e2) = (self.v1 - self.v0, self.v2 - self.v0);
        (e1, e2, f32::EPSILON * e1.length() * e2.length())
    }

    /// The lab's normal, from the vertex order: never flipped toward the viewer.
    pub fn normal(&self) -> Vec3 {
        (self.v1 - self.v0).cross(self.v2 - self.v0).normalize()
    }
}

/// Where a ray meets a triangle: the distance and the barycentric (u, v) of
/// the point, `v0 + u (v1 - v0) + v (v2 - v0)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangleHit {
    pub t: f32,
    pub uv: Vec2,
}

/// Moller-Trumbore on the edges `e1 = v1 - v0`, `e2 = v2 - v0` and
/// `edge_scale = EPSILON * |e1| * |e2|` (`Triangle::edges`) and
/// `dir_len = |ray.dir|`. The BVH's four-lane test (`bvh/tri4.rs`) does the
/// same operations in the same order.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn moller_trumbore(
    v0: Vec3,
    e1: Vec3,
    e2: Vec3,
    edge_scale: f32,
    ray: &Ray,
    dir_len: f32,
    t_min: f32,
    t_max: f32,
) -> Option<TriangleHit> {
    let p = ray.dir().cross(e2);
    let det = e1.dot(p);
    if det.abs() < edge_scale * dir_len {
        return None; // the ray runs parallel to the plane
    }
    let inv = 1.0 / det;
    let s = ray.origin() - v0;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = ray.dir().dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t > t_min && t < t_max).then_some(TriangleHit {
        t,
        uv: Vec2::new(u, v),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wall() -> Triangle {
        // Table 1.2's triangle.
        Triangle::new(
            Vec3::new(3.0, 3.0, -5.0),
            Vec3::new(-3.0, 3.0, -10.0),
            Vec3::new(-3.0, -3.0, -8.0),
        )
    }

    #[test]
    fn hit_from_both_sides() {
        let t = wall();
        let centroid = (t.v0 + t.v1 + t.v2) / 3.0;
        let front = Ray::new(
            Vec3::new(0.0, 0.0, 10.0),
            centroid - Vec3::new(0.0, 0.0, 10.0),
        );
        let back = Ray::new(centroid * 2.0 - front.origin(), front.origin() - centroid);
        let tf = t
            .intersect(&front, 0.0, f32::INFINITY)
            .expect("front hit")
            .t;
        let tb = t.intersect(&back, 0.0, f32::INFINITY).expect("back hit").t;
        assert!((front.at(tf) - centroid).length() < 1e-4);
        assert!((back.at(tb) - centroid).length() < 1e-4);
    }

    #[test]
    fn outside_the_edges_is_a_miss() {
        let t = wall();
        let ray = Ray::new(Vec3::new(0.0, 0.0, 10.0), Vec3::new(0.5, -0.5, -1.0));
        assert_eq!(t.intersect(&ray, 0.0, f32::INFINITY), None);
    }

    #[test]
    fn normal_follows_the_vertex_order() {
        let t = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
        assert_eq!(t.normal(), Vec3::Z);
        let flipped = Triangle::new(Vec3::ZERO, Vec3::Y, Vec3::X);
        assert_eq!(flipped.normal(), -Vec3::Z);
    }

    #[test]
    fn barycentric_uv_rebuilds_the_hit_point() {
        let t = wall();
        let eye = Vec3::new(0.0, 0.0, 10.0);
        // Points with known weights: near each vertex, and one inside.
        for (u, v) in [(0.01, 0.01), (0.98, 0.01), (0.01, 0.98), (0.25, 0.5)] {
            let p = t.v0 + u * (t.v1 - t.v0) + v * (t.v2 - t.v0);
            let hit = t.intersect(&Ray::new(eye, p - eye), 0.0, f32::INFINITY);
            let hit = hit.expect("a hit");
            assert!((hit.uv - Vec2::new(u, v)).length() < 1e-4, "{:?}", hit.uv);
        }
    }
}
