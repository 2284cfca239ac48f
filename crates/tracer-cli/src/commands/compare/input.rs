//! What `tracer compare` reads: 8-bit images, and scenes rendered as
//! `tracer render` renders them.

use crate::console::note;
use crate::progress::Progress;
use image::{DynamicImage, RgbImage};
use scene_format::validate::{MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE};
use scene_format::SceneKind;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use tracer_pipeline::{Input, Loaded, Options};

/// Largest image file read, as for a scene's texture images.
const MAX_IMAGE_BYTES: u64 = 256 * 1024 * 1024;

/// The user's mistake: a missing file, a file that is not an image, a
/// folder with nothing to compare (exit 2).
#[derive(Debug)]
pub struct BadInput(pub String);

impl fmt::Display for BadInput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BadInput {}

/// The 8-bit RGB image at `path` (PNG or JPEG; 16 bits read as the tracer
/// writes them, alpha dropped).
pub fn read_image(path: &Path) -> Result<RgbImage, BadInput> {
    image_at(path).map_err(|message| BadInput(format!("{}: {message}", path.display())))
}

/// [`read_image`], its error without the path.
pub fn image_at(path: &Path) -> Result<RgbImage, String> {
    let bytes = scene_format::read::read_capped(path, MAX_IMAGE_BYTES)
        .map_err(|e| format!("cannot read the image: {e}"))?;
    let reader = || {
        image::ImageReader::new(std::io::Cursor::new(&bytes))
            .with_guessed_format()
            .map_err(|e| e.to_string())
    };
    // The header first: its format, then its size.
    let header = reader()?;
    let Some(format) = header.format() else {
        return Err("not an image (expected a .png or .jpg file)".to_string());
    };
    let (width, height) = header
        .into_dimensions()
        .map_err(scene_format::images::unreadable)?;
    if width.max(height) > MAX_IMAGE_SIDE || u64::from(width) * u64::from(height) > MAX_IMAGE_PIXELS
    {
        return Err(format!(
            "{width}x{height} pixels; expected at most {MAX_IMAGE_SIDE} a side and \
             {MAX_IMAGE_PIXELS} (2^28) in all, the largest image the tracer renders"
        ));
    }
    let mut reader = reader()?;
    let mut limits = image::Limits::default();
    // The largest image allowed, at 16 bits in four channels.
    limits.max_alloc = Some(MAX_IMAGE_PIXELS * 8);
    reader.limits(limits);
    let image = reader.decode().map_err(scene_format::images::unreadable)?;
    if format == image::ImageFormat::Jpeg {
        note!(
            "note: {}: a JPEG's compression changes pixels, so even a right image saved \
             as JPEG is off somewhere; compare a PNG, or judge this one by PSNR and FLIP",
            path.display()
        );
    }
    if transparent(&image) {
        note!(
            "note: {}: has transparent pixels; its colours are compared as if opaque \
             (a viewer may show it otherwise)",
            path.display()
        );
    }
    to_rgb8(image)
}

/// Whether some pixel of `image` is not fully opaque (read in place: a
/// copy of the largest image would take gigabytes).
fn transparent(image: &DynamicImage) -> bool {
    match image {
        DynamicImage::ImageRgba8(i) => i.pixels().any(|p| p[3] < u8::MAX),
        DynamicImage::ImageLumaA8(i) => i.pixels().any(|p| p[1] < u8::MAX),
        DynamicImage::ImageRgba16(i) => i.pixels().any(|p| p[3] < u16::MAX),
        DynamicImage::ImageLumaA16(i) => i.pixels().any(|p| p[1] < u16::MAX),
        DynamicImage::ImageRgba32F(i) => i.pixels().any(|p| p[3] < 1.0),
        _ => false,
    }
}

/// The 8-bit values of `image`; float images are refused, their linear
/// values are not what a PNG of the scene holds.
fn to_rgb8(image: DynamicImage) -> Result<RgbImage, String> {
    match image {
        DynamicImage::ImageRgb32F(_) | DynamicImage::ImageRgba32F(_) => Err(
            "a float image holds linear values, not the 8-bit ones compared; \
             render to .png instead"
                .to_string(),
        ),
        DynamicImage::ImageRgb16(_)
        | DynamicImage::ImageRgba16(_)
        | DynamicImage::ImageLuma16(_)
        | DynamicImage::ImageLumaA16(_) => Ok(from_16_bits(&image)),
        other => Ok(other.into_rgb8()),
    }
}

/// A 16-bit image's 8-bit values as the tracer truncates them: a 16-bit
/// value divided by 257 (the `image` crate rounds instead).
fn from_16_bits(image: &DynamicImage) -> RgbImage {
    let wide = image.to_rgb16();
    let narrow = wide.as_raw().iter().map(|&v| (v / 257) as u8).collect();
    RgbImage::from_raw(wide.width(), wide.height(), narrow)
        .expect("the buffer holds exactly width * height pixels")
}

/// Whether `path` names a scene file rather than an image, by extension.
pub fn is_scene(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| ["toml", "json", "zip"].contains(&e.to_ascii_lowercase().as_str()))
}

