//! The prepared scene: what a render reads. Built by `prepare` from a
//! scene file, or by `Scene::new` from core types.

use crate::accel::{brute_force, Bvh};
use crate::camera::Camera;
use crate::geometry::{Object, Shape, SharedMesh, Sphere, SurfaceHit, UvMap};
use crate::image::Encoding;
use crate::light::area::{AreaShape, EllipsoidLight};
use crate::light::environment::Environment;
use crate::light::lights::{AreaLight, Emits, Lights, PointSource};
use crate::light::textured::{EmittingSurface, LightTexture, UvAt};
use crate::light::Light;
use crate::material::{Material, Phong};
use crate::ray::Ray;
use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

mod kept;

/// The recursion settings of the lab's `rayTrace` (lab 5.3), and how
/// finely sphere lights are sampled.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TraceSettings {
    /// The lab's MAX_RAY_TREE: how many mirror bounces a ray may take.
    pub max_depth: u32,
    /// The lab's MIN_RAY_ENERGY: below it a ray is not reflected further.
    pub min_energy: f32,
    /// What a ray that leaves the scene picks up, times its energy.
    pub background: Vec3,
    /// Shadow rays per sphere light at each shaded point.
    pub light_samples: u32,
    /// How light is computed.
    pub integrator: Integrator,
    /// Path mode: how many neighbouring pixels of a row share their
    /// paths' first bounces (`integrate::path::reuse`); 1 shares nothing.
    pub path_reuse: u32,
    /// Path mode: camera rays per path for what a pixel sees directly,
    /// where that changes across it (`integrate::path::seen`); 1 is the path's.
    pub camera_rays: u32,
    /// Path mode: paths shared out by noise past a pilot (`adaptive.rs`).
    pub adaptive: bool,
}

/// How a render computes light.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Integrator {
    /// The lab's `rayTrace` (`integrate::whitted`).
    #[default]
    Whitted,
    /// Path tracing (`integrate::path`).
    Path,
}

/// A scene ready to render: the camera, the objects with their materials,
/// the lights, the settings, and the hierarchy over the objects. The
/// fields are private so the hierarchy always answers for these objects.
/// Only a lean scene is serialized (a prepared scene kept for later
/// renders): its objects are never written.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Scene {
    camera: Camera,
    #[serde(skip)]
    objects: Vec<Object>,
    materials: Vec<Material>,
    lights: Vec<Light>,
    trace: TraceSettings,
    encoding: Encoding,
    samples: u32,
    #[serde(serialize_with = "without_instances")]
    accel: Accel,
    /// Whether some material lets light through, so shadow rays must look
    /// past the first surface.
    transparency: bool,
    /// Whether some material has a normal texture, which `closest_hit`
    /// bends the shading normal by.
    normal_maps: bool,
    /// `unique_primitives`, counted before a lean scene let its objects go.
    primitives: usize,
    bounds: Option<(Vec3, Vec3)>,
    /// Whether `objects` were let go (a lean scene of more than
    /// `KEPT_OBJECTS`, or one read back: they are not serialized).
    #[serde(skip, default = "let_go")]
    objects_let_go: bool,
    /// Path mode's lights: point lights, emitting surfaces and the
    /// environment, chosen by power (empty in Whitted mode). Boxed: most
    /// scenes leave it empty.
    path_lights: Box<Lights>,
    /// The light around the scene, if any: what rays that leave it see.
    environment: Option<Arc<Environment>>,
    /// Whether the objects were let go (`Scene::lean`).
    #[serde(serialize_with = "only_lean")]
    lean: bool,
}

/// A lean scene keeps its objects when it has at most this many: the
/// integrators' lanes, which only small scenes take, are made from them
/// for each render (`integrate::lanes`, `integrate::path::matte_lanes`), and a
/// few kilobytes are worth keeping for that.
pub const KEPT_OBJECTS: usize = 64;

/// What a scene read back knows of its objects: they were not written.
fn let_go() -> bool {
    true
}

