//! Four triangles tested at once, one per SIMD lane: `moller_trumbore`
//! in four lanes, so every distance is the one the scalar test finds.

use crate::geometry::{moller_trumbore, Edges, OriginTerms, SurfaceHit, TriangleHit};
use crate::ray::Ray;
use crate::simd::V3;
use glam::{Vec2, Vec3, Vec4};

/// One triangle as the test needs it: `e1 = v1 - v0`, `e2 = v2 - v0`,
/// `edge_scale = EPSILON * |e1| * |e2|`.
#[derive(Debug, Clone, Copy)]
pub(super) struct TriRecord {
    pub(super) v0: Vec3,
    pub(super) e1: Vec3,
    pub(super) e2: Vec3,
    pub(super) edge_scale: f32,
    pub(super) id: u32,
    pub(super) material: u32,
}

/// Up to four triangles, coordinates by lane; 192 bytes, three cache lines.
/// An unused lane has zero edges and an infinite `edge_scale`: every ray
/// runs "parallel" to it.
#[repr(C, align(64))]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct Tri4 {
    v0: [Vec4; 3],
    e1: [Vec4; 3],
    e2: [Vec4; 3],
    edge_scale: Vec4,
    pub(super) id: [u32; 4],
    material: [u32; 4],
}

/// The ray in every lane.
pub(super) struct Ray4 {
    origin: [Vec4; 3],
    dir: [Vec4; 3],
    dir_len: Vec4,
}

impl Ray4 {
    pub(super) fn new(ray: &Ray) -> Ray4 {
        Ray4 {
            origin: ray.origin().to_array().map(Vec4::splat),
            dir: ray.dir().to_array().map(Vec4::splat),
            dir_len: Vec4::splat(ray.dir().length()),
        }
    }
}

impl Tri4 {
    /// The block of `tris` (one to four).
    #[cfg(test)]
    pub(super) fn new(tris: &[TriRecord]) -> Tri4 {
        let mut block = Tri4::EMPTY;
        for (lane, t) in tris.iter().enumerate() {
            block.set(lane, t);
        }
        block
    }

    /// A block with every lane unused.
    /// Each lane's material, and whether the lane holds a triangle (an
    /// unused lane's infinite `edge_scale` never lets a ray hit it).
    pub(super) fn lane_materials(&self) -> [(u32, bool); 4] {
        std::array::from_fn(|lane| (self.material[lane], self.edge_scale[lane].is_finite()))
    }

    /// Lane `lane`'s material.
    #[inline(always)]
    pub(super) fn material(&self, lane: usize) -> u32 {
        self.material[lane]
    }

    pub(super) const EMPTY: Tri4 = Tri4 {
        v0: [Vec4::ZERO; 3],
        e1: [Vec4::ZERO; 3],
        e2: [Vec4::ZERO; 3],
        edge_scale: Vec4::INFINITY,
        id: [u32::MAX; 4],
        material: [0; 4],
    };

    /// Puts `t` in lane `lane`.
    #[inline(always)]
    pub(super) fn set(&mut self, lane: usize, t: &TriRecord) {
        for axis in 0..3 {
            self.v0[axis][lane] = t.v0[axis];
            self.e1[axis][lane] = t.e1[axis];
            self.e2[axis][lane] = t.e2[axis];
        }
        self.edge_scale[lane] = t.edge_scale;
        self.id[lane] = t.id;
        self.material[lane] = t.material;
    }

    /// The lanes hit within (t_min, t_max), as a bit mask, the distances
    /// and the barycentric u and v. Each step is the scalar test's, in the
    /// same order.
    #[inline(always)]
    pub(super) fn intersect(&self, r: &Ray4, t_min: f32, t_max: f32) -> (u32, Vec4, [Vec4; 2]) {
        self.intersect_with(&self.origin_terms(&r.origin), r, t_min, t_max)
    }

    /// What the test shares among rays from `origin` (in every lane).
    #[inline(always)]
    pub(super) fn origin_terms(&self, origin: &[Vec4; 3]) -> OriginTerms<Vec4> {
        OriginTerms::new(v3(origin), v3(&self.v0), v3(&self.e1), v3(&self.e2))
    }