/// A reference: its 8-bit image and the display gamma that made it.
pub struct Reference {
    /// Its pixels; none when a scene's size differs from the image's,
    /// which then is all that is compared.
    pub image: RgbImage,
    /// Its size, whether or not it was rendered.
    pub size: (u32, u32),
    /// The scene's gamma; `None` for a reference image, whose gamma is
    /// not known.
    pub gamma: Option<f32>,
    /// The scene file, for `tracer explain`; `None` for an image.
    pub scene: Option<PathBuf>,
    /// Every file read for it.
    pub files_read: Vec<PathBuf>,
    /// A path-traced scene's paths a pixel: its image is one draw of its
    /// noise, which no other render repeats.
    pub path_samples: Option<u32>,
    /// The scene's camera puts world +x on the image's right
    /// (`handedness = "right"`): a mirror image's advice differs.
    pub right_handed: bool,
    /// The scene, to render it again through the pixels' corners: a 3D
    /// scene not path traced.
    loaded: Option<Loaded>,
    /// Those renders (`through_corner`), made when first asked for.
    corners: [OnceLock<Option<RgbImage>>; 4],
}

/// The four corners of a pixel a tracer may aim its rays at instead of
/// the centre, as pixel shifts: left and up, right and up, left and down,
/// right and down.
pub const CORNERS: [[f32; 2]; 4] = [[-0.5, -0.5], [0.5, -0.5], [-0.5, 0.5], [0.5, 0.5]];

impl Reference {
    /// The reference scene rendered through corner `k` of [`CORNERS`] of
    /// each pixel rather than its centre: what a tracer that aims there
    /// makes. None for a reference image or a canvas, or if the render
    /// fails (the reference itself rendered).
    pub fn through_corner(&self, k: usize) -> Option<&RgbImage> {
        let render = || {
            let loaded = self.loaded.as_ref()?;
            if k == 0 {
                note!(
                    "the half-pixel test: {} rendered through the pixels' corners",
                    loaded.name.display()
                );
            }
            let options = Options {
                pixel_shift: Some(CORNERS[k]),
                ..Options::default()
            };
            let rendered = tracer_pipeline::render(loaded, &options, &|_| {}).ok()?;
            Some(rendered.image.to_rgb8())
        };
        self.corners[k].get_or_init(render).as_ref()
    }
}

/// The reference at `path`: an image, or a scene loaded and rendered if
/// its size is `wanted` (else only its size is known: a scene of 16384^2
/// pixels is not rendered to be found the wrong size).
pub fn read_reference(
    path: &Path,
    wanted: Option<(u32, u32)>,
    samples: Option<u32>,
) -> anyhow::Result<Reference> {
    if !is_scene(path) {
        let image = read_image(path)?;
        return Ok(Reference {
            size: image.dimensions(),
            image,
            gamma: None,
            scene: None,
            files_read: vec![path.to_path_buf()],
            path_samples: None,
            right_handed: false,
            loaded: None,
            corners: Default::default(),
        });
    }
    let loaded = tracer_pipeline::load(&Input::File(path.to_path_buf()))?;
    render(loaded, wanted, samples)
}

/// `loaded` rendered with the scene's own settings (but `samples`, when
/// given), as `tracer render` renders it to a PNG, with its warnings and a
/// progress bar on stderr; not rendered unless its size is `wanted` (or
/// nothing is).
pub fn render(
    loaded: Loaded,
    wanted: Option<(u32, u32)>,
    samples: Option<u32>,
) -> anyhow::Result<Reference> {
    let options = Options {
        samples,
        ..Options::default()
    };
    crate::report::warnings(&loaded, &options);
    crate::report::time_limit_unused(&loaded, &options);
    let size = tracer_pipeline::image_size(&loaded, &options)?;
    if wanted.is_some_and(|wanted| wanted != size) {
        return Ok(Reference {
            image: RgbImage::new(0, 0),
            size,
            gamma: None,
            scene: Some(loaded.name.clone()),
            files_read: loaded.files_read.clone(),
            path_samples: path_samples(&loaded, &options),
            right_handed: right_handed(&loaded),
            loaded: None,
            corners: Default::default(),
        });
    }
    let (_, rows) = size;
    let progress = Progress::new(rows.into(), false);
    let rendered = tracer_pipeline::render(&loaded, &options, &|n| progress.rows_done(n));
    progress.finish();
    let picture = rendered?.image;
    // A path-traced scene's noise would hide a shift of half a pixel, and
    // four more renders of it take long: not rendered through the corners.
    let path_samples = path_samples(&loaded, &options);
    let through_corners = matches!(loaded.kind, SceneKind::Scene3d(_)) && path_samples.is_none();
    Ok(Reference {
        size,
        image: picture.to_rgb8(),
        gamma: Some(picture.encoding.gamma),
        scene: Some(loaded.name.clone()),
        files_read: loaded.files_read.clone(),
        path_samples,
        right_handed: right_handed(&loaded),
        loaded: through_corners.then_some(loaded),
        corners: Default::default(),
    })
}

/// Whether the scene's camera puts world +x on the image's right.
fn right_handed(loaded: &Loaded) -> bool {
    matches!(&loaded.kind, SceneKind::Scene3d(file)
        if file.camera.handedness == scene_format::Handedness::Right)
}

/// The paths a pixel of a path-traced scene rendered with `options`.
fn path_samples(loaded: &Loaded, options: &Options) -> Option<u32> {
    match &loaded.kind {
        SceneKind::Scene3d(file) if loaded.is_path_traced(options) => {
            Some(options.samples.unwrap_or(file.render.samples))
        }
        _ => None,
    }
}
