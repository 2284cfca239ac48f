//! Progressive rendering in path mode: a film keeps, for each pixel of a
//! region, the sum and count of its samples so far, and passes add more
//! (samples 0..1, then 1..2, 2..4, 4..8, ...). Its memory does not grow with
//! the samples; each pixel's sums are the same additions, in the same order,
//! as one render of all the samples, so the last pass's image is that
//! render's, bit for bit.

use crate::adaptive::{self, Allocation, PILOT};
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
    /// Samples per pixel added so far (the image's mean, where adaptive).
    samples: u32,
    /// Where adaptive sampling sends the paths past the pilot, once known.
    allocation: Option<Allocation>,
    /// Each pixel's rays in the passes before there was an allocation:
    /// those of its row of its cell (`adaptive::cells`), what a path costs
    /// there.
    pilot_rays: Vec<u64>,
    /// Which set of scramblings the samples use (0 for renders).
    seed: u32,
}

/// Rows in one band of a pass, the unit of parallel work.
const BAND_ROWS: u32 = 4;

impl Film {
    /// An empty film of `region` of `scene`'s image (clipped to it).
    pub fn new(scene: &Scene, region: Region) -> Film {
        let camera = scene.camera();
        let region = region.within(camera.width, camera.height);
        let pixels = region.width() as usize * region.height() as usize;
        Film {
            region,
            sums: vec![PixelSum::default(); pixels],
            samples: 0,
            allocation: None,
            pilot_rays: vec![0; pixels],
            seed: 0,
        }
    }

    /// The same empty film taking its samples from another set of
    /// scramblings: independent renders of the same scene (tests).
    pub fn with_seed(self, seed: u32) -> Film {
        Film { seed, ..self }
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
    /// and the film no longer whole, when `cancel` became true. Where the
    /// scene samples adaptively (`adaptive.rs`), `samples` are the image's
    /// mean paths per pixel, past the pilot shared out by noise.
    pub fn add_pass(
        &mut self,
        scene: &Scene,
        samples: Range<u32>,
        rows_done: &(dyn Fn(u32) + Sync),
        cancel: &AtomicBool,
    ) -> Option<RayStats> {
        assert_eq!(samples.start, self.samples, "passes follow each other");
        let adaptive = scene.trace_settings().adaptive;
        if !adaptive {
            return self.add_cells(scene, samples, Cells::Rows, rows_done, cancel);
        }
        if samples.end <= PILOT {
            return self.add_cells(scene, samples, Cells::Pilot, rows_done, cancel);
        }
        let mut stats = RayStats::default();
        if samples.start < PILOT {
            stats = self.add_cells(scene, samples.start..PILOT, Cells::Pilot, &|_| {}, cancel)?;
        }
        let allocation = match self.allocation.take() {
            Some(allocation) => allocation,
            None => {
                let (allocation, pilot) = self.allocation(scene, cancel)?;
                stats = stats + pilot;
                allocation
            }
        };
        let means = PILOT.max(samples.start)..samples.end;
        let more = self.add_cells(scene, means, Cells::Shared(&allocation), rows_done, cancel);
        self.allocation = Some(allocation);
        Some(stats + more?)
    }

    /// The allocation of the whole image's pilot: this film's own when it
    /// is the whole image, else one rendered for it (the same values: a
    /// region's pixels are then the whole render's, at the cost of the
    /// image's pilot).
    fn allocation(&self, scene: &Scene, cancel: &AtomicBool) -> Option<(Allocation, RayStats)> {
        let camera = scene.camera();
        let (width, height) = (camera.width, camera.height);
        if self.region == Region::full(width, height) {
            let own = Allocation::from_pilot(width, height, &self.sums, &self.pilot_rays);
            return Some((own, RayStats::default()));
        }
        let mut whole = Film::new(scene, Region::full(width, height)).with_seed(self.seed);
        let stats = whole.add_cells(scene, 0..PILOT, Cells::Pilot, &|_| {}, cancel)?;
        let allocation = Allocation::from_pilot(width, height, &whole.sums, &whole.pilot_rays);
        Some((allocation, stats))
    }

    /// Adds to every pixel samples `means` (the image's mean paths per
    /// pixel), as `cells` says: whole rows at a time, or cell by cell
    /// (`adaptive::cells`), in the pilot counting each cell's rays to its
    /// pixels, past it each cell taking its share.
    fn add_cells(
        &mut self,
        scene: &Scene,
        means: Range<u32>,
        cells: Cells,
        rows_done: &(dyn Fn(u32) + Sync),
        cancel: &AtomicBool,
    ) -> Option<RayStats> {
        let region = self.region;
        let width = region.width() as usize;
        self.samples = means.end;
        if width == 0 {
            return Some(RayStats::default());
        }
        let cancelled = || cancel.load(Ordering::Relaxed);
        let seed = self.seed;
        let mut pixels: Vec<(&mut PixelSum, &mut u64)> = self
            .sums
            .iter_mut()
            .zip(self.pilot_rays.iter_mut())
            .collect();
        let stats = in_bands(
            &mut pixels,
            region.width(),
            BAND_ROWS,
            rows_done,
            |first, pixels| {
                let mut tracer = PathTracer::new(scene).with_seed(seed);
                let mut sums = Vec::with_capacity(width);
                for (y, row) in pixels.chunks_mut(width).enumerate() {
                    if cancelled() {
                        break;
                    }
                    let j = region.y0 + first + y as u32;
                    let runs: Box<dyn Iterator<Item = Range<u32>>> = match cells {
                        Cells::Rows => Box::new(std::iter::once(region.x0..region.x1)),
                        _ => Box::new(adaptive::cells(region.x0..region.x1)),
                    };
                    for xs in runs {
                        let cell = (xs.start - region.x0) as usize..(xs.end - region.x0) as usize;
                        let samples = match cells {
                            Cells::Shared(a) => {
                                a.paths((xs.start, j), means.start)
                                    ..a.paths((xs.start, j), means.end)
                            }
                            _ => means.clone(),
                        };
                        let cell = &mut row[cell];
                        sums.clear();
                        sums.extend(cell.iter().map(|(sum, _)| **sum));
                        let before = tracer.stats.nearest + tracer.stats.shadow;
                        tracer.add_row((xs, j), samples, &mut sums, cancelled);
                        // The run's rays, whole: kept in integers, the same
                        // whatever passes the pilot was rendered in.
                        let rays = tracer.stats.nearest + tracer.stats.shadow - before;
                        for ((sum, pilot_rays), new) in cell.iter_mut().zip(&sums) {
                            **sum = *new;
                            if matches!(cells, Cells::Pilot) {
                                **pilot_rays += rays;
                            }
                        }
                    }
                }
                tracer.stats
            },
        );
        (!cancelled()).then_some(stats)
    }

    /// Each pixel's paths so far (those whose value was finite): under
    /// adaptive sampling, where the paths went.
    pub fn paths(&self) -> Vec<u32> {
        self.sums.iter().map(|s| s.kept).collect()
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

/// How a pass goes over a row.
#[derive(Clone, Copy)]
enum Cells<'a> {
    /// The whole row at once, every pixel taking the same samples.
    Rows,
    /// Cell by cell, every pixel taking the same samples, each cell's rays
    /// counted (adaptive sampling's pilot).
    Pilot,
    /// Cell by cell, each cell taking its share.
    Shared(&'a Allocation),
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
