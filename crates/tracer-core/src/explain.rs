//! Why a pixel has its colour: one sample of it traced again by the
//! render's own integrator, with a recorder (`integrate::record`) that
//! keeps every ray, hit, light term and weight, up to its [`Limits`].
//! Plain data (serde), for `tracer explain` to print as text or JSON.

use crate::geometry::{Shape, SurfaceHit};
use crate::integrate::path::PathTracer;
use crate::integrate::record::{LightTerm, PathEvent, RayKind, Recorder, Stop};
use crate::integrate::whitted::Whitted;
use crate::ray::Ray;
use crate::sampler::PixelSampler;
use crate::scene::{Integrator, Scene};
use crate::EPSILON;
use glam::{Vec2, Vec3};
use serde::Serialize;

/// Most primitives listed as tested along a ray: beyond, a mesh's
/// thousands of triangles would bury the tree.
pub const MAX_TESTED: usize = 64;

/// Events a tree keeps by default (a ray, a light's term, a path's
/// event): a tree of glass under hundreds of lights has millions, which no
/// one reads; the lab's scenes have tens to a few hundred.
pub const DEFAULT_MAX_EVENTS: usize = 10_000;
/// Bytes a tree keeps at most, whatever the events asked for: its text is
/// of the same order.
pub const MAX_BYTES: usize = 256 << 20;

/// How much of a sample's tree is kept. The integrator computes the sample
/// whole either way (the colour is the render's); what is not kept is
/// counted in [`Cut`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Events kept at most (the primary ray always is).
    pub max_events: usize,
    /// Bytes of the tree's records kept at most.
    pub max_bytes: usize,
    /// Only this light's terms (its index in `[[lights]]`), in Whitted
    /// mode; None: every light's.
    pub light: Option<usize>,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            max_events: DEFAULT_MAX_EVENTS,
            max_bytes: MAX_BYTES,
            light: None,
        }
    }
}

/// What a tree left out at its limits: counted, so the reader is told.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct Cut {
    /// The limits it met.
    pub max_events: usize,
    /// Events kept, and those left out (a ray left out leaves out all of
    /// its own: they are counted too).
    pub kept: usize,
    pub left_out: usize,
    /// Of those left out: rays, and lights' terms.
    pub rays: usize,
    pub light_terms: usize,
    /// Whether the bytes' limit was met (else the events').
    pub bytes: bool,
}

/// One sample of one pixel, explained.
#[derive(Debug, Clone, Serialize)]
pub struct Explanation {
    /// Which sample of the pixel, of how many.
    pub sample: u32,
    pub samples: u32,
    /// The image point the primary ray goes through (a pixel's centre is
    /// (i + 0.5, j + 0.5)), and the lens point (0, 0 for a pinhole).
    pub image_point: Vec2,
    pub lens_point: Vec2,
    /// The camera's projection matrix P = [u v o] (lab 1.2.3): the
    /// primary ray's direction is P (x, y, 1), normalised.
    pub projection: [Vec3; 3],
    /// The sample's colour (linear, before the pixel's mean).
    pub colour: Vec3,
    pub trace: Trace,
    /// What the limits left out; None when the whole tree is kept.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cut: Option<Cut>,
    /// `Limits::light`: the one light whose terms the tree shows.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub only_light: Option<usize>,
}

/// What the integrator did with the sample.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "integrator", rename_all = "lowercase")]
pub enum Trace {
    /// The lab's ray tree, from the primary ray.
    Whitted { ray: RayNode },
    /// A path's events, in order.
    Path {
        ray: RayNode,
        events: Vec<PathEvent>,
    },
}

/// One ray of the tree and what it brought back.
#[derive(Debug, Clone, Serialize)]
pub struct RayNode {
    pub kind: RayKind,
    pub origin: Vec3,
    /// Unit length.
    pub direction: Vec3,
    /// Where it ends: its nearest hit's point; None when it leaves the
    /// scene.
    pub end: Option<Vec3>,
    pub energy: f32,
    pub depth: u32,
    /// Each primitive tested along the ray (when there are at most
    /// `MAX_TESTED`): its distance, or why it was not the hit.
    pub tested: Option<Vec<Tested>>,
    pub hit: Option<Hit>,
    /// Each light's ambient term (lab 4.2), in `[[lights]]` order.
    pub ambient: Vec<(usize, Vec3)>,
    /// Each light's diffuse and specular terms (a sphere light's, one per
    /// point of it), and what blocked a shadow ray.
    pub lights: Vec<Lit>,
    /// The sum of the terms, and the lab texture that multiplied it.
    pub local: Option<Vec3>,
    pub texture: Option<Vec3>,
    /// The hit's emission, added as seen (Whitted mode).
    pub emitted: Option<Vec3>,
    /// Why a mirror or glass hit spawned no ray.
    pub stopped: Option<Stop>,
    /// The reflected and refracted rays.
    pub children: Vec<RayNode>,
    /// What absorption left of the colour, for a ray that crossed glass
    /// (exp(-absorption * t)).
    pub absorbed: Option<Vec3>,
    /// The ray's colour, times its energy, children included.
    pub colour: Vec3,
    /// What the tree's limits left out of this ray: its lights' terms and
    /// its mirror and refracted rays (with theirs).
    #[serde(skip_serializing_if = "LeftOut::is_none")]
    pub left_out: LeftOut,
}

