//! Materials: how a surface answers light. An enum, so the shading loop
//! dispatches statically; the lab's Blinn-Phong is one variant, glass
//! (Blinn-Phong with refraction) another.

use crate::alpha_mask::AlphaMask;
use crate::geometry::SurfaceHit;
use crate::optics::{fresnel_reflectance, refract};
use crate::texture::{ColorTexture, Texture};
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// A surface's material.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Material {
    /// The lab's Blinn-Phong material with mirror reflection (lab 4.1, 5.2).
    Phong(Phong),
    /// A surface that lets light through, bent by Snell's law.
    Glass(Glass),
    /// A physically based material (glTF's and Blender's names).
    Principled(Box<PrincipledMaterial>),
}

impl Material {
    /// Whether some light passes through the surface (it does not block
    /// shadow rays outright).
    pub fn is_transparent(&self) -> bool {
        matches!(self.lab(), Material::Glass(g) if g.transmittance > 0.0)
    }

    /// The material as the lab's tracer shades it: itself, or a physically
    /// based material's Whitted-mode reading (`PrincipledMaterial::lab`).
    pub fn lab(&self) -> &Material {
        match self {
            Material::Principled(p) => &p.lab,
            lab => lab,
        }
    }

    /// Where the surface is cut out, if anywhere.
    pub fn alpha_mask(&self) -> Option<&Arc<AlphaMask>> {
        match self {
            Material::Principled(p) => p.alpha_mask.as_ref(),
            _ => self.surface().alpha_mask.as_ref(),
        }
    }

    /// Whether shading the material reads a hit's texture coordinates: a
    /// texture of any kind, a normal map, an alpha mask.
    pub fn reads_uv(&self) -> bool {
        let own = match self {
            Material::Principled(p) => {
                p.color_texture.is_some()
                    || p.metallic_roughness.is_some()
                    || p.normal_map.is_some()
            }
            _ => false,
        };
        let s = self.surface();
        own || self.alpha_mask().is_some()
            || s.texture.is_some()
            || s.color_texture.is_some()
            || s.emission_texture.is_some()
    }

    /// The lab's surface colours (glass's seen from outside; a physically
    /// based material's Whitted-mode reading of them).
    pub fn surface(&self) -> &Phong {
        match self.lab() {
            Material::Phong(p) => p,
            Material::Glass(g) => &g.surface,
            Material::Principled(_) => unreachable!("a lab reading is the lab's kind"),
        }
    }

    /// The radiance given off on the front side (where it varies over
    /// the surface, its most: the factor an emission texture multiplies;
    /// `emission_at` is a hit's own).
    pub fn emission(&self) -> Vec3 {
        self.surface().emission
    }

    /// The radiance given off on the front side, on average over the
    /// surface (`emission` times its texture's mean): what the pick of a
    /// light sample weighs it by, `light::Lights::pdf_hit`'s radiance.
    pub fn emission_mean(&self) -> Vec3 {
        self.surface().emission_mean()
    }

    /// The radiance given off on the front side at `hit`: `emission`, times
    /// the emission texture there, if any.
    #[inline(always)]
    pub fn emission_at(&self, hit: &SurfaceHit) -> Vec3 {
        self.surface().emission_at(hit.uv)
    }

    /// What the surface sends back at `hit` other than along single
    /// directions, as path mode reads it (`bsdf/`), each channel 0 to 1:
    /// the denoiser's albedo guide. A lab material's textured `diffuse`
    /// plus its highlight's `specular` colour, scaled as `bsdf::LabBsdf`
    /// scales them (its mirror and glass are left out: single directions);
    /// a physically based one's textured `base_color` in the share of its
    /// lobes that are not smooth (the opaque dielectric's diffuse base
    /// always; its thin specular coat, about 4 %, is left out), its
    /// metallic and roughness as its textures make them there.
    pub fn albedo(&self, hit: &SurfaceHit) -> Vec3 {
        let albedo = match self {
            Material::Principled(p) => {
                let at = p.at(hit);
                let [metal, glass, base] = at.shares();
                let rough = if at.is_smooth() { 0.0 } else { metal + glass };
                at.unit_base() * (rough + base)
            }
            lab => {
                let (diffuse, specular) = lab.surface().textured(hit);
                (diffuse + specular) / albedo_sum(lab).max(1.0)
            }
        };
        albedo.clamp(Vec3::ZERO, Vec3::ONE)
    }

