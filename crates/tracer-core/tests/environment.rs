//! The environment light against numbers worked out independently: one
//! bright texel lights a Lambertian plane as a directional light of the
//! texel's solid angle does; importance sampling and uniform sampling
//! converge to the same mean, importance sampling with far less noise on a
//! sky of high contrast; a uniform sky is a white furnace.

use glam::Vec3;
use rayon::prelude::*;
use scene_format::Format;
use std::f64::consts::PI;
use std::path::Path;
use std::sync::Arc;
use tracer_core::integrate::path::PathTracer;
use tracer_core::light::environment::Environment;
use tracer_core::scene::SceneParts;
use tracer_core::Scene;

/// The parts of a scene file (its environment to be set by the test).
fn parts(text: &str) -> SceneParts {
    let file = scene_format::load_str(text, Format::Toml, Path::new("env.toml"))
        .unwrap_or_else(|e| panic!("{e}\n{text}"));
    tracer_core::prepare::parts(&file).expect("prepare")
}

fn with_environment(parts: SceneParts, environment: Environment) -> Scene {
    Scene::new(SceneParts {
        environment: Some(Arc::new(environment)),
        ..parts
    })
}

/// The mean of the image's average channel at `samples` a pixel, scrambled
/// by `seed`.
fn image_mean(scene: &Scene, samples: u32, seed: u32) -> f64 {
    let camera = scene.camera();
    let (width, height) = (camera.width, camera.height);
    let sum: f64 = (0..height)
        .into_par_iter()
        .map(|j| {
            let mut tracer = PathTracer::new(scene).with_seed(seed);
            (0..width)
                .map(|i| f64::from(tracer.pixel(i, j, samples, || false).element_sum()) / 3.0)
                .sum::<f64>()
        })
        .sum();
    sum / f64::from(width * height)
}

fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// A Lambertian floor of albedo 0.5 seen straight from above, nothing else.
const FLOOR: &str = "[camera]\neye = [0, 1, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\nfov = 2\nwidth = 8\nheight = 8\n\
    [render]\nintegrator = \"path\"\nmax_depth = 1\n\
    [[objects]]\nquad = { corner = [-50, 0, 50], edge_u = [100, 0, 0], edge_v = [0, 0, -100] }\n\
    material = { diffuse = [0.5, 0.5, 0.5] }\n";

#[test]
fn one_bright_texel_lights_a_plane_as_a_directional_light_of_its_solid_angle() {
    // Texel (column c, row r) of a W x H image spans phi over 2 pi / W and
    // theta from pi r / H to pi (r + 1) / H: the irradiance it gives a
    // plane facing up is L int cos(theta) d omega = L (2 pi / W)
    // (sin^2 theta_1 - sin^2 theta_0) / 2, and a Lambertian plane of albedo
    // rho shows rho E / pi. Within 2 %.
    let (width, height, radiance) = (64u32, 32u32, 200.0f32);
    for (column, row) in [(40u32, 6u32), (10, 12), (33, 2)] {
        let mut texels = vec![[0.0f32; 3]; (width * height) as usize];
        texels[(row * width + column) as usize] = [radiance; 3];
        let environment = Environment::image(width, height, &texels, 1.0, 0.0);
        let scene = with_environment(parts(FLOOR), environment);
        let (t0, t1) = (
            PI * f64::from(row) / f64::from(height),
            PI * f64::from(row + 1) / f64::from(height),
        );
        let irradiance = f64::from(radiance)
            * (2.0 * PI / f64::from(width))
            * (t1.sin().powi(2) - t0.sin().powi(2))
            / 2.0;
        let expected = 0.5 * irradiance / PI;
        let got = image_mean(&scene, 64, 0);
        assert!(
            (got / expected - 1.0).abs() < 0.02,
            "texel ({column}, {row}): {got} vs {expected}"
        );
    }
}

/// A sky of high contrast: a dim blue dome and a small sun 2000 times as
/// bright, 3 x 3 texels high up.
fn sunny_sky() -> Environment {
    let (width, height) = (128u32, 64u32);
    let texels: Vec<[f32; 3]> = (0..width * height)
        .map(|k| {
            let (x, y) = (k % width, k / width);
            let sun = (80..83).contains(&x) && (10..13).contains(&y);
            match (sun, y < height / 2) {
                (true, _) => [400.0, 380.0, 340.0],
                (false, true) => [0.1, 0.15, 0.3],
                (false, false) => [0.05, 0.05, 0.05],
            }
        })
        .collect();
    Environment::image(width, height, &texels, 1.0, 0.0)
}

#[test]
fn importance_and_uniform_sampling_agree_and_importance_is_far_less_noisy() {
    // A matte ball on a floor under the sunny sky: both ways of drawing
    // the sky's directions give the same mean within 3 standard errors;
    // by luminance, the noise is far lower (the variance of a sample,
    // measured here, about 700 times lower; at least 100 asserted).
    let text = "[camera]\neye = [0, 1.5, 5]\nlook_at = [0, 0.5, 0]\nfov = 40\nwidth = 16\nheight = 12\n\
        [render]\nintegrator = \"path\"\nmax_depth = 3\n\
        [[objects]]\nquad = { corner = [-10, 0, 10], edge_u = [20, 0, 0], edge_v = [0, 0, -20] }\n\
        material = { diffuse = [0.6, 0.6, 0.6] }\n\
        [[objects]]\nsphere = { center = [0, 0.6, 0], radius = 0.6 }\nmaterial = { diffuse = [0.8, 0.4, 0.2] }\n";
    let seeds = 12;
    let estimate = |environment: Environment, samples: u32| {
        let scene = with_environment(parts(text), environment);
        let means: Vec<f64> = (0..seeds)
            .map(|seed| image_mean(&scene, samples, seed))
            .collect();
        mean_and_error(&means)
    };
    // Uniform sampling gets 32 times the samples, so its mean is as sure.
    let importance = estimate(sunny_sky(), 8);
    let uniform = estimate(sunny_sky().sampled_uniformly(), 256);
    let sigma = (importance.1.powi(2) + uniform.1.powi(2)).sqrt();
    assert!(
        (importance.0 - uniform.0).abs() < 3.0 * sigma,
        "{importance:?} vs {uniform:?}"
    );
    // The variance of one sample's estimate, each way.
    let ratio = (uniform.1.powi(2) * 256.0) / (importance.1.powi(2) * 8.0);
    assert!(
        ratio > 100.0,
        "variance ratio {ratio}: {importance:?} vs {uniform:?}"
    );
}

#[test]
fn a_convex_object_under_a_uniform_environment_of_radiance_1_shows_its_albedo() {
    // The white furnace with the environment as the light: a sphere of
    // albedo 0.7 shows 0.7 where it is seen (its light samples and BSDF
    // samples both find the sky, weighted by MIS).
    let text = "[camera]\neye = [0, 0, 6]\nlook_at = [0, 0, 0]\nfov = 20\nwidth = 8\nheight = 8\n\
        [render]\nintegrator = \"path\"\nmax_depth = 4\n\
        [[objects]]\nsphere = { center = [0, 0, 0], radius = 1.5 }\nmaterial = { diffuse = [0.7, 0.7, 0.7] }\n";
    let scene = with_environment(parts(text), Environment::uniform(Vec3::ONE));
    let means: Vec<f64> = (0..8).map(|seed| image_mean(&scene, 16, seed)).collect();
    let (mean, error) = mean_and_error(&means);
    assert!((mean - 0.7).abs() < 4.0 * error + 1e-4, "{mean} +- {error}");
}
