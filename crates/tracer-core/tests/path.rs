//! The path tracer against light transport worked out independently:
//! furnaces, a point light's and a square light's irradiance, and the
//! three ways of finding light converging to one mean. Monte Carlo
//! estimates use fixed seeds; each bound is a few standard errors, the
//! errors estimated from independent renders (other seeds).

mod common;

use common::path_image;
use glam::Vec3;
use rayon::prelude::*;
use scene_format::Format;
use std::f64::consts::PI;
use std::path::Path;
use tracer_core::integrate::path::{PathTracer, PixelSum, Strategy};
use tracer_core::{prepare, Scene};

fn scene_from(text: &str) -> Scene {
    let file = scene_format::load_str(text, Format::Toml, Path::new("path.toml"))
        .unwrap_or_else(|e| panic!("{e}\n{text}"));
    prepare(&file).expect("prepare")
}

/// `path_image` as renders trace rows (`PathTracer::add_row`), with groups of
/// `reuse` pixels sharing their paths' first bounces.
fn render_rows(scene: &Scene, samples: u32, seed: u32, reuse: u32) -> Vec<Vec3> {
    let camera = scene.camera();
    let (width, height) = (camera.width, camera.height);
    (0..height)
        .into_par_iter()
        .flat_map_iter(|j| {
            let mut tracer = PathTracer::new(scene).with_seed(seed).with_reuse(reuse);
            let mut sums = vec![PixelSum::default(); width as usize];
            tracer.add_row((0..width, j), 0..samples, &mut sums, || false);
            sums.into_iter().map(|s| s.mean()).collect::<Vec<_>>()
        })
        .collect()
}

/// The mean of every pixel's average channel.
fn image_mean(image: &[Vec3]) -> f64 {
    image
        .iter()
        .map(|c| f64::from(c.element_sum()) / 3.0)
        .sum::<f64>()
        / image.len() as f64
}

/// Mean and standard error of `values`, as independent estimates.
fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// The mean over the pixels `pick` keeps (by index) of the image's
/// average channel, for each of `seeds` independent renders.
fn means_over_seeds(
    scene: &Scene,
    samples: u32,
    seeds: u32,
    strategy: Strategy,
    pick: impl Fn(usize) -> bool + Sync,
) -> Vec<f64> {
    (0..seeds)
        .map(|seed| {
            let image = path_image(scene, samples, seed, strategy);
            let kept: Vec<f64> = image
                .iter()
                .enumerate()
                .filter(|(k, _)| pick(*k))
                .map(|(_, c)| f64::from(c.element_sum()) / 3.0)
                .collect();
            kept.iter().sum::<f64>() / kept.len() as f64
        })
        .collect()
}

const CAMERA: &str =
    "[camera]\neye = [0, 0, 6]\nlook_at = [0, 0, 0]\nfov = 40\nwidth = 32\nheight = 32\n";

#[test]
fn in_a_white_sky_an_object_of_albedo_rho_shows_rho() {
    // A convex object under a uniform sky of radiance 1 receives
    // irradiance pi from every side and sends back its albedo: Lambert
    // rho, a mirror and Fresnel glass (which lose nothing) 1. Every path
    // here carries exactly that, so the pixels do too, to rounding.
    let cases = [
        ("diffuse = [0.3, 0.6, 0.9]", Vec3::new(0.3, 0.6, 0.9)),
        ("diffuse = [1, 1, 1]", Vec3::ONE),
        ("reflectance = 1", Vec3::ONE),
        ("transmittance = 1\nfresnel = true", Vec3::ONE),
    ];
    for (material, expected) in cases {
        let scene = scene_from(&format!(
            "{CAMERA}[render]\nintegrator = \"path\"\nmax_depth = 64\nbackground = [1, 1, 1]\n\
             [materials.m]\n{material}\n[[objects]]\nsphere = {{ center = [0, 0, 0], radius = 1.5 }}\nmaterial = \"m\"\n"
        ));
        let image = path_image(&scene, 8, 0, Strategy::Mis);
        // Pixels well inside the sphere's disk (radius about 12 pixels).
        for (k, c) in image.iter().enumerate() {
            let (x, y) = ((k % 32) as f32 - 15.5, (k / 32) as f32 - 15.5);
            let on_sphere = x * x + y * y < 8.0 * 8.0;
            let off = (x * x + y * y).sqrt() > 14.0;
            if on_sphere {
                assert!(
                    (*c - expected).abs().max_element() < 1e-4,
                    "{material}: {c}"
                );
            } else if off {
                assert!(
                    (*c - Vec3::ONE).abs().max_element() < 1e-6,
                    "{material}: {c}"
                );
            }
        }
    }
}