    /// How a perfect mirror or smooth glass sends on a ray of unit
    /// direction `dir` that meets it at `hit` (path mode's reading of it);
    /// None for a surface with anything else (a diffuse colour, a
    /// highlight, roughness, an opaque dielectric's base): the surfaces the
    /// denoiser's guides are followed through.
    pub fn specular_split(&self, dir: Vec3, hit: &SurfaceHit) -> Option<SpecularSplit> {
        let facing = if dir.dot(hit.shading_normal) > 0.0 {
            -hit.shading_normal
        } else {
            hit.shading_normal
        };
        let reflected = (dir - 2.0 * dir.dot(facing) * facing).normalize();
        match self {
            Material::Principled(p) => p.specular_split(dir, hit, facing, reflected),
            lab => {
                let surface = lab.surface();
                if surface.diffuse != Vec3::ZERO || surface.specular != Vec3::ZERO {
                    return None;
                }
                let scale = 1.0 / albedo_sum(lab).max(1.0);
                let split = match lab {
                    Material::Glass(g) => g.split(dir, hit),
                    _ => Split {
                        reflected: surface.reflectance,
                        transmitted: None,
                    },
                };
                let split = SpecularSplit {
                    reflected: (reflected, Vec3::splat(split.reflected * scale)),
                    transmitted: split
                        .transmitted
                        .map(|(d, energy)| (d, Vec3::splat(energy * scale))),
                };
                (split.energy() > 0.0).then_some(split)
            }
        }
    }
}

/// A tangent-space normal texture: its texels (read as data) and how far
/// they bend the normal.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NormalMap {
    pub texture: ColorTexture,
    /// Scales the texel's x and y (glTF's `normalTexture.scale`).
    pub strength: f32,
}

impl NormalMap {
    /// The shading normal `n` (unit) bent by the texel at `uv`, in the
    /// frame of `tangent` (x, y, z along u; w the handedness, the
    /// bitangent w n x tangent pointing up the image); None where the
    /// tangent gives no frame.
    pub fn bend(&self, n: Vec3, tangent: glam::Vec4, uv: glam::Vec2) -> Option<Vec3> {
        let t = tangent.truncate();
        let t = (t - n * n.dot(t)).try_normalize()?;
        let b = tangent.w * n.cross(t);
        let c = self.texture.color(uv) * 2.0 - Vec3::ONE;
        let m = Vec3::new(c.x * self.strength, c.y * self.strength, c.z);
        (m.x * t + m.y * b + m.z * n).try_normalize()
    }
}

/// A physically based material's parameters at one hit, its textures read.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrincipledAt {
    pub base_color: Vec3,
    pub metallic: f32,
    pub roughness: f32,
    pub ior: f32,
    pub transmission: f32,
    pub emission: Vec3,
}

impl PrincipledAt {
    /// The BSDF's parameters.
    pub fn params(&self) -> Principled {
        Principled {
            base_color: self.base_color,
            metallic: self.metallic,
            roughness: self.roughness,
            ior: self.ior,
            transmission: self.transmission,
        }
    }

    /// The shares of the metal, the dielectric that transmits and the
    /// opaque dielectric in the mixture (`bsdf::principled`'s weights).
    fn shares(&self) -> [f32; 3] {
        let unit = |x: f32| if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
        let (metallic, transmission) = (unit(self.metallic), unit(self.transmission));
        [
            metallic,
            (1.0 - metallic) * transmission,
            (1.0 - metallic) * (1.0 - transmission),
        ]
    }

    /// Whether its lobes are single directions (GGX's mirror threshold).
    fn is_smooth(&self) -> bool {
        crate::bsdf::microfacet::Ggx::from_roughness(self.roughness).is_smooth()
    }

    /// `base_color` clamped to 0..1, as its BSDF takes it.
    fn unit_base(&self) -> Vec3 {
        self.base_color.clamp(Vec3::ZERO, Vec3::ONE)
    }
}

