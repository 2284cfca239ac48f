//! What a render gives back: the image and the numbers for its summary.

use crate::denoise::{Guides, Settings};
use crate::options::Aov;
use image::{ImageBuffer, Rgb, Rgb32FImage, RgbImage};
use tracer_core::image::{Encoding, LinearImage};

/// An image made, and what went into it.
#[derive(Debug, Clone)]
pub struct Rendered {
    pub image: Picture,
    pub summary: Summary,
    /// What denoising took and left (`--denoise`), if asked for.
    pub denoising: Option<Box<Denoising>>,
}

/// A render's denoising: its guides (which a tile carries, for `tracer
/// merge --denoise`), and the image before and the time taken when it was
/// denoised (a tile is not: its edges would not match its neighbours').
#[derive(Debug, Clone)]
pub struct Denoising {
    pub guides: Guides,
    pub settings: Settings,
    /// The image as rendered, before denoising; None when not denoised.
    pub noisy: Option<LinearImage>,
    /// Seconds the guides took to render, and OIDN to run.
    pub guide_seconds: f64,
    pub denoise_seconds: f64,
}

/// A rendered image before its file format: the renderer's linear values
/// and how a display encodes them. Carried to the output step so float
/// files get the values themselves and 8- and 16-bit files the same rule.
#[derive(Debug, Clone)]
pub struct Picture {
    pub linear: LinearImage,
    /// The gamma and saturation rule of 8- and 16-bit files.
    pub encoding: Encoding,
}

impl Picture {
    pub fn dimensions(&self) -> (u32, u32) {
        (self.linear.width, self.linear.height)
    }

    /// The picture blown up to `(width, height)` by repeating pixels (a
    /// preview shown at the size of the image it stands for).
    pub fn enlarged(&self, (width, height): (u32, u32)) -> Picture {
        let small = &self.linear;
        let mut linear = LinearImage::new(width, height);
        for y in 0..height {
            let sy = (u64::from(y) * u64::from(small.height) / u64::from(height)) as u32;
            for x in 0..width {
                let sx = (u64::from(x) * u64::from(small.width) / u64::from(width)) as u32;
                linear.pixels[(y * width + x) as usize] =
                    small.pixels[(sy * small.width + sx) as usize];
            }
        }
        Picture {
            linear,
            encoding: self.encoding,
        }
    }

    /// The 8-bit image (PNG, JPEG): the lab's encoding.
    pub fn to_rgb8(&self) -> RgbImage {
        self.linear.encode(&self.encoding)
    }

    /// The 16-bit image: the same rule truncated to 16 bits.
    pub fn to_rgb16(&self) -> ImageBuffer<Rgb<u16>, Vec<u16>> {
        self.linear.encode16(&self.encoding)
    }

    /// The linear values as they are: no gamma, no saturation rule.
    pub fn to_rgb32f(&self) -> Rgb32FImage {
        let values = self
            .linear
            .pixels
            .iter()
            .flat_map(|c| c.to_array())
            .collect();
        Rgb32FImage::from_raw(self.linear.width, self.linear.height, values)
            .expect("the buffer holds exactly width * height pixels")
    }
}

/// What was rendered, for a summary line.
#[derive(Debug, Clone, PartialEq)]
pub enum Summary {
    Shaded(ShadedStats),
    Aov(Aov),
    Canvas,
}

/// The numbers of a shaded 3D render.
#[derive(Debug, Clone, PartialEq)]
pub struct ShadedStats {
    /// Objects in the scene file (a mesh is one).
    pub objects: usize,
    /// Primitives the tracer intersects (a mesh is many triangles).
    pub primitives: usize,
    /// Rays traced: primary, shadow and reflected.
    pub rays: u64,
    pub prepare_seconds: f64,
    pub render_seconds: f64,
    /// Pixels made white by the lab's saturation rule (a channel above 1);
    /// 0 with `saturation = "clamp"`.
    pub forced_white: u64,
    /// Pixels in the image.
    pub pixels: u64,
    /// Samples a pixel the image has (of the last pass, for a render in
    /// passes).
    pub samples: u32,
    /// Path samples left out of their pixel for a value that was not
    /// finite (NaN or infinite); 0 in Whitted mode.
    pub dropped: u64,
    /// Whitted samples whose ray tree was cut at
    /// `tracer_core::integrate::whitted::MAX_TREE_RAYS` rays.
    pub cut_trees: u64,
    /// In path mode with point lights, the image's mean luminance (linear);
    /// None otherwise.
    pub point_lit_mean: Option<f32>,
    /// In path mode, the estimator the render used: the file's keys or,
    /// where it left them out, path mode's own choice; None in Whitted mode.
    pub estimator: Option<Estimator>,
}