/// Six quads facing into the cube [-3, 3]^3, of material `material`.
fn inward_box(material: &str) -> String {
    let faces = [
        ("[-3, -3, -3]", "[0, 0, 6]", "[6, 0, 0]"), // floor, up
        ("[-3, 3, -3]", "[6, 0, 0]", "[0, 0, 6]"),  // ceiling, down
        ("[-3, -3, -3]", "[6, 0, 0]", "[0, 6, 0]"), // back, +z
        ("[-3, -3, 3]", "[0, 6, 0]", "[6, 0, 0]"),  // front, -z
        ("[-3, -3, -3]", "[0, 6, 0]", "[0, 0, 6]"), // left, +x
        ("[3, -3, -3]", "[0, 0, 6]", "[0, 6, 0]"),  // right, -x
    ];
    faces
        .iter()
        .map(|(corner, u, v)| {
            format!("[[objects]]\nquad = {{ corner = {corner}, edge_u = {u}, edge_v = {v} }}\nmaterial = \"{material}\"\n")
        })
        .collect()
}

#[test]
fn inside_a_closed_emitter_every_material_of_albedo_1_shows_its_radiance() {
    // A closed box of radiance 1 that reflects nothing: whatever of
    // albedo 1 it holds is lit by 1 from every side and shows 1. Light
    // samples (the box's twelve triangles) and BSDF samples both find the
    // box here, so this checks their weights and densities add up.
    for material in [
        "diffuse = [1, 1, 1]",
        "reflectance = 1",
        "transmittance = 1\nfresnel = true",
    ] {
        let scene = scene_from(&format!(
            "[camera]\neye = [0, 0, 2.5]\nlook_at = [0, 0, 0]\nfov = 40\nwidth = 24\nheight = 24\n\
             [render]\nintegrator = \"path\"\nmax_depth = 64\n\
             [materials.glow]\nemission = [1, 1, 1]\n[materials.m]\n{material}\n{}\
             [[objects]]\nsphere = {{ center = [0, 0, 0], radius = 0.6 }}\nmaterial = \"m\"\n",
            inward_box("glow")
        ));
        let means = means_over_seeds(&scene, 16, 8, Strategy::Mis, |_| true);
        let (mean, error) = mean_and_error(&means);
        assert!(
            (mean - 1.0).abs() < 4.0 * error + 1e-5,
            "{material}: {mean} +- {error}"
        );
        // The noise is that of light sampling only; it is small.
        assert!(error < 0.01, "{material}: {error}");
    }
}

