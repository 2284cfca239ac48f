//! A dielectric interface (glass, water) that may be rough: smooth, it
//! reflects and refracts one direction each by the exact Fresnel equations
//! (as `Interface` does); rough, it is Walter et al.'s GGX microfacet BSDF
//! (2007, "Microfacet models for refraction through rough surfaces"): each
//! facet a smooth interface, the facet of a reflected pair their half
//! vector, that of a refracted pair the generalised half vector
//! n_o wo + n_i wi. Radiance crossing into a denser medium is compressed
//! into a narrower cone, so transmission is scaled by eta^2 = (n_o / n_i)^2
//! as the smooth interface's (Veach's thesis, 5.2).

use super::microfacet::{self, Ggx};
use super::specular::{mirror, refract};
use super::{BsdfSample, Sampled};
use crate::optics::fresnel_reflectance;
use crate::simd::{Mask, Real, V3};
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

    /// An estimate of its albedo for picking lobes: the smooth interface's
    /// reflected and (tinted) transmitted energies at wo.
    pub fn albedo_estimate(&self, wo: Vec3) -> f32 {
        let f = fresnel_reflectance(wo.z, self.eta);
        f + (1.0 - f) * self.tint.element_sum() / 3.0
    }

    /// f |cos theta_i| toward local `wi` (above: reflected, below:
    /// transmitted) and the density `sample` gives it (`eval_rough`);
    /// nothing when smooth.
    #[inline(always)]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        if self.is_smooth() {
            return (Vec3::ZERO, 0.0);
        }
        let (f, pdf) = eval_rough(self.lanes(), wo.into(), wi.into());
        (f.into(), pdf)
    }

    /// A direction toward local `wi` (in `BsdfSample::wi`), reflected or
    /// refracted as `pick` falls against the Fresnel-weighted chance of
    /// reflecting, through the smooth surface or a visible facet drawn by
    /// `u` (`sample_smooth`, `sample_rough`). None when the direction
    /// falls on the wrong side of the surface.
    #[inline(always)]
    pub fn sample(&self, wo: Vec3, pick: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let (r, wo) = (self.lanes(), V3::from(wo));
        match self.is_smooth() {
            true => sample_smooth(r, wo, pick),
            false => sample_rough(r, wo, pick, (u.x, u.y)),
        }
        .one()
    }

    /// Its numbers as the formulas below read them, on one lane.
    #[inline(always)]
    fn lanes(&self) -> Glass<f32> {
        Glass {
            eta: self.eta,
            alpha: self.ggx.alpha,
            tint: V3::from(self.tint),
        }
    }
}

// The interface's formulas, for any lane width (`simd::Real`): the
// one-path tracer's `Dielectric` instantiates them on f32.

/// An interface by lane: n(wo's side) / n(the far side), GGX's width (not
/// read by the smooth interface's formula) and the tint of transmitted
/// light.
#[derive(Debug, Clone, Copy)]
pub struct Glass<N: Real> {
    pub eta: N,
    pub alpha: N,
    pub tint: V3<N>,
}

/// The probability of reflecting rather than refracting at a facet whose
/// Fresnel reflectance is `f`: in proportion to the energies, F and (1 -
/// F) times the tint's mean; and where there is one (not both 0).
#[inline(always)]
pub fn p_reflect<N: Real>(f: N, tint: V3<N>) -> (N, N::Mask) {
    let t = (N::one() - f) * tint.element_sum() / N::splat(3.0);
    (f / (f + t), (f + t).gt(N::zero()))
}

/// f |cos theta_i| of `r` toward local `wi` (above: reflected, below:
/// transmitted) and the density `sample_rough` gives it; nothing for a wo
/// below the surface or a wi in it.
#[inline(always)]
pub fn eval_rough<N: Real>(r: Glass<N>, wo: V3<N>, wi: V3<N>) -> (V3<N>, N) {
    // Tested as `<=` and `==`, so that a NaN goes through as a NaN.
    let seen = !wo.z.le(N::zero()) & !wi.z.eq(N::zero());
    let reflected = wi.z.gt(N::zero());
    let (mut f, mut pdf, mut ok) = (V3::zero(), N::zero(), N::Mask::splat(false));
    // Each lobe worked out only where some lane needs it (one lane: the
    // lobe wi is in).
    if (seen & reflected).any() {
        let (f_r, pdf_r, ok_r) = eval_reflection(r, wo, wi);
        (f, pdf, ok) = (f_r, pdf_r, ok_r);
    }
    if (seen & !reflected).any() {
        let (f_t, pdf_t, ok_t) = eval_transmission(r, wo, wi);
        f = V3::select(reflected, f, f_t);
        pdf = N::select(reflected, pdf, pdf_t);
        ok = N::Mask::select(reflected, ok, ok_t);
    }
    let ok = ok & seen;
    (V3::select(ok, f, V3::zero()), N::select(ok, pdf, N::zero()))
}

