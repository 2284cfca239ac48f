//! A loaded scene and the options of a render in, the 8-bit image out: the
//! shaded 3D image, an AOV of a 3D scene, or a 2D canvas drawing.

use crate::load::Loaded;
use crate::{scene3d, Error};
use image::RgbImage;
use scene_format::{CanvasFile, SceneKind};
use std::path::{Path, PathBuf};

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
}

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

/// Renders a loaded scene on the current rayon pool. A shaded 3D render
/// calls `rows_done(0)` when its rows begin (after preparing the scene),
/// then `rows_done(n)` from the render threads as `n` more rows are done.
pub fn render(
    loaded: &Loaded,
    options: &Options,
    rows_done: &(dyn Fn(u32) + Sync),
) -> Result<Rendered, Error> {
    match (&loaded.kind, options.aov) {
        (SceneKind::Scene3d(file), None) => {
            let (image, stats) = scene3d::shade(file, &loaded.name, options.gamma, rows_done)?;
            Ok(Rendered {
                image,
                summary: Summary::Shaded(stats),
            })
        }
        (SceneKind::Scene3d(file), Some(aov)) => Ok(Rendered {
            image: scene3d::aov(file, &loaded.name, aov, options.gamma, rows_done)?,
            summary: Summary::Aov(aov),
        }),
        (SceneKind::Canvas(file), None) => Ok(Rendered {
            image: draw_canvas(file, options.gamma),
            summary: Summary::Canvas,
        }),
        (SceneKind::Canvas(_), Some(_)) => Err(Error::AovOfCanvas {
            scene: loaded.name.clone(),
        }),
    }
}

/// A canvas scene drawn and encoded with its own gamma (or `gamma`).
fn draw_canvas(file: &CanvasFile, gamma: Option<Gamma>) -> RgbImage {
    let mut encoding = lab_tools::canvas::encoding(file);
    if let Some(gamma) = gamma {
        encoding.gamma = gamma.get();
    }
    lab_tools::canvas::draw(file).encode(&encoding)
}

/// Where a render goes when no output is named: the scene's file stem
/// (with `-AOV` for an AOV) and `.png`, in the current folder.
pub fn default_output(scene: &Path, aov: Option<Aov>) -> PathBuf {
    let stem = scene.file_stem().unwrap_or(scene.as_os_str());
    let mut name = stem.to_os_string();
    if let Some(aov) = aov {
        name.push(format!("-{}", aov.name()));
    }
    PathBuf::from(name).with_extension("png")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::{load, Input};

    #[test]
    fn gamma_must_be_a_number_above_0() {
        assert_eq!(Gamma::new(2.2).unwrap().get(), 2.2);
        for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            let err = Gamma::new(bad).unwrap_err();
            assert!(err.is_bad_input());
            assert!(err
                .to_string()
                .starts_with("--gamma: expected a number > 0"));
        }
    }

    #[test]
    fn default_outputs_are_named_after_the_scene() {
        let scene = Path::new("scenes/shadows.toml");
        assert_eq!(default_output(scene, None), Path::new("shadows.png"));
        assert_eq!(
            default_output(scene, Some(Aov::RayDirX)),
            Path::new("shadows-ray-dir-x.png")
        );
    }

    #[test]
    fn an_aov_of_a_canvas_is_bad_input() {
        let robot = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/robot.toml");
        let loaded = load(&Input::File(robot)).unwrap();
        let options = Options {
            aov: Some(Aov::Depth),
            ..Options::default()
        };
        let err = render(&loaded, &options, &|_| {}).unwrap_err();
        assert!(matches!(err, Error::AovOfCanvas { .. }));
        assert!(err.is_bad_input());
    }

    #[test]
    fn no_lab_scene_forces_enough_pixels_white_to_warn() {
        let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
        let mut checked = 0;
        for entry in std::fs::read_dir(scenes).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_none_or(|e| e != "toml") {
                continue;
            }
            let loaded = load(&Input::File(path.clone())).unwrap();
            let Summary::Shaded(stats) = render(&loaded, &Options::default(), &|_| {})
                .unwrap()
                .summary
            else {
                continue;
            };
            assert_eq!(stats.forced_white_warning(), None, "{}", path.display());
            checked += 1;
        }
        assert_eq!(checked, 12);
    }
}
