//! Adaptive sampling in path mode (`render.adaptive`): after a pilot of
//! `PILOT` paths in every pixel, the image's other paths go where the
//! noise is. The image is cut into cells of `CELL_W` x `CELL_H` pixels,
//! fixed in the image; past the pilot, a cell takes paths in proportion to
//! sigma / sqrt(cost) of its neighbours' pilot (the standard deviation of
//! one path's value over the rays a path costs: the share that minimises
//! the image's squared error for the time spent), scaled so that the
//! image's mean is the paths per pixel asked for.
//!
//! A cell's share is read off its eight neighbours' pilot, never off its
//! own: its paths are then independent of how many it gets, and each pixel
//! stays an unbiased estimate. (Read off its own, a cell whose pilot drew a
//! firefly would get more paths to water it down: a bias toward dark.)

use crate::integrate::path::PixelSum;
use std::ops::Range;

/// The paths every pixel takes before any are shared out by noise.
pub const PILOT: u32 = 8;
/// A cell's width and height in pixels: its width a multiple of the
/// groups of `path_reuse` that divide 8, so that such a group never
/// straddles two cells.
pub const CELL_W: u32 = 8;
pub const CELL_H: u32 = 4;
/// The least and the most of the mean share a cell takes: a cell whose
/// neighbours look noiseless still converges, and no cell takes all.
const FLOOR: f64 = 0.125;
const CAP: f64 = 16.0;

/// Each cell's share of the paths past the pilot (1 is the image's mean).
#[derive(Debug, Clone, PartialEq)]
pub struct Allocation {
    /// Cells per row of cells, and rows of cells.
    columns: u32,
    rows: u32,
    share: Vec<f64>,
}

impl Allocation {
    /// The allocation of an image of `width` x `height` pixels from its
    /// pilot: each pixel's sums (`sums`, row by row) and the rays of its
    /// row of its cell (`rays`).
    pub fn from_pilot(width: u32, height: u32, sums: &[PixelSum], rays: &[u64]) -> Allocation {
        let (columns, rows) = (width.div_ceil(CELL_W), height.div_ceil(CELL_H));
        let noise = cell_noise((width, columns, rows), sums, rays);
        let mut share = Vec::with_capacity(noise.len());
        for r in 0..rows as i64 {
            for c in 0..columns as i64 {
                let around: Vec<f64> = NEIGHBOURS
                    .iter()
                    .map(|(dc, dr)| (c + dc, r + dr))
                    .filter(|&(c, r)| {
                        (0..columns as i64).contains(&c) && (0..rows as i64).contains(&r)
                    })
                    .map(|(c, r)| noise[(r * columns as i64 + c) as usize])
                    .collect();
                let mean = around.iter().sum::<f64>() / around.len().max(1) as f64;
                share.push(mean.sqrt());
            }
        }
        Allocation {
            columns,
            rows,
            share: normalised(share),
        }
    }

    /// The paths per pixel of the cell of pixel (x, y) when the image's
    /// mean is `mean`: the pilot's, then the cell's share of the rest.
    pub fn paths(&self, (x, y): (u32, u32), mean: u32) -> u32 {
        if mean <= PILOT {
            return mean;
        }
        let (c, r) = (
            (x / CELL_W).min(self.columns - 1),
            (y / CELL_H).min(self.rows - 1),
        );
        let share = self.share[(r * self.columns + c) as usize];
        PILOT + (f64::from(mean - PILOT) * share).round() as u32
    }
}

/// The columns `xs` of a row cut where cells meet.
pub fn cells(xs: Range<u32>) -> impl Iterator<Item = Range<u32>> {
    let mut next = xs.start;
    std::iter::from_fn(move || {
        (next < xs.end).then(|| {
            let end = ((next / CELL_W + 1) * CELL_W).min(xs.end);
            let run = next..end;
            next = end;
            run
        })
    })
}