/// Refuses to serialize a scene that holds its objects (they would be lost).
fn only_lean<S: serde::Serializer>(lean: &bool, serializer: S) -> Result<S::Ok, S::Error> {
    if !*lean {
        return Err(serde::ser::Error::custom(
            "only a lean scene (Scene::lean) is serialized",
        ));
    }
    serializer.serialize_bool(true)
}

/// Refuses to serialize a BVH with instances (its tree of them is skipped).
fn without_instances<S: serde::Serializer>(
    accel: &Accel,
    serializer: S,
) -> Result<S::Ok, S::Error> {
    if accel.has_instances() {
        return Err(serde::ser::Error::custom(
            "a scene with instances is not serialized",
        ));
    }
    accel.serialize(serializer)
}

/// How a scene finds the hits of a ray. (A scene holds one: the unused
/// bytes of the brute-force variant cost nothing.)
#[derive(Debug, Clone, Serialize, Deserialize)]
#[allow(clippy::large_enum_variant)]
enum Accel {
    Bvh(Bvh),
    /// Every ray tests every object: the reference the BVH is tested against.
    BruteForce,
}

impl Accel {
    fn has_instances(&self) -> bool {
        matches!(self, Accel::Bvh(bvh) if bvh.has_instances())
    }
}

/// What a `Scene` is made of, before its hierarchy is built.
#[derive(Debug, Clone)]
pub struct SceneParts {
    pub camera: Camera,
    /// Each object's `material` is an index into `materials`.
    pub objects: Vec<Object>,
    pub materials: Vec<Material>,
    pub lights: Vec<Light>,
    pub trace: TraceSettings,
    pub encoding: Encoding,
    /// Samples per pixel of a render of the whole scene.
    pub samples: u32,
    /// The light around the scene: what rays that leave it see (instead of
    /// the background), and in path mode a light.
    pub environment: Option<Arc<Environment>>,
}

impl Scene {
    /// The scene of `parts`, with its BVH built on the current rayon pool.
    /// Panics if an object names a material that is not in the list: a
    /// mistake of the caller (`prepare` resolves every name first).
    pub fn new(parts: SceneParts) -> Scene {
        let mut parts = parts;
        let path_mode = parts.trace.integrator == Integrator::Path;
        if path_mode {
            sphere_lights_as_emitters(&mut parts);
        }
        let count = parts.materials.len();
        let in_range = |o: &Object| match &o.shape {
            Shape::Instance(i) => i.materials().iter().all(|&m| m < count),
            _ => o.material < count,
        };
        assert!(
            parts.objects.iter().all(in_range),
            "an object's material index is out of range"
        );
        let masks: Vec<_> = parts
            .materials
            .iter()
            .map(|m| m.alpha_mask().cloned())
            .collect();
        let reads_uv = |m: usize| parts.materials[m].reads_uv();
        let bvh = Bvh::build(&parts.objects)
            .with_masks(masks)
            .with_uv_read_by(reads_uv);
        let bounds = bvh.bounds();
        let accel = Accel::Bvh(bvh);
        let transparency = parts.materials.iter().any(Material::is_transparent);
        let normal_maps = parts
            .materials
            .iter()
            .any(|m| matches!(m, Material::Principled(p) if p.normal_map.is_some()));
        let path_lights = Box::new(if path_mode {
            path_lights(&parts, bounds)
        } else {
            Lights::default()
        });
        Scene {
            objects_let_go: false,
            path_lights,
            environment: parts.environment,
            primitives: unique_primitives(&parts.objects),
            bounds,
            lean: false,
            camera: parts.camera,
            objects: parts.objects,
            materials: parts.materials,
            lights: parts.lights,
            trace: parts.trace,
            encoding: parts.encoding,
            samples: parts.samples.max(1),
            accel,
            transparency,
            normal_maps,
        }
    }

