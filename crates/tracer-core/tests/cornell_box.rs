//! The Cornell box against Mitsuba 3: `scenes/cornell-box.toml` is
//! `mitsuba.cornell_box()` (made by `xtask/peers/cornell_box.py`), and
//! `tests/data/cornell-box-mitsuba.exr` Mitsuba's render of it at 32768
//! paths per pixel (`xtask/peers/cornell.py reference`; see
//! `tests/data/README.md`). Our render agrees with it within its noise,
//! which falls as N^-1/2 or faster.

use glam::Vec3;
use rayon::prelude::*;
use std::path::Path;
use tracer_core::integrate::path::PathTracer;
use tracer_core::{prepare, Scene};

const SIZE: usize = 256;
/// Side of the blocks compared.
const BLOCK: usize = 16;

fn cornell_box() -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml");
    let file = scene_format::load_path(&path).unwrap_or_else(|e| panic!("{e}"));
    prepare(&file).expect("prepare")
}

/// Mitsuba's image, linear RGB, rows from the top.
fn reference() -> Vec<Vec3> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/cornell-box-mitsuba.exr");
    let image = image::open(&path).expect("the reference EXR").to_rgb32f();
    assert_eq!(image.dimensions(), (SIZE as u32, SIZE as u32));
    image.pixels().map(|p| Vec3::from(p.0)).collect()
}

/// Our image at `samples` paths per pixel, scrambled by `seed`.
fn render(scene: &Scene, samples: u32, seed: u32) -> Vec<Vec3> {
    (0..SIZE as u32)
        .into_par_iter()
        .flat_map_iter(|j| {
            let mut tracer = PathTracer::new(scene).with_seed(seed);
            (0..SIZE as u32)
                .map(|i| tracer.pixel(i, j, samples, || false))
                .collect::<Vec<_>>()
        })
        .collect()
}

/// The mean of each 16x16 block, over the three channels.
fn block_means(image: &[Vec3]) -> Vec<f64> {
    let blocks = SIZE / BLOCK;
    let mut sums = vec![0.0f64; blocks * blocks];
    for (k, c) in image.iter().enumerate() {
        let (x, y) = (k % SIZE / BLOCK, k / SIZE / BLOCK);
        sums[y * blocks + x] += f64::from(c.element_sum()) / 3.0;
    }
    let n = (BLOCK * BLOCK) as f64;
    sums.into_iter().map(|s| s / n).collect()
}

fn rmse(a: &[Vec3], b: &[Vec3]) -> f64 {
    let sum: f64 = a
        .iter()
        .zip(b)
        .map(|(a, b)| f64::from((*a - *b).length_squared()))
        .sum();
    (sum / (3 * a.len()) as f64).sqrt()
}

#[test]
fn the_cornell_box_agrees_with_mitsuba_3() {
    let (scene, reference) = (cornell_box(), reference());
    let seeds = 8;
    let renders: Vec<Vec<f64>> = (0..seeds)
        .map(|seed| block_means(&render(&scene, 16, seed)))
        .collect();
    let ours: Vec<f64> = (0..renders[0].len())
        .map(|b| renders.iter().map(|r| r[b]).sum::<f64>() / seeds as f64)
        .collect();
    let theirs = block_means(&reference);
    // The image's mean within 1 %.
    let (mean, mean_ref) = (
        ours.iter().sum::<f64>() / ours.len() as f64,
        theirs.iter().sum::<f64>() / theirs.len() as f64,
    );
    assert!(
        (mean / mean_ref - 1.0).abs() < 0.01,
        "mean {mean} vs Mitsuba's {mean_ref}"
    );
    // Each block within 4 standard errors: ours from the spread of the
    // seeds' renders, Mitsuba's from its README (0.00034 a pixel, over a
    // block's 256 pixels, as an upper bound: its noise is not independent
    // between neighbours).
    let reference_error = 0.00034;
    for (b, (&o, &t)) in ours.iter().zip(&theirs).enumerate() {
        let spread: f64 =
            renders.iter().map(|r| (r[b] - o).powi(2)).sum::<f64>() / (seeds - 1) as f64;
        let error = (spread / seeds as f64 + reference_error * reference_error).sqrt();
        assert!(
            (o - t).abs() <= 4.0 * error,
            "block ({}, {}): {o} vs Mitsuba's {t}, standard error {error}",
            b % (SIZE / BLOCK),
            b / (SIZE / BLOCK)
        );
    }
}

#[test]
fn the_error_against_mitsuba_falls_at_least_as_one_over_the_root_of_the_samples() {
    // Four times the paths, at most half the error (Mitsuba's own noise,
    // 0.0004 with its half floats, is far below both).
    let (scene, reference) = (cornell_box(), reference());
    let errors: Vec<f64> = [8, 32, 128]
        .iter()
        .map(|&n| rmse(&render(&scene, n, 0), &reference))
        .collect();
    for pair in errors.windows(2) {
        assert!(pair[1] <= 0.5 * pair[0], "{errors:?}");
    }
}
