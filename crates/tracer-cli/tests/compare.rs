//! `tracer compare`: an image against an image or a scene, the mistakes it
//! names (and does not name), the class report, bad input.

mod common;

use common::tracer;
use image::{Rgb, RgbImage};

use std::path::{Path, PathBuf};
use std::process::Output;
use std::time::Duration;

/// A lab scene, by its path as an argument for `tracer`.
fn scene(name: &str) -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../scenes/{name}"));
    p.to_str().unwrap().to_string()
}

fn scenes_dir() -> String {
    scene("")
}

/// The words that start a diagnosis line (the first five are the ones
/// scripts look for).
const WORDS: [&str; 7] = [
    "size",
    "mirror",
    "gamma",
    "half a pixel",
    "swapped",
    "upside down",
    "one pixel",
];

fn stdout_of(out: &Output) -> String {
    String::from_utf8(out.stdout.clone()).unwrap()
}

fn stderr_of(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// `tracer render SCENE -o OUT ARGS` in `dir`; the image read back.
fn render(dir: &Path, scene_file: &str, out: &str, args: &[&str]) -> RgbImage {
    let mut all = vec!["render", scene_file, "-o", out, "--quiet"];
    all.extend_from_slice(args);
    let run = tracer(dir, &all);
    assert!(run.status.success(), "{}", stderr_of(&run));
    image::open(dir.join(out)).unwrap().into_rgb8()
}

/// `tracer compare IMAGE REFERENCE` in `dir`.
fn compare(dir: &Path, image: &str, reference: &str) -> Output {
    tracer(dir, &["compare", image, reference])
}

/// The diagnosis lines of a compare's stdout: those starting with a word.
fn diagnoses(stdout: &str) -> Vec<String> {
    stdout
        .lines()
        .filter(|l| WORDS.iter().any(|w| l.starts_with(&format!("{w}: "))))
        .map(str::to_string)
        .collect()
}

/// `image` saved as `name` in `dir`.
fn save(dir: &Path, name: &str, image: &RgbImage) -> String {
    image.save(dir.join(name)).unwrap();
    name.to_string()
}

/// A compare that exits 1 and names exactly one mistake, which starts with `word`.
fn assert_named(out: &Output, word: &str) -> String {
    let stdout = stdout_of(out);
    assert_eq!(out.status.code(), Some(1), "{stdout}{}", stderr_of(out));
    let found = diagnoses(&stdout);
    assert_eq!(found.len(), 1, "{stdout}");
    assert!(found[0].starts_with(&format!("{word}: ")), "{stdout}");
    found[0].clone()
}

fn mirrored(image: &RgbImage) -> RgbImage {
    image::imageops::flip_horizontal(image)
}

fn channels_swapped(image: &RgbImage) -> RgbImage {
    let mut out = image.clone();
    for p in out.pixels_mut() {
        p.0.swap(0, 2);
    }
    out
}

/// A deterministic stream of numbers in 0..n (xorshift).
struct Noise(u64);

impl Noise {
    fn below(&mut self, n: u64) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0 % n
    }
}

/// Every channel of every pixel moved by up to +-10 levels.
fn noisy(image: &RgbImage) -> RgbImage {
    let mut noise = Noise(0x2545_f491_4f6c_dd1d);
    let mut out = image.clone();
    for p in out.pixels_mut() {
        for c in p.0.iter_mut() {
            *c = (i64::from(*c) + noise.below(21) as i64 - 10).clamp(0, 255) as u8;
        }
    }
    out
}

/// 2000 pixels of random colours at random places.
fn speckled(image: &RgbImage) -> RgbImage {
    let mut noise = Noise(0x9e37_79b9_7f4a_7c15);
    let mut out = image.clone();
    for _ in 0..2000 {
        let x = noise.below(u64::from(out.width())) as u32;
        let y = noise.below(u64::from(out.height())) as u32;
        let colour = [0; 3].map(|_| noise.below(256) as u8);
        out.put_pixel(x, y, Rgb(colour));
    }
    out
}

#[test]
fn an_identical_image_exits_0_against_its_scene_and_as_an_image() {
    let dir = tempfile::tempdir().unwrap();
    render(dir.path(), &scene("illumination.toml"), "mine.png", &[]);
    let out = compare(dir.path(), "mine.png", &scene("illumination.toml"));
    let stdout = stdout_of(&out);
    assert_eq!(out.status.code(), Some(0), "{stdout}{}", stderr_of(&out));
    assert!(stdout.contains("(0 of 200000)"), "{stdout}");
    assert!(stdout.contains("PSNR       infinite"), "{stdout}");
    assert!(stdout.contains("FLIP       0.0000"), "{stdout}");
    assert!(stdout.ends_with("within tolerance: no pixel is off by more than 2 of 255\n"));
    assert!(diagnoses(&stdout).is_empty(), "{stdout}");
    let copy = save(
        dir.path(),
        "copy.png",
        &image::open(dir.path().join("mine.png"))
            .unwrap()
            .into_rgb8(),
    );
    assert_eq!(
        compare(dir.path(), "mine.png", &copy).status.code(),
        Some(0)
    );
}

