//! The one pixel driver: a region of the image, a number of samples per
//! pixel, and what each sample computes (the shaded colour or an AOV).
//! Bands of rows are rendered in parallel on the current rayon pool
//! (`bands.rs`); path mode's colour is a film of one pass (`film.rs`).

use crate::accel::PACKET;
use crate::aov::{Aov, AovContext};
use crate::bands::in_bands;
use crate::film::Film;
use crate::geometry::SurfaceHit;
use crate::image::LinearImage;
use crate::integrate::lanes::LaneScene;
use crate::integrate::whitted::Whitted;
use crate::integrate::RayStats;
use crate::ray::{Ray, NO_RAY};
pub use crate::region::Region;
use crate::sampling::{concentric_disk, Rng, Shuffle, Strata};
use crate::scene::{Integrator, Scene};
use crate::EPSILON;
use glam::{BVec4A, Vec2, Vec3, Vec4};
use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};

/// What each sample of a pixel computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Output {
    /// The shaded colour (the lab's `rayTrace`).
    Shading,
    /// One quantity per pixel instead of the colour.
    Aov(Aov),
    /// The distance from the eye to the nearest hit, in every channel; 0
    /// for no hit (the grey depth AOV's black): the depth AOV's own
    /// numbers, for files that hold floats. Averaged over a pixel's
    /// samples like any output, misses counting 0.
    Distance,
}

/// One render: which pixels, how many samples each, of what.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RenderJob {
    pub region: Region,
    /// Samples per pixel: 1 is one ray through the pixel centre, as the
    /// lab; more are spread over the pixel in strata, jittered
    /// deterministically, and averaged before encoding.
    pub samples: u32,
    pub output: Output,
}

impl RenderJob {
    /// The scene's whole image at the samples per pixel it asks for (the
    /// lab's scenes: one ray per pixel centre).
    pub fn full(scene: &Scene) -> RenderJob {
        let camera = scene.camera();
        RenderJob {
            region: Region::full(camera.width, camera.height),
            samples: scene.samples(),
            output: Output::Shading,
        }
    }

    /// The same job at `samples` per pixel.
    pub fn with_samples(self, samples: u32) -> RenderJob {
        RenderJob { samples, ..self }
    }

    /// The same job computing `output`.
    pub fn with_output(self, output: Output) -> RenderJob {
        RenderJob { output, ..self }
    }
}

/// A rendered region: its linear image (the region's size; pixel (0, 0) is
/// the region's top-left) and the rays traced.
#[derive(Debug, Clone, PartialEq)]
pub struct Rendered {
    pub image: LinearImage,
    pub rays: RayStats,
}

/// Renders `job`, calling `rows_done(n)` as each band of `n` rows is
/// finished. Every pixel is computed on its own, from its own position and
/// samples, so the image depends neither on the threads nor on the region
/// (a region's pixels are those of the whole image). The part of the
/// region outside the camera's image is left out.
pub fn render(scene: &Scene, job: &RenderJob, rows_done: &(dyn Fn(u32) + Sync)) -> Rendered {
    let never = AtomicBool::new(false);
    render_cancellable(scene, job, rows_done, &never).expect("never cancelled")
}

/// `render`, given up (None) soon after `cancel` becomes true: it is read
/// before each row of a tile (of blocks, at one sample a pixel) and each
/// packet of a pixel's samples, so an edit in watch mode stops even a
/// costly render at once.
pub fn render_cancellable(
    scene: &Scene,
    job: &RenderJob,
    rows_done: &(dyn Fn(u32) + Sync),
    cancel: &AtomicBool,
) -> Option<Rendered> {
    // Zeroed pages from the allocator, touched first by the render threads.
    let region = job
        .region
        .within(scene.camera().width, scene.camera().height);
    let mut image = LinearImage::new(region.width(), region.height());
    let rays = render_into(scene, job, rows_done, cancel, &mut image)?;
    Some(Rendered { image, rays })
}

