//! An emission texture seen by light samples as by paths that meet it,
//! against light transport worked out here: a square emitter facing down
//! over a Lambertian floor, its texture 4 x 4 blocks of greys. The floor's
//! radiance is rho times the sum over the blocks of each block's radiance
//! times its form factor (Howell's catalogue, C-11, by superposition), and
//! light samples, BSDF samples and MIS each converge to it. The light's
//! pick is weighed by the texture's mean.

mod common;

use common::{path_image, srgb_decoded};
use glam::{Vec2, Vec3};
use std::f64::consts::PI;
use std::path::Path;
use tracer_core::integrate::path::{traces_paths_in_lanes, Strategy};
use tracer_core::{prepare, Scene};

/// The emitter's height, factor, and the floor's albedo.
const H: f64 = 2.0;
const FACTOR: f64 = 3.0;
const RHO: f64 = 0.7;

/// The 8-bit grey of block (column, row from the top) of the texture:
/// mostly dark, a few bright.
fn block_byte(column: usize, row: usize) -> u8 {
    [0, 20, 255, 60, 0, 180, 5, 120][(column * 5 + row * 3) % 8]
}

/// The 64 x 64 image of 4 x 4 blocks, each 16 texels wide: bilinear
/// filtering blends only within half a texel of a block's edge, evenly
/// either side, which leaves each block's light as if it were uniform.
fn write_texture(dir: &Path) {
    let image = image::GrayImage::from_fn(64, 64, |x, y| {
        image::Luma([block_byte(x as usize / 16, y as usize / 16)])
    });
    image.save(dir.join("glow.png")).unwrap();
}

/// The form factor from a point to a parallel rectangle of sides `a` and
/// `b` (signed) at height `h`, the point below one of its corners: odd in
/// `a` and in `b`, so rectangles anywhere are sums of four.
fn corner_form_factor(a: f64, b: f64, h: f64) -> f64 {
    let (x, y) = (a / h, b / h);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * PI)
}

/// The form factor from floor point (px, 0, pz) to the rectangle
/// [x0, x1] x [z0, z1] at height `H`.
fn form_factor(p: (f64, f64), [x0, x1]: [f64; 2], [z0, z1]: [f64; 2]) -> f64 {
    let f = |x: f64, z: f64| corner_form_factor(x - p.0, z - p.1, H);
    f(x1, z1) - f(x0, z1) - f(x1, z0) + f(x0, z0)
}

/// The floor's radiance at (px, 0, pz): rho / pi times the irradiance,
/// pi times the sum of the blocks' radiances times their form factors;
/// `there` says which blocks are (an alpha mask's holes give nothing).
/// The quad is x = -1 + 2u, z = -1 + 2v; the image's rows run down v.
fn floor_radiance(p: (f64, f64), there: impl Fn(usize, usize) -> bool) -> f64 {
    let mut sum = 0.0;
    for column in 0..4 {
        for row in (0..4).filter(|&row| there(column, row)) {
            let x0 = -1.0 + 0.5 * column as f64;
            let z1 = 1.0 - 0.5 * row as f64;
            let radiance = FACTOR * srgb_decoded(block_byte(column, row));
            sum += radiance * form_factor(p, [x0, x0 + 0.5], [z1 - 0.5, z1]);
        }
    }
    RHO * sum
}

/// Whether block (column, row) of the mask is opaque: a checkerboard.
fn opaque(column: usize, row: usize) -> bool {
    (column + row) % 2 == 1
}

/// The mask: 64 x 64 texels of alpha 0 or 255 by `opaque`'s blocks (its
/// alpha is 0.5 on the blocks' edges, where bilinear filtering crosses).
fn write_mask(dir: &Path) {
    let image = image::RgbaImage::from_fn(64, 64, |x, y| {
        let alpha = if opaque(x as usize / 16, y as usize / 16) {
            255
        } else {
            0
        };
        image::Rgba([255, 255, 255, alpha])
    });
    image.save(dir.join("mask.png")).unwrap();
}

fn scene(dir: &Path, objects: &str) -> Scene {
    let text = format!(
        "[camera]\neye = [0.05, 1, 0.1]\nlook_at = [0.05, 0, 0.1]\nup = [0, 0, -1]\nfov = 40\nwidth = 16\nheight = 16\n\
         [render]\nintegrator = \"path\"\nmax_depth = 1\n\
         [materials.glow]\nbase_color = [0, 0, 0]\nemission = [{FACTOR}, {FACTOR}, {FACTOR}]\n\
         emission_texture = {{ image = \"glow.png\", wrap = \"clamp\" }}\n\
         [materials.floor]\ndiffuse = [{RHO}, {RHO}, {RHO}]\n\
         [[objects]]\nquad = {{ corner = [-50, 0, 50], edge_u = [100, 0, 0], edge_v = [0, 0, -100] }}\nmaterial = \"floor\"\n{objects}"
    );
    std::fs::write(dir.join("scene.toml"), text).unwrap();
    let file = scene_format::load_path(&dir.join("scene.toml")).unwrap_or_else(|e| panic!("{e}"));
    prepare(&file).expect("prepare")
}

