//! A dielectric interface (glass, water) that may be rough: smooth, it
//! reflects and refracts one direction each by the exact Fresnel equations
//! (as `Interface` does); rough, it is Walter et al.'s GGX microfacet BSDF
//! (2007, "Microfacet models for refraction through rough surfaces"): each
//! facet a smooth interface, the facet of a reflected pair their half
//! vector, that of a refracted pair the generalised half vector
//! n_o wo + n_i wi. Radiance crossing into a denser medium is compressed
//! into a narrower cone, so transmission is scaled by eta^2 = (n_o / n_i)^2
//! as the smooth interface's (Veach's thesis, 5.2).

use super::microfacet::{reflect_about, refract_about, Ggx};
use super::specular::{reflect, refract};
use super::BsdfSample;
use crate::optics::fresnel_reflectance;
use glam::{Vec2, Vec3};

/// Closer than this to 1, `eta` makes the interface smooth whatever its
/// roughness: every facet then lets light straight through, a single
/// direction (and the generalised half vector of that pair vanishes).
const INDEX_MATCHED: f32 = 1e-3;

/// An interface between the side of `wo` and the far side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dielectric {
    /// n(wo's side) / n(the far side).
    pub eta: f32,
    pub ggx: Ggx,
    /// What multiplies transmitted light (glTF's transmission takes the
    /// base colour); reflection is not tinted.
    pub tint: Vec3,
}

impl Dielectric {
    /// An object of index `ior` in a medium of index 1, seen from outside
    /// when its front face was hit (eta = 1 / ior, entering) and from
    /// inside otherwise (eta = ior, leaving).
    pub fn new(ior: f32, front_face: bool, ggx: Ggx, tint: Vec3) -> Dielectric {
        Dielectric {
            eta: if front_face { 1.0 / ior } else { ior },
            ggx,
            tint,
        }
    }

    /// Whether both its lobes are single directions.
    pub fn is_smooth(&self) -> bool {
        self.ggx.is_smooth() || (self.eta - 1.0).abs() < INDEX_MATCHED
    }

    /// The probability of reflecting rather than refracting at a facet
    /// whose Fresnel reflectance is `f`: in proportion to the energies,
    /// F and (1 - F) times the tint's mean. None if both are 0.
    #[inline(always)]
    fn p_reflect(&self, f: f32) -> Option<f32> {
        let t = (1.0 - f) * self.tint.element_sum() / 3.0;
        (f + t > 0.0).then(|| f / (f + t))
    }

    /// An estimate of its albedo for picking lobes: the smooth interface's
    /// reflected and (tinted) transmitted energies at wo.
    pub fn albedo_estimate(&self, wo: Vec3) -> f32 {
        let f = fresnel_reflectance(wo.z, self.eta);
        f + (1.0 - f) * self.tint.element_sum() / 3.0
    }

