//! The lab's `rayTrace`: Blinn-Phong in the lab's order, shadows, texture,
//! and mirror recursion with energy (lab sections 4 and 5); beyond the
//! lab, refraction through glass and sphere lights' soft shadows.

use super::RayStats;
use crate::geometry::SurfaceHit;
use crate::light::{Light, SphereLight};
use crate::material::{Glass, Material, Phong};
use crate::ray::Ray;
use crate::sampling::{concentric_disk, Rng, Strata};
use crate::scene::Scene;
use crate::EPSILON;
use glam::Vec3;

/// The lab's threshold on the cosines of the diffuse and specular terms.
const COS_THRESHOLD: f32 = 0.001;

/// Surfaces a shadow ray may pass through before it counts as blocked: a
/// bound on the walk through a stack of glass.
const MAX_SHADOW_CROSSINGS: u32 = 64;

/// The colours of Blinn-Phong at one hit: the material's, with its colour
/// texture (if any) applied to ambient and diffuse.
struct Terms {
    ambient: Vec3,
    diffuse: Vec3,
    specular: Vec3,
    shininess: f32,
}

impl Terms {
    fn at(m: &Phong, hit: &SurfaceHit) -> Terms {
        let (mut ambient, mut diffuse) = (m.ambient, m.diffuse);
        // Without a colour texture the material's colours are used as
        // they are: the lab's arithmetic, bit for bit.
        if let Some(texture) = &m.color_texture {
            let c = texture.color(hit.uv);
            ambient *= c;
            diffuse *= c;
        }
        Terms {
            ambient,
            diffuse,
            specular: m.specular,
            shininess: m.shininess,
        }
    }
}

/// A point being shaded: where, its unit normal, the unit direction
/// back to the viewer, and where its shadow rays start (`p` but on a
/// smooth triangle; see `SurfaceHit::shadow_offset`).
struct Shaded {
    p: Vec3,
    n: Vec3,
    view: Vec3,
    shadow_origin: Vec3,
}

/// Traces rays through one scene, counting them; one per thread, reseeded
/// for each pixel sample so that soft shadows are the same on every run.
pub struct Whitted<'a> {
    scene: &'a Scene,
    pub stats: RayStats,
    rng: Rng,
}

impl<'a> Whitted<'a> {
    pub fn new(scene: &'a Scene) -> Self {
        Whitted {
            scene,
            stats: RayStats::default(),
            rng: Rng::new(0),
        }
    }

    /// The random numbers of the next pixel sample.
    pub fn reseed(&mut self, rng: Rng) {
        self.rng = rng;
    }

    /// The colour a ray carries back, already scaled by `energy`; `depth`
    /// is the lab's ray-tree counter. A primary ray starts at energy 1,
    /// depth 0.
    pub fn trace(&mut self, ray: &Ray, energy: f32, depth: u32) -> Vec3 {
        let hit = self.scene.closest_hit(ray, EPSILON, f32::INFINITY);
        self.trace_from(ray, hit, energy, depth)
    }

    /// `trace`, the ray's nearest hit (in (EPSILON, inf)) already found:
    /// a pixel's samples are searched together (`Scene::closest_hits`).
    pub fn trace_from(
        &mut self,
        ray: &Ray,
        hit: Option<SurfaceHit>,
        energy: f32,
        depth: u32,
    ) -> Vec3 {
        self.stats.nearest += 1;
        let scene = self.scene;
        let Some(hit) = hit else {
            // With the lab's black background this adds nothing, as in the lab.
            return energy * scene.trace_settings().background;
        };
        match scene.material(hit.material) {
            Material::Phong(m) => self.phong(m, ray, &hit, energy, depth),
            Material::Glass(g) => self.glass(g, ray, &hit, energy, depth),
        }
    }

    /// Whether a ray of `energy` at `depth` may spawn another (lab 5.3).
    fn may_recurse(&self, energy: f32, depth: u32) -> bool {
        let settings = self.scene.trace_settings();
        depth < settings.max_depth && energy > settings.min_energy
    }

    /// The lab's shading of a hit on a Blinn-Phong material, and its mirror ray.
    fn phong(&mut self, m: &Phong, ray: &Ray, hit: &SurfaceHit, energy: f32, depth: u32) -> Vec3 {
        let p = ray.at(hit.t);
        let n = hit.shading_normal;
        let mut colour = energy * self.textured_local(m, ray, hit, p);
        if m.reflectance > 0.0 && self.may_recurse(energy, depth) {
            let reflected = ray.reflected(p, n);
            colour += self.trace(&reflected, energy * m.reflectance, depth + 1);
        }
        colour
    }

    /// A hit on glass: the surface's own colour seen from outside, the
    /// mirror ray and the refracted ray, each with its share of the
    /// energy; a ray leaving the inside has lost to absorption what it
    /// lost on its way through.
    fn glass(&mut self, g: &Glass, ray: &Ray, hit: &SurfaceHit, energy: f32, depth: u32) -> Vec3 {
        let p = ray.at(hit.t);
        // From inside, the lights' highlights would be seen through the
        // surface from its back: leave them out.
        let mut colour = if hit.front_face {
            energy * self.textured_local(&g.surface, ray, hit, p)
        } else {
            Vec3::ZERO
        };
        let split = g.split(ray.dir, hit);
        if self.may_recurse(energy, depth) {
            if split.reflected > 0.0 {
                let reflected = ray.reflected(p, hit.shading_normal);
                colour += self.trace(&reflected, energy * split.reflected, depth + 1);
            }
            if let Some((dir, share)) = split.transmitted {
                colour += self.trace(&Ray::new(p, dir), energy * share, depth + 1);
            }
        }
        if !hit.front_face {
            colour *= g.absorbed_over(hit.t);
        }
        colour
    }