#[test]
fn a_planted_one_pixel_error_is_found_at_its_place_and_named_nothing_else() {
    let dir = tempfile::tempdir().unwrap();
    let scene_file = scene("illumination.toml");
    let mut image = render(dir.path(), &scene_file, "mine.png", &[]);
    // x counts columns from the left, y rows from the top.
    image.put_pixel(123, 45, Rgb([255, 0, 255]));
    let name = save(dir.path(), "planted.png", &image);
    let out = compare(dir.path(), &name, &scene_file);
    let stdout = stdout_of(&out);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert!(stdout.contains("(1 of 200000)"), "{stdout}");
    assert!(
        stdout.contains(
            "largest    255 of 255 at (123, 45): image (255, 0, 255), reference (0, 0, 0)"
        ),
        "{stdout}"
    );
    let explain = format!("  (123, 45)  image (255, 0, 255), reference (0, 0, 0)  tracer explain {scene_file} 123 45\n");
    assert!(stdout.contains(&explain), "{stdout}");
    assert!(diagnoses(&stdout).is_empty(), "{stdout}");
    assert!(stdout.ends_with("not within tolerance: 1 pixel off by more than 2 of 255\n"));

    // Off by 5 levels: beyond the default tolerance, within --tolerance 5.
    let mut image = image::open(dir.path().join("mine.png"))
        .unwrap()
        .into_rgb8();
    let Rgb([r, g, b]) = *image.get_pixel(250, 200);
    image.put_pixel(250, 200, Rgb([r.saturating_sub(5), g, b]));
    let name = save(dir.path(), "five.png", &image);
    assert_eq!(
        compare(dir.path(), &name, &scene_file).status.code(),
        Some(1)
    );
    let loose = tracer(
        dir.path(),
        &["compare", &name, &scene_file, "--tolerance", "5"],
    );
    assert_eq!(loose.status.code(), Some(0), "{}", stdout_of(&loose));
}

#[test]
fn gamma_applied_twice_or_not_at_all_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let scene_file = scene("illumination.toml");
    // c^(1/2.2) twice is c^(1/4.84).
    render(dir.path(), &scene_file, "twice.png", &["--gamma", "4.84"]);
    let line = assert_named(&compare(dir.path(), "twice.png", &scene_file), "gamma");
    assert!(line.contains("gamma is applied twice"), "{line}");
    render(dir.path(), &scene_file, "linear.png", &["--gamma", "1"]);
    let line = assert_named(&compare(dir.path(), "linear.png", &scene_file), "gamma");
    assert!(line.contains("no gamma is applied"), "{line}");
    // A display's measured gamma where the scene's was due.
    for gamma in ["1.8", "2.4", "2.6"] {
        render(dir.path(), &scene_file, "other.png", &["--gamma", gamma]);
        let line = assert_named(&compare(dir.path(), "other.png", &scene_file), "gamma");
        let said = format!("encoded with gamma {gamma}, the reference with 2.2");
        assert!(line.contains(&said), "{line}");
        assert!(
            line.contains(&format!("tracer render --gamma {gamma}")),
            "{line}"
        );
    }
}

#[test]
fn a_mirror_image_is_named_and_so_is_one_upside_down() {
    let dir = tempfile::tempdir().unwrap();
    let scene_file = scene("reflectance2.toml");
    let image = render(dir.path(), &scene_file, "mine.png", &[]);
    let name = save(dir.path(), "mirror.png", &mirrored(&image));
    let line = assert_named(&compare(dir.path(), &name, &scene_file), "mirror");
    assert!(line.contains("+x on the image's left"), "{line}");
    let name = save(
        dir.path(),
        "flipped.png",
        &image::imageops::flip_vertical(&image),
    );
    let line = assert_named(&compare(dir.path(), &name, &scene_file), "upside down");
    assert!(line.contains("Turned upright, 0 pixels off"), "{line}");
}

#[test]
fn a_mirror_image_of_a_right_handed_scene_gets_that_cameras_advice() {
    let dir = tempfile::tempdir().unwrap();
    let scene_file = scene("glass.toml");
    let text = std::fs::read_to_string(&scene_file).unwrap();
    assert!(
        text.contains("handedness = \"right\""),
        "glass.toml changed"
    );
    let image = render(dir.path(), &scene_file, "mine.png", &[]);
    let name = save(dir.path(), "mirror.png", &mirrored(&image));
    let line = assert_named(&compare(dir.path(), &name, &scene_file), "mirror");
    assert!(line.contains("handedness = \"right\""), "{line}");
    assert!(!line.contains("The lab's camera puts"), "{line}");
}

#[test]
fn a_mirror_image_of_a_canvas_is_named_alone() {
    // Flipped back it is exact: no second mistake (nor a half pixel) is
    // looked for.
    let dir = tempfile::tempdir().unwrap();
    let scene_file = scene("robot.toml");
    let image = render(dir.path(), &scene_file, "mine.png", &[]);
    let name = save(dir.path(), "mirror.png", &mirrored(&image));
    assert_named(&compare(dir.path(), &name, &scene_file), "mirror");
}

#[test]
fn swapped_channels_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let scene_file = scene("reflectance2.toml");
    let image = render(dir.path(), &scene_file, "mine.png", &[]);
    let name = save(dir.path(), "bgr.png", &channels_swapped(&image));
    let line = assert_named(&compare(dir.path(), &name, &scene_file), "swapped");
    assert!(line.contains("BGR"), "{line}");
}

#[test]
fn two_mistakes_at_once_are_both_named() {
    let dir = tempfile::tempdir().unwrap();
    let scene_file = scene("reflectance2.toml");
    // Mirrored and written BGR: undoing either alone leaves most pixels off.
    let image = render(dir.path(), &scene_file, "mine.png", &[]);
    let name = save(dir.path(), "both.png", &channels_swapped(&mirrored(&image)));
    let out = compare(dir.path(), &name, &scene_file);
    let found = diagnoses(&stdout_of(&out));
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(found[0].starts_with("mirror: "), "{found:?}");
    assert!(found[0].contains("and with the channels swapped back too, 0 pixels off"));
    assert!(found[1].starts_with("swapped: "), "{found:?}");
    assert!(found[1].contains("and with the image flipped back too, 0 pixels off"));
    // Upside down with no gamma: the linear values, flipped.
    render(dir.path(), &scene_file, "linear.png", &["--gamma", "1"]);
    let linear = image::open(dir.path().join("linear.png"))
        .unwrap()
        .into_rgb8();
    let name = save(
        dir.path(),
        "flipped.png",
        &image::imageops::flip_vertical(&linear),
    );
    let found = diagnoses(&stdout_of(&compare(dir.path(), &name, &scene_file)));
    let words: Vec<_> = found.iter().map(|f| f.split(':').next().unwrap()).collect();
    assert_eq!(words, ["upside down", "gamma"], "{found:?}");
    assert!(found[1].contains("no gamma is applied"), "{found:?}");
}

