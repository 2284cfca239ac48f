//! `tracer render --denoise --denoising-data -o OUT.exr`, read back with
//! the exr crate as any OpenEXR reader would: the denoised image in the
//! default layer, the noisy render and the guides in named layers, each
//! the image the tracer makes of it alone; and the refusals, before any
//! work; the prefilter (`--denoise-prefilter`) from the file or the
//! option. Needs Open Image Denoise (`cargo xtask oidn`): without it these
//! tests say so and pass, unless `CI` is set.

mod common;

use common::tracer;
use exr::prelude::{FlatSamples, ReadChannels, ReadLayers};
use std::path::{Path, PathBuf};
use std::process::Output;

fn cornell() -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml");
    path.to_str().unwrap().to_string()
}

/// Whether the library is there; when it is not, false (or a failure on CI).
fn oidn() -> bool {
    match tracer_pipeline::denoise::available() {
        Ok(()) => true,
        Err(e) if std::env::var_os("CI").is_some() => panic!("CI needs the denoiser: {e}"),
        Err(e) => {
            eprintln!("skipped: {e}");
            false
        }
    }
}

/// `tracer render` of the Cornell box, small, with `extra`; on 2 threads,
/// so that OIDN runs as in the other renders compared.
fn render(dir: &Path, extra: &[&str]) -> Output {
    render_scene(dir, &cornell(), extra)
}

/// `tracer render SCENE` at 64 pixels wide on 2 threads, with `extra`.
fn render_scene(dir: &Path, scene: &str, extra: &[&str]) -> Output {
    let mut args = vec!["render", scene, "--width", "64", "--threads", "2", "-q"];
    args.extend(extra);
    tracer(dir, &args)
}

fn ok(out: &Output) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
}

/// Every channel of the file's one part, by name, in the file's order.
fn channels(path: &Path) -> Vec<(String, Vec<f32>)> {
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_file(path)
        .unwrap();
    assert_eq!(image.layer_data.len(), 1, "one part");
    let layer = image.layer_data.into_iter().next().unwrap();
    layer
        .channel_data
        .list
        .into_iter()
        .map(|c| {
            let FlatSamples::F32(samples) = c.sample_data else {
                panic!("{} is not 32-bit float", c.name);
            };
            (c.name.to_string(), samples)
        })
        .collect()
}

/// The R, G, B channels of `layer` ("" for the default one), interleaved.
fn rgb(channels: &[(String, Vec<f32>)], layer: &str) -> Vec<f32> {
    let get = |c: &str| {
        let name = if layer.is_empty() {
            c.to_string()
        } else {
            format!("{layer}.{c}")
        };
        let found = channels.iter().find(|(n, _)| *n == name);
        &found.unwrap_or_else(|| panic!("no channel {name}")).1
    };
    let (r, g, b) = (get("R"), get("G"), get("B"));
    (0..r.len()).flat_map(|i| [r[i], g[i], b[i]]).collect()
}

/// That `got` is `expected` bit for bit; else where it first differs.
fn same_bits(what: &str, got: &[f32], expected: &[f32]) {
    assert_eq!(got.len(), expected.len(), "{what}: the number of values");
    let differs = got
        .iter()
        .zip(expected)
        .position(|(a, b)| a.to_bits() != b.to_bits());
    if let Some(i) = differs {
        panic!("{what}: value {i} is {}, expected {}", got[i], expected[i]);
    }
}

