//! Path tracing of small matte scenes sixteen paths at a time: a row's
//! samples go through the scene together, pixel by pixel, a lane that ends
//! a path taking up the next, their nearest hits and shadow rays found in
//! SIMD lanes (every ray of the group against one triangle at a time, each
//! triangle's numbers read once for sixteen rays), where a ray alone would
//! walk the tree. A scene qualifies when it is a few dozen
//! flat triangles (quads, boxes, small meshes) of Lambertian materials,
//! emissive or not, lit by its emitters and point lights: the Cornell box
//! and rooms like it, the scenes the global model of light is learnt on.
//!
//! Each path is the one `PathTracer::radiance` traces, bit for bit: the
//! same random numbers, the same arithmetic in the same order, and the same
//! sums in the same order. The intersection test is `tri4.rs`'s, lane by
//! lane (`rays.rs`); a shadow ray skips the triangles that cannot stand
//! between its light and the scene (`casters.rs`). The camera ray, the
//! density of an emitter a path meets and the MIS weight there are the
//! one-path tracer's own functions; the frame, the light sample
//! (`Lights::sample_of`), the Lambertian lobe, the power heuristic and the
//! roulette are the one-path tracer's formulas on sixteen lanes
//! (`shade.rs`), and a test holds the lanes to the one-path tracer's values
//! on random scenes. The nearest hit is the one testing every triangle finds (of
//! equal distances, the one listed first), which is the tree's but for a
//! few rays from far away or at sliver triangles, grazing where surfaces
//! nearly meet (`accel`). So an image, its ray counts and `tracer explain`
//! agree whichever way a pixel was traced.

// A lane's index reads several arrays at once (the lanes' state is kept
// by field, a structure of arrays, for the SIMD tests).
#![allow(clippy::needless_range_loop)]

mod casters;
mod groups;
mod rays;
mod shade;

use super::reuse::{self, Connection, FirstVertex, Shared};
use crate::bsdf;
use crate::geometry::{Object, Shape};
use crate::integrate::RayStats;
use crate::light::lights::Lights;
use crate::light::Light;
use crate::material::Material;
use crate::ray::Ray;
use crate::sampler::{LaneSamplers, PixelSampler};
use crate::sampling::mis::power_heuristic;
use crate::scene::{Integrator, Scene};
use crate::simd::{F16, V3};
use glam::Vec3;
use groups::Groups;
use multiversion::multiversion;
use rays::Rays;
use shade::{Hits, Pending};
use std::ops::Range;

/// Paths traced together: sixteen of a row's samples at a time.
pub const LANES: usize = 16;

/// Scenes of up to this many triangles qualify: every ray tests them all,
/// which costs less than a walk of the tree only while they are few (the
/// Cornell box has 36).
const MAX_TRIANGLES: usize = 40;

/// A number per lane.
type F = [f32; LANES];

/// A vector per lane, by axis.
type V = [F; 3];

/// One triangle as the test reads it (`Triangle::edges`), its unit normal
/// (`SurfaceHit::on_triangle`'s) and its material.
#[derive(Debug, Clone, Copy)]
struct Tri {
    v0: Vec3,
    e1: Vec3,
    e2: Vec3,
    edge_scale: f32,
    normal: Vec3,
    material: u32,
}

/// A Lambertian material as `LabBsdf` reads it: its albedo (scaled as
/// the BSDF scales it), the probability of picking the lobe (1, or 0 for
/// a material that reflects nothing), and its emission.
#[derive(Debug, Clone, Copy)]
struct Matte {
    albedo: Vec3,
    p_lambert: f32,
    emission: Vec3,
}

/// A scene small and plain enough to be traced in lanes.
#[derive(Debug, Clone)]
pub struct MatteLanes {
    tris: Vec<Tri>,
    materials: Vec<Matte>,
    /// For each light of the table, the triangles its shadow rays are
    /// tested against (`casters.rs`), in groups (`groups.rs`).
    casters: Vec<Groups>,
    /// Every triangle in groups: what the shadow rays of a step whose lanes
    /// picked different lights are tested against.
    all: Groups,
    /// The triangles a segment between two points of the scene can meet
    /// (`casters.rs`): what path reuse's connections are tested against.
    connection_casters: Groups,
}

