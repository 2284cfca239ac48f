//! `cargo xtask bench --only denoise`: what Open Image Denoise does for
//! the path tracer, measured against the Mitsuba references of the Cornell
//! box and the materials scene: the RMSE of the image denoised at 16 and
//! 64 paths a pixel beside the noisy image's at 16 to 1024 (the issue's
//! goal: denoised at N below noisy at 16 N); and OIDN's time on a
//! 1920x1080 image through the tracer against `oidnBenchmark`'s (shipped
//! with the library) in the same run. Renders go through the pipeline, as
//! `tracer render --samples N --denoise` makes them; those at 16 paths
//! also make the book's figures (`denoise_figure`).

use super::denoise_figure;
use super::path_peers::{self, BenchScene};
use anyhow::{bail, Context, Result};
use std::path::Path;
use std::process::Command;
use std::time::Instant;
use tracer_pipeline::denoise::{self, Guides, Quality};
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
    /// The same of the denoised ones, with the seconds OIDN took.
    pub denoised: Vec<(u32, f64, f64, f64)>,
}

/// OIDN's time on 1920x1080 through the tracer and by its own benchmark.
#[derive(Debug)]
pub struct Timing {
    pub quality: Quality,
    /// Our whole denoise call: the guides' two prefilters and the filter.
    pub ours_s: f64,
    /// `oidnBenchmark`'s `RT.hdr_calb_cnrm` (the main filter with clean
    /// guides, as ours) and `RT.hdr_alb_nrm` (no prefiltering).
    pub benchmark_clean_s: Option<f64>,
    pub benchmark_noisy_aux_s: Option<f64>,
}

pub fn measure(root: &Path) -> Result<(Vec<SceneErrors>, Vec<Timing>)> {
    if let Err(e) = denoise::available() {
        bail!("{e}");
    }
    let mut errors = Vec::new();
    for bench in SCENES {
        errors.push(scene_errors(root, bench)?);
    }
    let timings = [Quality::High, Quality::Fast]
        .into_iter()
        .map(timing)
        .collect::<Result<_>>()?;
    Ok((errors, timings))
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
                result.denoised.push((spp, all, below, d.denoise_seconds));
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

/// OIDN on a 1920x1080 image (a smooth gradient: its time does not depend
/// on the content) through `denoise::denoise`, median of 3, against
/// `oidnBenchmark` on the same size and quality.
fn timing(quality: Quality) -> Result<Timing> {
    eprintln!(
        "bench: Open Image Denoise on 1920x1080, {} ...",
        quality.name()
    );
    let (width, height) = (1920, 1080);
    let mut colour = LinearImage::new(width, height);
    for (i, c) in colour.pixels.iter_mut().enumerate() {
        let (x, y) = ((i as u32 % width) as f32, (i as u32 / width) as f32);
        *c = glam::Vec3::new(x / width as f32, y / height as f32, 0.5);
    }
    let mut normal = LinearImage::new(width, height);
    normal.pixels.fill(glam::Vec3::Z);
    let guides = Guides {
        albedo: colour.clone(),
        normal,
        emission: LinearImage::new(width, height),
    };
    let mut times = Vec::new();
    for _ in 0..3 {
        let start = Instant::now();
        denoise::denoise(&colour, &guides, quality, 0)?;
        times.push(start.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    Ok(Timing {
        quality,
        ours_s: times[1],
        benchmark_clean_s: benchmark("RT.hdr_calb_cnrm.1920x1080", quality),
        benchmark_noisy_aux_s: benchmark("RT.hdr_alb_nrm.1920x1080", quality),
    })
}

/// `oidnBenchmark`'s seconds a run of `name` (its "msec/image" line), or
/// None when it cannot be run.
fn benchmark(name: &str, quality: Quality) -> Option<f64> {
    let exe = crate::oidn::benchmark();
    let output = Command::new(&exe)
        .args(["-r", name, "-n", "3", "-q", quality.name()])
        .output()
        .ok()?;
    let text = String::from_utf8_lossy(&output.stdout);
    // "RT.hdr_calb_cnrm.1920x1080 ... 1234.56 msec/image"
    let msec = text.lines().filter(|l| l.contains(name)).find_map(|l| {
        let words: Vec<&str> = l.split_whitespace().collect();
        let at = words.iter().position(|w| w.starts_with("msec/image"))?;
        words.get(at.checked_sub(1)?)?.parse::<f64>().ok()
    });
    if msec.is_none() {
        eprintln!("bench: cannot read {}'s output:\n{text}", exe.display());
    }
    Some(msec? / 1e3)
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
    println!("\nDenoising (Open Image Denoise 2.5.1, RT filter, high quality, prefiltered albedo and normal, the light seen directly left out and added back)");
    println!(
        "RMSE against the Mitsuba reference (all pixels / pixels whose reference is below 1):"
    );
    for scene in errors {
        println!("  {}", scene.scene);
        for (spp, all, below) in &scene.noisy {
            println!("    noisy    {spp:5} spp: {all:.5} / {below:.5}");
        }
        for (spp, all, below, seconds) in &scene.denoised {
            println!("    denoised {spp:5} spp: {all:.5} / {below:.5}  (OIDN {seconds:.2} s)");
        }
    }
    println!("OIDN on 1920x1080 (median of 3; oidnBenchmark's own figure in the same run):");
    let show = |s: Option<f64>| s.map_or("-".to_string(), |s| format!("{s:.2} s"));
    for t in timings {
        println!(
            "  {:8} ours (2 prefilters + filter) {:.2} s; oidnBenchmark RT.hdr_calb_cnrm (filter alone) {}, RT.hdr_alb_nrm (no prefilter) {}",
            t.quality.name(),
            t.ours_s,
            show(t.benchmark_clean_s),
            show(t.benchmark_noisy_aux_s)
        );
    }
}