/// `render_cancellable` into `image`, made the region's size in the memory
/// it already has: renders that follow each other (the bench's) need not
/// map and first touch a new image each time, which cost a 1920x1080
/// render a tenth of its time on the bench's machine. Every pixel is
/// written, unless the render is given up (None): then the image holds
/// some pixels of this render and others of what it held.
pub fn render_into(
    scene: &Scene,
    job: &RenderJob,
    rows_done: &(dyn Fn(u32) + Sync),
    cancel: &AtomicBool,
    image: &mut LinearImage,
) -> Option<RayStats> {
    let camera = scene.camera();
    let region = job.region.within(camera.width, camera.height);
    let width = region.width();
    (image.width, image.height) = (width, region.height());
    image
        .pixels
        .resize(width as usize * region.height() as usize, Vec3::ZERO);
    if image.pixels.is_empty() {
        return Some(RayStats::default());
    }
    let pixel = PixelRenderer::new(scene, job, cancel);
    if pixel.traces_paths() {
        // Path mode's one driver: a film of one pass.
        let mut film = Film::new(scene, region);
        let rays = film.add_pass(scene, 0..pixel.samples, rows_done, cancel)?;
        film.mean_into(&mut image.pixels);
        return Some(rays);
    }
    let rays = in_bands(
        &mut image.pixels,
        width,
        BAND_ROWS,
        rows_done,
        |first, pixels| render_band(&pixel, region, region.y0 + first, pixels),
    );
    (!cancel.load(Ordering::Relaxed)).then_some(rays)
}

/// The primary ray of every sample of `job`, pixel by pixel (rows top to
/// bottom, each left to right), a pixel's samples in order: the rays its
/// render traces first, for a peer to trace the same (the bench).
pub fn sample_rays(scene: &Scene, job: &RenderJob, mut f: impl FnMut(&Ray)) {
    let never = AtomicBool::new(false);
    let pixel = PixelRenderer::new(scene, job, &never);
    let camera = scene.camera();
    let region = job.region.within(camera.width, camera.height);
    for j in region.y0..region.y1 {
        for i in region.x0..region.x1 {
            if pixel.samples == 1 {
                f(&pixel.centre_ray(i, j).0);
                continue;
            }
            let order = pixel.lens_order_of(i, j);
            for s in 0..pixel.samples {
                f(&pixel.sample_ray((i, j, order), s).0);
            }
        }
    }
}

/// Sample `s` of pixel (i, j) of a Whitted-mode render at `samples` per
/// pixel, as the render makes it: its image point, its lens point, its
/// primary ray and the random numbers its shading draws (`explain` traces
/// it again, one ray at a time).
pub fn pixel_sample(
    scene: &Scene,
    samples: u32,
    (i, j): (u32, u32),
    s: u32,
) -> (Vec2, Vec2, Ray, Rng) {
    let never = AtomicBool::new(false);
    let job = RenderJob::full(scene).with_samples(samples);
    let pixel = PixelRenderer::new(scene, &job, &never);
    let (at, lens, rng) = if pixel.samples == 1 {
        pixel.centre_point(i, j)
    } else {
        pixel.sample_point((i, j, pixel.lens_order_of(i, j)), s)
    };
    (at, lens, scene.camera().lens_ray(at.x, at.y, lens), rng)
}

/// Rows in one band, the unit of parallel work: small enough that the two
/// halves of the image, cheap sky and costly mesh, spread evenly on threads.
const BAND_ROWS: u32 = 8;

/// Width of the tiles a band is rendered in: neighbouring rays visit the
/// same BVH nodes while they are still in the cache.
const TILE_WIDTH: u32 = 32;

/// Renders the rows from `top` on, of `region`'s columns, into `pixels`,
/// tile by tile, each tile in blocks (`PixelRenderer::block_side`).
fn render_band(pixel: &PixelRenderer, region: Region, top: u32, pixels: &mut [Vec3]) -> RayStats {
    let width = region.width();
    let rows = pixels.len() as u32 / width;
    let mut tracer = Whitted::new(pixel.scene);
    let side = pixel.block_side();
    for left in (0..width).step_by(TILE_WIDTH as usize) {
        let right = (left + TILE_WIDTH).min(width);
        for y in (0..rows).step_by(side as usize) {
            // Per row of blocks of a tile: a costly pixel (thousands of
            // samples) still stops soon.
            if pixel.cancel.load(Ordering::Relaxed) {
                return tracer.stats;
            }
            if side == 1 {
                for x in left..right {
                    let colour = pixel.render(region.x0 + x, top + y, &mut tracer);
                    pixels[(y * width + x) as usize] = colour;
                }
                continue;
            }
            for x in (left..right).step_by(side as usize) {
                let block = Region {
                    x0: x,
                    y0: y,
                    x1: (x + side).min(right),
                    y1: (y + side).min(rows),
                };
                pixel.render_block(block, (region.x0, top), &mut tracer, |x, y, colour| {
                    pixels[(y * width + x) as usize] = colour;
                });
            }
        }
    }
    tracer.stats
}

