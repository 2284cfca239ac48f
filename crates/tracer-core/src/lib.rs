//! The ray tracer of the lab: camera, rays, shapes, Blinn-Phong shading,
//! shadows, mirror recursion, and the encoding of the image. It reads no
//! files and prints nothing.

pub mod aov;
pub mod bvh;
pub mod camera;
pub mod image;
pub mod light;
pub mod material;
pub mod ray;
pub mod render;
pub mod scene;
pub mod shade;
pub mod shapes;
pub mod texture;

pub use camera::Camera;
pub use image::{Encoding, LinearImage};
pub use ray::Ray;
pub use render::{render, render_with_progress};
pub use scene::Scene;
pub use shade::RayStats;

/// Minimum distance along a secondary ray, so it does not hit its own origin
/// surface (the lab's epsilon for self-hits).
pub const EPSILON: f32 = 1e-4;
