//! The pixel loop: one ray through each pixel centre, rows in parallel.

use crate::image::LinearImage;
use crate::scene::Scene;
use crate::shade::trace;
use glam::Vec3;
use rayon::prelude::*;

/// The linear colour of pixel (column i, row j).
pub fn render_pixel(scene: &Scene, i: u32, j: u32) -> Vec3 {
    trace(scene, &scene.camera.primary_ray(i, j), 1.0, 0)
}

/// Renders the whole image. Every pixel is computed on its own, so the result
/// does not depend on how rows are spread over threads.
pub fn render(scene: &Scene) -> LinearImage {
    let (width, height) = (scene.camera.width, scene.camera.height);
    let mut image = LinearImage::new(width, height);
    image
        .pixels
        .par_chunks_mut(width as usize)
        .enumerate()
        .for_each(|(j, row)| {
            for (i, pixel) in row.iter_mut().enumerate() {
                *pixel = render_pixel(scene, i as u32, j as u32);
            }
        });
    image
}
