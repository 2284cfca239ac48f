//! Adaptive sampling (`render.adaptive`, `adaptive.rs`): the image it
//! converges to is Mitsuba 3's, and a region, a tile or a render in passes
//! holds the whole one-shot render's pixels bit for bit. (The materials
//! scene is checked by the bench's error against its reference instead:
//! at a mean of 12 paths its rough glass's rare bright paths leave a block
//! 0.3 % low for even sampling as for adaptive, 1.0592 both over 64 seeds
//! against Mitsuba's 1.0621, beyond what the seeds' spread tells.)

// One pass is written as a list of one range, as several are.
#![allow(clippy::single_range_in_vec_init)]

mod mitsuba;

use mitsuba::{assert_renders_agree, reference, scene, Image};
use std::sync::atomic::AtomicBool;
use tracer_core::film::{passes, Film};
use tracer_core::scene::TraceSettings;
use tracer_core::{Region, Scene};

/// `scene` sampled adaptively or not, whatever its file says.
fn sampled(scene: Scene, adaptive: bool) -> Scene {
    let settings = TraceSettings {
        adaptive,
        ..scene.trace_settings().clone()
    };
    scene.with_trace_settings(settings)
}

/// `scene`'s film of `region` after `passes`, scrambled by `seed`.
fn film(scene: &Scene, region: Region, passes: &[std::ops::Range<u32>], seed: u32) -> Film {
    let mut film = Film::new(scene, region).with_seed(seed);
    let never = AtomicBool::new(false);
    for pass in passes {
        film.add_pass(scene, pass.clone(), &|_| {}, &never)
            .expect("never cancelled");
    }
    film
}

/// Eight renders of `scene`'s whole image of `width` x `height`, each of
/// one pass of `samples` paths a pixel, each scrambled by its own seed.
fn whole_renders(scene: &Scene, (width, height): (usize, usize), samples: u32) -> Vec<Image> {
    let full = Region::full(width as u32, height as u32);
    (0..8)
        .map(|seed| Image {
            width,
            height,
            pixels: film(scene, full, &[0..samples], seed).image().pixels,
        })
        .collect()
}

#[test]
fn an_adaptive_courtyard_agrees_with_mitsuba_3() {
    // As tests/courtyard.rs, at a mean of 24 paths a pixel: 8 of pilot,
    // the rest shared out by noise.
    let scene = sampled(scene("courtyard.toml"), true);
    let reference = reference("courtyard-mitsuba.exr", 320, 240);
    let renders = whole_renders(&scene, (320, 240), 24);
    assert_renders_agree(&renders, 24, &reference, (9216, 0.00254));
}

#[test]
fn an_adaptive_bunny_room_agrees_with_mitsuba_3() {
    // As tests/cornell_bunny.rs, with the room's own estimator (adaptive,
    // path reuse and camera rays: its defaults), at a mean of 24 paths: the
    // gold ball's caustics take the paths past the pilot.
    let scene = scene("cornell-bunny.toml");
    let trace = scene.trace_settings();
    assert!(trace.adaptive, "the gold ball makes the room adaptive");
    let reference = reference("cornell-bunny-mitsuba.exr", 256, 256);
    let renders = whole_renders(&scene, (256, 256), 24);
    assert_renders_agree(&renders, 24, &reference, (9216, 0.00118));
}

#[test]
fn a_region_and_passes_hold_the_one_shot_adaptive_render_s_pixels() {
    let scene = sampled(scene("materials.toml"), true);
    let camera = scene.camera();
    let (width, height) = (camera.width, camera.height);
    let whole = film(&scene, Region::full(width, height), &[0..20], 0).image();
    let in_passes: Vec<_> = passes(20).collect();
    assert_eq!(
        film(&scene, Region::full(width, height), &in_passes, 0).image(),
        whole
    );
    let region = Region {
        x0: 101,
        x1: 163,
        y0: 37,
        y1: 70,
    };
    let part = film(&scene, region, &in_passes, 0).image();
    for y in region.y0..region.y1 {
        for x in region.x0..region.x1 {
            let inside = part.pixels[((y - region.y0) * region.width() + x - region.x0) as usize];
            assert_eq!(
                inside,
                whole.pixels[(y * width + x) as usize],
                "pixel ({x}, {y})"
            );
        }
    }
}

#[test]
fn adaptive_sampling_spends_the_paths_where_the_noise_is() {
    // The same mean paths a pixel, shared out by noise: less error against
    // Mitsuba's reference than every pixel taking as many.
    let reference = reference("courtyard-mitsuba.exr", 320, 240);
    let plain = sampled(scene("courtyard.toml"), false);
    let full = Region::full(320, 240);
    let error = |scene: &Scene| {
        let pixels = film(scene, full, &[0..32], 3).image().pixels;
        mitsuba::rmse(
            &Image {
                width: 320,
                height: 240,
                pixels,
            },
            &reference,
        )
    };
    let (even, shared) = (error(&plain), error(&sampled(plain.clone(), true)));
    assert!(
        shared < 0.85 * even,
        "adaptive {shared} against even {even}"
    );
    // The mean asked, more on the copper ball than in the clear sky.
    let paths = film(&sampled(plain, true), full, &[0..32], 3).paths();
    let mean = paths.iter().map(|&p| f64::from(p)).sum::<f64>() / paths.len() as f64;
    assert!((mean / 32.0 - 1.0).abs() < 0.02, "mean paths {mean}");
    let at = |x: usize, y: usize| paths[y * 320 + x];
    assert!(
        at(175, 100) > 2 * at(160, 10),
        "copper {} sky {}",
        at(175, 100),
        at(160, 10)
    );
}
