//! Path tracing: the global model of light of lab section 1.5.1, where
//! objects light each other. A `PathTracer` per thread; the radiance of
//! one path is `estimator.rs`; this file runs it over a pixel's samples
//! and a row's pixels, alone, in lanes (`matte_lanes/`) or in groups that
//! share their paths (`reuse.rs`), with more camera rays where a pixel
//! sees an edge (`seen.rs`), as `defaults.rs` sets them.
//!
//! `max_depth` counts as pbrt-v4's `maxdepth`: 0 shows only what emits,
//! seen directly; 1 adds direct light; each more one bounce of indirect
//! light.

pub mod defaults;
mod estimator;
mod inside;
pub(crate) mod matte_lanes;
pub mod reuse;
pub(crate) mod roulette;
mod seen;

use crate::integrate::record::{Recorder, Silent};
use crate::integrate::RayStats;
use crate::ray::Ray;
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use crate::EPSILON;
use glam::{DVec3, Vec3};
use matte_lanes::{MatteLanes, LANES};
use reuse::{Combiner, Connection, FirstBounces, Glossy};
use std::cell::OnceCell;
use std::ops::Range;
use std::sync::Arc;

/// How many values of samples traced in lanes wait at most to be added in
/// order (12 bytes each): a row's pixels are traced together up to this
/// many samples in all.
const LANE_VALUES: usize = 1 << 16;

/// How many paths traced in lanes wait at most to be shared (about 100
/// bytes each, `reuse::Shared`): few enough to stay in the cache until
/// their groups are combined.
const SHARED_PATHS: usize = 1 << 12;

/// How the light reaching a smooth lobe is found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Strategy {
    /// Light samples and BSDF samples, weighted by the power heuristic.
    #[default]
    Mis,
    /// Light samples alone (a BSDF sample that meets a light adds nothing
    /// after a smooth bounce).
    Lights,
    /// BSDF samples alone (no light samples; point lights are then never
    /// found).
    Bsdf,
}

/// Traces paths through one scene, counting rays; one per thread.
pub struct PathTracer<'a, R: Recorder = Silent> {
    scene: &'a Scene,
    max_depth: u32,
    /// Which set of scramblings the samples use (0 for renders).
    seed: u32,
    strategy: Strategy,
    /// Whether a small matte scene's paths go sixteen at a time
    /// (`matte_lanes/`, the same values): where the processor has wide
    /// SIMD registers, unless a test says otherwise.
    in_lanes: bool,
    /// The scene as the lanes read it, made on the first call that asks
    /// (`matte_lanes`): None if it is not a small matte one.
    matte: OnceCell<Option<Arc<MatteLanes>>>,
    /// The values of samples traced in lanes, waiting to be added to
    /// their pixels in order (kept from call to call).
    lane_values: Vec<Vec3>,
    /// What those samples share, when pixels share their paths.
    lane_shared: Vec<reuse::Shared>,
    /// How many neighbouring pixels of a row share their paths' first
    /// bounces (`reuse.rs`): 1 shares nothing.
    reuse: u32,
    /// Camera rays per path for what a pixel sees directly, where that
    /// changes across it (`seen.rs`): 1 is the path's own.
    camera_rays: u32,
    pub stats: RayStats,
    /// Told what each bounce does (`record.rs`): nothing for renders.
    pub rec: R,
}

impl<'a> PathTracer<'a> {
    pub fn new(scene: &'a Scene) -> Self {
        PathTracer::with_recorder(scene, Silent)
    }
}

impl<'a, R: Recorder> PathTracer<'a, R> {
    /// A tracer that tells `rec` what each bounce does.
    pub fn with_recorder(scene: &'a Scene, rec: R) -> Self {
        PathTracer {
            scene,
            max_depth: scene.trace_settings().max_depth,
            seed: 0,
            strategy: Strategy::Mis,
            in_lanes: wide_simd(),
            matte: OnceCell::new(),
            lane_values: Vec::new(),
            lane_shared: Vec::new(),
            reuse: scene.trace_settings().path_reuse.clamp(1, reuse::MAX_GROUP),
            camera_rays: (scene.trace_settings().camera_rays).clamp(1, seen::MAX_CAMERA_RAYS),
            stats: RayStats::default(),
            rec,
        }
    }

