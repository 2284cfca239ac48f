//! The lab's `rayTrace`: Blinn-Phong in the lab's order, shadows, texture,
//! and mirror recursion with energy (lab sections 4 and 5); beyond the
//! lab, refraction through glass and sphere lights' soft shadows.

use super::record::{LightTerm, RayKind, Recorder, ShadowRay, Silent, Stop};
use super::RayStats;
use crate::accel::PACKET;
use crate::geometry::SurfaceHit;
use crate::light::{Light, SphereLight};
use crate::material::{Glass, Material, Phong};
use crate::ray::{Ray, NO_RAY};
use crate::sampling::{concentric_disk, Rng, Strata};
use crate::scene::Scene;
use crate::EPSILON;
use glam::Vec3;

/// The lab's threshold on the cosines of the diffuse and specular terms.
pub(super) const COS_THRESHOLD: f32 = 0.001;

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

impl Shaded {
    /// The hit `hit` of `ray`, at `p`.
    fn new(p: Vec3, ray: &Ray, hit: &SurfaceHit) -> Shaded {
        Shaded {
            p,
            n: hit.shading_normal,
            view: -ray.dir(),
            shadow_origin: p + hit.shadow_offset,
        }
    }
}

/// The light from a light point as a shaded point sees it: the unit
/// direction `l` toward it, the cosine `cos_a` of its angle with the
/// normal, and the shadow ray and its length.
struct LightRay {
    l: Vec3,
    cos_a: f32,
    shadow: Ray,
    length: f32,
}

impl LightRay {
    /// The light from `from` at `at`; None when it falls too flat or on
    /// the back (no shadow ray is cast then).
    fn new(at: &Shaded, from: Vec3) -> Option<LightRay> {
        let to_light = from - at.p;
        let distance = to_light.length();
        let l = to_light / distance;
        let cos_a = at.n.dot(l);
        if cos_a <= COS_THRESHOLD {
            return None;
        }
        let (shadow, length) = shadow_ray(at, from, l, distance);
        Some(LightRay {
            l,
            cos_a,
            shadow,
            length,
        })
    }
}

/// Most point lights whose shadow rays from a packet of samples' first
/// hits are searched together, ahead of their shading.
const AHEAD_LIGHTS: usize = 4;

/// The answers of the shadow rays searched ahead for the sample being
/// shaded, in the order its shading asks them: each ray, its length and
/// whether it is blocked.
#[derive(Clone, Copy)]
struct Ahead {
    answers: [(Ray, f32, bool); AHEAD_LIGHTS],
    len: usize,
    next: usize,
}

impl Ahead {
    const NONE: Ahead = Ahead {
        answers: [(NO_RAY, 0.0, false); AHEAD_LIGHTS],
        len: 0,
        next: 0,
    };

    fn push(&mut self, ray: Ray, length: f32, blocked: bool) {
        self.answers[self.len] = (ray, length, blocked);
        self.len += 1;
    }

    /// The answer found ahead for the shadow ray `ray` of `length`, if the
    /// next one is its: the same question, so the same answer.
    fn take(&mut self, ray: &Ray, length: f32) -> Option<bool> {
        let &(r, l, blocked) = self.answers[..self.len].get(self.next)?;
        (r == *ray && l == length).then(|| {
            self.next += 1;
            blocked
        })
    }
}

/// Traces rays through one scene, counting them; one per thread, reseeded
/// for each pixel sample so that soft shadows are the same on every run.
/// What it computes is told to `rec` (`record.rs`): nothing for renders.
pub struct Whitted<'a, R: Recorder = Silent> {
    scene: &'a Scene,
    pub stats: RayStats,
    pub rec: R,
    /// Why the next ray is traced, for the recorder.
    next_kind: RayKind,
    rng: Rng,
    /// The shadow rays searched ahead for each sample of a packet
    /// (`trace_samples`), and which sample is being shaded (none: no
    /// answers).
    ahead: [Ahead; PACKET],
    shading: Option<usize>,
    /// The mirror and refracted rays the current sample may still trace,
    /// and whether it has wanted one more (its tree is cut).
    rays_left: u32,
    tree_cut: bool,
}

/// The most mirror and refracted rays one sample traces. Glass splits
/// each ray in two, so a tree may double at every level: at `max_depth =
/// 64` with `min_energy = 0` a pixel would take 2^64 rays. The lab's
/// scenes take at most a few hundred; the rays past this are not traced
/// (and the render says so).
pub const MAX_TREE_RAYS: u32 = 4096;

impl<'a> Whitted<'a> {
    pub fn new(scene: &'a Scene) -> Self {
        Whitted::with_recorder(scene, Silent)
    }
}

