//! The lab's materials read physically: a mixture of a Lambertian lobe
//! (`diffuse`), a normalised Blinn-Phong lobe (`specular`, `shininess`) and
//! a mirror (`reflectance`) or glass (`transmittance`, `ior`, `fresnel`),
//! each picked for sampling in proportion to its albedo, their albedos
//! scaled down together where they add up to more than 1.

use super::lambert::{lambert_f, lambert_pdf};
use super::phong::{phong_direction, phong_f, phong_pdf};
use super::specular::sample_interface;
use super::{BsdfSample, Interface, Sampled};
use crate::geometry::SurfaceHit;
use crate::material::{albedo_sum, Glass, Material};
use crate::sampling::warp::cosine_hemisphere;
use crate::simd::{Mask, Real, V3};
use glam::{Vec2, Vec3};

/// A lab material at one hit, seen along `wo`: its lobes, in the hit's
/// local frame, by lane (`simd::Real`): the one-path tracer's is
/// `LabBsdf<f32>`.
#[derive(Debug, Clone, Copy)]
pub struct LabBsdf<N: Real = f32> {
    /// The direction toward the viewer, local (z > 0).
    wo: V3<N>,
    /// The Lambertian lobe's albedo.
    albedo: V3<N>,
    /// The Blinn-Phong lobe's colour and exponent.
    specular: V3<N>,
    shininess: N,
    interface: Interface<N>,
    /// Probabilities of picking the Lambertian and the Blinn-Phong lobe;
    /// the interface has the rest.
    p_lambert: N,
    p_phong: N,
}

impl LabBsdf<f32> {
    /// Lab material `m` (`Phong` or `Glass`) at `hit`, seen from local
    /// `wo_local` (z > 0). Opaque lobes are two-sided: the frame faces `wo`.
    pub fn new(m: &Material, hit: &SurfaceHit, wo_local: Vec3) -> LabBsdf {
        let (surface, interface) = match m {
            Material::Glass(g) => (&g.surface, glass_interface(g, wo_local, hit.front_face)),
            _ => {
                let p = m.surface();
                (p, Interface::mirror(p.reflectance))
            }
        };
        let (diffuse, specular) = surface.textured(hit);
        let scale = 1.0 / albedo_sum(m).max(1.0);
        let interface = Interface {
            reflected: interface.reflected * scale,
            transmitted: interface.transmitted * scale,
            ..interface
        };
        let (albedo, specular) = (diffuse * scale, specular * scale);
        let weights = [
            albedo.element_sum(),
            specular.element_sum(),
            3.0 * interface.total(),
        ];
        let total: f32 = weights.iter().sum();
        let (p_lambert, p_phong) = if total > 0.0 {
            (weights[0] / total, weights[1] / total)
        } else {
            (0.0, 0.0)
        };
        LabBsdf {
            wo: wo_local.into(),
            albedo: albedo.into(),
            specular: specular.into(),
            shininess: surface.shininess,
            interface,
            p_lambert,
            p_phong,
        }
    }

    /// Several side by side, lane `k` being `each(k)`.
    pub fn lanes<N: Real>(each: impl Fn(usize) -> LabBsdf) -> LabBsdf<N> {
        let all: Vec<LabBsdf> = (0..N::LANES).map(each).collect();
        let vector = |f: &dyn Fn(&LabBsdf) -> V3<f32>| V3::from_fn(|k| f(&all[k]).into());
        let number = |f: &dyn Fn(&LabBsdf) -> f32| N::from_fn(|k| f(&all[k]));
        LabBsdf {
            wo: vector(&|b| b.wo),
            albedo: vector(&|b| b.albedo),
            specular: vector(&|b| b.specular),
            shininess: number(&|b| b.shininess),
            interface: Interface::lanes(|k| all[k].interface),
            p_lambert: number(&|b| b.p_lambert),
            p_phong: number(&|b| b.p_phong),
        }
    }

    /// The Lambertian lobe's albedo and the probability of picking it, if
    /// it is the only lobe (no highlight, mirror or glass): the material
    /// as `integrate::path::matte_lanes` traces it. The probability is then 1, or
    /// 0 for a material that reflects nothing.
    pub(crate) fn lambert_only(&self) -> Option<(Vec3, f32)> {
        let alone = self.p_phong == 0.0 && self.interface.total() == 0.0;
        let whole = self.p_lambert == 1.0 || self.p_lambert == 0.0;
        (alone && whole).then_some((self.albedo.into(), self.p_lambert))
    }