    /// The same tracer with another set of scramblings: independent
    /// renders of the same scene (for tests of the noise).
    pub fn with_seed(self, seed: u32) -> Self {
        PathTracer { seed, ..self }
    }

    /// The same tracer with paths of at most `max_depth` (tests).
    pub fn with_max_depth(self, max_depth: u32) -> Self {
        PathTracer { max_depth, ..self }
    }

    /// The same tracer finding light by `strategy` alone (tests: each
    /// strategy converges to the same image).
    pub fn with_strategy(self, strategy: Strategy) -> Self {
        PathTracer { strategy, ..self }
    }

    /// The same tracer with groups of `pixels` sharing their paths' first
    /// bounces in rows (tests; scenes say it with `path_reuse`).
    pub fn with_reuse(self, pixels: u32) -> Self {
        PathTracer {
            reuse: pixels.clamp(1, reuse::MAX_GROUP),
            ..self
        }
    }

    /// The same tracer with `rays` camera rays per path for what a pixel
    /// sees directly (tests; scenes say it with `camera_rays`).
    pub fn with_camera_rays(self, rays: u32) -> Self {
        PathTracer {
            camera_rays: rays.clamp(1, seen::MAX_CAMERA_RAYS),
            ..self
        }
    }

    /// The same tracer tracing every path alone (tests: the lanes give
    /// the same values).
    pub fn one_at_a_time(self) -> Self {
        PathTracer {
            in_lanes: false,
            ..self
        }
    }

    /// The same tracer tracing a small matte scene's paths in lanes even
    /// where the processor's SIMD registers are narrow (tests).
    pub fn in_lanes(self) -> Self {
        PathTracer {
            in_lanes: true,
            ..self
        }
    }

    /// Pixel (column i, row j): the mean of `samples` paths through it, a
    /// sample whose value is not finite dropped (and counted). Gives up
    /// between samples once `cancelled` says so.
    pub fn pixel(&mut self, i: u32, j: u32, samples: u32, cancelled: impl Fn() -> bool) -> Vec3 {
        let mut sum = PixelSum::default();
        self.add_samples(i, j, 0..samples, &mut sum, cancelled);
        sum.mean()
    }

    /// Adds samples `samples` of pixel (i, j) to `sum`, in order, a sample
    /// whose value is not finite dropped (and counted): `pixel` over passes
    /// (`film.rs`), the same additions in the same order. Gives up between
    /// samples once `cancelled` says so.
    pub fn add_samples(
        &mut self,
        i: u32,
        j: u32,
        samples: Range<u32>,
        sum: &mut PixelSum,
        cancelled: impl Fn() -> bool,
    ) {
        // Fewer samples than lanes would leave lanes idle, each test of a
        // triangle costing what sixteen rays' would: one ray alone walks the
        // tree (a pixel's 1 sample takes 5 times as long in lanes; `add_row`
        // puts a row's together).
        if let Some(lanes) = self.lanes().filter(|_| samples.len() >= LANES) {
            let one = std::slice::from_mut(sum);
            self.add_pixels_in_lanes(&lanes, (i..i + 1, j), samples, one, cancelled);
            return;
        }
        let mut sampler = PixelSampler::new(i, j, self.seed);
        let varies = self.seen_varies((i, j));
        for s in samples {
            if s % 64 == 63 && cancelled() {
                break;
            }
            let radiance = self.sample(&mut sampler, (i, j), s);
            self.add_value(sum, radiance, (i, j, s), varies);
        }
    }

    /// Which of the pixels `xs` of row `j` take more camera rays for what
    /// they see directly (`seen_varies`).
    fn row_varies(&mut self, (xs, j): (Range<u32>, u32)) -> Vec<bool> {
        xs.map(|i| self.seen_varies((i, j))).collect()
    }

    /// Whether pixel (i, j) takes more camera rays for what it sees
    /// directly (`seen.rs`): never unless the scene asks for them (nor
    /// where a recorder follows the paths).
    fn seen_varies(&mut self, pixel: (u32, u32)) -> bool {
        self.takes_camera_rays() && seen::varies(&self.looks(pixel))
    }