/// The emitter: the quad x, z in [-1, 1] at height H, facing down.
const EMITTER: &str = "[[objects]]\nquad = { corner = [-1, 2, -1], edge_u = [2, 0, 0], edge_v = [0, 0, 2] }\nmaterial = \"glow\"\n";

/// The mean over the image's pixels of the red channel, rendered with
/// `strategy` at `samples` paths a pixel and the scramblings of `seed`.
fn image_mean(scene: &Scene, samples: u32, seed: u32, strategy: Strategy) -> f64 {
    let pixels = path_image(scene, samples, seed, strategy);
    pixels.iter().map(|c| f64::from(c.x)).sum::<f64>() / pixels.len() as f64
}

/// Mean and standard error of `values`, as independent estimates.
fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// The mean over the image's pixels of the floor's radiance worked out
/// at each pixel's centre, `there` saying which blocks emit.
fn expected_mean(scene: &Scene, there: impl Fn(usize, usize) -> bool + Copy) -> f64 {
    let camera = scene.camera();
    let mut sum = 0.0;
    for j in 0..camera.height {
        for i in 0..camera.width {
            let ray = camera.ray(i as f32 + 0.5, j as f32 + 0.5);
            let floor = ray.at(-ray.origin().y / ray.dir().y);
            sum += floor_radiance((f64::from(floor.x), f64::from(floor.z)), there);
        }
    }
    sum / f64::from(camera.width * camera.height)
}

/// Each way of finding the light, alone and weighed by MIS, within 4
/// standard errors of `expected` (and 0.1 % for the spread of a pixel's
/// samples over its area, which the centre stands for), so of each other.
fn converges(scene: &Scene, expected: f64) {
    for (strategy, samples) in [
        (Strategy::Lights, 16),
        (Strategy::Mis, 16),
        (Strategy::Bsdf, 64),
    ] {
        let means: Vec<f64> = (0..8)
            .map(|seed| image_mean(scene, samples, seed, strategy))
            .collect();
        let (mean, error) = mean_and_error(&means);
        assert!(error < 0.02 * expected, "{strategy:?}: {mean} +- {error}");
        assert!(
            (mean - expected).abs() < 4.0 * error + 1e-3 * expected,
            "{strategy:?}: {mean} +- {error}, expected {expected}"
        );
    }
}

#[test]
fn light_samples_of_an_emission_texture_light_the_floor_as_its_blocks_do() {
    let dir = tempfile::tempdir().unwrap();
    write_texture(dir.path());
    let scene = scene(dir.path(), EMITTER);
    converges(&scene, expected_mean(&scene, |_, _| true));
}

#[test]
fn the_holes_of_a_masked_emitter_give_off_no_light() {
    // The glowing blocks under a checkerboard of alpha (the base colour
    // texture's, as glTF's MASK reads it): only the opaque ones light the
    // floor, whether a light sample or a path finds them.
    let dir = tempfile::tempdir().unwrap();
    write_texture(dir.path());
    write_mask(dir.path());
    let masked = EMITTER.replace(
        "material = \"glow\"",
        "material = { base_color = [1, 1, 1], texture = { image = \"mask.png\", wrap = \"clamp\" }, alpha_cutoff = 0.5, \
         emission = [3, 3, 3], emission_texture = { image = \"glow.png\", wrap = \"clamp\" } }",
    );
    let scene = scene(dir.path(), &masked);
    let expected = expected_mean(&scene, opaque);
    assert!(expected < 0.8 * expected_mean(&scene, |_, _| true));
    converges(&scene, expected);
}