/// Of one ray, what the tree's limits left out.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct LeftOut {
    pub light_terms: usize,
    pub rays: usize,
}

impl LeftOut {
    pub fn is_none(&self) -> bool {
        *self == LeftOut::default()
    }
}

/// A light's terms at a hit.
#[derive(Debug, Clone, Serialize)]
pub struct Lit {
    #[serde(flatten)]
    pub term: LightTerm,
    /// The primitive a blocked shadow ray met first, and where.
    pub blocked_by: Option<Blocker>,
}

#[derive(Debug, Clone, Copy, Serialize)]
pub struct Blocker {
    pub object: usize,
    pub t: f32,
    /// Where the shadow ray meets it.
    pub point: Vec3,
}

/// The nearest hit of a ray.
#[derive(Debug, Clone, Serialize)]
pub struct Hit {
    pub t: f32,
    pub point: Vec3,
    /// The shading normal (unit; the lab's: never turned toward the ray).
    pub normal: Vec3,
    /// Whether the ray met the side the normal points to.
    pub front_face: bool,
    pub object: usize,
    pub material: usize,
    pub uv: Vec2,
}

/// A primitive tested along a ray.
#[derive(Debug, Clone, Serialize)]
pub struct Tested {
    pub object: usize,
    #[serde(flatten)]
    pub outcome: Outcome,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "outcome", rename_all = "lowercase")]
pub enum Outcome {
    /// The ray's nearest hit, at distance t.
    Nearest { t: f32 },
    /// Met beyond the nearest hit.
    Farther { t: f32 },
    /// Met where its material's alpha mask cuts it out: no hit.
    Cutout { t: f32 },
    /// Met only behind the ray's origin (or within its epsilon of it).
    Behind { t: f32 },
    /// Not met.
    Missed,
}

/// The recorder that builds the tree, within its limits.
struct TreeRecorder<'a> {
    scene: &'a Scene,
    /// The rays begun and not yet ended, innermost last.
    open: Vec<RayNode>,
    done: Option<RayNode>,
    events: Vec<PathEvent>,
    limits: Limits,
    /// Events and bytes kept so far.
    kept: usize,
    bytes: usize,
    /// What was left out.
    cut: Cut,
    /// Rays begun past the limits and not yet ended: not kept, and
    /// nothing of theirs is.
    skipped: usize,
}

impl<'a> TreeRecorder<'a> {
    fn new(scene: &'a Scene, limits: Limits) -> TreeRecorder<'a> {
        TreeRecorder {
            scene,
            open: Vec::new(),
            done: None,
            events: Vec::new(),
            limits,
            kept: 0,
            bytes: 0,
            cut: Cut::default(),
            skipped: 0,
        }
    }

    /// Whether one more event of `bytes` fits the limits: counted as kept
    /// if so, else as left out.
    fn keep(&mut self, bytes: usize) -> bool {
        let events_full = self.kept >= self.limits.max_events;
        let bytes_full = self.bytes + bytes > self.limits.max_bytes;
        if events_full || bytes_full {
            self.cut.left_out += 1;
            self.cut.bytes |= bytes_full && !events_full;
            return false;
        }
        self.kept += 1;
        self.bytes += bytes;
        true
    }

    /// Whether a light's term is shown: not when it is another light's
    /// than the one asked for, or inside a ray left out (counted), or past
    /// the limits (counted at its ray).
    fn keep_term(&mut self, light: usize, bytes: usize) -> bool {
        if self.limits.light.is_some_and(|only| only != light) {
            return false;
        }
        if self.skipped > 0 {
            self.cut.left_out += 1;
            self.cut.light_terms += 1;
            return false;
        }
        if self.keep(bytes) {
            return true;
        }
        self.cut.light_terms += 1;
        if let Some(node) = self.open.last_mut() {
            node.left_out.light_terms += 1;
        }
        false
    }

    /// The open ray that is kept, if the current one is.
    fn current(&mut self) -> Option<&mut RayNode> {
        if self.skipped > 0 {
            return None;
        }
        self.open.last_mut()
    }

    /// What was left out, if anything was.
    fn cut(&self) -> Option<Cut> {
        (self.cut.left_out > 0).then_some(Cut {
            max_events: self.limits.max_events,
            kept: self.kept,
            ..self.cut
        })
    }
}

impl Recorder for TreeRecorder<'_> {
    fn ray(&mut self, kind: RayKind, ray: &Ray, energy: f32, depth: u32) {
        // The primary ray is always kept: the tree's root.
        let root = self.open.is_empty() && self.done.is_none();
        if self.skipped > 0 || !root && !self.keep(std::mem::size_of::<RayNode>()) {
            if self.skipped > 0 {
                self.cut.left_out += 1;
            } else if let Some(parent) = self.open.last_mut() {
                parent.left_out.rays += 1;
            }
            self.cut.rays += 1;
            self.skipped += 1;
            return;
        }
        if root {
            self.kept += 1;
            self.bytes += std::mem::size_of::<RayNode>();
        }
        self.open.push(RayNode {
            kind,
            origin: ray.origin(),
            direction: ray.dir(),
            end: None,
            energy,
            depth,
            tested: None,
            hit: None,
            ambient: Vec::new(),
            lights: Vec::new(),
            local: None,
            texture: None,
            emitted: None,
            stopped: None,
            children: Vec::new(),
            absorbed: None,
            colour: Vec3::ZERO,
            left_out: LeftOut::default(),
        });
    }

