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
//! same random numbers, the same arithmetic in the same order, and the
//! same sums in the same order. The intersection test is `tri4.rs`'s,
//! lane by lane; the lights, the frame, the Lambertian lobe, the power
//! heuristic and the camera ray are the one-path tracer's own functions;
//! `LabBsdf`'s Lambertian branch, the light sample's and the roulette's
//! arithmetic are written again here, step for step, and a test holds
//! them to the one-path tracer's values on random scenes. The nearest hit
//! is the one testing every triangle finds (of equal distances, the one
//! listed first), which is the tree's but for a few rays from far away or
//! at sliver triangles, grazing where surfaces nearly meet (`accel`). So
//! an image, its ray counts and `tracer explain` agree whichever way a
//! pixel was traced.

// A lane's index reads several arrays at once (the lanes' state is kept
// by field, a structure of arrays, for the SIMD tests).
#![allow(clippy::needless_range_loop)]

use super::path::{power_heuristic, ROULETTE_DEPTH, SHADOW_SHORTEN};
use super::RayStats;
use crate::bsdf::{Frame, LabBsdf, Lambert};
use crate::geometry::{Object, Shape, SurfaceHit};
use crate::light::lights::{LightSample, Lights};
use crate::light::Light;
use crate::material::Material;
use crate::ray::Ray;
use crate::sampler::{LaneSamplers, PixelSampler};
use crate::EPSILON;
use glam::{Vec2, Vec3};
use multiversion::multiversion;
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
}

impl MatteLanes {
    /// The scene of `objects`, `materials` and `lights` in lanes, if it
    /// qualifies: up to `MAX_TRIANGLES` flat triangles, every material
    /// Lambertian without a texture, every light a point, no environment.
    pub fn new(
        objects: &[Object],
        materials: &[Material],
        lights: &[Light],
        has_environment: bool,
    ) -> Option<MatteLanes> {
        let qualifies = !has_environment
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
        Some(MatteLanes { tris, materials })
    }
}

/// Material `m` as a matte one, if it is Lambertian (no highlight, mirror,
/// glass or texture): its lobe as `LabBsdf` builds it at any hit.
fn matte(m: &Material) -> Option<Matte> {
    let Material::Phong(p) = m else {
        return None;
    };
    if p.texture.is_some() || p.color_texture.is_some() {
        return None;
    }
    let hit = SurfaceHit {
        t: 1.0,
        object: 0,
        material: 0,
        geometric_normal: Vec3::Z,
        shading_normal: Vec3::Z,
        uv: Vec2::ZERO,
        front_face: true,
        shadow_offset: Vec3::ZERO,
    };
    let (albedo, p_lambert) = LabBsdf::new(m, &hit, Vec3::Z).lambert_only()?;
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
}