/// Where a perfectly specular surface sends a ray: its mirror direction
/// and, through glass, its refracted one, each with the colour of the
/// light it carries (what a path along it is multiplied by).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpecularSplit {
    pub reflected: (Vec3, Vec3),
    /// None for a mirror, or under total internal reflection.
    pub transmitted: Option<(Vec3, Vec3)>,
}

impl SpecularSplit {
    /// The summed channels of both branches' colours.
    pub fn energy(&self) -> f32 {
        self.reflected.1.element_sum() + self.transmitted.map_or(0.0, |t| t.1.element_sum())
    }
}

/// A physically based material: its parameters (`bsdf::principled`), its
/// textures, and how Whitted mode shades it (`lab`, which also holds its
/// emission and the emission's texture, read by both modes).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PrincipledMaterial {
    pub base_color: Vec3,
    pub metallic: f32,
    pub roughness: f32,
    pub ior: f32,
    pub transmission: f32,
    /// Multiplies `base_color` at each hit.
    pub color_texture: Option<ColorTexture>,
    /// Its blue multiplies `metallic`, its green `roughness` (glTF's
    /// packing), at each hit.
    pub metallic_roughness: Option<ColorTexture>,
    /// Bends the shading normal (`Scene::closest_hit`).
    pub normal_map: Option<NormalMap>,
    /// Where the surface is cut out (glTF's MASK): read by the BVH's
    /// search (`Material::alpha_mask`), not by shading.
    pub alpha_mask: Option<Arc<AlphaMask>>,
    /// Whitted mode's reading (`PrincipledMaterial::new`): the lab's kind.
    pub lab: Material,
}

impl PrincipledMaterial {
    /// The material of these parameters, with its Whitted-mode reading, a
    /// documented approximation (the book's table, docs/src/guide/materials.md): the diffuse colour
    /// is `base_color` times the dielectric's opaque share; the highlight's
    /// colour is the reflection at normal incidence (`base_color` for a
    /// metal, the Fresnel F0 of `ior` for a dielectric), its exponent the
    /// Blinn-Phong equivalent of GGX's alpha, 2 / alpha^2 - 2; a metal is a
    /// mirror of `metallic (1 - roughness)^2`; with `transmission` it is
    /// Fresnel glass of that transmittance.
    pub fn new(p: Principled, emission: Vec3) -> PrincipledMaterial {
        let opaque = (1.0 - p.metallic) * (1.0 - p.transmission);
        let f0 = ((p.ior - 1.0) / (p.ior + 1.0)).powi(2);
        let alpha = (p.roughness * p.roughness).max(1e-3);
        let surface = Phong {
            ambient: Vec3::ZERO,
            diffuse: p.base_color * opaque,
            specular: Vec3::splat(f0).lerp(p.base_color, p.metallic),
            shininess: (2.0 / (alpha * alpha) - 2.0).clamp(0.0, 1e4),
            reflectance: p.metallic * (1.0 - p.roughness).powi(2),
            texture: None,
            color_texture: None,
            emission,
            emission_texture: None,
            alpha_mask: None,
        };
        let transmittance = (1.0 - p.metallic) * p.transmission;
        let lab = if transmittance > 0.0 {
            Material::Glass(Glass {
                surface,
                transmittance,
                ior: p.ior,
                fresnel: true,
                absorption: Vec3::ZERO,
            })
        } else {
            Material::Phong(surface)
        };
        PrincipledMaterial {
            base_color: p.base_color,
            metallic: p.metallic,
            roughness: p.roughness,
            ior: p.ior,
            transmission: p.transmission,
            color_texture: None,
            metallic_roughness: None,
            normal_map: None,
            alpha_mask: None,
            lab,
        }
    }