/// Path mode's estimator as `[render]`'s keys say it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Estimator {
    pub path_reuse: u32,
    pub camera_rays: u32,
    pub adaptive: bool,
}

impl std::fmt::Display for Estimator {
    /// The keys as a scene file writes them, so that a user who wants
    /// another choice knows what to set.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "path_reuse = {}, camera_rays = {}, adaptive = {}",
            self.path_reuse, self.camera_rays, self.adaptive
        )
    }
}

/// Above this share of pixels forced to white, a render warns: the lab's
/// rule whitens a pixel for one channel above 1, which in the lab's scenes
/// touches a few highlight pixels at most (0.013 % in `reflectance2`, none
/// in the others; a test keeps it so), while an over-lit scene turns into
/// white patches.
pub const FORCED_WHITE_WARNING: f64 = 0.03;

/// Below this mean luminance a path-mode image lit by point lights is
/// called nearly black: the lab's lights (colour 0.6, 10 units away) give
/// a white surface about 0.002 in path mode.
pub const DARK_MEAN: f32 = 0.01;

impl ShadedStats {
    /// A warning when a path-mode image lit by point lights came out nearly
    /// black: their light falls off with the square of the distance there,
    /// which the lab's scenes were not made for.
    pub fn dark_warning(&self) -> Option<String> {
        let mean = self.point_lit_mean.filter(|&m| m < DARK_MEAN)?;
        Some(format!(
            "the image is nearly black (mean {mean:.4}): in path mode a point light's `color` is its intensity, \
             which falls off with the square of the distance (a light 10 units away lights a surface 100 times less \
             than in Whitted mode); raise the lights' `color` by the square of their distance, or give a material `emission`"
        ))
    }

    /// A warning when ray trees were cut short.
    pub fn cut_trees_warning(&self) -> Option<String> {
        (self.cut_trees > 0).then(|| {
            format!(
                "{} sample{} reached {} mirror and refracted rays, and the rest of {} ray tree was not traced: \
                 glass splits every ray in two, so a tree can double at each of `max_depth` levels; \
                 raise `min_energy` (the lab's 0.01) or lower `max_depth`",
                self.cut_trees,
                if self.cut_trees == 1 { "" } else { "s" },
                tracer_core::integrate::whitted::MAX_TREE_RAYS,
                if self.cut_trees == 1 { "its" } else { "their" },
            )
        })
    }

    /// A warning when path samples were dropped.
    pub fn dropped_warning(&self) -> Option<String> {
        (self.dropped > 0).then(|| {
            format!(
                "{} path sample{} had a value that is not a number or infinite and {} left out of {} pixel{}",
                self.dropped,
                if self.dropped == 1 { "" } else { "s" },
                if self.dropped == 1 { "was" } else { "were" },
                if self.dropped == 1 { "its" } else { "their" },
                if self.dropped == 1 { "" } else { "s" },
            )
        })
    }

    /// A warning when more than [`FORCED_WHITE_WARNING`] of the pixels were
    /// forced to white.
    pub fn forced_white_warning(&self) -> Option<String> {
        let share = self.forced_white as f64 / self.pixels.max(1) as f64;
        (share > FORCED_WHITE_WARNING).then(|| {
            format!(
                "{:.1} % of the pixels ({} of {}) have a channel above 1 and were made white by the lab's saturation rule; \
                 `saturation = \"clamp\"` in [render] clamps each channel instead, or lower the lights or materials",
                share * 100.0,
                self.forced_white,
                self.pixels
            )
        })
    }
}