#[test]
fn a_furnace_of_albedo_one_half_and_emission_one_half_shows_one() {
    // Every surface of a closed box and of a sphere in it reflects 1/2 and
    // emits 1/2: L = 1/2 (1 + 1/2 + 1/4 + ...) = 1 - 2^-(D + 1) after
    // D bounces, so Russian roulette, the lights' densities (triangles and
    // a sphere) and MIS are all checked against one number.
    let depth = 20;
    let scene = scene_from(&format!(
        "[camera]\neye = [0, 0, 2.5]\nlook_at = [0, 0, 0]\nfov = 60\nwidth = 24\nheight = 24\n\
         [render]\nintegrator = \"path\"\nmax_depth = {depth}\n\
         [materials.m]\ndiffuse = [0.5, 0.5, 0.5]\nemission = [0.5, 0.5, 0.5]\n{}\
         [[objects]]\nsphere = {{ center = [0.5, -0.5, 0], radius = 1 }}\nmaterial = \"m\"\n",
        inward_box("m")
    ));
    let expected = 1.0 - 0.5f64.powi(depth + 1);
    // Light samples alone meet a singularity where two emitting faces
    // meet: a point of one sees the other at distances down to 0, and the
    // estimate's variance is infinite (its mean converges, slowly, from
    // below). They get more samples; MIS takes those directions from the
    // BSDF.
    for (strategy, samples) in [
        (Strategy::Mis, 16),
        (Strategy::Lights, 256),
        (Strategy::Bsdf, 16),
    ] {
        let means = means_over_seeds(&scene, samples, 8, strategy, |_| true);
        let (mean, error) = mean_and_error(&means);
        assert!(
            (mean - expected).abs() < 4.0 * error,
            "{strategy:?}: {mean} +- {error}, expected {expected}"
        );
    }
}

#[test]
fn with_path_reuse_the_furnace_of_albedo_one_half_still_shows_one() {
    // The furnace above, its pixels sharing their paths' first bounces in
    // groups of 8: every weight and density of the balance heuristic
    // (the sphere hiding parts of the walls from some pixels) must add up
    // for the mean to stay 1 - 2^-(D + 1). The box alone is traced in
    // lanes, the box with the sphere one path at a time.
    let depth = 20;
    let expected = 1.0 - 0.5f64.powi(depth + 1);
    let sphere =
        "[[objects]]\nsphere = { center = [0.5, -0.5, 0], radius = 1 }\nmaterial = \"m\"\n";
    for inside in ["", sphere] {
        let scene = scene_from(&format!(
            "[camera]\neye = [0, 0, 2.5]\nlook_at = [0, 0, 0]\nfov = 60\nwidth = 24\nheight = 24\n\
             [render]\nintegrator = \"path\"\nmax_depth = {depth}\n\
             [materials.m]\ndiffuse = [0.5, 0.5, 0.5]\nemission = [0.5, 0.5, 0.5]\n{}{inside}",
            inward_box("m")
        ));
        let means: Vec<f64> = (0..8)
            .map(|seed| image_mean(&render_rows(&scene, 16, seed, 8)))
            .collect();
        let (mean, error) = mean_and_error(&means);
        assert!(
            (mean - expected).abs() < 4.0 * error,
            "{inside}: {mean} +- {error}, expected {expected}"
        );
    }
}

#[test]
fn path_reuse_through_rough_gold_keeps_every_block_s_mean() {
    // A room lit by a lamp, a ball of rough gold in it: the pixels that
    // share their paths' second vertices on the gold (what lights the
    // caustics) must keep the means of paths traced alone, block by
    // block, within a few standard errors of the two.
    let scene = scene_from(&format!(
        "[camera]\neye = [0, 0, 2.5]\nlook_at = [0, -1, 0]\nfov = 60\nwidth = 24\nheight = 24\n\
         [render]\nintegrator = \"path\"\nmax_depth = 5\n\
         [materials.w]\ndiffuse = [0.6, 0.6, 0.6]\n\
         [materials.lamp]\ndiffuse = [0.5, 0.5, 0.5]\nemission = [8, 8, 8]\n\
         [materials.gold]\nbase_color = [1, 0.78, 0.34]\nmetallic = 1\nroughness = 0.3\n\
         [[objects]]\nquad = {{ corner = [-1, 2.9, -1], edge_u = [2, 0, 0], edge_v = [0, 0, 2] }}\nmaterial = \"lamp\"\n\
         [[objects]]\nsphere = {{ center = [0.8, -1.8, 0], radius = 1.2 }}\nmaterial = \"gold\"\n{}",
        inward_box("w")
    ));
    let blocks = |reuse: u32| -> Vec<Vec<f64>> {
        (0..8)
            .map(|seed| {
                let image = render_rows(&scene, 16, seed, reuse);
                let mut sums = vec![0.0; 16];
                for (k, c) in image.iter().enumerate() {
                    let block = (k / 24 / 6) * 4 + (k % 24) / 6;
                    sums[block] += f64::from(c.element_sum()) / 3.0 / 36.0;
                }
                sums
            })
            .collect()
    };
    let (shared, alone) = (blocks(8), blocks(1));
    for b in 0..16 {
        let of = |renders: &[Vec<f64>]| renders.iter().map(|r| r[b]).collect::<Vec<_>>();
        let (m8, e8) = mean_and_error(&of(&shared));
        let (m1, e1) = mean_and_error(&of(&alone));
        let bound = 4.0 * (e8 * e8 + e1 * e1).sqrt();
        assert!(
            (m8 - m1).abs() < bound,
            "block {b}: shared {m8} +- {e8}, alone {m1} +- {e1}"
        );
    }
}