    /// Whether more camera rays are asked for (and no recorder follows
    /// the paths).
    fn takes_camera_rays(&self) -> bool {
        self.camera_rays > 1 && R::SILENT
    }

    /// What pixel (i, j)'s centre and corners see directly (`seen::looks`).
    fn looks(&mut self, pixel: (u32, u32)) -> [Vec3; 5] {
        let scene = self.scene;
        seeing(scene, &mut self.stats, |see| seen::looks(scene, pixel, see))
    }

    /// What samples `samples` of pixel (i, j) see directly, in the mean,
    /// as `add_samples` counts it: the light their paths' first segments
    /// add (an emitter's front, the sky or background), through more
    /// camera rays where the pixel takes them (`seen.rs`). The pixel's
    /// value less this is the light that bounced, which a denoiser is
    /// given (the pipeline's `denoise`): exactly, but for rounding and a
    /// sample dropped for a value that was not finite. 0 where the
    /// pixel's centre and corners see no light (never more than the
    /// render counted, so the difference is never below 0): a room's walls
    /// cost five rays, not one a sample.
    pub fn seen_light(&mut self, i: u32, j: u32, samples: Range<u32>) -> Vec3 {
        let looks = self.looks((i, j));
        let varies = self.takes_camera_rays() && seen::varies(&looks);
        if !varies && seen::dark(&looks) {
            return Vec3::ZERO;
        }
        let (scene, seed, rays) = (self.scene, self.seed, self.camera_rays);
        let count = samples.len().max(1) as f32;
        seeing(scene, &mut self.stats, |see| {
            let mut sum = Vec3::ZERO;
            for s in samples {
                sum += match varies {
                    true => seen::extra(scene, (seed, rays), (i, j, s), &mut *see),
                    false => seen::own(scene, seed, (i, j, s), &mut *see),
                };
            }
            sum / count
        })
    }

    /// Adds `value`, of sample `s` of pixel (i, j), to `sum`, with what
    /// more camera rays see directly in place of its own where the pixel
    /// `varies`; a value that is not finite is dropped (and counted).
    fn add_value(
        &mut self,
        sum: &mut PixelSum,
        value: Vec3,
        (i, j, s): (u32, u32, u32),
        varies: bool,
    ) {
        let value = match varies {
            true => {
                let rays = (self.seed, self.camera_rays);
                let scene = self.scene;
                let pixel = (i, j, s);
                value
                    + seeing(scene, &mut self.stats, |see| {
                        seen::correction(scene, rays, pixel, see)
                    })
            }
            false => value,
        };
        if value.is_finite() {
            sum.add(value);
        } else {
            self.stats.dropped += 1;
        }
    }

    /// The scene in lanes, if it is a small matte one and nothing asks
    /// for paths one at a time (a recorder, a strategy of tests).
    fn lanes(&self) -> Option<Arc<MatteLanes>> {
        let alone = !R::SILENT || !self.in_lanes || self.strategy != Strategy::Mis;
        if alone {
            return None;
        }
        let made = self
            .matte
            .get_or_init(|| MatteLanes::of(self.scene).map(Arc::new));
        made.clone()
    }

    /// The pixels of a group that share their paths' first bounces, if
    /// any do: paths must have a bounce after the first, whose weights are
    /// the renders' (MIS) and not followed by a recorder.
    fn reuse_group(&self) -> Option<u32> {
        let shares = self.reuse > 1 && self.max_depth >= 2;
        (shares && R::SILENT && self.strategy == Strategy::Mis).then_some(self.reuse)
    }

