//! The pixel loop: one ray through each pixel centre, bands of rows in
//! parallel on the current rayon pool.

use crate::image::LinearImage;
use crate::scene::Scene;
use crate::shade::{trace_counted, RayStats};
use glam::Vec3;
use rayon::prelude::*;

/// Renders the whole image.
pub fn render(scene: &Scene) -> LinearImage {
    render_with_progress(scene, &|_| {}).0
}

/// Renders the whole image, calling `rows_done(n)` as each band of `n` rows
/// is finished, and counts the rays. Every pixel is computed on its own, so
/// the image does not depend on how bands are spread over threads.
pub fn render_with_progress(
    scene: &Scene,
    rows_done: &(dyn Fn(u32) + Sync),
) -> (LinearImage, RayStats) {
    let (width, height) = (scene.camera.width, scene.camera.height);
    let mut image = LinearImage::new(width, height);
    let stats = image
        .pixels
        .par_chunks_mut((width * BAND_ROWS) as usize)
        .enumerate()
        .map(|(band, pixels)| {
            let stats = render_band(scene, band as u32 * BAND_ROWS, pixels);
            rows_done(pixels.len() as u32 / width);
            stats
        })
        .reduce(RayStats::default, |a, b| a + b);
    (image, stats)
}

/// Rows in one band, the unit of parallel work: small enough that the two
/// halves of the image, cheap sky and costly mesh, spread evenly on threads.
const BAND_ROWS: u32 = 8;

/// Width of the tiles a band is rendered in: neighbouring rays visit the
/// same BVH nodes while they are still in the cache.
const TILE_WIDTH: u32 = 32;

/// Renders the rows from `top` on into `pixels`, tile by tile.
fn render_band(scene: &Scene, top: u32, pixels: &mut [Vec3]) -> RayStats {
    let width = scene.camera.width;
    let rows = pixels.len() as u32 / width;
    let mut stats = RayStats::default();
    for left in (0..width).step_by(TILE_WIDTH as usize) {
        for y in 0..rows {
            for x in left..(left + TILE_WIDTH).min(width) {
                let ray = scene.camera.primary_ray(x, top + y);
                pixels[(y * width + x) as usize] = trace_counted(scene, &ray, 1.0, 0, &mut stats);
            }
        }
    }
    stats
}