impl MatteLanes {
    /// `scene` as sixteen paths at a time read it, if it is a small matte
    /// one (`new`) that holds its objects and cuts no holes (the lanes'
    /// search reads no alpha masks): made for each render, by the path
    /// tracer that reads it.
    pub fn of(scene: &Scene) -> Option<MatteLanes> {
        let path_mode = scene.trace_settings().integrator == Integrator::Path;
        if !path_mode || scene.has_alpha_masks() {
            return None;
        }
        let (materials, lights) = (scene.materials(), scene.lights());
        MatteLanes::new(
            scene.every_object()?,
            materials,
            lights,
            scene.path_lights(),
        )
    }

    /// The scene of `objects`, `materials` and `lights` in lanes, if it
    /// qualifies: up to `MAX_TRIANGLES` flat triangles, every material
    /// Lambertian without a texture, every light a point, no environment;
    /// `path_lights` are its lights as path mode samples them.
    pub fn new(
        objects: &[Object],
        materials: &[Material],
        lights: &[Light],
        path_lights: &Lights,
    ) -> Option<MatteLanes> {
        let qualifies = shade::lanes_can_sample(path_lights)
            && !objects.is_empty()
            && objects.len() <= MAX_TRIANGLES
            && lights.iter().all(|l| matches!(l, Light::Point(_)));
        if !qualifies {
            return None;
        }
        let materials = materials.iter().map(matte).collect::<Option<Vec<_>>>()?;
        let tris = objects
            .iter()
            .map(|o| match &o.shape {
                Shape::Triangle(t) if o.vertex_normals.is_none() => {
                    let (e1, e2, edge_scale) = t.edges();
                    Some(Tri {
                        v0: t.v0,
                        e1,
                        e2,
                        edge_scale,
                        normal: e1.cross(e2).normalize(),
                        material: o.material as u32,
                    })
                }
                _ => None,
            })
            .collect::<Option<Vec<_>>>()?;
        let casters = casters::shadow_casters(&tris, path_lights);
        let connection_casters = casters::connection_casters(&tris);
        let size = groups::scene_size(&tris);
        Some(MatteLanes {
            casters: casters.iter().map(|c| Groups::new(c, size)).collect(),
            all: Groups::new(&tris, size),
            connection_casters: Groups::new(&connection_casters, size),
            tris,
            materials,
        })
    }
}

impl MatteLanes {
    /// Whether something lies on each of `connections` (segments between
    /// two points of the scene), sixteen tested at a time against the
    /// triangles that can stand on one: added to `blocked` in order.
    pub(super) fn occluded(&self, connections: &[Connection], blocked: &mut Vec<bool>) {
        for group in connections.chunks(LANES) {
            let mut rays = Rays::NONE;
            let mut reach = [f32::NEG_INFINITY; LANES];
            for (k, c) in group.iter().enumerate() {
                rays.set(k, c.from, c.dir);
                reach[k] = c.reach;
            }
            let hit = groups::occluded(&self.connection_casters, &rays, &reach);
            blocked.extend(hit[..group.len()].iter().map(|&b| b != 0));
        }
    }
}

/// Material `m` as a matte one, if it is Lambertian (no highlight, mirror,
/// glass or texture): its lobe as `LabBsdf` builds it at any hit.
fn matte(m: &Material) -> Option<Matte> {
    let Material::Phong(p) = m else {
        return None;
    };
    if p.texture.is_some() || p.color_texture.is_some() || p.emission_texture.is_some() {
        return None;
    }
    let (albedo, p_lambert) = bsdf::lambert_only(m)?;
    Some(Matte {
        albedo,
        p_lambert,
        emission: p.emission,
    })
}

/// What `PathTracer` lends the lanes: the scene's lights and background
/// (read from the scene's settings as the one-path tracer reads it), the
/// depth limit and its ray counts.
pub(super) struct Setup<'a> {
    pub lights: &'a Lights,
    pub background: Vec3,
    pub max_depth: u32,
    pub stats: &'a mut RayStats,
    /// Whether the paths' first bounces are kept for sharing (`reuse.rs`).
    pub share: bool,
}

