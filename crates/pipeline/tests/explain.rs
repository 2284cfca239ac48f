//! `explain` against the render and against the lab's formulas: for every
//! 3D scene and a grid of pixels its tree's colour is the rendered pixel
//! (both integrators), and for two pixels of `illumination.toml` its
//! numbers are those worked out by hand here from the lab's formulas.

use glam::{DVec3, Vec3};
use std::path::{Path, PathBuf};
use tracer_pipeline::explain::{explain, Outcome, Trace};
use tracer_pipeline::{load, render, Input, Options};

fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name)
}

#[test]
fn the_tree_s_colour_is_the_rendered_pixel_in_every_lab_scene() {
    // One sample a pixel: the tree's colour is the pixel, bit for bit, and
    // its 8-bit value the image's; several: the mean of the samples'.
    let names = [
        "sphere-intersection.toml",
        "triangle-intersection.toml",
        "illumination.toml",
        "illumination-shininess-10.toml",
        "texture.toml",
        "shadows.toml",
        "reflectance.toml",
        "reflectance2.toml",
        "glass.toml",
        "soft-shadows.toml",
    ];
    for name in names {
        let loaded = load(&Input::File(scene(name))).unwrap();
        let options = Options {
            width: Some(50),
            ..Options::default()
        };
        let image = render(&loaded, &options, &|_| {}).unwrap().image;
        let rgb8 = image.to_rgb8();
        let (width, height) = image.dimensions();
        for (x, y) in grid(width, height) {
            let pixel = explain(&loaded, &options, (x, y), 0).unwrap();
            let rendered = image.linear.get(x, y);
            assert_eq!(pixel.linear, rendered, "{name} ({x}, {y})");
            assert_eq!(pixel.rgb8, rgb8.get_pixel(x, y).0, "{name} ({x}, {y})");
            let samples = pixel.explanation.samples;
            if samples == 1 {
                assert_eq!(pixel.explanation.colour, rendered, "{name} ({x}, {y})");
            } else {
                let mean = (0..samples)
                    .map(|k| {
                        explain(&loaded, &options, (x, y), k)
                            .unwrap()
                            .explanation
                            .colour
                    })
                    .fold(Vec3::ZERO, |a, c| a + c)
                    / samples as f32;
                assert!(
                    (mean - rendered).abs().max_element() < 1e-5,
                    "{name} ({x}, {y})"
                );
            }
        }
    }
}

/// A 4 x 4 grid of pixels over the image, corners included.
fn grid(width: u32, height: u32) -> Vec<(u32, u32)> {
    let at = |k: u32, n: u32| k * (n - 1) / 3;
    (0..4)
        .flat_map(|j| (0..4).map(move |i| (at(i, width), at(j, height))))
        .collect()
}

#[test]
fn in_path_mode_the_samples_colours_average_to_the_rendered_pixel() {
    // The mean, in f64 as the render sums, of every sample's colour, where
    // each path is traced alone (path reuse and more camera rays make a
    // pixel more than the mean of its own paths' colours).
    let mut loaded = load(&Input::File(scene("cornell-box.toml"))).unwrap();
    let options = Options {
        width: Some(32),
        samples: Some(8),
        ..Options::default()
    };
    let rendered = |loaded: &tracer_pipeline::Loaded| render(loaded, &options, &|_| {}).unwrap();
    for alone in [false, true] {
        if alone {
            let scene_format::SceneKind::Scene3d(file) = &mut loaded.kind else {
                panic!("a 3D scene");
            };
            (file.render.path_reuse, file.render.camera_rays) = (Some(1), Some(1));
        }
        let image = rendered(&loaded).image;
        for (x, y) in [(16, 4), (5, 20), (27, 27)] {
            let pixels = (0..8).map(|k| explain(&loaded, &options, (x, y), k).unwrap());
            let mut sum = DVec3::ZERO;
            for pixel in pixels {
                assert!(matches!(pixel.explanation.trace, Trace::Path { .. }));
                // The pixel explain reports is the render's, either way.
                assert_eq!(pixel.linear, image.linear.get(x, y), "({x}, {y})");
                sum += pixel.explanation.colour.as_dvec3();
            }
            if alone {
                assert_eq!((sum / 8.0).as_vec3(), image.linear.get(x, y), "({x}, {y})");
            }
        }
    }
}