    /// `Scene::new`, keeping only what a render reads: the objects of a
    /// scene of more than `KEPT_OBJECTS` are let go once the BVH holds
    /// what its search and shading need of them (a million-triangle mesh's
    /// objects take 71 MB). `objects()` is then empty. A lean scene cannot
    /// become `brute_force`.
    pub fn lean(parts: SceneParts) -> Scene {
        let scene = Scene::new(parts);
        let let_go = scene.objects.len() > KEPT_OBJECTS;
        Scene {
            objects: if let_go { Vec::new() } else { scene.objects },
            objects_let_go: let_go,
            lean: true,
            ..scene
        }
    }

    /// The same scene searched without its BVH (the reference the BVH is
    /// tested against: it reads no alpha masks). Panics for a `lean`
    /// scene, which has no objects left to search: a mistake of the caller.
    pub fn brute_force(self) -> Scene {
        assert!(!self.lean, "a lean scene has let its objects go");
        Scene {
            accel: Accel::BruteForce,
            ..self
        }
    }

    /// Whether rays are searched through a BVH.
    pub fn has_bvh(&self) -> bool {
        matches!(self.accel, Accel::Bvh(_))
    }

    /// Whether rays searched together (`closest_hits`,
    /// `occluded_together`) walk a tree together: a small scene, searched
    /// flat, tests each ray on its own anyway.
    pub fn searches_together(&self) -> bool {
        match &self.accel {
            Accel::Bvh(bvh) => bvh.has_tree(),
            Accel::BruteForce => false,
        }
    }

    /// Whether some objects are instances of a shared mesh (such a scene
    /// is not serialized).
    pub fn has_instances(&self) -> bool {
        self.accel.has_instances()
    }

    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// Moves every image point the camera samples by `by` pixels (see
    /// `Camera::with_pixel_shift`).
    pub fn shift_pixels(&mut self, by: Vec2) {
        self.camera = self.camera.clone().with_pixel_shift(by);
    }

    /// The primitives: a mesh contributes one object per triangle, or one
    /// instance when several objects share it (`prepare::shared_meshes`).
    /// Empty for a `lean` scene of more than `KEPT_OBJECTS`.
    pub fn objects(&self) -> &[Object] {
        &self.objects
    }

    /// The sphere of object `k`, if it is one whose hits leave their uv
    /// out (its material reads none).
    pub fn sphere_without_uv(&self, k: usize) -> Option<&Sphere> {
        match &self.accel {
            Accel::Bvh(bvh) => bvh.sphere_without_uv(k),
            Accel::BruteForce => None,
        }
    }

    /// Every object, if the scene still holds them all (`lean`).
    pub fn every_object(&self) -> Option<&[Object]> {
        (!self.objects_let_go).then_some(&self.objects)
    }

    /// Every material, as objects index them.
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// Whether some material cuts holes by an alpha mask (which the lanes'
    /// own searches do not read).
    pub fn has_alpha_masks(&self) -> bool {
        self.materials.iter().any(|m| m.alpha_mask().is_some())
    }

    /// The primitives held in memory: the objects, and each shared mesh's
    /// triangles once however many instances place it (also after a `lean`
    /// scene let its objects go).
    pub fn unique_primitives(&self) -> usize {
        self.primitives
    }

    pub fn material(&self, index: usize) -> &Material {
        &self.materials[index]
    }

    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// Path mode's lights (empty in Whitted mode).
    pub fn path_lights(&self) -> &Lights {
        &self.path_lights
    }

    /// The light around the scene, if any.
    pub fn environment(&self) -> Option<&Environment> {
        self.environment.as_deref()
    }

    /// What a ray leaving the scene along unit `dir` sees: the environment,
    /// or the background colour.
    #[inline(always)]
    pub fn background(&self, dir: Vec3) -> Vec3 {
        match &self.environment {
            Some(environment) => environment.radiance(dir),
            None => self.trace.background,
        }
    }

