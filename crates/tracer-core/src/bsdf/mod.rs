//! What a surface does with light in path mode, one concept per file: the
//! local frame, and the lobes the lab's materials are read as (a table in
//! the README, "Global illumination"):
//!
//! - `lambert.rs`: `diffuse`, a Lambertian albedo;
//! - `phong.rs`: `specular` and `shininess`, a normalised Blinn-Phong lobe;
//! - `specular.rs`: `reflectance`, a mirror, and glass (`transmittance`,
//!   `ior`, `fresnel`), a smooth dielectric interface.
//!
//! - `lab.rs`: their mixture, scaled so that no material gives back more
//!   light than it receives.
//!
//! The physically based material (glTF's and Blender's names), GGX
//! microfacets: `microfacet.rs` (the distribution, its shadowing and its
//! visible normals), `conductor.rs` (metal), `dielectric.rs` (rough and
//! smooth glass), `plastic.rs` (a specular layer over a Lambertian base,
//! with `specular_albedo.rs`, the layer's albedo), and `principled.rs`
//! their mixture.
//!
//! `Bsdf` is a material of either kind at one hit, in its local frame.

pub(crate) mod frame;
mod lab;
pub(crate) mod lambert;
mod phong;
mod specular;

pub mod conductor;
pub mod dielectric;
pub mod microfacet;
pub mod plastic;
pub mod principled;
pub mod specular_albedo;

pub use frame::Frame;
pub use lab::LabBsdf;
pub use lambert::Lambert;
pub use phong::BlinnPhong;
pub use specular::{mirror, refract, Interface};

use crate::geometry::SurfaceHit;
use crate::material::Material;
use crate::simd::{Mask, Real, V3};
use glam::{Vec2, Vec3};
use principled::PrincipledBsdf;

/// Material `m`'s Lambertian lobe, if that is its only lobe (no highlight,
/// mirror, glass or microfacet layer): its albedo and the chance its
/// sampling picks it (1, or 0 when it reflects nothing), as `LabBsdf`
/// builds it at any hit.
pub fn lambert_only(m: &Material) -> Option<(Vec3, f32)> {
    if matches!(m, Material::Principled(_)) {
        return None;
    }
    let hit = SurfaceHit::facing(Vec3::Z, Vec2::ZERO);
    LabBsdf::new(m, &hit, Vec3::Z).lambert_only()
}

/// A direction drawn by `Bsdf::sample`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BsdfSample {
    /// The direction, away from the surface: world from `Bsdf::sample`,
    /// local from a lobe's own.
    pub wi: Vec3,
    /// f |cos| / pdf: what the path's throughput is multiplied by.
    pub weight: Vec3,
    /// The density of the direction among the non-specular lobes' (solid
    /// angle), for multiple importance sampling; for a specular lobe, the
    /// probability it was picked.
    pub pdf: f32,
    /// Whether a specular lobe (a single direction) was picked: no light
    /// sampling could have found this direction.
    pub specular: bool,
    /// Whether the direction crossed the surface (refraction).
    pub transmitted: bool,
    /// n(wo's side) / n(wi's side): 1 but for refraction, whose weight
    /// holds its square.
    pub eta: f32,
}

/// Directions drawn by a lobe's formula on any lane width (`simd::Real`):
/// `BsdfSample`'s fields by lane, local, and where there is one (`ok`).
#[derive(Debug, Clone, Copy)]
pub struct Sampled<N: Real> {
    pub wi: V3<N>,
    pub weight: V3<N>,
    pub pdf: N,
    pub specular: N::Mask,
    pub transmitted: N::Mask,
    /// n(wo's side) / n(wi's side).
    pub eta: N,
    pub ok: N::Mask,
}

impl<N: Real> Sampled<N> {
    /// Lane by lane, `a` where `m` is set, else `b`.
    #[inline(always)]
    pub fn select(m: N::Mask, a: Sampled<N>, b: Sampled<N>) -> Sampled<N> {
        let mask = |x: N::Mask, y: N::Mask| N::Mask::select(m, x, y);
        Sampled {
            wi: V3::select(m, a.wi, b.wi),
            weight: V3::select(m, a.weight, b.weight),
            pdf: N::select(m, a.pdf, b.pdf),
            specular: mask(a.specular, b.specular),
            transmitted: mask(a.transmitted, b.transmitted),
            eta: N::select(m, a.eta, b.eta),
            ok: mask(a.ok, b.ok),
        }
    }

