//! The lab's Blinn-Phong highlight (`specular`, `shininess`) as an energy
//! conserving lobe.

use super::microfacet::reflect_about;
use crate::simd::{Real, V3};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// f = ks c(n) (N.H)^n, with c(n) the normalisation that makes the
/// albedo at normal incidence exactly ks: integrating (N.H)^n cos(theta_i)
/// over the hemisphere (with theta_i = 2 theta_h) gives
/// 8 pi (n + 2^(-n/2)) / ((n + 2)(n + 4)). At other angles less comes back
/// (the lobe leaves the hemisphere), so it never reflects more than ks.
/// The common (n + 8) / (8 pi) is above this by up to 7.5 % (at n near 10).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlinnPhong {
    pub specular: Vec3,
    pub shininess: f32,
}

impl BlinnPhong {
    /// c(n).
    pub fn normalisation(n: f32) -> f32 {
        normalisation(n)
    }

    /// f for local directions with `wo.z >= 0` (`phong_f`).
    #[inline(always)]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        phong_f(self.specular.into(), self.shininess, wo.into(), wi.into()).into()
    }

    /// The density of `sample`'s directions (`phong_pdf`).
    #[inline(always)]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        phong_pdf(self.shininess, wo.into(), wi.into())
    }

    /// wo reflected about a half vector drawn from (N.H)^n
    /// (`phong_direction`); None when the reflection falls below the
    /// surface.
    #[inline(always)]
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<Vec3> {
        let (wi, above) = phong_direction(self.shininess, wo.into(), (u.x, u.y));
        above.then(|| wi.into())
    }
}

// The lobe's formulas, for any lane width (`simd::Real`): `BlinnPhong` is
// them on f32.

/// c(n) of `BlinnPhong`.
#[inline(always)]
pub fn normalisation<N: Real>(n: N) -> N {
    (n + 2.0) / (8.0 * PI) * ((n + 4.0) / (n + (n * -0.5).exp2()))
}

/// f of the lobe of colour `specular` and exponent `n` toward local `wi`
/// (for `wo.z >= 0`): nothing below the surface.
#[inline(always)]
pub fn phong_f<N: Real>(specular: V3<N>, n: N, wo: V3<N>, wi: V3<N>) -> V3<N> {
    let (h, half) = (wo + wi).try_normalize();
    let f = specular * (normalisation(n) * h.z.max(N::zero()).powf(n));
    // Tested as `<=`, so that a NaN goes on to the half vector's test.
    V3::select(half & !wi.z.le(N::zero()), f, V3::zero())
}

/// The density of `phong_direction`'s directions: H drawn with density
/// (n + 1) / (2 pi) (N.H)^n, and the change of variables from H to the
/// reflected direction, 1 / (4 wo.H).
#[inline(always)]
pub fn phong_pdf<N: Real>(n: N, wo: V3<N>, wi: V3<N>) -> N {
    let (h, half) = (wo + wi).try_normalize();
    let pdf_h = (n + 1.0) / (2.0 * PI) * h.z.max(N::zero()).powf(n);
    let pdf = pdf_h / (wo.dot(h) * 4.0).max(N::splat(f32::MIN_POSITIVE));
    N::select(half & !wi.z.le(N::zero()), pdf, N::zero())
}

/// wo reflected about a half vector drawn from (N.H)^n by `u`, and where
/// it is above the surface.
#[inline(always)]
pub fn phong_direction<N: Real>(n: N, wo: V3<N>, (u1, u2): (N, N)) -> (V3<N>, N::Mask) {
    let cos_h = u1.powf(N::one() / (n + 1.0));
    let sin_h = (N::one() - cos_h * cos_h).max(N::zero()).sqrt();
    let (sin, cos) = (u2 * (2.0 * PI)).sin_cos();
    let h = V3::new(sin_h * cos, sin_h * sin, cos_h);
    let wi = reflect_about(wo, h);
    (wi, wi.z.gt(N::zero()))
}