    /// Its parameters at `hit`, its textures read at the hit's uv.
    #[inline(always)]
    pub fn at(&self, hit: &SurfaceHit) -> PrincipledAt {
        let uv = hit.uv;
        let base_color = match &self.color_texture {
            Some(texture) => self.base_color * texture.color(uv),
            None => self.base_color,
        };
        let (metallic, roughness) = match &self.metallic_roughness {
            Some(texture) => {
                let texel = texture.color(uv);
                (self.metallic * texel.z, self.roughness * texel.y)
            }
            None => (self.metallic, self.roughness),
        };
        PrincipledAt {
            base_color,
            metallic,
            roughness,
            ior: self.ior,
            transmission: self.transmission,
            emission: self.lab.surface().emission_at(uv),
        }
    }

    /// Its emission's texture, if any: its Whitted-mode reading's, which
    /// holds its emission.
    pub fn emission_texture(&self) -> Option<&EmissionTexture> {
        self.lab.surface().emission_texture.as_ref()
    }

    /// `Material::specular_split` of a smooth metal or glass (or a mix of
    /// the two, without an opaque base): the metal reflects its base
    /// colour; the glass reflects Fresnel's share, untinted, and refracts
    /// the rest tinted by its base colour (each as its textures make it at
    /// `hit`). `facing` is the shading normal on `dir`'s side; `reflected`
    /// the mirror direction.
    fn specular_split(
        &self,
        dir: Vec3,
        hit: &SurfaceHit,
        facing: Vec3,
        reflected: Vec3,
    ) -> Option<SpecularSplit> {
        let at = self.at(hit);
        let [metal, glass, base] = at.shares();
        if base > 0.0 || !at.is_smooth() {
            return None;
        }
        let colour = at.unit_base();
        let ior = if self.ior.is_finite() && self.ior > 0.0 {
            self.ior
        } else {
            1.0
        };
        let eta = if hit.front_face { 1.0 / ior } else { ior };
        let refracted = refract(dir, facing, eta);
        let f = match refracted {
            Some(_) => fresnel_reflectance(-dir.dot(facing), eta),
            None => 1.0,
        };
        Some(SpecularSplit {
            reflected: (reflected, metal * colour + Vec3::splat(glass * f)),
            transmitted: refracted
                .filter(|_| glass * (1.0 - f) > 0.0)
                .map(|d| (d, glass * (1.0 - f) * colour)),
        })
    }

    /// The same material with `texture` on its emission (kept with the
    /// emission, by its Whitted-mode reading, which both modes read),
    /// whose texels' mean colour is `mean` (`ColorTexture::mean`, worked
    /// out once per image by the caller).
    pub fn with_emission_texture(mut self, texture: ColorTexture, mean: Vec3) -> Self {
        let surface = match &mut self.lab {
            Material::Phong(p) => p,
            Material::Glass(g) => &mut g.surface,
            Material::Principled(_) => unreachable!("a lab reading is the lab's kind"),
        };
        surface.emission_texture = Some(EmissionTexture { texture, mean });
        self
    }

    /// The same material with a colour texture on `base_color` (and on the
    /// diffuse colour of its Whitted-mode reading).
    pub fn with_color_texture(mut self, texture: ColorTexture) -> PrincipledMaterial {
        match &mut self.lab {
            Material::Phong(p) => p.color_texture = Some(texture.clone()),
            Material::Glass(g) => g.surface.color_texture = Some(texture.clone()),
            Material::Principled(_) => {}
        }
        self.color_texture = Some(texture);
        self
    }
}

/// The lab's Blinn-Phong material (section 4.1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Phong {
    pub ambient: Vec3,
    pub diffuse: Vec3,
    pub specular: Vec3,
    pub shininess: f32,
    /// 0 = no mirror reflection, 1 = perfect mirror.
    pub reflectance: f32,
    /// Multiplies the whole local colour of a hit (lab 4.5 and 7).
    pub texture: Option<Arc<Texture>>,
    /// Multiplies `ambient` and `diffuse` at each hit (an image or a
    /// checkerboard); specular and reflection are left as they are.
    pub color_texture: Option<ColorTexture>,
    /// Radiance given off on the front side (where the geometric normal
    /// points): an area light in path mode, a colour seen in Whitted mode.
    pub emission: Vec3,
    /// Multiplies `emission` at each hit.
    pub emission_texture: Option<EmissionTexture>,
    /// Where the surface is cut out (`alpha_cutoff`): read by the BVH's
    /// search (`Material::alpha_mask`), not by shading.
    pub alpha_mask: Option<Arc<AlphaMask>>,
}

