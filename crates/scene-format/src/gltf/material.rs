//! glTF materials (`pbrMetallicRoughness`, emission, normal textures and
//! the material extensions read) as the scene file's physically based
//! materials, their textures' images read (a file beside the glTF, a data
//! URI, or a buffer view of a .glb).

use super::doc::{self, Document};
use super::{buffers, Failure};
use crate::images::ImageCache;
use crate::key_path::KeyPath;
use crate::model::{ImageData, ImageTexture, Material, TextureRef, TextureScale, Wrap};
use crate::source::Source;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// glTF's default material, for primitives that name none: every
/// property's default (white, metallic 1, roughness 1), as the spec says.
pub fn default_material() -> Material {
    Material {
        base_color: Some([1.0; 3]),
        metallic: Some(1.0),
        roughness: Some(1.0),
        ..Material::default()
    }
}

/// Whether each material has a normal texture (its primitives need
/// tangents).
pub(crate) fn normal_mapped(doc: &Document) -> Vec<bool> {
    doc.materials
        .iter()
        .map(|m| m.normal_texture.is_some())
        .collect()
}

/// Material `m` (index `i`) in the scene file's terms.
pub(crate) fn read(
    m: &doc::Material,
    i: usize,
    textures: &mut Textures,
    warnings: &mut Vec<(KeyPath, String)>,
) -> Result<Material, Failure> {
    let at = KeyPath::root().key("materials").index(i);
    let pbr_at = at.key("pbrMetallicRoughness");
    let pbr = &m.pbr_metallic_roughness;
    let [r, g, b, _alpha] = pbr.base_color_factor;
    fractions(&pbr_at.key("baseColorFactor"), &pbr.base_color_factor)?;
    fractions(&pbr_at.key("metallicFactor"), &[pbr.metallic_factor])?;
    fractions(&pbr_at.key("roughnessFactor"), &[pbr.roughness_factor])?;
    fractions(&at.key("emissiveFactor"), &m.emissive_factor)?;
    let ext = &m.extensions;
    let ext_at = at.key("extensions");
    let strength = match &ext.emissive_strength {
        Some(s) => {
            let key = ext_at
                .key("KHR_materials_emissive_strength")
                .key("emissiveStrength");
            if !(s.emissive_strength >= 0.0 && s.emissive_strength.is_finite()) {
                return Err(Failure::at(
                    key,
                    format!("expected a number >= 0, found {}", s.emissive_strength),
                ));
            }
            s.emissive_strength
        }
        None => 1.0,
    };
    let mut material = Material {
        base_color: Some([r, g, b]),
        metallic: Some(pbr.metallic_factor),
        roughness: Some(pbr.roughness_factor),
        emission: m.emissive_factor.map(|e| e * strength),
        ..Material::default()
    };
    if let Some(t) = &ext.transmission {
        let key = ext_at
            .key("KHR_materials_transmission")
            .key("transmissionFactor");
        fractions(&key, &[t.transmission_factor])?;
        material.transmission = Some(t.transmission_factor);
        if t.transmission_texture.is_some() {
            warnings.push((
                ext_at
                    .key("KHR_materials_transmission")
                    .key("transmissionTexture"),
                "not read: the factor alone is used".to_string(),
            ));
        }
    }
    if let Some(ior) = &ext.ior {
        let key = ext_at.key("KHR_materials_ior").key("ior");
        if ior.ior == 0.0 {
            warnings.push((
                key,
                "an ior of 0 (a perfect reflector) is read as 1.5".to_string(),
            ));
        } else if !(ior.ior >= 1.0 && ior.ior.is_finite()) {
            return Err(Failure::at(
                key,
                format!("expected an index of refraction >= 1, found {}", ior.ior),
            ));
        } else {
            material.ior = ior.ior;
        }
    }
    if let Some(t) = &pbr.base_color_texture {
        let key = pbr_at.key("baseColorTexture");
        material.texture = textures.texture(info(t), &key, warnings)?;
    }
    if let Some(t) = &pbr.metallic_roughness_texture {
        let key = pbr_at.key("metallicRoughnessTexture");
        material.metallic_roughness_texture = textures.texture(info(t), &key, warnings)?;
    }
    if let Some(t) = &m.emissive_texture {
        let key = at.key("emissiveTexture");
        material.emission_texture = textures.texture(info(t), &key, warnings)?;
    }
    if let Some(t) = &m.normal_texture {
        let key = at.key("normalTexture");
        let found = (t.index, t.tex_coord, t.extensions.transform.as_ref());
        material.normal_texture = textures.texture(found, &key, warnings)?;
        if !t.scale.is_finite() {
            return Err(Failure::at(
                key.key("scale"),
                format!("expected a finite number, found {}", t.scale),
            ));
        }
        material.normal_strength = Some(t.scale);
    }
    material.alpha_cutoff = alpha_cutoff(m, &at, warnings)?;
    Ok(material)
}

