//! What the tests against Mitsuba 3's reference images share: our render of
//! a scene, the reference read back, and their comparison block by block
//! within the noise of both.
// Each test binary that includes this module uses a part of it.
#![allow(dead_code)]

use glam::Vec3;
use rayon::prelude::*;
use std::path::Path;
use tracer_core::integrate::path::{PathTracer, PixelSum};
use tracer_core::{prepare, Scene};

/// Side of the blocks compared.
pub const BLOCK: usize = 16;

/// A linear RGB image, rows from the top.
pub struct Image {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<Vec3>,
}

/// The scene `scenes/NAME`.
pub fn scene(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    let file = scene_format::load_path(&path).unwrap_or_else(|e| panic!("{e}"));
    prepare(&file).expect("prepare")
}

/// The reference `tests/data/NAME`, of `width` x `height` pixels.
pub fn reference(name: &str, width: usize, height: usize) -> Image {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name);
    let image = image::open(&path).expect("the reference EXR").to_rgb32f();
    assert_eq!(image.dimensions(), (width as u32, height as u32));
    Image {
        width,
        height,
        pixels: image.pixels().map(|p| Vec3::from(p.0)).collect(),
    }
}

/// Our image at `samples` paths per pixel, scrambled by `seed`, rendered
/// row by row as renders are (`PathTracer::add_row`), with groups of
/// `reuse` pixels sharing their paths' first bounces and `camera_rays`
/// camera rays per path for what a pixel sees directly.
pub fn render_rows(
    scene: &Scene,
    (width, height): (usize, usize),
    samples: u32,
    seed: u32,
    (reuse, camera_rays): (u32, u32),
) -> Image {
    let pixels = (0..height as u32)
        .into_par_iter()
        .flat_map_iter(|j| {
            let mut tracer = PathTracer::new(scene)
                .with_seed(seed)
                .with_reuse(reuse)
                .with_camera_rays(camera_rays);
            let mut sums = vec![PixelSum::default(); width];
            tracer.add_row((0..width as u32, j), 0..samples, &mut sums, || false);
            sums.into_iter().map(|s| s.mean()).collect::<Vec<_>>()
        })
        .collect();
    Image {
        width,
        height,
        pixels,
    }
}

/// The mean of each 16x16 block, over the three channels, row by row.
pub fn block_means(image: &Image) -> Vec<f64> {
    let columns = image.width / BLOCK;
    let mut sums = vec![0.0f64; columns * (image.height / BLOCK)];
    for (k, c) in image.pixels.iter().enumerate() {
        let (x, y) = (k % image.width / BLOCK, k / image.width / BLOCK);
        sums[y * columns + x] += f64::from(c.element_sum()) / 3.0;
    }
    let n = (BLOCK * BLOCK) as f64;
    sums.into_iter().map(|s| s / n).collect()
}

pub fn rmse(a: &Image, b: &Image) -> f64 {
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(a, b)| f64::from((*a - *b).length_squared()))
        .sum();
    (sum / (3 * a.pixels.len()) as f64).sqrt()
}

/// Asserts that the mean of `seeds` renders of `samples` paths (with groups
/// of `reuse` pixels sharing their paths' first bounces, and `camera_rays`
/// per path) agrees with
/// the reference of `reference_paths` paths a pixel: the image's mean within
/// 1 %, and each block within 4 standard errors. Ours is the spread of the
/// seeds' renders over the root of their count; the reference's is taken
/// from the same spread as if Mitsuba's paths were twice as noisy as ours (on
/// the scenes here they are about as noisy: per path, a pixel's RMSE is 0.56
/// in the materials' reference, 0.60 in ours), and at least `floor`; beside
/// them, the reference's rounding to half floats.
pub fn assert_agrees(
    scene: &Scene,
    reference: &Image,
    (reference_paths, floor): (u32, f64),
    seeds: u32,
    (samples, reuse, camera_rays): (u32, u32, u32),
) {
    let (width, height) = (reference.width, reference.height);
    let renders: Vec<Image> = (0..seeds)
        .map(|seed| render_rows(scene, (width, height), samples, seed, (reuse, camera_rays)))
        .collect();
    assert_renders_agree(&renders, samples, reference, (reference_paths, floor));
}

/// `assert_agrees` for `renders` of `samples` paths a pixel (the mean,
/// where sampling is adaptive), each scrambled by its own seed.
pub fn assert_renders_agree(
    renders: &[Image],
    samples: u32,
    reference: &Image,
    (reference_paths, floor): (u32, f64),
) {
    let width = reference.width;
    let seeds = renders.len() as u32;
    let renders: Vec<Vec<f64>> = renders.iter().map(block_means).collect();
    let n = f64::from(seeds);
    let ours: Vec<f64> = (0..renders[0].len())
        .map(|b| renders.iter().map(|r| r[b]).sum::<f64>() / n)
        .collect();
    let theirs = block_means(reference);
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let (mean, mean_ref) = (mean(&ours), mean(&theirs));
    assert!(
        (mean / mean_ref - 1.0).abs() < 0.01,
        "mean {mean} vs Mitsuba's {mean_ref}"
    );
    let columns = width / BLOCK;
    for (b, (&o, &t)) in ours.iter().zip(&theirs).enumerate() {
        let spread: f64 = renders.iter().map(|r| (r[b] - o).powi(2)).sum::<f64>() / (n - 1.0);
        let reference_variance =
            (2.0 * spread * f64::from(samples) / f64::from(reference_paths)).max(floor * floor);
        let error = (spread / n + reference_variance).sqrt();
        // The reference is stored as half floats: each value rounded to
        // 11 significant bits.
        let rounding = t.abs() * 2f64.powi(-11);
        assert!(
            (o - t).abs() <= 4.0 * error + rounding,
            "block ({}, {}): {o} vs Mitsuba's {t}, standard error {error}",
            b % columns,
            b / columns
        );
    }
}
