//! The pixel loop: one ray through each pixel centre, rows in parallel on
//! the current rayon pool.

use crate::image::LinearImage;
use crate::scene::Scene;
use crate::shade::{trace, trace_counted, RayStats};
use glam::Vec3;
use rayon::prelude::*;

/// The linear colour of pixel (column i, row j).
pub fn render_pixel(scene: &Scene, i: u32, j: u32) -> Vec3 {
    trace(scene, &scene.camera.primary_ray(i, j), 1.0, 0)
}

/// Renders the whole image.
pub fn render(scene: &Scene) -> LinearImage {
    render_with_progress(scene, &|| {}).0
}

/// Renders the whole image, calling `row_done` after each row, and counts
/// the rays. Every pixel is computed on its own, so the image does not
/// depend on how rows are spread over threads.
pub fn render_with_progress(
    scene: &Scene,
    row_done: &(dyn Fn() + Sync),
) -> (LinearImage, RayStats) {
    let (width, height) = (scene.camera.width, scene.camera.height);
    let mut image = LinearImage::new(width, height);
    let stats = image
        .pixels
        .par_chunks_mut(width as usize)
        .enumerate()
        .map(|(j, row)| {
            let mut stats = RayStats::default();
            for (i, pixel) in row.iter_mut().enumerate() {
                let ray = scene.camera.primary_ray(i as u32, j as u32);
                *pixel = trace_counted(scene, &ray, 1.0, 0, &mut stats);
            }
            row_done();
            stats
        })
        .reduce(RayStats::default, |a, b| a + b);
    (image, stats)
}
