//! An opaque dielectric (plastic, paint, wood): a GGX specular layer over a
//! Lambertian base. The layer's facets reflect by Schlick's approximation
//! with F0 = ((ior - 1) / (ior + 1))^2, as glTF 2.0's reference does (its
//! albedo is then linear in F0: `specular_albedo.rs`).
//!
//! The base receives what the layer does not reflect. Weighting it by
//! 1 - F(cos_o) alone is not enough: a rough layer reflects more than F at
//! normal incidence (its facets are tilted, and F grows with the angle), so
//! a white base would give back more than 1. It is weighted instead by what
//! the layer leaves in both directions (Kelemen and Szirmay-Kalos 2001; Kulla
//! and Conty 2017): f_base = base / pi (1 - E(wo)) (1 - E(wi)) / (1 - E_avg),
//! with E the layer's directional albedo and E_avg its cosine-weighted mean
//! (`specular_albedo.rs`). Then the base's albedo seen from wo is exactly
//! base (1 - E(wo)), so the whole gives back E(wo) + base (1 - E(wo)) <= 1,
//! and f stays reciprocal.

use super::conductor::schlick_weight;
use super::lambert::Lambert;
use super::microfacet::{reflect_about, Ggx};
use super::specular::reflect;
use super::specular_albedo::{table, Layer, SpecularAlbedo};
use super::BsdfSample;
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// A layer of index `ior` (outside 1) over a base of albedo `base`.
#[derive(Debug, Clone, Copy)]
pub struct Plastic {
    base: Vec3,
    /// The layer's reflectance at normal incidence.
    f0: f32,
    ggx: Ggx,
    table: &'static SpecularAlbedo,
    layer: Layer,
    /// 1 / (1 - E_avg), or 0 if the layer leaves nothing to the base.
    base_norm: f32,
}

impl Plastic {
    /// Base colour `base`, the layer's index `ior` (outside 1) and width.
    pub fn new(base: Vec3, ior: f32, ggx: Ggx) -> Plastic {
        let f0 = ((ior - 1.0) / (ior + 1.0)).powi(2);
        let f0 = if f0.is_nan() { 1.0 } else { f0.min(1.0) };
        let layer = SpecularAlbedo::layer(ggx, f0);
        let table = table();
        let room = 1.0 - table.mean(&layer);
        Plastic {
            base,
            f0,
            ggx,
            table,
            layer,
            base_norm: if room > 1e-4 { 1.0 / room } else { 0.0 },
        }
    }

    /// E(cos): the light the layer reflects (one scattering, from the
    /// table, raised by its margin).
    #[inline(always)]
    fn layer_albedo(&self, cos: f32) -> f32 {
        self.table.albedo(&self.layer, cos)
    }

    /// Schlick's F of a facet seen at `cos`.
    #[inline(always)]
    fn fresnel(&self, cos: f32) -> f32 {
        self.f0 + (1.0 - self.f0) * schlick_weight(cos)
    }

    /// The probability of sampling the layer rather than the base, in
    /// proportion to their albedos at wo.
    #[inline(always)]
    fn p_layer(&self, wo: Vec3) -> f32 {
        let e = self.layer_albedo(wo.z);
        let base = self.base.element_sum() / 3.0 * self.left(e);
        if e + base > 0.0 {
            e / (e + base)
        } else {
            1.0
        }
    }

    /// What the layer of albedo `e` leaves to the base (nothing if the
    /// layer reflects all, on average).
    #[inline(always)]
    fn left(&self, e: f32) -> f32 {
        if self.base_norm > 0.0 {
            (1.0 - e).max(0.0)
        } else {
            0.0
        }
    }

    /// An estimate of its albedo for picking lobes: E(wo) + base (1 - E(wo)).
    pub fn albedo_estimate(&self, wo: Vec3) -> f32 {
        let e = self.layer_albedo(wo.z);
        e + self.base.element_sum() / 3.0 * self.left(e)
    }

    /// Whether some part is not a single direction (the base always, if it
    /// gets light).
    pub fn has_smooth_part(&self) -> bool {
        !self.ggx.is_smooth() || (self.base_norm > 0.0 && self.base != Vec3::ZERO)
    }

    /// f |cos theta_i| toward local `wi` of the rough layer and the base,
    /// and the density `sample` gives it.
    #[inline(always)]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let p = self.p_layer(wo);
        let (layer, layer_pdf) = self.eval_layer(wo, wi);
        let coupling = self.left(self.layer_albedo(wo.z)) * self.left(self.layer_albedo(wi.z));
        let base = self.base * (FRAC_1_PI * coupling * self.base_norm * wi.z);
        let pdf = p * layer_pdf + (1.0 - p) * Lambert::pdf(wi);
        (Vec3::splat(layer) + base, pdf)
    }

    /// The rough layer's D G2 F / (4 cos_o cos_i) times cos_i, and the
    /// density of its visible-normal sampling; nothing when smooth.
    #[inline(always)]
    fn eval_layer(&self, wo: Vec3, wi: Vec3) -> (f32, f32) {
        if self.ggx.is_smooth() {
            return (0.0, 0.0);
        }
        let Some(m) = (wo + wi).try_normalize() else {
            return (0.0, 0.0);
        };
        let cos = wo.dot(m);
        let f = self.fresnel(cos);
        let value = f * self.ggx.d(m) * self.ggx.g2(wo, wi) / (4.0 * wo.z);
        let pdf = self.ggx.visible_d(wo, m) / (4.0 * cos).max(f32::MIN_POSITIVE);
        (value, pdf)
    }

    /// A direction toward local `wi` (in `BsdfSample::wi`): the layer's
    /// (its mirror direction, or wo mirrored about a visible normal) or the
    /// base's (cosine-weighted), as `pick` falls; the smooth parts' weight
    /// is their f cos over the mixture's density. None below the surface.
    #[inline(always)]
    pub fn sample(&self, wo: Vec3, pick: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let p = self.p_layer(wo);
        let wi = if pick < p {
            if self.ggx.is_smooth() {
                return Some(self.mirror(wo, p));
            }
            reflect_about(wo.into(), self.ggx.sample_visible(wo, u).into()).into()
        } else {
            Lambert::sample(u)
        };
        if wi.z <= 0.0 {
            return None;
        }
        let (f, pdf) = self.eval(wo, wi);
        (pdf > 0.0).then(|| BsdfSample {
            wi,
            weight: f / pdf,
            pdf,
            specular: false,
            transmitted: false,
            eta: 1.0,
        })
    }

    /// The smooth layer's mirror direction, picked with probability `p`.
    fn mirror(&self, wo: Vec3, p: f32) -> BsdfSample {
        BsdfSample {
            wi: reflect(wo),
            weight: Vec3::splat(self.fresnel(wo.z) / p),
            pdf: p,
            specular: true,
            transmitted: false,
            eta: 1.0,
        }
    }
}
