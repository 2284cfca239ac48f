//! Render-farm tiles: a part of an image rendered by one task, written as
//! an OpenEXR file whose data window is the part and whose display window
//! is the whole image, with the scene's digest and the display encoding in
//! its header; and the merge of such tiles into the whole image.
//!
//! Only EXR tiles are merged: a PNG of a region holds encoded 8-bit
//! values, from which neither the float file nor (after a gamma) the exact
//! PNG of the whole render could be remade.

use crate::denoise::{Guides, Prefilter, Quality, Settings};
use crate::load::{Input, Loaded};
use crate::options::{tile_region, Options, Region};
use crate::rendered::Picture;
use exr::prelude::traits::{ReadChannels, ReadLayers, WritableImage};
use exr::prelude::{
    AttributeValue, ChannelDescription, Encoding as ExrEncoding, Image, IntegerBounds, Layer,
    LayerAttributes, SpecificChannels, Text, Vec2,
};
use std::io::Read;
use std::path::{Path, PathBuf};
use tracer_core::image::{Encoding, LinearImage, Saturation};

/// Header attributes of a tile (`tracer:` keeps them apart from others').
const DIGEST: &str = "tracer:digest";
const GAMMA: &str = "tracer:gamma";
const SATURATION: &str = "tracer:saturation";
/// "I/N" for a tile made with `--tile`, to name a missing one.
const TILE: &str = "tracer:tile";
/// BLAKE3 of the other attributes, the windows and the pixels, written
/// with them: a tile flipped, cut or edited after it was written fails it.
const CHECKSUM: &str = "tracer:checksum";
/// Largest tile file read: the floats of the largest image, uncompressed.
const MAX_TILE_BYTES: u64 = 4 << 30;

/// Why tiles could not be read or merged; each names the file at fault.
#[derive(Debug, thiserror::Error)]
pub enum TileError {
    /// (`error`, not `source`: the message holds it, and a source would
    /// be printed a second time after it.)
    #[error("{}: cannot read it: {error}", path.display())]
    Read {
        path: PathBuf,
        error: std::io::Error,
    },
    #[error("{}: not a tile of `tracer render --tile/--region -o TILE.exr`: {reason}", path.display())]
    NotATile { path: PathBuf, reason: String },
    #[error("{}: the tile is damaged: {reason}", path.display())]
    Damaged { path: PathBuf, reason: String },
    #[error("{}: a tile of a {}x{} image, not of the {}x{} image of {} (the same digest: edited?)", path.display(), size.0, size.1, expected.0, expected.1, first.display())]
    OtherSize {
        path: PathBuf,
        size: (u32, u32),
        first: PathBuf,
        expected: (u32, u32),
    },
    #[error("{}: a tile of another scene or other render options (digest {}...), not of the {others} other tile{} (digest {}...)", path.display(), start(digest), if *others == 1 { "" } else { "s" }, start(expected))]
    Foreign {
        path: PathBuf,
        digest: String,
        expected: String,
        others: usize,
    },
    #[error("{}: overlaps {} (both hold pixel ({x}, {y})); every pixel must be in exactly one tile", path.display(), other.display())]
    Overlap {
        path: PathBuf,
        other: PathBuf,
        x: u32,
        y: u32,
    },
    #[error("missing {what}: no tile given holds pixel ({x}, {y}) of the {width}x{height} image")]
    Missing {
        what: String,
        x: u32,
        y: u32,
        width: u32,
        height: u32,
    },
    #[error("cannot encode the tile as OpenEXR: {0}")]
    Encode(String),
    /// `tracer merge --denoise` of tiles without the denoiser's guides.
    #[error("--denoise: the tiles carry no albedo and normal for the denoiser; render them with `tracer render --denoise --tile I/N -o TILE.exr`")]
    NoGuides,
    /// `--skip-existing` without an EXR tile to compare with.
    #[error("--skip-existing: only for tiles (--tile or --region with an .exr output), which carry the scene's digest")]
    SkipWithoutTile,
}

