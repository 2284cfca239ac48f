//! Materials: how a surface answers light. An enum, so the shading loop
//! dispatches statically; the lab's Blinn-Phong is one variant, and new
//! kinds (glass, ...) join as variants.

use crate::texture::Texture;
use glam::Vec3;
use std::sync::Arc;

/// A surface's material.
#[derive(Debug, Clone, PartialEq)]
pub enum Material {
    /// The lab's Blinn-Phong material with mirror reflection (lab 4.1, 5.2).
    Phong(Phong),
}

/// The lab's Blinn-Phong material (section 4.1).
#[derive(Debug, Clone, PartialEq)]
pub struct Phong {
    pub ambient: Vec3,
    pub diffuse: Vec3,
    pub specular: Vec3,
    pub shininess: f32,
    /// 0 = no mirror reflection, 1 = perfect mirror.
    pub reflectance: f32,
    /// Multiplies the whole local colour of a hit (lab 4.5 and 7).
    pub texture: Option<Arc<Texture>>,
}

impl Phong {
    /// What an object without a material gets: plain matte grey, so that a
    /// forgotten material still shows the shape.
    pub fn default_grey() -> Phong {
        Phong {
            ambient: Vec3::splat(0.1),
            diffuse: Vec3::splat(0.7),
            specular: Vec3::ZERO,
            shininess: 0.0,
            reflectance: 0.0,
            texture: None,
        }
    }
}