    /// f |cos theta_i| toward local `wi` (above: reflected, below:
    /// transmitted) and the density `sample` gives it; nothing when smooth.
    #[inline(always)]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        if self.is_smooth() || wo.z <= 0.0 || wi.z == 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        if wi.z > 0.0 {
            self.eval_reflection(wo, wi)
        } else {
            self.eval_transmission(wo, wi)
        }
    }

    /// D G2 F / (4 cos_o cos_i), times cos_i; its density the visible
    /// normal's times the Jacobian 1 / (4 wo.m), times the chance of
    /// reflecting.
    #[inline(always)]
    fn eval_reflection(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        let Some(m) = (wo + wi).try_normalize() else {
            return (Vec3::ZERO, 0.0);
        };
        let cos = wo.dot(m);
        let f = fresnel_reflectance(cos, self.eta);
        let Some(p) = self.p_reflect(f) else {
            return (Vec3::ZERO, 0.0);
        };
        let d = self.ggx.d(m);
        let value = f * d * self.ggx.g2(wo, wi) / (4.0 * wo.z);
        let pdf = p * self.ggx.visible_d(wo, m) / (4.0 * cos).max(f32::MIN_POSITIVE);
        (Vec3::splat(value), pdf)
    }

    /// Walter et al.'s eq. 21 with the index on wo's side taken as 1 (so
    /// n_i = 1 / eta): |wi.m| |wo.m| (1 - F) D G2 / (|cos_i| cos_o
    /// (wo.m + n_i wi.m)^2), which carries eta^2 relative to the
    /// symmetric part; times cos_i. Its density: the visible normal's times
    /// the Jacobian n_i^2 |wi.m| / (wo.m + n_i wi.m)^2, times the chance of
    /// refracting. Facets that face away from either direction give nothing.
    #[inline(always)]
    fn eval_transmission(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        let n_i = 1.0 / self.eta;
        let Some(mut m) = (wo + n_i * wi).try_normalize() else {
            return (Vec3::ZERO, 0.0);
        };
        if m.z < 0.0 {
            m = -m;
        }
        let (cos_o, cos_i) = (wo.dot(m), wi.dot(m));
        if cos_o <= 0.0 || cos_i >= 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let f = fresnel_reflectance(cos_o, self.eta);
        let Some(p) = self.p_reflect(f) else {
            return (Vec3::ZERO, 0.0);
        };
        let denom = cos_o + n_i * cos_i;
        let denom2 = (denom * denom).max(f32::MIN_POSITIVE);
        let d = self.ggx.d(m);
        let g = self.ggx.g2(wo, wi);
        let value = (1.0 - f) * d * g * (-cos_i) * cos_o / (wo.z * denom2);
        let pdf = (1.0 - p) * self.ggx.visible_d(wo, m) * n_i * n_i * (-cos_i) / denom2;
        (self.tint * value, pdf)
    }

    /// A direction toward local `wi` (in `BsdfSample::wi`), reflected or
    /// refracted as `pick` falls against the Fresnel-weighted chance of
    /// reflecting, through the smooth surface or a visible facet drawn by
    /// `u`. None when the direction falls on the wrong side of the surface.
    #[inline(always)]
    pub fn sample(&self, wo: Vec3, pick: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        if self.is_smooth() {
            return self.sample_smooth(wo, pick);
        }
        let m = self.ggx.sample_visible(wo, u);
        let cos = wo.dot(m);
        if cos <= 0.0 {
            return None;
        }
        let f = fresnel_reflectance(cos, self.eta);
        let p = self.p_reflect(f)?;
        if pick < p {
            let wi: Vec3 = reflect_about(wo.into(), m.into()).into();
            if wi.z <= 0.0 {
                return None;
            }
            return Some(BsdfSample {
                wi,
                weight: Vec3::splat(f / p * self.ggx.g2_over_g1(wo, wi)),
                pdf: p * self.ggx.visible_d(wo, m) / (4.0 * cos),
                specular: false,
                transmitted: false,
                eta: 1.0,
            });
        }
        let wi = refract_about(wo, m, self.eta)?;
        if wi.z >= 0.0 || p >= 1.0 {
            return None;
        }
        let n_i = 1.0 / self.eta;
        let cos_i = wi.dot(m);
        let denom = cos + n_i * cos_i;
        let jacobian = n_i * n_i * (-cos_i) / (denom * denom).max(f32::MIN_POSITIVE);
        let g = self.ggx.g2_over_g1(wo, wi);
        Some(BsdfSample {
            wi,
            weight: self.tint * ((1.0 - f) / (1.0 - p) * self.eta * self.eta * g),
            pdf: (1.0 - p) * self.ggx.visible_d(wo, m) * jacobian,
            specular: false,
            transmitted: true,
            eta: self.eta,
        })
    }

    /// The smooth interface: the mirror direction with probability p (its
    /// weight F / p) or the refracted one (weight (1 - F) tint eta^2 /
    /// (1 - p)); the density is the probability, as for every specular
    /// lobe.
    fn sample_smooth(&self, wo: Vec3, pick: f32) -> Option<BsdfSample> {
        let f = fresnel_reflectance(wo.z, self.eta);
        let p = self.p_reflect(f)?;
        if pick >= p && p < 1.0 {
            if let Some(wi) = refract(wo, self.eta) {
                return Some(BsdfSample {
                    wi,
                    weight: self.tint * ((1.0 - f) / (1.0 - p) * self.eta * self.eta),
                    pdf: 1.0 - p,
                    specular: true,
                    transmitted: true,
                    eta: self.eta,
                });
            }
        }
        (p > 0.0).then(|| BsdfSample {
            wi: reflect(wo),
            weight: Vec3::splat(f / p),
            pdf: p,
            specular: true,
            transmitted: false,
            eta: 1.0,
        })
    }
}