/// D G2 F / (4 cos_o cos_i), times cos_i; its density the visible normal's
/// times the Jacobian 1 / (4 wo.m), times the chance of reflecting; and
/// where they hold.
#[inline(always)]
fn eval_reflection<N: Real>(r: Glass<N>, wo: V3<N>, wi: V3<N>) -> (V3<N>, N, N::Mask) {
    let x = microfacet::reflection(r.alpha, wo, wi);
    let f = fresnel_reflectance(x.cos, r.eta);
    let (p, some) = p_reflect(f, r.tint);
    let value = f * x.d * x.g2 / (N::splat(4.0) * wo.z);
    let pdf = p * x.visible / x.jacobian;
    (V3::new(value, value, value), pdf, x.half & some)
}

/// Walter et al.'s eq. 21 with the index on wo's side taken as 1 (so n_i
/// = 1 / eta): |wi.m| |wo.m| (1 - F) D G2 / (|cos_i| cos_o (wo.m + n_i
/// wi.m)^2), which carries eta^2 relative to the symmetric part; times
/// cos_i. Its density: the visible normal's times the Jacobian n_i^2
/// |wi.m| / (wo.m + n_i wi.m)^2, times the chance of refracting. Facets
/// that face away from either direction give nothing.
#[inline(always)]
fn eval_transmission<N: Real>(r: Glass<N>, wo: V3<N>, wi: V3<N>) -> (V3<N>, N, N::Mask) {
    let n_i = N::one() / r.eta;
    let (m, half) = (wo + wi * n_i).try_normalize();
    let m = V3::select(m.z.lt(N::zero()), -m, m);
    let (cos_o, cos_i) = (wo.dot(m), wi.dot(m));
    let f = fresnel_reflectance(cos_o, r.eta);
    let (p, some) = p_reflect(f, r.tint);
    let denom = cos_o + n_i * cos_i;
    let denom2 = (denom * denom).max(N::splat(f32::MIN_POSITIVE));
    let d = microfacet::d(r.alpha, m);
    let g = microfacet::g2(r.alpha, wo, wi);
    let value = (N::one() - f) * d * g * (-cos_i) * cos_o / (wo.z * denom2);
    let vis = microfacet::visible_d(r.alpha, wo, m);
    let pdf = (N::one() - p) * vis * n_i * n_i * (-cos_i) / denom2;
    let facing = !cos_o.le(N::zero()) & !cos_i.ge(N::zero());
    (r.tint * value, pdf, half & facing & some)
}

/// A normal `wo` sees, drawn by `u`, and what both lobes read of it:
/// the cosine, the Fresnel reflectance, the chance of reflecting, the
/// density of the normal; `ok` where wo sees its front.
struct Facet<N: Real> {
    m: V3<N>,
    cos: N,
    f: N,
    p: N,
    visible: N,
    ok: N::Mask,
}

#[inline(always)]
fn facet<N: Real>(r: Glass<N>, wo: V3<N>, u: (N, N)) -> Facet<N> {
    let m = microfacet::sample_visible(r.alpha, wo, u);
    let cos = wo.dot(m);
    let f = fresnel_reflectance(cos, r.eta);
    let (p, some) = p_reflect(f, r.tint);
    Facet {
        m,
        cos,
        f,
        p,
        visible: microfacet::visible_d(r.alpha, wo, m),
        ok: !cos.le(N::zero()) & some,
    }
}

/// `wo` reflected about the facet: the direction, its weight F / p
/// G1(wi), its density, and where it is above the surface.
#[inline(always)]
fn reflected<N: Real>(r: Glass<N>, wo: V3<N>, x: &Facet<N>) -> (V3<N>, V3<N>, N, N::Mask) {
    let wi = microfacet::reflect_about(wo, x.m);
    let weight = x.f / x.p * microfacet::g1(r.alpha, wi);
    let pdf = x.p * x.visible / (N::splat(4.0) * x.cos);
    (
        wi,
        V3::new(weight, weight, weight),
        pdf,
        !wi.z.le(N::zero()),
    )
}

