//! The lab's `rayTrace`: Blinn-Phong in the lab's order, shadows, texture,
//! and mirror recursion with energy (lab sections 4 and 5).

use crate::material::Material;
use crate::ray::Ray;
use crate::scene::Scene;
use crate::EPSILON;
use glam::Vec3;

/// The lab's threshold on the cosines of the diffuse and specular terms.
const COS_THRESHOLD: f32 = 0.001;

/// How many rays of each kind a render traced.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RayStats {
    /// Rays that look for the nearest hit: primary and reflected.
    pub nearest: u64,
    /// Shadow rays: any hit between a point and a light.
    pub shadow: u64,
}

impl RayStats {
    pub fn total(&self) -> u64 {
        self.nearest + self.shadow
    }
}

impl std::ops::Add for RayStats {
    type Output = RayStats;
    fn add(self, o: RayStats) -> RayStats {
        RayStats {
            nearest: self.nearest + o.nearest,
            shadow: self.shadow + o.shadow,
        }
    }
}

/// The colour a ray carries back, already scaled by `energy`; `depth` is the
/// lab's ray-tree counter. A primary ray starts at energy 1, depth 0.
pub fn trace(scene: &Scene, ray: &Ray, energy: f32, depth: u32) -> Vec3 {
    trace_counted(scene, ray, energy, depth, &mut RayStats::default())
}

/// `trace`, counting the rays it casts into `stats`.
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
        return energy * scene.trace.background;
    };
    let material = &scene.materials[hit.material];
    let p = ray.at(hit.t);
    let n = hit.normal;
    let mut local = local_colour(scene, material, ray, p, n, stats);
    if let Some(texture) = &material.texture {
        let shape = &scene.objects[hit.object].shape;
        local *= texture.texel(shape.texture_uv(p, n));
    }
    let mut colour = energy * local;
    let settings = &scene.trace;
    if material.reflectance > 0.0 && depth < settings.max_depth && energy > settings.min_energy {
        let reflected = ray.reflected(p, n);
        let energy = energy * material.reflectance;
        colour += trace_counted(scene, &reflected, energy, depth + 1, stats);
    }
    colour
}

/// Ambient, diffuse and specular of every light at `p`, in the lab's order:
/// ambient once per light and always; diffuse and specular only when the
/// light is not shadowed.
fn local_colour(
    scene: &Scene,
    m: &Material,
    ray: &Ray,
    p: Vec3,
    n: Vec3,
    stats: &mut RayStats,
) -> Vec3 {
    let view = -ray.dir;
    let mut colour = Vec3::ZERO;
    for light in &scene.lights {
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