/// The illumination scene with the camera turned by half a pixel right
/// and down: each ray goes where a pixel corner's would.
fn half_pixel_scene(dir: &Path) -> String {
    let text = std::fs::read_to_string(scene("illumination.toml")).unwrap();
    // 10 units away, 50 degrees across 500 pixels.
    let half = 10.0 * 25f64.to_radians().tan() / 500.0;
    let turned = text.replace(
        "look_at = [0, 0, 0]",
        &format!("look_at = [{half}, {}, 0]", -half),
    );
    assert_ne!(turned, text);
    std::fs::write(dir.join("corner.toml"), turned).unwrap();
    "corner.toml".to_string()
}

#[test]
fn a_half_pixel_shift_is_named_and_a_whole_pixel_shift_told_apart() {
    let dir = tempfile::tempdir().unwrap();
    let scene_file = scene("illumination.toml");
    let corner = half_pixel_scene(dir.path());
    render(dir.path(), &corner, "corner.png", &[]);
    let line = assert_named(
        &compare(dir.path(), "corner.png", &scene_file),
        "half a pixel",
    );
    assert!(line.contains("corners, not their centres"), "{line}");
    // Anti-aliased (16 samples a pixel, the reference too), still found.
    render(dir.path(), &corner, "corner16.png", &["--samples", "16"]);
    render(
        dir.path(),
        &scene_file,
        "centre16.png",
        &["--samples", "16"],
    );
    assert_named(
        &compare(dir.path(), "corner16.png", "centre16.png"),
        "half a pixel",
    );
    // A whole pixel is another mistake.
    let image = render(dir.path(), &scene_file, "mine.png", &[]);
    let mut shifted = RgbImage::new(image.width(), image.height());
    image::imageops::replace(&mut shifted, &image, 1, 0);
    let name = save(dir.path(), "shifted.png", &shifted);
    let line = assert_named(&compare(dir.path(), &name, &scene_file), "one pixel");
    assert!(line.contains("(right)"), "{line}");
}

/// `scene_file` rendered as a tracer that aims each ray at a corner of
/// its pixel renders it (every sample moved by `shift` pixels), saved as
/// `out` in `dir`.
fn render_through_corner(dir: &Path, scene_file: &str, shift: [f32; 2], out: &str) -> String {
    let input = tracer_pipeline::Input::File(PathBuf::from(scene_file));
    let loaded = tracer_pipeline::load(&input).unwrap();
    let options = tracer_pipeline::Options {
        pixel_shift: Some(shift),
        ..Default::default()
    };
    let rendered = tracer_pipeline::render(&loaded, &options, &|_| {}).unwrap();
    save(dir, out, &rendered.image.to_rgb8())
}

#[test]
fn a_half_pixel_shift_is_named_against_a_scene_textured_and_anti_aliased() {
    let dir = tempfile::tempdir().unwrap();
    // Image textures, four samples a pixel: resampling the reference image
    // at the corners cannot stand in for a render there.
    let scene_file = scene("textures.toml");
    let left_up = render_through_corner(dir.path(), &scene_file, [-0.5, -0.5], "mine.png");
    let line = assert_named(&compare(dir.path(), &left_up, &scene_file), "half a pixel");
    assert!(line.contains("(right and down)"), "{line}");
    assert!(line.contains(", 0 pixels off"), "{line}");
    let right_up = render_through_corner(dir.path(), &scene_file, [0.5, -0.5], "mine2.png");
    let line = assert_named(&compare(dir.path(), &right_up, &scene_file), "half a pixel");
    assert!(line.contains("(left and down)"), "{line}");
}

#[test]
fn a_path_traced_reference_is_said_to_be_one_draw_of_its_noise() {
    let dir = tempfile::tempdir().unwrap();
    // The Cornell box, small: 64x64 pixels, 16 paths each.
    let text = std::fs::read_to_string(scene("cornell-box.toml")).unwrap();
    let small = text
        .replace("width = 256", "width = 64")
        .replace("height = 256", "height = 64")
        .replace("samples = 64", "samples = 16");
    std::fs::write(dir.path().join("box.toml"), small).unwrap();
    let scene_file = "box.toml";
    // Fewer paths: other noise, most pixels off, and no mistake named.
    render(dir.path(), scene_file, "fewer.png", &["--samples", "4"]);
    let out = compare(dir.path(), "fewer.png", scene_file);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(diagnoses(&stdout_of(&out)), Vec::<String>::new());
    let note = "the reference is path traced (16 paths a pixel)";
    assert!(stderr_of(&out).contains(note), "{}", stderr_of(&out));
    // Rendered with as many paths as the image: the same pixels.
    let args = ["compare", "fewer.png", scene_file, "--samples", "4"];
    let out = tracer(dir.path(), &args);
    assert_eq!(out.status.code(), Some(0), "{}", stdout_of(&out));
    // A time limit would make the reference the machine's: not used, said.
    let limited = std::fs::read_to_string(dir.path().join(scene_file)).unwrap();
    let limited = limited.replace("samples = 16", "samples = 16\ntime_limit = 60");
    std::fs::write(dir.path().join("limited.toml"), limited).unwrap();
    for args in [
        vec!["compare", "fewer.png", "limited.toml", "--samples", "4"],
        vec!["explain", "limited.toml", "3", "4"],
    ] {
        let out = tracer(dir.path(), &args);
        let said = "the scene's time_limit (60 s) is not used here: every sample is rendered";
        assert!(
            stderr_of(&out).contains(said),
            "{args:?}: {}",
            stderr_of(&out)
        );
    }
    // The same render (the samples are the same on every run): no note.
    render(dir.path(), scene_file, "same.png", &[]);
    let out = compare(dir.path(), "same.png", scene_file);
    assert_eq!(out.status.code(), Some(0), "{}", stdout_of(&out));
    assert!(!stderr_of(&out).contains(note));
    // Another size is the mistake, not the noise.
    render(dir.path(), scene_file, "wide.png", &["--width", "65"]);
    let out = compare(dir.path(), "wide.png", scene_file);
    assert_eq!(out.status.code(), Some(1));
    assert!(!stderr_of(&out).contains(note), "{}", stderr_of(&out));
}