#[test]
fn the_layers_are_the_denoised_the_noisy_render_and_the_guides_each_as_made_alone() {
    if !oidn() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Each path traced alone and one camera ray, set in the file (a
    // denoised render otherwise takes 16 at edges), so the render without
    // --denoise is the one the denoiser was given.
    let text = std::fs::read_to_string(cornell()).unwrap();
    let plain = text.replacen(
        "[render]\n",
        "[render]\npath_reuse = 1\ncamera_rays = 1\n",
        1,
    );
    std::fs::write(d.join("cornell.toml"), plain).unwrap();
    let render = |d: &Path, extra: &[&str]| render_scene(d, "cornell.toml", extra);
    let paths = ["--samples", "4"];
    ok(&render(
        d,
        &[
            &paths[..],
            &["--denoise", "--denoising-data", "-o", "data.exr"],
        ]
        .concat(),
    ));
    ok(&render(
        d,
        &[&paths[..], &["--denoise", "-o", "denoised.exr"]].concat(),
    ));
    ok(&render(d, &[&paths[..], &["-o", "noisy.exr"]].concat()));
    // The guides take 16 samples a pixel whatever the paths.
    for aov in ["albedo", "shading-normal"] {
        let out = format!("{aov}.exr");
        ok(&render(d, &["--aov", aov, "--samples", "16", "-o", &out]));
    }
    let data = channels(&d.join("data.exr"));
    let names: Vec<&str> = data.iter().map(|(n, _)| n.as_str()).collect();
    let layers = ["", "albedo.", "emission.", "noisy.", "normal."];
    let expected: Vec<String> = layers
        .iter()
        .flat_map(|l| ["B", "G", "R"].map(|c| format!("{l}{c}")))
        .collect();
    assert_eq!(names, expected);
    let alone = |name: &str| channels(&d.join(name));
    // Bit for bit: the render is the same every time, and so is OIDN's
    // work on one machine and thread count.
    let denoised = rgb(&data, "");
    same_bits("denoised", &denoised, &rgb(&alone("denoised.exr"), ""));
    same_bits("noisy", &rgb(&data, "noisy"), &rgb(&alone("noisy.exr"), ""));
    assert!(rgb(&data, "noisy") != denoised, "the denoised differs");
    same_bits(
        "albedo",
        &rgb(&data, "albedo"),
        &rgb(&alone("albedo.exr"), ""),
    );
    // The normal as OIDN takes it, -1 to 1: the AOV's (n + 1) / 2 undone.
    let normal: Vec<f32> = rgb(&alone("shading-normal.exr"), "")
        .into_iter()
        .map(|v| v * 2.0 - 1.0)
        .collect();
    same_bits("normal", &rgb(&data, "normal"), &normal);
    // The lamp, seen at the top middle: its emission, 18.4 in red.
    let emission = rgb(&data, "emission");
    let lamp = (9 * 64 + 32) * 3;
    assert!((emission[lamp] - 18.387).abs() < 1e-3, "{}", emission[lamp]);
    // What the render's own camera rays saw, not a guide sampled apart:
    // the render less it (what OIDN filtered) is never below 0, even at
    // the lamp's edge, where its share of lamp is noise at 4 paths.
    let noisy = rgb(&data, "noisy");
    for (k, (n, e)) in noisy.iter().zip(&emission).enumerate() {
        assert!(n - e > -1e-4 * e.max(1.0), "value {k}: {n} less {e}");
    }
    let edges = emission.iter().filter(|&&e| e > 0.5 && e < 17.0).count();
    assert!(edges > 10, "the lamp's edge is among them: {edges} values");
}

#[test]
fn denoising_data_is_refused_before_any_work_but_to_a_denoised_exr() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cases: [(&[&str], &str); 3] = [
        (
            &["--denoise", "--denoising-data", "-o", "out.png"],
            "out.png: --denoising-data keeps the noisy image and the denoiser's guides as layers of an OpenEXR file",
        ),
        (
            &["--denoising-data", "-o", "out.exr"],
            "this render is not denoised: add --denoise",
        ),
        (
            &["--denoise", "--denoising-data", "--tile", "0/2", "-o", "out.exr"],
            "'--denoising-data' cannot be used with '--tile <I/N>'",
        ),
    ];
    for (args, message) in cases {
        // 65536 paths a pixel: a render would not end in the test's time.
        let out = render(d, &[&["--samples", "65536"], args].concat());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(message), "{args:?}: {stderr}");
    }
    let left: Vec<_> = std::fs::read_dir(d).unwrap().collect();
    assert!(left.is_empty(), "no file written: {left:?}");
}

#[test]
fn the_prefilter_is_set_in_the_file_or_by_the_option_and_each_denoises_its_own_way() {
    if !oidn() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = std::fs::read_to_string(cornell()).unwrap();
    let none = text.replacen("[render]\n", "[render]\ndenoise_prefilter = \"none\"\n", 1);
    std::fs::write(d.join("none.toml"), none).unwrap();
    let paths = ["--samples", "4", "--denoise"];
    ok(&render_scene(
        d,
        "none.toml",
        &[&paths[..], &["-o", "file.exr"]].concat(),
    ));
    for prefilter in ["none", "fast", "accurate"] {
        let out = format!("{prefilter}.exr");
        let option = ["--denoise-prefilter", prefilter, "-o", &out];
        ok(&render(d, &[&paths[..], &option].concat()));
    }
    let image = |name: &str| rgb(&channels(&d.join(name)), "");
    same_bits("the file's none", &image("file.exr"), &image("none.exr"));
    let [none, fast, accurate] = ["none.exr", "fast.exr", "accurate.exr"].map(image);
    assert!(none != fast && none != accurate && fast != accurate);
    // The summary says which.
    let args = [
        &["render", "none.toml", "--width", "64"][..],
        &paths,
        &["-o", "a.png"],
    ];
    let out = tracer(d, &args.concat());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("denoised (high, no prefilter)"), "{stderr}");
    let out = render(
        d,
        &["--denoise", "--denoise-prefilter", "sharp", "-o", "b.png"],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("[possible values: none, fast, accurate]"),
        "{stderr}"
    );
}
