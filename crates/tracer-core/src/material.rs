use crate::texture::Texture;
use glam::Vec3;
use std::sync::Arc;

/// The lab's Blinn-Phong material (section 4.1).
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub ambient: Vec3,
    pub diffuse: Vec3,
    pub specular: Vec3,
    pub shininess: f32,
    /// 0 = no mirror reflection, 1 = perfect mirror.
    pub reflectance: f32,
    /// Multiplies the whole local colour of a hit (lab 4.5 and 7).
    pub texture: Option<Arc<Texture>>,
}

impl Material {
    pub fn from_scene(m: &scene_format::Material, texture: Option<Arc<Texture>>) -> Self {
        Material {
            ambient: m.ambient.into(),
            diffuse: m.diffuse.into(),
            specular: m.specular.into(),
            shininess: m.shininess,
            reflectance: m.reflectance,
            texture,
        }
    }

    /// What an object without a material gets: plain matte grey, so that a
    /// forgotten material still shows the shape.
    pub fn default_grey() -> Self {
        Material {
            ambient: Vec3::splat(0.1),
            diffuse: Vec3::splat(0.7),
            specular: Vec3::ZERO,
            shininess: 0.0,
            reflectance: 0.0,
            texture: None,
        }
    }
}
