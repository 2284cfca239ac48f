//! What can go wrong between a scene file and an image, sorted into the
//! user's mistakes (bad input) and the machine's failures.

use crate::output::OutputError;
use scene_format::SceneError;
use std::path::PathBuf;

/// Why the pipeline made no image. [`Error::is_bad_input`] tells the
/// user's mistakes (the CLI's exit status 2) from other failures (1).
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The scene file could not be read, or has mistakes; the CLI shows the
    /// diagnostics with their source lines.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A gamma override that is not a number > 0.
    #[error("--gamma: expected a number > 0, found {0}")]
    Gamma(f32),
    /// A calibration chart of a size that cannot be made.
    #[error("--width/--height: expected 5 to {max} by 1 to {max} pixels, found {width}x{height}")]
    ChartSize { width: u32, height: u32, max: u32 },
    /// An option of 3D renders (`--aov`, `--samples`, ...) given for a
    /// 2D canvas scene.
    #[error("{}: {option} needs a 3D scene; this is a 2D canvas scene", scene.display())]
    CanvasOption {
        scene: PathBuf,
        option: &'static str,
    },
    /// `--width`/`--height` that make an image too large (or empty).
    #[error("--width/--height: the image would be {width}x{height} pixels; expected 1 to {side} a side and at most {pixels} (2^28) in all", side = scene_format::validate::MAX_IMAGE_SIDE, pixels = scene_format::validate::MAX_IMAGE_PIXELS)]
    ImageSize { width: u64, height: u64 },
    /// More samples than Whitted mode takes (given by `--samples`).
    #[error("--samples {0}: expected 1 to {max} with the Whitted integrator; more are allowed in path mode (--integrator path, or integrator = \"path\" in [render])", max = scene_format::validate::MAX_SAMPLES)]
    Samples(u32),
    /// A path-traced scene's samples, too many for `--integrator whitted`.
    #[error("--integrator whitted: the scene's samples = {0} is more than Whitted mode takes (1 to {max}); expected --samples {max} or fewer with it", max = scene_format::validate::MAX_SAMPLES)]
    SceneSamples(u32),
    /// An option of path mode's passes for a scene in Whitted mode.
    #[error("{option}: needs path mode, which renders in passes (integrator = \"path\" in [render], or --integrator path); Whitted mode renders in one")]
    NeedsPathMode { option: &'static str },
    /// `--denoise` for a scene in Whitted mode.
    #[error("--denoise: needs path mode (integrator = \"path\" in [render], or --integrator path); Whitted mode's images have no path-tracing noise for the denoiser to take out")]
    DenoiseWhitted,
    /// The denoiser is missing or failed.
    #[error(transparent)]
    Denoise(#[from] crate::denoise::DenoiseError),
    /// A pixel outside the image.
    #[error("pixel ({x}, {y}) is outside the {width}x{height} image; expected X from 0 to {} and Y from 0 to {} (X counts columns from the left, Y rows from the top)", width - 1, height - 1)]
    Pixel {
        x: u32,
        y: u32,
        width: u32,
        height: u32,
    },
    /// A sample number beyond the pixel's samples.
    #[error("--sample {sample}: the scene renders {samples} sample(s) a pixel; expected 0 to {}", samples - 1)]
    Sample { sample: u32, samples: u32 },
    /// A sample number beyond the paths the pixel kept: those adaptive
    /// sampling gave it, less any whose value was not finite.
    #[error("--sample {sample}: this pixel kept {paths} path(s) (the scene's {mean} a pixel, or under adaptive sampling its share of that mean, less any whose value was not a finite number); {}", kept_range(*paths))]
    SampleAdaptive { sample: u32, paths: u32, mean: u32 },
    /// A `--reference` image that cannot be read or is not the render's size.
    #[error("--light {light}: the scene has {lights} light(s) in [[lights]]; expected 0 to {}", lights.saturating_sub(1))]
    Light { light: usize, lights: usize },

    #[error("--light: a path's light samples do not say which light they drew; --light picks the light terms of Whitted mode (--integrator whitted)")]
    LightInPathMode,

    #[error("--reference {}: {message}", path.display())]
    Reference { path: PathBuf, message: String },
    /// A `--region` or `--tile` that is empty or leaves the image.
    #[error("{0}")]
    Part(String),
    /// A render-farm tile that cannot be written, read or merged.
    #[error(transparent)]
    Tile(#[from] crate::tiles::TileError),
    /// A valid scene file the tracer still cannot build.
    #[error("{}: {message}", scene.display())]
    Prepare { scene: PathBuf, message: String },
    /// A measurements file that is missing or malformed.
    #[error("{}: {message}", file.display())]
    Measurements { file: PathBuf, message: String },
    /// The gamma plot could not be drawn (no plot in the browser build).
    #[cfg(not(target_arch = "wasm32"))]
    #[error(transparent)]
    Plot(#[from] lab_tools::gamma_plot::PlotError),
    /// An output file could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A scene could not be packed into an archive.
    #[error(transparent)]
    Pack(#[from] crate::pack::PackError),
}

impl Error {
    /// Whether the user's input is at fault (exit 2) rather than the machine (exit 1).
    pub fn is_bad_input(&self) -> bool {
        match self {
            Error::Scene(e) => scene_error_is_bad_input(e),
            Error::Gamma(_)
            | Error::ChartSize { .. }
            | Error::CanvasOption { .. }
            | Error::ImageSize { .. }
            | Error::Samples(_)
            | Error::SceneSamples(_)
            | Error::Reference { .. }
            | Error::NeedsPathMode { .. }
            | Error::Pixel { .. }
            | Error::Sample { .. }
            | Error::SampleAdaptive { .. }
            | Error::Light { .. }
            | Error::LightInPathMode
            | Error::Part(_)
            | Error::Prepare { .. }
            | Error::Measurements { .. } => true,
            Error::DenoiseWhitted => true,
            Error::Denoise(e) => e.is_bad_input(),
            Error::Output(e) => e.is_bad_input(),
            Error::Pack(e) => e.is_bad_input(),
            Error::Tile(e) => e.is_bad_input(),
            #[cfg(not(target_arch = "wasm32"))]
            Error::Plot(_) => false,
        }
    }
}

/// Whether a scene error is the user's input rather than the machine's: a
/// missing, unreadable (permissions) or oversized file, a folder or a
/// device named as the scene is a wrong argument; a failing disk is not.
pub fn scene_error_is_bad_input(error: &SceneError) -> bool {
    use std::io::ErrorKind;
    match error {
        SceneError::Io { source, .. } => matches!(
            source.kind(),
            ErrorKind::NotFound
                | ErrorKind::PermissionDenied
                | ErrorKind::IsADirectory
                | ErrorKind::NotADirectory
                // What `scene_format::read` refuses: folders, devices, size.
                | ErrorKind::InvalidInput
                // A zip archive that is not one, or holds unsafe entries.
                | ErrorKind::InvalidData
        ),
        SceneError::UnknownFormat { .. } | SceneError::Invalid { .. } | SceneError::Several(_) => {
            true
        }
    }
}

/// The samples of a pixel that kept `paths` paths, in words.
fn kept_range(paths: u32) -> String {
    match paths {
        0 => "none of its samples can be explained".into(),
        n => format!("expected 0 to {}", n - 1),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pixel_that_kept_no_path_says_so_rather_than_0_to_0() {
        let none = Error::SampleAdaptive {
            sample: 0,
            paths: 0,
            mean: 16,
        };
        assert!(none
            .to_string()
            .ends_with("none of its samples can be explained"));
        let some = Error::SampleAdaptive {
            sample: 5,
            paths: 3,
            mean: 16,
        };
        assert!(some.to_string().contains("kept 3 path(s)"));
        assert!(some.to_string().ends_with("expected 0 to 2"));
    }
}