#[test]
fn a_point_light_lights_a_lambertian_plane_by_the_inverse_square_law() {
    // Intensity I at height h over a plane of albedo rho: the point below
    // gets irradiance I / h^2 and shows rho I / (pi h^2); a point at r
    // from it, rho I cos / (pi d^2) with d^2 = h^2 + r^2, cos = h / d.
    // The camera looks straight down; each pixel is compared with the
    // value at its centre, its neighbours' spread being well below 1 %.
    let (rho, intensity, h) = (0.6, 2.0, 3.0);
    let scene = |radius: f32| {
        scene_from(&format!(
            "[camera]\neye = [0, 2, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\nfov = 60\nwidth = 16\nheight = 16\n\
             [render]\nintegrator = \"path\"\nmax_depth = 1\n\
             [[lights]]\nposition = [0, {h}, 0]\ncolor = [{intensity}, {intensity}, {intensity}]\nradius = {radius}\n\
             [materials.m]\ndiffuse = [{rho}, {rho}, {rho}]\n\
             [[objects]]\nquad = {{ corner = [-50, 0, 50], edge_u = [100, 0, 0], edge_v = [0, 0, -100] }}\nmaterial = \"m\"\n"
        ))
    };
    let point = scene(0.0);
    let camera = point.camera();
    let image = path_image(&point, 64, 0, Strategy::Mis);
    for (k, c) in image.iter().enumerate() {
        let (i, j) = ((k % 16) as f32 + 0.5, (k / 16) as f32 + 0.5);
        let ray = camera.ray(i, j);
        let hit = ray.at(-ray.origin().y / ray.dir().y);
        let d2 = f64::from(h as f32 - hit.y).powi(2) + f64::from(hit.x * hit.x + hit.z * hit.z);
        let cos = h / d2.sqrt();
        let expected = rho * intensity * cos / (PI * d2);
        let got = f64::from(c.x);
        assert!(
            (got / expected - 1.0).abs() < 0.01,
            "pixel {k}: {got} vs {expected}"
        );
    }
    // A sphere light of the same intensity is a sphere of radiance
    // I / (pi r^2), whose irradiance on its axis is pi L r^2 / d^2 = I /
    // d^2 exactly: the centre pixels agree, within the noise of sampling it.
    let sphere = scene(0.5);
    let centre = |k: usize| matches!((k % 16, k / 16), (6..=9, 6..=9));
    let (mean, error) = mean_and_error(&means_over_seeds(&sphere, 64, 8, Strategy::Mis, centre));
    let expected_centre = means_over_seeds(&point, 4, 1, Strategy::Mis, centre)[0];
    assert!(
        (mean - expected_centre).abs() < 4.0 * error + 1e-3 * expected_centre,
        "{mean} +- {error} vs {expected_centre}"
    );
}

/// The form factor from a point to a parallel rectangle of sides `a` and
/// `b` at height `h`, the point below one of its corners (Howell's
/// catalogue, C-11).
fn corner_form_factor(a: f64, b: f64, h: f64) -> f64 {
    let (x, y) = (a / h, b / h);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * PI)
}

