//! A loaded scene and the options of a render in, the linear image and its
//! encoding out: the shaded 3D image, an AOV of a 3D scene, or a 2D canvas
//! drawing.

use crate::load::Loaded;
use crate::options::{Aov, Gamma, Options};
use crate::rendered::{Picture, Rendered, Summary};
use crate::scene3d::{PassCallbacks, PreparedScene};
use crate::{scene3d, Error};
use scene_format::{CanvasFile, SceneFile, SceneKind};
use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// Whether the file asks for path mode itself.
fn is_path(file: &SceneFile) -> bool {
    file.render.integrator == scene_format::Integrator::Path
}

/// Renders a loaded scene on the current rayon pool. A shaded 3D render
/// calls `rows_done(0)` when its rows begin (after preparing the scene),
/// then `rows_done(n)` from the render threads as `n` more rows are done.
pub fn render(
    loaded: &Loaded,
    options: &Options,
    rows_done: &(dyn Fn(u32) + Sync),
) -> Result<Rendered, Error> {
    let never = AtomicBool::new(false);
    let rendered = render_cancellable(loaded, options, rows_done, &never)?;
    Ok(rendered.expect("never cancelled"))
}

/// `render`, given up (`Ok(None)`) soon after `cancel` becomes true.
pub fn render_cancellable(
    loaded: &Loaded,
    options: &Options,
    rows_done: &(dyn Fn(u32) + Sync),
    cancel: &AtomicBool,
) -> Result<Option<Rendered>, Error> {
    match &loaded.kind {
        SceneKind::Scene3d(file) => {
            let was_path = is_path(file);
            let file = options.apply(file)?;
            crate::limits::check_path_mode(&loaded.origins, was_path, &file)?;
            render_3d(file, &loaded.name, options, rows_done, cancel)
        }
        SceneKind::Canvas(file) => draw(file, &loaded.name, options).map(Some),
    }
}

/// `render`, taking the scene: its meshes' triangles are let go once the
/// scene's objects are made of them, before the BVH is built (the peak
/// memory of a large mesh, where the caller needs only the scene's name
/// afterwards).
pub fn render_taking(
    loaded: Loaded,
    options: &Options,
    rows_done: &(dyn Fn(u32) + Sync),
) -> Result<Rendered, Error> {
    let never = AtomicBool::new(false);
    let rendered = match loaded.kind {
        SceneKind::Scene3d(file) => {
            let was_path = is_path(&file);
            let file = Cow::Owned(options.apply_owned(file)?);
            crate::limits::check_path_mode(&loaded.origins, was_path, &file)?;
            render_3d(file, &loaded.name, options, rows_done, &never)?
        }
        SceneKind::Canvas(ref file) => Some(draw(file, &loaded.name, options)?),
    };
    Ok(rendered.expect("never cancelled"))
}

/// The first half of a shaded render of a 3D scene, taking it as
/// `render_taking` does: the prepared scene, to render with
/// `render_prepared` (and to keep: `cache`). A canvas is refused, as
/// with any option of 3D scenes (`option`: the one that asked for this).
pub fn prepare_taking(
    loaded: Loaded,
    options: &Options,
    option: &'static str,
) -> Result<PreparedScene, Error> {
    match loaded.kind {
        SceneKind::Scene3d(file) => {
            let was_path = is_path(&file);
            let file = Cow::Owned(options.apply_owned(file)?);
            crate::limits::check_path_mode(&loaded.origins, was_path, &file)?;
            scene3d::prepare_shaded(file, &loaded.name)
        }
        SceneKind::Canvas(_) => Err(Error::CanvasOption {
            scene: loaded.name,
            option,
        }),
    }
}

/// The shaded image of a prepared scene (`options.aov` is not looked at:
/// a prepared scene is for shaded renders); progress as for `render`.
pub fn render_prepared(
    prepared: &PreparedScene,
    options: &Options,
    rows_done: &(dyn Fn(u32) + Sync),
) -> Result<Rendered, Error> {
    let region = options
        .part
        .map(|p| p.region(prepared.size()))
        .transpose()?;
    let never = AtomicBool::new(false);
    rows_done(0);
    let (image, stats) =
        scene3d::shade_prepared(prepared, options.gamma, region, rows_done, &never)
            .expect("never cancelled");
    let rendered = Rendered {
        image,
        summary: Summary::Shaded(stats),
        denoising: None,
    };
    scene3d::denoised(prepared, region, rendered, options.part.is_some())
}

/// The shaded image of a prepared scene in passes: in path mode samples
/// 0..1, 1..2, 2..4, ... up to the scene's (or `--samples`), `on_pass`
/// called after each with the picture so far (its return false stops the
/// render there); in Whitted mode one pass. The last pass's image, which
/// for a render that ran to its samples is `render_prepared`'s bit for
/// bit; None when `cancel` became true. `options.aov` is not looked at,
/// and the image is not denoised (`denoise_rendered`).
/// `rows_done(n)` as `n` more rows of the current pass are done.
pub fn render_prepared_progressive(
    prepared: &PreparedScene,
    options: &Options,
    cancel: &AtomicBool,
    passes: PassCallbacks,
) -> Result<Option<Rendered>, Error> {
    let region = options
        .part
        .map(|p| p.region(prepared.size()))
        .transpose()?;
    let rendered = scene3d::shade_progressive(prepared, options.gamma, region, cancel, passes);
    Ok(rendered.map(|(image, stats, _)| Rendered {
        image,
        summary: Summary::Shaded(stats),
        denoising: None,
    }))
}

