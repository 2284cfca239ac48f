//! A metal: a mirror, or a rough surface of GGX microfacets that are
//! mirrors, each reflecting by Schlick's approximation of a conductor's
//! Fresnel term with its colour at normal incidence F0 (the principled
//! material's `base_color`, as glTF 2.0 takes it).

use super::microfacet::{reflect_about, Ggx};
use super::specular::reflect;
use super::BsdfSample;
use glam::{Vec2, Vec3};

/// Schlick's approximation: F0 + (1 - F0)(1 - cos)^5.
#[inline(always)]
pub fn schlick(f0: Vec3, cos: f32) -> Vec3 {
    f0 + (Vec3::ONE - f0) * schlick_weight(cos)
}

/// (1 - cos)^5, Schlick's share of 1 - F0 at `cos`.
#[inline(always)]
pub fn schlick_weight(cos: f32) -> f32 {
    let c = 1.0 - cos.clamp(0.0, 1.0);
    let c2 = c * c;
    c2 * c2 * c
}

/// A conductor of reflectance `f0` at normal incidence.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Conductor {
    pub f0: Vec3,
    pub ggx: Ggx,
}

impl Conductor {
    /// Whether its one lobe is a mirror (a single direction).
    pub fn is_smooth(&self) -> bool {
        self.ggx.is_smooth()
    }

    /// An estimate of its albedo for picking lobes: the mean over the
    /// hemisphere of Schlick's F, F0 + (1 - F0) / 21 (never 0, as a black
    /// metal still reflects at grazing angles).
    pub fn albedo_estimate(&self) -> f32 {
        let f0 = self.f0.element_sum() / 3.0;
        f0 + (1.0 - f0) / 21.0
    }

    /// f |cos theta_i| toward local `wi` and the density `sample` gives it:
    /// the microfacet BRDF D G2 F / (4 cos_o cos_i), F at the half vector.
    /// Nothing for a mirror (its lobe is a single direction).
    #[inline(always)]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        if self.is_smooth() || wo.z <= 0.0 || wi.z <= 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let Some(m) = (wo + wi).try_normalize() else {
            return (Vec3::ZERO, 0.0);
        };
        let cos = wo.dot(m);
        let d = self.ggx.d(m);
        let f = schlick(self.f0, cos) * (d * self.ggx.g2(wo, wi) / (4.0 * wo.z));
        // The reflection's Jacobian from m to wi: 1 / (4 wo.m).
        let pdf = self.ggx.visible_d(wo, m) / (4.0 * cos).max(f32::MIN_POSITIVE);
        (f, pdf)
    }

    /// A direction toward local `wi` (in `BsdfSample::wi`): the mirror's,
    /// or wo mirrored about a visible normal (weight F G2 / G1(wo)). None
    /// when the reflection falls below the surface.
    #[inline(always)]
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        if self.is_smooth() {
            return Some(BsdfSample {
                wi: reflect(wo),
                weight: schlick(self.f0, wo.z),
                pdf: 1.0,
                specular: true,
                transmitted: false,
                eta: 1.0,
            });
        }
        let m = self.ggx.sample_visible(wo, u);
        let cos = wo.dot(m);
        let wi = reflect_about(wo, m);
        if wi.z <= 0.0 || cos <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: schlick(self.f0, cos) * self.ggx.g2_over_g1(wo, wi),
            pdf: self.ggx.visible_d(wo, m) / (4.0 * cos),
            specular: false,
            transmitted: false,
            eta: 1.0,
        })
    }
}