    fn emitted(&mut self, emission: Vec3) {
        if let Some(node) = self.current() {
            node.emitted = Some(emission);
        }
    }

    fn absorbed(&mut self, factor: Vec3) {
        if let Some(node) = self.current() {
            node.absorbed = Some(factor);
        }
    }

    fn stopped(&mut self, why: Stop) {
        if let Some(node) = self.current() {
            node.stopped = Some(why);
        }
    }

    fn hit(&mut self, hit: Option<&SurfaceHit>) {
        let Some(node) = self.current() else {
            return;
        };
        let ray = Ray::new(node.origin, node.direction);
        let tested = tested(self.scene, &ray, hit.map(|h| (h.object, h.t)));
        // The list of primitives tested is left out past the bytes' limit
        // (the hit is kept: a ray without its hit says nothing).
        let list_bytes = tested
            .as_ref()
            .map_or(0, |t| t.len() * std::mem::size_of::<Tested>());
        let fits = self.bytes + list_bytes <= self.limits.max_bytes;
        if fits {
            self.bytes += list_bytes;
        }
        let node = self.open.last_mut().expect("the current ray");
        node.tested = tested.filter(|_| fits);
        node.end = hit.map(|h| ray.at(h.t));
        node.hit = hit.map(|h| Hit {
            t: h.t,
            point: ray.at(h.t),
            normal: h.shading_normal,
            front_face: h.front_face,
            object: h.object,
            material: h.material,
            uv: uv_of(self.scene, h, ray.at(h.t)),
        });
    }

    fn ambient(&mut self, light: usize, term: Vec3) {
        if !self.keep_term(light, std::mem::size_of::<(usize, Vec3)>()) {
            return;
        }
        if let Some(node) = self.current() {
            node.ambient.push((light, term));
        }
    }

    fn light(&mut self, term: &LightTerm) {
        if !self.keep_term(term.light, std::mem::size_of::<Lit>()) {
            return;
        }
        let blocked_by = term.shadow.filter(|s| s.passes.is_none()).and_then(|s| {
            let ray = Ray::new(s.origin, s.direction);
            let hit = self.scene.closest_hit(&ray, EPSILON, s.length)?;
            Some(Blocker {
                object: hit.object,
                t: hit.t,
                point: ray.at(hit.t),
            })
        });
        if let Some(node) = self.current() {
            node.lights.push(Lit {
                term: *term,
                blocked_by,
            });
        }
    }

    fn local(&mut self, colour: Vec3, texture: Option<Vec3>) {
        if let Some(node) = self.current() {
            (node.local, node.texture) = (Some(colour), texture);
        }
    }

    fn end_ray(&mut self, colour: Vec3) {
        if self.skipped > 0 {
            self.skipped -= 1;
            return;
        }
        let Some(mut node) = self.open.pop() else {
            return;
        };
        node.colour = colour;
        match self.open.last_mut() {
            Some(parent) => parent.children.push(node),
            None => self.done = Some(node),
        }
    }

    fn path(&mut self, event: PathEvent) {
        if self.keep(std::mem::size_of::<PathEvent>()) {
            self.events.push(event);
        }
    }
}

/// The texture coordinates of hit `h` at `point`: a sphere whose material
/// reads none leaves them out of its hits, and they are found here.
fn uv_of(scene: &Scene, h: &SurfaceHit, point: Vec3) -> Vec2 {
    match scene.sphere_without_uv(h.object) {
        Some(s) => s.uv(point, s.normal(point)),
        None => h.uv,
    }
}