/// An image on a surface's emission, and the mean colour of its texels
/// (`ColorTexture::mean`): a light's pick weighs the emission by it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EmissionTexture {
    pub texture: ColorTexture,
    pub mean: Vec3,
}

impl Phong {
    /// `emission` times the emission texture at `uv`, if any.
    #[inline(always)]
    pub fn emission_at(&self, uv: glam::Vec2) -> Vec3 {
        match &self.emission_texture {
            Some(e) if self.emission != Vec3::ZERO => self.emission * e.texture.color(uv),
            _ => self.emission,
        }
    }

    /// `emission` times its texture's mean colour: the radiance given off
    /// on average.
    pub fn emission_mean(&self) -> Vec3 {
        match &self.emission_texture {
            Some(e) => self.emission * e.mean,
            None => self.emission,
        }
    }

    /// The diffuse and highlight colours at `hit`: a colour texture
    /// multiplies the diffuse one, a lab texture both (it multiplies the
    /// lab's whole local colour), as path mode reads them.
    pub fn textured(&self, hit: &SurfaceHit) -> (Vec3, Vec3) {
        let (mut diffuse, mut specular) = (self.diffuse, self.specular);
        if let Some(texture) = &self.color_texture {
            diffuse *= texture.color(hit.uv);
        }
        if let Some(texture) = &self.texture {
            let texel = texture.texel(hit.uv);
            diffuse *= texel;
            specular *= texel;
        }
        (diffuse, specular)
    }

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
            color_texture: None,
            emission: Vec3::ZERO,
            emission_texture: None,
            alpha_mask: None,
        }
    }
}

/// A dielectric: the lab's Blinn-Phong surface (seen from outside), a
/// mirror ray, and a refracted ray into or out of the inside.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Glass {
    /// The local colour and, without `fresnel`, the mirror's energy.
    pub surface: Phong,
    /// Energy of the refracted ray (without `fresnel`), or the fraction
    /// of the Fresnel-transmitted light that passes (with it).
    pub transmittance: f32,
    /// Index of refraction of the inside; the outside is taken as 1.
    pub ior: f32,
    /// Reflection and transmission from the Fresnel equations.
    pub fresnel: bool,
    /// Beer-Lambert coefficient per unit length inside, per channel.
    pub absorption: Vec3,
}

/// The material's parameters, as the scene file gives them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Principled {
    pub base_color: Vec3,
    /// 0 (dielectric) to 1 (metal).
    pub metallic: f32,
    /// 0 (a mirror) to 1; GGX's alpha is its square.
    pub roughness: f32,
    /// The index of refraction of the dielectric, outside taken as 1.
    pub ior: f32,
    /// 0 (opaque) to 1 (all the dielectric's light refracted through).
    pub transmission: f32,
}

impl Default for Principled {
    fn default() -> Self {
        Principled {
            base_color: Vec3::splat(0.8),
            metallic: 0.0,
            roughness: 0.5,
            ior: 1.5,
            transmission: 0.0,
        }
    }
}