impl<'a, R: Recorder> Whitted<'a, R> {
    /// A tracer that tells `rec` what it computes.
    pub fn with_recorder(scene: &'a Scene, rec: R) -> Self {
        Whitted {
            scene,
            stats: RayStats::default(),
            rec,
            next_kind: RayKind::Primary,
            rng: Rng::new(0),
            ahead: [Ahead::NONE; PACKET],
            shading: None,
            rays_left: MAX_TREE_RAYS,
            tree_cut: false,
        }
    }

    /// The colours of samples (a pixel's, or neighbouring pixels'), into
    /// `colours`: primary rays `rays`, their nearest hits `hits`
    /// (`Scene::closest_hits`) and random numbers `rngs`. The shadow rays
    /// of their hits toward the point lights are searched together first;
    /// each sample's shading then takes their answers, and the colours are
    /// those of `trace`.
    pub fn trace_samples(
        &mut self,
        rays: &[Ray],
        hits: &[Option<SurfaceHit>],
        rngs: &[Rng],
        colours: &mut [Vec3],
    ) {
        self.shadows_ahead(rays, hits);
        for (k, ((ray, hit), rng)) in rays.iter().zip(hits).zip(rngs).enumerate() {
            self.reseed(*rng);
            self.shading = Some(k);
            colours[k] = self.trace_from(ray, hit.as_ref(), 1.0, 0);
        }
        self.shading = None;
    }

    /// Finds, into `ahead`, the answers of the shadow rays the shading of
    /// `hits` will cast toward the first `AHEAD_LIGHTS` point lights,
    /// searched together light by light: none where glass makes a shadow
    /// ray a walk, or where there is no tree to walk together.
    fn shadows_ahead(&mut self, rays: &[Ray], hits: &[Option<SurfaceHit>]) {
        for ahead in &mut self.ahead[..rays.len()] {
            (ahead.len, ahead.next) = (0, 0);
        }
        let scene = self.scene;
        if scene.has_transparency() || !scene.searches_together() {
            return;
        }
        let points = scene.lights().iter().filter_map(|light| match light {
            Light::Point(point) => Some(point.position),
            _ => None,
        });
        for from in points.take(AHEAD_LIGHTS) {
            let (mut samples, mut shadow_rays, mut lengths) =
                ([0; PACKET], [NO_RAY; PACKET], [0.0; PACKET]);
            let mut n = 0;
            for (k, (ray, hit)) in rays.iter().zip(hits).enumerate() {
                let Some(hit) = hit.filter(|hit| self.shaded_locally(hit)) else {
                    continue;
                };
                let at = Shaded::new(ray.at(hit.t), ray, &hit);
                if let Some(light) = LightRay::new(&at, from) {
                    (samples[n], shadow_rays[n], lengths[n]) = (k, light.shadow, light.length);
                    n += 1;
                }
            }
            let blocked = scene.occluded_together(&shadow_rays[..n], EPSILON, &lengths[..n]);
            for j in 0..n {
                let blocked = blocked & (1 << j) != 0;
                self.ahead[samples[j]].push(shadow_rays[j], lengths[j], blocked);
            }
        }
    }