/// Each primitive along `ray` (when there are few enough), against the
/// nearest hit `nearest` (object, t): its distance, or why not. A lean
/// scene (its objects let go) lists none.
fn tested(scene: &Scene, ray: &Ray, nearest: Option<(usize, f32)>) -> Option<Vec<Tested>> {
    let objects = scene.objects();
    if objects.is_empty() || objects.len() > MAX_TESTED {
        return None;
    }
    let tests = objects.iter().enumerate().map(|(k, o)| {
        let forward = o.surface_hit(k, ray, EPSILON, f32::INFINITY);
        let cut = forward.is_some_and(|h| {
            let mask = scene.material(h.material).alpha_mask();
            matches!(o.shape, Shape::Triangle(_)) && mask.is_some_and(|m| m.cuts(h.uv))
        });
        let outcome = match (forward.map(|h| h.t), nearest) {
            (Some(t), _) if cut => Outcome::Cutout { t },
            (Some(t), Some((n, _))) if n == k => Outcome::Nearest { t },
            (Some(t), _) => Outcome::Farther { t },
            (None, _) => match behind(&o.shape, ray) {
                Some(t) => Outcome::Behind { t },
                None => Outcome::Missed,
            },
        };
        Tested { object: k, outcome }
    });
    Some(tests.collect())
}

/// The distance at which the line of `ray` meets `shape` behind its
/// origin (or within the epsilon of it), if it does.
fn behind(shape: &Shape, ray: &Ray) -> Option<f32> {
    let t = match shape {
        Shape::Sphere(s) => s.intersect(ray, f32::NEG_INFINITY, EPSILON),
        Shape::Triangle(t) => t.intersect(ray, f32::NEG_INFINITY, EPSILON).map(|h| h.t),
        Shape::Plane(p) => p.intersect(ray, f32::NEG_INFINITY, EPSILON),
        Shape::Instance(_) => None,
    };
    t.filter(|t| t.is_finite())
}

/// Sample `sample` of pixel (i, j) of `scene` rendered at `samples` a
/// pixel, traced again with the scene's integrator, explained within the
/// default [`Limits`].
pub fn explain(scene: &Scene, pixel: (u32, u32), samples: u32, sample: u32) -> Explanation {
    explain_within(scene, pixel, samples, sample, Limits::default())
}

/// [`explain`] within `limits`. Lists the primitives tested along each ray
/// only for a scene that holds its objects (`Scene::new`, not
/// `Scene::lean`).
pub fn explain_within(
    scene: &Scene,
    (i, j): (u32, u32),
    samples: u32,
    sample: u32,
    limits: Limits,
) -> Explanation {
    let camera = scene.camera();
    let projection = [
        camera.projection.x_axis,
        camera.projection.y_axis,
        camera.projection.z_axis,
    ];
    let recorder = TreeRecorder::new(scene, limits);
    let only_light = limits.light;
    match scene.trace_settings().integrator {
        Integrator::Whitted => {
            let (image_point, lens_point, ray, rng) =
                crate::pixel_sample(scene, samples, (i, j), sample);
            let mut tracer = Whitted::with_recorder(scene, recorder);
            tracer.reseed(rng);
            let colour = tracer.trace(&ray, 1.0, 0);
            let cut = tracer.rec.cut();
            let tree = tracer.rec.done.expect("the primary ray ended");
            Explanation {
                sample,
                samples,
                image_point,
                lens_point,
                projection,
                colour,
                trace: Trace::Whitted { ray: tree },
                cut,
                only_light,
            }
        }
        Integrator::Path => {
            let mut tracer = PathTracer::with_recorder(scene, recorder);
            let mut sampler = PixelSampler::new(i, j, tracer.seed());
            let colour = tracer.sample(&mut sampler, (i, j), sample);
            let cut = tracer.rec.cut();
            // The camera's ray, as `sample` made it: the first of its numbers.
            let mut again = PixelSampler::new(i, j, tracer.seed());
            again.start(sample);
            let image_point = Vec2::new(i as f32, j as f32) + again.get2();
            let lens_point = match camera.lens {
                Some(_) => crate::sampling::concentric_disk(again.get2()),
                None => Vec2::ZERO,
            };
            let ray = camera.lens_ray(image_point.x, image_point.y, lens_point);
            let mut first = TreeRecorder::new(scene, limits);
            first.ray(RayKind::Primary, &ray, 1.0, 0);
            first.hit(scene.closest_hit(&ray, EPSILON, f32::INFINITY).as_ref());
            first.end_ray(colour);
            Explanation {
                sample,
                samples,
                image_point,
                lens_point,
                projection,
                colour,
                trace: Trace::Path {
                    ray: first.done.expect("the primary ray ended"),
                    events: tracer.rec.events,
                },
                cut,
                // Path mode's light samples do not name their light.
                only_light: None,
            }
        }
    }
}