/// `wo` refracted through the facet: the direction, its weight (1 - F) /
/// (1 - p) eta^2 G1(wi) tint, its density, and where it goes through
/// (below the surface, not past the critical angle, p below 1).
#[inline(always)]
fn refracted<N: Real>(r: Glass<N>, wo: V3<N>, x: &Facet<N>) -> (V3<N>, V3<N>, N, N::Mask) {
    let (wi, through) = microfacet::refract_about(wo, x.m, r.eta);
    let n_i = N::one() / r.eta;
    let cos_i = wi.dot(x.m);
    let denom = x.cos + n_i * cos_i;
    let jacobian = n_i * n_i * (-cos_i) / (denom * denom).max(N::splat(f32::MIN_POSITIVE));
    let g = microfacet::g1(r.alpha, wi);
    let weight = r.tint * ((N::one() - x.f) / (N::one() - x.p) * r.eta * r.eta * g);
    let pdf = (N::one() - x.p) * x.visible * jacobian;
    let ok = through & !wi.z.ge(N::zero()) & !x.p.ge(N::one());
    (wi, weight, pdf, ok)
}

/// `wo` (above the surface) reflected about or refracted through a
/// normal it sees, drawn by `u`, as `pick` falls against the chance of
/// reflecting. None (`ok` unset) when the direction falls on the wrong
/// side of the surface.
#[inline(always)]
pub fn sample_rough<N: Real>(r: Glass<N>, wo: V3<N>, pick: N, u: (N, N)) -> Sampled<N> {
    let x = facet(r, wo, u);
    let back = pick.lt(x.p);
    let mut s = Sampled::none();
    // Each lobe worked out only where some lane takes it.
    if (x.ok & back).any() {
        let (wi, weight, pdf, ok) = reflected(r, wo, &x);
        s = Sampled {
            wi,
            weight,
            pdf,
            ok,
            ..s
        };
    }
    if (x.ok & !back).any() {
        let (wi, weight, pdf, ok) = refracted(r, wo, &x);
        let through = Sampled {
            wi,
            weight,
            pdf,
            transmitted: N::Mask::splat(true),
            eta: r.eta,
            ok,
            ..s
        };
        s = Sampled::select(back, s, through);
    }
    Sampled {
        ok: x.ok & s.ok,
        ..s
    }
}

