//! What a render is asked for: a checked display gamma, an AOV, and
//! overrides of the scene's samples and image size.

use crate::Error;
use scene_format::validate::{MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE, MAX_SAMPLES};
use scene_format::{Integrator, SceneFile};
use std::borrow::Cow;
pub use tracer_core::Region;

/// One quantity per pixel instead of the shaded colour: the core's list.
pub use tracer_core::aov::Aov;

/// A display gamma, checked: a finite number > 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gamma(f32);

impl Gamma {
    /// The gamma `g`, or [`Error::Gamma`] unless it is finite and > 0.
    pub fn new(g: f32) -> Result<Gamma, Error> {
        if g.is_finite() && g > 0.0 {
            Ok(Gamma(g))
        } else {
            Err(Error::Gamma(g))
        }
    }

    pub fn get(self) -> f32 {
        self.0
    }
}

/// What to render of a loaded scene.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Options {
    /// Overrides the scene's gamma (an AOV's is 1 otherwise).
    pub gamma: Option<Gamma>,
    /// An AOV instead of the shaded colour; 3D scenes only.
    pub aov: Option<Aov>,
    /// Overrides `[render] samples` (checked by the caller: 1 to 65536;
    /// above 4096 only in path mode, checked here).
    pub samples: Option<u32>,
    /// Overrides `[render] integrator`.
    pub integrator: Option<Integrator>,
    /// Overrides the camera's width; alone, the height follows so the view
    /// keeps its shape.
    pub width: Option<u32>,
    /// Overrides the camera's height; alone, the width follows.
    pub height: Option<u32>,
    /// With `aov: Some(Aov::Depth)`, the distances from the eye (0 for no
    /// hit) instead of the greys: what a float file (EXR, HDR) holds.
    pub raw_depth: bool,
    /// Only a part of the image (`--region`, `--tile`): its pixels are
    /// those of the whole image, bit for bit.
    pub part: Option<Part>,
    /// Every image point the camera samples moved by (x, y) pixels, for a
    /// shaded 3D image: `tracer compare` renders a reference through the
    /// pixels' corners (-0.5 or 0.5) to recognise a tracer that aims
    /// there. No command-line option sets it.
    pub pixel_shift: Option<[f32; 2]>,
    /// Denoise the shaded image (`--denoise`; the scene's `[render]
    /// denoise` asks the same): path mode only.
    pub denoise: bool,
    /// Overrides `[render] denoise_quality`.
    pub denoise_quality: Option<crate::denoise::Quality>,
    /// Overrides `[render] denoise_prefilter`.
    pub denoise_prefilter: Option<crate::denoise::Prefilter>,
}

/// A part of the image to render, checked against the image's size.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    /// Pixels `x0..x1` by `y0..y1` (end exclusive).
    Region(Region),
    /// The `index`-th (0-based) of `count` tiles: see [`tile_region`].
    Tile { index: u32, count: u32 },
}

impl Part {
    /// The pixels of this part of an image of `width` x `height`, or
    /// [`Error::Part`] when they are empty or leave the image.
    pub fn region(self, (width, height): (u32, u32)) -> Result<Region, Error> {
        let bad = |message: String| Err(Error::Part(message));
        match self {
            Part::Region(r) => {
                if r.x0 >= r.x1 || r.y0 >= r.y1 {
                    return bad(format!(
                        "--region {}: empty; expected X0,Y0,X1,Y1 with X0 < X1 and Y0 < Y1 (ends exclusive)",
                        show(r)
                    ));
                }
                if r.x1 > width || r.y1 > height {
                    return bad(format!(
                        "--region {}: outside the {width}x{height} image; expected X1 <= {width} and Y1 <= {height} (ends exclusive)",
                        show(r)
                    ));
                }
                Ok(r)
            }
            Part::Tile { index, count } => {
                if count == 0 || index >= count {
                    return bad(format!(
                        "--tile {index}/{count}: expected I/N with 0 <= I < N"
                    ));
                }
                if count > height {
                    return bad(format!(
                        "--tile {index}/{count}: the image has {height} rows; expected at most {height} tiles"
                    ));
                }
                Ok(tile_region(index, count, (width, height)))
            }
        }
    }
}

fn show(r: Region) -> String {
    format!("{},{},{},{}", r.x0, r.y0, r.x1, r.y1)
}