    /// None of them: every lane `ok` unset.
    #[inline(always)]
    pub fn none() -> Sampled<N> {
        let no = N::Mask::splat(false);
        Sampled {
            wi: V3::zero(),
            weight: V3::zero(),
            pdf: N::zero(),
            specular: no,
            transmitted: no,
            eta: N::one(),
            ok: no,
        }
    }
}

impl Sampled<f32> {
    /// The one lane's sample, if there is one.
    #[inline(always)]
    pub fn one(self) -> Option<BsdfSample> {
        self.ok.then(|| BsdfSample {
            wi: self.wi.into(),
            weight: self.weight.into(),
            pdf: self.pdf,
            specular: self.specular,
            transmitted: self.transmitted,
            eta: self.eta,
        })
    }
}

/// A material at one hit, seen along `wo`: its local frame and its lobes,
/// by lane (`simd::Real`): the one-path tracer's is `Bsdf<f32>`, which
/// holds one kind.
#[derive(Debug, Clone, Copy)]
pub struct Bsdf<N: Real = f32> {
    frame: Frame<N>,
    /// The lab materials' lobes, where some lane has one.
    lab: Option<LabBsdf<N>>,
    /// The physically based materials' lobes, where some lane has one.
    principled: Option<PrincipledBsdf<N>>,
    /// The lanes of a physically based material.
    is_principled: N::Mask,
}

impl Bsdf<f32> {
    /// Material `m` at `hit`, seen from direction `wo` (unit, away from
    /// the surface). The frame faces `wo` (opaque lobes are two-sided);
    /// glass enters at the front face.
    pub fn new(m: &Material, hit: &SurfaceHit, wo: Vec3) -> Bsdf {
        let facing = if hit.front_face { 1.0 } else { -1.0 };
        let mut frame = Frame::new(hit.shading_normal * facing);
        let mut wo_local = frame.to_local(wo);
        if wo_local.z <= 0.0 {
            // An interpolated normal turned away from the viewer: the
            // geometric one is the surface the ray really met.
            frame = Frame::new(hit.geometric_normal * facing);
            wo_local = frame.to_local(wo);
        }
        let wo_local = Vec3::new(wo_local.x, wo_local.y, wo_local.z.max(1e-7));
        let (lab, principled) = match m {
            Material::Principled(p) => {
                let at = p.at(hit);
                let params = at.params();
                let b = PrincipledBsdf::new(&params, at.base_color, wo_local, hit.front_face);
                (None, Some(b))
            }
            lab => (Some(LabBsdf::new(lab, hit, wo_local)), None),
        };
        Bsdf {
            frame,
            lab,
            principled,
            is_principled: principled.is_some(),
        }
    }

    /// Several side by side, lane `k` being `each(k)`.
    pub fn lanes<N: Real>(each: impl Fn(usize) -> Bsdf) -> Bsdf<N> {
        let all: Vec<Bsdf> = (0..N::LANES).map(&each).collect();
        let axis = |f: &dyn Fn(&Frame) -> V3<f32>| V3::from_fn(|k| f(&all[k].frame).into());
        // A lane of the other kind has any material of this one: its values
        // are not kept.
        let some_lab = all.iter().find_map(|b| b.lab);
        let some_principled = all.iter().find_map(|b| b.principled);
        Bsdf {
            frame: Frame {
                s: axis(&|f| f.s),
                t: axis(&|f| f.t),
                n: axis(&|f| f.n),
            },
            lab: some_lab.map(|any| LabBsdf::lanes(|k| all[k].lab.unwrap_or(any))),
            principled: some_principled
                .map(|any| PrincipledBsdf::lanes(|k| all[k].principled.unwrap_or(any))),
            is_principled: N::Mask::from_fn(|k| all[k].is_principled),
        }
    }