#[test]
fn a_square_light_lights_the_point_below_it_by_its_form_factor() {
    // A square of radiance Le, side s, at height h, facing down: the
    // point below its centre gets E = pi Le F (F the form factor: four
    // corner rectangles of s/2), and a Lambertian floor of albedo rho
    // shows rho E / pi. Within 1 %, the camera's few central pixels
    // seeing points within 1e-3 of it.
    let (le, s, h, rho) = (3.0, 1.0, 1.5, 0.8);
    let scene = scene_from(&format!(
        "[camera]\neye = [0, 1, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\nfov = 1\nwidth = 8\nheight = 8\n\
         [render]\nintegrator = \"path\"\nmax_depth = 1\n\
         [materials.glow]\nemission = [{le}, {le}, {le}]\n[materials.floor]\ndiffuse = [{rho}, {rho}, {rho}]\n\
         [[objects]]\nquad = {{ corner = [-0.5, {h}, -0.5], edge_u = [1, 0, 0], edge_v = [0, 0, 1] }}\nmaterial = \"glow\"\n\
         [[objects]]\nquad = {{ corner = [-50, 0, 50], edge_u = [100, 0, 0], edge_v = [0, 0, -100] }}\nmaterial = \"floor\"\n"
    ));
    let form_factor = 4.0 * corner_form_factor(s / 2.0, s / 2.0, h);
    let expected = rho * le * form_factor;
    let (mean, error) = mean_and_error(&means_over_seeds(&scene, 256, 8, Strategy::Mis, |_| true));
    assert!(error < 0.002 * expected, "{error}");
    assert!(
        (mean / expected - 1.0).abs() < 0.01,
        "{mean} +- {error} vs {expected}"
    );
}

/// Which pixels (by index) a mean is taken over.
type PixelFilter = fn(usize) -> bool;

#[test]
fn light_samples_bsdf_samples_and_mis_converge_to_the_same_mean() {
    // A glossy floor and a matte sphere lit by a square, a sphere and an
    // ellipsoid that emit: each way of finding light is unbiased on its own, so the
    // three images have the same mean, within 3 standard errors of the
    // difference, over the whole image and each quarter of it (4).
    let scene = scene_from(
        "[camera]\neye = [0, 1.5, 5]\nlook_at = [0, 0.3, 0]\nfov = 50\nwidth = 24\nheight = 18\n\
         [render]\nintegrator = \"path\"\nmax_depth = 3\n\
         [materials.glow]\nemission = [4, 4, 3]\n[materials.warm]\nemission = [6, 2, 1]\n\
         [materials.floor]\ndiffuse = [0.3, 0.3, 0.3]\nspecular = [0.5, 0.5, 0.5]\nshininess = 30\n\
         [materials.matte]\ndiffuse = [0.7, 0.5, 0.3]\n\
         [[objects]]\nquad = { corner = [-0.5, 2.5, -0.5], edge_u = [1, 0, 0], edge_v = [0, 0, 1] }\nmaterial = \"glow\"\n\
         [[objects]]\nsphere = { center = [1.5, 0.8, -1], radius = 0.2 }\nmaterial = \"warm\"\n\
         [[objects]]\nsphere = { center = [0, 0, 0], radius = 0.25 }\nmaterial = { emission = [1, 2, 5] }\n\
         transform = { scale = [2.5, 0.6, 1], rotate = [0, 20, 30], translate = [-1.3, 1.3, -0.8] }\n\
         [[objects]]\nsphere = { center = [-0.4, 0.5, 0], radius = 0.5 }\nmaterial = \"matte\"\n\
         [[objects]]\nquad = { corner = [-10, 0, 10], edge_u = [20, 0, 0], edge_v = [0, 0, -20] }\nmaterial = \"floor\"\n",
    );
    let regions: [(&str, PixelFilter); 5] = [
        ("image", |_| true),
        ("top left", |k| k % 24 < 12 && k / 24 < 9),
        ("top right", |k| k % 24 >= 12 && k / 24 < 9),
        ("bottom left", |k| k % 24 < 12 && k / 24 >= 9),
        ("bottom right", |k| k % 24 >= 12 && k / 24 >= 9),
    ];
    for (name, pick) in regions {
        let estimate = |strategy| mean_and_error(&means_over_seeds(&scene, 32, 8, strategy, pick));
        let (mis, lights, bsdf) = (
            estimate(Strategy::Mis),
            estimate(Strategy::Lights),
            estimate(Strategy::Bsdf),
        );
        let bound = if name == "image" { 3.0 } else { 4.0 };
        for (a, b, what) in [
            (mis, lights, "MIS vs lights"),
            (mis, bsdf, "MIS vs BSDF"),
            (lights, bsdf, "lights vs BSDF"),
        ] {
            let sigma = (a.1 * a.1 + b.1 * b.1).sqrt();
            assert!(
                (a.0 - b.0).abs() < bound * sigma,
                "{name}, {what}: {} +- {} vs {} +- {}",
                a.0,
                a.1,
                b.0,
                b.1
            );
        }
        // MIS is never the noisiest of the three.
        assert!(
            mis.1 <= lights.1.max(bsdf.1),
            "{name}: {mis:?} {lights:?} {bsdf:?}"
        );
    }
}

