//! What a surface does with light in path mode, one concept per file: the
//! local frame, and the lobes the lab's materials are read as (a table in
//! the README, "Global illumination"):
//!
//! - `lambert.rs`: `diffuse`, a Lambertian albedo;
//! - `phong.rs`: `specular` and `shininess`, a normalised Blinn-Phong lobe;
//! - `specular.rs`: `reflectance`, a mirror, and glass (`transmittance`,
//!   `ior`, `fresnel`), a smooth dielectric interface.
//!
//! `Bsdf` is a material at one hit: the mixture of its lobes, each picked
//! for sampling in proportion to its albedo. The lobes' albedos are scaled
//! down together where they add up to more than 1, so no material gives
//! back more light than it receives.

mod frame;
mod lambert;
mod phong;
mod specular;

pub mod conductor;
pub mod dielectric;
pub mod microfacet;
pub mod plastic;
pub mod principled;
pub mod specular_albedo;

pub use frame::Frame;
pub use lambert::Lambert;
pub use phong::BlinnPhong;
pub use specular::{reflect, refract, Interface};

use crate::geometry::SurfaceHit;
use crate::material::{Glass, Material, Phong};
use glam::{Vec2, Vec3};

/// A direction drawn by `Bsdf::sample`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BsdfSample {
    /// The world direction, away from the surface.
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

/// A material at one hit, seen along `wo`.
#[derive(Debug, Clone, Copy)]
pub struct Bsdf {
    frame: Frame,
    /// The direction toward the viewer, local (z >= 0).
    wo: Vec3,
    lambert: Lambert,
    phong: BlinnPhong,
    interface: Interface,
    /// Probabilities of picking the Lambertian and the Blinn-Phong lobe;
    /// the interface has the rest.
    p_lambert: f32,
    p_phong: f32,
}

impl Bsdf {
    /// Material `m` at `hit`, seen from direction `wo` (unit, away from
    /// the surface). Opaque lobes are two-sided: the frame faces `wo`.
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
        let (surface, interface) = match m {
            Material::Phong(p) => (p, mirror(p.reflectance)),
            Material::Glass(g) => (&g.surface, glass_interface(g, wo_local, hit.front_face)),
        };
        let (diffuse, specular) = textured(surface, hit);
        let scale = 1.0 / albedo_sum(m).max(1.0);
        let interface = Interface {
            reflected: interface.reflected * scale,
            transmitted: interface.transmitted * scale,
            ..interface
        };
        let lambert = Lambert {
            albedo: diffuse * scale,
        };
        let phong = BlinnPhong {
            specular: specular * scale,
            shininess: surface.shininess,
        };
        let weights = [
            lambert.albedo.element_sum(),
            phong.specular.element_sum(),
            3.0 * interface.total(),
        ];
        let total: f32 = weights.iter().sum();
        let (p_lambert, p_phong) = if total > 0.0 {
            (weights[0] / total, weights[1] / total)
        } else {
            (0.0, 0.0)
        };
        Bsdf {
            frame,
            wo: wo_local,
            lambert,
            phong,
            interface,
            p_lambert,
            p_phong,
        }
    }

    /// Whether some lobe is not specular: light sampling can find its
    /// directions.
    pub fn has_smooth_lobes(&self) -> bool {
        self.p_lambert + self.p_phong > 0.0
    }

    /// f |cos theta_i| toward world direction `wi`, of the smooth lobes
    /// (the specular ones are nothing in any given direction), and the
    /// density `sample` gives it.
    #[inline(always)]
    pub fn eval(&self, wi: Vec3) -> (Vec3, f32) {
        let wi = self.frame.to_local(wi);
        if wi.z <= 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        (self.smooth_f(wi) * wi.z, self.smooth_pdf(wi))
    }

    /// f of the smooth lobes toward local `wi` (above the surface); a lobe
    /// never picked (of albedo 0) is not evaluated.
    #[inline(always)]
    fn smooth_f(&self, wi: Vec3) -> Vec3 {
        let mut f = Vec3::ZERO;
        if self.p_lambert > 0.0 {
            f += self.lambert.eval(wi);
        }
        if self.p_phong > 0.0 {
            f += self.phong.eval(self.wo, wi);
        }
        f
    }

    /// The density of local `wi` among the smooth lobes, each weighted by
    /// the probability of picking it.
    #[inline(always)]
    fn smooth_pdf(&self, wi: Vec3) -> f32 {
        let mut pdf = 0.0;
        if self.p_lambert > 0.0 {
            pdf += self.p_lambert * Lambert::pdf(wi);
        }
        if self.p_phong > 0.0 {
            pdf += self.p_phong * self.phong.pdf(self.wo, wi);
        }
        pdf
    }

    /// A direction: a lobe picked by `pick`, a direction of it drawn by
    /// `u`. None when the material sends nothing back or the direction
    /// fell below the surface.
    #[inline(always)]
    pub fn sample(&self, pick: f32, u: Vec2) -> Option<BsdfSample> {
        let smooth = self.p_lambert + self.p_phong;
        if pick >= smooth {
            return self.sample_interface((pick - smooth) / (1.0 - smooth));
        }
        let wi = if pick < self.p_lambert {
            Lambert::sample(u)
        } else {
            self.phong.sample(self.wo, u)?
        };
        let f = self.smooth_f(wi);
        let pdf = self.smooth_pdf(wi);
        if pdf <= 0.0 || wi.z <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi: self.frame.to_world(wi),
            weight: f * (wi.z / pdf),
            pdf,
            specular: false,
            transmitted: false,
            eta: 1.0,
        })
    }

    /// The specular lobe's direction, picked reflected or refracted by `u`.
    fn sample_interface(&self, u: f32) -> Option<BsdfSample> {
        let p = 1.0 - self.p_lambert - self.p_phong;
        let (wi, weight, transmitted) = self.interface.sample(self.wo, u.min(1.0))?;
        Some(BsdfSample {
            wi: self.frame.to_world(wi),
            weight: Vec3::splat(weight / p),
            pdf: p,
            specular: true,
            transmitted,
            eta: if transmitted { self.interface.eta } else { 1.0 },
        })
    }
}

