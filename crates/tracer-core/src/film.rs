//! Progressive rendering in path mode: a film keeps, for each pixel of a
//! region, the sum and count of its samples so far, and passes add more
//! (samples 0..1, then 1..2, 2..4, 4..8, ...). Its memory does not grow with
//! the samples; each pixel's sums are the same additions, in the same order,
//! as one render of all the samples, so the last pass's image is that
//! render's, bit for bit.

use crate::bands::in_bands;
use crate::image::LinearImage;
use crate::integrate::path::{PathTracer, PixelSum};
use crate::integrate::RayStats;
use crate::region::Region;
use crate::scene::Scene;
use glam::Vec3;
use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};

/// The samples so far of every pixel of a region.
#[derive(Debug, Clone, PartialEq)]
pub struct Film {
    region: Region,
    sums: Vec<PixelSum>,
    /// Samples per pixel added so far.
    samples: u32,
}

/// Rows in one band of a pass, the unit of parallel work.
const BAND_ROWS: u32 = 4;

impl Film {
    /// An empty film of `region` of `scene`'s image (clipped to it).
    pub fn new(scene: &Scene, region: Region) -> Film {
        let camera = scene.camera();
        let region = region.within(camera.width, camera.height);
        Film {
            region,
            sums: vec![PixelSum::default(); region.width() as usize * region.height() as usize],
            samples: 0,
        }
    }

    /// Samples per pixel added so far.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    pub fn region(&self) -> Region {
        self.region
    }

    /// Adds samples `samples.start..samples.end` (the next ones: `start` is
    /// `self.samples()`) to every pixel, in bands of rows in parallel on the
    /// current rayon pool, calling `rows_done(n)` as bands finish. None,
    /// and the film no longer whole, when `cancel` became true.
    pub fn add_pass(
        &mut self,
        scene: &Scene,
        samples: Range<u32>,
        rows_done: &(dyn Fn(u32) + Sync),
        cancel: &AtomicBool,
    ) -> Option<RayStats> {
        assert_eq!(samples.start, self.samples, "passes follow each other");
        let region = self.region;
        let width = region.width() as usize;
        if width == 0 {
            self.samples = samples.end;
            return Some(RayStats::default());
        }
        let cancelled = || cancel.load(Ordering::Relaxed);
        let stats = in_bands(
            &mut self.sums,
            region.width(),
            BAND_ROWS,
            rows_done,
            |first, sums| {
                let mut tracer = PathTracer::new(scene);
                for (y, row) in sums.chunks_mut(width).enumerate() {
                    if cancelled() {
                        break;
                    }
                    let pixels = (region.x0..region.x1, region.y0 + first + y as u32);
                    tracer.add_row(pixels, samples.clone(), row, cancelled);
                }
                tracer.stats
            },
        );
        self.samples = samples.end;
        (!cancelled()).then_some(stats)
    }

    /// The image so far: each pixel the mean of its samples.
    pub fn image(&self) -> LinearImage {
        let mut image = LinearImage::new(self.region.width(), self.region.height());
        self.mean_into(&mut image.pixels);
        image
    }

    /// Each pixel's mean so far into `pixels`, the region's row by row.
    pub fn mean_into(&self, pixels: &mut [Vec3]) {
        for (pixel, sum) in pixels.iter_mut().zip(&self.sums) {
            *pixel = sum.mean();
        }
    }
}

/// The passes of a progressive render of `samples` per pixel: 0..1, 1..2,
/// 2..4, 4..8, ..., the last one ending at `samples`.
pub fn passes(samples: u32) -> impl Iterator<Item = Range<u32>> {
    let samples = samples.max(1);
    std::iter::successors(Some(0..1), move |last: &Range<u32>| {
        (last.end < samples).then(|| last.end..(last.end * 2).min(samples))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_double_the_samples_up_to_the_last() {
        let all: Vec<Range<u32>> = passes(20).collect();
        assert_eq!(all, [0..1, 1..2, 2..4, 4..8, 8..16, 16..20]);
        assert_eq!(passes(1).collect::<Vec<_>>(), vec![0..1]);
        assert_eq!(passes(64).last(), Some(32..64));
    }
}