/// The state of the lanes' paths.
struct Paths {
    alive: [bool; LANES],
    /// Which sample each lane traces: where its value goes.
    sample: [u32; LANES],
    /// Bounces so far.
    depth: [u32; LANES],
    /// Each lane's ray, by axis: the triangle tests read it as it is.
    rays: Rays,
    radiance: [Vec3; LANES],
    throughput: [Vec3; LANES],
    /// The last bounce: where it left from, its density, whether specular.
    from: [Vec3; LANES],
    pdf: F,
    specular: [bool; LANES],
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

/// A lane's shading point: the frame, the material, where light samples
/// and the next ray start.
#[derive(Clone, Copy)]
struct Shading {
    frame: Frame,
    material: Matte,
    point: Vec3,
    from: Vec3,
}

/// A light sample waiting for its shadow ray.
#[derive(Clone, Copy)]
struct Pending {
    added: Vec3,
    /// The shadow ray's direction and reach; None when no ray is needed.
    shadow: Option<(Vec3, f32)>,
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
        values: &mut Vec<Vec3>,
        cancelled: impl Fn() -> bool,
    ) {
        let total = row.0.len() * samples.len();
        values.clear();
        values.resize(total, Vec3::ZERO);
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
                    values[paths.sample[k] as usize] = paths.radiance[k];
                    queue.start((&mut paths, &mut samplers), k, &camera);
                }
            }
        }
        values.truncate(queue.end);
    }

    /// One segment of every busy lane's path: its nearest hit, what it
    /// sees there, its light sample and its bounce (`PathTracer::radiance`'s
    /// loop, once).
    fn step(&self, setup: &mut Setup, paths: &mut Paths, samplers: &mut LaneSamplers<LANES>) {
        let (t, tri) = self.nearest(paths);
        let mut shading = [None; LANES];
        for k in 0..LANES {
            if paths.alive[k] {
                setup.stats.nearest += 1;
                shading[k] = self.meet(setup, paths, k, (t[k], tri[k]));
            }
        }
        let shaded = shading.map(|at| at.is_some());
        let numbers = bounce_numbers(samplers, &shaded);
        let pending = self.light_samples(setup, paths, &shading, &numbers);
        self.add_light(setup, paths, &shading, &pending);
        for k in 0..LANES {
            if let Some(at) = &shading[k] {
                bounce(paths, k, at, &numbers);
            }
        }
    }

    /// Each lane's nearest hit: its distance and triangle (`u32::MAX` for
    /// none).
    fn nearest(&self, paths: &Paths) -> (F, [u32; LANES]) {
        nearest(&self.tris, &paths.rays)
    }

    /// Lane `k`'s ray meets triangle `tri` at `t` (or leaves the scene):
    /// what it sees is added, and the shading point returned unless the
    /// path ends there. `PathTracer::radiance`'s loop up to the light
    /// sample.
    fn meet(
        &self,
        setup: &Setup,
        paths: &mut Paths,
        k: usize,
        (t, tri): (f32, u32),
    ) -> Option<Shading> {
        let Some(tri) = self.tris.get(tri as usize) else {
            let added = paths.throughput[k] * (setup.background * 1.0);
            paths.radiance[k] += added;
            paths.alive[k] = false;
            return None;
        };
        let material = self.materials[tri.material as usize];
        let dir = paths.rays.dir(k);
        let p = paths.rays.origin(k) + t * dir;
        let front_face = dir.dot(tri.normal) < 0.0;
        if material.emission != Vec3::ZERO && front_face {
            let weight = if paths.specular[k] {
                1.0
            } else {
                let cos = -dir.dot(tri.normal);
                let from = paths.from[k];
                // The object matters only to emissive spheres: none here.
                let light_pdf = setup.lights.pdf_hit(from, p, cos, material.emission, 0);
                power_heuristic(paths.pdf[k], light_pdf)
            };
            paths.radiance[k] += paths.throughput[k] * (material.emission * weight);
        }
        if paths.depth[k] == setup.max_depth {
            paths.alive[k] = false;
            return None;
        }
        paths.depth[k] += 1;
        let facing = if front_face { 1.0 } else { -1.0 };
        Some(Shading {
            frame: Frame::new(tri.normal * facing),
            material,
            point: p,
            from: if front_face { p + Vec3::ZERO } else { p },
        })
    }

    /// Each shaded lane's light sample (`PathTracer::light_sample`): what
    /// it adds if its shadow ray is clear.
    fn light_samples(
        &self,
        setup: &Setup,
        paths: &Paths,
        shading: &[Option<Shading>; LANES],
        numbers: &Numbers,
    ) -> [Pending; LANES] {
        let none = Pending {
            added: Vec3::ZERO,
            shadow: None,
        };
        let mut pending = [none; LANES];
        for k in 0..LANES {
            let Some(at) = &shading[k] else { continue };
            if at.material.p_lambert <= 0.0 {
                continue;
            }
            let (pick, u) = (numbers.pick[k], numbers.light[k]);
            if let Some(light) = setup.lights.sample(at.from, pick, u) {
                pending[k] = light_term(at, &light, paths.throughput[k]);
            }
        }
        pending
    }

    /// Adds each lane's light sample whose shadow ray is clear, all the
    /// shadow rays tested together.
    fn add_light(
        &self,
        setup: &mut Setup,
        paths: &mut Paths,
        shading: &[Option<Shading>; LANES],
        pending: &[Pending; LANES],
    ) {
        let mut shadow = Rays::NONE;
        let mut reach = [f32::NEG_INFINITY; LANES];
        for k in 0..LANES {
            if let (Some(at), Some((wi, r))) = (&shading[k], pending[k].shadow) {
                setup.stats.shadow += 1;
                shadow.set(k, at.from, wi);
                reach[k] = r;
            }
        }
        let blocked = occluded(&self.tris, &shadow, &reach);
        for k in 0..LANES {
            if shading[k].is_none() {
                continue;
            }
            let p = &pending[k];
            let clear = p.shadow.is_some() && blocked[k] == 0;
            paths.radiance[k] += if clear { p.added } else { Vec3::ZERO };
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
            radiance: [Vec3::ZERO; LANES],
            throughput: [Vec3::ONE; LANES],
            from: [Vec3::ZERO; LANES],
            pdf: [0.0; LANES],
            specular: [true; LANES],
        }
    }

    /// Lane `k` starts the sample whose value goes to `sample`, along
    /// camera ray `ray`.
    fn begin(&mut self, k: usize, sample: u32, ray: Ray) {
        self.alive[k] = true;
        self.sample[k] = sample;
        self.depth[k] = 0;
        self.rays.set(k, ray.origin(), ray.dir());
        self.radiance[k] = Vec3::ZERO;
        self.throughput[k] = Vec3::ONE;
        (self.from[k], self.pdf[k], self.specular[k]) = (ray.origin(), 0.0, true);
    }
}

