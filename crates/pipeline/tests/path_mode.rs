//! Path mode through the pipeline: the same image whatever the threads,
//! tiles and kept-scene cache; every 3D scene renders in it; its
//! encoding's defaults; its limits on samples; emission in Whitted mode.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use tracer_pipeline::cache::SceneCache;
use tracer_pipeline::{
    load, prepare_taking, render, render_prepared, render_progressive, tiles, Input, Options, Part,
    Picture, Region, Summary,
};

fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name)
}

fn bits(picture: &Picture) -> Vec<[u32; 3]> {
    let p = &picture.linear.pixels;
    p.iter()
        .map(|c| [c.x.to_bits(), c.y.to_bits(), c.z.to_bits()])
        .collect()
}

fn path_options(part: Option<Part>) -> Options {
    Options {
        width: Some(40),
        samples: Some(8),
        integrator: Some(scene_format::Integrator::Path),
        part,
        ..Options::default()
    }
}

fn render_on(threads: usize, input: &Input, options: &Options) -> Picture {
    let loaded = load(input).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| render(&loaded, options, &|_| {}).unwrap().image)
}

fn cornell() -> Input {
    Input::File(scene("cornell-box.toml"))
}

#[test]
fn path_mode_tiles_and_regions_are_the_whole_render_s_pixels_at_any_thread_count() {
    let full = render_on(2, &cornell(), &path_options(None));
    assert_eq!(
        render_on(1, &cornell(), &path_options(None)).linear,
        full.linear
    );
    let dir = tempfile::tempdir().unwrap();
    let size = (40, 40);
    let paths: Vec<PathBuf> = (0..3)
        .map(|index| {
            let options = path_options(Some(Part::Tile { index, count: 3 }));
            let loaded = load(&cornell()).unwrap();
            let picture = render_on(1 + index as usize, &cornell(), &options);
            let digest = tiles::digest(&cornell(), &loaded, &options).unwrap();
            let region = tracer_pipeline::tile_region(index, 3, size);
            let bytes =
                tiles::encode(&picture, region, size, &digest, Some((index, 3)), None).unwrap();
            let path = dir.path().join(format!("tile-{index}.exr"));
            std::fs::write(&path, bytes).unwrap();
            path
        })
        .collect();
    let read: Vec<_> = paths
        .iter()
        .map(|p| (p.clone(), tiles::read(p).unwrap()))
        .collect();
    let merged = tiles::merge(&read).unwrap();
    assert_eq!(bits(&merged), bits(&full));
    let region = Region {
        x0: 7,
        y0: 3,
        x1: 29,
        y1: 31,
    };
    let part = render_on(2, &cornell(), &path_options(Some(Part::Region(region))));
    let width = full.linear.width;
    for y in region.y0..region.y1 {
        for x in region.x0..region.x1 {
            let whole = full.linear.pixels[(y * width + x) as usize];
            let inside = part.linear.pixels[((y - region.y0) * 22 + x - region.x0) as usize];
            assert_eq!(whole, inside, "({x}, {y})");
        }
    }
}

#[test]
fn a_kept_path_mode_scene_renders_as_one_prepared_from_its_files() {
    // Sphere lights (emitters in path mode), area lights, glass.
    let dir = tempfile::tempdir().unwrap();
    let cache = SceneCache::new(dir.path().join("kept"));
    for name in ["cornell-box.toml", "soft-shadows.toml", "glass.toml"] {
        let input = Input::File(scene(name));
        let options = path_options(None);
        let fresh = render(&load(&input).unwrap(), &options, &|_| {}).unwrap();
        let loaded = load(&input).unwrap();
        let files_read = loaded.files_read.clone();
        let digest = tiles::digest(&input, &loaded, &options).unwrap();
        let prepared = prepare_taking(loaded, &options, "--cache").unwrap();
        let entry = cache.entry(&input, &options).unwrap();
        entry.write(&prepared, &files_read, &digest, &[]).unwrap();
        let kept = entry.read(&input, &options).unwrap().expect("kept");
        let again = render_prepared(&kept.prepared, &options, &|_| {}).unwrap();
        assert_eq!(bits(&again.image), bits(&fresh.image), "{name}");
    }
}