/// The material's `alpha_cutoff`: MASK's `alphaCutoff` (0.5 when left
/// out) over the base colour factor's alpha, so that the texture's alpha
/// alone is compared with it (the spec's factor x texel < cutoff); BLEND
/// read as MASK at 0.5, with a warning; none for OPAQUE, or where nothing
/// can be below the cutoff.
fn alpha_cutoff(
    m: &doc::Material,
    at: &KeyPath,
    warnings: &mut Vec<(KeyPath, String)>,
) -> Result<Option<f32>, Failure> {
    let cutoff = match m.alpha_mode.as_deref() {
        None | Some("OPAQUE") => return Ok(None),
        Some("MASK") => {
            let cutoff = m.alpha_cutoff.unwrap_or(0.5);
            if !(cutoff >= 0.0 && cutoff.is_finite()) {
                return Err(Failure::at(
                    at.key("alphaCutoff"),
                    format!("expected a number >= 0, found {cutoff}"),
                ));
            }
            cutoff
        }
        Some("BLEND") => {
            let named = match &m.name {
                Some(name) => format!("material {name:?}: "),
                None => String::new(),
            };
            warnings.push((
                at.key("alphaMode"),
                format!("{named}BLEND is read as MASK with alphaCutoff 0.5: the surface is there where its alpha is at least 0.5 and cut out elsewhere (a path tracer has nothing to blend; for glass use KHR_materials_transmission)"),
            ));
            0.5
        }
        Some(other) => {
            return Err(Failure::at(
                at.key("alphaMode"),
                format!("expected \"OPAQUE\", \"MASK\" or \"BLEND\", found {other:?}"),
            ))
        }
    };
    let factor = m.pbr_metallic_roughness.base_color_factor[3];
    Ok(match (cutoff > 0.0, factor > 0.0) {
        (false, _) => None,
        (true, true) => Some(cutoff / factor),
        // A factor of 0 leaves no alpha at the cutoff: all of it is cut.
        (true, false) => Some(f32::INFINITY),
    })
}

/// A textureInfo's index, texCoord and transform.
fn info(t: &doc::TextureInfo) -> (usize, u32, Option<&doc::TextureTransform>) {
    (t.index, t.tex_coord, t.extensions.transform.as_ref())
}

/// Values that must be fractions (0 to 1), as glTF's factors are.
fn fractions(at: &KeyPath, values: &[f32]) -> Result<(), Failure> {
    match values.iter().find(|x| !(0.0..=1.0).contains(*x)) {
        Some(x) => Err(Failure::at(
            at.clone(),
            format!("expected numbers from 0 to 1, found {x}"),
        )),
        None => Ok(()),
    }
}

/// The images of one file's textures, each read and decoded once.
pub(crate) struct Textures<'a> {
    doc: &'a Document,
    buffers: &'a [Vec<u8>],
    base: &'a Path,
    source: &'a dyn Source,
    cache: &'a mut ImageCache,
    file: &'a Path,
    /// By image index.
    read: HashMap<usize, Arc<ImageData>>,
}

impl<'a> Textures<'a> {
    pub(crate) fn new(
        doc: &'a Document,
        buffers: &'a [Vec<u8>],
        base: &'a Path,
        source: &'a dyn Source,
        cache: &'a mut ImageCache,
        file: &'a Path,
    ) -> Self {
        Textures {
            doc,
            buffers,
            base,
            source,
            cache,
            file,
            read: HashMap::new(),
        }
    }

