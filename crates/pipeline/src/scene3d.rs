//! Every call into tracer-core's 3D API: preparing a scene file, rendering
//! it shaded or as an AOV, encoding it. The rest of the pipeline reaches
//! the core through here (and names the core's `Aov` list), so a change of
//! that API stays in this file.

use crate::clock::Instant;
use crate::denoise::{Guides, Settings};
use crate::options::{Aov, Gamma, Options};
use crate::rendered::{Estimator, Picture, ShadedStats};
use crate::Error;
use scene_format::SceneFile;
use std::borrow::Cow;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use tracer_core::image::Saturation;
use tracer_core::{Output, Region, RenderJob, Scene};

/// A 3D scene prepared for shaded renders (lean: its BVH, not its
/// objects), with what a render's summary says of it; what `--cache`
/// keeps.
#[derive(Debug, serde::Serialize, serde::Deserialize)]
pub struct PreparedScene {
    pub(crate) scene: Scene,
    /// Objects in the scene file (a mesh is one).
    pub(crate) objects: usize,
    /// The scene file's `[render] time_limit`, in seconds.
    pub(crate) time_limit: Option<f32>,
    /// How the render is denoised, when it is to be (`[render] denoise`
    /// or `--denoise`, in path mode).
    pub(crate) denoise: Option<Settings>,
    #[serde(skip)]
    pub(crate) prepare_seconds: f64,
}

impl PreparedScene {
    /// The image's size in pixels, (width, height).
    pub fn size(&self) -> (u32, u32) {
        let camera = self.scene.camera();
        (camera.width, camera.height)
    }

    /// Whether the scene is path traced (and so renders in passes).
    pub fn is_path_traced(&self) -> bool {
        self.scene.trace_settings().integrator == tracer_core::scene::Integrator::Path
    }

    /// The scene file's `[render] time_limit`, in seconds.
    pub fn time_limit(&self) -> Option<f64> {
        self.time_limit.map(crate::load::as_written)
    }

    /// How the render is denoised, if it is to be.
    pub fn denoise(&self) -> Option<Settings> {
        self.denoise
    }
}

/// The shaded image, with the scene's gamma (or `options.gamma`) and
/// saturation rule for its encoding, its pixels moved by
/// `options.pixel_shift`; `rows_done(0)` once the scene is prepared, then
/// `rows_done(n)` from the render threads as `n` more rows are done.
pub(crate) fn shade(
    file: Cow<SceneFile>,
    name: &Path,
    options: &Options,
    region: Option<Region>,
    rows_done: &(dyn Fn(u32) + Sync),
    cancel: &AtomicBool,
) -> Result<Option<crate::Rendered>, Error> {
    let mut prepared = prepare_shaded(file, name)?;
    if let Some([x, y]) = options.pixel_shift {
        prepared.scene.shift_pixels(glam::Vec2::new(x, y));
    }
    rows_done(0);
    let Some((image, stats)) = shade_prepared(&prepared, options.gamma, region, rows_done, cancel)
    else {
        return Ok(None);
    };
    let rendered = crate::Rendered {
        image,
        summary: crate::Summary::Shaded(stats),
        denoising: None,
    };
    denoised(&prepared, region, rendered, options.part.is_some()).map(Some)
}

/// The scene of `file`, prepared and lean (see `prepare_releasing`).
pub(crate) fn prepare_shaded(file: Cow<SceneFile>, name: &Path) -> Result<PreparedScene, Error> {
    let start = Instant::now();
    let objects = file.objects.len();
    let time_limit = file.render.time_limit;
    let denoise = denoise_asked(&file)?;
    let scene = prepare_releasing(file, name)?;
    Ok(PreparedScene {
        scene,
        objects,
        time_limit,
        denoise,
        prepare_seconds: start.elapsed().as_secs_f64(),
    })
}

/// The denoiser's settings if `file` (its options applied) asks for
/// denoising in path mode; checked before any work that the library is
/// there. Whitted mode's images have no noise: its `denoise` key is
/// ignored (with a warning, `scene_format::checks`), and the browser
/// build has no denoiser.
fn denoise_asked(file: &SceneFile) -> Result<Option<Settings>, Error> {
    let render = &file.render;
    if !render.denoise
        || render.integrator != scene_format::Integrator::Path
        || cfg!(target_arch = "wasm32")
    {
        return Ok(None);
    }
    #[cfg(not(target_arch = "wasm32"))]
    crate::denoise::available()?;
    Ok(Some(Settings {
        quality: render.denoise_quality.unwrap_or_default(),
        prefilter: render.denoise_prefilter.unwrap_or_default(),
    }))
}

/// Samples per pixel of the denoiser's guides: first hits (and mirrors
/// and glass) only, so cheap beside the paths; enough to average a
/// pixel's edges and textures as its paths do.
pub const GUIDE_SAMPLES: u32 = 16;