#[test]
fn every_3d_scene_renders_in_path_mode() {
    let mut rendered = 0;
    let mut folders = vec![scene("")];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
                continue;
            }
            if path.extension().is_none_or(|e| e != "toml") {
                continue;
            }
            let loaded = load(&Input::File(path.clone())).unwrap();
            if matches!(loaded.kind, scene_format::SceneKind::Canvas(_)) {
                continue;
            }
            let options = Options {
                width: Some(24),
                samples: Some(2),
                integrator: Some(scene_format::Integrator::Path),
                ..Options::default()
            };
            let picture = render(&loaded, &options, &|_| {})
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
                .image;
            assert!(
                picture.linear.pixels.iter().all(|c| c.is_finite()),
                "{}",
                path.display()
            );
            rendered += 1;
        }
    }
    assert!(rendered >= 20, "{rendered}");
}

#[test]
fn path_mode_clamps_each_channel_unless_the_scene_says_otherwise() {
    use tracer_core::image::Saturation;
    let whitted = render_on(1, &Input::File(scene("shadows.toml")), &Options::default());
    assert_eq!(whitted.encoding.saturation, Saturation::White);
    let path = render_on(1, &cornell(), &path_options(None));
    assert_eq!(path.encoding.saturation, Saturation::Clamp);
    // The light's pixels are far above 1, and kept so in linear values.
    let brightest = path
        .linear
        .pixels
        .iter()
        .map(|c| c.max_element())
        .fold(0.0, f32::max);
    assert!(brightest > 10.0, "{brightest}");
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(scene("cornell-box.toml"))
        .unwrap()
        .replace("saturation = \"clamp\"", "saturation = \"white\"");
    let file = dir.path().join("white.toml");
    std::fs::write(&file, text).unwrap();
    let white = render_on(1, &Input::File(file), &path_options(None));
    assert_eq!(white.encoding.saturation, Saturation::White);
}

#[test]
fn more_than_4096_samples_are_path_mode_s_only() {
    let input = Input::File(scene("shadows.toml"));
    let loaded = load(&input).unwrap();
    let many = Options {
        samples: Some(5000),
        width: Some(2),
        ..Options::default()
    };
    let err = render(&loaded, &many, &|_| {}).unwrap_err();
    assert!(err.is_bad_input());
    assert!(err.to_string().contains("path mode"), "{err}");
    let path = Options {
        integrator: Some(scene_format::Integrator::Path),
        ..many
    };
    let rendered = render(&loaded, &path, &|_| {}).unwrap();
    let Summary::Shaded(stats) = rendered.summary else {
        panic!("shaded")
    };
    assert_eq!(stats.dropped, 0);
    // A path-traced scene's own 5000, with --integrator whitted: the scene's
    // samples are named, not a --samples never given.
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(scene("cornell-box.toml"))
        .unwrap()
        .replace("samples = 64", "samples = 5000");
    let file = dir.path().join("many.toml");
    std::fs::write(&file, text).unwrap();
    let loaded = load(&Input::File(file)).unwrap();
    let whitted = Options {
        integrator: Some(scene_format::Integrator::Whitted),
        width: Some(2),
        ..Options::default()
    };
    let err = render(&loaded, &whitted, &|_| {}).unwrap_err();
    assert!(err.is_bad_input());
    let said = err.to_string();
    assert!(
        said.starts_with("--integrator whitted: the scene's samples = 5000"),
        "{said}"
    );
}