/// What every pixel of a job shares.
struct PixelRenderer<'a> {
    scene: &'a Scene,
    samples: u32,
    /// Where in the pixel each sample falls.
    strata: Strata,
    /// Which stratum of the lens each sample takes: another order than the
    /// pixel's, drawn afresh for each pixel, so that blur and
    /// anti-aliasing do not move together.
    lens_order: Shuffle,
    /// Whether the camera has a lens: a pinhole ignores the lens point, so
    /// its order and its disk mapping (a sine and cosine) are skipped.
    thin_lens: bool,
    output: Output,
    aov: AovContext,
    /// The scene shaded four rays at a time, if it is one of the simple
    /// scenes that path handles (`integrate::lanes`).
    lanes: Option<LaneScene>,
    /// Read before each packet of a pixel's samples (`PACKET` of them): a
    /// pixel of thousands of samples stops too when the render is given up.
    cancel: &'a AtomicBool,
}

impl<'a> PixelRenderer<'a> {
    fn new(scene: &'a Scene, job: &RenderJob, cancel: &'a AtomicBool) -> Self {
        let samples = job.samples.max(1);
        PixelRenderer {
            scene,
            samples,
            strata: Strata::new(samples),
            lens_order: Shuffle::new(samples),
            // An orthographic camera's rays, as a lens's, each start
            // elsewhere: made one at a time by `lens_ray`.
            thin_lens: !scene.camera().is_pinhole(),
            output: job.output,
            aov: AovContext::new(scene),
            lanes: (job.output == Output::Shading)
                .then(|| LaneScene::of(scene))
                .flatten(),
            cancel,
        }
    }

    /// The side of the square blocks of pixels rendered together: at one
    /// sample a pixel, 4 x 4 neighbours' rays are made four at a time and
    /// searched together (walking the tree once, or, in a small scene
    /// searched flat, one after the other from memory: either costs less
    /// than a pixel's setup alone); at more, each pixel's own samples are
    /// (`render`).
    fn block_side(&self) -> u32 {
        if self.samples == 1 {
            4
        } else {
            1
        }
    }

    /// The pixels of `block` (of a band whose top-left pixel is (x0, y0)
    /// of the whole image), each handed to `put` with its place in the
    /// band.
    #[inline(always)]
    fn render_block(
        &self,
        block: Region,
        (x0, y0): (u32, u32),
        tracer: &mut Whitted,
        mut put: impl FnMut(u32, u32, Vec3),
    ) {
        if let Some(lanes) = self.lanes.as_ref().filter(|_| !self.thin_lens) {
            self.render_block_in_lanes(lanes, block, (x0, y0), &mut tracer.stats, put);
            return;
        }
        let places =
            || (block.y0..block.y1).flat_map(|y| (block.x0..block.x1).map(move |x| (x, y)));
        let mut points = [(Vec2::ZERO, Vec2::ZERO, Rng::new(0)); PACKET];
        let mut n = 0;
        for (x, y) in places() {
            points[n] = self.centre_point(x0 + x, y0 + y);
            n += 1;
        }
        let mut colours = [Vec3::ZERO; PACKET];
        self.trace_points(&points[..n], tracer, &mut colours[..n]);
        for ((x, y), colour) in places().zip(colours) {
            put(x, y, colour);
        }
    }

    /// `render_block` for a scene shaded in lanes through a pinhole: each
    /// row of the block (up to four pixels) is one group of lanes, its
    /// rays made in place (`Camera::pinhole_dirs4`, the rays of
    /// `camera_rays`), without the random numbers nothing there draws.
    #[inline(always)]
    fn render_block_in_lanes(
        &self,
        lanes: &LaneScene,
        block: Region,
        (x0, y0): (u32, u32),
        stats: &mut RayStats,
        mut put: impl FnMut(u32, u32, Vec3),
    ) {
        let (camera, trace) = (self.scene.camera(), self.scene.trace_settings());
        let width = block.width().min(4);
        let active = BVec4A::from_array(std::array::from_fn(|k| (k as u32) < width));
        // A short row repeats its last pixel in the lanes past it.
        let column = |k: u32| (x0 + block.x0 + k.min(width - 1)) as f32 + 0.5;
        let fx = Vec4::from_array(std::array::from_fn(|k| column(k as u32)));
        for y in block.y0..block.y1 {
            let fy = Vec4::splat((y0 + y) as f32 + 0.5);
            let rays = (camera.eye, camera.pinhole_dirs4(fx, fy));
            let colours = lanes.trace_dirs(trace, rays, active, stats);
            for (k, colour) in (0..width).zip(colours) {
                put(block.x0 + k, y, colour);
            }
        }
    }