impl TileError {
    /// Whether the user gave a wrong tile (exit 2) rather than the machine failing.
    pub fn is_bad_input(&self) -> bool {
        match self {
            TileError::Read { error, .. } => matches!(
                error.kind(),
                std::io::ErrorKind::NotFound
                    | std::io::ErrorKind::PermissionDenied
                    | std::io::ErrorKind::InvalidInput
            ),
            TileError::Encode(_) => false,
            _ => true,
        }
    }
}

/// What makes two tiles parts of one image: BLAKE3, in hex, of the
/// bytes of every file the scene read (the scene file, included files,
/// meshes, textures; the archive of a packed scene; the built-in scene's
/// text), and of the render options (samples, size, gamma, AOV) but not the
/// part; and of the tracer's version. Paths are left out, so tasks may
/// see the scene at other paths. (BLAKE3, not SHA-256: every task hashes
/// its meshes again, and BLAKE3 takes a third of the time.)
pub fn digest(input: &Input, loaded: &Loaded, options: &Options) -> Result<String, TileError> {
    let size = crate::image_size(loaded, options).unwrap_or_default();
    digest_of(input, &loaded.files_read, options, size)
}

/// `digest` of a scene read from `files_read`, its image `size` pixels
/// with `options` (a scene prepared earlier and kept: `cache`).
pub(crate) fn digest_of(
    input: &Input,
    files_read: &[PathBuf],
    options: &Options,
    size: (u32, u32),
) -> Result<String, TileError> {
    let mut hash = blake3::Hasher::new();
    // Another release may render other values: its tiles do not mix.
    let version = concat!("tracer tile 3, version ", env!("CARGO_PKG_VERSION"));
    add(&mut hash, version.as_bytes());
    if *input == Input::DefaultScene {
        add(&mut hash, crate::load::DEFAULT_SCENE.as_bytes());
    }
    for path in files_read {
        add_file(&mut hash, path).map_err(|error| TileError::Read {
            path: path.clone(),
            error,
        })?;
    }
    let options = Options {
        part: None,
        ..*options
    };
    add(&mut hash, format!("{options:?}").as_bytes());
    add(&mut hash, format!("{size:?}").as_bytes());
    Ok(hash.finalize().to_hex().to_string())
}

/// Bytes after their count, so no two sequences hash alike.
pub(crate) fn add(hash: &mut blake3::Hasher, bytes: &[u8]) {
    hash.update(&(bytes.len() as u64).to_le_bytes());
    hash.update(bytes);
}

/// A file's bytes after their count, as `add`, streamed in blocks large
/// enough for BLAKE3's SIMD lanes (a mesh is not held in memory twice).
pub(crate) fn add_file(hash: &mut blake3::Hasher, path: &Path) -> std::io::Result<()> {
    let mut file = std::fs::File::open(path)?;
    let size = file.metadata()?.len();
    hash.update(&size.to_le_bytes());
    let mut block = vec![0u8; 1 << 16];
    let mut total = 0u64;
    loop {
        let n = file.read(&mut block)?;
        if n == 0 {
            break;
        }
        hash.update(&block[..n]);
        total += n as u64;
    }
    if total != size {
        return Err(std::io::Error::other("it changed while it was read"));
    }
    Ok(())
}

/// The names of a tile's layers when it carries the denoiser's guides (a
/// multi-part EXR names every part): the colour first, as a reader of the
/// first layer expects.
const COLOUR_LAYER: &str = "colour";
const ALBEDO_LAYER: &str = "albedo";
const NORMAL_LAYER: &str = "normal";
const EMISSION_LAYER: &str = "emission";
/// The denoiser's quality the tile was rendered for, with its guides.
const DENOISE: &str = "tracer:denoise";
/// Its prefilter (a tile without it, of an earlier tracer: "accurate").
const PREFILTER: &str = "tracer:denoise-prefilter";

/// A tile as read from its file.
#[derive(Debug, Clone)]
pub struct Tile {
    pub digest: String,
    /// The whole image's size.
    pub size: (u32, u32),
    pub region: Region,
    /// The region's linear values, row by row.
    pub linear: LinearImage,
    /// How 8-bit outputs of the merged image are encoded.
    pub encoding: Encoding,
    /// `(index, count)` of `--tile`.
    pub tile: Option<(u32, u32)>,
    /// The denoiser's guides of the region and its settings, when the
    /// render was to be denoised (`--denoise`).
    pub guides: Option<(Guides, Settings)>,
}