    /// `intersect`, for a ray from the origin `terms` were worked out for.
    #[inline(always)]
    pub(super) fn intersect_with(
        &self,
        terms: &OriginTerms<Vec4>,
        r: &Ray4,
        t_min: f32,
        t_max: f32,
    ) -> (u32, Vec4, [Vec4; 2]) {
        let edges = Edges {
            e1: v3(&self.e1),
            e2: v3(&self.e2),
            scale: self.edge_scale,
        };
        let range = (Vec4::splat(t_min), Vec4::splat(t_max));
        let (hit, t, uv) = moller_trumbore(terms, v3(&r.dir), r.dir_len, &edges, range);
        (hit.bitmask(), t, uv)
    }

    /// The hit on `lane` at distance `t` and barycentric `uv`, as
    /// `Object::surface_hit` gives it.
    /// Lane `lane`'s `v0`, `e1` and `e2`, as its `TriRecord` gave them.
    pub(super) fn corners(&self, lane: usize) -> [Vec3; 3] {
        let at = |v: &[Vec4; 3]| Vec3::new(v[0][lane], v[1][lane], v[2][lane]);
        [at(&self.v0), at(&self.e1), at(&self.e2)]
    }

    pub(super) fn hit(&self, lane: usize, ray: &Ray, t: f32, uv: Vec2) -> SurfaceHit {
        let at = |v: &[Vec4; 3]| Vec3::new(v[0][lane], v[1][lane], v[2][lane]);
        SurfaceHit::on_triangle(
            at(&self.e1),
            at(&self.e2),
            ray,
            TriangleHit { t, uv },
            self.id[lane] as usize,
            self.material[lane] as usize,
        )
    }
}

/// Coordinates by axis as a vector of lanes.
#[inline(always)]
fn v3(a: &[Vec4; 3]) -> V3<Vec4> {
    V3::new(a[0], a[1], a[2])
}

#[cfg(test)]
mod tests {
    use super::super::tests::Rng;
    use super::*;
    use crate::geometry::Triangle;

    fn record(t: &Triangle, id: u32) -> TriRecord {
        let (e1, e2, edge_scale) = t.edges();
        TriRecord {
            v0: t.v0,
            e1,
            e2,
            edge_scale,
            id,
            material: 0,
        }
    }

    #[test]
    fn each_lane_finds_the_scalar_tests_distance_bit_for_bit() {
        let mut rng = Rng(0x2545_F491_4F6C_DD1D);
        let mut hits = 0;
        for k in 0..20_000 {
            // Some triangles slivers, some rays in their plane.
            let triangles: Vec<Triangle> = (0..1 + k % 4)
                .map(|i| {
                    let a = rng.vec(1.0);
                    let b = a + rng.vec(0.5);
                    let c = if i == 1 {
                        a + (b - a) * 0.5 + rng.vec(1e-6)
                    } else {
                        a + rng.vec(0.5)
                    };
                    Triangle::new(a, b, c)
                })
                .collect();
            let origin = rng.vec(3.0);
            let aim = &triangles[k % triangles.len()];
            let dir = if k % 7 == 0 {
                aim.v1 - aim.v0
            } else {
                (aim.v0 + aim.v1 + aim.v2) / 3.0 + rng.vec(0.1) - origin
            };
            let ray = Ray::new(origin, dir);
            let records: Vec<TriRecord> = triangles
                .iter()
                .enumerate()
                .map(|(i, t)| record(t, i as u32))
                .collect();
            let block = Tri4::new(&records);
            let t_max = if k % 3 == 0 { 2.0 } else { f32::INFINITY };
            let (mask, t, [u, v]) = block.intersect(&Ray4::new(&ray), 1e-4, t_max);
            for (lane, tri) in triangles.iter().enumerate() {
                let scalar = tri.intersect(&ray, 1e-4, t_max);
                let simd = (mask >> lane & 1 == 1).then_some([t[lane], u[lane], v[lane]]);
                let bits = |x: [f32; 3]| x.map(f32::to_bits);
                assert_eq!(
                    simd.map(bits),
                    scalar.map(|h| bits([h.t, h.uv.x, h.uv.y])),
                    "ray {k} lane {lane}"
                );
                hits += scalar.is_some() as u32;
            }
            assert_eq!(
                mask >> triangles.len(),
                0,
                "ray {k}: an unused lane was hit"
            );
        }
        assert!(hits > 5000, "only {hits} hits: the test would prove little");
    }
}
