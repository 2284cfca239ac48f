//! The triangles a shadow ray is tested against, in small groups of
//! neighbours, each in a box: a group whose box none of the sixteen rays
//! enters within its reach is passed over whole. Most shadow rays and
//! connections of path reuse pass by most of a room's boxes, and a box
//! costs less than a triangle to test. Whether a ray is blocked does not
//! depend on the order its triangles are tested in, and each box is
//! widened far beyond what rounding in the triangle test or the box test
//! can cross, so the answer stays the one testing every triangle gives,
//! bit for bit.

use super::rays::Rays;
use super::{by_axis, Tri, F, LANES};
use crate::simd::{Mask, Real, F16, M16, V3};
use glam::Vec3;
use multiversion::multiversion;

/// Whether something of `groups` lies on each lane's ray in (EPSILON,
/// reach), 1 or 0 (as wide as a float: a SIMD mask); a lane of reach -inf
/// has no ray and reads 1, so that the search ends once every ray is
/// blocked.
#[multiversion(targets("x86_64+avx512f+avx512bw+avx512dq+avx512vl", "x86_64+avx2"))]
pub(super) fn occluded(groups: &Groups, rays: &Rays, reach: &F) -> [u32; LANES] {
    let reach = F16(*reach);
    let mut blocked = reach.eq(F16::splat(f32::NEG_INFINITY));
    groups.occluded(rays, reach, &mut blocked);
    blocked.0.map(|b| b & 1)
}

/// Triangles a group holds at most: a box test costs about half a
/// triangle's, and pairs (a quad's two halves) passed over the most time
/// in the Cornell box (3.37 s at 64 paths on one thread; 3.43 s a
/// triangle a box, 3.50 s four, 3.63 s eight, 4.64 s no boxes).
const GROUP: usize = 2;

/// How much wider than its triangles a box is, in proportion to the size
/// of the scene's coordinates (`scene_size`): Moller-Trumbore's rounding
/// of a ray just outside an edge into a hit grows with the ray's distance
/// from the triangle, which the scene bounds, and a hundred times what
/// the tree's boxes take for a triangle's own size (`accel/build.rs`)
/// covers it, and the box test's own rounding, by far.
const BOX_PAD: f32 = 1e-4;

/// Triangles in groups, each group's box and its run of `tris`.
#[derive(Debug, Clone, Default)]
pub(super) struct Groups {
    tris: Vec<Tri>,
    boxes: Vec<Bounds>,
}

/// A group's box and where its triangles stand in `Groups::tris`.
#[derive(Debug, Clone, Copy)]
struct Bounds {
    lo: Vec3,
    hi: Vec3,
    start: usize,
    end: usize,
}

impl Groups {
    /// `tris` sorted into groups of neighbours: split in two at the
    /// median of their centres along the widest axis, until each part
    /// holds at most `GROUP`; their boxes widened for a scene of size
    /// `scene` (`scene_size` of all its triangles, where every ray starts).
    pub(super) fn new(tris: &[Tri], scene: f32) -> Groups {
        let mut groups = Groups::default();
        groups.split(&mut tris.to_vec(), Vec3::splat(scene * BOX_PAD));
        groups
    }

    fn split(&mut self, tris: &mut [Tri], pad: Vec3) {
        if tris.len() <= GROUP {
            self.push(tris, pad);
            return;
        }
        let (lo, hi) = centre_bounds(tris);
        let axis = (hi - lo).max_position();
        let mid = tris.len() / 2;
        tris.select_nth_unstable_by(mid, |a, b| centre(a)[axis].total_cmp(&centre(b)[axis]));
        let (left, right) = tris.split_at_mut(mid);
        self.split(left, pad);
        self.split(right, pad);
    }

    fn push(&mut self, tris: &[Tri], pad: Vec3) {
        if tris.is_empty() {
            return;
        }
        let (lo, hi) = bounds(tris);
        let start = self.tris.len();
        self.tris.extend_from_slice(tris);
        self.boxes.push(Bounds {
            lo: lo - pad,
            hi: hi + pad,
            start,
            end: self.tris.len(),
        });
    }

    /// Whether something lies on each lane's ray in (EPSILON, reach), as
    /// testing every triangle answers: the groups whose box some ray
    /// enters are tested, until every ray is blocked.
    #[inline(always)]
    pub(super) fn occluded(&self, rays: &Rays, reach: F16, blocked: &mut M16) {
        let (origin, inv) = (by_axis(&rays.origin), by_axis(&rays.dir).safe_recip());
        let dir_len = rays.dir_len();
        for b in &self.boxes {
            if !enters(b, origin, inv, reach).any() {
                continue;
            }
            let tris = &self.tris[b.start..b.end];
            *blocked = *blocked | rays.blocked_by(tris, reach, dir_len);
            if blocked.all() {
                return;
            }
        }
    }
}

/// Which lanes' rays (from `origin`, 1 / direction `inv`) meet box `b`
/// somewhere in (0, reach].
#[inline(always)]
fn enters(b: &Bounds, origin: V3<F16>, inv: V3<F16>, reach: F16) -> M16 {
    let slab = |lo: f32, hi: f32, o: F16, inv: F16| {
        let (a, b) = ((F16::splat(lo) - o) * inv, (F16::splat(hi) - o) * inv);
        (a.min(b), a.max(b))
    };
    let (nx, fx) = slab(b.lo.x, b.hi.x, origin.x, inv.x);
    let (ny, fy) = slab(b.lo.y, b.hi.y, origin.y, inv.y);
    let (nz, fz) = slab(b.lo.z, b.hi.z, origin.z, inv.z);
    let near = nx.max(ny).max(nz).max(F16::zero());
    let far = fx.min(fy).min(fz).min(reach);
    near.le(far)
}