/// The guides of `region` (or the whole image) of a prepared scene
/// rendered at `samples` a pixel: the albedo and shading-normal AOVs, the
/// normal back in -1..1, and the light seen directly (`emission_guide`).
pub(crate) fn guides(prepared: &PreparedScene, region: Option<Region>, samples: u32) -> Guides {
    let scene = &prepared.scene;
    let job = job(scene, region).with_samples(GUIDE_SAMPLES);
    let aov = |aov| tracer_core::render(scene, &job.with_output(Output::Aov(aov)), &|_| {}).image;
    let albedo = aov(Aov::Albedo);
    let mut normal = aov(Aov::ShadingNormal);
    for n in &mut normal.pixels {
        *n = *n * 2.0 - glam::Vec3::ONE;
    }
    Guides {
        albedo,
        normal,
        emission: emission_guide(scene, region, samples),
    }
}

/// The light the denoiser takes out of a render of `region` (or the whole
/// image) at `samples` a pixel and adds back: what the render's camera
/// rays saw directly (`seen_light`), and what mirrors and glass show,
/// which a path's camera ray does not see alone (`reflected_light`).
pub(crate) fn emission_guide(
    scene: &Scene,
    region: Option<Region>,
    samples: u32,
) -> tracer_core::LinearImage {
    let mut emission = reflected_light(scene, job(scene, region).region, samples);
    let seen = seen_light(scene, region, samples);
    for (e, s) in emission.pixels.iter_mut().zip(&seen.pixels) {
        *e += *s;
    }
    emission
}

/// The light the camera rays of a path-mode render of `region` (or the
/// whole image) at `samples` a pixel saw directly, each pixel as the render counts it
/// (`PathTracer::seen_light`): the render less this is exactly the light
/// that bounced, which the denoiser filters (`denoise::emission`).
fn seen_light(scene: &Scene, region: Option<Region>, samples: u32) -> tracer_core::LinearImage {
    use rayon::prelude::*;
    let camera = scene.camera();
    let region = job(scene, region)
        .region
        .within(camera.width, camera.height);
    let rows: Vec<Vec<glam::Vec3>> = (region.y0..region.y1)
        .into_par_iter()
        .map(|y| {
            let mut tracer = tracer_core::integrate::path::PathTracer::new(scene);
            (region.x0..region.x1)
                .map(|x| tracer.seen_light(x, y, 0..samples))
                .collect()
        })
        .collect();
    let mut light = tracer_core::LinearImage::new(region.width(), region.height());
    light.pixels = rows.concat();
    light
}

/// The light seen through mirrors and glass (`Aov::ReflectedEmission`) of
/// `region` at [`GUIDE_SAMPLES`] a pixel, and at more at its edges
/// (`denoise::emission`; for a render of `samples` a pixel), found with
/// one pixel more on each side so that a tile's are the whole image's.
fn reflected_light(scene: &Scene, region: Region, samples: u32) -> tracer_core::LinearImage {
    use crate::denoise::emission::{edge_rows, edge_samples, widened};
    use rayon::prelude::*;
    let camera = scene.camera();
    let region = region.within(camera.width, camera.height);
    let wide = widened(region, (camera.width, camera.height));
    let output = Output::Aov(Aov::ReflectedEmission);
    let render = |region, samples| {
        let job = RenderJob {
            region,
            samples,
            output,
        };
        tracer_core::render(scene, &job, &|_| {}).image
    };
    let coarse = render(wide, GUIDE_SAMPLES);
    let mut light = tracer_core::LinearImage::new(region.width(), region.height());
    for y in region.y0..region.y1 {
        for x in region.x0..region.x1 {
            let i = ((y - region.y0) * region.width() + x - region.x0) as usize;
            light.pixels[i] = coarse.get(x - wide.x0, y - wide.y0);
        }
    }
    let rows = edge_rows(&coarse, wide, region);
    let samples = edge_samples(samples);
    let fine: Vec<_> = rows.par_iter().map(|&row| render(row, samples)).collect();
    for (row, pixels) in rows.iter().zip(fine) {
        let start = ((row.y0 - region.y0) * region.width() + row.x0 - region.x0) as usize;
        light.pixels[start..start + pixels.pixels.len()].copy_from_slice(&pixels.pixels);
    }
    light
}

