//! `tracer explain`: one pixel's sample traced again by the render's own
//! integrator, with every ray, hit, light term and weight kept
//! (`tracer_core::explain`), and the pixel as the render writes it.

use crate::load::Loaded;
use crate::options::Options;
use crate::Error;
use glam::Vec3;
use scene_format::SceneKind;
use std::sync::atomic::AtomicBool;
pub use tracer_core::explain::{
    Cut, Explanation, LeftOut, Limits, Lit, Outcome, RayNode, Trace, DEFAULT_MAX_EVENTS,
};
pub use tracer_core::image::Saturation;
use tracer_core::image::{encode_pixel, Encoding};
pub use tracer_core::integrate::record::{PathEvent, PathEventKind, RayKind, Stop};
pub use tracer_core::names::Names;
use tracer_core::{Region, RenderJob};

/// A pixel explained: one sample's tree, and the pixel the render writes.
#[derive(Debug, Clone)]
pub struct ExplainedPixel {
    pub explanation: Explanation,
    /// The image's size.
    pub size: (u32, u32),
    /// The pixel's linear colour (the mean of its samples) and its 8-bit
    /// value, by `encoding`: the rendered pixel, bit for bit.
    pub linear: Vec3,
    pub rgb8: [u8; 3],
    pub encoding: Encoding,
    /// Whether the scene is path traced.
    pub path_traced: bool,
    /// The samples (in path mode, the paths) the pixel is the mean of:
    /// the image's, or under adaptive sampling its share.
    pub paths: u32,
    /// What the file calls the objects and materials the tree numbers.
    pub names: Names,
    /// Where the tree's rays are, in the scene and in the image.
    pub drawing: crate::explain_draw::Drawing,
    /// The scene's shapes and camera, for the playground's 3D view.
    pub scene_view: crate::explain_scene::SceneView,
}

/// Pixel (x, y) (x from the left, y from the top, of the written image)
/// of `loaded` rendered with `options`, its sample `sample` explained
/// within the default limits.
pub fn explain(
    loaded: &Loaded,
    options: &Options,
    pixel: (u32, u32),
    sample: u32,
) -> Result<ExplainedPixel, Error> {
    explain_within(loaded, options, pixel, sample, Limits::default())
}

/// [`explain`], the tree kept within `limits` (`tracer explain
/// --max-events N --light K`).
pub fn explain_within(
    loaded: &Loaded,
    options: &Options,
    (x, y): (u32, u32),
    sample: u32,
    limits: Limits,
) -> Result<ExplainedPixel, Error> {
    let SceneKind::Scene3d(file) = &loaded.kind else {
        return Err(Error::CanvasOption {
            scene: loaded.name.clone(),
            option: "explain",
        });
    };
    let was_path = file.render.integrator == scene_format::Integrator::Path;
    let file = options.apply(file)?;
    crate::limits::check_path_mode(&loaded.origins, was_path, &file)?;
    let (width, height) = (file.camera.width, file.camera.height);
    if x >= width || y >= height {
        return Err(Error::Pixel {
            x,
            y,
            width,
            height,
        });
    }
    let samples = file.render.samples;
    if sample >= samples {
        return Err(Error::Sample { sample, samples });
    }
    if let Some(light) = limits.light {
        if file.render.integrator == scene_format::Integrator::Path {
            return Err(Error::LightInPathMode);
        }
        let lights = file.lights.len();
        if light >= lights {
            return Err(Error::Light { light, lights });
        }
    }
    // Not lean: the tree lists the primitives each ray was tested against.
    let (scene, names) =
        tracer_core::prepare::prepare_named(&file).map_err(|e| Error::Prepare {
            scene: loaded.name.clone(),
            message: e.to_string(),
        })?;
    let job = RenderJob {
        region: Region {
            x0: x,
            y0: y,
            x1: x + 1,
            y1: y + 1,
        },
        ..RenderJob::full(&scene)
    };
    let never = AtomicBool::new(false);
    let path_traced = scene.trace_settings().integrator == tracer_core::scene::Integrator::Path;
    let (pixel, paths) = if path_traced {
        // The render's own film, which knows the paths adaptive sampling
        // gave the pixel.
        let mut film = tracer_core::film::Film::new(&scene, job.region);
        film.add_pass(&scene, 0..job.samples, &|_| {}, &never)
            .expect("never cancelled");
        (film.image().pixels[0], film.paths()[0])
    } else {
        let rendered = tracer_core::render_cancellable(&scene, &job, &|_| {}, &never);
        (
            rendered.expect("never cancelled").image.pixels[0],
            job.samples,
        )
    };
    if sample >= paths {
        return Err(Error::SampleAdaptive {
            sample,
            paths,
            mean: samples,
        });
    }
    let explanation = tracer_core::explain::explain_within(&scene, (x, y), samples, sample, limits);
    let drawing = crate::explain_draw::drawing(&scene, &explanation, (x, y), &names);
    let scene_view = crate::explain_scene::scene_view(&scene, &names, (x, y));
    let mut encoding = *scene.encoding();
    if let Some(gamma) = options.gamma {
        encoding.gamma = gamma.get();
    }
    Ok(ExplainedPixel {
        explanation,
        size: (width, height),
        linear: pixel,
        rgb8: encode_pixel(pixel, &encoding),
        encoding,
        path_traced,
        paths,
        names,
        drawing,
        scene_view,
    })
}