/// The bytes of the EXR file of `picture`, the `region` of an image of
/// `size`: linear f32 values, lossless; with `guides`, the denoiser's
/// albedo, normal and emission as three more layers.
pub fn encode(
    picture: &Picture,
    region: Region,
    size: (u32, u32),
    digest: &str,
    tile: Option<(u32, u32)>,
    guides: Option<(&Guides, Settings)>,
) -> Result<Vec<u8>, TileError> {
    let linear = &picture.linear;
    let position = Vec2(region.x0 as i32, region.y0 as i32);
    let named = |name: Option<&str>| LayerAttributes {
        layer_position: position,
        layer_name: name.map(Text::from),
        ..LayerAttributes::default()
    };
    let mut attributes = named(guides.map(|_| COLOUR_LAYER));
    let mut put =
        |key: &str, value: AttributeValue| attributes.other.insert(Text::from(key), value);
    put(DIGEST, AttributeValue::Text(Text::from(digest)));
    put(GAMMA, AttributeValue::F32(picture.encoding.gamma));
    let saturation = match picture.encoding.saturation {
        Saturation::White => "white",
        Saturation::Clamp => "clamp",
    };
    put(SATURATION, AttributeValue::Text(Text::from(saturation)));
    if let Some((index, count)) = tile {
        put(
            TILE,
            AttributeValue::Text(Text::from(format!("{index}/{count}").as_str())),
        );
    }
    if let Some((_, settings)) = guides {
        let name = |n: &str| AttributeValue::Text(Text::from(n));
        put(DENOISE, name(settings.quality.name()));
        put(PREFILTER, name(settings.prefilter.name()));
    }
    let guide_images = guides.map(|(g, _)| [&g.albedo, &g.normal, &g.emission]);
    let sum = checksum(
        digest,
        &picture.encoding,
        tile,
        (region, size),
        linear,
        guide_images,
    );
    put(CHECKSUM, AttributeValue::Text(Text::from(sum.as_str())));
    let mut layers = vec![rgb_layer(attributes, linear)];
    if let Some([albedo, normal, emission]) = guide_images {
        layers.push(rgb_layer(named(Some(ALBEDO_LAYER)), albedo));
        layers.push(rgb_layer(named(Some(NORMAL_LAYER)), normal));
        layers.push(rgb_layer(named(Some(EMISSION_LAYER)), emission));
    }
    let display = IntegerBounds::from_dimensions((size.0 as usize, size.1 as usize));
    let image = Image::from_layers(exr::prelude::ImageAttributes::new(display), layers);
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write()
        .non_parallel()
        .to_buffered(&mut bytes)
        .map_err(|e| TileError::Encode(e.to_string()))?;
    Ok(bytes.into_inner())
}

/// The EXR layer of `image`: lossless RGB floats (one function makes every
/// layer, so they are of one type).
#[allow(clippy::type_complexity)]
fn rgb_layer(
    attributes: LayerAttributes,
    image: &LinearImage,
) -> Layer<
    SpecificChannels<
        impl Fn(Vec2<usize>) -> (f32, f32, f32) + Sync + '_,
        (ChannelDescription, ChannelDescription, ChannelDescription),
    >,
> {
    let width = image.width as usize;
    Layer::new(
        (width, image.height as usize),
        attributes,
        ExrEncoding::FAST_LOSSLESS,
        SpecificChannels::rgb(move |p: Vec2<usize>| {
            let c = image.pixels[p.y() * width + p.x()];
            (c.x, c.y, c.z)
        }),
    )
}