/// The state of the lanes' paths, kept by field.
struct Paths {
    alive: [bool; LANES],
    /// Which sample each lane traces: where its value goes.
    sample: [u32; LANES],
    /// Bounces so far.
    depth: [u32; LANES],
    /// Each lane's ray, by axis: the triangle tests read it as it is.
    rays: Rays,
    radiance: V,
    throughput: V,
    /// The last bounce: where it left from, its density, whether specular.
    from: V,
    pdf: F,
    specular: [bool; LANES],
    /// What the path shares (`Setup::share`): its first vertex, and its
    /// second's point, normal, the path's value there and its throughput.
    first: [Option<FirstVertex>; LANES],
    second: [Option<(Vec3, Vec3, Vec3)>; LANES],
    throughput_second: [Vec3; LANES],
}

/// The samples still to trace: those of the pixels `xs` of row `j`,
/// pixel by pixel, each pixel's `samples` in order.
struct Queue<C: Fn() -> bool> {
    row: (Range<u32>, u32),
    samples: Range<u32>,
    seed: u32,
    /// The next one, counted over all of them.
    next: usize,
    /// How many are traced: all of them, unless cancelled.
    end: usize,
    cancelled: C,
}

impl<C: Fn() -> bool> Queue<C> {
    /// Starts lane `k` on the next sample, if there is one: its sampler
    /// into `samplers`, its camera ray from `camera`.
    fn start(
        &mut self,
        (paths, samplers): (&mut Paths, &mut LaneSamplers<LANES>),
        k: usize,
        camera: impl Fn(&mut PixelSampler, (u32, u32)) -> Ray,
    ) {
        let per_pixel = self.samples.len();
        let next = self.next;
        let s = self.samples.start + (next % per_pixel) as u32;
        if next >= self.end || (s % 64 == 63 && (self.cancelled)()) {
            self.end = next;
            return;
        }
        self.next += 1;
        let (i, j) = (self.row.0.start + (next / per_pixel) as u32, self.row.1);
        let mut sampler = PixelSampler::new(i, j, self.seed);
        sampler.start(s);
        let ray = camera(&mut sampler, (i, j));
        samplers.set(k, &sampler);
        paths.begin(k, next as u32, ray);
    }
}

impl MatteLanes {
    /// The values of samples `samples` of each of the pixels `xs` of row
    /// `j` (with the scramblings of `seed`), into `values`, pixel by pixel
    /// and each pixel's in the samples' order (for `PathTracer` to add in
    /// that order), `camera` making each sample's camera ray from its
    /// sampler, started at it. A lane whose path ends takes the next
    /// sample, of its pixel or the next one, so the lanes stay busy. Takes
    /// no new sample once `cancelled` says so (asked as the one-path tracer
    /// asks, every 64 samples of a pixel): `values` then ends there.
    pub(super) fn trace_pixels(
        &self,
        setup: &mut Setup,
        (row, samples, seed): ((Range<u32>, u32), Range<u32>, u32),
        camera: impl Fn(&mut PixelSampler, (u32, u32)) -> Ray,
        (values, shared): (&mut Vec<Vec3>, &mut Vec<Shared>),
        cancelled: impl Fn() -> bool,
    ) {
        let total = row.0.len() * samples.len();
        values.clear();
        values.resize(total, Vec3::ZERO);
        shared.clear();
        if setup.share {
            shared.resize(total, Shared::alone(Vec3::ZERO));
        }
        let mut queue = Queue {
            row,
            samples,
            seed,
            next: 0,
            end: total,
            cancelled,
        };
        let mut samplers = LaneSamplers::new();
        let mut paths = Paths::idle();
        for k in 0..LANES {
            queue.start((&mut paths, &mut samplers), k, &camera);
        }
        while paths.alive.contains(&true) {
            let was_alive = paths.alive;
            self.step(setup, &mut paths, &mut samplers);
            for k in 0..LANES {
                if was_alive[k] && !paths.alive[k] {
                    let (at, value) = (paths.sample[k] as usize, lane(&paths.radiance, k));
                    values[at] = value;
                    if setup.share {
                        shared[at] = paths.shared(k, value);
                    }
                    queue.start((&mut paths, &mut samplers), k, &camera);
                }
            }
        }
        values.truncate(queue.end);
        shared.truncate(queue.end);
    }

