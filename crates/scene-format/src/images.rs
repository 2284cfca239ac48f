//! Image textures: PNG and JPEG files read at load time, like OBJ files,
//! each file once however many textures name it.

use crate::diagnostic::Diagnostic;
use crate::key_path::KeyPath;
use crate::model::{ImageData, Material, Object, Texels, TextureRef};
use crate::source::{Folder, Source};
use std::collections::{BTreeMap, HashMap};
use std::io::Cursor;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Largest image file read.
pub const MAX_IMAGE_BYTES: u64 = crate::read::MAX_OBJ_BYTES / 4;
/// Largest image side decoded: four times the largest image rendered.
const MAX_IMAGE_SIDE: u32 = 4 * crate::validate::MAX_IMAGE_SIDE;
/// Most memory the decoder may take for one image.
const MAX_DECODE_BYTES: u64 = 2 << 30;
/// Most texels a texture image may have: 8192 x 8192, 201 MB as the bytes
/// of an 8-bit image, 805 MB as the floats of a 16-bit one. Counted from
/// the header before decoding: a small PNG may claim 40000 x 40000 of one
/// grey byte each, whose floats alone would take 19 GB.
pub const MAX_TEXTURE_TEXELS: u64 = 1 << 26;

/// Most texels the texture images of one scene may have together: one
/// 8192 x 8192 image, or many smaller ones (each file counted once,
/// however many textures name it). Without it, a packed scene of a few KB
/// naming a few well-compressed 8192 x 8192 PNGs took 1.6 GB for each.
pub const MAX_SCENE_TEXELS: u64 = MAX_TEXTURE_TEXELS;

/// Most texels an environment image may have: 8192 x 4096, a studio HDR's
/// usual size (400 MB as the floats it is kept in).
pub const MAX_ENVIRONMENT_TEXELS: u64 = 1 << 25;

/// Reads the image of `environment` (if it names one) from `source`,
/// relative to `base`: a Radiance HDR or an OpenEXR file, kept as linear
/// floats. A file that cannot be read or decoded, or is too large, gives a
/// diagnostic at `environment.image`.
pub fn load_environment(
    environment: &mut crate::model::Environment,
    base: &Path,
    source: &dyn Source,
) -> Vec<Diagnostic> {
    let Some(name) = environment.image.clone() else {
        return Vec::new();
    };
    let path = KeyPath::root().key("environment").key("image");
    match read_environment(source, &base.join(&name)) {
        Ok(data) => {
            let floats = data.texels.to_floats();
            let brightest = floats.iter().flatten().fold(0.0f32, |a, &b| a.max(b));
            let overflow = crate::validate::environment_overflow(
                brightest,
                environment.strength,
                "its brightest texel",
            );
            environment.data = Some(Arc::new(data));
            let strength = KeyPath::root().key("environment").key("strength");
            overflow
                .map(|m| Diagnostic::new(strength, m))
                .into_iter()
                .collect()
        }
        Err(e) => vec![Diagnostic::new(path, format!("cannot load `{name}`: {e}"))],
    }
}

/// The texels of the HDR or EXR file at `path` of `source`, linear.
fn read_environment(source: &dyn Source, path: &Path) -> Result<ImageData, String> {
    use image::ImageFormat;
    let bytes = source
        .read(path, MAX_IMAGE_BYTES)
        .map_err(|e| e.to_string())?;
    let format = image::guess_format(&bytes).ok();
    if !matches!(format, Some(ImageFormat::Hdr | ImageFormat::OpenExr)) {
        return Err(
            "expected a Radiance .hdr or an OpenEXR .exr image (linear light); the file is neither"
                .to_string(),
        );
    }
    let mut reader = image::ImageReader::new(Cursor::new(&bytes));
    reader.set_format(format.expect("matched above"));
    let (width, height) = reader.into_dimensions().map_err(unreadable)?;
    if width == 0 || height == 0 {
        return Err(format!(
            "{width}x{height} texels: the image is empty; expected at least 1x1"
        ));
    }
    // Counted before decoding: the header's claim decides the memory.
    if u64::from(width) * u64::from(height) > MAX_ENVIRONMENT_TEXELS {
        return Err(format!(
            "{width}x{height} texels; expected at most {MAX_ENVIRONMENT_TEXELS} (8192x4096)"
        ));
    }
    let mut reader = image::ImageReader::new(Cursor::new(&bytes));
    reader.set_format(format.expect("matched above"));
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(MAX_DECODE_BYTES);
    reader.limits(limits);
    let image = reader.decode().map_err(unreadable)?.into_rgb32f();
    let texels = texels_of(image.into_raw());
    if texels.len() as u64 != u64::from(width) * u64::from(height) {
        return Err(format!(
            "{width}x{height} texels in its header, {} decoded; expected as many as it declares",
            texels.len()
        ));
    }
    if texels.iter().flatten().any(|x| !x.is_finite() || *x < 0.0) {
        return Err(
            "has texels that are negative or not finite numbers; expected radiance >= 0"
                .to_string(),
        );
    }
    Ok(ImageData {
        width,
        height,
        texels: Texels::Floats(texels),
        alpha: None,
    })
}