    /// The texture of a textureInfo at `at`: (index, texCoord, its
    /// KHR_texture_transform), with its image and sampler.
    fn texture(
        &mut self,
        (index, tex_coord, transform): (usize, u32, Option<&doc::TextureTransform>),
        at: &KeyPath,
        warnings: &mut Vec<(KeyPath, String)>,
    ) -> Result<Option<TextureRef>, Failure> {
        let texture = listed(&self.doc.textures, "textures", index, &at.key("index"))?;
        let coord = transform.and_then(|t| t.tex_coord).unwrap_or(tex_coord);
        if coord != 0 {
            warnings.push((
                at.key("texCoord"),
                format!("the texture reads TEXCOORD_{coord}; only TEXCOORD_0 is read, so it is left out"),
            ));
            return Ok(None);
        }
        let texture_at = KeyPath::root().key("textures").index(index);
        let Some(source) = texture.source else {
            warnings.push((
                texture_at.key("source"),
                "the texture has no image (`source`), or only one in an extension not read; left out".to_string(),
            ));
            return Ok(None);
        };
        let data = self.image(source, &texture_at.key("source"))?;
        let (wrap, wrap_v) = self.wrap(texture.sampler, &texture_at.key("sampler"))?;
        let (scale, rotate, offset) = match transform {
            Some(t) => uv_transform(t, &at.key("extensions").key("KHR_texture_transform"))?,
            None => ([1.0; 2], 0.0, [0.0; 2]),
        };
        Ok(Some(TextureRef::Image(ImageTexture {
            image: format!("images[{source}]"),
            scale: TextureScale::PerAxis(scale),
            wrap,
            wrap_v: (wrap_v != wrap).then_some(wrap_v),
            rotate,
            offset,
            data: Some(data),
        })))
    }

    /// The sampler's wrap modes along u and v.
    fn wrap(&self, sampler: Option<usize>, at: &KeyPath) -> Result<(Wrap, Wrap), Failure> {
        let Some(s) = sampler else {
            return Ok((Wrap::Repeat, Wrap::Repeat));
        };
        let sampler = listed(&self.doc.samplers, "samplers", s, at)?;
        let at = KeyPath::root().key("samplers").index(s);
        let mode = |value: u32, key: &str| {
            match value {
            doc::REPEAT => Ok(Wrap::Repeat),
            doc::CLAMP_TO_EDGE => Ok(Wrap::Clamp),
            doc::MIRRORED_REPEAT => Ok(Wrap::Mirror),
            other => Err(Failure::at(
                at.key(key),
                format!("expected 10497 (REPEAT), 33071 (CLAMP_TO_EDGE) or 33648 (MIRRORED_REPEAT), found {other}"),
            )),
        }
        };
        Ok((
            mode(sampler.wrap_s, "wrapS")?,
            mode(sampler.wrap_t, "wrapT")?,
        ))
    }

    /// Image `index`, read and decoded once.
    fn image(&mut self, index: usize, at: &KeyPath) -> Result<Arc<ImageData>, Failure> {
        if let Some(data) = self.read.get(&index) {
            return Ok(data.clone());
        }
        let image = listed(&self.doc.images, "images", index, at)?;
        let at = KeyPath::root().key("images").index(index);
        let data = match (&image.uri, image.buffer_view) {
            (Some(uri), _) if !uri.starts_with("data:") => {
                let name =
                    buffers::percent_decoded(uri).map_err(|m| Failure::at(at.key("uri"), m))?;
                if name.contains("://") {
                    let m = format!("cannot read `{uri}`: only files beside the glTF file and data URIs are read, nothing from the network");
                    return Err(Failure::at(at.key("uri"), m));
                }
                let path = self.base.join(&name);
                self.cache
                    .get(self.source, &path)
                    .map_err(|m| Failure::at(at.key("uri"), format!("cannot load `{name}`: {m}")))?
            }
            (Some(uri), _) => {
                let (bytes, _) = buffers::read_uri(uri, self.base, self.source, 0)
                    .map_err(|m| Failure::at(at.key("uri"), m))?;
                self.decoded(index, &bytes, &at.key("uri"))?
            }
            (None, Some(view)) => {
                let bytes = self.view_bytes(view, &at.key("bufferView"))?;
                self.decoded(index, bytes, &at.key("bufferView"))?
            }
            (None, None) => {
                return Err(Failure::at(
                    at,
                    "expected a `uri` or a `bufferView` holding the image",
                ))
            }
        };
        self.read.insert(index, data.clone());
        Ok(data)
    }

    /// Image `index`'s bytes (held in the glTF file), decoded; a mistake
    /// placed `at` the key that gave them.
    fn decoded(
        &mut self,
        index: usize,
        bytes: &[u8],
        at: &KeyPath,
    ) -> Result<Arc<ImageData>, Failure> {
        let key = self.file.join(format!("#images[{index}]"));
        self.cache
            .decoded(&key, bytes)
            .map_err(|m| Failure::at(at.clone(), m))
    }