/// BLAKE3, in hex, of what a tile says: its digest, encoding, tile number,
/// region, image size and pixels (their f32 bits, little-endian), then its
/// guides' pixels if it has them.
fn checksum(
    digest: &str,
    encoding: &Encoding,
    tile: Option<(u32, u32)>,
    (region, size): (Region, (u32, u32)),
    linear: &LinearImage,
    guides: Option<[&LinearImage; 3]>,
) -> String {
    let mut hash = blake3::Hasher::new();
    add(&mut hash, digest.as_bytes());
    let saturation = matches!(encoding.saturation, Saturation::White);
    let said = format!(
        "{} {saturation} {tile:?} {region:?} {size:?} {}x{}",
        encoding.gamma.to_bits(),
        linear.width,
        linear.height
    );
    add(&mut hash, said.as_bytes());
    let images = std::iter::once(linear).chain(guides.into_iter().flatten());
    for c in images.flat_map(|image| &image.pixels) {
        for x in c.to_array() {
            hash.update(&x.to_le_bytes());
        }
    }
    hash.finalize().to_hex().to_string()
}

/// Reads the tile at `path`: a regular file of bounded size, its windows
/// checked before any pixel is allocated, its checksum and pixels after.
pub fn read(path: &Path) -> Result<Tile, TileError> {
    let bytes =
        scene_format::read::read_capped(path, MAX_TILE_BYTES).map_err(|error| TileError::Read {
            path: path.to_path_buf(),
            error,
        })?;
    let not_a_tile = |reason: String| TileError::NotATile {
        path: path.to_path_buf(),
        reason,
    };
    check_windows(&bytes).map_err(not_a_tile)?;
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |size: Vec2<usize>, _: &_| LinearImage::new(size.width() as u32, size.height() as u32),
            |image: &mut LinearImage, p: Vec2<usize>, (r, g, b): (f32, f32, f32)| {
                let i = p.y() * image.width as usize + p.x();
                image.pixels[i] = glam::Vec3::new(r, g, b);
            },
        )
        .all_layers()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(|e| not_a_tile(format!("not an RGB OpenEXR file ({e})")))?;
    let mut layers = image.layer_data.into_iter();
    let main = layers
        .next()
        .ok_or_else(|| not_a_tile("no layer".to_string()))?;
    let mut named: Vec<_> = layers
        .map(|l| {
            (
                l.attributes.layer_name.as_ref().map(Text::to_string),
                l.channel_data.pixels,
            )
        })
        .collect();
    let mut take = |name: &str| {
        let at = named.iter().position(|(n, _)| n.as_deref() == Some(name))?;
        Some(named.swap_remove(at).1)
    };
    let guide_layers = [ALBEDO_LAYER, NORMAL_LAYER, EMISSION_LAYER].map(&mut take);
    let other = &main.attributes.other;
    let text = |key: &str| match other.get(&Text::from(key)) {
        Some(AttributeValue::Text(t)) => Some(t.to_string()),
        _ => None,
    };
    let digest = text(DIGEST).ok_or_else(|| not_a_tile(format!("no `{DIGEST}` attribute")))?;
    let gamma = match other.get(&Text::from(GAMMA)) {
        Some(AttributeValue::F32(g)) if g.is_finite() && *g > 0.0 => *g,
        Some(_) => return Err(not_a_tile(format!("its `{GAMMA}` is not a number > 0"))),
        _ => return Err(not_a_tile(format!("no `{GAMMA}` attribute"))),
    };
    let saturation = match text(SATURATION).as_deref() {
        Some("white") => Saturation::White,
        Some("clamp") => Saturation::Clamp,
        _ => return Err(not_a_tile(format!("no `{SATURATION}` attribute"))),
    };
    let sum = text(CHECKSUM).ok_or_else(|| {
        not_a_tile(format!(
            "no `{CHECKSUM}` attribute (a tile of an older tracer: render it again)"
        ))
    })?;
    let tile = text(TILE).and_then(|t| {
        let (i, n) = t.split_once('/')?;
        Some((i.parse().ok()?, n.parse().ok()?))
    });
    let quality = match text(DENOISE).as_deref() {
        None => None,
        Some(name) => Some(
            by_name(Quality::ALL, Quality::name, name)
                .ok_or_else(|| not_a_tile(format!("its `{DENOISE}` is not a quality")))?,
        ),
    };
    let prefilter = match text(PREFILTER).as_deref() {
        None => Prefilter::default(),
        Some(name) => by_name(Prefilter::ALL, Prefilter::name, name)
            .ok_or_else(|| not_a_tile(format!("its `{PREFILTER}` is not a prefilter")))?,
    };
    let settings = quality.map(|quality| Settings { quality, prefilter });
    let display = image.attributes.display_window;
    let position = main.attributes.layer_position;
    let linear = main.channel_data.pixels;
    let size = (display.size.width() as u32, display.size.height() as u32);
    let region = Region {
        x0: position.x().max(0) as u32,
        y0: position.y().max(0) as u32,
        x1: position.x().max(0) as u32 + linear.width,
        y1: position.y().max(0) as u32 + linear.height,
    };
    let inside = display.position == Vec2(0, 0)
        && position.x() >= 0
        && position.y() >= 0
        && region.x1 <= size.0
        && region.y1 <= size.1;
    if !inside {
        return Err(not_a_tile(
            "its data window leaves its display window".to_string(),
        ));
    }
    let encoding = Encoding { gamma, saturation };
    let damaged = |reason: &str| TileError::Damaged {
        path: path.to_path_buf(),
        reason: reason.to_string(),
    };
    let guides = match (guide_layers, settings) {
        ([Some(albedo), Some(normal), Some(emission)], Some(settings)) => {
            let guides = Guides {
                albedo,
                normal,
                emission,
            };
            Some((guides, settings))
        }
        ([None, None, None], None) => None,
        _ => return Err(damaged(
            "it has some of the denoiser's guides but not all (albedo, normal and emission; a tile of an older tracer has no emission: render it again)",
        )),
    };
    let guide_images = guides
        .as_ref()
        .map(|(g, _)| [&g.albedo, &g.normal, &g.emission]);
    let sum_now = checksum(
        &digest,
        &encoding,
        tile,
        (region, size),
        &linear,
        guide_images,
    );
    if sum_now != sum {
        return Err(damaged(
            "its pixels or attributes are not those it was written with (its checksum fails)",
        ));
    }
    let sizes_match = guide_images.is_none_or(|images| {
        images
            .iter()
            .all(|i| (i.width, i.height) == (linear.width, linear.height))
    });
    if !sizes_match {
        return Err(damaged("its guides are not the size of its pixels"));
    }
    if linear.pixels.iter().any(|c| !c.is_finite()) {
        return Err(damaged("it holds pixels that are not finite numbers"));
    }
    Ok(Tile {
        digest,
        size,
        region,
        linear,
        encoding,
        tile,
        guides,
    })
}