/// Why the decoder could not read an image, as a reader says it: a file
/// that ends early is said to, where the decoder said "failed to fill
/// whole buffer".
pub fn unreadable(e: image::ImageError) -> String {
    match e {
        image::ImageError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            "not a readable image: it ends before the pixels its header declares".to_string()
        }
        e => format!("not a readable image: {e}"),
    }
}

/// Images read so far for one scene, by path (as joined to the folder of
/// the file that names it), or why they could not be; and the texels the
/// scene's budget has left.
#[derive(Debug)]
pub struct ImageCache {
    read: HashMap<PathBuf, Result<Arc<ImageData>, String>>,
    texels_left: u64,
}

impl Default for ImageCache {
    fn default() -> Self {
        ImageCache {
            read: HashMap::new(),
            texels_left: MAX_SCENE_TEXELS,
        }
    }
}

impl ImageCache {
    /// A cache whose scene may read `texels` texels (tests use few).
    pub fn with_budget(texels: u64) -> ImageCache {
        ImageCache {
            texels_left: texels,
            ..ImageCache::default()
        }
    }

    /// The image at `path` of `source`, read on first use, if the scene's
    /// budget has room for its texels.
    pub fn get(&mut self, source: &dyn Source, path: &Path) -> Result<Arc<ImageData>, String> {
        if let Some(read) = self.read.get(path) {
            return read.clone();
        }
        let read = source
            .read(path, MAX_IMAGE_BYTES)
            .map_err(|e| e.to_string())
            .and_then(|bytes| decode(&bytes, self.texels_left))
            .map(Arc::new);
        if let Ok(image) = &read {
            let texels = u64::from(image.width) * u64::from(image.height);
            self.texels_left = self.texels_left.saturating_sub(texels);
        }
        self.read.insert(path.to_path_buf(), read.clone());
        read
    }
}

impl ImageCache {
    /// The image of `bytes` (a glTF file's embedded image), known by
    /// `key` (the file and the image's place in it), decoded once, if the
    /// scene's budget has room for its texels.
    pub fn decoded(&mut self, key: &Path, bytes: &[u8]) -> Result<Arc<ImageData>, String> {
        if let Some(read) = self.read.get(key) {
            return read.clone();
        }
        let read = decode(bytes, self.texels_left).map(Arc::new);
        if let Ok(image) = &read {
            let texels = u64::from(image.width) * u64::from(image.height);
            self.texels_left = self.texels_left.saturating_sub(texels);
        }
        self.read.insert(key.to_path_buf(), read.clone());
        read
    }
}

/// Reads the image of every image texture of one file's materials, inline
/// materials and objects from `source`, relative to `base` (that file's
/// folder). Every image that cannot be read gives a diagnostic at its
/// `texture.image` key, a path within that file.
pub fn load_part_images(
    (materials, objects): (&mut BTreeMap<String, Material>, &mut [Object]),
    base: &Path,
    source: &dyn Source,
    cache: &mut ImageCache,
) -> Vec<Diagnostic> {
    let mut diagnostics = Vec::new();
    let root = KeyPath::root();
    let mut images = (source, cache);
    for (name, m) in materials.iter_mut() {
        let path = root.key("materials").key(name);
        for (key, texture) in textures_of(m) {
            load(texture, path.key(key), base, &mut images, &mut diagnostics);
        }
    }
    for (i, o) in objects.iter_mut().enumerate() {
        let object = root.key("objects").index(i);
        if let Some(crate::MaterialRef::Inline(m)) = o.material.as_mut() {
            let path = object.key("material");
            for (key, texture) in textures_of(m) {
                load(texture, path.key(key), base, &mut images, &mut diagnostics);
            }
        }
        let path = object.key("texture");
        load(
            o.texture.as_mut(),
            path,
            base,
            &mut images,
            &mut diagnostics,
        );
    }
    diagnostics
}

