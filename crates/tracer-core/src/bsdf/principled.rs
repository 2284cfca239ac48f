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

use super::conductor::{self, Conductor};
use super::dielectric::{self, Dielectric, Glass};
use super::microfacet::Ggx;
use super::plastic::{eval_layered, sample_layered, Plastic};
use super::{BsdfSample, Sampled};
pub use crate::material::Principled;
use crate::simd::{Mask, Real, V3};
use glam::{Vec2, Vec3};

/// The lobes in their order in `PrincipledBsdf`'s arrays.
const CONDUCTOR: usize = 0;
const DIELECTRIC: usize = 1;
const PLASTIC: usize = 2;

/// The largest f32 below 1: a lobe's own `pick`, rescaled from the
/// mixture's, must stay in [0, 1).
const BELOW_ONE: f32 = 1.0 - f32::EPSILON / 2.0;

/// The principled material at one hit, seen along `wo`, by lane
/// (`simd::Real`): the one-path tracer's is `PrincipledBsdf<f32>`.
#[derive(Debug, Clone, Copy)]
pub struct PrincipledBsdf<N: Real = f32> {
    /// Toward the viewer, local (z > 0).
    wo: V3<N>,
    /// The metal's colour at normal incidence.
    f0: V3<N>,
    /// The dielectric; its GGX width is every lobe's.
    glass: Glass<N>,
    /// Where the metal is a mirror.
    smooth: N::Mask,
    /// Where the dielectric's lobes are single directions.
    glass_smooth: N::Mask,
    /// None where no lane weighs it (a metal, glass): never asked then.
    plastic: Option<Plastic<N>>,
    /// Each lobe's share of the mixture.
    weight: [N; 3],
    /// The probability of sampling each: its share times an estimate of
    /// its albedo at wo, normalised (all 0 if nothing comes back).
    prob: [N; 3],
}

impl PrincipledBsdf<f32> {
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
            wo: wo.into(),
            f0: color.into(),
            glass: Glass {
                eta: dielectric.eta,
                alpha: ggx.alpha,
                tint: color.into(),
            },
            smooth: conductor.is_smooth(),
            glass_smooth: dielectric.is_smooth(),
            plastic,
            weight,
            prob,
        }
    }

    /// Several materials side by side, lane `k` being `each(k)`.
    pub fn lanes<N: Real>(mut each: impl FnMut(usize) -> PrincipledBsdf) -> PrincipledBsdf<N> {
        let all: Vec<PrincipledBsdf> = (0..N::LANES).map(&mut each).collect();
        let mask = |f: &dyn Fn(&PrincipledBsdf) -> bool| N::Mask::from_fn(|k| f(&all[k]));
        let number = |f: &dyn Fn(&PrincipledBsdf) -> f32| N::from_fn(|k| f(&all[k]));
        let vector = |f: &dyn Fn(&PrincipledBsdf) -> V3<f32>| V3::from_fn(|k| f(&all[k]).into());
        // A lane without the layer has it of no weight: any layer will do.
        let some_plastic = all.iter().find_map(|b| b.plastic);
        PrincipledBsdf {
            wo: vector(&|b| b.wo),
            f0: vector(&|b| b.f0),
            glass: Glass {
                eta: number(&|b| b.glass.eta),
                alpha: number(&|b| b.glass.alpha),
                tint: vector(&|b| b.glass.tint),
            },
            smooth: mask(&|b| b.smooth),
            glass_smooth: mask(&|b| b.glass_smooth),
            plastic: some_plastic.map(|any| Plastic::lanes(|k| all[k].plastic.unwrap_or(any))),
            weight: [0, 1, 2].map(|i| number(&|b| b.weight[i])),
            prob: [0, 1, 2].map(|i| number(&|b| b.prob[i])),
        }
    }

    /// Whether some lobe that can be sampled is not a single direction:
    /// light sampling can find its directions.
    pub fn has_smooth_lobes(&self) -> bool {
        (self.prob[CONDUCTOR] > 0.0 && !self.smooth)
            || (self.prob[DIELECTRIC] > 0.0 && !self.glass_smooth)
            || (self.prob[PLASTIC] > 0.0
                && self.plastic.as_ref().is_some_and(|p| p.has_smooth_part()))
    }

    /// Whether no lobe transmits and none is a single direction (the
    /// lobes share one roughness), and some reflects.
    pub fn reflects_smoothly_only(&self) -> bool {
        self.prob[DIELECTRIC] == 0.0 && !self.smooth && self.prob.iter().any(|&p| p > 0.0)
    }

    /// f |cos theta_i| toward local `wi` (below the surface: transmitted)
    /// of the lobes that are not single directions, and the density
    /// `sample` gives it (`eval_principled`).
    #[inline(always)]
    pub fn eval(&self, wi: Vec3) -> (Vec3, f32) {
        let (f, pdf) = eval_principled(self, wi.into());
        (f.into(), pdf)
    }

    /// A local direction (in `BsdfSample::wi`), a lobe picked by `pick`
    /// (`sample_principled`).
    #[inline(always)]
    pub fn sample(&self, pick: f32, u: Vec2) -> Option<BsdfSample> {
        sample_principled(self, pick, (u.x, u.y)).one()
    }
}

