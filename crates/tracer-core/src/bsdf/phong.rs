//! The lab's Blinn-Phong highlight (`specular`, `shininess`) as an energy
//! conserving lobe.

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
        (n + 2.0) / (8.0 * PI) * ((n + 4.0) / (n + (-0.5 * n).exp2()))
    }

    /// f for local directions with `wo.z >= 0`.
    #[inline(always)]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let Some(h) = (wo + wi).try_normalize() else {
            return Vec3::ZERO;
        };
        let n = self.shininess;
        self.specular * (Self::normalisation(n) * h.z.max(0.0).powf(n))
    }

    /// The density of `sample`'s directions: H drawn with density
    /// (n + 1) / (2 pi) (N.H)^n, and the change of variables from H to the
    /// reflected direction, 1 / (4 wo.H).
    #[inline(always)]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wi.z <= 0.0 {
            return 0.0;
        }
        let Some(h) = (wo + wi).try_normalize() else {
            return 0.0;
        };
        let n = self.shininess;
        let pdf_h = (n + 1.0) / (2.0 * PI) * h.z.max(0.0).powf(n);
        pdf_h / (4.0 * wo.dot(h)).max(f32::MIN_POSITIVE)
    }

    /// wo reflected about a half vector drawn from (N.H)^n; None when the
    /// reflection falls below the surface.
    #[inline(always)]
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<Vec3> {
        let cos_h = u.x.powf(1.0 / (self.shininess + 1.0));
        let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let h = Vec3::new(sin_h * phi.cos(), sin_h * phi.sin(), cos_h);
        let wi = 2.0 * wo.dot(h) * h - wo;
        (wi.z > 0.0).then_some(wi)
    }
}