    pub fn trace_settings(&self) -> &TraceSettings {
        &self.trace
    }

    /// The same scene with other recursion settings (the hierarchy stays).
    pub fn with_trace_settings(self, trace: TraceSettings) -> Scene {
        Scene { trace, ..self }
    }

    /// Samples per pixel the scene asks for.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Whether some material lets light through.
    pub fn has_transparency(&self) -> bool {
        self.transparency
    }

    /// How the scene's linear image becomes 8-bit values.
    pub fn encoding(&self) -> &Encoding {
        &self.encoding
    }

    /// The smallest box holding every bounded object (planes are left out),
    /// or None for a scene without one.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        self.bounds
    }

    /// The nearest hit in (t_min, t_max); of hits at the same distance, the
    /// object listed first.
    pub fn closest_hit(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<SurfaceHit> {
        let hit = match &self.accel {
            Accel::Bvh(bvh) => bvh.closest_hit(ray, t_min, t_max),
            Accel::BruteForce => brute_force::closest_hit(&self.objects, ray, t_min, t_max),
        };
        match hit {
            Some(hit) if self.normal_maps => Some(self.bent(hit)),
            hit => hit,
        }
    }

    /// `hit` with its shading normal bent by its material's normal
    /// texture, where it has one and the hit a tangent.
    fn bent(&self, mut hit: SurfaceHit) -> SurfaceHit {
        let Material::Principled(p) = &self.materials[hit.material] else {
            return hit;
        };
        let Some(map) = p
            .normal_map
            .as_ref()
            .filter(|_| hit.tangent != glam::Vec4::ZERO)
        else {
            return hit;
        };
        if let Some(n) = map.bend(hit.shading_normal, hit.tangent, hit.uv) {
            hit.shading_normal = n;
        }
        hit
    }

    /// The nearest hits of `rays` (at most `accel::PACKET`) in (t_min,
    /// t_max), into `hits`: each the one `closest_hit` finds for it, but
    /// rays from one origin (a pixel's samples) searched together.
    pub fn closest_hits(
        &self,
        rays: &[Ray],
        t_min: f32,
        t_max: f32,
        hits: &mut [Option<SurfaceHit>],
    ) {
        match &self.accel {
            Accel::Bvh(bvh) => bvh.closest_hits(rays, t_min, t_max, &mut *hits),
            Accel::BruteForce => {
                for (ray, hit) in rays.iter().zip(hits.iter_mut()) {
                    *hit = brute_force::closest_hit(&self.objects, ray, t_min, t_max);
                }
            }
        }
        if self.normal_maps {
            for hit in hits.iter_mut() {
                *hit = hit.map(|h| self.bent(h));
            }
        }
    }

    /// Which of `rays` (at most `accel::PACKET`) something lies on within
    /// (t_min, t_max[i]), as a bit mask (bit i for ray i): each as
    /// `occluded` finds it, but searched together.
    pub fn occluded_together(&self, rays: &[Ray], t_min: f32, t_max: &[f32]) -> u32 {
        match &self.accel {
            Accel::Bvh(bvh) => bvh.occluded_together(rays, t_min, t_max),
            Accel::BruteForce => (0..rays.len()).fold(0, |mask, i| {
                let blocked = brute_force::occluded(&self.objects, &rays[i], t_min, t_max[i]);
                mask | (blocked as u32) << i
            }),
        }
    }

    /// Whether anything lies on the ray within (t_min, t_max): shadow rays.
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        match &self.accel {
            Accel::Bvh(bvh) => bvh.occluded(ray, t_min, t_max),
            Accel::BruteForce => brute_force::occluded(&self.objects, ray, t_min, t_max),
        }
    }
}