/// The size of the coordinates of `tris`: the largest of their absolute
/// values and of their extents (the tree's measure, `accel/build.rs`).
pub(super) fn scene_size(tris: &[Tri]) -> f32 {
    let (lo, hi) = bounds(tris);
    lo.abs().max(hi.abs()).max_element() + (hi - lo).max_element()
}

/// The box of the corners of `tris`.
fn bounds(tris: &[Tri]) -> (Vec3, Vec3) {
    let corners = || tris.iter().flat_map(corners);
    let lo = corners().fold(Vec3::INFINITY, Vec3::min);
    let hi = corners().fold(Vec3::NEG_INFINITY, Vec3::max);
    (lo, hi)
}

fn corners(t: &Tri) -> [Vec3; 3] {
    [t.v0, t.v0 + t.e1, t.v0 + t.e2]
}

fn centre(t: &Tri) -> Vec3 {
    t.v0 + (t.e1 + t.e2) / 3.0
}

fn centre_bounds(tris: &[Tri]) -> (Vec3, Vec3) {
    tris.iter()
        .map(centre)
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), c| {
            (lo.min(c), hi.max(c))
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::hash;

    /// A number of [-1, 1) from `(i, j)`.
    fn unit(i: u32, j: u32) -> f32 {
        (hash(i, j, 7) >> 40) as f32 / (1u64 << 23) as f32 - 1.0
    }

    fn point(i: u32, j: u32, size: f32) -> Vec3 {
        Vec3::new(unit(i, 3 * j), unit(i, 3 * j + 1), unit(i, 3 * j + 2)) * size
    }

    /// Random triangles, some tiny (slivers far from their neighbours, or
    /// near the origin, where their own coordinates are small beside the
    /// rays' distances).
    fn triangles(seed: u32) -> Vec<Tri> {
        (0..24)
            .map(|n| {
                let near_origin = n % 10 == 0;
                let v0 = point(seed, 10 * n, if near_origin { 0.02 } else { 4.0 });
                let size = if n % 5 == 0 { 0.01 } else { 1.5 };
                let (e1, e2) = (point(seed, 10 * n + 1, size), point(seed, 10 * n + 2, size));
                Tri {
                    v0,
                    e1,
                    e2,
                    edge_scale: 1e-7 * e1.length().max(e2.length()),
                    normal: e1.cross(e2).normalize(),
                    material: n,
                }
            })
            .collect()
    }

    /// Rays from random points toward the triangles' corners and edges,
    /// a hair beside or beyond them, of random reach: grazing what the
    /// boxes hold where rounding decides.
    fn rays(tris: &[Tri], seed: u32) -> Vec<(Rays, F)> {
        (0..200)
            .map(|r| {
                let mut rays = Rays::NONE;
                let mut reach = [0.0; LANES];
                for (k, reach) in reach.iter_mut().enumerate() {
                    let n = r * LANES as u32 + k as u32;
                    let t = &tris[(hash(seed, n, 1) % tris.len() as u64) as usize];
                    let along = unit(seed, n).abs();
                    let edge = [t.e1, t.e2, t.e2 - t.e1][(hash(seed, n, 2) % 3) as usize];
                    let start = if edge == t.e2 - t.e1 {
                        t.v0 + t.e1
                    } else {
                        t.v0
                    };
                    let target = start + edge * along + point(seed, n, 1e-6);
                    let origin = point(seed ^ 1, n, 6.0);
                    let dir = (target - origin).normalize();
                    rays.set(k, origin, dir);
                    *reach = (target - origin).length() * (1.0 + unit(seed ^ 2, n) * 1e-3);
                }
                (rays, reach)
            })
            .collect()
    }

    #[test]
    fn the_groups_block_the_rays_every_triangle_blocks() {
        let (mut passed_over, mut hits) = (0, 0);
        for seed in 0..8 {
            let tris = triangles(seed);
            let spatial = Groups::new(&tris, scene_size(&tris));
            for (rays, reach) in rays(&tris, seed) {
                let reach = F16(reach);
                let every = rays.blocked_by(&tris, reach, rays.dir_len());
                let mut blocked = M16::splat(false);
                spatial.occluded(&rays, reach, &mut blocked);
                assert_eq!(blocked.0, every.0, "seed {seed}");
                hits += (0..LANES).filter(|&k| every.lane(k)).count();
                let (origin, inv) = (by_axis(&rays.origin), by_axis(&rays.dir).safe_recip());
                passed_over += spatial
                    .boxes
                    .iter()
                    .filter(|b| !enters(b, origin, inv, reach).any())
                    .count();
            }
        }
        // The boxes were put to use, not all entered, and the rays aimed
        // at edges were blocked about a third of the time (8055).
        assert!(passed_over > 1000, "{passed_over}");
        assert!((5000..20000).contains(&hits), "{hits} of 25600 blocked");
    }
}
