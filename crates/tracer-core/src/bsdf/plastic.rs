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
use super::lambert::lambert_pdf;
use super::microfacet::{self, reflect_about, Ggx};
use super::specular::mirror;
use super::specular_albedo::{table, Layer, SpecularAlbedo};
use super::{BsdfSample, Sampled};
use crate::sampling::warp::cosine_hemisphere;
use crate::simd::{Mask, Real, V3};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// A layer of index `ior` (outside 1) over a base of albedo `base`, by
/// lane (`simd::Real`): the one-path tracer's is `Plastic<f32>`.
#[derive(Clone, Copy)]
pub struct Plastic<N: Real = f32> {
    base: V3<N>,
    /// The layer's reflectance at normal incidence.
    f0: N,
    alpha: N,
    /// Where the layer is a mirror (a single direction).
    smooth: N::Mask,
    table: &'static SpecularAlbedo,
    /// Each lane's place in the table.
    layer: N::Array<Layer>,
    /// 1 / (1 - E_avg), or 0 if the layer leaves nothing to the base.
    base_norm: N,
}

impl<N: Real> std::fmt::Debug for Plastic<N> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Plastic")
            .field("base", &self.base)
            .field("f0", &self.f0)
            .field("alpha", &self.alpha)
            .field("base_norm", &self.base_norm)
            .finish_non_exhaustive()
    }
}

impl Plastic<f32> {
    /// Base colour `base`, the layer's index `ior` (outside 1) and width.
    pub fn new(base: Vec3, ior: f32, ggx: Ggx) -> Plastic {
        let f0 = ((ior - 1.0) / (ior + 1.0)).powi(2);
        let f0 = if f0.is_nan() { 1.0 } else { f0.min(1.0) };
        let layer = SpecularAlbedo::layer(ggx, f0);
        let table = table();
        let room = 1.0 - table.mean(&layer);
        Plastic {
            base: base.into(),
            f0,
            alpha: ggx.alpha,
            smooth: ggx.is_smooth(),
            table,
            layer: [layer],
            base_norm: if room > 1e-4 { 1.0 / room } else { 0.0 },
        }
    }

    /// Sixteen (or any number of) layers side by side, lane `k` being
    /// `each(k)`.
    pub fn lanes<N: Real>(mut each: impl FnMut(usize) -> Plastic) -> Plastic<N> {
        let all: Vec<Plastic> = (0..N::LANES).map(&mut each).collect();
        let mut layer = <N::Array<Layer>>::default();
        let mut smooth = N::Mask::splat(false);
        for (k, p) in all.iter().enumerate() {
            layer[k] = p.layer[0];
            smooth.set_lane(k, p.smooth);
        }
        Plastic {
            base: V3::from_fn(|k| all[k].base.into()),
            f0: N::from_fn(|k| all[k].f0),
            alpha: N::from_fn(|k| all[k].alpha),
            smooth,
            table: all[0].table,
            layer,
            base_norm: N::from_fn(|k| all[k].base_norm),
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
        !self.smooth || (self.base_norm > 0.0 && Vec3::from(self.base) != Vec3::ZERO)
    }

    /// f |cos theta_i| toward local `wi` of the rough layer and the base,
    /// and the density `sample` gives it (`eval_layered`).
    #[inline(always)]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        // What the lanes' mask would give, without working it out.
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let (f, pdf) = eval_layered(self, wo.into(), wi.into());
        (f.into(), pdf)
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
        sample_layered(self, wo.into(), pick, (u.x, u.y)).one()
    }
}

// The layered lobe's formulas, for any lane width: the one-path tracer's
// `Plastic` is them on f32.

impl<N: Real> Plastic<N> {
    /// E(cos): the light the layer reflects (one scattering, from the
    /// table, raised by its margin), read a lane at a time.
    #[inline(always)]
    fn layer_albedo(&self, cos: N) -> N {
        N::from_fn(|k| self.table.albedo(&self.layer[k], cos.lane(k)))
    }

    /// Schlick's F of a facet seen at `cos`.
    #[inline(always)]
    fn fresnel(&self, cos: N) -> N {
        self.f0 + (N::one() - self.f0) * schlick_weight(cos)
    }