    /// Whether the shading of `hit` lights it (and casts shadow rays):
    /// Blinn-Phong, and glass seen from outside.
    fn shaded_locally(&self, hit: &SurfaceHit) -> bool {
        match self.scene.material(hit.material).lab() {
            Material::Glass(_) => hit.front_face,
            _ => true,
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
        self.trace_from(ray, hit.as_ref(), energy, depth)
    }

    /// `trace`, the ray's nearest hit (in (EPSILON, inf)) already found:
    /// a pixel's samples are searched together (`Scene::closest_hits`).
    pub fn trace_from(
        &mut self,
        ray: &Ray,
        hit: Option<&SurfaceHit>,
        energy: f32,
        depth: u32,
    ) -> Vec3 {
        self.stats.nearest += 1;
        if depth == 0 {
            // A primary ray: a new tree.
            (self.rays_left, self.tree_cut) = (MAX_TREE_RAYS, false);
        }
        let scene = self.scene;
        let kind = std::mem::replace(&mut self.next_kind, RayKind::Primary);
        self.rec.ray(kind, ray, energy, depth);
        self.rec.hit(hit);
        let Some(hit) = hit else {
            // With the lab's black background this adds nothing, as in the lab.
            let colour = energy * scene.background(ray.dir());
            self.rec.end_ray(colour);
            return colour;
        };
        // A physically based material is shaded by its lab reading.
        let colour = match scene.material(hit.material).lab() {
            Material::Glass(g) => self.glass(g, ray, hit, energy, depth),
            m => self.phong(m.surface(), ray, hit, energy, depth),
        };
        self.rec.end_ray(colour);
        colour
    }

    /// `trace` of a ray traced for `kind`.
    /// Past the sample's budget of rays it brings nothing back.
    fn trace_as(&mut self, kind: RayKind, ray: &Ray, energy: f32, depth: u32) -> Vec3 {
        if self.rays_left == 0 {
            self.rec.stopped(Stop::RayBudget {
                rays: MAX_TREE_RAYS,
            });
            // Counted once a sample: a tree of exactly the budget is whole.
            self.stats.cut_trees += u64::from(!self.tree_cut);
            self.tree_cut = true;
            return Vec3::ZERO;
        }
        self.rays_left -= 1;
        self.next_kind = kind;
        self.trace(ray, energy, depth)
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
        let mut colour = energy * self.textured_local(m, ray, hit);
        let emission = m.emission_at(hit.uv);
        if emission != Vec3::ZERO && hit.front_face {
            // Seen (and mirrored), lighting nothing: Whitted mode has no
            // area lights. Skipped otherwise, so the lab's sums stay.
            self.rec.emitted(emission);
            colour += energy * emission;
        }
        if m.reflectance > 0.0 && self.may_recurse(energy, depth) {
            let reflected = ray.reflected(p, n);
            colour += self.trace_as(
                RayKind::Reflected,
                &reflected,
                energy * m.reflectance,
                depth + 1,
            );
        } else if m.reflectance > 0.0 {
            self.record_stop(depth);
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
            energy * self.textured_local(&g.surface, ray, hit)
        } else {
            Vec3::ZERO
        };
        let emission = g.surface.emission_at(hit.uv);
        if emission != Vec3::ZERO && hit.front_face {
            self.rec.emitted(emission);
            colour += energy * emission;
        }
        let split = g.split(ray.dir(), hit);
        if !self.may_recurse(energy, depth) {
            if split.reflected > 0.0 || split.transmitted.is_some() {
                self.record_stop(depth);
            }
        } else {
            if split.reflected > 0.0 {
                let reflected = ray.reflected(p, hit.shading_normal);
                let energy = energy * split.reflected;
                colour += self.trace_as(RayKind::Reflected, &reflected, energy, depth + 1);
            }
            if let Some((dir, share)) = split.transmitted {
                let refracted = Ray::new(p, dir);
                colour += self.trace_as(RayKind::Refracted, &refracted, energy * share, depth + 1);
            }
        }
        if !hit.front_face {
            let factor = g.absorbed_over(hit.t);
            self.rec.absorbed(factor);
            colour *= factor;
        }
        colour
    }

    /// Tells the recorder which of the tree's limits stopped it here.
    fn record_stop(&mut self, depth: u32) {
        let settings = self.scene.trace_settings();
        self.rec.stopped(if depth >= settings.max_depth {
            Stop::MaxDepth {
                max_depth: settings.max_depth,
            }
        } else {
            Stop::MinEnergy {
                min_energy: settings.min_energy,
            }
        });
    }

    /// The local colour of material `m` at `ray`'s hit `hit` (its colour
    /// texture on ambient and diffuse), times its lab texture. The point is
    /// found here, not passed: handed over in memory, it was read back in
    /// pieces the processor could not forward from the caller's writes.
    fn textured_local(&mut self, m: &Phong, ray: &Ray, hit: &SurfaceHit) -> Vec3 {
        let p = ray.at(hit.t);
        let terms = Terms::at(m, hit);
        let local = self.local_colour(&terms, ray, p, hit);
        match &m.texture {
            Some(texture) => {
                let texel = texture.texel(hit.uv);
                self.rec.local(local, Some(texel));
                local * texel
            }
            None => {
                self.rec.local(local, None);
                local
            }
        }
    }

    /// Ambient, diffuse and specular of every light at `p`, in the lab's
    /// order: ambient once per light and always; diffuse and specular only
    /// where the light is not shadowed.
    fn local_colour(&mut self, m: &Terms, ray: &Ray, p: Vec3, hit: &SurfaceHit) -> Vec3 {
        let at = Shaded::new(p, ray, hit);
        let mut colour = Vec3::ZERO;
        for (k, light) in self.scene.lights().iter().enumerate() {
            colour += light.color() * m.ambient;
            self.rec.ambient(k, light.color() * m.ambient);
            match light {
                Light::Point(light) => {
                    self.direct(m, &at, (k, light.position), light.color, &mut colour);
                }
                Light::Sphere(light) => colour += self.sphere_light(m, &at, (k, light)),
                Light::Spot(light) => {
                    let color = light.color * light.falloff(at.p);
                    self.direct(m, &at, (k, light.position), color, &mut colour);
                }
                Light::Directional(light) => {
                    let from = at.p - light.direction * crate::light::FAR_AWAY;
                    self.direct(m, &at, (k, from), light.color, &mut colour);
                }
            }
        }
        colour
    }

    /// Diffuse and specular of a sphere light: the mean over
    /// `light_samples` points of its disk, stratified, each with its own
    /// shadow ray.
    fn sphere_light(&mut self, m: &Terms, at: &Shaded, (k, light): (usize, &SphereLight)) -> Vec3 {
        let samples = self.scene.trace_settings().light_samples.max(1);
        let strata = Strata::new(samples);
        let mut sum = Vec3::ZERO;
        for s in 0..samples {
            let disk = concentric_disk(strata.point(s, self.rng.square()));
            let from = light.point_seen_from(at.p, disk);
            self.direct(m, at, (k, from), light.color, &mut sum);
        }
        sum / samples as f32
    }

    /// Adds to `colour` the diffuse and specular of light `color` from
    /// point `from` (lab 4.4), dimmed by what lies between; term by term,
    /// in the lab's order of additions. Inlined: called apart, it read the
    /// shading point back from memory just after its caller wrote it, in
    /// pieces the processor cannot forward from those writes (a fifth of
    /// its time at 1.1M; reflectance2 renders 13 % faster).
    #[inline(always)]
    fn direct(
        &mut self,
        m: &Terms,
        at: &Shaded,
        (light, from): (usize, Vec3),
        color: Vec3,
        colour: &mut Vec3,
    ) {
        let term = LightTerm {
            light,
            from,
            color,
            l: (from - at.p).normalize(),
            n_dot_l: at.n.dot((from - at.p).normalize()),
            shadow: None,
            h: None,
            n_dot_h: None,
            n_dot_h_pow: None,
            diffuse: Vec3::ZERO,
            specular: Vec3::ZERO,
        };
        let Some(LightRay {
            l,
            cos_a,
            shadow,
            length,
        }) = LightRay::new(at, from)
        else {
            self.rec.light(&term);
            return;
        };
        let passes = self.shadow(&shadow, length);
        let term = LightTerm {
            l,
            n_dot_l: cos_a,
            shadow: Some(ShadowRay {
                origin: shadow.origin(),
                direction: shadow.dir(),
                length,
                passes,
            }),
            ..term
        };
        let Some(through) = passes else {
            self.rec.light(&term);
            return;
        };
        // 1 exactly unless glass is in the way: the lab's arithmetic stays.
        let color = color * through;
        let diffuse = color * m.diffuse * cos_a;
        *colour += diffuse;
        let h = (l + at.view).normalize();
        let cos_b = at.n.dot(h);
        // No specular colour adds nothing: powf is skipped, the sum is the same.
        let mut term = LightTerm {
            diffuse,
            h: Some(h),
            n_dot_h: Some(cos_b),
            ..term
        };
        if cos_b > COS_THRESHOLD && m.specular != Vec3::ZERO {
            let power = cos_b.powf(m.shininess);
            let specular = color * m.specular * power;
            *colour += specular;
            (term.n_dot_h_pow, term.specular) = (Some(power), specular);
        }
        self.rec.light(&term);
    }

    /// What reaches along `ray` over `distance`: `None` when something
    /// opaque is in the way, else the product of the transparent surfaces'
    /// transmittances and their insides' absorption (no refraction: shadow
    /// rays go straight, so glass casts no caustics).
    fn shadow(&mut self, ray: &Ray, distance: f32) -> Option<Vec3> {
        self.stats.shadow += 1;
        let scene = self.scene;
        if !scene.has_transparency() {
            let ahead = self.shading.map(|k| &mut self.ahead[k]);
            let blocked = match ahead.and_then(|ahead| ahead.take(ray, distance)) {
                Some(blocked) => blocked,
                None => scene.occluded(ray, EPSILON, distance),
            };
            return (!blocked).then_some(Vec3::ONE);
        }
        let mut through = Vec3::ONE;
        let mut ray = *ray;
        let mut left = distance;
        for _ in 0..MAX_SHADOW_CROSSINGS {
            let Some(hit) = scene.closest_hit(&ray, EPSILON, left) else {
                return Some(through);
            };
            let Material::Glass(g) = scene.material(hit.material).lab() else {
                return None;
            };
            let passes = g.shadow_transmission(ray.dir(), &hit);
            if passes <= 0.0 {
                return None;
            }
            through *= passes;
            if !hit.front_face {
                through *= g.absorbed_over(hit.t);
            }
            ray = Ray::new(ray.at(hit.t), ray.dir());
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
        let Material::Glass(g) = scene.material(hit.material).lab() else {
            break;
        };
        let Some((dir, _)) = g.split(last.dir(), &hit).transmitted else {
            break;
        };
        path.push(Ray::new(last.at(hit.t), dir));
    }
    path
}