/// The largest channel of what material `m` sends back: its diffuse,
/// specular and mirror albedos, and its glass's reflected and transmitted
/// energies (at most 1 with `fresnel`). The same sum as the scene file's
/// warning (`scene_format::checks::albedo_sum`).
pub fn albedo_sum(m: &Material) -> f32 {
    let (surface, interface) = match m {
        Material::Glass(g) if g.fresnel => (&g.surface, 1.0),
        Material::Glass(g) => (&g.surface, g.surface.reflectance + g.transmittance),
        _ => (m.surface(), m.surface().reflectance),
    };
    (surface.diffuse + surface.specular).max_element() + interface
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::{ImageTexels, Wrap};

    /// A normal texture of one texel (data, not colour: (r, g, b) / 255).
    fn one_texel(rgb: [u8; 3]) -> NormalMap {
        let texels = ImageTexels::from_raw8(1, 1, Arc::new(vec![rgb]));
        NormalMap {
            texture: ColorTexture::Image {
                texels: Arc::new(texels),
                scale: glam::Vec2::ONE,
                wrap: Wrap::Repeat,
                place: None,
            },
            strength: 1.0,
        }
    }

    #[test]
    fn a_material_reads_uv_where_some_texture_or_mask_does() {
        let checker = ColorTexture::Checker {
            colors: [Vec3::ZERO, Vec3::ONE],
            scale: glam::Vec2::ONE,
        };
        let plain = Phong::default_grey();
        let phongs = [
            Phong {
                color_texture: Some(checker.clone()),
                ..plain.clone()
            },
            Phong {
                texture: Some(Arc::new(crate::texture::Texture::new(
                    1,
                    1,
                    vec![Vec3::ONE],
                ))),
                ..plain.clone()
            },
            Phong {
                emission_texture: Some(EmissionTexture {
                    texture: checker.clone(),
                    mean: Vec3::splat(0.5),
                }),
                ..plain.clone()
            },
            Phong {
                alpha_mask: AlphaMask::new(None, 2.0).map(Arc::new),
                ..plain.clone()
            },
        ];
        assert!(!Material::Phong(plain.clone()).reads_uv());
        for (k, p) in phongs.into_iter().enumerate() {
            assert!(Material::Phong(p.clone()).reads_uv(), "phong {k}");
            let glass = Glass {
                surface: p,
                transmittance: 1.0,
                ior: 1.5,
                fresnel: true,
                absorption: Vec3::ZERO,
            };
            assert!(Material::Glass(glass).reads_uv(), "glass {k}");
        }
        let principled = Principled {
            base_color: Vec3::splat(0.5),
            metallic: 0.0,
            roughness: 0.5,
            ior: 1.5,
            transmission: 0.0,
        };
        let bare = PrincipledMaterial::new(principled, Vec3::ZERO);
        assert!(!Material::Principled(Box::new(bare.clone())).reads_uv());
        let textured = [
            PrincipledMaterial {
                color_texture: Some(checker.clone()),
                ..bare.clone()
            },
            PrincipledMaterial {
                metallic_roughness: Some(checker),
                ..bare.clone()
            },
            PrincipledMaterial {
                normal_map: Some(one_texel([128, 128, 255])),
                ..bare.clone()
            },
            PrincipledMaterial {
                alpha_mask: AlphaMask::new(None, 2.0).map(Arc::new),
                ..bare
            },
        ];
        for (k, p) in textured.into_iter().enumerate() {
            assert!(
                Material::Principled(Box::new(p)).reads_uv(),
                "principled {k}"
            );
        }
    }

    #[test]
    fn the_albedo_guide_reads_metallic_and_roughness_as_their_texture_makes_them() {
        // A smooth metal by its factors, whose texture (blue 0) makes it a
        // dielectric: its diffuse base, all of base_color, is the albedo.
        let principled = Principled {
            base_color: Vec3::splat(0.5),
            metallic: 1.0,
            roughness: 0.0,
            ior: 1.5,
            transmission: 0.0,
        };
        let mut metal = PrincipledMaterial::new(principled, Vec3::ZERO);
        let hit = SurfaceHit::facing(Vec3::Z, glam::Vec2::splat(0.5));
        // Untextured, a smooth metal is followed, not a guide's colour.
        assert_eq!(
            Material::Principled(Box::new(metal.clone())).albedo(&hit),
            Vec3::ZERO
        );
        metal.metallic_roughness = Some(one_texel([0, 0, 0]).texture);
        let material = Material::Principled(Box::new(metal));
        assert_eq!(material.albedo(&hit), Vec3::splat(0.5));
        assert!(material.specular_split(-Vec3::Z, &hit).is_none());
    }

    #[test]
    fn a_normal_texture_bends_the_normal_in_the_tangent_frame() {
        let (n, uv) = (Vec3::Z, glam::Vec2::splat(0.5));
        let tangent = glam::Vec4::new(1.0, 0.0, 0.0, 1.0);
        // (128, 128, 255): straight out, the normal kept (to 1/255).
        let flat = one_texel([128, 128, 255]).bend(n, tangent, uv).unwrap();
        assert!((flat - n).length() < 0.01, "{flat}");
        // Red and blue full: tilted 45 degrees toward the tangent (+x).
        let right = one_texel([255, 128, 255]).bend(n, tangent, uv).unwrap();
        let want = Vec3::new(1.0, 0.0, 1.0).normalize();
        assert!((right - want).length() < 0.01, "{right}");
        // Green and blue full: toward the bitangent, w n x t = +y, up the image...
        let up = one_texel([128, 255, 255]).bend(n, tangent, uv).unwrap();
        let want = Vec3::new(0.0, 1.0, 1.0).normalize();
        assert!((up - want).length() < 0.01, "{up}");
        // ...and down it where the handedness is -1 (a mirrored layout).
        let mirrored = glam::Vec4::new(1.0, 0.0, 0.0, -1.0);
        let down = one_texel([128, 255, 255]).bend(n, mirrored, uv).unwrap();
        let want = Vec3::new(0.0, -1.0, 1.0).normalize();
        assert!((down - want).length() < 0.01, "{down}");
        // A tangent along the normal gives no frame.
        let along = glam::Vec4::new(0.0, 0.0, 1.0, 1.0);
        assert!(one_texel([255, 0, 0]).bend(n, along, uv).is_none());
    }
}