    /// One segment of every busy lane's path: its nearest hit, what it
    /// sees there, its light sample and its bounce (`PathTracer::radiance`'s
    /// loop, once).
    fn step(&self, setup: &mut Setup, paths: &mut Paths, samplers: &mut LaneSamplers<LANES>) {
        let (t, tri) = rays::nearest(&self.tris, &paths.rays);
        let hits = self.meet(setup, paths, (&t, &tri));
        let numbers = bounce_numbers(samplers, &hits.shaded);
        let frames = shade::frames(&hits.normal);
        let light_numbers = (&numbers.pick, &numbers.light);
        let pending = shade::light_terms(
            setup.lights,
            (&hits, &frames),
            light_numbers,
            &paths.throughput,
        );
        self.add_light(setup, paths, &hits, &pending);
        shade::bounce(paths, &hits, &frames, &numbers);
    }

    /// Each busy lane's ray meets triangle `tri` at `t` (or leaves the
    /// scene): what it sees is added, and the lane is shaded there unless
    /// the path ends. `PathTracer::radiance`'s loop up to the light sample.
    fn meet(&self, setup: &mut Setup, paths: &mut Paths, (t, tri): (&F, &[u32; LANES])) -> Hits {
        let mut hits = Hits::NONE;
        for k in 0..LANES {
            if !paths.alive[k] {
                continue;
            }
            setup.stats.nearest += 1;
            let Some(tri) = self.tris.get(tri[k] as usize) else {
                let added = lane(&paths.throughput, k) * (setup.background * 1.0);
                add(&mut paths.radiance, k, added);
                paths.alive[k] = false;
                continue;
            };
            let material = self.materials[tri.material as usize];
            let dir = paths.rays.dir(k);
            let p = paths.rays.origin(k) + t[k] * dir;
            let front_face = dir.dot(tri.normal) < 0.0;
            if material.emission != Vec3::ZERO && front_face {
                let weight = if paths.specular[k] {
                    1.0
                } else {
                    let cos = -dir.dot(tri.normal);
                    let from = lane(&paths.from, k);
                    // The object matters only to emissive spheres: none here.
                    let light_pdf = setup.lights.pdf_hit(from, p, cos, material.emission, 0);
                    power_heuristic(paths.pdf[k], light_pdf)
                };
                let added = lane(&paths.throughput, k) * (material.emission * weight);
                add(&mut paths.radiance, k, added);
            }
            if paths.depth[k] == setup.max_depth {
                paths.alive[k] = false;
                continue;
            }
            paths.depth[k] += 1;
            let facing = if front_face { 1.0 } else { -1.0 };
            if setup.share {
                paths.keep_for_sharing(k, (p, tri.normal * facing), &material);
            }
            hits.shaded[k] = true;
            set(&mut hits.point, k, p);
            set(
                &mut hits.from,
                k,
                if front_face { p + Vec3::ZERO } else { p },
            );
            set(&mut hits.normal, k, tri.normal * facing);
            set(&mut hits.albedo, k, material.albedo);
            hits.p_lambert[k] = material.p_lambert;
        }
        hits
    }

    /// Adds each lane's light sample whose shadow ray is clear, all the
    /// shadow rays tested together: against the triangles that can shade
    /// the light they go to, when they all go to one.
    fn add_light(&self, setup: &mut Setup, paths: &mut Paths, hits: &Hits, pending: &Pending) {
        let mut shadow = Rays::NONE;
        let mut reach = [f32::NEG_INFINITY; LANES];
        for k in 0..LANES {
            if pending.shadow[k] {
                setup.stats.shadow += 1;
                shadow.set(k, lane(&hits.from, k), lane(&pending.wi, k));
                reach[k] = pending.reach[k];
            }
        }
        let tris = match pending.one_light() {
            Some(i) => self.casters.get(i).unwrap_or(&self.all),
            None => &self.all,
        };
        let blocked = groups::occluded(tris, &shadow, &reach);
        for k in 0..LANES {
            let clear = pending.shadow[k] & (blocked[k] == 0);
            for a in 0..3 {
                let added = if clear { pending.added[a][k] } else { 0.0 };
                let sum = paths.radiance[a][k] + added;
                paths.radiance[a][k] = if hits.shaded[k] {
                    sum
                } else {
                    paths.radiance[a][k]
                };
            }
        }
    }
}

impl Paths {
    /// No lane busy.
    fn idle() -> Paths {
        Paths {
            alive: [false; LANES],
            sample: [0; LANES],
            depth: [0; LANES],
            rays: Rays::NONE,
            radiance: [[0.0; LANES]; 3],
            throughput: [[1.0; LANES]; 3],
            from: [[0.0; LANES]; 3],
            pdf: [0.0; LANES],
            specular: [true; LANES],
            first: [None; LANES],
            second: [None; LANES],
            throughput_second: [Vec3::ZERO; LANES],
        }
    }