#[test]
fn a_textured_emitting_sphere_is_found_alike_by_light_and_bsdf_samples() {
    // No closed form here: the three estimates agree, within 4 standard
    // errors of their differences.
    let dir = tempfile::tempdir().unwrap();
    write_texture(dir.path());
    let sphere =
        "[[objects]]\nsphere = { center = [0.3, 1.6, -0.2], radius = 0.4 }\nmaterial = \"glow\"\n";
    let scene = scene(dir.path(), sphere);
    let estimate = |strategy, samples| {
        let means: Vec<f64> = (0..8)
            .map(|seed| image_mean(&scene, samples, seed, strategy))
            .collect();
        mean_and_error(&means)
    };
    let (mis, lights, bsdf) = (
        estimate(Strategy::Mis, 16),
        estimate(Strategy::Lights, 16),
        estimate(Strategy::Bsdf, 64),
    );
    for (a, b, what) in [
        (mis, lights, "MIS vs lights"),
        (mis, bsdf, "MIS vs BSDF"),
        (lights, bsdf, "lights vs BSDF"),
    ] {
        let sigma = (a.1 * a.1 + b.1 * b.1).sqrt();
        assert!((a.0 - b.0).abs() < 4.0 * sigma, "{what}: {a:?} vs {b:?}");
    }
    // What the sphere's factor alone would give, against the texture's.
    let plain = scene_with_plain_sphere(dir.path(), sphere);
    let untextured = image_mean(&plain, 16, 0, Strategy::Mis);
    assert!(mis.0 < 0.7 * untextured, "{mis:?} vs {untextured}");
}

/// `scene` with the emitter's texture left out.
fn scene_with_plain_sphere(dir: &Path, sphere: &str) -> Scene {
    let plain = sphere.replace(
        "material = \"glow\"",
        "material = { base_color = [0, 0, 0], emission = [3, 3, 3] }",
    );
    scene(dir, &plain)
}

#[test]
fn a_light_is_picked_by_its_texture_s_mean() {
    let dir = tempfile::tempdir().unwrap();
    write_texture(dir.path());
    // Beside the textured emitter, one of the same size and factor without
    // a texture (its radiance the factor all over).
    let plain =
        "[[objects]]\nquad = { corner = [2, 2, -1], edge_u = [2, 0, 0], edge_v = [0, 0, 2] }\n\
                 material = { base_color = [0, 0, 0], emission = [3, 3, 3] }\n";
    let scene = scene(dir.path(), &format!("{EMITTER}{plain}"));
    let lights = scene.path_lights();
    // Each quad is one light: the halves of the textured one too.
    assert_eq!(lights.areas().len(), 2);
    let mean = (0..64 * 64)
        .map(|k| srgb_decoded(block_byte(k % 64 / 16, k / 64 / 16)))
        .sum::<f64>()
        / (64.0 * 64.0);
    let expected = mean / (mean + 1.0);
    // Picks spread evenly over [0, 1), from a point below both: the share
    // of them that land on the textured quad (x < 1).
    let n = 20_000;
    let from = Vec3::new(1.0, 0.0, 0.0);
    let textured = (0..n)
        .filter(|&k| {
            let pick = (k as f32 + 0.5) / n as f32;
            let s = lights
                .sample(from, pick, Vec2::splat(0.5))
                .expect("a point");
            (from + s.wi * s.distance).x < 1.0
        })
        .count();
    let share = textured as f64 / f64::from(n);
    assert!((share - expected).abs() < 1e-3, "{share} vs {expected}");
}

#[test]
fn a_kept_scene_whose_texture_lost_texels_is_refused() {
    // As a prepared scene read back from a file (`--cache`) could be: an
    // emission texture's image whose size claims more texels than it has.
    // Whitted mode (no light holds the texture) and path mode alike.
    use tracer_core::material::Material;
    let dir = tempfile::tempdir().unwrap();
    write_texture(dir.path());
    for integrator in ["whitted", "path"] {
        let text = format!(
            "[camera]\neye = [0, 1, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\n[render]\nintegrator = \"{integrator}\"\n\
             [materials.glow]\nbase_color = [0, 0, 0]\nemission = [3, 3, 3]\nemission_texture = {{ image = \"glow.png\" }}\n{EMITTER}"
        );
        let mut parts = kept_parts(dir.path(), &text);
        let Material::Principled(p) = &mut parts.materials[0] else {
            panic!("a physically based material")
        };
        let broken = without_texels(&p.emission_texture().expect("a texture").texture);
        let mean = Vec3::ONE;
        **p = p.as_ref().clone().with_emission_texture(broken, mean);
        let kept = Scene::lean(parts);
        assert!(kept.check_kept().is_err(), "{integrator}");
    }
}

