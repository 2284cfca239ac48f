//! What the scene-level tests share: where the scenes are and how to load one,
//! a path-traced image, sRGB decoding.
// Each test binary that includes this module uses a part of it.
#![allow(dead_code)]

use glam::Vec3;
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use tracer_core::integrate::path::{PathTracer, Strategy};
use tracer_core::Scene;

pub fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

pub fn load(path: &Path) -> scene_format::SceneFile {
    scene_format::load_path(path).unwrap_or_else(|e| panic!("{e}"))
}

/// What `work` gives on a pool of `threads` threads.
pub fn on_threads<T: Send>(threads: usize, work: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(work)
}

/// The lab's scene tables, one file each in `scenes/`.
pub const LAB_SCENES: [&str; 12] = [
    "sphere-intersection",
    "triangle-intersection",
    "illumination-ambient",
    "illumination-diffuse",
    "illumination-specular",
    "illumination",
    "illumination-shininess-10",
    "illumination-shininess-50",
    "texture",
    "shadows",
    "reflectance",
    "reflectance2",
];

/// The image of `scene` at `samples` paths per pixel, with the samples'
/// scramblings of `seed` and light found by `strategy`: rows in parallel.
pub fn path_image(scene: &Scene, samples: u32, seed: u32, strategy: Strategy) -> Vec<Vec3> {
    let camera = scene.camera();
    let (width, height) = (camera.width, camera.height);
    (0..height)
        .into_par_iter()
        .flat_map_iter(|j| {
            let mut tracer = PathTracer::new(scene)
                .with_seed(seed)
                .with_strategy(strategy);
            (0..width)
                .map(|i| tracer.pixel(i, j, samples, || false))
                .collect::<Vec<_>>()
        })
        .collect()
}

/// The sRGB decoding of an 8-bit value, from IEC 61966-2-1, in f64.
pub fn srgb_decoded(byte: u8) -> f64 {
    let c = f64::from(byte) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}