#[test]
fn a_different_size_is_named_and_compared_no_further() {
    let dir = tempfile::tempdir().unwrap();
    let scene_file = scene("illumination.toml");
    render(dir.path(), &scene_file, "small.png", &["--width", "250"]);
    let out = tracer(
        dir.path(),
        &["compare", "small.png", &scene_file, "-o", "heat.png"],
    );
    let line = assert_named(&out, "size");
    assert!(
        line.contains("250x200 pixels, the reference 500x400 (half its width and height)"),
        "{line}"
    );
    assert!(stderr_of(&out).contains("no heat-map: the sizes differ"));
    assert!(!dir.path().join("heat.png").exists());
    assert_eq!(leftovers(dir.path()), Vec::<String>::new());
    // Known from the camera, not rendered: a 16384x16384 scene took 3.9 GB
    // to be found the wrong size.
    let text = std::fs::read_to_string(&scene_file).unwrap();
    let huge = text.replacen("width = 500", "width = 16384", 1).replacen(
        "height = 400",
        "height = 16384",
        1,
    );
    assert_ne!(huge, text, "the scene's size is written as expected");
    std::fs::write(dir.path().join("huge.toml"), huge).unwrap();
    let out = compare(dir.path(), "small.png", "huge.toml");
    assert!(
        stdout_of(&out).contains("(a scene not rendered, its camera's 16384x16384)"),
        "{}",
        stdout_of(&out)
    );
    assert!(
        !stderr_of(&out).contains("rows"),
        "no progress: {}",
        stderr_of(&out)
    );
}

#[test]
fn plain_noise_is_not_taken_for_a_mistake() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["illumination.toml", "reflectance2.toml", "texture.toml"] {
        let scene_file = scene(name);
        let image = render(dir.path(), &scene_file, "mine.png", &[]);
        for (kind, changed) in [("noisy", noisy(&image)), ("speckled", speckled(&image))] {
            let file = save(dir.path(), &format!("{kind}.png"), &changed);
            let out = compare(dir.path(), &file, &scene_file);
            let stdout = stdout_of(&out);
            assert_eq!(out.status.code(), Some(1), "{name} {kind}: {stdout}");
            assert!(stdout.contains("of the pixels"), "{stdout}");
            assert!(diagnoses(&stdout).is_empty(), "{name} {kind}: {stdout}");
        }
    }
}

#[test]
fn the_heat_map_is_flips_error_in_magma_and_written_whole() {
    let dir = tempfile::tempdir().unwrap();
    let scene_file = scene("illumination.toml");
    let mut image = render(dir.path(), &scene_file, "mine.png", &[]);
    for x in 100..110 {
        image.put_pixel(x, 50, Rgb([255, 255, 255]));
    }
    save(dir.path(), "line.png", &image);
    let out = tracer(
        dir.path(),
        &["compare", "line.png", &scene_file, "-o", "heat.png"],
    );
    assert_eq!(out.status.code(), Some(1));
    let map = image::open(dir.path().join("heat.png"))
        .unwrap()
        .into_rgb8();
    assert_eq!(map.dimensions(), (500, 400));
    // Magma: near black where nothing differs, bright on the planted line.
    let brightness = |p: &Rgb<u8>| p.0.iter().map(|&c| u32::from(c)).sum::<u32>();
    assert!(brightness(map.get_pixel(400, 350)) < 30);
    assert!(brightness(map.get_pixel(105, 50)) > 300);
    assert_eq!(leftovers(dir.path()), Vec::<String>::new());
}

/// Temporary output files left in `dir`.
fn leftovers(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.starts_with(".tracer-"))
        .collect()
}

/// A PNG of `width` x `height` RGB pixels by its header, with one row of
/// data: what a decoder sizes its buffer from.
fn png_header(width: u32, height: u32) -> Vec<u8> {
    let mut png = Vec::new();
    RgbImage::new(1, 1)
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    // IHDR's type, width and height follow the signature and its length.
    png[16..20].copy_from_slice(&width.to_be_bytes());
    png[20..24].copy_from_slice(&height.to_be_bytes());
    let crc = crc32fast::hash(&png[12..29]);
    png[29..33].copy_from_slice(&crc.to_be_bytes());
    png
}

#[test]
fn bad_input_exits_2_without_a_heat_map() {
    let dir = tempfile::tempdir().unwrap();
    let scene_file = scene("illumination.toml");
    render(dir.path(), &scene_file, "mine.png", &[]);
    std::fs::write(dir.path().join("text.png"), "not an image at all").unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(
        &bad,
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nfvo = 50\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("huge.png"), png_header(100_000, 100_000)).unwrap();
    let cases: [(&[&str], &str); 6] = [
        (&["text.png", "mine.png"], "text.png: not an image"),
        (
            &["huge.png", "mine.png"],
            "huge.png: 100000x100000 pixels; expected at most 16384 a side",
        ),
        (&["mine.png", "text.png"], "text.png: not an image"),
        (
            &["missing.png", "mine.png"],
            "missing.png: cannot read the image",
        ),
        (&["mine.png", "missing.toml"], "missing.toml"),
        (&["mine.png", "bad.toml"], "unknown key `fvo` in [camera]"),
    ];
    for (args, message) in cases {
        let mut all = vec!["compare"];
        all.extend_from_slice(args);
        all.extend_from_slice(&["-o", "heat.png"]);
        let out = tracer(dir.path(), &all);
        let stderr = stderr_of(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(message), "{args:?}: {stderr}");
        assert!(!dir.path().join("heat.png").exists(), "{args:?}");
        assert_eq!(leftovers(dir.path()), Vec::<String>::new());
    }
}