#[test]
fn a_lab_material_s_emission_texture_lights_the_floor_as_well() {
    // `diffuse` and `emission`, the lab's kind: its emission texture is
    // read by light samples and paths alike, as a physically based one's.
    let dir = tempfile::tempdir().unwrap();
    write_texture(dir.path());
    let lab = EMITTER.replace(
        "material = \"glow\"",
        "material = { diffuse = [0, 0, 0], emission = [3, 3, 3], \
         emission_texture = { image = \"glow.png\", wrap = \"clamp\" } }",
    );
    let scene = scene(dir.path(), &lab);
    let expected = expected_mean(&scene, |_, _| true);
    converges(&scene, expected);
    // As `tracer render` traces it: a matte scene goes to the lanes,
    // which read no texture; this one is traced a path at a time.
    assert!(!traces_paths_in_lanes(&scene));
    let job = tracer_core::RenderJob {
        samples: 256,
        ..tracer_core::RenderJob::full(&scene)
    };
    let image = tracer_core::render(&scene, &job, &|_| {}).image;
    let mean = image.pixels.iter().map(|c| f64::from(c.x)).sum::<f64>() / 256.0;
    assert!(
        (mean - expected).abs() < 0.05 * expected,
        "{mean} vs {expected}"
    );
}

#[test]
fn whitted_mode_shows_an_emission_texture_on_either_kind_of_material() {
    // An emitting quad filling the view, its texture black on the left
    // and white on the right: the pixels run from none of the emission
    // to all of it (white is 1 in sRGB and linear alike).
    let dir = tempfile::tempdir().unwrap();
    image::GrayImage::from_fn(2, 1, |x, _| image::Luma([if x == 0 { 0 } else { 255 }]))
        .save(dir.path().join("halves.png"))
        .unwrap();
    let texture = "emission_texture = { image = \"halves.png\", wrap = \"clamp\" }";
    for kind in ["diffuse = [0, 0, 0]", "base_color = [0, 0, 0]"] {
        let text = format!(
            "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 20\nwidth = 16\nheight = 16\n\
             [[objects]]\nquad = {{ corner = [-1, -1, 0], edge_u = [2, 0, 0], edge_v = [0, 2, 0] }}\n\
             material = {{ {kind}, emission = [0.5, 0.5, 0.5], {texture} }}\n"
        );
        std::fs::write(dir.path().join("whitted.toml"), text).unwrap();
        let file = scene_format::load_path(&dir.path().join("whitted.toml")).unwrap();
        let scene = prepare(&file).expect("prepare");
        let job = tracer_core::RenderJob::full(&scene);
        let pixels = tracer_core::render(&scene, &job, &|_| {}).image.pixels;
        let red = |c: &Vec3| c.x;
        let (darkest, brightest) = pixels
            .iter()
            .map(red)
            .fold((1.0f32, 0.0f32), |(lo, hi), r| (lo.min(r), hi.max(r)));
        assert!(darkest < 0.01, "{kind}: {darkest}");
        assert!((brightest - 0.5).abs() < 1e-3, "{kind}: {brightest}");
    }
}

#[test]
fn a_kept_scene_whose_lab_emission_texture_lost_texels_is_refused() {
    use tracer_core::material::{EmissionTexture, Material};
    let dir = tempfile::tempdir().unwrap();
    write_texture(dir.path());
    let text = format!(
        "[camera]\neye = [0, 1, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\n\
         [materials.glow]\ndiffuse = [0, 0, 0]\nemission = [3, 3, 3]\nemission_texture = {{ image = \"glow.png\" }}\n{EMITTER}"
    );
    let mut parts = kept_parts(dir.path(), &text);
    let Material::Phong(p) = &mut parts.materials[0] else {
        panic!("a lab material")
    };
    let emission = p.emission_texture.as_ref().expect("a texture");
    let texture = without_texels(&emission.texture);
    p.emission_texture = Some(EmissionTexture {
        texture,
        mean: Vec3::ONE,
    });
    assert!(Scene::lean(parts).check_kept().is_err());
}

/// The parts of the scene `text` (written to `dir` as `kept.toml`), as a
/// kept scene holds them, checked whole before a test breaks them.
fn kept_parts(dir: &Path, text: &str) -> tracer_core::scene::SceneParts {
    std::fs::write(dir.join("kept.toml"), text).unwrap();
    let file = scene_format::load_path(&dir.join("kept.toml")).unwrap();
    let parts = tracer_core::prepare::parts(&file).unwrap();
    assert!(Scene::lean(parts.clone()).check_kept().is_ok());
    parts
}

/// `texture` as a file read back could hold it: its size claiming more
/// texels than it has.
fn without_texels(
    texture: &tracer_core::texture::ColorTexture,
) -> tracer_core::texture::ColorTexture {
    let mut stored = serde_json::to_value(texture).unwrap();
    stored["Image"]["texels"]["width"] = serde_json::json!(65);
    serde_json::from_value(stored).unwrap()
}