/// The smooth interface seen from local `wo` (above the surface): the
/// mirror direction with probability p (its weight F / p) or the
/// refracted one (weight (1 - F) tint eta^2 / (1 - p)) as `pick` falls,
/// the mirror's past the critical angle; the density is the probability,
/// as for every specular lobe. None (`ok` unset) where nothing comes back.
#[inline(always)]
pub fn sample_smooth<N: Real>(r: Glass<N>, wo: V3<N>, pick: N) -> Sampled<N> {
    let f = fresnel_reflectance(wo.z, r.eta);
    let (p, some) = p_reflect(f, r.tint);
    let (through, refracts) = refract(wo, r.eta);
    let crosses = !pick.lt(p) & p.lt(N::one()) & refracts;
    let back = f / p;
    let weight = r.tint * ((N::one() - f) / (N::one() - p) * r.eta * r.eta);
    Sampled {
        wi: V3::select(crosses, through, mirror(wo)),
        weight: V3::select(crosses, weight, V3::new(back, back, back)),
        pdf: N::select(crosses, N::one() - p, p),
        specular: N::Mask::splat(true),
        transmitted: crosses,
        eta: N::select(crosses, r.eta, N::one()),
        ok: some & (crosses | p.gt(N::zero())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::microfacet::tests::direction;
    use crate::sampling::Rng;
    use crate::simd::F16;

    /// Sixteen lanes give each lane's one-lane value, bit for bit: the
    /// rough interface is written once, and `Dielectric` is it on f32.
    #[test]
    fn rough_glass_in_lanes_is_the_one_lane_glass() {
        let mut rng = Rng::new(7);
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        // Samples through and back, and values of both lobes, were met.
        let (mut through, mut back, mut lit) = (0, 0, [0, 0]);
        for round in 0..300 {
            let glass: [Dielectric; 16] = std::array::from_fn(|k| {
                let etas = [1.0 / 1.5, 1.5, 1.0 / 1.33, 2.4, 1.0 / 2.4];
                let alphas = [0.002, 0.0625, 0.3, 1.0];
                let tint = Vec3::new(1.0, 0.9, 0.5) * ((k % 3) as f32 / 2.0);
                Dielectric::new(etas[(k + round) % 5], true, Ggx::new(alphas[k % 4]), tint)
            });
            let wo: [Vec3; 16] = std::array::from_fn(|k| direction(&mut rng, (k + round) % 20));
            let wi: [Vec3; 16] = std::array::from_fn(|k| direction(&mut rng, (k + 3 * round) % 20));
            let u: [Vec2; 16] = std::array::from_fn(|_| rng.square());
            let pick: [f32; 16] = std::array::from_fn(|_| rng.square().x);
            let lanes = |v: &[Vec3; 16]| V3::<F16>::from_fn(|k| v[k]);
            let r = Glass {
                eta: F16::from_fn(|k| glass[k].eta),
                alpha: F16::from_fn(|k| glass[k].ggx.alpha),
                tint: V3::<F16>::from_fn(|k| glass[k].tint),
            };
            let (f16, pdf16) = eval_rough(r, lanes(&wo), lanes(&wi));
            let u16 = (F16::from_fn(|k| u[k].x), F16::from_fn(|k| u[k].y));
            let drawn = sample_rough(r, lanes(&wo), F16::from_fn(|k| pick[k]), u16);
            for k in 0..16 {
                let case = format!("round {round}, lane {k}");
                let (f, pdf) = glass[k].eval(wo[k], wi[k]);
                assert_eq!(bits(f16.lane(k)), bits(f), "{case}");
                assert_eq!(pdf16.lane(k).to_bits(), pdf.to_bits(), "{case}");
                let one = glass[k].sample(wo[k], pick[k], u[k]);
                // The one-lane sample refuses a wo below the surface first.
                let lane = (drawn.ok.lane(k) && wo[k].z > 0.0).then(|| {
                    let w = (bits(drawn.wi.lane(k)), bits(drawn.weight.lane(k)));
                    (w, drawn.pdf.lane(k).to_bits(), drawn.transmitted.lane(k))
                });
                let one =
                    one.map(|s| ((bits(s.wi), bits(s.weight)), s.pdf.to_bits(), s.transmitted));
                assert_eq!(lane, one, "{case}");
                match one {
                    Some((.., true)) => through += 1,
                    Some((.., false)) => back += 1,
                    None => {}
                }
                if pdf > 0.0 {
                    lit[usize::from(wi[k].z < 0.0)] += 1;
                }
            }
        }
        assert!(
            through > 500 && back > 500,
            "{through} through, {back} back"
        );
        assert!(lit[0] > 1000 && lit[1] > 50, "{lit:?}");
    }

    /// The smooth interface too: sixteen lanes, each lane's one-lane
    /// sample bit for bit, through it, back, and past the critical angle.
    #[test]
    fn smooth_glass_in_lanes_is_the_one_lane_glass() {
        let mut rng = Rng::new(8);
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        let (mut through, mut back) = (0, 0);
        for round in 0..200 {
            let glass: [Dielectric; 16] = std::array::from_fn(|k| {
                let etas = [1.0 / 1.5, 1.5, 1.0 / 1.33, 2.4, 1.0005];
                let tint = Vec3::new(1.0, 0.9, 0.5) * ((k % 3) as f32 / 2.0);
                Dielectric::new(etas[(k + round) % 5], true, Ggx::new(0.0), tint)
            });
            let wo: [Vec3; 16] = std::array::from_fn(|k| direction(&mut rng, (k + round) % 20));
            let pick: [f32; 16] = std::array::from_fn(|_| rng.square().x);
            let r = Glass {
                eta: F16::from_fn(|k| glass[k].eta),
                alpha: F16::zero(),
                tint: V3::<F16>::from_fn(|k| glass[k].tint),
            };
            let wo16 = V3::<F16>::from_fn(|k| wo[k]);
            let drawn = sample_smooth(r, wo16, F16::from_fn(|k| pick[k]));
            for k in 0..16 {
                let one = glass[k].sample(wo[k], pick[k], Vec2::ZERO);
                let lane = (drawn.ok.lane(k) && wo[k].z > 0.0).then(|| {
                    let w = (bits(drawn.wi.lane(k)), bits(drawn.weight.lane(k)));
                    (w, drawn.pdf.lane(k).to_bits(), drawn.transmitted.lane(k))
                });
                let one =
                    one.map(|s| ((bits(s.wi), bits(s.weight)), s.pdf.to_bits(), s.transmitted));
                assert_eq!(lane, one, "round {round}, lane {k}");
                match one {
                    Some((.., true)) => through += 1,
                    Some((.., false)) => back += 1,
                    None => {}
                }
            }
        }
        assert!(
            through > 300 && back > 300,
            "{through} through, {back} back"
        );
    }
}
