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
pub use specular::{reflect, refract, Interface};

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

/// A material at one hit, seen along `wo`: its local frame and its lobes.
#[derive(Debug, Clone, Copy)]
pub struct Bsdf {
    frame: Frame,
    kind: Kind,
}

#[derive(Debug, Clone, Copy)]
#[allow(clippy::large_enum_variant)]
enum Kind {
    Lab(LabBsdf),
    Principled(PrincipledBsdf),
}

impl Bsdf {
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
        let kind = match m {
            Material::Principled(p) => {
                let at = p.at(hit);
                Kind::Principled(PrincipledBsdf::new(
                    &at.params(),
                    at.base_color,
                    wo_local,
                    hit.front_face,
                ))
            }
            lab => Kind::Lab(LabBsdf::new(lab, hit, wo_local)),
        };
        Bsdf { frame, kind }
    }

    /// The albedo of a material that is a Lambertian lobe alone, and the
    /// chance its sampling picks the lobe (1, or 0 when it reflects
    /// nothing).
    pub fn lambert_only(&self) -> Option<(Vec3, f32)> {
        match &self.kind {
            Kind::Lab(b) => b.lambert_only(),
            Kind::Principled(_) => None,
        }
    }

    /// The shading normal on the side the surface is seen from: the axis
    /// of its directions.
    pub fn normal(&self) -> Vec3 {
        self.frame.n
    }

    /// Whether the material only reflects, and in no single direction: an
    /// opaque principled material that is not smooth (a rough metal or
    /// plastic). What it sends toward any viewer is then `eval` of the
    /// light arriving, which path reuse shares (`reuse.rs`).
    pub fn reflects_smoothly_only(&self) -> bool {
        match &self.kind {
            Kind::Lab(_) => false,
            Kind::Principled(b) => b.reflects_smoothly_only(),
        }
    }

    /// Whether some lobe is not specular: light sampling can find its
    /// directions.
    pub fn has_smooth_lobes(&self) -> bool {
        match &self.kind {
            Kind::Lab(b) => b.has_smooth_lobes(),
            Kind::Principled(b) => b.has_smooth_lobes(),
        }
    }

    /// f |cos theta_i| toward world direction `wi`, of the smooth lobes
    /// (the specular ones are nothing in any given direction), and the
    /// density `sample` gives it.
    #[inline(always)]
    pub fn eval(&self, wi: Vec3) -> (Vec3, f32) {
        let wi = self.frame.to_local(wi);
        match &self.kind {
            Kind::Lab(b) => b.eval(wi),
            Kind::Principled(b) => b.eval(wi),
        }
    }

    /// A direction: a lobe picked by `pick`, a direction of it drawn by
    /// `u`. None when the material sends nothing back or the direction
    /// fell below the surface.
    #[inline(always)]
    pub fn sample(&self, pick: f32, u: Vec2) -> Option<BsdfSample> {
        let sample = match &self.kind {
            Kind::Lab(b) => b.sample(pick, u),
            Kind::Principled(b) => b.sample(pick, u),
        }?;
        Some(BsdfSample {
            wi: self.frame.to_world(sample.wi),
            ..sample
        })
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
