//! What a pixel sees, for the denoiser: the albedo and shading normal of
//! the first surface a primary ray meets that is not a perfect mirror or
//! smooth glass, the ray followed through those (as Open Image Denoise's
//! documentation asks, and Blender's denoising passes do), and the light
//! given off on the way (emitting surfaces, the environment or
//! background), each sample of a pixel on its own, the pixel the mean of
//! its samples.
//!
//! Where glass both reflects and refracts, each sample's albedo and normal
//! follow one branch, picked by its own random numbers (the pixel's sample
//! stream, after its position) in proportion to the branch's energy and
//! weighted by energy over probability: a pixel's mean is then the two
//! branches' albedos weighted by Fresnel, and a sample costs one ray a
//! surface. The light follows both branches at the first surfaces of
//! glass (`SPLITS`), and one picked so beyond: what the denoiser adds back
//! unfiltered must not be speckled.

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
}

/// The guides of a primary `ray` whose nearest hit is `hit`.
pub(crate) fn seen(scene: &Scene, ray: &Ray, hit: Option<&SurfaceHit>, rng: &mut Rng) -> Seen {
    let mut weight = Vec3::ONE;
    let mut ray = *ray;
    let mut hit = hit.copied();
    for _ in 0..=MAX_SPECULAR {
        let dir = ray.dir().normalize();
        let Some(h) = hit else {
            let background = scene.background(dir);
            return Seen {
                albedo: weight * background.clamp(Vec3::ZERO, Vec3::ONE),
                normal: Vec3::ZERO,
            };
        };
        let material = scene.material(h.material);
        let Some(split) = material.specular_split(dir, &h) else {
            let normal = if dir.dot(h.shading_normal) > 0.0 {
                -h.shading_normal
            } else {
                h.shading_normal
            };
            return Seen {
                albedo: weight * material.albedo(&h),
                normal,
            };
        };
        let (next, colour) = pick(&split, rng);
        weight *= colour;
        ray = Ray::new(ray.at(h.t), next);
        hit = scene.closest_hit(&ray, EPSILON, f32::INFINITY);
    }
    Seen {
        albedo: Vec3::ZERO,
        normal: Vec3::ZERO,
    }
}

/// Glass surfaces at which the light follows both branches, each weighted
/// by its colour (at most 2^SPLITS rays on from the first surface),
/// before it picks one at random as `seen` does: the light seen through
/// glass is then free of the noise of that pick where it matters most, at
/// the first surfaces (a glass ball's front and back).
const SPLITS: u32 = 3;

/// The radiance given off toward the eye by what a primary `ray` whose
/// nearest hit is `hit` meets (the front sides of emitting surfaces, as
/// path mode reads `emission`, and where the ray leaves the scene the
/// environment or background) through mirrors and glass, times their
/// colours and what glass absorbs: the light a path brings back with no
/// bounce off a surface that is not a perfect mirror or smooth glass.
pub(crate) fn light(scene: &Scene, ray: &Ray, hit: Option<&SurfaceHit>, rng: &mut Rng) -> Vec3 {
    let (own, beyond) = met_at(scene, ray, hit, Vec3::ONE, (0, SPLITS), rng);
    own + beyond
}

/// The part of `light` met after a mirror or glass, not by the primary
/// ray itself: the denoiser's (`Aov::ReflectedEmission`).
pub(crate) fn reflected(scene: &Scene, ray: &Ray, hit: Option<&SurfaceHit>, rng: &mut Rng) -> Vec3 {
    met_at(scene, ray, hit, Vec3::ONE, (0, SPLITS), rng).1
}

/// The light `ray` meets at its nearest hit `hit`, times `weight`, and
/// what the mirror or glass there shows beyond, `depth` of them on the
/// way so far and `splits` left.
fn met_at(
    scene: &Scene,
    ray: &Ray,
    hit: Option<&SurfaceHit>,
    weight: Vec3,
    (depth, splits): (u32, u32),
    rng: &mut Rng,
) -> (Vec3, Vec3) {
    let dir = ray.dir().normalize();
    let Some(h) = hit else {
        return (weight * scene.background(dir), Vec3::ZERO);
    };
    let material = scene.material(h.material);
    // A back face of glass ends a stretch inside it, as path mode reads
    // it for a path that did not enter it.
    let weight = match (material, h.front_face) {
        (Material::Glass(g), false) => weight * g.absorbed_over(h.t),
        _ => weight,
    };
    let emitted = match h.front_face {
        true => weight * material.emission_at(h),
        false => Vec3::ZERO,
    };
    let beyond = match material.specular_split(dir, h) {
        Some(split) if depth < MAX_SPECULAR => {
            let on = (ray.at(h.t), &split);
            both_or_one(scene, on, weight, (depth + 1, splits), rng)
        }
        _ => Vec3::ZERO,
    };
    (emitted, beyond)
}

/// The light met on from `origin` along the branches of `split`, each
/// weighted by `weight` and its colour: both while `splits` are left.
fn both_or_one(
    scene: &Scene,
    (origin, split): (Vec3, &SpecularSplit),
    weight: Vec3,
    (depth, splits): (u32, u32),
    rng: &mut Rng,
) -> Vec3 {
    let along = |(dir, colour): (Vec3, Vec3), splits, rng: &mut Rng| {
        let ray = Ray::new(origin, dir);
        let hit = scene.closest_hit(&ray, EPSILON, f32::INFINITY);
        let (own, beyond) = met_at(
            scene,
            &ray,
            hit.as_ref(),
            weight * colour,
            (depth, splits),
            rng,
        );
        own + beyond
    };
    match split.transmitted {
        Some(through) if splits > 0 => {
            along(split.reflected, splits - 1, rng) + along(through, splits - 1, rng)
        }
        _ => along(pick(split, rng), splits, rng),
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
