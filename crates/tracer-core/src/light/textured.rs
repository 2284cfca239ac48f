//! What varies over an emitting surface, read where a light sample's point
//! falls: its emission texture (times its factor) and the holes of its
//! alpha mask, which give off nothing. A light without them has one
//! radiance all over (`AreaLight::radiance`); with them, its pick is
//! weighed by the mean radiance, so a mostly black texture is seldom
//! picked, and its points by area as any light's.

use super::area::AreaPoint;
use crate::alpha_mask::AlphaMask;
use crate::geometry::{Sphere, UvMap};
use crate::material::Material;
use crate::texture::ColorTexture;
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// An emitting material's texture and mask, shared by its lights (each
/// triangle of a mesh), and its mean radiance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EmittingSurface {
    /// Multiplies the light's radiance.
    pub texture: Option<ColorTexture>,
    pub mask: Option<Arc<AlphaMask>>,
    /// The radiance given off on average (`Material::emission_mean`): the
    /// light's power, and `Lights::pdf_hit`'s radiance, are reckoned by it.
    pub mean: Vec3,
}

impl EmittingSurface {
    /// What varies over the emitters of `material`: its emission texture
    /// and, on `triangles` (which masks cut), its holes; None when nothing
    /// does.
    pub fn of(material: &Material, triangles: bool) -> Option<EmittingSurface> {
        let emission = material.surface().emission_texture.as_ref();
        let texture = emission.map(|e| e.texture.clone());
        let mask = material.alpha_mask().filter(|_| triangles).cloned();
        (texture.is_some() || mask.is_some()).then(|| EmittingSurface {
            texture,
            mask,
            mean: material.emission_mean(),
        })
    }
}

/// How a point drawn on a light finds its uv on the surface.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum UvAt {
    /// A flat light's `AreaPoint::at` (a triangle's barycentrics, a
    /// parallelogram's (s, t)) through the surface's map.
    Map(UvMap),
    /// A sphere's or ellipsoid's own mapping of its points.
    Sphere(Box<Sphere>),
}

/// What an area light's texture reads: the surface, and where its points
/// fall in the surface's uv.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LightTexture {
    pub surface: Arc<EmittingSurface>,
    pub uv: UvAt,
}

impl LightTexture {
    /// The radiance given off at `s` by a light of factor `radiance`: as
    /// `Material::emission_at` gives it where a path meets the surface.
    #[inline]
    pub fn radiance(&self, radiance: Vec3, s: &AreaPoint) -> Vec3 {
        let uv = match &self.uv {
            UvAt::Map(map) => map.apply(s.at),
            UvAt::Sphere(sphere) => sphere.uv(s.point, sphere.normal(s.point)),
        };
        if self.surface.mask.as_ref().is_some_and(|m| m.cuts(uv)) {
            return Vec3::ZERO;
        }
        match &self.surface.texture {
            Some(texture) if radiance != Vec3::ZERO => radiance * texture.color(uv),
            _ => radiance,
        }
    }

    /// Whether its images (read back from a file) have their texels.
    pub(crate) fn is_whole(&self) -> bool {
        let image = match &self.surface.texture {
            Some(ColorTexture::Image { texels, .. }) => texels.is_whole(),
            _ => true,
        };
        image && self.surface.mask.as_ref().is_none_or(|m| m.is_whole())
    }
}