/// A light sample at `at` (`PathTracer::light_sample` for a Lambertian
/// lobe): f cos and its density toward the light, the MIS weight, what it
/// adds, and the shadow ray it needs.
fn light_term(at: &Shading, light: &LightSample, throughput: Vec3) -> Pending {
    let (f, bsdf_pdf) = eval(at, light.wi);
    let unlit = f == Vec3::ZERO || light.pdf.is_nan() || light.pdf <= 0.0;
    if unlit {
        return Pending {
            added: Vec3::ZERO,
            shadow: None,
        };
    }
    let weight = if light.point {
        1.0
    } else {
        power_heuristic(light.pdf, bsdf_pdf)
    };
    // Times 1: what no glass absorbs, as the one-path tracer multiplies.
    let added = throughput * (f * light.radiance * (weight / light.pdf)) * Vec3::ONE;
    let reach = light.distance * (1.0 - SHADOW_SHORTEN);
    Pending {
        added,
        shadow: Some((light.wi, reach)),
    }
}

/// `LabBsdf::eval` of a Lambertian lobe toward world direction `wi`.
#[inline(always)]
fn eval(at: &Shading, wi: Vec3) -> (Vec3, f32) {
    let wi = at.frame.to_local(wi);
    if wi.z <= 0.0 {
        return (Vec3::ZERO, 0.0);
    }
    (
        smooth_f(&at.material, wi) * wi.z,
        smooth_pdf(&at.material, wi),
    )
}

/// `LabBsdf::smooth_f` of the Lambertian lobe alone.
#[inline(always)]
fn smooth_f(m: &Matte, wi: Vec3) -> Vec3 {
    let mut f = Vec3::ZERO;
    if m.p_lambert > 0.0 {
        f += Lambert { albedo: m.albedo }.eval(wi);
    }
    f
}

/// `LabBsdf::smooth_pdf` of the Lambertian lobe alone.
#[inline(always)]
fn smooth_pdf(m: &Matte, wi: Vec3) -> f32 {
    let mut pdf = 0.0;
    if m.p_lambert > 0.0 {
        pdf += m.p_lambert * Lambert::pdf(wi);
    }
    pdf
}