#[test]
fn illumination_s_numbers_are_the_lab_s_formulas() {
    // The lab's camera (eye (0, 0, 10), looking at the origin, up +y, fov
    // 50 over 500 x 400): u = normalize(up x look) = (-1, 0, 0), v =
    // normalize(u x look) = (0, -1, 0), o = look_unit * f - (250 u + 200
    // v) with f = 250 / tan 25 = 536.1267; pixel (i, j)'s ray is
    // normalize(u (i + 0.5) + v (j + 0.5) + o). The sphere of radius 1.6 at
    // the origin, the light (-3, -2, 8) of colour 0.6, the material's
    // ambient 0.1, diffuse 0.6 (red), specular 0.7, shininess 30.
    let loaded = load(&Input::File(scene("illumination.toml"))).unwrap();
    let f = 250.0 / (25.0f64.to_radians()).tan();
    for (i, j) in [(250u32, 200u32), (230, 170)] {
        let pixel = explain(&loaded, &Options::default(), (i, j), 0).unwrap();
        let Trace::Whitted { ray } = &pixel.explanation.trace else {
            panic!("Whitted")
        };
        let eye = DVec3::new(0.0, 0.0, 10.0);
        let d = DVec3::new(
            -(f64::from(i) + 0.5) + 250.0,
            -(f64::from(j) + 0.5) + 200.0,
            -f,
        )
        .normalize();
        close(ray.direction, d, "direction");
        // |eye + t d|^2 = 1.6^2: t = -b - sqrt(b^2 - c), b = eye.d.
        let b = eye.dot(d);
        let t = -b - (b * b - (eye.length_squared() - 1.6 * 1.6)).sqrt();
        let hit = ray.hit.as_ref().expect("the sphere");
        assert!((f64::from(hit.t) - t).abs() < 1e-4, "t {} vs {t}", hit.t);
        let p = eye + t * d;
        let n = p / 1.6;
        close(hit.normal, n, "normal");
        let tested = ray.tested.as_ref().expect("one object");
        assert!(matches!(tested[0].outcome, Outcome::Nearest { .. }));
        let light = DVec3::new(-3.0, -2.0, 8.0);
        let l = (light - p).normalize();
        let term = &ray.lights[0].term;
        close(term.l, l, "L");
        assert!((f64::from(term.n_dot_l) - n.dot(l)).abs() < 1e-4);
        let h = (l - d).normalize();
        close(term.h.unwrap(), h, "H");
        let power = n.dot(h).powf(30.0);
        assert!((f64::from(term.n_dot_h_pow.unwrap()) - power).abs() < 1e-3 * power.max(1e-3));
        close(
            term.diffuse,
            DVec3::new(0.6 * 0.6 * n.dot(l), 0.0, 0.0),
            "diffuse",
        );
        close(term.specular, DVec3::splat(0.6 * 0.7 * power), "specular");
        close(ray.ambient[0].1, DVec3::new(0.06, 0.0, 0.0), "ambient");
        let local = DVec3::new(0.06 + 0.36 * n.dot(l), 0.0, 0.0) + DVec3::splat(0.42 * power);
        close(ray.colour, local, "colour");
        // Gamma 2.2, then (int)(c * 255), the lab's encoding.
        let expected = local
            .to_array()
            .map(|c| (c.min(1.0).powf(1.0 / 2.2) * 255.0) as u8);
        for (got, want) in pixel.rgb8.iter().zip(expected) {
            assert!(got.abs_diff(want) <= 1, "{:?} vs {expected:?}", pixel.rgb8);
        }
    }
}

fn close(got: Vec3, want: DVec3, what: &str) {
    assert!(
        (got.as_dvec3() - want).abs().max_element() < 1e-4,
        "{what}: {got} vs {want}"
    );
}