/// A shaded render of `prepared` with `options` denoised, when the scene
/// asks for it (`PreparedScene::denoise`): what `render_prepared` does
/// after rendering, for a render in passes (`render_prepared_progressive`
/// leaves it to its caller, who may denoise each pass instead:
/// `denoise_picture`). A region or tile is given its guides only.
pub fn denoise_rendered(
    prepared: &PreparedScene,
    options: &Options,
    rendered: Rendered,
) -> Result<Rendered, Error> {
    let region = options
        .part
        .map(|p| p.region(prepared.size()))
        .transpose()?;
    scene3d::denoised(prepared, region, rendered, options.part.is_some())
}

/// `picture`, a pass of the whole image of `prepared` at `samples` a
/// pixel, denoised as the scene says (`PreparedScene::denoise`; as it
/// is without one), with the guides kept in `guides` (rendered at the
/// first call; the light seen directly, which follows the samples, again
/// at each): `tracer watch`'s passes.
#[cfg(not(target_arch = "wasm32"))]
pub fn denoise_picture(
    prepared: &PreparedScene,
    guides: &mut Option<crate::denoise::Guides>,
    picture: &Picture,
    samples: u32,
) -> Result<Picture, Error> {
    let Some(settings) = prepared.denoise() else {
        return Ok(picture.clone());
    };
    let guides = match guides {
        Some(guides) => {
            guides.emission = scene3d::emission_guide(&prepared.scene, None, samples);
            guides
        }
        None => guides.insert(scene3d::guides(prepared, None, samples)),
    };
    let threads = rayon::current_num_threads();
    Ok(Picture {
        linear: crate::denoise::denoise(&picture.linear, guides, settings, threads)?,
        encoding: picture.encoding,
    })
}

/// How many samples a pixel the pass after `samples` (of `total`) adds: 0
/// after the last (the passes are `tracer_core::film::passes`).
pub fn next_pass_samples(samples: u32, total: u32) -> u32 {
    tracer_core::film::passes(total)
        .find(|pass| pass.start == samples)
        .map_or(0, |pass| pass.end - pass.start)
}

/// About how long the next pass of a render in passes takes, `next` more
/// samples a pixel, when this one took `this_pass` seconds for `added`:
/// each sample costs about what the last ones did (what a time limit
/// stops the render by).
pub fn next_pass_seconds(this_pass: f64, added: u32, next: u32) -> f64 {
    this_pass * f64::from(next) / f64::from(added.max(1))
}

/// `render_prepared_progressive` of a loaded scene (a 3D scene: a canvas is
/// refused, naming `option`, the option that asked for passes).
pub fn render_progressive(
    loaded: &Loaded,
    options: &Options,
    option: &'static str,
    cancel: &AtomicBool,
    passes: PassCallbacks,
) -> Result<Option<Rendered>, Error> {
    let prepared = prepare_taking(loaded.clone(), options, option)?;
    render_prepared_progressive(&prepared, options, cancel, passes)
}

/// A canvas drawn, refusing options of 3D scenes.
fn draw(file: &CanvasFile, name: &Path, options: &Options) -> Result<Rendered, Error> {
    if let Some(option) = options.option_of_3d() {
        return Err(Error::CanvasOption {
            scene: name.to_path_buf(),
            option,
        });
    }
    Ok(Rendered {
        image: draw_canvas(file, options.gamma),
        summary: Summary::Canvas,
        denoising: None,
    })
}

/// The shaded image or an AOV of `file`, its options applied.
fn render_3d(
    file: Cow<SceneFile>,
    name: &Path,
    options: &Options,
    rows_done: &(dyn Fn(u32) + Sync),
    cancel: &AtomicBool,
) -> Result<Option<Rendered>, Error> {
    let size = (file.camera.width, file.camera.height);
    let region = options.part.map(|p| p.region(size)).transpose()?;
    match options.aov {
        None => scene3d::shade(file, name, options, region, rows_done, cancel),
        Some(aov) => Ok(Some(Rendered {
            image: scene3d::aov(&file, name, aov, options, region, rows_done)?,
            summary: Summary::Aov(aov),
            denoising: None,
        })),
    }
}

/// The size of the image `render` makes of `loaded` with `options`.
pub fn image_size(loaded: &Loaded, options: &Options) -> Result<(u32, u32), Error> {
    match &loaded.kind {
        SceneKind::Scene3d(file) => options.image_size(file),
        SceneKind::Canvas(_) => Ok(loaded.size()),
    }
}

/// A canvas scene drawn, with its own gamma (or `gamma`).
fn draw_canvas(file: &CanvasFile, gamma: Option<Gamma>) -> Picture {
    let mut encoding = lab_tools::canvas::encoding(file);
    if let Some(gamma) = gamma {
        encoding.gamma = gamma.get();
    }
    Picture {
        linear: lab_tools::canvas::draw(file),
        encoding,
    }
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
    fn the_next_pass_doubles_the_samples_up_to_the_total() {
        let next = |samples| next_pass_samples(samples, 20);
        assert_eq!(
            [next(1), next(2), next(8), next(16), next(20)],
            [1, 2, 8, 4, 0]
        );
        assert_eq!(next_pass_samples(1, 1), 0);
    }

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
        assert!(matches!(
            err,
            Error::CanvasOption {
                option: "--aov",
                ..
            }
        ));
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
        // The lab's 12 and the scenes beyond the lab.
        assert!(checked >= 15, "{checked}");
    }
}