/// A mirror of energy `reflectance` (nothing transmitted).
fn mirror(reflectance: f32) -> Interface {
    Interface {
        eta: 1.0,
        reflected: reflectance,
        transmitted: 0.0,
        refracted: None,
    }
}

/// Glass's interface for local `wo`: entering when the front face was
/// hit (the outside's index taken as 1, as Whitted mode does).
fn glass_interface(g: &Glass, wo: Vec3, front_face: bool) -> Interface {
    let eta = if front_face { 1.0 / g.ior } else { g.ior };
    Interface::new(wo, eta, g.fresnel, g.surface.reflectance, g.transmittance)
}

/// The diffuse and specular colours at `hit`: a colour texture multiplies
/// the diffuse one, a lab texture both (it multiplies the lab's whole
/// local colour).
fn textured(m: &Phong, hit: &SurfaceHit) -> (Vec3, Vec3) {
    let mut diffuse = m.diffuse;
    let mut specular = m.specular;
    if let Some(texture) = &m.color_texture {
        diffuse *= texture.color(hit.uv);
    }
    if let Some(texture) = &m.texture {
        let texel = texture.texel(hit.uv);
        diffuse *= texel;
        specular *= texel;
    }
    (diffuse, specular)
}

/// The largest channel of what material `m` sends back: its diffuse,
/// specular and mirror albedos, and its glass's reflected and transmitted
/// energies (at most 1 with `fresnel`). The same sum as the scene file's
/// warning (`scene_format::checks::albedo_sum`).
pub fn albedo_sum(m: &Material) -> f32 {
    let (surface, interface) = match m {
        Material::Phong(p) => (p, p.reflectance),
        Material::Glass(g) if g.fresnel => (&g.surface, 1.0),
        Material::Glass(g) => (&g.surface, g.surface.reflectance + g.transmittance),
    };
    (surface.diffuse + surface.specular).max_element() + interface
}