#[test]
fn a_sample_that_is_not_finite_is_dropped_and_counted() {
    // The camera inside a glass ball looks out at an emitter of radiance
    // 3e38: leaving the glass scales radiance by eta^2 = 2.25, past the
    // largest float. Seen straight, the emitter is finite (and so is the
    // sum of many such samples); the samples through the glass are left
    // out of their pixel's mean, and counted.
    let scene = scene_from(
        "[camera]\neye = [0, 0, 0]\nlook_at = [0, 0, -1]\nfov = 20\nwidth = 4\nheight = 4\n\
         [render]\nintegrator = \"path\"\nmax_depth = 4\n\
         [materials.sun]\nemission = [3e38, 3e38, 3e38]\n\
         [materials.glass]\ntransmittance = 1\nfresnel = true\n\
         [[objects]]\nsphere = { center = [0, 0, 0], radius = 2 }\nmaterial = \"glass\"\n\
         [[objects]]\nquad = { corner = [-10, -10, -5], edge_u = [20, 0, 0], edge_v = [0, 20, 0] }\nmaterial = \"sun\"\n",
    );
    let mut tracer = PathTracer::new(&scene);
    let through = tracer.pixel(1, 2, 16, || false);
    assert!(through.is_finite(), "{through}");
    assert!(tracer.stats.dropped > 0, "{}", tracer.stats.dropped);
    let straight = scene_from(
        "[camera]\neye = [0, 0, 0]\nlook_at = [0, 0, -1]\nfov = 20\nwidth = 4\nheight = 4\n\
         [render]\nintegrator = \"path\"\n[materials.sun]\nemission = [3e38, 3e38, 3e38]\n\
         [[objects]]\nquad = { corner = [-10, -10, -5], edge_u = [20, 0, 0], edge_v = [0, 20, 0] }\nmaterial = \"sun\"\n",
    );
    let mut tracer = PathTracer::new(&straight);
    assert_eq!(tracer.pixel(1, 2, 64, || false), Vec3::splat(3e38));
    assert_eq!(tracer.stats.dropped, 0);
}