// The mixture's formulas, for any lane width: each lobe is worked out only
// where some lane needs it (one lane: only its own).

impl<N: Real> PrincipledBsdf<N> {
    /// Lobe `lobe`'s f |cos theta_i| toward `wi` and its density, where
    /// `need`; nothing elsewhere, nor where it is a single direction.
    #[inline(always)]
    fn eval_lobe(&self, lobe: usize, wi: V3<N>, need: N::Mask) -> (V3<N>, N) {
        let none = (V3::zero(), N::zero());
        let masked = |ok: N::Mask, (f, pdf): (V3<N>, N)| {
            (V3::select(ok, f, V3::zero()), N::select(ok, pdf, N::zero()))
        };
        match lobe {
            CONDUCTOR if (need & !self.smooth & !wi.z.le(N::zero())).any() => {
                let f = conductor::eval_rough(self.f0, self.glass.alpha, self.wo, wi);
                masked(!self.smooth, f)
            }
            DIELECTRIC if (need & !self.glass_smooth).any() => masked(
                !self.glass_smooth,
                dielectric::eval_rough(self.glass, self.wo, wi),
            ),
            PLASTIC => match &self.plastic {
                Some(p) if need.any() => eval_layered(p, self.wo, wi),
                _ => none,
            },
            _ => none,
        }
    }

    /// The lobe `pick` falls in (a mask a lobe), where in it (rescaled to
    /// [0, 1)), and where some lobe can be picked.
    #[inline(always)]
    fn pick_lobe(&self, pick: N) -> ([N::Mask; 3], N, N::Mask) {
        let positive = self.prob.map(|p| p.gt(N::zero()));
        let last = [
            positive[0] & !positive[1] & !positive[2],
            positive[1] & !positive[2],
            positive[2],
        ];
        let no = N::Mask::splat(false);
        let (mut low, mut chosen, mut rest, mut picked) = (N::zero(), no, N::zero(), [no; 3]);
        for lobe in 0..3 {
            let p = self.prob[lobe];
            let here = !chosen & positive[lobe] & (pick.lt(low + p) | last[lobe]);
            rest = N::select(here, ((pick - low) / p).clamp(0.0, BELOW_ONE), rest);
            picked[lobe] = here;
            chosen = chosen | here;
            low = low + p;
        }
        (picked, rest, chosen)
    }

    /// The picked lobe's own draw: `wo` toward a direction of it.
    #[inline(always)]
    fn sample_lobe(&self, picked: [N::Mask; 3], pick: N, u: (N, N)) -> Sampled<N> {
        let (wo, [metal, glass, plastic]) = (self.wo, picked);
        let mut s = Sampled::none();
        if (metal & self.smooth).any() {
            s = conductor::sample_mirror(self.f0, wo);
        }
        if (metal & !self.smooth).any() {
            let rough = conductor::sample_rough(self.f0, self.glass.alpha, wo, u);
            s = Sampled::select(self.smooth, s, rough);
        }
        if (glass & self.glass_smooth).any() {
            let smooth = dielectric::sample_smooth(self.glass, wo, pick);
            s = Sampled::select(glass, smooth, s);
        }
        if (glass & !self.glass_smooth).any() {
            let rough = dielectric::sample_rough(self.glass, wo, pick, u);
            s = Sampled::select(glass & !self.glass_smooth, rough, s);
        }
        if let Some(p) = self.plastic.as_ref().filter(|_| plastic.any()) {
            s = Sampled::select(plastic, sample_layered(p, wo, pick, u), s);
        }
        s
    }
}

/// f |cos theta_i| of `b` toward local `wi` (below the surface:
/// transmitted) of the lobes that are not single directions, and the
/// density `sample_principled` gives it.
#[inline(always)]
pub fn eval_principled<N: Real>(b: &PrincipledBsdf<N>, wi: V3<N>) -> (V3<N>, N) {
    let (mut f, mut pdf) = (V3::zero(), N::zero());
    for lobe in 0..3 {
        let need = b.prob[lobe].gt(N::zero());
        if need.any() {
            let (lf, lpdf) = b.eval_lobe(lobe, wi, need);
            f = V3::select(need, f + lf * b.weight[lobe], f);
            pdf = N::select(need, pdf + b.prob[lobe] * lpdf, pdf);
        }
    }
    (f, pdf)
}

