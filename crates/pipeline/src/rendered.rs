//! What a render gives back: the image and the numbers for its summary.

use crate::options::Aov;
use image::RgbImage;

/// An image made, and what went into it.
#[derive(Debug, Clone)]
pub struct Rendered {
    pub image: RgbImage,
    pub summary: Summary,
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
}

/// Above this share of pixels forced to white, a render warns: the lab's
/// rule whitens a pixel for one channel above 1, which in the lab's scenes
/// touches a few highlight pixels at most (0.013 % in `reflectance2`, none
/// in the others; a test keeps it so), while an over-lit scene turns into
/// white patches.
pub const FORCED_WHITE_WARNING: f64 = 0.03;

impl ShadedStats {
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
