//! `--denoise`: a path-traced image cleaned by Intel Open Image Denoise
//! (OIDN), guided by the albedo and the normal of what each pixel sees
//! (the core's `albedo` and `shading-normal` AOVs).
//!
//! - `library.rs`: finding and loading OIDN at run time (`cargo xtask oidn`).
//! - `filter.rs`: its `RT` filter with prefiltered guides (`cleanAux`).
//! - `stages.rs`: how long each stage of a denoise took (for the bench).
//! - `emission.rs`: the light each pixel sees directly, left out of what
//!   OIDN filters and added back (and where that guide is sampled finely).
//!
//! Nothing that is not a finite, non-negative number reaches OIDN (one NaN
//! would spread over a whole neighbourhood of its output): such values are
//! made 0 first (`finite`).

pub(crate) mod emission;
#[cfg(not(target_arch = "wasm32"))]
mod filter;
#[cfg(not(target_arch = "wasm32"))]
mod library;
#[cfg(not(target_arch = "wasm32"))]
pub mod stages;

#[cfg(not(target_arch = "wasm32"))]
pub use library::{available, find_in, project_folder};

use glam::Vec3;
use std::path::PathBuf;
use tracer_core::LinearImage;

/// What OIDN does with the guides, as Blender names it (the scene file's).
pub use scene_format::DenoisePrefilter as Prefilter;
/// OIDN's filter quality, as OIDN names them (the scene file's).
pub use scene_format::DenoiseQuality as Quality;

/// How an image is denoised: `[render] denoise_quality` and
/// `denoise_prefilter`, or the options over them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub struct Settings {
    pub quality: Quality,
    pub prefilter: Prefilter,
}

impl Settings {
    /// "high, accurate prefilter" or "fast, no prefilter": as the summary
    /// line says it.
    pub fn name(&self) -> String {
        let quality = self.quality.name();
        match self.prefilter {
            Prefilter::None => format!("{quality}, no prefilter"),
            other => format!("{quality}, {} prefilter", other.name()),
        }
    }
}

/// `OIDN_QUALITY_FAST`, `_BALANCED`, `_HIGH`.
#[cfg(not(target_arch = "wasm32"))]
fn oidn_quality(quality: Quality) -> i32 {
    match quality {
        Quality::Fast => 4,
        Quality::Balanced => 5,
        Quality::High => 6,
    }
}

/// The quality of OIDN's number for it (None for another number).
#[cfg(not(target_arch = "wasm32"))]
fn quality_of_oidn(value: i32) -> Option<Quality> {
    [Quality::Fast, Quality::Balanced, Quality::High]
        .into_iter()
        .find(|&q| oidn_quality(q) == value)
}

/// Why an image could not be denoised.
#[derive(Debug, Clone, thiserror::Error)]
pub enum DenoiseError {
    /// The library is not installed: the message names the command.
    #[error("--denoise needs Intel Open Image Denoise 2.5, which is not installed; install it with `{command}` in the tracer's source folder ({}), or `pip install pyoidn==2.5.1.0` (looked in {})", workspace().display(), looked.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", "), command = INSTALL)]
    Missing { looked: Vec<PathBuf> },
    /// The library is there but could not be loaded.
    #[error("--denoise: cannot load Intel Open Image Denoise from {}: {message}; reinstall it with `{command}`", path.display(), command = INSTALL)]
    Load { path: PathBuf, message: String },
    /// OIDN itself failed.
    #[error("Intel Open Image Denoise failed: {0}")]
    Oidn(String),
    /// A version other than OIDN 2.
    #[error("--denoise: {} is Open Image Denoise {version}; expected version 2 (reinstall it with `{command}`)", path.display(), command = INSTALL)]
    Version { version: String, path: PathBuf },
}

impl DenoiseError {
    /// Whether the user can put it right (exit 2): the library missing,
    /// unloadable or of another version.
    pub fn is_bad_input(&self) -> bool {
        !matches!(self, DenoiseError::Oidn(_))
    }
}

/// The command that installs the library (in the workspace's folder).
pub const INSTALL_COMMAND: &str = "cargo xtask oidn";
const INSTALL: &str = INSTALL_COMMAND;

/// The workspace the tracer was built from, where `cargo xtask oidn` runs.
pub fn workspace() -> PathBuf {
    let crate_folder = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    crate_folder
        .ancestors()
        .nth(2)
        .unwrap_or(crate_folder)
        .to_path_buf()
}