/// How a ray's energy divides at a glass surface.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Split {
    /// Energy of the mirror ray.
    pub reflected: f32,
    /// Direction and energy of the refracted ray; `None` under total
    /// internal reflection (its energy then goes to the mirror ray) or
    /// when nothing is transmitted.
    pub transmitted: Option<(Vec3, f32)>,
}

impl Glass {
    /// How a ray of unit direction `dir` meeting the surface at `hit`
    /// divides: entering when it met the front face (the side the
    /// geometric normal points to), leaving otherwise.
    pub fn split(&self, dir: Vec3, hit: &SurfaceHit) -> Split {
        let (normal, eta) = if hit.front_face {
            (hit.shading_normal, 1.0 / self.ior)
        } else {
            (-hit.shading_normal, self.ior)
        };
        let refracted = refract(dir, normal, eta);
        let (reflected, transmitted) = if self.fresnel {
            let cos_i = -dir.dot(normal);
            let f = fresnel_reflectance(cos_i, eta);
            (f, (1.0 - f) * self.transmittance)
        } else {
            let r = self.surface.reflectance;
            match refracted {
                // Total internal reflection: nothing is transmitted.
                None => (r + self.transmittance, 0.0),
                Some(_) => (r, self.transmittance),
            }
        };
        Split {
            reflected,
            transmitted: refracted
                .filter(|_| transmitted > 0.0)
                .map(|d| (d, transmitted)),
        }
    }

    /// The fraction of light along `dir` that passes the surface at `hit`,
    /// for shadow rays, which go on unbent (no caustics): the transmitted
    /// energy of a crossing at `dir`'s angle from outside, going in or out
    /// alike. The light that really gets through was bent on the way in
    /// and meets the far side at that bent angle, where the Fresnel
    /// transmission is the one going in (reciprocity) and there is no
    /// total internal reflection; the straight line's own angle from
    /// inside would dim it wrongly and, past the critical angle, block it.
    pub fn shadow_transmission(&self, dir: Vec3, hit: &SurfaceHit) -> f32 {
        if !self.fresnel {
            return self.transmittance;
        }
        let cos_i = dir.dot(hit.shading_normal).abs();
        (1.0 - fresnel_reflectance(cos_i, 1.0 / self.ior)) * self.transmittance
    }

    /// What is left of light after `distance` inside (Beer-Lambert).
    pub fn absorbed_over(&self, distance: f32) -> Vec3 {
        if self.absorption == Vec3::ZERO {
            return Vec3::ONE;
        }
        // A channel that absorbs nothing keeps all, even over an infinite
        // distance (where 0 * inf would be NaN); otherwise the same bits.
        let kept = (-self.absorption * distance).exp();
        Vec3::select(self.absorption.cmpeq(Vec3::ZERO), Vec3::ONE, kept)
    }
}