    /// The local colour of material `m` at `p` (its colour texture on
    /// ambient and diffuse), times its lab texture.
    fn textured_local(&mut self, m: &Phong, ray: &Ray, hit: &SurfaceHit, p: Vec3) -> Vec3 {
        let terms = Terms::at(m, hit);
        let local = self.local_colour(&terms, ray, p, hit);
        match &m.texture {
            Some(texture) => local * texture.texel(hit.uv),
            None => local,
        }
    }

    /// Ambient, diffuse and specular of every light at `p`, in the lab's
    /// order: ambient once per light and always; diffuse and specular only
    /// where the light is not shadowed.
    fn local_colour(&mut self, m: &Terms, ray: &Ray, p: Vec3, hit: &SurfaceHit) -> Vec3 {
        let at = Shaded {
            p,
            n: hit.shading_normal,
            view: -ray.dir,
            shadow_origin: p + hit.shadow_offset,
        };
        let mut colour = Vec3::ZERO;
        for light in self.scene.lights() {
            colour += light.color() * m.ambient;
            match light {
                Light::Point(light) => {
                    self.direct(m, &at, light.position, light.color, &mut colour);
                }
                Light::Sphere(light) => colour += self.sphere_light(m, &at, light),
            }
        }
        colour
    }

    /// Diffuse and specular of a sphere light: the mean over
    /// `light_samples` points of its disk, stratified, each with its own
    /// shadow ray.
    fn sphere_light(&mut self, m: &Terms, at: &Shaded, light: &SphereLight) -> Vec3 {
        let samples = self.scene.trace_settings().light_samples.max(1);
        let strata = Strata::new(samples);
        let mut sum = Vec3::ZERO;
        for s in 0..samples {
            let disk = concentric_disk(strata.point(s, self.rng.square()));
            let from = light.point_seen_from(at.p, disk);
            self.direct(m, at, from, light.color, &mut sum);
        }
        sum / samples as f32
    }

    /// Adds to `colour` the diffuse and specular of light `color` from
    /// point `from` (lab 4.4), dimmed by what lies between; term by term,
    /// in the lab's order of additions.
    fn direct(&mut self, m: &Terms, at: &Shaded, from: Vec3, color: Vec3, colour: &mut Vec3) {
        let to_light = from - at.p;
        let distance = to_light.length();
        let l = to_light / distance;
        let cos_a = at.n.dot(l);
        if cos_a <= COS_THRESHOLD {
            return;
        }
        let (shadow_ray, distance) = shadow_ray(at, from, l, distance);
        let Some(through) = self.shadow(&shadow_ray, distance) else {
            return;
        };
        // 1 exactly unless glass is in the way: the lab's arithmetic stays.
        let color = color * through;
        *colour += color * m.diffuse * cos_a;
        let h = (l + at.view).normalize();
        let cos_b = at.n.dot(h);
        // No specular colour adds nothing: powf is skipped, the sum is the same.
        if cos_b > COS_THRESHOLD && m.specular != Vec3::ZERO {
            *colour += color * m.specular * cos_b.powf(m.shininess);
        }
    }

    /// What reaches along `ray` over `distance`: `None` when something
    /// opaque is in the way, else the product of the transparent surfaces'
    /// transmittances and their insides' absorption (no refraction: shadow
    /// rays go straight, so glass casts no caustics).
    fn shadow(&mut self, ray: &Ray, distance: f32) -> Option<Vec3> {
        self.stats.shadow += 1;
        let scene = self.scene;
        if !scene.has_transparency() {
            return (!scene.occluded(ray, EPSILON, distance)).then_some(Vec3::ONE);
        }
        let mut through = Vec3::ONE;
        let mut ray = *ray;
        let mut left = distance;
        for _ in 0..MAX_SHADOW_CROSSINGS {
            let Some(hit) = scene.closest_hit(&ray, EPSILON, left) else {
                return Some(through);
            };
            let Material::Glass(g) = scene.material(hit.material) else {
                return None;
            };
            let passes = g.shadow_transmission(ray.dir, &hit);
            if passes <= 0.0 {
                return None;
            }
            through *= passes;
            if !hit.front_face {
                through *= g.absorbed_over(hit.t);
            }
            ray = Ray::new(ray.at(hit.t), ray.dir);
            left -= hit.t;
            self.stats.shadow += 1;
        }
        None
    }
}

/// The shadow ray from `at` to the light point `from` (unit direction `l`
/// and `distance` from `at.p`), and its length: from `at.p` itself unless
/// the shadow rays start elsewhere.
fn shadow_ray(at: &Shaded, from: Vec3, l: Vec3, distance: f32) -> (Ray, f32) {
    if at.shadow_origin == at.p {
        return (Ray::new(at.p, l), distance);
    }
    let to_light = from - at.shadow_origin;
    let length = to_light.length();
    (Ray::new(at.shadow_origin, to_light / length), length)
}

/// One transmitted path: from `ray`, the rays that glass refracts it into,
/// one per surface crossed, as the renderer bends them (mirror rays are
/// left out); ends at an opaque surface, where nothing is transmitted, or
/// after `max` rays. For tests of the optics against the textbook.
pub fn refracted_path(scene: &Scene, ray: &Ray, max: usize) -> Vec<Ray> {
    let mut path = vec![*ray];
    while path.len() < max {
        let last = path[path.len() - 1];
        let Some(hit) = scene.closest_hit(&last, EPSILON, f32::INFINITY) else {
            break;
        };
        let Material::Glass(g) = scene.material(hit.material) else {
            break;
        };
        let Some((dir, _)) = g.split(last.dir, &hit).transmitted else {
            break;
        };
        path.push(Ray::new(last.at(hit.t), dir));
    }
    path
}