    /// Lane `k` starts the sample whose value goes to `sample`, along
    /// camera ray `ray`.
    fn begin(&mut self, k: usize, sample: u32, ray: Ray) {
        self.alive[k] = true;
        self.sample[k] = sample;
        self.depth[k] = 0;
        self.rays.set(k, ray.origin(), ray.dir());
        set(&mut self.radiance, k, Vec3::ZERO);
        set(&mut self.throughput, k, Vec3::ONE);
        set(&mut self.from, k, ray.origin());
        (self.pdf[k], self.specular[k]) = (0.0, true);
        (self.first[k], self.second[k]) = (None, None);
    }

    /// Keeps what lane `k`'s path shares at the vertex it is shaded at,
    /// `p` of normal `normal` (on the side the path came from), of
    /// `material`: its first vertex where that is Lambertian, and its
    /// second after such a first. `FirstBounces` for the one-path tracer.
    fn keep_for_sharing(&mut self, k: usize, (p, normal): (Vec3, Vec3), material: &Matte) {
        match self.depth[k] {
            1 if material.p_lambert == 1.0 => {
                self.first[k] = Some(FirstVertex {
                    point: p,
                    from: p,
                    normal,
                    albedo: material.albedo,
                })
            }
            2 if self.first[k].is_some() => {
                self.second[k] = Some((p, normal, lane(&self.radiance, k)));
                self.throughput_second[k] = lane(&self.throughput, k);
            }
            _ => {}
        }
    }

    /// What lane `k`'s ended path of value `value` shares.
    fn shared(&self, k: usize, value: Vec3) -> Shared {
        reuse::shared(
            value,
            self.first[k],
            self.second[k],
            self.throughput_second[k],
        )
    }
}

/// Lanes by axis as vectors of lanes.
#[inline(always)]
fn by_axis(v: &V) -> V3<F16> {
    V3::new(F16(v[0]), F16(v[1]), F16(v[2]))
}

/// Vectors of lanes as lanes by axis.
#[inline(always)]
fn axes(v: V3<F16>) -> V {
    [v.x.0, v.y.0, v.z.0]
}

/// Lane `k` of `v`.
#[inline(always)]
fn lane(v: &V, k: usize) -> Vec3 {
    Vec3::new(v[0][k], v[1][k], v[2][k])
}

/// Sets lane `k` of `v` to `x`.
#[inline(always)]
fn set(v: &mut V, k: usize, x: Vec3) {
    (v[0][k], v[1][k], v[2][k]) = (x.x, x.y, x.z);
}

/// Adds `x` to lane `k` of `v`, as `Vec3`'s `+=`.
#[inline(always)]
fn add(v: &mut V, k: usize, x: Vec3) {
    set(v, k, lane(v, k) + x);
}

/// The random numbers of one bounce of each lane, in the order the
/// one-path tracer draws them: the light sample's pick and point, the
/// BSDF sample's lobe and direction, the roulette's; pairs by axis.
struct Numbers {
    pick: F,
    light: (F, F),
    lobe: F,
    direction: (F, F),
    survive: F,
}

/// The numbers of a bounce of each lane in `shaded`, drawn together
/// (`LaneSamplers`: the hashes in SIMD registers), and those lanes moved
/// past them. A lane's numbers are those its one path would draw (it
/// skips what it does not use, so every bounce's numbers stay where they
/// are); the other lanes' are drawn and ignored.
#[multiversion(targets(
    "x86_64+avx512f+avx512bw+avx512dq+avx512vl+gfni",
    "x86_64+avx512f+avx512bw+avx512dq+avx512vl",
    "x86_64+avx2"
))]
fn bounce_numbers(samplers: &mut LaneSamplers<LANES>, shaded: &[bool; LANES]) -> Numbers {
    let numbers = Numbers {
        pick: samplers.get1(0),
        light: samplers.get2(1),
        lobe: samplers.get1(2),
        direction: samplers.get2(3),
        survive: samplers.get1(4),
    };
    for k in 0..LANES {
        samplers.skip(k, if shaded[k] { 5 } else { 0 });
    }
    numbers
}
