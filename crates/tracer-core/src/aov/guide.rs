//! What a pixel sees, for the denoiser: the albedo and shading normal of
//! the first surface a primary ray meets that is not a perfect mirror or
//! smooth glass, the ray followed through those (as Open Image Denoise's
//! documentation asks, and Blender's denoising passes do), and the light
//! given off on the way (emitting surfaces, the environment or
//! background), each sample of a pixel on its own, the pixel the mean of
//! its samples.
//!
//! Where glass both reflects and refracts, each sample follows one branch,
//! picked by its own random numbers (the pixel's sample stream, after its
//! position) in proportion to the branch's energy and weighted by energy
//! over probability: a pixel's mean is then the two branches' albedos
//! weighted by Fresnel, and a sample costs one ray a surface.

use crate::geometry::SurfaceHit;
use crate::material::{Material, SpecularSplit};
use crate::ray::Ray;
use crate::sampling::{unit_float, Rng};
use crate::scene::Scene;
use crate::EPSILON;
use glam::Vec3;

/// Mirrors and glass followed at most: a ray caught between two mirrors
/// stops there, seeing black.
const MAX_SPECULAR: u32 = 16;

/// One sample's guides.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Seen {
    pub albedo: Vec3,
    /// Unit, toward the ray; zero where the ray left the scene.
    pub normal: Vec3,
    /// The radiance given off toward the eye by the surfaces met (their
    /// front sides, as path mode reads `emission`) and, where the ray
    /// leaves the scene, by the environment or background, times the
    /// colours of the mirrors and glass on the way: the light a path
    /// brings back with no bounce off a surface that is not a perfect
    /// mirror or smooth glass.
    pub light: Vec3,
    /// The part of `light` seen after a mirror or glass, not by the
    /// primary ray itself.
    pub reflected: Vec3,
}

/// The guides of a primary `ray` whose nearest hit is `hit`.
pub(crate) fn seen(scene: &Scene, ray: &Ray, hit: Option<&SurfaceHit>, rng: &mut Rng) -> Seen {
    let mut weight = Vec3::ONE;
    // What glass absorbed on the way: the light's alone, the albedo being
    // the surfaces' colours.
    let mut absorbed = Vec3::ONE;
    let mut light = Light::default();
    let mut ray = *ray;
    let mut hit = hit.copied();
    for _ in 0..=MAX_SPECULAR {
        let dir = ray.dir().normalize();
        let Some(h) = hit else {
            let background = scene.background(dir);
            light.add(weight * absorbed * background);
            return Seen {
                albedo: weight * background.clamp(Vec3::ZERO, Vec3::ONE),
                normal: Vec3::ZERO,
                light: light.all,
                reflected: light.reflected,
            };
        };
        let material = scene.material(h.material);
        // A back face of glass ends a stretch inside it, as path mode
        // reads it for a path that did not enter it.
        if let (Material::Glass(g), false) = (material, h.front_face) {
            absorbed *= g.absorbed_over(h.t);
        }
        if h.front_face {
            light.add(weight * absorbed * material.emission_at(&h));
        }
        let Some(split) = material.specular_split(dir, &h) else {
            let normal = if dir.dot(h.shading_normal) > 0.0 {
                -h.shading_normal
            } else {
                h.shading_normal
            };
            return Seen {
                albedo: weight * material.albedo(&h),
                normal,
                light: light.all,
                reflected: light.reflected,
            };
        };
        light.bounced = true;
        let (next, colour) = pick(&split, rng);
        weight *= colour;
        ray = Ray::new(ray.at(h.t), next);
        hit = scene.closest_hit(&ray, EPSILON, f32::INFINITY);
    }
    Seen {
        albedo: Vec3::ZERO,
        normal: Vec3::ZERO,
        light: light.all,
        reflected: light.reflected,
    }
}

/// The light a primary ray meets on its way through mirrors and glass,
/// all of it, and the part met after a mirror or glass
/// (`Seen::reflected`).
#[derive(Default)]
struct Light {
    all: Vec3,
    reflected: Vec3,
    /// Whether the ray has left its first segment.
    bounced: bool,
}

impl Light {
    fn add(&mut self, light: Vec3) {
        self.all += light;
        if self.bounced {
            self.reflected += light;
        }
    }
}

/// One branch of `split` (direction and weight), picked with probability
/// in proportion to its energy.
fn pick(split: &SpecularSplit, rng: &mut Rng) -> (Vec3, Vec3) {
    let (reflected, colour) = split.reflected;
    let Some((refracted, through)) = split.transmitted else {
        return (reflected, colour);
    };
    let total = split.energy();
    let p_through = through.element_sum() / total;
    if unit_float(rng.next_u64()) < p_through {
        (refracted, through / p_through)
    } else {
        (reflected, colour / (1.0 - p_through))
    }
}
