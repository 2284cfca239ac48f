//! Four spheres tested at once, one per SIMD lane: `sphere_roots` in four
//! lanes, so every distance is the one `Sphere::intersect` finds. Block k
//! holds spheres 4k to 4k + 3 of the tree's list; an ellipsoid (hit in
//! its own round frame) and a lane past the list are left to the scalar
//! test (`stretched`), and a run of the list is tested block by block.

use super::leaves::SpherePrim;
use crate::geometry::sphere_roots;
use crate::ray::Ray;
use crate::simd::V3;
use glam::Vec4;
use std::ops::Range;

/// Four round spheres by lane: 64 bytes, one cache line.
#[repr(C, align(64))]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct Sphere4 {
    center: [Vec4; 3],
    /// The squared radius; -infinity past the list and NaN for an
    /// ellipsoid: no ray meets either here (neither gives a root).
    radius2: Vec4,
}

impl Sphere4 {
    /// The blocks of `spheres`, four to a block.
    pub(super) fn blocks(spheres: &[SpherePrim]) -> Vec<Sphere4> {
        spheres
            .chunks(4)
            .map(|four| {
                let mut block = Sphere4 {
                    center: [Vec4::ZERO; 3],
                    radius2: Vec4::NEG_INFINITY,
                };
                for (lane, s) in four.iter().enumerate() {
                    for axis in 0..3 {
                        block.center[axis][lane] = s.sphere.center[axis];
                    }
                    block.radius2[lane] = match s.sphere.stretch {
                        None => s.sphere.radius * s.sphere.radius,
                        Some(_) => f32::NAN,
                    };
                }
                block
            })
            .collect()
    }

    /// The lanes whose sphere lies on `ray` in (t_min, t_max), as a bit
    /// mask, and the distances (`Sphere::intersect`'s, lane by lane).
    #[inline(always)]
    pub(super) fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> (u32, Vec4) {
        let (o, d) = (ray.origin(), ray.dir());
        let v = V3 {
            x: Vec4::splat(o.x) - self.center[0],
            y: Vec4::splat(o.y) - self.center[1],
            z: Vec4::splat(o.z) - self.center[2],
        };
        let dir = V3::from(d);
        let a = dir.dot(dir);
        let dir = V3 {
            x: Vec4::splat(d.x),
            y: Vec4::splat(d.y),
            z: Vec4::splat(d.z),
        };
        let limits = (Vec4::splat(t_min), Vec4::splat(t_max));
        let (hit, t) = sphere_roots(v, dir, Vec4::splat(a), self.radius2, limits);
        (hit.bitmask(), t)
    }

    /// The lanes holding an ellipsoid, as a bit mask.
    #[inline(always)]
    pub(super) fn stretched(&self) -> u32 {
        self.radius2.is_nan_mask().bitmask()
    }
}

/// Equal bits, as the tree is compared (an ellipsoid's NaN too).
impl PartialEq for Sphere4 {
    fn eq(&self, other: &Sphere4) -> bool {
        bytemuck::bytes_of(self) == bytemuck::bytes_of(other)
    }
}

/// The blocks holding `run` of the sphere list.
#[inline(always)]
pub(super) fn blocks_of(run: &Range<usize>) -> Range<usize> {
    if run.is_empty() {
        return 0..0;
    }
    run.start / 4..(run.end - 1) / 4 + 1
}

/// The lanes of block `block` that lie in `run` of the sphere list.
#[inline(always)]
pub(super) fn lanes_in(block: usize, run: &Range<usize>) -> u32 {
    let first = block * 4;
    let lo = run.start.saturating_sub(first).min(4);
    let hi = run.end.saturating_sub(first).min(4);
    ((1u32 << hi) - 1) & !((1u32 << lo) - 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_covers_its_blocks_lanes_and_no_others() {
        let lanes = |run: Range<usize>| {
            blocks_of(&run)
                .map(|b| (b, lanes_in(b, &run)))
                .collect::<Vec<_>>()
        };
        assert_eq!(lanes(0..0), []);
        assert_eq!(lanes(0..4), [(0, 0b1111)]);
        assert_eq!(lanes(2..3), [(0, 0b0100)]);
        assert_eq!(lanes(3..9), [(0, 0b1000), (1, 0b1111), (2, 0b0001)]);
        assert_eq!(lanes(8..10), [(2, 0b0011)]);
    }
}
