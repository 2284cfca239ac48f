//! The lab's triangle (section 3): Moller-Trumbore, hit from both sides,
//! normal from the vertex order.

use crate::ray::Ray;
use crate::simd::{Mask, Real, V3};
use glam::{Vec2, Vec3};

/// Three vertices, in the lab's clockwise order.
#[derive(Debug, Clone, PartialEq)]
pub struct Triangle {
    pub v0: Vec3,
    pub v1: Vec3,
    pub v2: Vec3,
    /// Whether the edge from `v1` to `v2` is a quad's diagonal, which its
    /// other half has as its own `v1` to `v2` edge (`prepare`'s quads and
    /// boxes): a ray on it is found by at least one half (`moller_trumbore`).
    pub shared_diagonal: bool,
}

impl Triangle {
    pub fn new(v0: Vec3, v1: Vec3, v2: Vec3) -> Self {
        Triangle {
            v0,
            v1,
            v2,
            shared_diagonal: false,
        }
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
    /// precomputes to find the same distances. The scale is negative for
    /// a `shared_diagonal`: so every form of the test (the BVH's blocks, the
    /// lanes), which keeps only the edges and the scale, knows it.
    pub(crate) fn edges(&self) -> (Vec3, Vec3, f32) {
        let (e1, e2) = (self.v1 - self.v0, self.v2 - self.v0);
        let scale = f32::EPSILON * e1.length() * e2.length();
        (e1, e2, if self.shared_diagonal { -scale } else { scale })
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
    /// Its size scales the parallel test; negative where the `v1` to `v2`
    /// edge is a `Triangle::shared_diagonal`.
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
    let parallel = det.abs().lt(edges.scale.abs() * dir_len);
    let inv = N::one() / det;
    let u = terms.s.dot(p) * inv;
    let u_inside = u.ge(N::zero()) & u.le(N::one());
    let v = dir.dot(terms.q) * inv;
    let v_outside = v.lt(N::zero()) | (u + v).gt(N::one());
    let t = terms.t_times_det * inv;
    let t_inside = t.gt(t_min) & t.lt(t_max);
    let hit = !parallel & u_inside & !v_outside & t_inside;
    // On a quad's diagonal u + v is 1, which rounding can make a little
    // more in both halves: a crack. Just past a shared diagonal, a ray gets
    // a second look, which forgives u + v its rounding error; every other
    // ray keeps the answer it had, bit for bit.
    let shared = edges.scale.lt(N::zero());
    if shared.none() {
        return (hit, t, [u, v]);
    }
    let past_diagonal = shared
        & !hit
        & !parallel
        & t_inside
        & u.ge(N::zero())
        & v.ge(N::zero())
        & (u + v).le(N::splat(1.0 + 2.0 * DIAGONAL_BAND));
    if past_diagonal.none() {
        return (hit, t, [u, v]);
    }
    let slack = rounding_bound(terms, dir_len, edges, det);
    // A tie with the other half, which found the ray itself, goes to the
    // other half: its distance is a few ulps from this one's.
    let nudged = t * (1.0 + TIE_NUDGE);
    let on_diagonal = past_diagonal & (u + v).le(N::one() + slack + slack) & nudged.lt(t_max);
    (hit | on_diagonal, N::select(on_diagonal, nudged, t), [u, v])
}

/// How far past a shared diagonal (in barycentric units) a miss gets
/// `rounding_bound`'s second look: far more than the bound, unless the
/// triangle is tiny against its distance from the ray's origin.
const DIAGONAL_BAND: f32 = 1.0 / 256.0;

/// How far rounding can move Moller-Trumbore's barycentrics, in their
/// units: the errors of `s`, of the cross and dot products and of the
/// division by `det` are each a few epsilons of the terms' sizes, which
/// `|dir| L (|s| + L) / |det|` bounds, L the longer edge. One epsilon of
/// it: about three times what the worst of a million rays at the
/// diagonals of random quads needed.
#[inline(always)]
fn rounding_bound<N: Real>(terms: &OriginTerms<N>, dir_len: N, edges: &Edges<N>, det: N) -> N {
    let (e1, e2) = (edges.e1.length_squared(), edges.e2.length_squared());
    let longest = e1.max(e2).sqrt();
    let size = dir_len * longest * (terms.s.length() + longest);
    size * f32::EPSILON / det.abs()
}

/// A second look's hit is reported this much (relatively) farther than
/// it is: 64 ulps, more than the halves' distances differ by, and so
/// little behind the surface that a shadow ray's start (`EPSILON`, 1e-4)
/// covers it within 13 units.
const TIE_NUDGE: f32 = 1.0 / 131_072.0;

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

    /// The first half of the quad (-1, -1, 0) + s (2, 0, 0) + t (0, 2, 0),
    /// its diagonal from (1, -1, 0) to (-1, 1, 0) shared or not.
    fn half_quad(shared_diagonal: bool) -> Triangle {
        let corner = Vec3::new(-1.0, -1.0, 0.0);
        Triangle {
            shared_diagonal,
            ..Triangle::new(corner, corner + 2.0 * Vec3::X, corner + 2.0 * Vec3::Y)
        }
    }

    /// A ray from (0.3, -0.7, 7) to the diagonal's point at `k / 1024`,
    /// moved by `off` along (1, 1, 0), off the triangle for `off` > 0.
    fn toward_diagonal(k: u32, off: f32) -> Ray {
        let s = k as f32 / 1024.0;
        let p = Vec3::new(1.0 - 2.0 * s + off, -1.0 + 2.0 * s + off, 0.0);
        let origin = Vec3::new(0.3, -0.7, 7.0);
        Ray::new(origin, p - origin)
    }

    #[test]
    fn a_shared_diagonal_forgives_rounding_and_no_more() {
        let (plain, shared) = (half_quad(false), half_quad(true));
        let mut rounded_off = 0;
        for k in 1..1024 {
            let ray = toward_diagonal(k, 0.0);
            let hit = shared.intersect(&ray, 0.0, f32::INFINITY);
            assert!(hit.is_some(), "point {k} of the diagonal");
            match plain.intersect(&ray, 0.0, f32::INFINITY) {
                // Found by the first look: the same distance, bit for bit.
                Some(first) => assert_eq!(hit, Some(first)),
                // Found by the second: reported a hair farther.
                None => {
                    rounded_off += 1;
                    let t = hit.unwrap().t;
                    assert!(t > 1.0 && t < 1.0 + 1e-5, "{t}");
                }
            }
            // A millionth of the quad past the diagonal is off the triangle.
            let past = toward_diagonal(k, 2e-6);
            assert_eq!(shared.intersect(&past, 0.0, f32::INFINITY), None, "{k}");
        }
        // Rounding put some points of the diagonal off the plain triangle.
        assert!(rounded_off > 10, "{rounded_off}");
    }

    #[test]
    fn a_shared_diagonal_leaves_the_other_edges_as_they_were() {
        let (plain, shared) = (half_quad(false), half_quad(true));
        let origin = Vec3::new(0.3, -0.7, 7.0);
        // Along the edges u = 0 and v = 0 (short of the diagonal's ends),
        // and past them by a hair.
        for k in 0..1024 {
            let s = k as f32 / 512.0 - 1.0;
            for p in [
                Vec3::new(-1.0, s, 0.0),
                Vec3::new(s, -1.0, 0.0),
                Vec3::new(-1.0 - 1e-7, s, 0.0),
                Vec3::new(s, -1.0 - 1e-7, 0.0),
            ] {
                let ray = Ray::new(origin, p - origin);
                assert_eq!(
                    shared.intersect(&ray, 0.0, f32::INFINITY),
                    plain.intersect(&ray, 0.0, f32::INFINITY),
                    "{p}"
                );
            }
        }
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