/// Lane `k`'s BSDF sample, throughput and roulette at `at`, after its
/// light sample (`PathTracer::radiance`'s loop from the BSDF sample on):
/// its next ray, or its end.
fn bounce(paths: &mut Paths, k: usize, at: &Shading, numbers: &Numbers) {
    let (lobe, u) = (numbers.lobe[k], numbers.direction[k]);
    let Some((wi, weight, pdf)) = sample(&at.material, lobe, u) else {
        paths.alive[k] = false;
        return;
    };
    let wi = at.frame.to_world(wi);
    let mut throughput = paths.throughput[k] * weight;
    (paths.from[k], paths.pdf[k], paths.specular[k]) = (at.from, pdf, false);
    if paths.depth[k] >= ROULETTE_DEPTH {
        let survive = numbers.survive[k];
        // The one-path tracer's eta scale is 1 without glass.
        let q = (throughput * 1.0).max_element();
        if q < 1.0 {
            if survive >= q {
                paths.alive[k] = false;
                return;
            }
            throughput /= q;
        }
    }
    paths.throughput[k] = throughput;
    if throughput == Vec3::ZERO {
        paths.alive[k] = false;
        return;
    }
    paths.rays.set(k, at.point, wi);
    // `Ray::new` keeps the direction as given.
    debug_assert_eq!(Ray::new(at.point, wi).dir(), wi);
}

/// `LabBsdf::sample` of a Lambertian lobe: a local direction, its weight
/// (f cos / pdf) and density; None when the material reflects nothing.
#[inline(always)]
fn sample(m: &Matte, pick: f32, u: Vec2) -> Option<(Vec3, Vec3, f32)> {
    // The lobe is picked when pick < p_lambert: always for 1, never for 0.
    if pick >= m.p_lambert {
        return None;
    }
    let wi = Lambert::sample(u);
    let f = smooth_f(m, wi);
    let pdf = smooth_pdf(m, wi);
    if pdf <= 0.0 || wi.z <= 0.0 {
        return None;
    }
    Some((wi, f * (wi.z / pdf), pdf))
}

/// The random numbers of one bounce of each lane, in the order the
/// one-path tracer draws them: the light sample's pick and point, the
/// BSDF sample's lobe and direction, the roulette's.
struct Numbers {
    pick: F,
    light: [Vec2; LANES],
    lobe: F,
    direction: [Vec2; LANES],
    survive: F,
}

/// The numbers of a bounce of each lane in `shaded`, drawn together
/// (`LaneSamplers`: the hashes in SIMD registers), and those lanes moved
/// past them. A lane's numbers are those its one path would draw (it
/// skips what it does not use, so every bounce's numbers stay where they
/// are); the other lanes' are drawn and ignored.
#[multiversion(targets("x86_64+avx512f+avx512bw+avx512dq+avx512vl", "x86_64+avx2"))]
fn bounce_numbers(samplers: &mut LaneSamplers<LANES>, shaded: &[bool; LANES]) -> Numbers {
    let pair = |(x, y): (F, F)| std::array::from_fn(|k| Vec2::new(x[k], y[k]));
    let numbers = Numbers {
        pick: samplers.get1(0),
        light: pair(samplers.get2(1)),
        lobe: samplers.get1(2),
        direction: pair(samplers.get2(3)),
        survive: samplers.get1(4),
    };
    for k in 0..LANES {
        samplers.skip(k, if shaded[k] { 5 } else { 0 });
    }
    numbers
}

/// Each lane's nearest hit among `tris`: its distance and triangle
/// (`u32::MAX` for none), every triangle tested in list order, a hit
/// taken only when strictly nearer: of equal distances the one listed
/// first, as the tree's rule. Compiled for each processor's widest SIMD
/// registers (the same arithmetic: nothing is fused).
#[multiversion(targets("x86_64+avx512f+avx512bw+avx512dq+avx512vl", "x86_64+avx2"))]
fn nearest(tris: &[Tri], rays: &Rays) -> (F, [u32; LANES]) {
    let mut best = [f32::INFINITY; LANES];
    let mut id = [u32::MAX; LANES];
    let dir_len = rays.dir_len();
    for (j, tri) in tris.iter().enumerate() {
        for k in 0..LANES {
            let (hit, t) = rays.intersect(k, tri, best[k], &dir_len);
            best[k] = if hit { t } else { best[k] };
            id[k] = if hit { j as u32 } else { id[k] };
        }
    }
    (best, id)
}