    /// The probability of sampling the layer rather than the base, in
    /// proportion to their albedos at wo (the layer's `e_o`).
    #[inline(always)]
    fn p_layer(&self, e_o: N) -> N {
        let base = self.base.element_sum() / 3.0 * self.left(e_o);
        let some = (e_o + base).gt(N::zero());
        N::select(some, e_o / (e_o + base), N::one())
    }

    /// What the layer of albedo `e` leaves to the base (nothing if the
    /// layer reflects all, on average).
    #[inline(always)]
    fn left(&self, e: N) -> N {
        let room = self.base_norm.gt(N::zero());
        N::select(room, (N::one() - e).max(N::zero()), N::zero())
    }

    /// The rough layer's D G2 F / (4 cos_o cos_i) times cos_i, and the
    /// density of its visible-normal sampling; nothing when smooth.
    #[inline(always)]
    fn eval_layer(&self, wo: V3<N>, wi: V3<N>) -> (N, N) {
        let x = microfacet::reflection(self.alpha, wo, wi);
        let value = self.fresnel(x.cos) * x.d * x.g2 / (N::splat(4.0) * wo.z);
        let pdf = x.visible / x.jacobian;
        let rough = x.half & !self.smooth;
        (
            N::select(rough, value, N::zero()),
            N::select(rough, pdf, N::zero()),
        )
    }

    /// wo mirrored about a normal it sees, drawn by `u`.
    #[inline(always)]
    fn layer_direction(&self, wo: V3<N>, u: (N, N)) -> V3<N> {
        reflect_about(wo, microfacet::sample_visible(self.alpha, wo, u))
    }

    /// `eval_layered` with the layer's albedo at wo, `e_o`, already read.
    #[inline(always)]
    fn eval_seen(&self, e_o: N, wo: V3<N>, wi: V3<N>) -> (V3<N>, N) {
        let p_layer = self.p_layer(e_o);
        let (layer, layer_pdf) = self.eval_layer(wo, wi);
        let coupling = self.left(e_o) * self.left(self.layer_albedo(wi.z));
        let base = self.base * (N::splat(FRAC_1_PI) * coupling * self.base_norm * wi.z);
        let pdf = p_layer * layer_pdf + (N::one() - p_layer) * lambert_pdf(wi.z);
        // Tested as `<=`, so that a NaN goes through as a NaN.
        let above = !wo.z.le(N::zero()) & !wi.z.le(N::zero());
        (
            V3::select(above, V3::new(layer, layer, layer) + base, V3::zero()),
            N::select(above, pdf, N::zero()),
        )
    }

    /// `wi` drawn by a part that is not a single direction: its weight the
    /// whole's f cos over the whole's density, where that is above 0.
    #[inline(always)]
    fn sampled(&self, e_o: N, wo: V3<N>, wi: V3<N>) -> Sampled<N> {
        let (f, pdf) = self.eval_seen(e_o, wo, wi);
        Sampled {
            wi,
            weight: f / pdf,
            pdf,
            ok: !wi.z.le(N::zero()) & pdf.gt(N::zero()),
            ..Sampled::none()
        }
    }

    /// The smooth layer's mirror direction, picked with probability `p`.
    #[inline(always)]
    fn mirror(&self, wo: V3<N>, p: N) -> Sampled<N> {
        let weight = self.fresnel(wo.z) / p;
        Sampled {
            wi: mirror(wo),
            weight: V3::new(weight, weight, weight),
            pdf: p,
            specular: N::Mask::splat(true),
            ok: N::Mask::splat(true),
            ..Sampled::none()
        }
    }
}

/// f |cos theta_i| of `p` toward local `wi`, the rough layer's and the
/// base's, and the density `sample_layered` gives it; nothing where wo or
/// wi is below the surface.
#[inline(always)]
pub fn eval_layered<N: Real>(p: &Plastic<N>, wo: V3<N>, wi: V3<N>) -> (V3<N>, N) {
    p.eval_seen(p.layer_albedo(wo.z), wo, wi)
}