/// Tile `index` of `count` (`count` <= `height`): a band of whole rows,
/// bands of near-equal height (they differ by one row at most), top to
/// bottom.
///
/// Why bands of rows: a tile is one EXR data window, so it must be a
/// rectangle, and full-width bands are the rectangles whose pixel counts
/// are equal for any N (a grid of N cells needs N to factor). Interleaved
/// rows would balance better still (a costly mesh in one band of the
/// image is shared by all tasks) but are no rectangle. Within a band the
/// render spreads rows over threads as a full render does; across tasks,
/// a scene whose cost sits in a few rows gives the tasks unequal times:
/// choose N a few times the number of machines so a scheduler can even
/// them out.
pub fn tile_region(index: u32, count: u32, (width, height): (u32, u32)) -> Region {
    let row = |i: u32| (u64::from(i) * u64::from(height) / u64::from(count)) as u32;
    Region {
        x0: 0,
        y0: row(index),
        x1: width,
        y1: row(index + 1),
    }
}

impl Options {
    /// Whether an option that only a 3D scene has is set: its name.
    pub(crate) fn option_of_3d(&self) -> Option<&'static str> {
        [
            ("--aov", self.aov.is_some()),
            ("--samples", self.samples.is_some()),
            ("--integrator", self.integrator.is_some()),
            ("--width", self.width.is_some()),
            ("--height", self.height.is_some()),
            ("--region/--tile", self.part.is_some()),
            ("--denoise", self.denoise),
            ("--denoise-quality", self.denoise_quality.is_some()),
            ("--denoise-prefilter", self.denoise_prefilter.is_some()),
        ]
        .into_iter()
        .find_map(|(name, set)| set.then_some(name))
    }

    /// The image size of `file` with `--width`/`--height` applied: the same
    /// view (the horizontal field of view is kept) at another resolution.
    pub fn image_size(&self, file: &SceneFile) -> Result<(u32, u32), Error> {
        let (w, h) = (file.camera.width, file.camera.height);
        let scaled = |side: u32, by: u32, of: u32| {
            let exact = u64::from(side) * u64::from(by);
            ((exact + u64::from(of) / 2) / u64::from(of)).max(1)
        };
        let (width, height) = match (self.width, self.height) {
            (None, None) => return Ok((w, h)),
            (Some(width), Some(height)) => (u64::from(width), u64::from(height)),
            (Some(width), None) => (u64::from(width), scaled(h, width, w)),
            (None, Some(height)) => (scaled(w, height, h), u64::from(height)),
        };
        let side = 1..=u64::from(MAX_IMAGE_SIDE);
        if !side.contains(&width) || !side.contains(&height) || width * height > MAX_IMAGE_PIXELS {
            return Err(Error::ImageSize { width, height });
        }
        Ok((width as u32, height as u32))
    }

    /// `file` with the overrides applied (borrowed when there are none).
    pub(crate) fn apply<'a>(&self, file: &'a SceneFile) -> Result<Cow<'a, SceneFile>, Error> {
        let overrides = [
            self.samples.is_some(),
            self.width.is_some(),
            self.height.is_some(),
            self.integrator.is_some(),
            self.denoise,
            self.denoise_quality.is_some(),
            self.denoise_prefilter.is_some(),
        ];
        if !overrides.contains(&true) {
            return Ok(Cow::Borrowed(file));
        }
        let (width, height) = self.image_size(file)?;
        let mut file = file.clone();
        file.camera.width = width;
        file.camera.height = height;
        if let Some(integrator) = self.integrator {
            file.render.integrator = integrator;
        }
        if let Some(samples) = self.samples {
            file.render.samples = samples;
        }
        file.render.denoise |= self.denoise;
        if self.denoise_quality.is_some() {
            file.render.denoise_quality = self.denoise_quality;
        }
        if self.denoise_prefilter.is_some() {
            file.render.denoise_prefilter = self.denoise_prefilter;
        }
        let render = &file.render;
        if self.denoise && render.integrator == Integrator::Whitted {
            return Err(Error::DenoiseWhitted);
        }
        if render.integrator == Integrator::Whitted && render.samples > MAX_SAMPLES {
            return Err(match self.samples {
                Some(given) => Error::Samples(given),
                None => Error::SceneSamples(render.samples),
            });
        }
        Ok(Cow::Owned(file))
    }

    /// `apply` to a file owned: the same file, or the changed copy alone.
    pub(crate) fn apply_owned(&self, file: SceneFile) -> Result<SceneFile, Error> {
        let changed = match self.apply(&file)? {
            Cow::Owned(changed) => Some(changed),
            Cow::Borrowed(_) => None,
        };
        Ok(changed.unwrap_or(file))
    }
}