    /// `add_row` with the row's paths shared in groups of `group` pixels.
    /// The groups are fixed in the image (their first columns multiples of
    /// `group`), so a region or a tile renders its pixels as the whole
    /// image does: a group that the row `xs` cuts is traced whole, and its
    /// pixels outside `xs` are left out.
    fn add_row_reused(
        &mut self,
        (xs, j): (Range<u32>, u32),
        samples: Range<u32>,
        sums: &mut [PixelSum],
        cancelled: impl Fn() -> bool,
        group: u32,
    ) {
        let width = self.scene.camera().width.max(xs.end);
        let whole = xs.start / group * group..(xs.end.div_ceil(group) * group).min(width);
        let mut whole_sums: Vec<PixelSum> = whole
            .clone()
            .map(|i| match xs.contains(&i) {
                true => sums[(i - xs.start) as usize],
                false => PixelSum::default(),
            })
            .collect();
        let paths = whole.len() * samples.len();
        let lanes = self.lanes().filter(|_| paths >= LANES);
        // In lanes, whole groups at a time, as many as `SHARED_PATHS`
        // allows; alone, a group at a time.
        let per_group = group as usize * samples.len().max(1);
        let together = match &lanes {
            Some(_) => (SHARED_PATHS / per_group).max(1) * group as usize,
            None => group as usize,
        };
        for (xs, sums) in row_chunks(whole.start, &mut whole_sums, together) {
            match &lanes {
                Some(lanes) => {
                    let work = ((xs, j), samples.clone(), group);
                    self.add_groups_in_lanes(lanes, work, sums, &cancelled);
                }
                None => self.add_group((xs, j), samples.clone(), sums, &cancelled),
            }
        }
        for (i, sum) in whole.zip(whole_sums) {
            if xs.contains(&i) {
                sums[(i - xs.start) as usize] = sum;
            }
        }
    }

    /// `add_group` for the groups of `group` pixels of `xs` in row `j`,
    /// their paths traced sixteen at a time (`matte_lanes/`) and their
    /// connections tested sixteen at a time.
    fn add_groups_in_lanes(
        &mut self,
        lanes: &MatteLanes,
        ((xs, j), samples, group): ((Range<u32>, u32), Range<u32>, u32),
        sums: &mut [PixelSum],
        cancelled: impl Fn() -> bool,
    ) {
        let varies = self.row_varies((xs.clone(), j));
        let per_pixel = samples.len();
        let (x0, s0) = (xs.start, samples.start);
        self.trace_in_lanes(lanes, ((xs, j), samples), true, cancelled);
        // A render given up leaves its last pixels without values: only
        // the groups whose every pixel has them are added.
        let traced = self.lane_shared.len() / per_pixel.max(1);
        let (mut paths, mut values) = (Vec::new(), Vec::new());
        let mut combiner = Combiner::default();
        let group = group as usize;
        for first in (0..sums.len()).step_by(group) {
            let members = first..(first + group).min(sums.len());
            if members.end > traced {
                break;
            }
            for s in 0..per_pixel {
                paths.clear();
                paths.extend(members.clone().map(|p| self.lane_shared[p * per_pixel + s]));
                let stats = &mut self.stats;
                let mut occluded = |connections: &[Connection], blocked: &mut Vec<bool>| {
                    stats.shadow += connections.len() as u64;
                    lanes.occluded(connections, blocked);
                };
                // The lanes' scenes are Lambertian: no vertex is glossy.
                let mut glossy = |_: usize, _: Vec3| None;
                combiner.combine(&paths, &mut occluded, &mut glossy, &mut values);
                for (p, value) in members.clone().zip(&values) {
                    let sample = (x0 + p as u32, j, s0 + s as u32);
                    self.add_value(&mut sums[p], *value, sample, varies[p]);
                }
            }
        }
    }