    /// Pixel (column i, row j) of the whole image, of several samples
    /// (one a pixel is rendered in blocks): the mean of its samples.
    #[inline(always)]
    fn render(&self, i: u32, j: u32, tracer: &mut Whitted) -> Vec3 {
        // One sample is the pixel's centre (`render_block`), not a stratum's.
        debug_assert!(self.samples > 1, "one sample a pixel is rendered in blocks");
        let order = self.lens_order_of(i, j);
        let mut sum = Vec3::ZERO;
        let mut first = 0;
        while first < self.samples && !self.cancel.load(Ordering::Relaxed) {
            let last = (first + PACKET as u32).min(self.samples);
            self.add_samples((i, j, order), first..last, tracer, &mut sum);
            first = last;
        }
        sum / self.samples as f32
    }

    /// The one sample of pixel (i, j) at one sample a pixel: the ray
    /// through its centre (the lab's), and its random numbers.
    #[inline(always)]
    fn centre_ray(&self, i: u32, j: u32) -> (Ray, Rng) {
        let (at, lens, rng) = self.centre_point(i, j);
        (self.scene.camera().lens_ray(at.x, at.y, lens), rng)
    }

    /// `centre_ray`'s image point, lens point and random numbers.
    #[inline(always)]
    fn centre_point(&self, i: u32, j: u32) -> (Vec2, Vec2, Rng) {
        let centre = Vec2::new(i as f32 + 0.5, j as f32 + 0.5);
        let mut rng = Rng::for_sample(i, j, 0);
        let lens = self.lens_point(rng.square(), |p| p);
        (centre, lens, rng)
    }

    /// The rays of samples `points` (image point, lens point, random
    /// numbers) into `rays`, and their random numbers into `rngs`: through
    /// a pinhole four at a time (`Camera::pinhole_rays4`, the same rays as
    /// `lens_ray`).
    #[inline(always)]
    fn camera_rays(&self, points: &[(Vec2, Vec2, Rng)], rays: &mut [Ray], rngs: &mut [Rng]) {
        let camera = self.scene.camera();
        for (rng, point) in rngs.iter_mut().zip(points) {
            *rng = point.2;
        }
        if self.thin_lens {
            for (ray, &(at, lens, _)) in rays.iter_mut().zip(points) {
                *ray = camera.lens_ray(at.x, at.y, lens);
            }
            return;
        }
        for (four, points) in rays.chunks_mut(4).zip(points.chunks(4)) {
            // A short last group repeats its first point.
            let at = |k: usize| points.get(k).unwrap_or(&points[0]).0;
            let fx = Vec4::from_array(std::array::from_fn(|k| at(k).x));
            let fy = Vec4::from_array(std::array::from_fn(|k| at(k).y));
            four.copy_from_slice(&camera.pinhole_rays4(fx, fy)[..four.len()]);
        }
    }

    /// The lens order of pixel (i, j), from a stream none of its samples
    /// uses.
    fn lens_order_of(&self, i: u32, j: u32) -> u32 {
        if self.thin_lens {
            Rng::for_sample(i, j, self.samples).next_u64() as u32
        } else {
            0
        }
    }

    /// Sample `s` of pixel (i, j) whose lens order is `order`, of several a
    /// pixel: its primary ray and its random numbers.
    #[inline(always)]
    fn sample_ray(&self, pixel: (u32, u32, u32), s: u32) -> (Ray, Rng) {
        let (at, lens, rng) = self.sample_point(pixel, s);
        (self.scene.camera().lens_ray(at.x, at.y, lens), rng)
    }

    /// `sample_ray`'s image point, lens point and random numbers.
    #[inline(always)]
    fn sample_point(&self, (i, j, order): (u32, u32, u32), s: u32) -> (Vec2, Vec2, Rng) {
        let mut rng = Rng::for_sample(i, j, s);
        let at = Vec2::new(i as f32, j as f32) + self.strata.point(s, rng.square());
        let lens = self.lens_point(rng.square(), |jitter| {
            self.strata.point(self.lens_order.apply(s, order), jitter)
        });
        (at, lens, rng)
    }