#[test]
fn a_reference_scene_with_errors_is_shown_as_tracer_check_shows_it() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("bad.toml"),
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nfvo = 50\n",
    )
    .unwrap();
    RgbImage::new(4, 4)
        .save(dir.path().join("mine.png"))
        .unwrap();
    let check = stderr_of(&tracer(dir.path(), &["check", "bad.toml"]));
    let located = check
        .strip_suffix("1 of 1 scene file failed the check\n")
        .expect("check's last line");
    assert!(located.contains("bad.toml:4:1"), "{check}");
    let out = compare(dir.path(), "mine.png", "bad.toml");
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stderr_of(&out), located);
    assert_eq!(stdout_of(&out), "");
}

/// A class of five: two lab scenes, each image with its planted fault (or
/// none), named by each of the rules, and a file named after no scene.
fn planted_class(dir: &Path) -> Vec<(&'static str, f64)> {
    let class = dir.join("class");
    std::fs::create_dir_all(class.join("alice")).unwrap();
    std::fs::create_dir_all(class.join("carol")).unwrap();
    let illumination = render(dir, &scene("illumination.toml"), "i.png", &[]);
    let reflectance = render(dir, &scene("reflectance2.toml"), "r.png", &[]);
    render(
        dir,
        &scene("illumination.toml"),
        "class/illumination-erin.png",
        &["--width", "250"],
    );
    save(&class, "alice/illumination.png", &mirrored(&illumination));
    save(&class, "illumination-bob.png", &illumination);
    save(
        &class,
        "carol/reflectance2.png",
        &channels_swapped(&reflectance),
    );
    let mut one = reflectance.clone();
    one.put_pixel(7, 8, Rgb([255, 255, 255]));
    save(&class, "reflectance2-dave.png", &one);
    save(&class, "notes.png", &one);
    // Worst first: another size counts as every pixel off.
    vec![
        ("class/illumination-erin.png", 1.0),
        ("class/carol/reflectance2.png", 0.142495),
        ("class/alice/illumination.png", 0.114650),
        ("class/reflectance2-dave.png", 0.000005),
        ("class/illumination-bob.png", 0.0),
    ]
}

#[test]
fn the_report_lists_a_planted_class_worst_first() {
    let dir = tempfile::tempdir().unwrap();
    let expected = planted_class(dir.path());
    let scenes = scenes_dir();
    let args = ["compare", "--report", "class", "--scenes", &scenes];
    let out = tracer(dir.path(), &args);
    let (stdout, stderr) = (stdout_of(&out), stderr_of(&out));
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    // Each scene rendered once, for all its images.
    for name in ["illumination", "reflectance2"] {
        let line = format!("rendering {scenes}{name}.toml");
        assert_eq!(stderr.matches(&line).count(), 1, "{stderr}");
    }
    assert!(
        stderr.contains("skipped: class/notes.png is named after no scene"),
        "{stderr}"
    );

    let report = dir.path().join("report");
    let csv = std::fs::read_to_string(report.join("report.csv")).unwrap();
    let mut rows = csv.lines();
    assert_eq!(
        rows.next(),
        Some("image,scene,differing,largest,x,y,psnr_db,flip,mistakes")
    );
    let rows: Vec<Vec<&str>> = rows.map(|r| r.split(',').collect()).collect();
    let found: Vec<(&str, f64)> = rows.iter().map(|r| (r[0], r[2].parse().unwrap())).collect();
    assert_eq!(found.len(), expected.len(), "{csv}");
    for ((path, share), (want, want_share)) in found.iter().zip(&expected) {
        assert_eq!(path, want, "{csv}");
        assert!((share - want_share).abs() < 1e-6, "{csv}");
    }
    let mistakes: Vec<&str> = rows.iter().map(|r| r[8]).collect();
    assert_eq!(mistakes, ["size", "swapped", "mirror", "", ""]);
    assert_eq!(rows[3][3..6], ["255", "7", "8"]);

    // The same order on stdout and on the page.
    let order = |text: &str| -> Vec<usize> {
        expected
            .iter()
            .map(|(p, _)| text.find(p).unwrap_or_else(|| panic!("{p}: {text}")))
            .collect()
    };
    let is_sorted = |v: &[usize]| v.windows(2).all(|w| w[0] < w[1]);
    assert!(is_sorted(&order(&stdout)), "{stdout}");
    let page = std::fs::read_to_string(report.join("index.html")).unwrap();
    let sections = &page[page.find("<section").unwrap()..];
    assert!(is_sorted(&order(sections)), "{page}");
    assert!(page.contains("5 images compared: 1 within tolerance, 4 not"));
    for file in [
        "reference-illumination.png",
        "reference-reflectance2.png",
        "1-image.png",
        "2-heatmap.png",
        "5-heatmap.png",
    ] {
        assert!(report.join(file).is_file(), "{file}");
    }
    // Another size has no heat-map.
    assert!(!report.join("1-heatmap.png").exists());

    // An earlier report is replaced, and nothing is left beside it.
    std::fs::remove_file(dir.path().join("class/illumination-erin.png")).unwrap();
    let again = tracer(dir.path(), &args);
    assert_eq!(again.status.code(), Some(1), "{}", stderr_of(&again));
    let csv = std::fs::read_to_string(report.join("report.csv")).unwrap();
    assert_eq!(csv.lines().count(), 5, "{csv}");
    assert!(!report.join("5-image.png").exists());
    assert_eq!(leftovers(dir.path()), Vec::<String>::new());
}