/// Path mode's reading of the lab's sphere lights: a sphere of the same
/// size that emits, of the same total light (a sphere of radiance L and
/// radius r sends pi r^2 L toward any far point, so L = I / (pi r^2), I the
/// light's intensity), and absorbs what falls on it. Seen and met by
/// paths as any emissive object.
fn sphere_lights_as_emitters(parts: &mut SceneParts) {
    for light in &parts.lights {
        let Light::Sphere(s) = light else {
            continue;
        };
        let area = std::f32::consts::PI * s.radius * s.radius;
        let surface = Phong {
            ambient: Vec3::ZERO,
            diffuse: Vec3::ZERO,
            specular: Vec3::ZERO,
            emission: s.color / area,
            ..Phong::default_grey()
        };
        parts.materials.push(Material::Phong(surface));
        let sphere = Shape::Sphere(Sphere::new(s.centre, s.radius));
        parts
            .objects
            .push(Object::new(sphere, parts.materials.len() - 1));
    }
}

/// The lights path mode samples: the point lights, every emitting triangle
/// and sphere (an instance's emitting triangles placed in the world), and
/// the environment around the scene's `bounds`. Planes cannot be sampled:
/// validation refuses emissive ones.
fn path_lights(parts: &SceneParts, bounds: Option<(Vec3, Vec3)>) -> Lights {
    let radius = bounds.map_or(1.0, |(lo, hi)| ((hi - lo).length() / 2.0).max(1e-3));
    let points = parts
        .lights
        .iter()
        .filter_map(|light| match light {
            Light::Point(p) => Some(PointSource::point(p.position, p.color)),
            Light::Spot(s) => Some(PointSource {
                position: s.position,
                intensity: s.color,
                emits: Emits::Cone {
                    axis: s.axis,
                    cos_inner: s.cos_inner,
                    cos_outer: s.cos_outer,
                },
            }),
            Light::Directional(d) => Some(PointSource {
                position: Vec3::ZERO,
                intensity: d.color,
                emits: Emits::Parallel {
                    direction: d.direction,
                    radius,
                },
            }),
            Light::Sphere(_) => None,
        })
        .collect();
    let emission = |material: usize| parts.materials[material].emission();
    // What varies over each material's emitting triangles, if anything.
    let surfaces: Vec<Option<Arc<EmittingSurface>>> = parts
        .materials
        .iter()
        .map(|m| EmittingSurface::of(m, true).map(Arc::new))
        .collect();
    let emitter = |corners, material: usize, uv| Emitter {
        corners,
        radiance: emission(material),
        uv,
        surface: surfaces[material].clone(),
    };
    let mut triangles = Vec::new();
    let mut areas = Vec::new();
    let mut sphere_objects = Vec::new();
    for (index, object) in parts.objects.iter().enumerate() {
        match &object.shape {
            Shape::Triangle(t) if emission(object.material) != Vec3::ZERO => {
                let corners = [t.v0, t.v1, t.v2];
                triangles.push(emitter(corners, object.material, object.uv_map()));
            }
            Shape::Instance(instance) => {
                for o in instance.mesh().objects() {
                    let Shape::Triangle(t) = &o.shape else {
                        continue;
                    };
                    let slots = instance.materials();
                    let material = *slots.get(o.material).unwrap_or(&slots[0]);
                    if emission(material) != Vec3::ZERO {
                        // A mirroring placement swaps the last two corners.
                        let uv = o.uv_map();
                        let uv = match instance.mirrors() {
                            true => UvMap {
                                du: uv.dv,
                                dv: uv.du,
                                ..uv
                            },
                            false => uv,
                        };
                        triangles.push(emitter(instance.world_triangle(t), material, uv));
                    }
                }
            }
            _ => {}
        }
        if let Shape::Sphere(s) = &object.shape {
            let radiance = emission(object.material);
            if let Some(shape) = round_light(s).filter(|_| radiance != Vec3::ZERO) {
                let mut light = AreaLight::new(shape, radiance);
                // Masks cut no sphere: only the texture varies over one.
                let surface = EmittingSurface::of(&parts.materials[object.material], false);
                light.texture = surface.map(|surface| {
                    let uv = UvAt::Sphere(Box::new(s.clone()));
                    Box::new(LightTexture {
                        surface: Arc::new(surface),
                        uv,
                    })
                });
                areas.push(light);
                sphere_objects.push(index as u32);
            }
        }
    }
    areas.extend(flat_lights(&triangles));
    let environment = parts.environment.clone().map(|e| (e, radius));
    Lights::new(points, areas, &sphere_objects, environment)
}

