//! Where a surface is cut out: glTF's `alphaMode` MASK, a scene
//! material's `alpha_cutoff`. A hit whose alpha is below the cutoff is no
//! hit at all: the BVH's search passes over it to the next one
//! (`accel::Bvh::with_masks`), so every ray (from the camera, bounced,
//! toward a light) goes through the hole, as pbrt-v4 tests a shape's
//! alpha inside its intersection. Surfaces without a mask pay nothing.

use crate::texture::ColorTexture;
use glam::Vec2;
use serde::{Deserialize, Serialize};

/// A surface's alpha (its colour texture's, 1 without one) and the
/// cutoff below which it is not there.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AlphaMask {
    texture: Option<ColorTexture>,
    cutoff: f32,
}

impl AlphaMask {
    /// The mask that cuts where `texture`'s alpha (1 where it has none)
    /// is below `cutoff`; None where nothing would be cut.
    pub fn new(texture: Option<ColorTexture>, cutoff: f32) -> Option<AlphaMask> {
        let texture = texture.filter(ColorTexture::has_alpha);
        let least = if texture.is_some() { 0.0 } else { 1.0 };
        (cutoff > least).then_some(AlphaMask { texture, cutoff })
    }

    /// Whether the surface is cut out at `uv`.
    #[inline]
    pub fn cuts(&self, uv: Vec2) -> bool {
        let alpha = self.texture.as_ref().map_or(1.0, |t| t.alpha(uv));
        alpha < self.cutoff
    }

    /// Whether its image (read back from a file) has its texels.
    pub(crate) fn is_whole(&self) -> bool {
        match &self.texture {
            Some(ColorTexture::Image { texels, .. }) => texels.is_whole(),
            _ => true,
        }
    }
}