#[test]
fn a_bad_class_or_scene_exits_2_and_writes_no_report() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    std::fs::create_dir_all(dir.path().join("class")).unwrap();
    std::fs::create_dir_all(&scenes).unwrap();
    std::fs::write(
        scenes.join("bad.toml"),
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nfvo = 50\n",
    )
    .unwrap();
    std::fs::copy(scene("illumination.toml"), scenes.join("illumination.toml")).unwrap();
    RgbImage::new(4, 4)
        .save(dir.path().join("class/bad-alice.png"))
        .unwrap();
    let run = || tracer(dir.path(), &["compare", "--report", "class", "-o", "out"]);

    let out = run();
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr_of(&out).contains("bad.toml:4:1"),
        "{}",
        stderr_of(&out)
    );

    std::fs::remove_file(dir.path().join("class/bad-alice.png")).unwrap();
    let out = run();
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr_of(&out).contains("no image is named after a scene"),
        "{}",
        stderr_of(&out)
    );
    assert!(!dir.path().join("out").exists());

    // A folder that is not a report is not replaced.
    render(
        dir.path(),
        &scene("illumination.toml"),
        "class/illumination.png",
        &[],
    );
    std::fs::create_dir(dir.path().join("out")).unwrap();
    std::fs::write(dir.path().join("out/keep.txt"), "mine").unwrap();
    let out = run();
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr_of(&out).contains("is not a report"),
        "{}",
        stderr_of(&out)
    );
    assert_eq!(
        std::fs::read_to_string(dir.path().join("out/keep.txt")).unwrap(),
        "mine"
    );
    assert_eq!(leftovers(dir.path()), Vec::<String>::new());
}

#[test]
fn an_unreadable_image_is_reported_beside_the_others_and_a_pipe_is_skipped() {
    let dir = tempfile::tempdir().unwrap();
    let class = dir.path().join("class");
    std::fs::create_dir_all(&class).unwrap();
    render(
        dir.path(),
        &scene("illumination.toml"),
        "class/illumination-alice.png",
        &[],
    );
    std::fs::write(class.join("illumination-bob.png"), "not an image").unwrap();
    // A link to a file is read; a pipe would block a read for ever.
    std::os::unix::fs::symlink(
        "illumination-alice.png",
        class.join("illumination-carol.png"),
    )
    .unwrap();
    let fifo = class.join("illumination-dave.png");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    let scenes = scenes_dir();
    let out = tracer(
        dir.path(),
        &["compare", "--report", "class", "--scenes", &scenes],
    );
    let (stdout, stderr) = (stdout_of(&out), stderr_of(&out));
    // Not all within tolerance: exit 1, and the report is written.
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    assert!(
        stderr.contains("skipped: class/illumination-dave.png is not a file"),
        "{stderr}"
    );
    assert!(
        stderr.contains("not compared: class/illumination-bob.png: not an image"),
        "{stderr}"
    );
    assert!(
        stdout.contains("2 images against 1 scene: 2 within tolerance, 0 not; 1 not compared"),
        "{stdout}"
    );
    let report = dir.path().join("report");
    let csv = std::fs::read_to_string(report.join("report.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len(), 3, "{csv}");
    assert!(
        rows[0].starts_with("class/illumination-alice.png,illumination,0.000000"),
        "{csv}"
    );
    assert!(
        rows[1].starts_with("class/illumination-carol.png,illumination,0.000000"),
        "{csv}"
    );
    assert_eq!(
        rows[2],
        "class/illumination-bob.png,illumination,,,,,,,\
         unreadable: not an image (expected a .png or .jpg file)"
    );
    let page = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert!(page.contains("2 images compared: 2 within tolerance, 0 not; 1 not compared"));
    assert!(page.contains("Not compared"), "{page}");
}

#[test]
fn a_heat_map_that_cannot_be_written_is_not_taken_for_a_verdict() {
    let dir = tempfile::tempdir().unwrap();
    render(dir.path(), &scene("shadows.toml"), "mine.png", &[]);
    let out = tracer(
        dir.path(),
        &[
            "compare",
            "mine.png",
            "mine.png",
            "-o",
            "no/such/folder/heat.png",
        ],
    );
    // Identical images: 1 ("not within tolerance") would be a false verdict.
    assert_eq!(out.status.code(), Some(2), "{}", stderr_of(&out));
    assert!(
        stderr_of(&out).contains("no/such/folder"),
        "{}",
        stderr_of(&out)
    );
}

#[test]
fn a_jpeg_or_a_transparent_image_is_noted() {
    let dir = tempfile::tempdir().unwrap();
    let scene_file = scene("shadows.toml");
    let image = render(dir.path(), &scene_file, "mine.png", &[]);
    image::DynamicImage::ImageRgb8(image.clone())
        .save(dir.path().join("mine.jpg"))
        .unwrap();
    let out = compare(dir.path(), "mine.jpg", &scene_file);
    assert!(
        stderr_of(&out).contains("mine.jpg: a JPEG's compression"),
        "{}",
        stderr_of(&out)
    );
    let mut clear = image::DynamicImage::ImageRgb8(image).to_rgba8();
    clear.pixels_mut().for_each(|p| p.0[3] = 0);
    clear.save(dir.path().join("clear.png")).unwrap();
    let out = compare(dir.path(), "clear.png", &scene_file);
    // Its colours are the render's: within tolerance, and said to be clear.
    assert_eq!(out.status.code(), Some(0));
    assert!(
        stderr_of(&out).contains("clear.png: has transparent pixels"),
        "{}",
        stderr_of(&out)
    );
    let out = compare(dir.path(), "mine.png", &scene_file);
    assert!(!stderr_of(&out).contains("note:"), "{}", stderr_of(&out));
}

#[test]
fn a_report_written_into_the_class_is_not_compared_again() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("class")).unwrap();
    render(
        dir.path(),
        &scene("shadows.toml"),
        "class/shadows-amy.png",
        &[],
    );
    let scenes = scenes_dir();
    // A report in a folder named after a scene, among the submissions.
    let first = [
        "compare",
        "--report",
        "class",
        "--scenes",
        &scenes,
        "-o",
        "class/shadows",
    ];
    assert_eq!(tracer(dir.path(), &first).status.code(), Some(0));
    let again = tracer(
        dir.path(),
        &["compare", "--report", "class", "--scenes", &scenes],
    );
    let stdout = stdout_of(&again);
    assert_eq!(
        again.status.code(),
        Some(0),
        "{stdout}{}",
        stderr_of(&again)
    );
    assert!(
        stdout.contains("1 image against 1 scene: 1 within tolerance"),
        "{stdout}"
    );
}