    /// Samples `samples` of the group of pixels `xs` of row `j`, each
    /// sample's paths traced and shared (`reuse::combine`), each pixel's
    /// values added to its sum of `sums` in the samples' order.
    fn add_group(
        &mut self,
        (xs, j): (Range<u32>, u32),
        samples: Range<u32>,
        sums: &mut [PixelSum],
        cancelled: impl Fn() -> bool,
    ) {
        let scene = self.scene;
        let mut tracer = PathTracer::with_recorder(scene, FirstBounces::default())
            .with_seed(self.seed)
            .with_max_depth(self.max_depth);
        let (mut paths, mut glossy, mut values) = (Vec::new(), Vec::new(), Vec::new());
        let mut combiner = Combiner::default();
        let varies = self.row_varies((xs.clone(), j));
        for s in samples {
            if s % 64 == 63 && cancelled() {
                break;
            }
            paths.clear();
            glossy.clear();
            for i in xs.clone() {
                let mut sampler = PixelSampler::new(i, j, self.seed);
                tracer.rec.clear();
                let value = tracer.sample(&mut sampler, (i, j), s);
                let (path, vertex) = tracer.rec.shared(value);
                paths.push(path);
                glossy.push(vertex);
            }
            let stats = &mut tracer.stats;
            let mut occluded = |connections: &[Connection], blocked: &mut Vec<bool>| {
                stats.shadow += connections.len() as u64;
                let ray = |c: &Connection| Ray::new(c.from, c.dir);
                let hidden = |c: &Connection| scene.occluded(&ray(c), EPSILON, c.reach);
                blocked.extend(connections.iter().map(hidden));
            };
            let mut reflected = |k: usize, to: Vec3| {
                let g: &Glossy = glossy[k].as_ref()?;
                Some(g.reflected(scene.material(g.hit.material), to.normalize()))
            };
            combiner.combine(&paths, &mut occluded, &mut reflected, &mut values);
            for (k, (sum, value)) in sums.iter_mut().zip(&values).enumerate() {
                let pixel = (xs.start + k as u32, j, s);
                self.add_value(sum, *value, pixel, varies[k]);
            }
        }
        self.stats = self.stats + tracer.stats;
    }

    /// `add_samples` for the pixels (i, j) of `xs` in row `j`, each into
    /// its sum of `sums`: the same values added in the same order. In a
    /// small matte scene the row's paths go sixteen at a time, a lane that
    /// ends one path taking up the next, of its pixel or the next one.
    pub fn add_row(
        &mut self,
        (xs, j): (Range<u32>, u32),
        samples: Range<u32>,
        sums: &mut [PixelSum],
        cancelled: impl Fn() -> bool,
    ) {
        debug_assert_eq!(xs.len(), sums.len(), "a sum for each pixel");
        if let Some(group) = self.reuse_group() {
            return self.add_row_reused((xs, j), samples, sums, cancelled, group);
        }
        let paths = xs.len() * samples.len();
        let Some(lanes) = self.lanes().filter(|_| paths >= LANES) else {
            for (i, sum) in xs.zip(sums) {
                self.add_samples(i, j, samples.clone(), sum, &cancelled);
            }
            return;
        };
        // Each pixel's values wait until the pixels traced together are
        // done: a few pixels at a time when they have many samples.
        let together = (LANE_VALUES / samples.len().max(1)).max(1);
        for (xs, sums) in row_chunks(xs.start, sums, together) {
            self.add_pixels_in_lanes(&lanes, (xs, j), samples.clone(), sums, &cancelled);
        }
    }

    /// The samples `samples` of the pixels `xs` of row `j` sixteen paths at
    /// a time, each pixel's values added to its sum of `sums` in the
    /// samples' order.
    fn add_pixels_in_lanes(
        &mut self,
        lanes: &MatteLanes,
        row: (Range<u32>, u32),
        samples: Range<u32>,
        sums: &mut [PixelSum],
        cancelled: impl Fn() -> bool,
    ) {
        let varies = self.row_varies(row.clone());
        let per_pixel = samples.len();
        let ((x0, j), s0) = ((row.0.start, row.1), samples.start);
        self.trace_in_lanes(lanes, (row, samples), false, cancelled);
        let values = std::mem::take(&mut self.lane_values);
        for (p, (pixel_values, sum)) in values.chunks(per_pixel).zip(sums).enumerate() {
            for (s, radiance) in pixel_values.iter().enumerate() {
                let sample = (x0 + p as u32, j, s0 + s as u32);
                self.add_value(sum, *radiance, sample, varies[p]);
            }
        }
        self.lane_values = values;
    }