    /// Whether some lobe is not specular: light sampling can find its
    /// directions.
    pub fn has_smooth_lobes(&self) -> bool {
        self.p_lambert + self.p_phong > 0.0
    }

    /// f |cos theta_i| toward local direction `wi`, of the smooth lobes
    /// (the specular ones are nothing in any given direction), and the
    /// density `sample` gives it (`eval_lab`).
    #[inline(always)]
    pub fn eval(&self, wi: Vec3) -> (Vec3, f32) {
        let (f, pdf) = eval_lab(self, wi.into());
        (f.into(), pdf)
    }

    /// A direction: a lobe picked by `pick`, a direction of it drawn by
    /// `u` (`sample_lab`). None when the material sends nothing back or
    /// the direction fell below the surface.
    #[inline(always)]
    pub fn sample(&self, pick: f32, u: Vec2) -> Option<BsdfSample> {
        sample_lab(self, pick, (u.x, u.y)).one()
    }
}

// The mixture's formulas, for any lane width: a lobe is worked out only
// where some lane needs it.

impl<N: Real> LabBsdf<N> {
    /// f of the smooth lobes toward local `wi` (above the surface); a lobe
    /// never picked (of albedo 0) is not evaluated.
    #[inline(always)]
    fn smooth_f(&self, wi: V3<N>) -> V3<N> {
        let mut f = V3::zero();
        let (lambert, phong) = (self.p_lambert.gt(N::zero()), self.p_phong.gt(N::zero()));
        if lambert.any() {
            f = V3::select(lambert, f + lambert_f(self.albedo, wi.z), f);
        }
        if phong.any() {
            let lobe = phong_f(self.specular, self.shininess, self.wo, wi);
            f = V3::select(phong, f + lobe, f);
        }
        f
    }

    /// The density of local `wi` among the smooth lobes, each weighted by
    /// the probability of picking it.
    #[inline(always)]
    fn smooth_pdf(&self, wi: V3<N>) -> N {
        let mut pdf = N::zero();
        let (lambert, phong) = (self.p_lambert.gt(N::zero()), self.p_phong.gt(N::zero()));
        if lambert.any() {
            pdf = N::select(lambert, pdf + self.p_lambert * lambert_pdf(wi.z), pdf);
        }
        if phong.any() {
            let lobe = self.p_phong * phong_pdf(self.shininess, self.wo, wi);
            pdf = N::select(phong, pdf + lobe, pdf);
        }
        pdf
    }

    /// The smooth lobes' direction: the Lambertian's where `pick` falls in
    /// its share, else the highlight's.
    #[inline(always)]
    fn sample_smooth(&self, pick: N, u: (N, N)) -> Sampled<N> {
        let on_lambert = pick.lt(self.p_lambert);
        let (mut wi, mut drawn) = (V3::zero(), N::Mask::splat(true));
        if on_lambert.any() {
            wi = cosine_hemisphere(u);
        }
        if (!on_lambert).any() {
            let (towards, above) = phong_direction(self.shininess, self.wo, u);
            wi = V3::select(on_lambert, wi, towards);
            drawn = on_lambert | above;
        }
        let (f, pdf) = (self.smooth_f(wi), self.smooth_pdf(wi));
        Sampled {
            wi,
            weight: f * (wi.z / pdf),
            pdf,
            ok: drawn & !(pdf.le(N::zero()) | wi.z.le(N::zero())),
            ..Sampled::none()
        }
    }

    /// The specular lobe's direction, picked reflected or refracted by `u`.
    #[inline(always)]
    fn sample_specular(&self, u: N) -> Sampled<N> {
        let p = N::one() - self.p_lambert - self.p_phong;
        let (wi, weight, transmitted, ok) =
            sample_interface(&self.interface, self.wo, u.min(N::one()));
        let weight = weight / p;
        Sampled {
            wi,
            weight: V3::new(weight, weight, weight),
            pdf: p,
            specular: N::Mask::splat(true),
            transmitted,
            eta: N::select(transmitted, self.interface.eta, N::one()),
            ok,
        }
    }
}