/// What guides the filter: each pixel's albedo (0 to 1) and shading
/// normal (-1 to 1; zero where the pixel sees nothing), and the light it
/// sees directly, as the render counted it and through mirrors and glass
/// (`emission.rs`: not filtered), the size of the image denoised.
#[derive(Debug, Clone, PartialEq)]
pub struct Guides {
    pub albedo: LinearImage,
    pub normal: LinearImage,
    pub emission: LinearImage,
}

/// `colour` denoised with `guides` as `settings` say, on `threads`
/// threads (0: one per core): OIDN filters the colour less the light seen
/// directly, which is added back (`emission.rs`). The guides are
/// prefiltered on a copy: they are kept as rendered, for the tiles that
/// carry them.
#[cfg(not(target_arch = "wasm32"))]
pub fn denoise(
    colour: &LinearImage,
    guides: &Guides,
    settings: Settings,
    threads: usize,
) -> Result<LinearImage, DenoiseError> {
    denoise_in_stages(colour, guides, settings, threads).map(|(image, _)| image)
}

/// [`denoise`], with how long each of its stages took.
#[cfg(not(target_arch = "wasm32"))]
pub fn denoise_in_stages(
    colour: &LinearImage,
    guides: &Guides,
    settings: Settings,
    threads: usize,
) -> Result<(LinearImage, stages::Stages), DenoiseError> {
    let start = std::time::Instant::now();
    let api = library::api()?;
    let device = filter::Device::new(api, threads)?;
    if device.version() / 10000 != 2 {
        return Err(DenoiseError::Version {
            version: device.version().to_string(),
            path: api.path.clone(),
        });
    }
    let made = std::time::Instant::now();
    let size = (colour.width as usize, colour.height as usize);
    let light = finite(&guides.emission.pixels);
    let colour = emission::without(&finite(&colour.pixels), &light);
    let mut albedo = finite(&guides.albedo.pixels).into_owned();
    let mut normal = guides.normal.pixels.clone();
    zero_non_finite(&mut normal);
    let mut output = LinearImage::new(size.0 as u32, size.1 as u32);
    let prepared = std::time::Instant::now();
    let runs = device.denoise(
        size,
        &colour,
        &mut albedo,
        &mut normal,
        &mut output.pixels,
        settings,
    )?;
    let filtered = std::time::Instant::now();
    for (c, e) in output.pixels.iter_mut().zip(light.iter()) {
        *c += *e;
    }
    let stages = stages::Stages {
        device_seconds: (made - start).as_secs_f64(),
        prepare_seconds: (prepared - made).as_secs_f64(),
        albedo: runs.albedo,
        normal: runs.normal,
        colour: runs.colour,
        finish_seconds: filtered.elapsed().as_secs_f64(),
    };
    Ok((output, stages))
}

/// The pixels with every channel that is not a finite number >= 0 made
/// 0 (borrowed when there is none: the path tracer leaves such samples
/// out already).
pub fn finite(pixels: &[Vec3]) -> std::borrow::Cow<'_, [Vec3]> {
    let fine = |c: &Vec3| c.is_finite() && c.min_element() >= 0.0;
    if pixels.iter().all(fine) {
        return std::borrow::Cow::Borrowed(pixels);
    }
    let clean = |x: f32| if x.is_finite() && x >= 0.0 { x } else { 0.0 };
    std::borrow::Cow::Owned(pixels.iter().map(|c| c.map(clean)).collect())
}

/// Normals may be negative: only NaN and infinities are made 0.
#[cfg(not(target_arch = "wasm32"))]
fn zero_non_finite(pixels: &mut [Vec3]) {
    for c in pixels {
        *c = c.map(|x| if x.is_finite() { x } else { 0.0 });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_that_are_not_finite_or_are_negative_become_0() {
        let pixels = [
            Vec3::new(0.5, f32::NAN, 2.0),
            Vec3::new(f32::INFINITY, -1.0, 0.25),
        ];
        let clean = finite(&pixels);
        assert_eq!(
            &clean[..],
            &[Vec3::new(0.5, 0.0, 2.0), Vec3::new(0.0, 0.0, 0.25)]
        );
        let fine = [Vec3::ONE, Vec3::ZERO];
        assert!(matches!(finite(&fine), std::borrow::Cow::Borrowed(_)));
    }
}