#[test]
fn a_pixel_outside_the_image_or_a_sample_beyond_its_own_is_bad_input() {
    let loaded = load(&Input::File(scene("illumination.toml"))).unwrap();
    let err = explain(&loaded, &Options::default(), (500, 10), 0).unwrap_err();
    assert!(err.is_bad_input());
    assert!(err.to_string().contains("500x400"), "{err}");
    let err = explain(&loaded, &Options::default(), (10, 10), 1).unwrap_err();
    assert!(
        err.is_bad_input() && err.to_string().contains("1 sample"),
        "{err}"
    );
}

#[test]
fn glass_shows_its_absorption_its_inside_and_where_the_tree_stops() {
    // Red glass (absorption (0.05, 1.6, 1.6)): a ray through it keeps
    // exp(-absorption * t) of its colour, t the hit's distance inside.
    let loaded = load(&Input::File(scene("glass.toml"))).unwrap();
    let pixel = explain(&loaded, &Options::default(), (270, 190), 0).unwrap();
    let Trace::Whitted { ray } = &pixel.explanation.trace else {
        panic!("Whitted")
    };
    let inside = ray
        .children
        .iter()
        .find(|c| c.hit.as_ref().is_some_and(|h| !h.front_face))
        .expect("a refracted ray that meets the glass from inside");
    let t = inside.hit.as_ref().unwrap().t;
    let absorbed = inside.absorbed.expect("absorbed");
    for (got, sigma) in absorbed.to_array().into_iter().zip([0.05f32, 1.6, 1.6]) {
        assert!(
            (got - (-sigma * t).exp()).abs() < 1e-5,
            "{absorbed} at t {t}"
        );
    }
    let text =
        tracer_pipeline::explain_text::tree_text(&loaded, &Options::default(), (270, 190), 0)
            .unwrap();
    for said in [
        "times what absorption leaves of it through the glass, exp(-absorption * t) = (0.9245, 0.0811, 0.0811)",
        "seen from inside the glass: no light terms",
        "no mirror or refracted ray: energy 0.0015458782 is at or below min_energy = 0.01",
    ] {
        assert!(text.contains(said), "{said}\n{text}");
    }
}

#[test]
fn an_emitter_in_whitted_mode_says_its_emission_is_added() {
    let loaded = load(&Input::File(scene("cornell-box.toml"))).unwrap();
    let whitted = Options {
        integrator: Some(scene_format::Integrator::Whitted),
        ..Options::default()
    };
    // The lamp, seen from the camera.
    let text = tracer_pipeline::explain_text::tree_text(&loaded, &whitted, (128, 40), 0).unwrap();
    assert!(
        text.contains("plus its emission (18.3870, 13.9873, 6.7536)"),
        "{text}"
    );
}

#[test]
fn under_adaptive_sampling_a_pixel_is_the_mean_of_its_own_share_of_paths() {
    // The courtyard samples adaptively (an environment lights it): its
    // clear sky takes fewer paths than the image's mean, and each of them
    // averages to the rendered pixel; a sample beyond them is refused.
    let loaded = load(&Input::File(scene("courtyard.toml"))).unwrap();
    let options = Options {
        width: Some(80),
        samples: Some(16),
        ..Options::default()
    };
    let image = render(&loaded, &options, &|_| {}).unwrap().image;
    let sky = (40, 2);
    let first = explain(&loaded, &options, sky, 0).unwrap();
    assert_eq!(first.linear, image.linear.get(sky.0, sky.1));
    let paths = first.paths;
    assert!((8..16).contains(&paths), "the sky's paths: {paths}");
    let mut sum = DVec3::ZERO;
    for k in 0..paths {
        sum += explain(&loaded, &options, sky, k)
            .unwrap()
            .explanation
            .colour
            .as_dvec3();
    }
    assert_eq!((sum / f64::from(paths)).as_vec3(), first.linear);
    let err = explain(&loaded, &options, sky, paths).unwrap_err();
    assert!(
        err.is_bad_input() && err.to_string().contains("adaptive"),
        "{err}"
    );
}
