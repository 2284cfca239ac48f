//! The output formats against numbers worked out here, not by the
//! pipeline's encoders: the EXR holds what the PNG encodes, 16 bits relate
//! to 8 by the truncation rule, a JPEG stays near the PNG, and the depth
//! EXR holds the distances of the geometry.

use std::path::{Path, PathBuf};
use tracer_pipeline::output::{BitDepth, PendingOutput};
use tracer_pipeline::{load, render, Aov, Input, Options};

fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name)
}

/// Renders `input` with `options` to `path` as the CLI does.
fn write(input: Input, options: Options, path: &Path, depth: BitDepth) {
    let loaded = load(&input).unwrap();
    let pending = PendingOutput::create(path).unwrap();
    let options = Options {
        raw_depth: pending.format().is_linear(),
        ..options
    };
    let rendered = render(&loaded, &options, &|_| {}).unwrap();
    pending.write_picture(&rendered.image, depth).unwrap();
}

fn shaded(name: &str, path: &Path, depth: BitDepth) {
    write(Input::File(scene(name)), Options::default(), path, depth);
}

/// The lab's encoding, by hand: any channel over 1 whitens the pixel,
/// then c^(1/2.2), then truncation to `levels` - 1.
fn by_hand(c: [f32; 3], levels: f32) -> [u32; 3] {
    if c.iter().any(|&x| x > 1.0) {
        return [levels as u32 - 1; 3];
    }
    c.map(|x| (x.clamp(0.0, 1.0).powf(1.0 / 2.2) * (levels - 1.0)) as u32)
}

#[test]
fn the_exr_holds_exactly_the_linear_values_the_png_encodes() {
    let dir = tempfile::tempdir().unwrap();
    let (png, exr) = (dir.path().join("r.png"), dir.path().join("r.exr"));
    shaded("reflectance2.toml", &png, BitDepth::Eight);
    shaded("reflectance2.toml", &exr, BitDepth::Eight);
    let png = image::open(&png).unwrap().into_rgb8();
    let exr = image::open(&exr).unwrap().into_rgb32f();
    assert_eq!(png.dimensions(), (500, 400));
    assert_eq!(exr.dimensions(), png.dimensions());
    let mut over_one = 0;
    for (p, e) in png.pixels().zip(exr.pixels()) {
        let expected = by_hand(e.0, 256.0).map(|v| v as u8);
        assert_eq!(p.0, expected, "linear {:?}", e.0);
        over_one += usize::from(e.0.iter().any(|&x| x > 1.0));
    }
    // The file keeps what the lab's rule whitens (25 pixels here):
    // unsaturated, so a test that the values are the renderer's own.
    eprintln!("exr: {over_one} pixels over 1");
    assert!(over_one > 0, "no value over 1 in the EXR");
}

#[test]
fn the_hdr_holds_the_linear_values_to_rgbe_precision() {
    let dir = tempfile::tempdir().unwrap();
    let (hdr, exr) = (dir.path().join("r.hdr"), dir.path().join("r.exr"));
    shaded("reflectance2.toml", &hdr, BitDepth::Eight);
    shaded("reflectance2.toml", &exr, BitDepth::Eight);
    let hdr = image::open(&hdr).unwrap().into_rgb32f();
    let exr = image::open(&exr).unwrap().into_rgb32f();
    assert_eq!(hdr.dimensions(), exr.dimensions());
    for (h, e) in hdr.pixels().zip(exr.pixels()) {
        // RGBE: 8-bit mantissas under the largest channel's exponent, so
        // each channel within 1/128 of the largest (truncated, then read
        // back at the middle of its step).
        let largest = e.0.iter().copied().fold(0.0, f32::max);
        for (&a, &b) in h.0.iter().zip(&e.0) {
            assert!((a - b).abs() <= largest / 128.0, "{:?} vs {:?}", h.0, e.0);
        }
    }
}

#[test]
fn a_16_bit_png_is_the_same_rule_at_16_bits() {
    let dir = tempfile::tempdir().unwrap();
    let paths = ["r8.png", "r16.png", "r.exr"].map(|n| dir.path().join(n));
    shaded("reflectance2.toml", &paths[0], BitDepth::Eight);
    shaded("reflectance2.toml", &paths[1], BitDepth::Sixteen);
    shaded("reflectance2.toml", &paths[2], BitDepth::Eight);
    let p8 = image::open(&paths[0]).unwrap().into_rgb8();
    let p16 = image::open(&paths[1]).unwrap();
    let p16 = p16.as_rgb16().expect("a 16-bit PNG");
    let exr = image::open(&paths[2]).unwrap().into_rgb32f();
    let (mut shifted_up, mut finer, mut between) = (0, 0, 0);
    for ((a, b), e) in p8.pixels().zip(p16.pixels()).zip(exr.pixels()) {
        let expected = by_hand(e.0, 65536.0).map(|v| v as u16);
        assert_eq!(b.0, expected, "linear {:?}", e.0);
        for (&v8, &v16) in a.0.iter().zip(&b.0) {
            // 65535 = 255 * 257: floor(floor(x * 65535) / 257) = floor(x * 255).
            assert_eq!(v16 / 257, u16::from(v8));
            // The top byte is the 8-bit value or one more (x * 255 / 256
            // more is added before the truncation).
            let top = v16 >> 8;
            assert!(top == u16::from(v8) || top == u16::from(v8) + 1);
            shifted_up += usize::from(top != u16::from(v8));
            if v16 > 0 && v16 < 65535 {
                between += 1;
                finer += usize::from(v16 != u16::from(v8) * 257);
            }
        }
    }
    eprintln!("16-bit: {finer} of {between} grey channels finer than 8 bits; top byte one more in {shifted_up}");
    // Not the 8-bit values scaled: the channels that are neither black nor
    // full hold bits below the top byte.
    assert!(finer * 100 > between * 99, "{finer} of {between}");
    assert!(shifted_up > 0, "{shifted_up}");
}