/// Checks every layer's display and data window against the largest image
/// the tracer renders, from the header alone: a small file may claim a
/// window of 100000 x 100000, whose pixels would take 120 GB.
fn check_windows(bytes: &[u8]) -> Result<(), String> {
    use scene_format::validate::{MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE};
    let meta = exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(bytes), false)
        .map_err(|e| format!("not an RGB OpenEXR file ({e})"))?;
    for header in &meta.headers {
        let display = header.shared_attributes.display_window.size;
        for (what, w, h) in [
            ("display", display.width(), display.height()),
            (
                "data",
                header.layer_size.width(),
                header.layer_size.height(),
            ),
        ] {
            let side = MAX_IMAGE_SIDE as usize;
            if w > side || h > side || (w as u64) * (h as u64) > MAX_IMAGE_PIXELS {
                return Err(format!(
                    "its {what} window is {w}x{h}; expected at most {side} pixels a side and {MAX_IMAGE_PIXELS} in all"
                ));
            }
        }
    }
    Ok(())
}

/// Whether the file at `path` is already the tile of `region` with
/// `digest` (a task retried or preempted has nothing to do).
pub fn is_done(path: &Path, digest: &str, region: Region) -> bool {
    read(path).is_ok_and(|t| t.digest == digest && t.region == region)
}