/// A direction of `p` from local `wo` (above the surface): the layer's or
/// the base's as `pick` falls against the chance of the layer, drawn by
/// `u` (the smooth layer's mirror direction is specular). None (`ok`
/// unset) below the surface. Each part is worked out only where some lane
/// takes it.
#[inline(always)]
pub fn sample_layered<N: Real>(p: &Plastic<N>, wo: V3<N>, pick: N, u: (N, N)) -> Sampled<N> {
    let e_o = p.layer_albedo(wo.z);
    let p_layer = p.p_layer(e_o);
    let on_layer = pick.lt(p_layer);
    let specular = on_layer & p.smooth;
    let (on_facet, on_base) = (on_layer & !p.smooth, !on_layer);
    let mut wi = V3::zero();
    if on_facet.any() {
        wi = p.layer_direction(wo, u);
    }
    if on_base.any() {
        wi = V3::select(on_base, cosine_hemisphere(u), wi);
    }
    let mut s = Sampled::none();
    if (on_facet | on_base).any() {
        s = p.sampled(e_o, wo, wi);
    }
    if specular.any() {
        s = Sampled::select(specular, p.mirror(wo, p_layer), s);
    }
    Sampled {
        ok: s.ok & !wo.z.le(N::zero()),
        ..s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::microfacet::tests::direction;
    use crate::sampling::Rng;
    use crate::simd::F16;

    /// Sixteen lanes give each lane's one-lane value, bit for bit: the
    /// layered lobe is written once, and `Plastic` is it on f32.
    #[test]
    fn plastic_in_lanes_is_the_one_lane_plastic() {
        let mut rng = Rng::new(11);
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        // Mirror, layer and base samples were all met, and values.
        let (mut mirror, mut drawn_ok, mut lit) = (0, 0, 0);
        for round in 0..300 {
            let one: [Plastic; 16] = std::array::from_fn(|k| {
                let iors = [1.5, 1.0, 1.33, 2.4, 0.5];
                let roughness = [0.0, 0.25, 0.6, 1.0, 0.01];
                let base = Vec3::new(1.0, 0.7, 0.2) * ((k % 3) as f32 / 2.0);
                let ggx = Ggx::from_roughness(roughness[(k + round) % 5]);
                Plastic::new(base, iors[(k + 2 * round) % 5], ggx)
            });
            let wo: [Vec3; 16] = std::array::from_fn(|k| direction(&mut rng, (k + round) % 20));
            let wi: [Vec3; 16] = std::array::from_fn(|k| direction(&mut rng, (k + 3 * round) % 20));
            let u: [Vec2; 16] = std::array::from_fn(|_| rng.square());
            let pick: [f32; 16] = std::array::from_fn(|_| rng.square().x);
            let lanes = |v: &[Vec3; 16]| V3::<F16>::from_fn(|k| v[k]);
            let p16 = Plastic::lanes::<F16>(|k| one[k]);
            let (f16, pdf16) = eval_layered(&p16, lanes(&wo), lanes(&wi));
            let u16 = (F16::from_fn(|k| u[k].x), F16::from_fn(|k| u[k].y));
            let s16 = sample_layered(&p16, lanes(&wo), F16::from_fn(|k| pick[k]), u16);
            for k in 0..16 {
                let case = format!("round {round}, lane {k}");
                let (f, pdf) = one[k].eval(wo[k], wi[k]);
                assert_eq!(bits(f16.lane(k)), bits(f), "{case}");
                assert_eq!(pdf16.lane(k).to_bits(), pdf.to_bits(), "{case}");
                let drawn = one[k].sample(wo[k], pick[k], u[k]);
                let lane = s16.ok.lane(k).then(|| {
                    let w = (bits(s16.wi.lane(k)), bits(s16.weight.lane(k)));
                    (w, s16.pdf.lane(k).to_bits(), s16.specular.lane(k))
                });
                let drawn =
                    drawn.map(|s| ((bits(s.wi), bits(s.weight)), s.pdf.to_bits(), s.specular));
                assert_eq!(lane, drawn, "{case}");
                mirror += usize::from(matches!(drawn, Some((.., true))));
                drawn_ok += usize::from(drawn.is_some());
                lit += usize::from(pdf > 0.0);
            }
        }
        assert!(
            mirror > 100 && drawn_ok > 1500,
            "{mirror} mirrored, {drawn_ok} drawn"
        );
        assert!(lit > 1000, "{lit}");
    }
}