#[test]
fn in_whitted_mode_an_emitter_is_seen_and_lights_nothing() {
    // A quad of emission [2, 1, 0.5] facing the camera, nothing else lit:
    // its pixels are its emission (the lab's arithmetic adds no light
    // term without lights), the others the black background.
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("glow.toml");
    std::fs::write(
        &file,
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nwidth = 16\nheight = 16\nfov = 30\n\
         [render]\nsaturation = \"clamp\"\n\
         [[objects]]\nquad = { corner = [-0.5, -0.5, 0], edge_u = [1, 0, 0], edge_v = [0, 1, 0] }\n\
         material = { emission = [2, 1, 0.5] }\n\
         [[objects]]\nsphere = { center = [1.2, 0, 0], radius = 0.3 }\nmaterial = { diffuse = [1, 1, 1] }\n",
    )
    .unwrap();
    let picture = render_on(1, &Input::File(file), &Options::default());
    let centre = picture.linear.get(8, 8);
    assert_eq!(centre, glam::Vec3::new(2.0, 1.0, 0.5));
    // The white sphere beside it stays black: Whitted has no area lights.
    assert!(picture
        .linear
        .pixels
        .iter()
        .all(|c| *c == glam::Vec3::ZERO || *c == glam::Vec3::new(2.0, 1.0, 0.5)));
}

#[test]
fn a_render_in_passes_is_the_render_of_as_many_samples_bit_for_bit() {
    // Passes of 1, 2, 4 and 8 samples a pixel: run to the end, the image
    // of one render of 8; stopped after the second pass, the image of one
    // render of 2 (a sample's numbers do not depend on how many there are).
    let loaded = load(&cornell()).unwrap();
    let options = path_options(None);
    let whole = render(&loaded, &options, &|_| {}).unwrap().image;
    let never = AtomicBool::new(false);
    let mut seen = Vec::new();
    let mut on_pass = |pass: tracer_pipeline::Pass| {
        seen.push((pass.samples, pass.total));
        true
    };
    let passes = render_progressive(&loaded, &options, "test", &never, (&|_| {}, &mut on_pass))
        .unwrap()
        .expect("not cancelled");
    assert_eq!(seen, [(1, 8), (2, 8), (4, 8), (8, 8)]);
    assert_eq!(bits(&passes.image), bits(&whole));
    let mut stop_at_two = |pass: tracer_pipeline::Pass| pass.samples < 2;
    let two = render_progressive(
        &loaded,
        &options,
        "test",
        &never,
        (&|_| {}, &mut stop_at_two),
    )
    .unwrap()
    .unwrap();
    let two_samples = Options {
        samples: Some(2),
        ..options
    };
    let render_of_two = render(&loaded, &two_samples, &|_| {}).unwrap().image;
    assert_eq!(bits(&two.image), bits(&render_of_two));
    assert_ne!(bits(&two.image), bits(&whole));
}

#[test]
fn light_from_inside_absorbing_glass_loses_what_beer_lambert_says() {
    // A glass block (z from -1 to 1) of ior 1 and Fresnel's rule (nothing
    // reflected at ior 1: every path passes straight in), an emitter of
    // radiance 1 inside it at z = 0, facing the camera: its light crosses
    // one unit of glass, and keeps exp(-absorption), whatever it meets
    // inside (not only when it leaves through the glass's back).
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("inside.toml");
    std::fs::write(
        &file,
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nwidth = 9\nheight = 9\nfov = 5\n\
         [render]\nintegrator = \"path\"\nsamples = 4\nmax_depth = 4\n\
         [[objects]]\nbox = { min = [-2, -2, -1], max = [2, 2, 1] }\n\
         material = { diffuse = [0, 0, 0], specular = [0, 0, 0], transmittance = 1, ior = 1, fresnel = true, absorption = [0.5, 1, 2] }\n\
         [[objects]]\nquad = { corner = [-1, -1, 0], edge_u = [2, 0, 0], edge_v = [0, 2, 0] }\n\
         material = { diffuse = [0, 0, 0], emission = [1, 1, 1] }\n",
    )
    .unwrap();
    let picture = render_on(1, &Input::File(file), &Options::default());
    let centre = picture.linear.pixels[4 * 9 + 4];
    let expected = [0.5f32, 1.0, 2.0].map(|sigma| (-sigma).exp());
    for (got, want) in centre.to_array().into_iter().zip(expected) {
        assert!(
            (got - want).abs() < 1e-3 * want,
            "{centre} against {expected:?}"
        );
    }
}