    /// The bytes of buffer view `v`, checked to lie in its buffer.
    fn view_bytes(&self, v: usize, at: &KeyPath) -> Result<&'a [u8], Failure> {
        let doc = self.doc;
        let view = listed(&doc.buffer_views, "bufferViews", v, at)?;
        let buffer_at = KeyPath::root().key("bufferViews").index(v).key("buffer");
        let bytes = listed(self.buffers, "buffers", view.buffer, &buffer_at)?;
        let end = view.byte_offset.checked_add(view.byte_length);
        match end {
            Some(end) if end <= doc.buffers[view.buffer].byte_length => {
                Ok(&bytes[view.byte_offset as usize..end as usize])
            }
            _ => Err(Failure::at(
                KeyPath::root().key("bufferViews").index(v),
                format!(
                    "the view runs from byte {} for {} bytes, past the end of buffers[{}] ({} bytes)",
                    view.byte_offset, view.byte_length, view.buffer, doc.buffers[view.buffer].byte_length
                ),
            )),
        }
    }
}

/// Element `i` of the file's `list`, or a mistake at `at` (the key that
/// names it).
fn listed<'d, T>(items: &'d [T], list: &str, i: usize, at: &KeyPath) -> Result<&'d T, Failure> {
    items
        .get(i)
        .ok_or_else(|| Failure::at(at.clone(), super::nodes::not_an_index(list, i, items.len())))
}

/// `KHR_texture_transform` (offset, counter-clockwise rotation in
/// radians, scale, in glTF's texture space, where v runs down the image)
/// as the scene file's texture keys, in its texture space, where v runs up:
/// (scale, rotate in degrees, offset). With F the flip (u, 1 - v), the
/// glTF transform M g + t read on g = F o becomes R(-theta) S o +
/// F (t + R S (0, 1)) + (0, 1).
fn uv_transform(
    t: &doc::TextureTransform,
    at: &KeyPath,
) -> Result<([f32; 2], f32, [f32; 2]), Failure> {
    let values = [t.offset[0], t.offset[1], t.rotation, t.scale[0], t.scale[1]];
    if !values.iter().all(|x| x.is_finite()) {
        return Err(Failure::at(
            at.clone(),
            format!(
                "expected finite numbers, found offset {:?}, rotation {}, scale {:?}",
                t.offset, t.rotation, t.scale
            ),
        ));
    }
    let (sin, cos) = t.rotation.sin_cos();
    let [_, sy] = t.scale;
    let offset = [t.offset[0] - sin * sy, 1.0 - t.offset[1] - cos * sy];
    Ok((t.scale, -t.rotation.to_degrees(), offset))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point of glTF's texture space through the extension's own
    /// formula (translation * rotation * scale, rotation as its GLSL
    /// writes it), against the scene file's keys on the flipped point.
    #[test]
    fn a_texture_transform_reads_the_same_texel_in_either_space() {
        let t = doc::TextureTransform {
            offset: [0.25, -0.5],
            rotation: 0.4,
            scale: [2.0, 0.5],
            tex_coord: None,
        };
        let (scale, rotate, offset) = uv_transform(&t, &KeyPath::root()).unwrap();
        for g in [[0.0f32, 0.0], [0.3, 0.7], [1.0, 1.0], [-2.0, 0.5]] {
            let (s, c) = t.rotation.sin_cos();
            let (x, y) = (g[0] * t.scale[0], g[1] * t.scale[1]);
            let gltf = [c * x - s * y + t.offset[0], s * x + c * y + t.offset[1]];
            // The same point in the tracer's space, through its keys.
            let o = [g[0], 1.0 - g[1]];
            let (x, y) = (o[0] * scale[0], o[1] * scale[1]);
            let (s, c) = rotate.to_radians().sin_cos();
            let ours = [c * x - s * y + offset[0], s * x + c * y + offset[1]];
            assert!((ours[0] - gltf[0]).abs() < 1e-5, "{g:?}: {ours:?} {gltf:?}");
            assert!(
                (ours[1] - (1.0 - gltf[1])).abs() < 1e-5,
                "{g:?}: {ours:?} {gltf:?}"
            );
        }
    }
}