/// A material's texture keys, each with its name.
fn textures_of(m: &mut Material) -> [(&'static str, Option<&mut TextureRef>); 4] {
    [
        ("texture", m.texture.as_mut()),
        (
            "metallic_roughness_texture",
            m.metallic_roughness_texture.as_mut(),
        ),
        ("emission_texture", m.emission_texture.as_mut()),
        ("normal_texture", m.normal_texture.as_mut()),
    ]
}

fn load(
    texture: Option<&mut TextureRef>,
    path: KeyPath,
    base: &Path,
    (source, cache): &mut (&dyn Source, &mut ImageCache),
    diagnostics: &mut Vec<Diagnostic>,
) {
    let Some(TextureRef::Image(image)) = texture else {
        return;
    };
    match cache.get(*source, &base.join(&image.image)) {
        Ok(data) => image.data = Some(data),
        Err(message) => diagnostics.push(Diagnostic::new(
            path.key("image"),
            format!("cannot load `{}`: {message}", image.image),
        )),
    }
}

/// The texels of the PNG or JPEG file at `path`.
pub fn read_image(path: &Path) -> Result<ImageData, String> {
    read_image_from(&Folder::new(), path)
}

/// [`read_image`] from `source`.
pub fn read_image_from(source: &dyn Source, path: &Path) -> Result<ImageData, String> {
    let bytes = source
        .read(path, MAX_IMAGE_BYTES)
        .map_err(|e| e.to_string())?;
    decode(&bytes, MAX_SCENE_TEXELS)
}

/// PNG or JPEG bytes as texels, told apart by their content, if they are
/// at most `texels_left` (what the scene's budget has left).
fn decode(bytes: &[u8], texels_left: u64) -> Result<ImageData, String> {
    use image::ImageFormat;
    let format = image::guess_format(bytes).ok();
    if !matches!(format, Some(ImageFormat::Png | ImageFormat::Jpeg)) {
        return Err("expected a PNG or JPEG image; the file is neither".to_string());
    }
    let format = format.expect("matched above");
    let reader = || {
        let mut reader = image::ImageReader::new(Cursor::new(bytes));
        reader.set_format(format);
        reader
    };
    let (width, height) = reader().into_dimensions().map_err(unreadable)?;
    if width == 0 || height == 0 {
        return Err(format!(
            "{width}x{height} texels: the image is empty; expected at least 1x1"
        ));
    }
    let texels = u64::from(width) * u64::from(height);
    if texels > MAX_TEXTURE_TEXELS {
        return Err(format!(
            "{width}x{height} texels; expected at most {MAX_TEXTURE_TEXELS} (8192x8192)"
        ));
    }
    if texels > texels_left {
        return Err(format!(
            "{width}x{height} texels, more than the {texels_left} left of the {MAX_SCENE_TEXELS} (8192x8192) the texture images of one scene may have together"
        ));
    }
    let mut reader = reader();
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_IMAGE_SIDE);
    limits.max_image_height = Some(MAX_IMAGE_SIDE);
    limits.max_alloc = Some(MAX_DECODE_BYTES);
    reader.limits(limits);
    let image = reader.decode().map_err(unreadable)?;
    let (width, height) = (image.width(), image.height());
    let alpha = alpha_of(&image).map(Arc::new);
    // 8-bit images keep their bytes; others become floats (the decoded
    // samples go before the floats are made).
    let eight_bit = matches!(
        image.color(),
        image::ColorType::L8
            | image::ColorType::La8
            | image::ColorType::Rgb8
            | image::ColorType::Rgba8
    );
    let texels = if eight_bit {
        Texels::Bytes(std::sync::Arc::new(texels_of(image.into_rgb8().into_raw())))
    } else {
        Texels::Floats(texels_of(image.into_rgb32f().into_raw()))
    };
    Ok(ImageData {
        width,
        height,
        texels,
        alpha,
    })
}

