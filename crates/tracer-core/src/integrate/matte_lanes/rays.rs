//! The lanes' rays and their triangle tests: every ray of the group against
//! one triangle at a time, each triangle's numbers read once for sixteen
//! rays, compiled for each processor's widest SIMD registers.

use super::{lane, set, Tri, F, LANES, V};
use crate::EPSILON;
use glam::Vec3;
use multiversion::multiversion;

/// Each lane's nearest hit among `tris`: its distance and triangle
/// (`u32::MAX` for none), every triangle tested in list order, a hit
/// taken only when strictly nearer: of equal distances the one listed
/// first, as the tree's rule. Compiled for each processor's widest SIMD
/// registers (the same arithmetic: nothing is fused).
#[multiversion(targets("x86_64+avx512f+avx512bw+avx512dq+avx512vl", "x86_64+avx2"))]
pub(super) fn nearest(tris: &[Tri], rays: &Rays) -> (F, [u32; LANES]) {
    let mut best = [f32::INFINITY; LANES];
    let mut id = [u32::MAX; LANES];
    let dir_len = rays.dir_len();
    for (j, tri) in tris.iter().enumerate() {
        for k in 0..LANES {
            let (hit, t) = rays.intersect(k, tri, best[k], &dir_len);
            best[k] = if hit { t } else { best[k] };
            id[k] = if hit { j as u32 } else { id[k] };
        }
    }
    (best, id)
}

/// Whether something of `tris` lies on each lane's ray in (EPSILON,
/// reach), 1 or 0 (as wide as a float: a SIMD mask); a lane of reach -inf
/// has no ray and reads 1, so that the search ends once every ray is
/// blocked.
#[multiversion(targets("x86_64+avx512f+avx512bw+avx512dq+avx512vl", "x86_64+avx2"))]
pub(super) fn occluded(tris: &[Tri], rays: &Rays, reach: &F) -> [u32; LANES] {
    let mut blocked = reach.map(|r| u32::from(r == f32::NEG_INFINITY));
    let dir_len = rays.dir_len();
    // Whether all are blocked is asked every few triangles only: it is
    // rarely so, and asked after each triangle the question took 3.5 % of
    // the Cornell box's time.
    for group in tris.chunks(8) {
        for tri in group {
            for k in 0..LANES {
                blocked[k] |= rays.intersect(k, tri, reach[k], &dir_len).0 as u32;
            }
        }
        if blocked.iter().all(|&b| b != 0) {
            break;
        }
    }
    blocked
}

/// The lanes' rays by axis, for the triangle test in lanes.
#[derive(Clone, Copy)]
pub(super) struct Rays {
    pub(super) origin: V,
    pub(super) dir: V,
}

impl Rays {
    /// No ray: a zero direction meets nothing.
    pub(super) const NONE: Rays = Rays {
        origin: [[0.0; LANES]; 3],
        dir: [[0.0; LANES]; 3],
    };

    pub(super) fn origin(&self, k: usize) -> Vec3 {
        lane(&self.origin, k)
    }

    pub(super) fn dir(&self, k: usize) -> Vec3 {
        lane(&self.dir, k)
    }

    pub(super) fn set(&mut self, k: usize, origin: Vec3, dir: Vec3) {
        set(&mut self.origin, k, origin);
        set(&mut self.dir, k, dir);
    }

    /// Each direction's length, as `Vec3::length` (the test's scale).
    #[inline(always)]
    fn dir_len(&self) -> F {
        let d = &self.dir;
        std::array::from_fn(|k| (d[0][k] * d[0][k] + d[1][k] * d[1][k] + d[2][k] * d[2][k]).sqrt())
    }

    /// Moller-Trumbore of lane `k`'s ray against `tri` within (EPSILON,
    /// t_max): `Tri4::intersect_with`'s operations in its order, so the
    /// one-ray search's distances bit for bit. Whether it hits, and where.
    #[inline(always)]
    fn intersect(&self, k: usize, tri: &Tri, t_max: f32, dir_len: &F) -> (bool, f32) {
        let (v0, e1, e2) = (tri.v0.to_array(), tri.e1.to_array(), tri.e2.to_array());
        let o = [self.origin[0][k], self.origin[1][k], self.origin[2][k]];
        let d = [self.dir[0][k], self.dir[1][k], self.dir[2][k]];
        let s = [o[0] - v0[0], o[1] - v0[1], o[2] - v0[2]];
        let q = cross(s, e1);
        let t_times_det = dot(e2, q);
        let p = cross(d, e2);
        let det = dot(e1, p);
        let parallel = det.abs() < tri.edge_scale * dir_len[k];
        let inv = 1.0 / det;
        let u = dot(s, p) * inv;
        // `&` and `|`, not `&&` and `||` (nor `contains`): no branch, so
        // the lanes are tested in SIMD registers.
        #[allow(clippy::manual_range_contains)]
        let u_inside = (u >= 0.0) & (u <= 1.0);
        let v = dot(d, q) * inv;
        let v_outside = (v < 0.0) | (u + v > 1.0);
        let t = t_times_det * inv;
        let t_inside = (t > EPSILON) & (t < t_max);
        (!parallel & u_inside & !v_outside & t_inside, t)
    }
}

/// `a x b`, as `Vec3::cross`.
#[inline(always)]
fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - b[1] * a[2],
        a[2] * b[0] - b[2] * a[0],
        a[0] * b[1] - b[0] * a[1],
    ]
}

/// `a . b`, as `Vec3::dot`.
#[inline(always)]
fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
