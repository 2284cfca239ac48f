//! The 3D ray tracer of the lab, and beyond it: camera, rays, shapes and
//! their BVH, materials, lights, shading with shadows and mirror recursion,
//! the pixel driver, and the encoding of the image. It reads no files and
//! prints nothing; `prepare` is the one module that reads the scene file's
//! types.
//!
//! The flow: `prepare(&SceneFile) -> Scene`, then
//! `render(&Scene, &RenderJob, progress) -> Rendered` (a linear image and
//! the ray counts), then `LinearImage::encode(scene.encoding())`.

pub mod accel;
pub mod adaptive;
pub mod alpha_mask;
pub mod aov;
mod bands;
pub mod bsdf;
pub mod camera;
pub mod explain;
pub mod film;
mod gamma_table;
pub mod geometry;
pub mod image;
pub mod integrate;
pub mod light;
pub mod material;
pub mod names;
pub mod optics;
pub mod prepare;
pub mod ray;
pub mod region;
pub mod render;
pub mod sampler;
pub mod sampling;
pub mod scene;
pub mod simd;
pub mod texture;

pub use camera::Camera;
pub use image::{Encoding, LinearImage};
pub use integrate::RayStats;
pub use prepare::{prepare, PrepareError};
pub use ray::Ray;
pub use render::{
    pixel_sample, render, render_cancellable, render_into, sample_rays, Output, Region, RenderJob,
    Rendered,
};
pub use scene::Scene;

/// Minimum distance along a secondary ray, so it does not hit its own origin
/// surface (the lab's epsilon for self-hits).
pub const EPSILON: f32 = 1e-4;
