//! What the scene-level tests share: where the scenes are and how to load one.

use std::path::{Path, PathBuf};

pub fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

pub fn load(path: &Path) -> scene_format::SceneFile {
    scene_format::load_path(path).unwrap_or_else(|e| panic!("{e}"))
}

/// What `work` gives on a pool of `threads` threads.
// Not every test binary that includes this module renders on threads.
#[allow(dead_code)]
pub fn on_threads<T: Send>(threads: usize, work: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(work)
}

/// The lab's scene tables, one file each in `scenes/`.
// Not every test binary that includes this module uses the list.
#[allow(dead_code)]
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
