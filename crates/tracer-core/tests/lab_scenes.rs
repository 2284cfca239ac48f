//! The lab's scenes, rendered from the files in `scenes/`, checked against
//! values worked out by hand from the lab's formulas.

use glam::Vec3;
mod common;

use common::{load, scenes_dir, LAB_SCENES};
use std::path::Path;
use tracer_core::scene::TraceSettings;
use tracer_core::{prepare, render, LinearImage, RenderJob, Scene};

fn render_file(path: &Path) -> (Scene, LinearImage) {
    let scene = prepare(&load(path)).expect("prepare");
    let image = render_image(&scene);
    (scene, image)
}

fn render_image(scene: &Scene) -> LinearImage {
    render(scene, &RenderJob::full(scene), &|_| {}).image
}

fn render_lab(name: &str) -> (Scene, LinearImage) {
    render_file(&scenes_dir().join(format!("{name}.toml")))
}

fn encoded(name: &str, i: u32, j: u32) -> [u8; 3] {
    let (scene, image) = render_lab(name);
    image.encode(scene.encoding()).get_pixel(i, j).0
}

#[test]
fn every_lab_scene_file_exists_and_renders_500x400() {
    for name in LAB_SCENES {
        let (scene, image) = render_lab(name);
        assert_eq!((image.width, image.height), (500, 400), "{name}");
        assert_eq!(scene.encoding().gamma, 2.2, "{name}");
        assert_eq!(scene.trace_settings().max_depth, 1, "{name}");
        assert_eq!(scene.trace_settings().min_energy, 0.01, "{name}");
        assert!(
            image.pixels.iter().any(|p| p.max_element() > 0.0),
            "{name} is black"
        );
    }
}

#[test]
fn json_twins_render_the_same_image() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    for name in ["reflectance2", "texture"] {
        let toml = load(&scenes_dir().join(format!("{name}.toml")));
        let json = load(&data.join(format!("{name}.json")));
        assert_eq!(
            toml, json,
            "{name}: the two files describe different scenes"
        );
        let (_, a) = render_file(&scenes_dir().join(format!("{name}.toml")));
        let (_, b) = render_file(&data.join(format!("{name}.json")));
        assert!(a == b, "{name}: the images differ");
    }
}

#[test]
fn intersection_hits_are_half_green_and_misses_black() {
    // (0, 0.5, 0) with gamma 2.2: 0.5^(1/2.2) * 255 = 186.08 -> 186.
    assert_eq!(encoded("sphere-intersection", 250, 200), [0, 186, 0]);
    assert_eq!(encoded("sphere-intersection", 5, 5), [0, 0, 0]);
    // The small sphere (-2.5, 1.3, -3) is top-RIGHT: +x points left.
    assert_eq!(encoded("sphere-intersection", 355, 145), [0, 186, 0]);
    assert_eq!(encoded("sphere-intersection", 145, 145), [0, 0, 0]);
    assert_eq!(encoded("triangle-intersection", 250, 200), [0, 186, 0]);
    assert_eq!(encoded("triangle-intersection", 5, 395), [0, 0, 0]);
}

#[test]
fn ambient_only_is_light_times_ambient() {
    // 0.6 * 0.5 = 0.3; 0.3^(1/2.2) * 255 = 147.5 -> 147.
    let (_, image) = render_lab("illumination-ambient");
    assert!((image.get(250, 200) - Vec3::new(0.3, 0.0, 0.0)).length() < 1e-6);
    assert_eq!(encoded("illumination-ambient", 250, 200), [147, 0, 0]);
}

#[test]
fn diffuse_at_the_front_of_the_sphere() {
    // Near p = (0, 0, 1.6): L = normalize((-3, -2, 6.4)), cos = 6.4 / 7.3457 = 0.8713;
    // 0.6 * 0.7 * 0.8713 = 0.3659.
    let (_, image) = render_lab("illumination-diffuse");
    let c = image.get(250, 200);
    assert!(
        (c.x - 0.3659).abs() < 0.004 && c.y == 0.0 && c.z == 0.0,
        "{c:?}"
    );
}

#[test]
fn shadowed_wall_gets_ambient_only() {
    let (_, image) = render_lab("shadows");
    // Inside the red sphere's shadow on the back wall: 0.6 * 0.1 grey.
    assert!((image.get(100, 150) - Vec3::splat(0.06)).length() < 1e-6);
    // Lit wall: ambient plus a positive diffuse term.
    assert!(image.get(400, 50).x > 0.06 + 0.01);
}

#[test]
fn mirror_wall_shows_the_red_sphere() {
    let (scene, image) = render_lab("reflectance2");
    let settings = TraceSettings {
        max_depth: 0,
        ..scene.trace_settings().clone()
    };
    let flat = scene.with_trace_settings(settings);
    let no_mirror = render_image(&flat);
    // Below the red sphere the wall reflects the sphere's unlit underside:
    // its ambient under both lights, (0.6 + 0.3) * 0.1 = 0.09 red, is added to
    // the plain grey that the wall shows without recursion.
    let (i, j) = (250, 310);
    let c = image.get(i, j);
    let g = no_mirror.get(i, j);
    assert!(
        (g.x - g.y).abs() < 1e-6 && (g.y - g.z).abs() < 1e-6,
        "{g:?}"
    );
    assert!(
        (c - g - Vec3::new(0.09, 0.0, 0.0)).length() < 1e-5,
        "{c:?} vs {g:?}"
    );
}

#[test]
fn textured_sphere_stripes_scale_the_local_colour() {
    // At the front the texture row is floor(400 * 0.5) = 200: grey 200 or 10.
    // The ratio of the textured to the plain colour must be one of the two greys.
    let (_, plain) = render_lab("illumination");
    let (_, textured) = render_lab("texture");
    let ratio = textured.get(250, 200).x / plain.get(250, 200).x;
    let greys = [10.0 / 255.0, 200.0 / 255.0];
    assert!(
        greys.iter().any(|g| (ratio - g).abs() < 1e-4),
        "ratio {ratio}"
    );
}
