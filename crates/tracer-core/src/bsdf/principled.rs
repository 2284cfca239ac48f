//! The physically based ("principled") material, with glTF 2.0's and
//! Blender's names: a mixture of three lobes,
//!
//! - `metallic`: a metal (`conductor.rs`) whose colour at normal incidence
//!   is `base_color` (Schlick's approximation);
//! - `(1 - metallic) transmission`: a dielectric interface of index `ior`
//!   (`dielectric.rs`), its transmitted light tinted by `base_color` as
//!   glTF's `KHR_materials_transmission` does;
//! - `(1 - metallic) (1 - transmission)`: an opaque dielectric
//!   (`plastic.rs`), a specular layer of index `ior` over a Lambertian base
//!   of `base_color` that gets what the layer leaves.
//!
//! All three are GGX of alpha = roughness^2, mirrors below a roughness of
//! about 0.03. Each lobe gives back at most what it receives, so their
//! convex mixture does too. Directions are local (z = the shading normal
//! turned toward the viewer).

use super::conductor::Conductor;
use super::dielectric::Dielectric;
use super::microfacet::Ggx;
use super::plastic::Plastic;
use super::BsdfSample;
pub use crate::material::Principled;
use glam::{Vec2, Vec3};

/// The lobes in their order in `PrincipledBsdf`'s arrays.
const CONDUCTOR: usize = 0;
const DIELECTRIC: usize = 1;
const PLASTIC: usize = 2;

/// The largest f32 below 1: a lobe's own `pick`, rescaled from the
/// mixture's, must stay in [0, 1).
const BELOW_ONE: f32 = 1.0 - f32::EPSILON / 2.0;

/// The principled material at one hit, seen along `wo`.
#[derive(Debug, Clone, Copy)]
pub struct PrincipledBsdf {
    /// Toward the viewer, local (z > 0).
    wo: Vec3,
    conductor: Conductor,
    dielectric: Dielectric,
    /// None where its weight is 0 (a metal, glass): never asked then.
    plastic: Option<Plastic>,
    /// Each lobe's share of the mixture.
    weight: [f32; 3],
    /// The probability of sampling each: its share times an estimate of
    /// its albedo at wo, normalised (all 0 if nothing comes back).
    prob: [f32; 3],
}

impl PrincipledBsdf {
    /// Material `params` with the colour `base_color` at the hit (textured
    /// or `params.base_color`), seen from local `wo` (z = the shading
    /// normal turned toward wo; a z at or below 0 is lifted just above it),
    /// `front_face` if wo is outside the object (the dielectric then
    /// enters it). Colours are clamped to [0, 1] and the weights too.
    pub fn new(params: &Principled, base_color: Vec3, wo: Vec3, front_face: bool) -> Self {
        let wo = Vec3::new(wo.x, wo.y, wo.z.max(1e-7))
            .try_normalize()
            .unwrap_or(Vec3::Z);
        let color = base_color.max(Vec3::ZERO).min(Vec3::ONE);
        let ggx = Ggx::from_roughness(unit(params.roughness));
        let ior = if params.ior.is_finite() && params.ior > 0.0 {
            params.ior
        } else {
            1.0
        };
        let conductor = Conductor { f0: color, ggx };
        let dielectric = Dielectric::new(ior, front_face, ggx, color);
        let (metallic, transmission) = (unit(params.metallic), unit(params.transmission));
        let weight = [
            metallic,
            (1.0 - metallic) * transmission,
            (1.0 - metallic) * (1.0 - transmission),
        ];
        // Its table's look-ups cost a tenth of a metal's or glass's hit.
        let plastic = (weight[PLASTIC] > 0.0).then(|| Plastic::new(color, ior, ggx));
        // A lobe of no weight is never picked: its estimate is not needed.
        let estimate = |lobe: usize, albedo: &dyn Fn() -> f32| {
            if weight[lobe] > 0.0 {
                albedo()
            } else {
                0.0
            }
        };
        let albedo = [
            estimate(CONDUCTOR, &|| conductor.albedo_estimate()),
            estimate(DIELECTRIC, &|| dielectric.albedo_estimate(wo)),
            plastic.map_or(0.0, |p| p.albedo_estimate(wo)),
        ];
        let mut prob = [0.0; 3];
        let total: f32 = (0..3).map(|i| weight[i] * albedo[i]).sum();
        if total > 0.0 {
            prob = [0, 1, 2].map(|i| weight[i] * albedo[i] / total);
        }
        PrincipledBsdf {
            wo,
            conductor,
            dielectric,
            plastic,
            weight,
            prob,
        }
    }