    /// The albedo of a material that is a Lambertian lobe alone, and the
    /// chance its sampling picks the lobe (1, or 0 when it reflects
    /// nothing).
    pub fn lambert_only(&self) -> Option<(Vec3, f32)> {
        self.lab.as_ref().and_then(|b| b.lambert_only())
    }

    /// The shading normal on the side the surface is seen from: the axis
    /// of its directions.
    pub fn normal(&self) -> Vec3 {
        self.frame.n.into()
    }

    /// Whether the material only reflects, and in no single direction: an
    /// opaque principled material that is not smooth (a rough metal or
    /// plastic). What it sends toward any viewer is then `eval` of the
    /// light arriving, which path reuse shares (`reuse.rs`).
    pub fn reflects_smoothly_only(&self) -> bool {
        self.principled
            .as_ref()
            .is_some_and(|b| b.reflects_smoothly_only())
    }

    /// Whether some lobe is not specular: light sampling can find its
    /// directions.
    pub fn has_smooth_lobes(&self) -> bool {
        match (&self.lab, &self.principled) {
            (Some(b), _) => b.has_smooth_lobes(),
            (_, Some(b)) => b.has_smooth_lobes(),
            _ => false,
        }
    }

    /// f |cos theta_i| toward world direction `wi`, of the smooth lobes
    /// (the specular ones are nothing in any given direction), and the
    /// density `sample` gives it (`eval_bsdf`).
    #[inline(always)]
    pub fn eval(&self, wi: Vec3) -> (Vec3, f32) {
        let (f, pdf) = eval_bsdf(self, wi.into());
        (f.into(), pdf)
    }

    /// A direction: a lobe picked by `pick`, a direction of it drawn by
    /// `u` (`sample_bsdf`). None when the material sends nothing back or
    /// the direction fell below the surface.
    #[inline(always)]
    pub fn sample(&self, pick: f32, u: Vec2) -> Option<BsdfSample> {
        sample_bsdf(self, pick, (u.x, u.y)).one()
    }
}

/// f |cos theta_i| of `b` toward world direction `wi`, of the smooth
/// lobes, and the density `sample_bsdf` gives it: each lane's material's
/// (`eval_lab`, `eval_principled`).
#[inline(always)]
pub fn eval_bsdf<N: Real>(b: &Bsdf<N>, wi: V3<N>) -> (V3<N>, N) {
    let wi = b.frame.local(wi);
    let (mut f, mut pdf) = (V3::zero(), N::zero());
    if let Some(lab) = &b.lab {
        (f, pdf) = lab::eval_lab(lab, wi);
    }
    if let Some(principled) = &b.principled {
        let (f_p, pdf_p) = principled::eval_principled(principled, wi);
        f = V3::select(b.is_principled, f_p, f);
        pdf = N::select(b.is_principled, pdf_p, pdf);
    }
    (f, pdf)
}

/// A world direction of `b`: a lobe of each lane's material picked by
/// `pick`, its direction drawn by `u` (`sample_lab`,
/// `sample_principled`). None (`ok` unset) where the material sends
/// nothing back or the direction fell below the surface.
#[inline(always)]
pub fn sample_bsdf<N: Real>(b: &Bsdf<N>, pick: N, u: (N, N)) -> Sampled<N> {
    let mut s = Sampled::none();
    if let Some(lab) = &b.lab {
        s = lab::sample_lab(lab, pick, u);
    }
    if let Some(principled) = &b.principled {
        let p = principled::sample_principled(principled, pick, u);
        s = Sampled::select(b.is_principled, p, s);
    }
    Sampled {
        wi: b.frame.world(s.wi),
        ..s
    }
}

/// What the lane tests of the mixtures share: one lane of sixteen held to
/// the one-lane material's values.
#[cfg(test)]
pub(crate) mod lane_check {
    use super::{BsdfSample, Sampled};
    use crate::simd::{Mask, Real, F16, V3};
    use glam::Vec3;

    /// What a lane test met: draws in all, specular ones, ones that went
    /// through, and values above 0.
    #[derive(Debug, Default)]
    pub(crate) struct Met {
        pub drawn: usize,
        pub specular: usize,
        pub through: usize,
        pub lit: usize,
    }

