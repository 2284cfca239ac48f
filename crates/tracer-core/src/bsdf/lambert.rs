//! The Lambertian lobe: the lab's `diffuse` read as an albedo. Its
//! formulas are written for any lane width: the one-path tracer's BSDFs
//! and the lanes (`matte_lanes`) use the same ones.

use crate::sampling::warp::cosine_hemisphere;
use crate::simd::{Real, V3};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// Light scattered equally in every direction of the hemisphere: f =
/// albedo / pi, so a white surface (albedo 1) reflects all it receives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lambert {
    pub albedo: Vec3,
}

impl Lambert {
    /// f for local directions with `wo.z >= 0`: nothing below the surface.
    #[inline(always)]
    pub fn eval(&self, wi: Vec3) -> Vec3 {
        lambert_f(V3::from(self.albedo), wi.z).into()
    }

    /// The density of `sample`'s directions: cosine-weighted.
    #[inline(always)]
    pub fn pdf(wi: Vec3) -> f32 {
        lambert_pdf(wi.z)
    }

    /// A cosine-weighted direction of the upper hemisphere from a point of
    /// the unit square; below it (z = 0) where the disk's edge lifts to it.
    #[inline(always)]
    pub fn sample(u: Vec2) -> Vec3 {
        cosine_hemisphere((u.x, u.y)).into()
    }
}

/// f of albedo `albedo` toward a local direction of cosine `cos`: albedo /
/// pi above the surface, nothing below (nor where the cosine is NaN).
#[inline(always)]
pub fn lambert_f<N: Real>(albedo: V3<N>, cos: N) -> V3<N> {
    let above = cos.gt(N::zero());
    V3::select(above, albedo * N::splat(FRAC_1_PI), V3::zero())
}

/// The density of a cosine-weighted direction of cosine `cos`.
#[inline(always)]
pub fn lambert_pdf<N: Real>(cos: N) -> N {
    cos.max(N::zero()) * FRAC_1_PI
}