/// The eight cells around a cell.
const NEIGHBOURS: [(i64, i64); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// Each cell's variance of one path's value (its pixels' mean) over the
/// rays a path costs there (at least 1).
fn cell_noise(
    (width, columns, rows): (u32, u32, u32),
    sums: &[PixelSum],
    rays: &[u64],
) -> Vec<f64> {
    // Per cell: summed variance, summed rays per path, pixels.
    let mut cells = vec![(0.0f64, 0.0f64, 0u32); (columns * rows) as usize];
    for (k, (sum, &rays)) in sums.iter().zip(rays).enumerate() {
        let (x, y) = (k as u32 % width, k as u32 / width);
        let cell = &mut cells[((y / CELL_H) * columns + x / CELL_W) as usize];
        cell.0 += settled(sum);
        // The rays of the pixel's row of its cell, over its pixels.
        let run = (width - x / CELL_W * CELL_W).min(CELL_W);
        cell.1 += rays as f64 / f64::from(run) / f64::from(sum.kept.max(1));
        cell.2 += 1;
    }
    cells
        .iter()
        .map(|&(variance, cost, n)| {
            let n = f64::from(n.max(1));
            coarse(variance / n / (cost / n).max(1.0))
        })
        .collect()
}

/// `x` (at least 0) with its mantissa cut to its first two bits, by exact
/// operations on its bits: the allocation must not follow the last bits
/// in which one platform's maths library rounds a path's value otherwise
/// than another's (the playground's WebAssembly renders the image that
/// `tracer render` does), and the shares lose nothing that counts by it.
fn coarse(x: f64) -> f64 {
    const KEPT: u64 = !((1u64 << 50) - 1);
    f64::from_bits(x.to_bits() & KEPT)
}

/// A pixel's variance, 0 where it is below what rounding makes of a
/// constant value (a clear sky seen directly): there it is the last bits
/// of the values, which platforms round each their own way.
fn settled(sum: &PixelSum) -> f64 {
    let variance = sum.variance();
    let scale = (sum.sum / f64::from(sum.kept.max(1))).length_squared();
    if variance <= 1e-9 * scale {
        0.0
    } else {
        variance
    }
}

/// `share` scaled to a mean of 1, each within `FLOOR` and `CAP` (a few
/// rounds of clamping and scaling again); all zero, or not finite, gives
/// all 1.
fn normalised(mut share: Vec<f64>) -> Vec<f64> {
    for _ in 0..4 {
        let mean = share.iter().sum::<f64>() / share.len().max(1) as f64;
        if !(mean > 0.0 && mean.is_finite()) {
            return vec![1.0; share.len()];
        }
        for s in &mut share {
            *s = (*s / mean).clamp(FLOOR, CAP);
        }
    }
    share
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A pilot of `PILOT` samples a pixel whose values alternate by
    /// `spread(x, y)` around 1, and one ray a path (widths of whole cells).
    fn pilot(
        width: u32,
        height: u32,
        spread: impl Fn(u32, u32) -> f32,
    ) -> (Vec<PixelSum>, Vec<u64>) {
        let sums = (0..width * height)
            .map(|k| {
                let d = spread(k % width, k / width);
                let mut sum = PixelSum::default();
                for s in 0..PILOT {
                    sum.add(Vec3::splat(if s % 2 == 0 { 1.0 + d } else { 1.0 - d }));
                }
                sum
            })
            .collect();
        (
            sums,
            vec![u64::from(PILOT * CELL_W); (width * height) as usize],
        )
    }

    fn mean_paths(a: &Allocation, (width, height): (u32, u32), mean: u32) -> f64 {
        let all: u64 = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|p| u64::from(a.paths(p, mean)))
            .sum();
        all as f64 / f64::from(width * height)
    }

    #[test]
    fn the_image_takes_the_mean_asked_and_the_noise_takes_more() {
        // The right half noisy, the left flat.
        let (w, h) = (64, 32);
        let (sums, rays) = pilot(w, h, |x, _| if x >= 32 { 0.5 } else { 0.0 });
        let a = Allocation::from_pilot(w, h, &sums, &rays);
        let mean = mean_paths(&a, (w, h), 128);
        assert!((mean - 128.0).abs() < 2.0, "{mean}");
        assert!(a.paths((60, 10), 128) > 4 * a.paths((2, 10), 128));
        // A flat cell still converges: at least the floor's share.
        assert!(a.paths((2, 10), 128) >= PILOT + ((128 - PILOT) as f64 * FLOOR) as u32);
        assert_eq!(
            a.paths((2, 10), PILOT),
            PILOT,
            "the pilot is the same everywhere"
        );
    }

    #[test]
    fn a_cell_s_paths_do_not_read_its_own_pilot() {
        let (w, h) = (48, 24);
        let (sums, rays) = pilot(w, h, |x, y| ((x * 7 + y * 3) % 5) as f32 * 0.1);
        let before = Allocation::from_pilot(w, h, &sums, &rays);
        // A firefly in cell (2, 2)'s pixel (17, 9): its own share stays.
        let mut edited = sums.clone();
        edited[(9 * w + 17) as usize].add(Vec3::splat(30.0));
        let after = Allocation::from_pilot(w, h, &edited, &rays);
        let cell = |a: &Allocation, c: u32, r: u32| a.share[(r * a.columns + c) as usize];
        let own = (cell(&before, 2, 2), cell(&after, 2, 2));
        let neighbour = (cell(&before, 3, 2), cell(&after, 3, 2));
        assert!(neighbour.1 > 1.5 * neighbour.0, "{neighbour:?}");
        // Its share moves only by the image's scaling, as every far cell's.
        let far = cell(&after, 5, 5) / cell(&before, 5, 5);
        assert!((own.1 / own.0 - far).abs() < 1e-9, "{own:?} {far}");
    }

    #[test]
    fn a_noiseless_image_is_sampled_evenly() {
        let (sums, rays) = pilot(40, 20, |_, _| 0.0);
        let a = Allocation::from_pilot(40, 20, &sums, &rays);
        assert!(a.share.iter().all(|&s| s == 1.0));
        assert_eq!(a.paths((39, 19), 100), 100);
    }

    #[test]
    fn rows_are_cut_where_cells_meet() {
        let runs: Vec<Range<u32>> = cells(3..21).collect();
        assert_eq!(runs, [3..8, 8..16, 16..21]);
        assert_eq!(cells(5..5).count(), 0);
    }
}