/// The whole image the `tiles` (each with its file's path) make, or the
/// first fault found: a foreign tile (its digest not the one most tiles
/// have), an overlap, a missing part.
pub fn merge(tiles: &[(PathBuf, Tile)]) -> Result<Picture, TileError> {
    let Some((_, first)) = tiles.first() else {
        return Err(TileError::Missing {
            what: "every tile".to_string(),
            x: 0,
            y: 0,
            width: 0,
            height: 0,
        });
    };
    let expected = majority_digest(tiles);
    let same = tiles.iter().filter(|(_, t)| t.digest == expected).count();
    if let Some((path, tile)) = tiles.iter().find(|(_, t)| t.digest != expected) {
        return Err(TileError::Foreign {
            path: path.clone(),
            digest: tile.digest.clone(),
            expected,
            others: same,
        });
    }
    let first_path = &tiles[0].0;
    if let Some((path, tile)) = tiles.iter().find(|(_, t)| t.size != first.size) {
        return Err(TileError::OtherSize {
            path: path.clone(),
            size: tile.size,
            first: first_path.clone(),
            expected: first.size,
        });
    }
    let (width, height) = first.size;
    // Before the image is allocated: one 1-pixel tile of a 16384x16384
    // image took 4 GB to be found wanting.
    if let Some((x, y)) = first_uncovered(tiles, (width, height)) {
        return Err(TileError::Missing {
            what: missing_tile(tiles, (x, y)),
            x,
            y,
            width,
            height,
        });
    }
    // u32: the owner of each of up to 2^28 pixels, a gigabyte at most.
    let mut owner = vec![u32::MAX; width as usize * height as usize];
    for (n, (path, tile)) in tiles.iter().enumerate() {
        let r = tile.region;
        for y in r.y0..r.y1 {
            for x in r.x0..r.x1 {
                let at = (y * width + x) as usize;
                if owner[at] != u32::MAX {
                    return Err(TileError::Overlap {
                        path: path.clone(),
                        other: tiles[owner[at] as usize].0.clone(),
                        x,
                        y,
                    });
                }
                owner[at] = n as u32;
            }
        }
    }
    // Every pixel has its tile: `first_uncovered` found none without.
    Ok(Picture {
        linear: paste(tiles, first.size, |t| Some(&t.linear)).expect("every tile has pixels"),
        encoding: first.encoding,
    })
}

/// The one of `all` that `name_of` calls `name`: a setting as a tile's
/// attribute names it.
fn by_name<T: Copy, const N: usize>(
    all: [T; N],
    name_of: fn(T) -> &'static str,
    name: &str,
) -> Option<T> {
    all.into_iter().find(|&value| name_of(value) == name)
}

/// The denoiser's guides of the whole image and their settings, when every
/// tile carries them (tiles `merge` has checked).
pub fn merged_guides(tiles: &[(PathBuf, Tile)]) -> Option<(Guides, Settings)> {
    let (_, first) = tiles.first()?;
    let settings = first.guides.as_ref()?.1;
    let albedo = paste(tiles, first.size, |t| {
        t.guides.as_ref().map(|g| &g.0.albedo)
    })?;
    let normal = paste(tiles, first.size, |t| {
        t.guides.as_ref().map(|g| &g.0.normal)
    })?;
    let emission = paste(tiles, first.size, |t| {
        t.guides.as_ref().map(|g| &g.0.emission)
    })?;
    Some((
        Guides {
            albedo,
            normal,
            emission,
        },
        settings,
    ))
}

/// The image of `size` that each tile's `image` (of its region) makes;
/// None if a tile has none.
fn paste<'a>(
    tiles: &'a [(PathBuf, Tile)],
    (width, height): (u32, u32),
    image: impl Fn(&'a Tile) -> Option<&'a LinearImage>,
) -> Option<LinearImage> {
    let mut whole = LinearImage::new(width, height);
    for (_, tile) in tiles {
        let (r, part) = (tile.region, image(tile)?);
        for y in r.y0..r.y1 {
            let from = ((y - r.y0) * part.width) as usize;
            let at = (y * width + r.x0) as usize;
            let n = r.width() as usize;
            whole.pixels[at..at + n].copy_from_slice(&part.pixels[from..from + n]);
        }
    }
    Some(whole)
}