/// A local direction of `b`: a lobe picked by `pick` with its
/// probability, the rest of `pick` and `u` its direction. A single
/// direction's weight is its lobe's over the probability of the lobe (its
/// pdf that probability times its own), as is that of a lobe that is the
/// whole mixture; any other's is the mixture's f |cos| over the mixture's
/// density. None (`ok` unset) where the material
/// sends nothing back or the direction fell on the wrong side.
#[inline(always)]
pub fn sample_principled<N: Real>(b: &PrincipledBsdf<N>, pick: N, u: (N, N)) -> Sampled<N> {
    let (picked, pick, some) = b.pick_lobe(pick);
    let s = b.sample_lobe(picked, pick, u);
    let [metal, glass, _] = picked;
    let of_lobe = |v: [N; 3]| N::select(metal, v[0], N::select(glass, v[1], v[2]));
    let p = of_lobe(b.prob);
    let mut out = Sampled {
        weight: s.weight * (of_lobe(b.weight) / p),
        pdf: s.pdf * p,
        ..s
    };
    // Where one lobe is the whole mixture, its draw's weight and density
    // are already the mixture's (its f |cos| over its density, equal but
    // for rounding): not worked out again (4 % of the materials scene).
    let alone = p.eq(N::one());
    // The lanes whose draw's own weight and density stand.
    let own = s.specular | alone;
    out.ok = out.ok & (s.specular | !alone | out.pdf.gt(N::zero()));
    let remix = some & s.ok & !own;
    if remix.any() {
        let (f, pdf) = eval_principled(b, s.wi);
        let mixed = Sampled {
            weight: f / pdf,
            pdf,
            ok: s.ok & pdf.gt(N::zero()),
            ..s
        };
        out = Sampled::select(own, out, mixed);
    }
    Sampled {
        ok: out.ok & some,
        ..out
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

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::bsdf::lane_check::{same_lane, Met};
    use crate::bsdf::microfacet::tests::direction;
    use crate::sampling::Rng;
    use crate::simd::F16;

    /// A material of the mixture drawn by `rng`: pure lobes, mixtures of
    /// two or three, smooth and rough, now and then out of range.
    pub(crate) fn material(rng: &mut Rng, k: usize) -> Principled {
        let shares = [0.0, 1.0, 0.5, rng.square().x, 1.5];
        let roughness = [0.0, 0.2, 0.6, 1.0, rng.square().y];
        let (a, b) = (rng.square(), rng.square());
        Principled {
            base_color: Vec3::new(a.x, a.y, b.x) * ((k % 3) as f32 / 2.0),
            metallic: shares[k % 5],
            roughness: roughness[(k / 5) % 5],
            ior: [1.5, 1.0, 2.4, 1.33][k % 4],
            transmission: shares[(k / 2) % 5],
        }
    }

    /// Sixteen lanes of different materials give each lane's one-lane
    /// value, bit for bit: the mixture is written once, and
    /// `PrincipledBsdf` is it on f32.
    #[test]
    fn principled_in_lanes_is_the_one_lane_principled() {
        let mut rng = Rng::new(12);
        let mut met = Met::default();
        for round in 0..400 {
            let one: [PrincipledBsdf; 16] = std::array::from_fn(|k| {
                let params = material(&mut rng, k + 7 * round);
                let wo = direction(&mut rng, (k + round) % 20);
                PrincipledBsdf::new(&params, params.base_color, wo, (k + round) % 3 > 0)
            });
            let wi: [Vec3; 16] = std::array::from_fn(|k| direction(&mut rng, (k + 3 * round) % 20));
            let u: [Vec2; 16] = std::array::from_fn(|_| rng.square());
            let pick: [f32; 16] = std::array::from_fn(|_| rng.square().x);
            let b16 = PrincipledBsdf::lanes::<F16>(|k| one[k]);
            let (f16, pdf16) = eval_principled(&b16, V3::<F16>::from_fn(|k| wi[k]));
            let u16 = (F16::from_fn(|k| u[k].x), F16::from_fn(|k| u[k].y));
            let s16 = sample_principled(&b16, F16::from_fn(|k| pick[k]), u16);
            for k in 0..16 {
                let case = format!("round {round}, lane {k}: {:?}", one[k]);
                let value = one[k].eval(wi[k]);
                let drawn = one[k].sample(pick[k], u[k]);
                same_lane(k, (f16, pdf16), &s16, (value, drawn), &case, &mut met);
            }
        }
        let enough = met.specular > 300 && met.through > 300 && met.lit > 2000;
        assert!(enough && met.drawn > 3000, "{met:?}");
    }
}
