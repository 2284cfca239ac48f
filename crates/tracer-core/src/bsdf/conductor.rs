//! A metal: a mirror, or a rough surface of GGX microfacets that are
//! mirrors, each reflecting by Schlick's approximation of a conductor's
//! Fresnel term with its colour at normal incidence F0 (the principled
//! material's `base_color`, as glTF 2.0 takes it).

use super::microfacet::{self, Ggx};
use super::specular::mirror;
use super::{BsdfSample, Sampled};
use crate::simd::{Mask, Real, V3};
use glam::{Vec2, Vec3};

/// Schlick's approximation: F0 + (1 - F0)(1 - cos)^5.
#[inline(always)]
pub fn schlick<N: Real>(f0: V3<N>, cos: N) -> V3<N> {
    f0 + (V3::splat(Vec3::ONE) - f0) * schlick_weight(cos)
}

/// (1 - cos)^5, Schlick's share of 1 - F0 at `cos`.
#[inline(always)]
pub fn schlick_weight<N: Real>(cos: N) -> N {
    let c = N::one() - cos.clamp(0.0, 1.0);
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

    /// f |cos theta_i| toward local `wi` and the density `sample` gives it
    /// (`eval_rough`); nothing for a mirror (its lobe is a single
    /// direction).
    #[inline(always)]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        // What the lanes' mask would give, without working it out.
        if self.is_smooth() || wo.z <= 0.0 || wi.z <= 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        let (f, pdf) = eval_rough(V3::from(self.f0), self.ggx.alpha, wo.into(), wi.into());
        (f.into(), pdf)
    }

    /// A direction toward local `wi` (in `BsdfSample::wi`): the mirror's,
    /// or wo mirrored about a visible normal (`sample_rough`). None when
    /// the reflection falls below the surface.
    #[inline(always)]
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let f0 = V3::from(self.f0);
        match self.is_smooth() {
            true => sample_mirror(f0, wo.into()),
            false => sample_rough(f0, self.ggx.alpha, wo.into(), (u.x, u.y)),
        }
        .one()
    }
}

// The lobe's formulas, for any lane width (`simd::Real`): the
// one-path tracer's `Conductor` instantiates them on f32.

/// The rough metal of reflectance `f0` and GGX width `alpha`: f |cos
/// theta_i| toward local `wi`, the microfacet BRDF D G2 F / (4 cos_o
/// cos_i) with F at the half vector, and the density `sample_rough` gives
/// it; nothing where `wo` or `wi` is below the surface.
#[inline(always)]
pub fn eval_rough<N: Real>(f0: V3<N>, alpha: N, wo: V3<N>, wi: V3<N>) -> (V3<N>, N) {
    let r = microfacet::reflection(alpha, wo, wi);
    let f = schlick(f0, r.cos) * (r.d * r.g2 / (N::splat(4.0) * wo.z));
    let pdf = r.visible / r.jacobian;
    // Tested as `<=`, so that a NaN goes through as a NaN.
    let above = !wo.z.le(N::zero()) & !wi.z.le(N::zero()) & r.half;
    (
        V3::select(above, f, V3::zero()),
        N::select(above, pdf, N::zero()),
    )
}

/// The mirror of reflectance `f0` seen from local `wo`: its one
/// direction, weighted by Schlick's F at wo.
#[inline(always)]
pub fn sample_mirror<N: Real>(f0: V3<N>, wo: V3<N>) -> Sampled<N> {
    Sampled {
        wi: mirror(wo),
        weight: schlick(f0, wo.z),
        pdf: N::one(),
        specular: N::Mask::splat(true),
        ok: N::Mask::splat(true),
        ..Sampled::none()
    }
}

/// `wo` (above the surface) mirrored about a normal it sees, drawn by `u`:
/// weight F G2 / G1(wo) = F G1(wi). None (`ok` unset) when the reflection
/// falls below the surface.
#[inline(always)]
pub fn sample_rough<N: Real>(f0: V3<N>, alpha: N, wo: V3<N>, u: (N, N)) -> Sampled<N> {
    let m = microfacet::sample_visible(alpha, wo, u);
    let cos = wo.dot(m);
    let wi = microfacet::reflect_about(wo, m);
    Sampled {
        wi,
        weight: schlick(f0, cos) * microfacet::g1(alpha, wi),
        pdf: microfacet::visible_d(alpha, wo, m) / (N::splat(4.0) * cos),
        ok: !wi.z.le(N::zero()) & !cos.le(N::zero()),
        ..Sampled::none()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::microfacet::tests::direction;
    use crate::sampling::Rng;
    use crate::simd::{Mask, F16};

    /// Sixteen lanes give each lane's one-lane value, bit for bit: the
    /// rough lobe is written once, and `Conductor` is it on f32.
    #[test]
    fn a_rough_metal_in_lanes_is_the_one_lane_metal() {
        let mut rng = Rng::new(5);
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        for round in 0..300 {
            let alphas = [0.002, 0.0625, 0.3, 1.0];
            let alpha: [f32; 16] = std::array::from_fn(|k| alphas[(k + round) % 4]);
            let f0: [Vec3; 16] =
                std::array::from_fn(|k| Vec3::new(1.0, 0.78, 0.34) * (k as f32 / 15.0));
            let wo: [Vec3; 16] = std::array::from_fn(|k| direction(&mut rng, (k + round) % 20));
            let wi: [Vec3; 16] = std::array::from_fn(|k| direction(&mut rng, (k + 3 * round) % 20));
            let u: [Vec2; 16] = std::array::from_fn(|_| rng.square());
            let lanes = |v: &[Vec3; 16]| V3::<F16>::from_fn(|k| v[k]);
            let a = F16::from_fn(|k| alpha[k]);
            let (f16, pdf16) = eval_rough(lanes(&f0), a, lanes(&wo), lanes(&wi));
            let u16 = (F16::from_fn(|k| u[k].x), F16::from_fn(|k| u[k].y));
            let drawn = sample_rough(lanes(&f0), a, lanes(&wo), u16);
            for k in 0..16 {
                let metal = Conductor {
                    f0: f0[k],
                    ggx: Ggx::new(alpha[k]),
                };
                let case = format!("round {round}, lane {k}");
                let (f, pdf) = metal.eval(wo[k], wi[k]);
                assert_eq!(bits(f16.lane(k)), bits(f), "{case}");
                assert_eq!(pdf16.lane(k).to_bits(), pdf.to_bits(), "{case}");
                let one = metal.sample(wo[k], u[k]);
                // The one-lane sample refuses a wo below the surface first.
                let lane = (drawn.ok.lane(k) && wo[k].z > 0.0).then(|| {
                    (
                        bits(drawn.wi.lane(k)),
                        bits(drawn.weight.lane(k)),
                        drawn.pdf.lane(k).to_bits(),
                    )
                });
                let one = one.map(|s| (bits(s.wi), bits(s.weight), s.pdf.to_bits()));
                assert_eq!(lane, one, "{case}");
            }
        }
    }
}