/// f |cos theta_i| of `b` toward local direction `wi`, of the smooth
/// lobes, and the density `sample_lab` gives it; nothing below the
/// surface.
#[inline(always)]
pub fn eval_lab<N: Real>(b: &LabBsdf<N>, wi: V3<N>) -> (V3<N>, N) {
    let above = !wi.z.le(N::zero());
    if above.none() {
        return (V3::zero(), N::zero());
    }
    let (f, pdf) = (b.smooth_f(wi) * wi.z, b.smooth_pdf(wi));
    (
        V3::select(above, f, V3::zero()),
        N::select(above, pdf, N::zero()),
    )
}

/// A direction of `b`: a lobe picked by `pick`, a direction of it drawn by
/// `u`. None (`ok` unset) where the material sends nothing back or the
/// direction fell below the surface.
#[inline(always)]
pub fn sample_lab<N: Real>(b: &LabBsdf<N>, pick: N, u: (N, N)) -> Sampled<N> {
    let smooth = b.p_lambert + b.p_phong;
    let specular = pick.ge(smooth);
    let mut s = Sampled::none();
    if (!specular).any() {
        s = b.sample_smooth(pick, u);
    }
    if specular.any() {
        let rest = (pick - smooth) / (N::one() - smooth);
        s = Sampled::select(specular, b.sample_specular(rest), s);
    }
    s
}

/// Glass's interface for local `wo`: entering when the front face was
/// hit (the outside's index taken as 1, as Whitted mode does).
fn glass_interface(g: &Glass, wo: Vec3, front_face: bool) -> Interface {
    let eta = if front_face { 1.0 / g.ior } else { g.ior };
    Interface::new(wo, eta, g.fresnel, g.surface.reflectance, g.transmittance)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::bsdf::lane_check::{same_lane, Met};
    use crate::bsdf::microfacet::tests::direction;
    use crate::material::Phong;
    use crate::sampling::Rng;
    use crate::simd::F16;

    /// A lab material drawn by `rng`: matte, highlights of several
    /// exponents, mirrors, glass with and without Fresnel, too bright ones.
    pub(crate) fn material(rng: &mut Rng, k: usize) -> Material {
        let (a, b) = (rng.square(), rng.square());
        let surface = Phong {
            diffuse: Vec3::new(a.x, a.y, b.x) * [0.0, 0.5, 1.0, 1.5][k % 4],
            specular: Vec3::splat(b.y) * [0.0, 1.0, 0.3][k % 3],
            shininess: [1.0, 10.0, 100.0, 1000.0][(k / 3) % 4],
            reflectance: [0.0, 0.0, 0.5, 1.0][(k / 2) % 4],
            ..Phong::default_grey()
        };
        match k % 5 {
            0 | 1 => Material::Glass(Glass {
                surface,
                transmittance: [1.0, 0.6][k % 2],
                ior: [1.5, 2.4, 1.33][k % 3],
                fresnel: k % 10 < 5,
                absorption: Vec3::ZERO,
            }),
            _ => Material::Phong(surface),
        }
    }

    /// Sixteen lanes of different lab materials give each lane's one-lane
    /// value, bit for bit: the mixture is written once, and `LabBsdf` is it
    /// on f32.
    #[test]
    fn a_lab_material_in_lanes_is_the_one_lane_material() {
        let mut rng = Rng::new(13);
        let mut met = Met::default();
        for round in 0..400 {
            let one: [LabBsdf; 16] = std::array::from_fn(|k| {
                let m = material(&mut rng, k + 7 * round);
                let mut hit = SurfaceHit::facing(Vec3::Z, Vec2::ZERO);
                hit.front_face = (k + round) % 3 > 0;
                let wo = direction(&mut rng, (k + round) % 20);
                let wo = Vec3::new(wo.x, wo.y, wo.z.abs().max(1e-7));
                LabBsdf::new(&m, &hit, wo)
            });
            let wi: [Vec3; 16] = std::array::from_fn(|k| direction(&mut rng, (k + 3 * round) % 20));
            let u: [Vec2; 16] = std::array::from_fn(|_| rng.square());
            let pick: [f32; 16] = std::array::from_fn(|_| rng.square().x);
            let b16 = LabBsdf::lanes::<F16>(|k| one[k]);
            let (f16, pdf16) = eval_lab(&b16, V3::<F16>::from_fn(|k| wi[k]));
            let u16 = (F16::from_fn(|k| u[k].x), F16::from_fn(|k| u[k].y));
            let s16 = sample_lab(&b16, F16::from_fn(|k| pick[k]), u16);
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
