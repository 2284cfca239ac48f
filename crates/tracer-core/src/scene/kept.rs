//! Whether a scene read back from a file (a prepared scene kept by
//! `--cache`) can be rendered: its checksum proves who wrote it, not that
//! its contents agree with themselves, so every count and index a render
//! would follow is checked first.

use super::{Accel, Scene};
use crate::material::Material;
use crate::texture::ColorTexture;

use scene_format::validate::{MAX_IMAGE_SIDE as MAX_SIDE, MAX_SAMPLES};

impl Scene {
    /// Why this scene, read back from a file, cannot be rendered, if so.
    pub fn check_kept(&self) -> Result<(), String> {
        let (w, h) = (self.camera.width, self.camera.height);
        if !(1..=MAX_SIDE).contains(&w) || !(1..=MAX_SIDE).contains(&h) {
            return Err(format!("an image of {w}x{h} pixels"));
        }
        if !(1..=MAX_SAMPLES).contains(&self.samples) {
            return Err(format!("{} samples a pixel", self.samples));
        }
        for (i, m) in self.materials.iter().enumerate() {
            if !textures_whole(m) {
                return Err(format!("material {i}'s image of the wrong size"));
            }
        }
        if let Accel::Bvh(bvh) = &self.accel {
            bvh.check(self.materials.len())?;
        }
        self.path_lights.check()?;
        match &self.environment {
            Some(e) if !e.is_whole() => Err("an environment of the wrong size".into()),
            _ => Ok(()),
        }
    }
}

/// Whether the images of a material's textures (and of its alpha mask)
/// have their texels.
fn textures_whole(m: &Material) -> bool {
    let whole = |t: Option<&ColorTexture>| match t {
        Some(ColorTexture::Image { texels, .. }) => texels.is_whole(),
        _ => true,
    };
    let own = match m {
        Material::Principled(p) => {
            let normals = p.normal_map.as_ref().map(|n| &n.texture);
            [&p.color_texture, &p.metallic_roughness]
                .iter()
                .all(|t| whole(t.as_ref()))
                && whole(normals)
        }
        _ => true,
    };
    let mask = m.alpha_mask().is_none_or(|mask| mask.is_whole());
    let surface = m.surface();
    let emission = surface.emission_texture.as_ref().map(|e| &e.texture);
    own && mask && whole(surface.color_texture.as_ref()) && whole(emission)
}