/// The first pixel, row by row, that no tile holds: each row's tiles
/// sorted by where they start, and the first gap between them.
fn first_uncovered(tiles: &[(PathBuf, Tile)], (width, height): (u32, u32)) -> Option<(u32, u32)> {
    let mut spans: Vec<(u32, u32)> = Vec::new();
    for y in 0..height {
        spans.clear();
        let across = tiles.iter().map(|(_, t)| t.region);
        spans.extend(
            across
                .filter(|r| (r.y0..r.y1).contains(&y))
                .map(|r| (r.x0, r.x1)),
        );
        spans.sort_unstable();
        let mut x = 0;
        for &(x0, x1) in &spans {
            if x0 > x {
                break;
            }
            x = x.max(x1);
        }
        if x < width {
            return Some((x, y));
        }
    }
    None
}

/// The first 12 characters of a digest, for a message (a forged one may
/// be shorter, or not ASCII).
fn start(digest: &str) -> String {
    digest.chars().take(12).collect()
}

/// The digest most tiles carry (the first tile's on a tie): the odd one
/// out is the foreign tile.
fn majority_digest(tiles: &[(PathBuf, Tile)]) -> String {
    let count = |d: &str| tiles.iter().filter(|(_, t)| t.digest == d).count();
    let mut best = tiles[0].1.digest.clone();
    for (_, tile) in tiles {
        if count(&tile.digest) > count(&best) {
            best = tile.digest.clone();
        }
    }
    best
}

/// "tile 3/7 (rows 120..160)" when the tiles were made with `--tile` of one
/// N, else "a part".
fn missing_tile(tiles: &[(PathBuf, Tile)], (x, y): (u32, u32)) -> String {
    let count = match tiles[0].1.tile {
        Some((_, n))
            if tiles
                .iter()
                .all(|(_, t)| t.tile.is_some_and(|(_, m)| m == n)) =>
        {
            n
        }
        _ => return "a part".to_string(),
    };
    let size = tiles[0].1.size;
    (0..count)
        .map(|i| (i, tile_region(i, count, size)))
        .find(|(_, r)| (r.y0..r.y1).contains(&y) && (r.x0..r.x1).contains(&x))
        .map_or("a part".to_string(), |(i, r)| {
            format!("tile {i}/{count} (rows {}..{})", r.y0, r.y1)
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tile of a `size` image holding `region`, of digest `digest`.
    fn tile(digest: &str, size: (u32, u32), region: Region) -> (PathBuf, Tile) {
        let linear = LinearImage::new(region.x1 - region.x0, region.y1 - region.y0);
        let encoding = Encoding {
            gamma: 1.0,
            saturation: Saturation::Clamp,
        };
        let tile = Tile {
            digest: digest.to_string(),
            size,
            region,
            linear,
            encoding,
            tile: None,
            guides: None,
        };
        (PathBuf::from(format!("{digest}.exr")), tile)
    }

    fn region(x0: u32, y0: u32, x1: u32, y1: u32) -> Region {
        Region { x0, y0, x1, y1 }
    }

    #[test]
    fn a_forged_short_or_wide_digest_is_named_without_a_panic() {
        let whole = region(0, 0, 2, 1);
        for odd in ["abc", "ééééééééééééé"] {
            let tiles = [
                tile(&"x".repeat(64), (2, 1), whole),
                tile(&"x".repeat(64), (2, 1), whole),
                tile(odd, (2, 1), whole),
            ];
            let error = merge(&tiles).unwrap_err().to_string();
            assert!(error.contains("a tile of another scene"), "{error}");
        }
    }

    #[test]
    fn a_missing_pixel_is_found_before_the_image_is_made() {
        // One pixel of a 2^28-pixel image: found without its 3 GB.
        let tiles = [tile("d", (16384, 16384), region(0, 0, 1, 1))];
        let error = merge(&tiles).unwrap_err();
        assert!(
            matches!(error, TileError::Missing { x: 1, y: 0, .. }),
            "{error}"
        );
        let tiles = [
            tile("d", (4, 2), region(0, 0, 4, 1)),
            tile("d", (4, 2), region(0, 1, 2, 2)),
            tile("d", (4, 2), region(3, 1, 4, 2)),
        ];
        let error = merge(&tiles).unwrap_err();
        assert!(
            matches!(error, TileError::Missing { x: 2, y: 1, .. }),
            "{error}"
        );
        assert_eq!(first_uncovered(&tiles[..2], (4, 2)), Some((2, 1)));
    }
}
