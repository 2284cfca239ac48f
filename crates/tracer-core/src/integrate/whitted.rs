//! The lab's `rayTrace`: Blinn-Phong in the lab's order, shadows, texture,
//! and mirror recursion with energy (lab sections 4 and 5).

use super::RayStats;
use crate::geometry::SurfaceHit;
use crate::light::Light;
use crate::material::{Material, Phong};
use crate::ray::Ray;
use crate::scene::Scene;
use crate::EPSILON;
use glam::Vec3;

/// The lab's threshold on the cosines of the diffuse and specular terms.
const COS_THRESHOLD: f32 = 0.001;

/// The colour a ray carries back, already scaled by `energy`, counting the
/// rays it casts into `stats`; `depth` is the lab's ray-tree counter. A
/// primary ray starts at energy 1, depth 0.
pub fn trace_counted(
    scene: &Scene,
    ray: &Ray,
    energy: f32,
    depth: u32,
    stats: &mut RayStats,
) -> Vec3 {
    stats.nearest += 1;
    let Some(hit) = scene.closest_hit(ray, EPSILON, f32::INFINITY) else {
        // With the lab's black background this adds nothing, as in the lab.
        return energy * scene.trace_settings().background;
    };
    match scene.material(hit.material) {
        Material::Phong(m) => phong(scene, m, ray, &hit, energy, depth, stats),
    }
}

/// The lab's shading of a hit on a Blinn-Phong material, and its mirror ray.
fn phong(
    scene: &Scene,
    m: &Phong,
    ray: &Ray,
    hit: &SurfaceHit,
    energy: f32,
    depth: u32,
    stats: &mut RayStats,
) -> Vec3 {
    let p = ray.at(hit.t);
    let n = hit.shading_normal;
    let mut local = local_colour(scene, m, ray, p, n, stats);
    if let Some(texture) = &m.texture {
        local *= texture.texel(hit.uv);
    }
    let mut colour = energy * local;
    let settings = scene.trace_settings();
    if m.reflectance > 0.0 && depth < settings.max_depth && energy > settings.min_energy {
        let reflected = ray.reflected(p, n);
        let energy = energy * m.reflectance;
        colour += trace_counted(scene, &reflected, energy, depth + 1, stats);
    }
    colour
}

/// Ambient, diffuse and specular of every light at `p`, in the lab's order:
/// ambient once per light and always; diffuse and specular only when the
/// light is not shadowed.
fn local_colour(
    scene: &Scene,
    m: &Phong,
    ray: &Ray,
    p: Vec3,
    n: Vec3,
    stats: &mut RayStats,
) -> Vec3 {
    let view = -ray.dir;
    let mut colour = Vec3::ZERO;
    for light in scene.lights() {
        let Light::Point(light) = light;
        colour += light.color * m.ambient;
        let to_light = light.position - p;
        let distance = to_light.length();
        let l = to_light / distance;
        let cos_a = n.dot(l);
        if cos_a <= COS_THRESHOLD {
            continue;
        }
        stats.shadow += 1;
        if scene.occluded(&Ray::new(p, l), EPSILON, distance) {
            continue;
        }
        colour += light.color * m.diffuse * cos_a;
        let h = (l + view).normalize();
        let cos_b = n.dot(h);
        // No specular colour adds nothing: powf is skipped, the sum is the same.
        if cos_b > COS_THRESHOLD && m.specular != Vec3::ZERO {
            colour += light.color * m.specular * cos_b.powf(m.shininess);
        }
    }
    colour
}