/// `rendered`, a shaded render of `region` of `prepared`, denoised when
/// the scene asks for it: its guides rendered and, unless `guides_only`
/// (a tile, denoised once merged), OIDN run on the current thread pool's
/// threads.
pub(crate) fn denoised(
    prepared: &PreparedScene,
    region: Option<Region>,
    mut rendered: crate::Rendered,
    guides_only: bool,
) -> Result<crate::Rendered, Error> {
    let Some(settings) = prepared.denoise else {
        return Ok(rendered);
    };
    let start = Instant::now();
    let samples = match &rendered.summary {
        crate::Summary::Shaded(stats) => stats.samples,
        _ => prepared.scene.samples(),
    };
    let guides = guides(prepared, region, samples);
    let guide_seconds = start.elapsed().as_secs_f64();
    let denoising = crate::Denoising {
        guides,
        settings,
        noisy: None,
        guide_seconds,
        denoise_seconds: 0.0,
    };
    rendered.denoising = Some(Box::new(denoising));
    if !guides_only {
        denoise_image(&mut rendered)?;
    }
    Ok(rendered)
}

/// Replaces the render's image by its denoised one, keeping the noisy one
/// beside it (the guides are in its `denoising`).
#[cfg(not(target_arch = "wasm32"))]
fn denoise_image(rendered: &mut crate::Rendered) -> Result<(), Error> {
    let Some(denoising) = rendered.denoising.as_deref_mut() else {
        return Ok(());
    };
    let start = Instant::now();
    // As many threads as the render had (its pool, `--threads`).
    let threads = rayon::current_num_threads();
    let (image, guides) = (&rendered.image.linear, &denoising.guides);
    let clean = crate::denoise::denoise(image, guides, denoising.settings, threads)?;
    denoising.denoise_seconds = start.elapsed().as_secs_f64();
    denoising.noisy = Some(std::mem::replace(&mut rendered.image.linear, clean));
    Ok(())
}

/// No denoiser in the browser (OIDN is a native library): the image stays
/// as rendered, the guides beside it.
#[cfg(target_arch = "wasm32")]
fn denoise_image(_: &mut crate::Rendered) -> Result<(), Error> {
    Ok(())
}

/// `shade` of a prepared scene; progress from the render threads only.
pub(crate) fn shade_prepared(
    prepared: &PreparedScene,
    gamma: Option<Gamma>,
    region: Option<Region>,
    rows_done: &(dyn Fn(u32) + Sync),
    cancel: &AtomicBool,
) -> Option<(Picture, ShadedStats)> {
    let scene = &prepared.scene;
    let start = Instant::now();
    let job = job(scene, region);
    let rendered = tracer_core::render_cancellable(scene, &job, rows_done, cancel)?;
    let seconds = start.elapsed().as_secs_f64();
    let rays = (rendered.rays, job.samples);
    Some(shaded(prepared, gamma, rendered.image, rays, seconds))
}

/// What a render in passes reports to: `rows_done(0)` as the passes begin
/// (the scene prepared), `rows_done(n)` as `n` more rows of the pass under
/// way are done, and `on_pass` after each pass (its return false stops the
/// render there).
pub type PassCallbacks<'a> = (&'a (dyn Fn(u32) + Sync), &'a mut dyn FnMut(Pass) -> bool);

/// A pass of a progressive render: the picture so far, and how far it got.
pub struct Pass<'a> {
    pub picture: &'a Picture,
    pub stats: &'a ShadedStats,
    /// Samples per pixel so far, of `total`.
    pub samples: u32,
    pub total: u32,
}

/// `shade_prepared` in passes of doubling samples per pixel (path mode:
/// `tracer_core::film`), `on_pass` called after each with the picture so
/// far; it returns false to stop there. `rows_done(0)` as the passes
/// begin (the scene prepared), then `rows_done(n)` as `n` more rows of the
/// current pass are done. The last pass's picture (and the samples it
/// has), or None when cancelled. A scene in Whitted mode is one pass.
pub(crate) fn shade_progressive(
    prepared: &PreparedScene,
    gamma: Option<Gamma>,
    region: Option<Region>,
    cancel: &AtomicBool,
    (rows_done, on_pass): PassCallbacks,
) -> Option<(Picture, ShadedStats, u32)> {
    let scene = &prepared.scene;
    let job = job(scene, region);
    rows_done(0);
    if scene.trace_settings().integrator != tracer_core::scene::Integrator::Path {
        let (picture, stats) = shade_prepared(prepared, gamma, region, rows_done, cancel)?;
        let samples = job.samples;
        on_pass(Pass {
            picture: &picture,
            stats: &stats,
            samples,
            total: samples,
        });
        return Some((picture, stats, samples));
    }
    let start = Instant::now();
    let mut film = tracer_core::film::Film::new(scene, job.region);
    let mut rays = tracer_core::RayStats::default();
    let mut last = None;
    for pass in tracer_core::film::passes(job.samples) {
        rays = rays + film.add_pass(scene, pass, rows_done, cancel)?;
        let seconds = start.elapsed().as_secs_f64();
        let image = film.image();
        let (picture, stats) = shaded(prepared, gamma, image, (rays, film.samples()), seconds);
        let go_on = on_pass(Pass {
            picture: &picture,
            stats: &stats,
            samples: film.samples(),
            total: job.samples,
        });
        last = Some((picture, stats, film.samples()));
        if !go_on {
            break;
        }
    }
    last
}