    /// The values of samples `samples` of the pixels of `row`, traced
    /// sixteen at a time, into `lane_values` pixel by pixel (and what each
    /// path shares into `lane_shared`, if it is to be `shared`).
    fn trace_in_lanes(
        &mut self,
        lanes: &MatteLanes,
        (row, samples): ((Range<u32>, u32), Range<u32>),
        share: bool,
        cancelled: impl Fn() -> bool,
    ) {
        let camera = self.scene.camera();
        let mut setup = matte_lanes::Setup {
            lights: self.scene.path_lights(),
            background: self.scene.trace_settings().background,
            max_depth: self.max_depth,
            stats: &mut self.stats,
            share,
        };
        let ray = |sampler: &mut PixelSampler, pixel| camera.sampled_ray(sampler, pixel);
        let work = (row, samples, self.seed);
        let out = (&mut self.lane_values, &mut self.lane_shared);
        lanes.trace_pixels(&mut setup, work, ray, out, cancelled);
    }

    /// Sample `s` of pixel (i, j): its camera ray and path's radiance, its
    /// numbers from `sampler` (the pixel's).
    #[inline(always)]
    pub fn sample(&mut self, sampler: &mut PixelSampler, (i, j): (u32, u32), s: u32) -> Vec3 {
        sampler.start(s);
        let ray = self.scene.camera().sampled_ray(sampler, (i, j));
        self.radiance(ray, sampler)
    }

    /// The seed of its samples' scramblings.
    pub fn seed(&self) -> u32 {
        self.seed
    }
}

/// Runs `f` with what camera rays see directly (`seen::See`): the light
/// of paths of depth 0, their rays counted into `stats`.
fn seeing<T>(scene: &Scene, stats: &mut RayStats, f: impl FnOnce(seen::See) -> T) -> T {
    let mut tracer = PathTracer::new(scene).with_max_depth(0);
    // A path of depth 0 draws no number.
    let mut unused = PixelSampler::new(0, 0, 0);
    let found = f(&mut |ray| tracer.radiance(ray, &mut unused));
    stats.nearest += tracer.stats.nearest;
    found
}

/// Whether path mode traces `scene` sixteen paths at a time (a small matte
/// scene, `matte_lanes/`): the same values, sooner.
pub fn traces_paths_in_lanes(scene: &Scene) -> bool {
    MatteLanes::of(scene).is_some()
}

/// The sums of a row's pixels from column `x0` on, `size` at a time, each
/// run with its columns.
fn row_chunks(
    x0: u32,
    sums: &mut [PixelSum],
    size: usize,
) -> impl Iterator<Item = (Range<u32>, &mut [PixelSum])> {
    sums.chunks_mut(size).scan(x0, |next, sums| {
        let xs = *next..*next + sums.len() as u32;
        *next = xs.end;
        Some((xs, sums))
    })
}

/// Whether the processor has SIMD registers of 8 or 16 floats (AVX2,
/// AVX-512), where testing sixteen rays against every triangle of a small
/// scene costs less than each ray's walk of the tree; with 4 (SSE2 alone,
/// WebAssembly) it costs more.
fn wide_simd() -> bool {
    #[cfg(target_arch = "x86_64")]
    return std::arch::is_x86_feature_detected!("avx2");
    #[cfg(not(target_arch = "x86_64"))]
    return false;
}

/// A pixel's finite samples so far: their sum, in f64 (finite samples
/// never add up to infinity), and how many.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PixelSum {
    pub sum: DVec3,
    /// The sum of their squares, for the noise (`adaptive.rs`).
    pub squares: DVec3,
    pub kept: u32,
}

impl PixelSum {
    #[inline(always)]
    pub fn add(&mut self, radiance: Vec3) {
        let value = radiance.as_dvec3();
        self.sum += value;
        self.squares += value * value;
        self.kept += 1;
    }

    /// The variance of one sample's value (the mean of the channels'),
    /// unbiased; 0 for fewer than two samples.
    pub fn variance(&self) -> f64 {
        if self.kept < 2 {
            return 0.0;
        }
        let n = f64::from(self.kept);
        let mean = self.sum / n;
        let v = (self.squares / n - mean * mean) * (n / (n - 1.0));
        v.max(DVec3::ZERO).element_sum() / 3.0
    }

    /// The mean of the samples (black for none).
    pub fn mean(&self) -> Vec3 {
        (self.sum / f64::from(self.kept.max(1))).as_vec3()
    }
}
