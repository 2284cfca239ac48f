//! The lanes' rays and their triangle tests: every ray of the group against
//! one triangle at a time, each triangle's numbers read once for sixteen
//! rays. The nearest hit tests every triangle: the boxes of a room's walls
//! hold every ray, and passing over the others by their boxes
//! (`groups.rs`) cost more than it saved (3.8 s against 3.4 s for the
//! Cornell box at 64 paths on one thread).

use super::{by_axis, lane, set, Tri, F, LANES, V};
use crate::geometry::{moller_trumbore, Edges, OriginTerms};
use crate::simd::{Mask, Real, F16, M16, V3};
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
    let mut best = F16::splat(f32::INFINITY);
    let mut id = [u32::MAX; LANES];
    let dir_len = rays.dir_len();
    for (j, tri) in tris.iter().enumerate() {
        let (hit, t) = rays.intersect(tri, best, dir_len);
        best = F16::select(hit, t, best);
        for k in 0..LANES {
            id[k] = if hit.lane(k) { j as u32 } else { id[k] };
        }
    }
    (best.0, id)
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
    pub(super) fn dir_len(&self) -> F16 {
        by_axis(&self.dir).length()
    }

    /// The lanes whose ray meets one of `tris` in (EPSILON, reach).
    #[inline(always)]
    pub(super) fn blocked_by(&self, tris: &[Tri], reach: F16, dir_len: F16) -> M16 {
        let mut blocked = M16::splat(false);
        for tri in tris {
            blocked = blocked | self.intersect(tri, reach, dir_len).0;
        }
        blocked
    }

    /// `moller_trumbore` of every lane's ray against `tri` within
    /// (EPSILON, t_max): whether each hits, and where.
    #[inline(always)]
    fn intersect(&self, tri: &Tri, t_max: F16, dir_len: F16) -> (M16, F16) {
        let (e1, e2) = (V3::splat(tri.e1), V3::splat(tri.e2));
        let terms = OriginTerms::new(by_axis(&self.origin), V3::splat(tri.v0), e1, e2);
        let edges = Edges {
            e1,
            e2,
            scale: F16::splat(tri.edge_scale),
        };
        let range = (F16::splat(EPSILON), t_max);
        let (hit, t, _) = moller_trumbore(&terms, by_axis(&self.dir), dir_len, &edges, range);
        (hit, t)
    }
}