/// The picture of a rendered `image` of `prepared` (`rays` traced in
/// `render_seconds`, `samples` a pixel), with the scene's gamma (or `gamma`) and saturation
/// rule, and its numbers.
fn shaded(
    prepared: &PreparedScene,
    gamma: Option<Gamma>,
    image: tracer_core::LinearImage,
    (rays, samples): (tracer_core::RayStats, u32),
    render_seconds: f64,
) -> (Picture, ShadedStats) {
    let scene = &prepared.scene;
    let mut encoding = *scene.encoding();
    if let Some(gamma) = gamma {
        encoding.gamma = gamma.get();
    }
    // Counted here, where the rule is applied, so the count is the image's.
    let forced_white = match encoding.saturation {
        Saturation::White => image
            .pixels
            .iter()
            .filter(|c| c.max_element() > 1.0)
            .count() as u64,
        Saturation::Clamp => 0,
    };
    let stats = ShadedStats {
        objects: prepared.objects,
        primitives: scene.unique_primitives(),
        rays: rays.total(),
        prepare_seconds: prepared.prepare_seconds,
        render_seconds,
        forced_white,
        pixels: image.pixels.len() as u64,
        samples,
        dropped: rays.dropped,
        cut_trees: rays.cut_trees,
        point_lit_mean: point_lit_mean(scene, &image),
        estimator: estimator(scene),
    };
    let picture = Picture {
        linear: image,
        encoding,
    };
    (picture, stats)
}

/// The estimator a path-mode render of `scene` used.
fn estimator(scene: &Scene) -> Option<Estimator> {
    let trace = scene.trace_settings();
    (trace.integrator == tracer_core::scene::Integrator::Path).then_some(Estimator {
        path_reuse: trace.path_reuse,
        camera_rays: trace.camera_rays,
        adaptive: trace.adaptive,
    })
}

/// The mean luminance of a path-mode image of a scene with point lights.
fn point_lit_mean(scene: &Scene, image: &tracer_core::LinearImage) -> Option<f32> {
    let path_mode = scene.trace_settings().integrator == tracer_core::scene::Integrator::Path;
    if !path_mode || scene.path_lights().points().is_empty() || image.pixels.is_empty() {
        return None;
    }
    let luminance = glam::Vec3::new(0.2126, 0.7152, 0.0722);
    let sum: f64 = image
        .pixels
        .iter()
        .map(|c| f64::from(c.dot(luminance)))
        .sum();
    Some((sum / image.pixels.len() as f64) as f32)
}

/// The image of one AOV, encoded linearly unless `options.gamma` is given
/// (the depth AOV as distances with `options.raw_depth`); progress is
/// reported as for `shade`.
pub(crate) fn aov(
    file: &SceneFile,
    name: &Path,
    aov: Aov,
    options: &Options,
    region: Option<Region>,
    rows_done: &(dyn Fn(u32) + Sync),
) -> Result<Picture, Error> {
    let scene = prepare(file, name)?;
    let mut encoding = tracer_core::aov::AOV_ENCODING;
    if let Some(gamma) = options.gamma {
        encoding.gamma = gamma.get();
    }
    let output = match aov {
        Aov::Depth if options.raw_depth => Output::Distance,
        _ => Output::Aov(aov),
    };
    let job = job(&scene, region).with_output(output);
    rows_done(0);
    let linear = tracer_core::render(&scene, &job, rows_done).image;
    Ok(Picture { linear, encoding })
}

/// The whole image, or only `region` of it (checked by the caller).
fn job(scene: &Scene, region: Option<Region>) -> RenderJob {
    let full = RenderJob::full(scene);
    RenderJob {
        region: region.unwrap_or(full.region),
        ..full
    }
}

fn prepare(file: &SceneFile, name: &Path) -> Result<Scene, Error> {
    tracer_core::prepare(file).map_err(|e| prepare_error(name, e))
}

/// `prepare`, holding no more memory than the render needs: a file owned
/// here is dropped before the BVH is built, and with it the meshes'
/// triangles when nothing else holds them; the objects go once the BVH
/// is built (a lean scene).
fn prepare_releasing(file: Cow<SceneFile>, name: &Path) -> Result<Scene, Error> {
    let parts = tracer_core::prepare::parts(&file).map_err(|e| prepare_error(name, e))?;
    drop(file);
    Ok(Scene::lean(parts))
}

fn prepare_error(name: &Path, e: tracer_core::PrepareError) -> Error {
    Error::Prepare {
        scene: name.to_path_buf(),
        message: e.to_string(),
    }
}