#[test]
fn a_scene_with_mistakes_leaves_its_images_uncompared_not_the_class() {
    let dir = tempfile::tempdir().unwrap();
    let (class, scenes) = (dir.path().join("class"), dir.path().join("scenes"));
    std::fs::create_dir_all(&class).unwrap();
    std::fs::create_dir_all(&scenes).unwrap();
    std::fs::copy(scene("shadows.toml"), scenes.join("shadows.toml")).unwrap();
    std::fs::write(
        scenes.join("broken.toml"),
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n\n\
         [[objects]]\nsphere = { center = [0, 0, 0], radius = 1 }\nmaterial = \"nope\"\n",
    )
    .unwrap();
    render(
        dir.path(),
        &scene("shadows.toml"),
        "class/shadows-amy.png",
        &[],
    );
    std::fs::copy(
        dir.path().join("class/shadows-amy.png"),
        class.join("broken-amy.png"),
    )
    .unwrap();
    let out = tracer(
        dir.path(),
        &["compare", "--report", "class", "--scenes", "scenes"],
    );
    let (stdout, stderr) = (stdout_of(&out), stderr_of(&out));
    // The other image is compared and the report written; exit 1, as for
    // an unreadable image.
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    assert!(stderr.contains("unknown material `nope`"), "{stderr}");
    assert!(
        stderr.contains(
            "not compared: class/broken-amy.png: its scene scenes/broken.toml has mistakes"
        ),
        "{stderr}"
    );
    assert!(
        stdout.contains("1 image against 1 scene: 1 within tolerance, 0 not; 1 not compared"),
        "{stdout}"
    );
    let csv = std::fs::read_to_string(dir.path().join("report/report.csv")).unwrap();
    assert!(
        csv.contains("class/shadows-amy.png,shadows,0.000000"),
        "{csv}"
    );
    assert!(
        csv.contains("class/broken-amy.png,broken,,,,,,,not compared: its scene"),
        "{csv}"
    );
    // More samples than a Whitted scene takes: its images are not
    // compared, and why is said; the run goes on.
    let args = [
        "compare",
        "--report",
        "class",
        "--scenes",
        "scenes",
        "--samples",
        "5000",
        "-o",
        "many",
    ];
    let out = tracer(dir.path(), &args);
    let stderr = stderr_of(&out);
    assert!(
        stderr.contains("its scene scenes/shadows.toml could not be rendered: --samples 5000"),
        "{stderr}"
    );
    // Nothing compared at all: exit 2, no report.
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(!dir.path().join("many").exists());
}

/// The report's `index.html` in `dir` as headless Chromium has it once its
/// script ran: what its image check recorded.
fn loaded_in_chromium(chromium: &Path, dir: &Path) -> headless::ImageCheck {
    let page = dir.join("my report/index.html");
    let dom = headless::dump_dom(chromium, &page, Duration::from_secs(120)).unwrap();
    headless::image_check(&dom).unwrap_or_else(|e| panic!("{e:#}\n{dom}"))
}

#[test]
fn every_image_of_the_report_loads_in_chromium() {
    let Some(chromium) = headless::chromium_for_test("the browser check of the compare report")
    else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    planted_class(dir.path());
    let scenes = scenes_dir();
    let out = tracer(
        dir.path(),
        &[
            "compare",
            "--report",
            "class",
            "--scenes",
            &scenes,
            "-o",
            "my report",
        ],
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr_of(&out));
    let check = loaded_in_chromium(&chromium, dir.path());
    // Each image, its reference, and the heat-maps of the four of its size.
    assert_eq!((check.total, check.loaded), (14, 14), "{check:?}");
    // The check notices an image that does not load.
    std::fs::remove_file(dir.path().join("my report/3-heatmap.png")).unwrap();
    let check = loaded_in_chromium(&chromium, dir.path());
    assert_eq!((check.total, check.loaded), (14, 13), "{check:?}");
    assert_eq!(check.failed, ["3-heatmap.png"]);
}

/// A scenes folder of one 8x8 scene, `tiny`, and a class folder holding
/// its render as `class/tiny-alice.png`: a class report in a moment.
fn tiny_class(dir: &Path) {
    std::fs::create_dir_all(dir.join("scenes")).unwrap();
    std::fs::create_dir_all(dir.join("class")).unwrap();
    std::fs::write(
        dir.join("scenes/tiny.toml"),
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nwidth = 8\nheight = 8\n\
         [[objects]]\nsphere = { center = [0, 0, 0], radius = 3 }\n\
         [[lights]]\nposition = [5, 5, 10]\ncolor = [1, 1, 1]\n",
    )
    .unwrap();
    render(dir, "scenes/tiny.toml", "class/tiny-alice.png", &[]);
}

/// `tracer compare --report class --scenes scenes -o OUT` in `dir`.
fn class_report(dir: &Path, out: &str) -> Output {
    let args = [
        "compare", "--report", "class", "--scenes", "scenes", "-o", out,
    ];
    tracer(dir, &args)
}

#[test]
fn a_report_folder_holding_other_files_is_refused_and_left_whole() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_class(d);
    // What looks like an earlier report, beside a student's other files.
    let out = d.join("out");
    std::fs::create_dir_all(out.join("sub")).unwrap();
    for (name, text) in [
        ("index.html", "<p>mine</p>"),
        ("report.csv", "a,b\n"),
        ("thesis.txt", "chapter 1"),
        ("sub/data.bin", "data"),
    ] {
        std::fs::write(out.join(name), text).unwrap();
    }
    let run = class_report(d, "out");
    let stderr = stderr_of(&run);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("refusing to replace it"), "{stderr}");
    for (name, text) in [
        ("index.html", "<p>mine</p>"),
        ("thesis.txt", "chapter 1"),
        ("sub/data.bin", "data"),
    ] {
        assert_eq!(std::fs::read_to_string(out.join(name)).unwrap(), text);
    }
    assert_eq!(leftovers(d), Vec::<String>::new());

    // A report is replaced by the next; once a file of the user's is put
    // in it, it is not, and the reason names the file.
    let run = class_report(d, "report");
    assert_eq!(run.status.code(), Some(0), "{}", stderr_of(&run));
    let run = class_report(d, "report");
    assert_eq!(run.status.code(), Some(0), "{}", stderr_of(&run));
    std::fs::write(d.join("report/thesis.txt"), "chapter 2").unwrap();
    let run = class_report(d, "report");
    assert_eq!(run.status.code(), Some(2));
    assert!(
        stderr_of(&run).contains("holds thesis.txt, which is not a file of the report"),
        "{}",
        stderr_of(&run)
    );
    assert!(d.join("report/index.html").is_file());
    assert_eq!(
        std::fs::read_to_string(d.join("report/thesis.txt")).unwrap(),
        "chapter 2"
    );
    // An empty folder has nothing to lose: it takes the report.
    std::fs::create_dir(d.join("empty")).unwrap();
    let run = class_report(d, "empty");
    assert_eq!(run.status.code(), Some(0), "{}", stderr_of(&run));
    assert!(d.join("empty/index.html").is_file());
    assert_eq!(leftovers(d), Vec::<String>::new());
}

