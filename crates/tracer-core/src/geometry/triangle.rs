//! The lab's triangle (section 3): Moller-Trumbore, hit from both sides,
//! normal from the vertex order.

use crate::ray::Ray;
use crate::simd::{Real, V3};
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
        let (e1, e2, scale) = self.edges();
        let (e1, e2) = (e1.into(), e2.into());
        let terms = OriginTerms::new(ray.origin().into(), self.v0.into(), e1, e2);
        let edges = Edges { e1, e2, scale };
        let dir_len = ray.dir().length();
        let (hit, t, [u, v]) =
            moller_trumbore(&terms, ray.dir().into(), dir_len, &edges, (t_min, t_max));
        hit.then_some(TriangleHit {
            t,
            uv: Vec2::new(u, v),
        })
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

/// A triangle's edges from `v0` and the scale of its parallel test
/// (`Triangle::edges`), one per lane.
#[derive(Debug, Clone, Copy)]
pub struct Edges<N> {
    pub e1: V3<N>,
    pub e2: V3<N>,
    pub scale: N,
}

/// What Moller-Trumbore shares among rays from one origin: `s = origin -
/// v0`, `q = s x e1` and `e2 . q` (the distance times the determinant).
#[derive(Debug, Clone, Copy)]
pub struct OriginTerms<N> {
    s: V3<N>,
    q: V3<N>,
    t_times_det: N,
}

impl<N: Real> OriginTerms<N> {
    #[inline(always)]
    pub fn new(origin: V3<N>, v0: V3<N>, e1: V3<N>, e2: V3<N>) -> Self {
        let s = origin - v0;
        let q = s.cross(e1);
        OriginTerms {
            s,
            q,
            t_times_det: e2.dot(q),
        }
    }
}

/// Moller-Trumbore, two-sided, lane by lane: the rays from the origins of
/// `terms` along `dir` (of lengths `dir_len`) against the triangles of
/// `edges`, within (t_min, t_max). Which lanes hit, the distances and the
/// barycentric (u, v). The one test of every form: one ray and one
/// triangle, the BVH's four triangles against one ray (`accel/tri4.rs`),
/// and rays in lanes against one triangle.
#[inline(always)]
pub fn moller_trumbore<N: Real>(
    terms: &OriginTerms<N>,
    dir: V3<N>,
    dir_len: N,
    edges: &Edges<N>,
    (t_min, t_max): (N, N),
) -> (N::Mask, N, [N; 2]) {
    let p = dir.cross(edges.e2);
    let det = edges.e1.dot(p);
    // The ray runs parallel to the plane.
    let parallel = det.abs().lt(edges.scale * dir_len);
    let inv = N::one() / det;
    let u = terms.s.dot(p) * inv;
    let u_inside = u.ge(N::zero()) & u.le(N::one());
    let v = dir.dot(terms.q) * inv;
    let v_outside = v.lt(N::zero()) | (u + v).gt(N::one());
    let t = terms.t_times_det * inv;
    let t_inside = t.gt(t_min) & t.lt(t_max);
    (!parallel & u_inside & !v_outside & t_inside, t, [u, v])
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