#[test]
fn a_jpeg_decodes_to_within_jpeg_error_of_the_png() {
    let dir = tempfile::tempdir().unwrap();
    let (png, jpg) = (dir.path().join("r.png"), dir.path().join("r.jpg"));
    shaded("reflectance2.toml", &png, BitDepth::Eight);
    shaded("reflectance2.toml", &jpg, BitDepth::Eight);
    let png = image::open(&png).unwrap().into_rgb8();
    let jpg = image::open(&jpg).unwrap().into_rgb8();
    assert_eq!(jpg.dimensions(), png.dimensions());
    let diffs: Vec<i32> = png
        .as_raw()
        .iter()
        .zip(jpg.as_raw())
        .map(|(&a, &b)| (i32::from(a) - i32::from(b)).abs())
        .collect();
    let mean = diffs.iter().sum::<i32>() as f64 / diffs.len() as f64;
    let within_8 = diffs.iter().filter(|&&d| d <= 8).count() as f64 / diffs.len() as f64;
    eprintln!("jpeg: mean error {mean}, within 8 levels {within_8}");
    // Quality 90 on flat shading with sharp silhouettes: the error is in
    // the 8x8 blocks on the edges, a level or so on average.
    assert!(mean < 1.0, "mean error {mean}");
    assert!(within_8 > 0.99, "{within_8}");
}

#[test]
fn the_depth_exr_holds_the_distances_to_a_sphere_and_a_plane() {
    // The lab's camera (horizontal fov 50, 500x400) at (0, 0, 10) looking
    // down -z; a sphere r 1.6 at the origin; a square plane, x and y in
    // [-3, 3], at z = -5, 15 from the eye.
    let text = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
                [[objects]]\nsphere = { center = [0, 0, 0], radius = 1.6 }\n\
                [[objects]]\ntriangle = [[-3, -3, -5], [3, -3, -5], [3, 3, -5]]\n\
                [[objects]]\ntriangle = [[-3, -3, -5], [3, 3, -5], [-3, 3, -5]]\n";
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("depth.toml");
    std::fs::write(&file, text).unwrap();
    let (exr, png) = (dir.path().join("d.exr"), dir.path().join("d.png"));
    let options = Options {
        aov: Some(Aov::Depth),
        ..Options::default()
    };
    write(Input::File(file.clone()), options, &exr, BitDepth::Eight);
    write(Input::File(file), options, &png, BitDepth::Eight);
    let depth = image::open(&exr).unwrap().into_rgb32f();
    // The pixel (i, j)'s ray through its centre makes an angle with the
    // axis whose cosine is f / |(dx, dy, f)|, f = 250 / tan(25 deg).
    let f = 250.0 / 25f64.to_radians().tan();
    let cos = |i: u32, j: u32| {
        let (dx, dy) = (i as f64 + 0.5 - 250.0, j as f64 + 0.5 - 200.0);
        f / (dx * dx + dy * dy + f * f).sqrt()
    };
    // The sphere: the nearer root of t^2 - 2 t 10 cos + (100 - r^2) = 0.
    let sphere = |c: f64| 10.0 * c - (100.0 * c * c - (100.0 - 1.6 * 1.6)).sqrt();
    let plane = |c: f64| 15.0 / c;
    let checks = [
        ((249, 199), sphere(cos(249, 199))),
        ((299, 229), sphere(cos(299, 229))),
        ((190, 180), sphere(cos(190, 180))),
        ((349, 199), plane(cos(349, 199))),
        ((249, 294), plane(cos(249, 294))),
        ((150, 120), plane(cos(150, 120))),
        ((0, 0), 0.0),
        ((249, 330), 0.0),
    ];
    for ((i, j), expected) in checks {
        let got = depth.get_pixel(i, j).0;
        assert!(got[0] == got[1] && got[1] == got[2], "{got:?}");
        let error = (f64::from(got[0]) - expected).abs();
        assert!(
            error < 1e-4 * expected.max(1.0),
            "({i}, {j}): {got:?}, expected {expected}"
        );
    }
    // The PNG keeps the greys (the sphere's front point, at the box's
    // nearest, is white); the EXR's values are not greys.
    let greys = image::open(&png).unwrap().into_rgb8();
    assert_eq!(greys.get_pixel(249, 199).0, [254; 3]);
    assert!(depth.get_pixel(249, 199).0[0] > 8.0);
}