#[test]
fn control_and_bidi_characters_of_class_names_are_shown_escaped() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_class(d);
    let class = d.join("class");
    // Clears the screen where printed raw; the other reads "tiny-bob.png"
    // backwards from its override on, passing for another student's.
    let image = image::open(class.join("tiny-alice.png"))
        .unwrap()
        .into_rgb8();
    image.save(class.join("tiny-\u{1b}[2Jcarol.png")).unwrap();
    let mut other = image.clone();
    other.put_pixel(1, 1, Rgb([255, 0, 255]));
    other.save(class.join("tiny-\u{202e}gnp.bob.png")).unwrap();
    // Named after no scene: said on stderr.
    image.save(class.join("x\u{1b}]0;PWNED\u{7}.png")).unwrap();
    let run = class_report(d, "report");
    let (stdout, stderr) = (stdout_of(&run), stderr_of(&run));
    assert_eq!(run.status.code(), Some(1), "{stdout}{stderr}");
    let page = std::fs::read_to_string(d.join("report/index.html")).unwrap();
    for (what, text) in [("table", &stdout), ("notes", &stderr), ("page", &page)] {
        for hidden in ['\u{1b}', '\u{7}', '\u{202e}'] {
            assert!(!text.contains(hidden), "{what}: {hidden:?} in {text}");
        }
    }
    assert!(
        stdout.contains("class/tiny-\\u{1b}[2Jcarol.png"),
        "{stdout}"
    );
    assert!(
        stdout.contains("class/tiny-\\u{202e}gnp.bob.png"),
        "{stdout}"
    );
    assert!(
        stderr.contains("skipped: class/x\\u{1b}]0;PWNED\\u{7}.png is named after no scene"),
        "{stderr}"
    );
    assert!(page.contains("tiny-\\u{202e}gnp.bob.png"), "{page}");
}

#[test]
fn a_class_file_whose_name_is_not_text_is_said_so() {
    use std::os::unix::ffi::OsStrExt;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_class(d);
    // Latin-1's é: not UTF-8.
    let name = std::ffi::OsStr::from_bytes(b"tiny-jos\xe9.png");
    std::fs::copy(d.join("class/tiny-alice.png"), d.join("class").join(name)).unwrap();
    let run = class_report(d, "report");
    let stderr = stderr_of(&run);
    assert_eq!(run.status.code(), Some(0), "{stderr}");
    assert!(
        stderr.contains(
            "skipped: class/tiny-jos\u{fffd}.png its name cannot be read as text (it is not UTF-8)"
        ),
        "{stderr}"
    );
    assert!(!stderr.contains("named after no scene"), "{stderr}");
    let page = std::fs::read_to_string(d.join("report/index.html")).unwrap();
    assert!(page.contains("its name cannot be read as text"), "{page}");
}

/// The peak resident memory of `tracer ARGS` in `dir`, in bytes, and
/// whether it exited 0 or 1 (wait4 reports the child's own peak).
// Waited for by wait4, which clippy does not see.
#[allow(clippy::zombie_processes)]
fn peak_memory(dir: &Path, args: &[&str]) -> (u64, i32) {
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_tracer"))
        .args(args)
        .current_dir(dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let mut status = 0;
    // SAFETY: rusage is plain data that wait4 fills in; the pid is our
    // child's, waited for once.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let pid = unsafe { libc::wait4(child.id() as libc::pid_t, &mut status, 0, &mut usage) };
    assert_eq!(pid, child.id() as libc::pid_t);
    assert!(libc::WIFEXITED(status));
    // Linux gives ru_maxrss in kilobytes.
    (usage.ru_maxrss as u64 * 1024, libc::WEXITSTATUS(status))
}

#[test]
fn the_report_s_memory_does_not_grow_with_the_class() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_class(d);
    // Images of 2048x2048 (12 MB each decoded, a few KB as PNG), another
    // size than the scene's: each compared at once, without FLIP.
    let big = RgbImage::from_pixel(2048, 2048, Rgb([10, 20, 30]));
    std::fs::remove_file(d.join("class/tiny-alice.png")).unwrap();
    let args = [
        "compare", "--report", "class", "--scenes", "scenes", "-o", "report",
    ];
    let mut peaks = Vec::new();
    for (k, count) in [(0, 2), (2, 14)] {
        for i in k..count {
            big.save(d.join(format!("class/tiny-{i}.png"))).unwrap();
        }
        let (peak, code) = peak_memory(d, &args);
        assert_eq!(code, 1, "images of another size are not within tolerance");
        peaks.push(peak);
    }
    let csv = std::fs::read_to_string(d.join("report/report.csv")).unwrap();
    assert_eq!(csv.lines().count(), 15, "{csv}");
    // Holding the 12 more images would take 150 MB more.
    let (two, fourteen) = (peaks[0], peaks[1]);
    assert!(
        fourteen < two + 40_000_000,
        "2 images: {two} bytes at the peak, 14: {fourteen}"
    );
}