/// The alpha channel of `image` as bytes (a 16-bit or float alpha rounded
/// to 8 bits), row by row; None without one, or where every texel is
/// opaque (nothing to cut: no memory spent on it).
fn alpha_of(image: &image::DynamicImage) -> Option<Vec<u8>> {
    use image::DynamicImage as D;
    let to_byte = |a: f32| (a.clamp(0.0, 1.0) * 255.0).round() as u8;
    let alpha: Vec<u8> = match image {
        D::ImageLumaA8(i) => i.pixels().map(|p| p.0[1]).collect(),
        D::ImageRgba8(i) => i.pixels().map(|p| p.0[3]).collect(),
        D::ImageLumaA16(i) => i
            .pixels()
            .map(|p| to_byte(f32::from(p.0[1]) / 65535.0))
            .collect(),
        D::ImageRgba16(i) => i
            .pixels()
            .map(|p| to_byte(f32::from(p.0[3]) / 65535.0))
            .collect(),
        D::ImageRgba32F(i) => i.pixels().map(|p| to_byte(p.0[3])).collect(),
        _ => return None,
    };
    alpha.iter().any(|&a| a < 255).then_some(alpha)
}

/// Interleaved RGB samples as texels, in the same memory (a copy only if
/// the allocation cannot be taken over): the float texels of an 8192 x
/// 8192 image are 805 MB, and a copy doubled that at its peak.
fn texels_of<T: bytemuck::Pod>(samples: Vec<T>) -> Vec<[T; 3]> {
    bytemuck::allocation::try_cast_vec(samples).unwrap_or_else(|(_, samples)| {
        samples
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(width: u32, height: u32, pixels: &[u8]) -> Vec<u8> {
        let img = image::RgbImage::from_raw(width, height, pixels.to_vec()).unwrap();
        let mut bytes = Vec::new();
        img.write_to(&mut Cursor::new(&mut bytes), image::ImageFormat::Png)
            .unwrap();
        bytes
    }

    #[test]
    fn png_texels_are_read_row_by_row_from_the_top_as_stored() {
        let bytes = png(2, 2, &[0, 51, 255, 255, 0, 0, 1, 2, 3, 102, 204, 153]);
        let data = decode(&bytes, MAX_SCENE_TEXELS).unwrap();
        assert_eq!((data.width, data.height), (2, 2));
        assert_eq!(data.texels.at(0), [0.0, 0.2, 1.0]);
        assert_eq!(data.texels.at(1), [1.0, 0.0, 0.0]);
        assert_eq!(data.texels.at(3), [0.4, 0.8, 0.6]);
        // An 8-bit image keeps its bytes, a quarter of the floats' memory.
        assert!(matches!(data.texels, Texels::Bytes(_)));
    }

    fn png_rgba(width: u32, height: u32, pixels: &[u8]) -> Vec<u8> {
        let img = image::RgbaImage::from_raw(width, height, pixels.to_vec()).unwrap();
        let mut bytes = Vec::new();
        img.write_to(&mut Cursor::new(&mut bytes), image::ImageFormat::Png)
            .unwrap();
        bytes
    }

    #[test]
    fn alpha_is_kept_where_some_texel_is_not_opaque() {
        let pixels = [10, 20, 30, 0, 40, 50, 60, 128, 1, 2, 3, 255, 4, 5, 6, 254];
        let data = decode(&png_rgba(2, 2, &pixels), MAX_SCENE_TEXELS).unwrap();
        assert_eq!(data.alpha.as_deref(), Some(&vec![0, 128, 255, 254]));
        assert_eq!(
            data.texels.at(1),
            [40.0 / 255.0, 50.0 / 255.0, 60.0 / 255.0]
        );
        // Opaque everywhere, or without an alpha channel: nothing kept.
        let opaque = pixels.map(|_| 255);
        let data = decode(&png_rgba(2, 2, &opaque), MAX_SCENE_TEXELS).unwrap();
        assert_eq!(data.alpha, None);
        let data = decode(&png(1, 1, &[1, 2, 3]), MAX_SCENE_TEXELS).unwrap();
        assert_eq!(data.alpha, None);
    }

    /// The start of a PNG (signature and header) of `width` x `height`
    /// grey bytes, its pixels left out.
    fn png_header(width: u32, height: u32) -> Vec<u8> {
        let mut chunk = b"IHDR".to_vec();
        chunk.extend(width.to_be_bytes());
        chunk.extend(height.to_be_bytes());
        chunk.extend([8, 0, 0, 0, 0]);
        let mut bytes = b"\x89PNG\r\n\x1a\n".to_vec();
        bytes.extend(13u32.to_be_bytes());
        bytes.extend(&chunk);
        bytes.extend(crc32(&chunk).to_be_bytes());
        // An empty IDAT: the decoder reads the header up to the first.
        bytes.extend(0u32.to_be_bytes());
        bytes.extend(b"IDAT");
        bytes.extend(crc32(b"IDAT").to_be_bytes());
        bytes
    }

    fn crc32(bytes: &[u8]) -> u32 {
        let mut crc = !0u32;
        for &b in bytes {
            crc ^= u32::from(b);
            for _ in 0..8 {
                crc = if crc & 1 == 1 {
                    (crc >> 1) ^ 0xEDB8_8320
                } else {
                    crc >> 1
                };
            }
        }
        !crc
    }

    #[test]
    fn the_cap_counts_the_texels_kept_before_decoding() {
        // 40000 x 40000 grey passes the decoder's memory limit (1.6 GB)
        // but would take 19 GB as floats; 16384 x 16384 would take 3.2 GB.
        for (width, height) in [(40000, 40000), (16384, 16384), (8193, 8192)] {
            let error = decode(&png_header(width, height), MAX_SCENE_TEXELS).unwrap_err();
            let expected = format!("{width}x{height} texels; expected at most 67108864");
            assert!(error.starts_with(&expected), "{error}");
        }
        // At the cap the header is read on: its missing pixels are the fault.
        let error = decode(&png_header(8192, 8192), MAX_SCENE_TEXELS).unwrap_err();
        assert!(error.contains("not a readable image"), "{error}");
    }

    #[test]
    fn other_files_are_refused_with_a_reason() {
        let bad = decode(b"P6 1 1 255 abc", MAX_SCENE_TEXELS).unwrap_err();
        assert!(bad.contains("expected a PNG or JPEG"), "{bad}");
        // A PNG signature followed by garbage.
        let truncated = png(2, 2, &[0; 12])[..20].to_vec();
        assert!(decode(&truncated, MAX_SCENE_TEXELS)
            .unwrap_err()
            .contains("not a readable image"));
        let dir = tempfile::tempdir().unwrap();
        let missing = read_image(&dir.path().join("none.png")).unwrap_err();
        assert!(missing.contains("No such file"), "{missing}");
    }

    #[test]
    fn the_images_of_a_scene_share_one_budget_of_texels() {
        let dir = tempfile::tempdir().unwrap();
        let write = |name: &str| {
            let path = dir.path().join(name);
            std::fs::write(&path, png(4, 4, &[128; 48])).unwrap();
            path
        };
        let (a, b) = (write("a.png"), write("b.png"));
        let mut cache = ImageCache::with_budget(20);
        let folder = Folder::new();
        assert!(cache.get(&folder, &a).is_ok());
        // The same file again costs nothing more.
        assert!(cache.get(&folder, &a).is_ok());
        let refused = cache.get(&folder, &b).unwrap_err();
        assert!(
            refused.contains("4x4 texels, more than the 4 left of the"),
            "{refused}"
        );
    }

    #[test]
    fn texels_take_over_the_decoded_floats() {
        let floats = vec![0.0, 0.5, 1.0, 0.25, 0.75, 2.0];
        let at = floats.as_ptr();
        let texels = texels_of(floats);
        assert_eq!(texels, [[0.0, 0.5, 1.0], [0.25, 0.75, 2.0]]);
        assert_eq!(texels.as_ptr().cast::<f32>(), at, "no copy");
    }

    #[test]
    fn an_image_cut_short_is_said_to_end_before_its_pixels() {
        let whole = png(8, 8, &[77; 192]);
        let error = decode(&whole[..whole.len() - 40], MAX_SCENE_TEXELS).unwrap_err();
        assert!(
            error.contains("ends before the pixels its header declares"),
            "{error}"
        );
    }
}