#[test]
fn inside_absorbing_glass_light_samples_lose_what_the_glass_absorbs() {
    // A point light of intensity I at h = 2 over a Lambertian quad of
    // albedo rho, both inside a block of glass (ior 1, so nothing is
    // reflected at its faces) absorbing sigma per unit, seen from above
    // through 3 units of it: rho I / (pi h^2) exp(-sigma (h + 3)).
    let (rho, intensity, sigma) = (0.5f32, 4.0f32, [0.1f32, 0.3, 0.6]);
    let scene = scene_from(&format!(
        "[camera]\neye = [0, 6, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\nfov = 2\nwidth = 9\nheight = 9\n\
         [render]\nintegrator = \"path\"\nmax_depth = 2\n\
         [[lights]]\nposition = [0, 2, 0]\ncolor = [{intensity}, {intensity}, {intensity}]\n\
         [[objects]]\nbox = {{ min = [-3, -1, -3], max = [3, 3, 3] }}\n\
         material = {{ diffuse = [0, 0, 0], specular = [0, 0, 0], transmittance = 1, ior = 1, fresnel = true, absorption = [{}, {}, {}] }}\n\
         [[objects]]\nquad = {{ corner = [-1, 0, 1], edge_u = [2, 0, 0], edge_v = [0, 0, -2] }}\n\
         material = {{ diffuse = [{rho}, {rho}, {rho}] }}\n",
        sigma[0], sigma[1], sigma[2]
    ));
    let image = path_image(&scene, 4, 0, Strategy::Mis);
    let centre = image[4 * 9 + 4];
    for (got, s) in centre.to_array().into_iter().zip(sigma) {
        let want = rho * intensity / (std::f32::consts::PI * 4.0) * (-s * 5.0).exp();
        assert!(
            (got - want).abs() < 0.01 * want,
            "{centre}: {got} against {want}"
        );
    }
}

#[test]
fn a_path_that_leaves_glass_inside_glass_is_still_in_the_outer_one() {
    // Seen from above: block A (absorbing sigma) from y = -1 to 3, block B
    // (clear) inside it from y = 1 to 2, an emitter of radiance 1 at y = 0
    // facing up; both of ior 1. The path crosses 2 units of A, and 1 of B.
    let sigma = [0.2f32, 0.4, 0.8];
    let glass = |absorption: [f32; 3]| {
        format!(
            "material = {{ diffuse = [0, 0, 0], specular = [0, 0, 0], transmittance = 1, ior = 1, fresnel = true, absorption = [{}, {}, {}] }}\n",
            absorption[0], absorption[1], absorption[2]
        )
    };
    let scene = scene_from(&format!(
        "[camera]\neye = [0, 6, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\nfov = 2\nwidth = 9\nheight = 9\n\
         [render]\nintegrator = \"path\"\nmax_depth = 8\n\
         [[objects]]\nbox = {{ min = [-3, -1, -3], max = [3, 3, 3] }}\n{}\
         [[objects]]\nbox = {{ min = [-2, 1, -2], max = [2, 2, 2] }}\n{}\
         [[objects]]\nquad = {{ corner = [-1, 0, 1], edge_u = [2, 0, 0], edge_v = [0, 0, -2] }}\n\
         material = {{ diffuse = [0, 0, 0], emission = [1, 1, 1] }}\n",
        glass(sigma),
        glass([0.0; 3])
    ));
    let centre = path_image(&scene, 4, 0, Strategy::Mis)[4 * 9 + 4];
    for (got, s) in centre.to_array().into_iter().zip(sigma) {
        let want = (-s * 2.0).exp();
        assert!(
            (got - want).abs() < 1e-3 * want,
            "{centre}: {got} against {want}"
        );
    }
}

#[test]
fn out_through_open_absorbing_glass_the_sky_keeps_what_absorbs_nothing() {
    // A pane (a quad) of glass absorbing [0, 0.5, 0.5], ior 1, before a
    // white sky: open glass is entered and never left, so what absorbs
    // is gone over the sky's infinite distance, and the channel that
    // absorbs nothing passes whole (not 0 * inf, a NaN dropping samples).
    let scene = scene_from(
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 2\nwidth = 9\nheight = 9\n\
         [render]\nintegrator = \"path\"\nmax_depth = 4\nbackground = [1, 1, 1]\n\
         [[objects]]\nquad = { corner = [-1, -1, 0], edge_u = [2, 0, 0], edge_v = [0, 2, 0] }\n\
         material = { diffuse = [0, 0, 0], specular = [0, 0, 0], transmittance = 1, ior = 1, fresnel = true, absorption = [0, 0.5, 0.5] }\n",
    );
    let centre = path_image(&scene, 4, 0, Strategy::Mis)[4 * 9 + 4];
    assert_eq!(centre, Vec3::new(1.0, 0.0, 0.0));
}