    /// Lane `k` of the lanes' value `(f16, pdf16)` and draw `s16` against
    /// the one-lane `value` and `drawn`, bit for bit (`case` names it).
    pub(crate) fn same_lane(
        k: usize,
        (f16, pdf16): (V3<F16>, F16),
        s16: &Sampled<F16>,
        (value, drawn): ((Vec3, f32), Option<BsdfSample>),
        case: &str,
        met: &mut Met,
    ) {
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        assert_eq!(bits(f16.lane(k)), bits(value.0), "{case}");
        assert_eq!(pdf16.lane(k).to_bits(), value.1.to_bits(), "{case}");
        let lane = s16.ok.lane(k).then(|| {
            let w = (bits(s16.wi.lane(k)), bits(s16.weight.lane(k)));
            let flags = (s16.specular.lane(k), s16.transmitted.lane(k));
            (
                w,
                s16.pdf.lane(k).to_bits(),
                flags,
                s16.eta.lane(k).to_bits(),
            )
        });
        let one = drawn.map(|s| {
            let w = (bits(s.wi), bits(s.weight));
            (
                w,
                s.pdf.to_bits(),
                (s.specular, s.transmitted),
                s.eta.to_bits(),
            )
        });
        assert_eq!(lane, one, "{case}");
        if let Some(s) = drawn {
            met.drawn += 1;
            met.specular += usize::from(s.specular);
            met.through += usize::from(s.transmitted);
        }
        met.lit += usize::from(value.1 > 0.0);
    }
}

#[cfg(test)]
mod tests {
    use super::lane_check::{same_lane, Met};
    use super::*;
    use crate::bsdf::microfacet::tests::direction;
    use crate::material::PrincipledMaterial;
    use crate::sampling::Rng;
    use crate::simd::F16;

    /// Sixteen lanes of lab and physically based materials at hits of
    /// every orientation (shading normals turned from the geometric ones,
    /// back faces) give each lane's one-lane `Bsdf`, bit for bit, in world
    /// directions.
    #[test]
    fn materials_of_both_kinds_in_lanes_are_the_one_lane_bsdf() {
        let mut rng = Rng::new(14);
        let mut met = Met::default();
        for round in 0..300 {
            let one: [Bsdf; 16] = std::array::from_fn(|k| {
                let m = if (k + round) % 2 == 0 {
                    lab::tests::material(&mut rng, k + 5 * round)
                } else {
                    let p = principled::tests::material(&mut rng, k + 5 * round);
                    Material::Principled(Box::new(PrincipledMaterial::new(p, Vec3::ZERO)))
                };
                let n = direction(&mut rng, 5 + k).normalize_or(Vec3::Y);
                let mut hit = SurfaceHit::facing(n, Vec2::ZERO);
                let tilt = direction(&mut rng, 6 + k) * 0.3;
                hit.shading_normal = (n + tilt).normalize_or(n);
                hit.front_face = (k + round) % 3 > 0;
                Bsdf::new(&m, &hit, direction(&mut rng, 7 + k).normalize_or(Vec3::Z))
            });
            let wi: [Vec3; 16] = std::array::from_fn(|k| direction(&mut rng, (k + 3 * round) % 20));
            let u: [Vec2; 16] = std::array::from_fn(|_| rng.square());
            let pick: [f32; 16] = std::array::from_fn(|_| rng.square().x);
            let b16 = Bsdf::lanes::<F16>(|k| one[k]);
            let (f16, pdf16) = eval_bsdf(&b16, V3::<F16>::from_fn(|k| wi[k]));
            let u16 = (F16::from_fn(|k| u[k].x), F16::from_fn(|k| u[k].y));
            let s16 = sample_bsdf(&b16, F16::from_fn(|k| pick[k]), u16);
            for k in 0..16 {
                let case = format!("round {round}, lane {k}: {:?}", one[k]);
                let value = one[k].eval(wi[k]);
                let drawn = one[k].sample(pick[k], u[k]);
                same_lane(k, (f16, pdf16), &s16, (value, drawn), &case, &mut met);
            }
        }
        let enough = met.specular > 200 && met.through > 200 && met.lit > 1000;
        assert!(enough && met.drawn > 2000, "{met:?}");
    }
}