/// Whether something of `tris` lies on each lane's ray in (EPSILON,
/// reach), 1 or 0 (as wide as a float: a SIMD mask); a lane of reach -inf
/// has no ray and reads 1, so that the search ends once every ray is
/// blocked.
#[multiversion(targets("x86_64+avx512f+avx512bw+avx512dq+avx512vl", "x86_64+avx2"))]
fn occluded(tris: &[Tri], rays: &Rays, reach: &F) -> [u32; LANES] {
    let mut blocked = reach.map(|r| u32::from(r == f32::NEG_INFINITY));
    let dir_len = rays.dir_len();
    for tri in tris {
        for k in 0..LANES {
            blocked[k] |= rays.intersect(k, tri, reach[k], &dir_len).0 as u32;
        }
        if blocked.iter().all(|&b| b != 0) {
            break;
        }
    }
    blocked
}

/// The lanes' rays by axis, for the triangle test in lanes.
#[derive(Clone, Copy)]
struct Rays {
    origin: V,
    dir: V,
}

impl Rays {
    /// No ray: a zero direction meets nothing.
    const NONE: Rays = Rays {
        origin: [[0.0; LANES]; 3],
        dir: [[0.0; LANES]; 3],
    };

    fn origin(&self, k: usize) -> Vec3 {
        Vec3::new(self.origin[0][k], self.origin[1][k], self.origin[2][k])
    }

    fn dir(&self, k: usize) -> Vec3 {
        Vec3::new(self.dir[0][k], self.dir[1][k], self.dir[2][k])
    }

    fn set(&mut self, k: usize, origin: Vec3, dir: Vec3) {
        for a in 0..3 {
            (self.origin[a][k], self.dir[a][k]) = (origin[a], dir[a]);
        }
    }

    /// Each direction's length, as `Vec3::length` (the test's scale).
    #[inline(always)]
    fn dir_len(&self) -> F {
        let d = &self.dir;
        std::array::from_fn(|k| (d[0][k] * d[0][k] + d[1][k] * d[1][k] + d[2][k] * d[2][k]).sqrt())
    }

    /// Moller-Trumbore of lane `k`'s ray against `tri` within (EPSILON,
    /// t_max): `Tri4::intersect_with`'s operations in its order, so the
    /// one-ray search's distances bit for bit. Whether it hits, and where.
    #[inline(always)]
    fn intersect(&self, k: usize, tri: &Tri, t_max: f32, dir_len: &F) -> (bool, f32) {
        let (v0, e1, e2) = (tri.v0.to_array(), tri.e1.to_array(), tri.e2.to_array());
        let o = [self.origin[0][k], self.origin[1][k], self.origin[2][k]];
        let d = [self.dir[0][k], self.dir[1][k], self.dir[2][k]];
        let s = [o[0] - v0[0], o[1] - v0[1], o[2] - v0[2]];
        let q = cross(s, e1);
        let t_times_det = dot(e2, q);
        let p = cross(d, e2);
        let det = dot(e1, p);
        let parallel = det.abs() < tri.edge_scale * dir_len[k];
        let inv = 1.0 / det;
        let u = dot(s, p) * inv;
        // `&` and `|`, not `&&` and `||` (nor `contains`): no branch, so
        // the lanes are tested in SIMD registers.
        #[allow(clippy::manual_range_contains)]
        let u_inside = (u >= 0.0) & (u <= 1.0);
        let v = dot(d, q) * inv;
        let v_outside = (v < 0.0) | (u + v > 1.0);
        let t = t_times_det * inv;
        let t_inside = (t > EPSILON) & (t < t_max);
        (!parallel & u_inside & !v_outside & t_inside, t)
    }
}

/// `a x b`, as `Vec3::cross`.
#[inline(always)]
fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - b[1] * a[2],
        a[2] * b[0] - b[2] * a[0],
        a[0] * b[1] - b[0] * a[1],
    ]
}

/// `a . b`, as `Vec3::dot`.
#[inline(always)]
fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
