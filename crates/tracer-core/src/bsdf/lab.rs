//! The lab's materials read physically: a mixture of a Lambertian lobe
//! (`diffuse`), a normalised Blinn-Phong lobe (`specular`, `shininess`) and
//! a mirror (`reflectance`) or glass (`transmittance`, `ior`, `fresnel`),
//! each picked for sampling in proportion to its albedo, their albedos
//! scaled down together where they add up to more than 1.

use super::{BlinnPhong, BsdfSample, Interface, Lambert};
use crate::geometry::SurfaceHit;
use crate::material::{albedo_sum, Glass, Material};
use glam::{Vec2, Vec3};

/// A lab material at one hit, seen along `wo`: its lobes, in the hit's
/// local frame.
#[derive(Debug, Clone, Copy)]
pub struct LabBsdf {
    /// The direction toward the viewer, local (z > 0).
    wo: Vec3,
    lambert: Lambert,
    phong: BlinnPhong,
    interface: Interface,
    /// Probabilities of picking the Lambertian and the Blinn-Phong lobe;
    /// the interface has the rest.
    p_lambert: f32,
    p_phong: f32,
}

impl LabBsdf {
    /// Lab material `m` (`Phong` or `Glass`) at `hit`, seen from local
    /// `wo_local` (z > 0). Opaque lobes are two-sided: the frame faces `wo`.
    pub fn new(m: &Material, hit: &SurfaceHit, wo_local: Vec3) -> LabBsdf {
        let (surface, interface) = match m {
            Material::Glass(g) => (&g.surface, glass_interface(g, wo_local, hit.front_face)),
            _ => {
                let p = m.surface();
                (p, mirror(p.reflectance))
            }
        };
        let (diffuse, specular) = surface.textured(hit);
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
        LabBsdf {
            wo: wo_local,
            lambert,
            phong,
            interface,
            p_lambert,
            p_phong,
        }
    }

    /// The Lambertian lobe's albedo and the probability of picking it, if
    /// it is the only lobe (no highlight, mirror or glass): the material
    /// as `integrate::path::matte_lanes` traces it. The probability is then 1, or
    /// 0 for a material that reflects nothing.
    pub(crate) fn lambert_only(&self) -> Option<(Vec3, f32)> {
        let alone = self.p_phong == 0.0 && self.interface.total() == 0.0;
        let whole = self.p_lambert == 1.0 || self.p_lambert == 0.0;
        (alone && whole).then_some((self.lambert.albedo, self.p_lambert))
    }

    /// Whether some lobe is not specular: light sampling can find its
    /// directions.
    pub fn has_smooth_lobes(&self) -> bool {
        self.p_lambert + self.p_phong > 0.0
    }

    /// f |cos theta_i| toward local direction `wi`, of the smooth lobes
    /// (the specular ones are nothing in any given direction), and the
    /// density `sample` gives it.
    #[inline(always)]
    pub fn eval(&self, wi: Vec3) -> (Vec3, f32) {
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
            wi,
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
            wi,
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
