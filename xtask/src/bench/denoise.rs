//! `cargo xtask bench --only denoise`: what Open Image Denoise does for
//! the path tracer, measured against the Mitsuba references of the Cornell
//! box and the materials scene: the RMSE of the image denoised at 16 and
//! 64 paths a pixel beside the noisy image's at 16 to 1024 (the issue's
//! goal: denoised at N below noisy at 16 N), with each of Blender's
//! prefilters (the render's own, `accurate`, then `none` and `fast` on
//! the same noisy image and guides); and OIDN's time on a
//! 1920x1080 image through the tracer against `oidnBenchmark`'s in the
//! same run (`denoise_time`). Renders go through the pipeline, as
//! `tracer render --samples N --denoise` makes them; those at 16 paths
//! also make the book's figures (`denoise_figure`).

use super::denoise_figure;
use super::denoise_time::{self, Timing};
use super::path_peers::{self, BenchScene};
use anyhow::{bail, Context, Result};
use std::path::Path;
use tracer_pipeline::denoise::{self, Prefilter, Settings};
use tracer_pipeline::{Input, LinearImage, Options};

/// The `--only` name of this measurement.
pub const DENOISE: &str = "denoise";

/// Paths a pixel of the noisy renders, and of those denoised.
const NOISY_SPP: [u32; 4] = [16, 64, 256, 1024];
const DENOISED_SPP: [u32; 2] = [16, 64];

/// The scenes, as the path bench has them.
const SCENES: [BenchScene; 2] = [path_peers::CORNELL_BOX, path_peers::MATERIALS];

/// One scene's errors.
#[derive(Debug)]
pub struct SceneErrors {
    pub scene: &'static str,
    /// (spp, RMSE, RMSE where the reference is below 1) of the noisy renders.
    pub noisy: Vec<(u32, f64, f64)>,
    /// The same of the denoised ones, with their prefilter and the
    /// seconds OIDN took.
    pub denoised: Vec<(u32, Prefilter, f64, f64, f64)>,
}

pub fn measure(root: &Path) -> Result<(Vec<SceneErrors>, Vec<Timing>)> {
    if let Err(e) = denoise::available() {
        bail!("{e}");
    }
    let mut errors = Vec::new();
    for bench in SCENES {
        errors.push(scene_errors(root, bench)?);
    }
    Ok((errors, denoise_time::measure()?))
}

fn scene_errors(root: &Path, bench: BenchScene) -> Result<SceneErrors> {
    let reference = to_linear(&path_peers::read_image(&root.join(bench.reference))?);
    let input = Input::File(root.join(bench.scene));
    let loaded = tracer_pipeline::load(&input)?;
    let mut result = SceneErrors {
        scene: bench.scene,
        noisy: Vec::new(),
        denoised: Vec::new(),
    };
    for spp in NOISY_SPP {
        eprintln!("bench: {} at {spp} paths a pixel ...", bench.scene);
        let options = Options {
            samples: Some(spp),
            denoise: DENOISED_SPP.contains(&spp),
            ..Options::default()
        };
        let rendered = tracer_pipeline::render(&loaded, &options, &|_| {})?;
        let image = &rendered.image.linear;
        match &rendered.denoising {
            Some(d) => {
                let noisy = d.noisy.as_ref().context("a whole image is denoised")?;
                result
                    .noisy
                    .push((spp, rmse(noisy, &reference), dim(noisy, &reference)));
                let (all, below) = (rmse(image, &reference), dim(image, &reference));
                let prefilter = d.settings.prefilter;
                result
                    .denoised
                    .push((spp, prefilter, all, below, d.denoise_seconds));
                for other in Prefilter::ALL.into_iter().filter(|&p| p != prefilter) {
                    let settings = Settings {
                        prefilter: other,
                        ..d.settings
                    };
                    let start = std::time::Instant::now();
                    let image = denoise::denoise(noisy, &d.guides, settings, 0)?;
                    let seconds = start.elapsed().as_secs_f64();
                    let (all, below) = (rmse(&image, &reference), dim(&image, &reference));
                    result.denoised.push((spp, other, all, below, seconds));
                }
                if spp == denoise_figure::SPP {
                    denoise_figure::write(root, &bench, &rendered, &reference)?;
                }
            }
            None => result
                .noisy
                .push((spp, rmse(image, &reference), dim(image, &reference))),
        }
    }
    Ok(result)
}

pub(super) fn to_linear(image: &path_peers::FloatImage) -> LinearImage {
    let mut linear = LinearImage::new(image.width, image.height);
    for (pixel, rgb) in linear.pixels.iter_mut().zip(image.rgb.chunks(3)) {
        *pixel = glam::Vec3::new(rgb[0], rgb[1], rgb[2]);
    }
    linear
}

fn rmse(a: &LinearImage, b: &LinearImage) -> f64 {
    tracer_pipeline::reference::rmse(a, b)
}

/// The RMSE over the pixels whose reference has every channel below 1: the
/// image without the lamps and highlights, whose values of 10 or more
/// weigh in the RMSE far beyond what a display shows of them.
pub(super) fn dim(a: &LinearImage, reference: &LinearImage) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for (x, r) in a.pixels.iter().zip(&reference.pixels) {
        if r.max_element() < 1.0 {
            sum += (x.as_dvec3() - r.as_dvec3()).length_squared();
            n += 3;
        }
    }
    (sum / n.max(1) as f64).sqrt()
}

pub fn report((errors, timings): &(Vec<SceneErrors>, Vec<Timing>)) {
    println!("\nDenoising (Open Image Denoise 2.5.1, RT filter, high quality, the light seen directly left out and added back; Blender's prefilters of the albedo and normal: accurate, the default, none, fast)");
    println!(
        "RMSE against the Mitsuba reference (all pixels / pixels whose reference is below 1):"
    );
    for scene in errors {
        println!("  {}", scene.scene);
        for (spp, all, below) in &scene.noisy {
            println!("    noisy    {spp:5} spp: {all:.5} / {below:.5}");
        }
        for (spp, prefilter, all, below, seconds) in &scene.denoised {
            let prefilter = prefilter.name();
            println!(
                "    denoised {spp:5} spp: {all:.5} / {below:.5}  ({prefilter} prefilter, OIDN {seconds:.2} s)"
            );
        }
    }
    denoise_time::report(timings);
}
