//! The unit square warped onto shapes, area for area, for any lane width:
//! the disk, the cosine-weighted hemisphere, the triangle.

use crate::simd::{Real, V3};
use std::f32::consts::FRAC_PI_4;

/// The unit square mapped onto the unit disk, area for area (Shirley and
/// Chiu's concentric map: strata of the square stay compact on the disk).
#[inline(always)]
pub fn concentric_disk<N: Real>((ux, uy): (N, N)) -> (N, N) {
    let (qx, qy) = (N::splat(2.0) * ux - 1.0, N::splat(2.0) * uy - 1.0);
    let centre = qx.eq(N::zero()) & qy.eq(N::zero());
    let wide = qx.abs().gt(qy.abs());
    let r = N::select(wide, qx, qy);
    let quarter = N::splat(FRAC_PI_4);
    let theta = N::select(
        wide,
        quarter * (qy / qx),
        N::splat(2.0) * quarter - quarter * (qx / qy),
    );
    let (sin, cos) = theta.sin_cos();
    let zero = N::zero();
    (
        N::select(centre, zero, r * cos),
        N::select(centre, zero, r * sin),
    )
}

/// A cosine-weighted direction of the upper hemisphere (z up) from a
/// point of the unit square (Malley's method: the disk lifted onto it).
#[inline(always)]
pub fn cosine_hemisphere<N: Real>(u: (N, N)) -> V3<N> {
    let (x, y) = concentric_disk(u);
    let z = (N::one() - (x * x + y * y)).max(N::zero()).sqrt();
    V3::new(x, y, z)
}

/// Heitz's low-distortion map of the unit square onto a triangle ("A
/// low-distortion map between triangle and square", 2019): barycentric
/// (b1, b2), uniform by area, strata kept compact.
#[inline(always)]
pub fn square_to_triangle<N: Real>((ux, uy): (N, N)) -> (N, N) {
    let upper = uy.gt(ux);
    let half_x = ux / 2.0;
    let half_y = uy / 2.0;
    (
        N::select(upper, half_x, ux - half_y),
        N::select(upper, uy - half_x, half_y),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;
    use crate::simd::F16;

    /// Sixteen lanes give each lane's one-lane value, bit for bit.
    #[test]
    fn warps_in_lanes_are_the_one_lane_warps() {
        let mut rng = Rng::new(3);
        for _ in 0..200 {
            let points: [glam::Vec2; 16] = std::array::from_fn(|k| match k {
                0 => glam::Vec2::splat(0.5),
                1 => glam::Vec2::new(0.5, 0.9),
                _ => rng.square(),
            });
            let u = (F16::from_fn(|k| points[k].x), F16::from_fn(|k| points[k].y));
            let (dx, dy) = concentric_disk(u);
            let (tx, ty) = square_to_triangle(u);
            let h = cosine_hemisphere(u);
            for (k, p) in points.iter().enumerate() {
                let one = concentric_disk((p.x, p.y));
                assert_eq!((dx.lane(k), dy.lane(k)), one, "disk, lane {k}");
                let t = square_to_triangle((p.x, p.y));
                assert_eq!((tx.lane(k), ty.lane(k)), t, "triangle, lane {k}");
                assert_eq!(h.lane(k), cosine_hemisphere((p.x, p.y)).into());
            }
        }
    }

    #[test]
    fn the_triangle_map_is_uniform_by_area() {
        // The share of points with b1 + b2 < 1/2 is the small triangle's
        // area, a quarter; with b1 < 1/2, three quarters.
        let n = 200u32;
        let (mut corner, mut left) = (0, 0);
        for i in 0..n {
            for j in 0..n {
                let u = ((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let (b1, b2) = square_to_triangle(u);
                assert!(b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0);
                corner += usize::from(b1 + b2 < 0.5);
                left += usize::from(b1 < 0.5);
            }
        }
        let total = (n * n) as f32;
        assert!((corner as f32 / total - 0.25).abs() < 0.005);
        assert!((left as f32 / total - 0.75).abs() < 0.005);
    }
}