    /// Adds to `sum`, in order, the values of samples `samples` of pixel
    /// (i, j) whose lens order is `order`, traced together.
    #[inline(always)]
    fn add_samples(
        &self,
        (i, j, order): (u32, u32, u32),
        samples: Range<u32>,
        tracer: &mut Whitted,
        sum: &mut Vec3,
    ) {
        let mut points = [(Vec2::ZERO, Vec2::ZERO, Rng::new(0)); PACKET];
        let n = samples.len();
        for (s, point) in samples.zip(&mut points) {
            *point = self.sample_point((i, j, order), s);
        }
        let mut colours = [Vec3::ZERO; PACKET];
        self.trace_points(&points[..n], tracer, &mut colours[..n]);
        for colour in &colours[..n] {
            *sum += *colour;
        }
    }

    /// The values of the samples `points` (image point, lens point, random
    /// numbers), into `colours`: their camera rays traced together.
    #[inline(always)]
    fn trace_points(
        &self,
        points: &[(Vec2, Vec2, Rng)],
        tracer: &mut Whitted,
        colours: &mut [Vec3],
    ) {
        let (mut rays, mut rngs) = ([NO_RAY; PACKET], [Rng::new(0); PACKET]);
        let (rays, rngs) = (&mut rays[..points.len()], &mut rngs[..points.len()]);
        self.camera_rays(points, rays, rngs);
        self.trace_together(rays, rngs, tracer, colours);
    }

    /// The values of the samples whose rays are `rays` and random numbers
    /// `rngs`, into `colours`: the rays' nearest hits searched together
    /// (`Scene::closest_hits`), and for the shaded colour their shadow rays
    /// too (`Whitted::trace_samples`).
    #[inline(always)]
    fn trace_together(
        &self,
        rays: &[Ray],
        rngs: &[Rng],
        tracer: &mut Whitted,
        colours: &mut [Vec3],
    ) {
        if !self.needs_hit() {
            for ((ray, rng), colour) in rays.iter().zip(rngs).zip(colours) {
                *colour = self.aov_of(ray, None, *rng);
            }
            return;
        }
        if let Some(lanes) = &self.lanes {
            lanes.trace(
                self.scene.trace_settings(),
                rays,
                colours,
                &mut tracer.stats,
            );
            return;
        }
        let mut hits = [None; PACKET];
        let hits = &mut hits[..rays.len()];
        self.scene.closest_hits(rays, EPSILON, f32::INFINITY, hits);
        if self.output == Output::Shading {
            tracer.trace_samples(rays, hits, rngs, colours);
            return;
        }
        for (((ray, hit), rng), colour) in rays.iter().zip(hits).zip(rngs).zip(colours) {
            *colour = self.aov_of(ray, hit.as_ref(), *rng);
        }
    }

    /// Whether each pixel's colour is path traced.
    fn traces_paths(&self) -> bool {
        self.output == Output::Shading && self.scene.trace_settings().integrator == Integrator::Path
    }

    /// Whether the output depends on the primary rays' nearest hits.
    fn needs_hit(&self) -> bool {
        match self.output {
            Output::Aov(aov) => aov.needs_hit(),
            Output::Shading | Output::Distance => true,
        }
    }

    /// The AOV or the distance (the outputs other than the shaded
    /// colour) of a primary ray whose nearest hit is `hit` and whose
    /// sample's random numbers are `rng`.
    #[inline(always)]
    fn aov_of(&self, ray: &Ray, hit: Option<&SurfaceHit>, mut rng: Rng) -> Vec3 {
        match self.output {
            Output::Aov(aov) => self.aov.value(self.scene, aov, (ray, hit), &mut rng),
            _ => self.aov.distance(ray, hit),
        }
    }

    /// The lens point of a sample whose lens jitter is `jitter` (drawn
    /// anyway, so that the tracer's random numbers stay the same), placed in
    /// the unit square by `in_square`; the centre for a pinhole.
    #[inline(always)]
    fn lens_point(&self, jitter: Vec2, in_square: impl FnOnce(Vec2) -> Vec2) -> Vec2 {
        if self.thin_lens {
            concentric_disk(in_square(jitter))
        } else {
            Vec2::ZERO
        }
    }
}