    /// Whether some lobe that can be sampled is not a single direction:
    /// light sampling can find its directions.
    pub fn has_smooth_lobes(&self) -> bool {
        (self.prob[CONDUCTOR] > 0.0 && !self.conductor.is_smooth())
            || (self.prob[DIELECTRIC] > 0.0 && !self.dielectric.is_smooth())
            || (self.prob[PLASTIC] > 0.0
                && self.plastic.as_ref().is_some_and(|p| p.has_smooth_part()))
    }

    /// Whether no lobe transmits and none is a single direction (the
    /// lobes share one roughness), and some reflects.
    pub fn reflects_smoothly_only(&self) -> bool {
        self.prob[DIELECTRIC] == 0.0
            && !self.conductor.is_smooth()
            && self.prob.iter().any(|&p| p > 0.0)
    }

    /// f |cos theta_i| toward local `wi` (below the surface: transmitted)
    /// of the lobes that are not single directions, and the density
    /// `sample` gives it.
    #[inline(always)]
    pub fn eval(&self, wi: Vec3) -> (Vec3, f32) {
        let (mut f, mut pdf) = (Vec3::ZERO, 0.0);
        for lobe in 0..3 {
            if self.prob[lobe] > 0.0 {
                let (lf, lpdf) = self.eval_lobe(lobe, wi);
                f += self.weight[lobe] * lf;
                pdf += self.prob[lobe] * lpdf;
            }
        }
        (f, pdf)
    }

    #[inline(always)]
    fn eval_lobe(&self, lobe: usize, wi: Vec3) -> (Vec3, f32) {
        match lobe {
            CONDUCTOR => self.conductor.eval(self.wo, wi),
            DIELECTRIC => self.dielectric.eval(self.wo, wi),
            _ => self
                .plastic
                .as_ref()
                .map_or((Vec3::ZERO, 0.0), |p| p.eval(self.wo, wi)),
        }
    }

    /// A local direction (in `BsdfSample::wi`): a lobe picked by `pick`
    /// with its probability, the rest of `pick` and `u` its direction. A
    /// single direction's weight is its lobe's over the probability of the
    /// lobe (its pdf that probability times its own); any other's is the
    /// mixture's f |cos| over the mixture's density. None when the
    /// material sends nothing back or the direction fell on the wrong side.
    #[inline(always)]
    pub fn sample(&self, pick: f32, u: Vec2) -> Option<BsdfSample> {
        let (lobe, pick) = self.pick_lobe(pick)?;
        let s = match lobe {
            CONDUCTOR => self.conductor.sample(self.wo, u),
            DIELECTRIC => self.dielectric.sample(self.wo, pick, u),
            _ => self
                .plastic
                .as_ref()
                .and_then(|p| p.sample(self.wo, pick, u)),
        }?;
        if s.specular {
            let p = self.prob[lobe];
            return Some(BsdfSample {
                weight: s.weight * (self.weight[lobe] / p),
                pdf: s.pdf * p,
                ..s
            });
        }
        let (f, pdf) = self.eval(s.wi);
        (pdf > 0.0).then_some(BsdfSample {
            weight: f / pdf,
            pdf,
            ..s
        })
    }

    /// The lobe `pick` falls in, and where in it (rescaled to [0, 1)).
    #[inline(always)]
    fn pick_lobe(&self, pick: f32) -> Option<(usize, f32)> {
        let mut low = 0.0;
        let last = (0..3).rev().find(|&i| self.prob[i] > 0.0)?;
        for lobe in 0..3 {
            let p = self.prob[lobe];
            if p > 0.0 && (pick < low + p || lobe == last) {
                return Some((lobe, ((pick - low) / p).clamp(0.0, BELOW_ONE)));
            }
            low += p;
        }
        None
    }
}

/// `x` clamped to [0, 1], a NaN to 0.
fn unit(x: f32) -> f32 {
    if x.is_nan() {
        0.0
    } else {
        x.clamp(0.0, 1.0)
    }
}