/// An emitting sphere's or ellipsoid's shape as a light; None for an
/// ellipsoid squashed flat (validation keeps scales from zero).
fn round_light(s: &Sphere) -> Option<AreaShape> {
    match &s.stretch {
        None => Some(AreaShape::Sphere {
            center: s.center,
            radius: s.radius,
        }),
        Some(m) => {
            let light = EllipsoidLight::new(s.center, s.radius, m.inverse())?;
            Some(AreaShape::Ellipsoid(Box::new(light)))
        }
    }
}

/// An emitting triangle: its corners, radiance (the factor of a
/// texture), the map of its barycentrics to uv, and what varies over it.
struct Emitter {
    corners: [Vec3; 3],
    radiance: Vec3,
    uv: UvMap,
    surface: Option<Arc<EmittingSurface>>,
}

/// Emitting triangles as area lights, each pair that is a quad's two
/// halves (as `prepare` cuts a quad or a box's face: (c, c + u, c + v)
/// then (c + u + v, c + v, c + u), of one radiance, and of one texture
/// laid evenly over both) as one parallelogram.
fn flat_lights(triangles: &[Emitter]) -> Vec<AreaLight> {
    let mut lights = Vec::with_capacity(triangles.len());
    let mut k = 0;
    while k < triangles.len() {
        let first = &triangles[k];
        let ([a, b, c], radiance) = (first.corners, first.radiance);
        let halves = triangles.get(k + 1).filter(|second| {
            let s = second.corners;
            second.radiance == radiance
                && s[1] == c
                && s[2] == b
                && {
                    let far = b + c - a;
                    (s[0] - far).length() <= 1e-5 * (b - a).length().max((c - a).length())
                }
                && one_texture(first, second)
        });
        let shape = match halves {
            Some(_) => AreaShape::parallelogram(a, b - a, c - a),
            None => AreaShape::triangle(a, b - a, c - a),
        };
        lights.extend(shape.map(|shape| AreaLight {
            shape,
            radiance,
            // A parallelogram's (s, t) are its first half's barycentrics.
            texture: first.surface.clone().map(|surface| {
                let uv = UvAt::Map(first.uv);
                Box::new(LightTexture { surface, uv })
            }),
        }));
        k += if halves.is_some() { 2 } else { 1 };
    }
    lights
}

/// Whether a quad's two halves (`flat_lights`) have nothing varying over
/// them, or one surface whose uv runs on across both: the second's map is
/// the first's at (1 - b1, 1 - b2).
fn one_texture(first: &Emitter, second: &Emitter) -> bool {
    match (&first.surface, &second.surface) {
        (None, None) => true,
        (Some(s1), Some(s2)) if Arc::ptr_eq(s1, s2) => {
            let (m1, m2) = (first.uv, second.uv);
            let near = |a: Vec2, b: Vec2| (a - b).length() <= 1e-5 * (1.0 + a.length());
            near(m2.origin, m1.origin + m1.du + m1.dv) && near(m2.du, -m1.du) && near(m2.dv, -m1.dv)
        }
        _ => false,
    }
}

/// The objects, and each shared mesh's triangles once.
fn unique_primitives(objects: &[Object]) -> usize {
    let meshes: std::collections::HashMap<*const SharedMesh, usize> = objects
        .iter()
        .filter_map(|o| match &o.shape {
            Shape::Instance(i) => Some((Arc::as_ptr(i.mesh()), i.mesh().objects().len())),
            _ => None,
        })
        .collect();
    objects.len() + meshes.values().sum::<usize>()
}
