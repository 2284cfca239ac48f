//! The one pixel driver: a region of the image, a number of samples per
//! pixel, and what each sample computes (the shaded colour or an AOV).
//! Bands of rows are rendered in parallel on the current rayon pool.

use crate::aov::{Aov, AovContext};
use crate::image::LinearImage;
use crate::integrate::whitted::trace_counted;
use crate::integrate::RayStats;
use crate::scene::Scene;
use glam::{Vec2, Vec3};
use rayon::prelude::*;

/// A rectangle of pixels: columns `x0..x1`, rows `y0..y1` (ends exclusive).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Region {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

impl Region {
    /// The whole image of `width` x `height` pixels.
    pub fn full(width: u32, height: u32) -> Region {
        Region {
            x0: 0,
            y0: 0,
            x1: width,
            y1: height,
        }
    }

    pub fn width(&self) -> u32 {
        self.x1.saturating_sub(self.x0)
    }

    pub fn height(&self) -> u32 {
        self.y1.saturating_sub(self.y0)
    }

    /// The part of the region inside an image of `width` x `height`.
    pub fn within(self, width: u32, height: u32) -> Region {
        Region {
            x0: self.x0.min(width),
            y0: self.y0.min(height),
            x1: self.x1.min(width),
            y1: self.y1.min(height),
        }
    }
}

/// What each sample of a pixel computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Output {
    /// The shaded colour (the lab's `rayTrace`).
    Shading,
    /// One quantity per pixel instead of the colour.
    Aov(Aov),
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
    /// The lab's render of the scene's whole image: one ray per pixel centre.
    pub fn full(scene: &Scene) -> RenderJob {
        let camera = scene.camera();
        RenderJob {
            region: Region::full(camera.width, camera.height),
            samples: 1,
            output: Output::Shading,
        }
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
    let camera = scene.camera();
    let region = job.region.within(camera.width, camera.height);
    let width = region.width();
    let mut image = LinearImage::new(width, region.height());
    if image.pixels.is_empty() {
        return Rendered {
            image,
            rays: RayStats::default(),
        };
    }
    let pixel = PixelRenderer::new(scene, job);
    let rays = image
        .pixels
        .par_chunks_mut((width * BAND_ROWS) as usize)
        .enumerate()
        .map(|(band, pixels)| {
            let top = region.y0 + band as u32 * BAND_ROWS;
            let stats = render_band(&pixel, region, top, pixels);
            rows_done(pixels.len() as u32 / width);
            stats
        })
        .reduce(RayStats::default, |a, b| a + b);
    Rendered { image, rays }
}

/// Rows in one band, the unit of parallel work: small enough that the two
/// halves of the image, cheap sky and costly mesh, spread evenly on threads.
const BAND_ROWS: u32 = 8;

/// Width of the tiles a band is rendered in: neighbouring rays visit the
/// same BVH nodes while they are still in the cache.
const TILE_WIDTH: u32 = 32;

/// Renders the rows from `top` on, of `region`'s columns, into `pixels`,
/// tile by tile.
fn render_band(pixel: &PixelRenderer, region: Region, top: u32, pixels: &mut [Vec3]) -> RayStats {
    let width = region.width();
    let rows = pixels.len() as u32 / width;
    let mut stats = RayStats::default();
    for left in (0..width).step_by(TILE_WIDTH as usize) {
        for y in 0..rows {
            for x in left..(left + TILE_WIDTH).min(width) {
                let colour = pixel.render(region.x0 + x, top + y, &mut stats);
                pixels[(y * width + x) as usize] = colour;
            }
        }
    }
    stats
}

/// What every pixel of a job shares.
struct PixelRenderer<'a> {
    scene: &'a Scene,
    samples: u32,
    output: Output,
    aov: AovContext,
}

impl<'a> PixelRenderer<'a> {
    fn new(scene: &'a Scene, job: &RenderJob) -> Self {
        PixelRenderer {
            scene,
            samples: job.samples.max(1),
            output: job.output,
            aov: AovContext::new(scene),
        }
    }

    /// Pixel (column i, row j) of the whole image: the mean of its samples.
    #[inline(always)]
    fn render(&self, i: u32, j: u32, stats: &mut RayStats) -> Vec3 {
        if self.samples == 1 {
            return self.sample(Vec2::new(i as f32 + 0.5, j as f32 + 0.5), stats);
        }
        let sum: Vec3 = (0..self.samples)
            .map(|s| self.sample(sample_position(i, j, s, self.samples), stats))
            .sum();
        sum / self.samples as f32
    }

    /// The value of one sample at image point `at`.
    #[inline(always)]
    fn sample(&self, at: Vec2, stats: &mut RayStats) -> Vec3 {
        let ray = self.scene.camera().ray(at.x, at.y);
        match self.output {
            Output::Shading => trace_counted(self.scene, &ray, 1.0, 0, stats),
            Output::Aov(aov) => self.aov.value(self.scene, aov, &ray),
        }
    }
}

/// Where sample `s` of `n` of pixel (i, j) falls: the pixel is cut into `n`
/// strata (a grid as square as `n` allows) and each stratum gets one point,
/// jittered by a hash of the pixel and the sample, so every run and every
/// thread count gives the same image.
fn sample_position(i: u32, j: u32, s: u32, n: u32) -> Vec2 {
    let columns = grid_columns(n);
    let rows = n / columns;
    let (cx, cy) = (s % columns, s / columns);
    let h = hash(i, j, s);
    let jitter = Vec2::new(unit_float(h), unit_float(h >> 32));
    let offset =
        (Vec2::new(cx as f32, cy as f32) + jitter) / Vec2::new(columns as f32, rows as f32);
    Vec2::new(i as f32, j as f32) + offset
}

/// The largest divisor of `n` not above its square root: the columns of a
/// grid of exactly `n` strata.
fn grid_columns(n: u32) -> u32 {
    (1..=n.isqrt())
        .rev()
        .find(|c| n.is_multiple_of(*c))
        .unwrap_or(1)
}

/// A 64-bit mix of a pixel and a sample index (SplitMix64's finaliser).
fn hash(i: u32, j: u32, s: u32) -> u64 {
    let mut z = (u64::from(i) << 40) ^ (u64::from(j) << 20) ^ u64::from(s);
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A float in [0, 1) from the low 24 bits.
fn unit_float(bits: u64) -> f32 {
    (bits & 0xFF_FFFF) as f32 / (1u32 << 24) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strata_tile_the_pixel_once_each() {
        for n in [2, 3, 4, 6, 9, 16, 7] {
            let columns = grid_columns(n);
            assert_eq!(n % columns, 0);
            let rows = n / columns;
            let mut seen = vec![false; n as usize];
            for s in 0..n {
                let p = sample_position(3, 5, s, n) - Vec2::new(3.0, 5.0);
                assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
                let cell = (p.y * rows as f32) as u32 * columns + (p.x * columns as f32) as u32;
                assert!(!seen[cell as usize], "n {n}: stratum {cell} twice");
                seen[cell as usize] = true;
            }
        }
        assert_eq!(grid_columns(16), 4);
        assert_eq!(grid_columns(6), 2);
        assert_eq!(grid_columns(7), 1);
    }

    #[test]
    fn jitter_differs_between_pixels_and_samples() {
        let a = sample_position(0, 0, 0, 4);
        assert_ne!(a, sample_position(1, 0, 0, 4) - Vec2::X);
        assert_ne!(a - sample_position(0, 1, 0, 4), -Vec2::Y);
        assert_eq!(a, sample_position(0, 0, 0, 4), "deterministic");
    }
}
