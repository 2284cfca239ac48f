//! The golden check: the real scenes against `golden/`, and proof that the
//! check fails when a render drifts.

use image::{Rgb, RgbImage};
use std::path::{Path, PathBuf};
use std::process::Command;
use xtask::golden::manifest::Manifest;
use xtask::golden::{self, Blessed, Case, CaseResult, Outcome};

fn root() -> PathBuf {
    xtask::workspace_root()
}

fn golden_dir() -> PathBuf {
    root().join("golden")
}

fn real_golden(name: &str) -> RgbImage {
    image::open(golden_dir().join(format!("{name}.png")))
        .unwrap()
        .to_rgb8()
}

/// The `*.toml` files in `scenes/` and its folders, counted by a walk of its own.
fn scene_file_count() -> usize {
    fn count(dir: &Path) -> usize {
        std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .map(|p| match p.is_dir() {
                true => count(&p),
                false => usize::from(p.extension().is_some_and(|x| x == "toml")),
            })
            .sum()
    }
    count(&root().join("scenes"))
}

/// Checks one case that returns `image` against the real golden `name`.
fn check_as(name: &str, image: RgbImage, manifest: &Manifest) -> CaseResult {
    let case = Case::new(name, move || Ok(image.clone()));
    golden::check(&[case], &golden_dir(), manifest)
        .pop()
        .unwrap()
}

fn comparison(result: &CaseResult) -> &xtask::golden::compare::Comparison {
    match &result.outcome {
        Outcome::Compared(c) => c,
        other => panic!("expected a comparison, got {other:?}"),
    }
}

/// Flipping the top bit changes a channel by exactly 128, whatever its value.
fn flip_block(image: &mut RgbImage, x0: u32, y0: u32, w: u32, h: u32) {
    for y in y0..y0 + h {
        for x in x0..x0 + w {
            let p = image.get_pixel_mut(x, y);
            *p = Rgb(p.0.map(|c| c ^ 0x80));
        }
    }
}

/// The README's test command runs the whole golden check; the report is
/// written where `cargo xtask golden` writes it, for a person to open.
#[test]
fn every_image_matches_its_golden() {
    let report = xtask::target_dir().join("golden");
    let summary = golden::run_check(&root(), &[], &report).unwrap();
    assert!(
        summary.all_passed(),
        "golden check failed; report: {}\n{}",
        summary.report.display(),
        summary.table
    );
    let lab_images = golden::lab_image_cases(&root()).len();
    assert_eq!(summary.results.len(), scene_file_count() + lab_images);
    assert!(summary.results.len() >= 12 + 8);
}

/// The committed goldens themselves, checked against values worked out by
/// hand from the lab's formulas (gamma 2.2, truncation to 8 bits), so that a
/// wrongly blessed image is caught whatever the renderer does.
#[test]
fn the_goldens_hold_the_labs_hand_worked_values() {
    let px = |name: &str, i, j| real_golden(name).get_pixel(i, j).0;
    // Hit colour (0, 0.5, 0): 0.5^(1/2.2) * 255 = 186.08 -> 186; a miss is black.
    assert_eq!(px("sphere-intersection", 250, 200), [0, 186, 0]);
    assert_eq!(px("sphere-intersection", 5, 5), [0, 0, 0]);
    // The small sphere (-2.5, 1.3, -3) projects to column 250 + 2.5/13 * 536 = 353,
    // row 200 - 1.3/13 * 536 = 146: top-RIGHT, since +x points left.
    assert_eq!(px("sphere-intersection", 353, 146), [0, 186, 0]);
    assert_eq!(px("sphere-intersection", 147, 146), [0, 0, 0]);
    // Triangle (3,3,-5) (-3,3,-10) (-3,-3,-8): its centroid (-1, 1, -7.67)
    // projects to column 250 + 1/17.67 * 536 = 280, row 200 - 30 = 170.
    assert_eq!(px("triangle-intersection", 280, 170), [0, 186, 0]);
    assert_eq!(px("triangle-intersection", 200, 300), [0, 0, 0]);
    // Ambient only: 0.6 * 0.5 = 0.3; 0.3^(1/2.2) * 255 = 147.5 -> 147.
    assert_eq!(px("illumination-ambient", 250, 200), [147, 0, 0]);
    // Diffuse at the front, p ~ (0, 0, 1.6): cos = 6.4 / |(-3,-2,6.4)| = 0.8713,
    // 0.6 * 0.7 * 0.8713 = 0.3659 -> 0.6332 * 255 = 161.5 -> 161 (+-1: p is near the front).
    let [r, g, b] = px("illumination-diffuse", 250, 200);
    assert!(r.abs_diff(161) <= 1 && g == 0 && b == 0, "{r} {g} {b}");
    // The red sphere's shadow on the back wall: ambient 0.6 * 0.1 = 0.06 only;
    // 0.06^(1/2.2) * 255 = 70.98 -> 70.
    assert_eq!(px("shadows", 100, 150), [70, 70, 70]);
    // The lab's scenes are all 500x400; the scenes beyond the lab (checked
    // by the physics tests of tracer-core) are not.
    const BEYOND_LAB: [&str; 17] = [
        "antialiasing",
        "bench-bunny",
        "boxes",
        "cornell-box",
        "cornell-bunny",
        "courtyard",
        "ellipsoids",
        "global-illumination",
        "gltf-box",
        "depth-of-field",
        "glass",
        "materials",
        "showcase",
        "smooth-mesh",
        "soft-shadows",
        "studio-bunny",
        "textures",
    ];
    let cases = golden::scene_cases(&root().join("scenes")).unwrap();
    let lab = cases
        .iter()
        .map(|c| &c.name)
        .filter(|n| !BEYOND_LAB.contains(&n.as_str()));
    // The 12 3D tables and the 2 canvas scenes.
    assert_eq!(lab.clone().count(), 14);
    for name in lab {
        assert_eq!(real_golden(name).dimensions(), (500, 400), "{name}");
    }
}

/// The Cornell box's golden against Mitsuba 3's render of the same scene
/// (`crates/tracer-core/tests/data`, 32768 paths a pixel), encoded by the
/// scene's rule (clamp, gamma 2.2, truncation): the same image but for the
/// golden's noise (64 paths a pixel), which 16x16 blocks average out.
#[test]
fn the_cornell_box_golden_is_mitsuba_s_image() {
    assert_golden_is_mitsuba_s_image("cornell-box", "cornell-box-mitsuba.exr", 3.0);
}

/// The materials' golden against Mitsuba 3's render (8448 paths a pixel).
/// Where the golden is noisy (the rough glass, at 128 paths a pixel) its
/// blocks run darker than the reference's, by up to 6 levels: gamma is
/// concave and fireflies are clamped, so noisy pixels encode darker on
/// average. The physics are checked in linear light by tracer-core's
/// `tests/materials.rs`.
#[test]
fn the_materials_golden_is_mitsuba_s_image() {
    assert_golden_is_mitsuba_s_image("materials", "materials-mitsuba.exr", 6.5);
}

/// The bunny-in-the-box golden against Mitsuba 3's render (9216 paths a
/// pixel): the gold's caustics throw fireflies at the golden's 64 paths,
/// which clamping and gamma darken (3 levels at most, measured).
#[test]
fn the_cornell_bunny_golden_is_mitsuba_s_image() {
    assert_golden_is_mitsuba_s_image("cornell-bunny", "cornell-bunny-mitsuba.exr", 4.5);
}

/// The courtyard's golden against Mitsuba 3's render (9216 paths a pixel):
/// the noisiest blocks, where the copper reflects the sun, differ by up to
/// 5.6 levels (measured), as the materials' rough glass.
#[test]
fn the_courtyard_golden_is_mitsuba_s_image() {
    assert_golden_is_mitsuba_s_image("courtyard", "courtyard-mitsuba.exr", 7.0);
}

/// Each 16x16 block of golden `name` within `levels` (of 255) of the
/// reference `exr`'s, channel by channel, and the whole image's mean
/// within 1 %.
fn assert_golden_is_mitsuba_s_image(name: &str, exr: &str, levels: f64) {
    let exr = root().join("crates/tracer-core/tests/data").join(exr);
    let reference = image::open(exr).unwrap().to_rgb32f();
    let golden = real_golden(name);
    assert_eq!(golden.dimensions(), reference.dimensions());
    let (width, height) = golden.dimensions();
    let columns = width / 16;
    let encode = |c: f32| (c.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0) as u8;
    let blocks = |level: &dyn Fn(u32, u32, usize) -> f64| {
        let mut sums = vec![0.0; (columns * (height / 16) * 3) as usize];
        for (x, y) in (0..height).flat_map(|y| (0..width).map(move |x| (x, y))) {
            for c in 0..3 {
                sums[((y / 16 * columns + x / 16) * 3) as usize + c] += level(x, y, c) / 256.0;
            }
        }
        sums
    };
    let ours = blocks(&|x, y, c| f64::from(golden.get_pixel(x, y).0[c]));
    let theirs = blocks(&|x, y, c| f64::from(encode(reference.get_pixel(x, y).0[c])));
    for (k, (o, t)) in ours.iter().zip(&theirs).enumerate() {
        let (block, channel) = (k as u32 / 3, k % 3);
        assert!(
            (o - t).abs() <= levels,
            "{name}: block ({}, {}), channel {channel}: {o:.1} vs Mitsuba's {t:.1}",
            block % columns,
            block / columns
        );
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    assert!((mean(&ours) / mean(&theirs) - 1.0).abs() < 0.01);
}

/// The global look of `global-illumination.toml`'s golden, by numbers: the
/// floor is warmer beside the orange wall than beside the teal one and the
/// box's sides take each wall's colour (colour bleeding), a corner is
/// darker than the middle of its wall, and the glass ball's caustic is
/// brighter than the floor beside it. Regions read off the image's layout
/// (320x240, the camera of the scene file).
#[test]
fn the_global_illumination_golden_shows_the_global_look() {
    let golden = real_golden("global-illumination");
    let mean = |x0: u32, y0: u32, x1: u32, y1: u32| {
        let mut sum = [0.0f64; 3];
        for y in y0..y1 {
            for x in x0..x1 {
                for (c, v) in golden.get_pixel(x, y).0.iter().enumerate() {
                    sum[c] += f64::from(*v);
                }
            }
        }
        sum.map(|s| s / f64::from((x1 - x0) * (y1 - y0)))
    };
    let grey = |c: [f64; 3]| (c[0] + c[1] + c[2]) / 3.0;
    let (floor_right, floor_left) = (mean(255, 195, 295, 215), mean(25, 195, 65, 215));
    assert!(
        floor_right[0] / floor_right[2] > 1.15 * floor_left[0] / floor_left[2],
        "{floor_right:?} {floor_left:?}"
    );
    let (box_left, box_right) = (mean(95, 110, 110, 150), mean(125, 110, 145, 150));
    assert!(
        box_left[1] > box_left[0],
        "teal on the side facing it: {box_left:?}"
    );
    assert!(
        box_right[0] > box_right[1],
        "orange on the other: {box_right:?}"
    );
    let (corner, middle) = (mean(88, 150, 96, 160), mean(150, 60, 170, 80));
    assert!(grey(corner) < 0.6 * grey(middle), "{corner:?} {middle:?}");
    let (caustic, beside) = (mean(160, 175, 185, 190), mean(100, 175, 125, 190));
    assert!(grey(caustic) > 1.2 * grey(beside), "{caustic:?} {beside:?}");
}

/// `studio-bunny.toml`'s golden, by numbers: the bunny is gold (a metal
/// whose reflection takes its base colour, blue at most 3/4 of red), the
/// frosted glass and the far floor stay grey, and the floor just in front
/// of the bunny's feet takes the gold's colour (light bounced off it).
#[test]
fn the_studio_bunny_golden_is_gold_on_grey() {
    let golden = real_golden("studio-bunny");
    let blue_over_red = |x0: u32, y0: u32, x1: u32, y1: u32| {
        let (mut red, mut blue) = (0.0f64, 0.0f64);
        for y in y0..y1 {
            for x in x0..x1 {
                let [r, _, b] = golden.get_pixel(x, y).0;
                (red, blue) = (red + f64::from(r), blue + f64::from(b));
            }
        }
        blue / red
    };
    let bunny = blue_over_red(150, 160, 230, 210);
    let (glass, far_floor) = (
        blue_over_red(290, 140, 340, 190),
        blue_over_red(20, 90, 80, 110),
    );
    let feet = blue_over_red(130, 288, 220, 299);
    assert!(bunny < 0.75, "{bunny}");
    assert!(glass > 0.9 && far_floor > 0.9, "{glass} {far_floor}");
    assert!(feet < far_floor - 0.03, "{feet} vs {far_floor}");
}

/// The floor of `textures.toml`, worked out from its camera: eye (0, 3, 9)
/// looking at (0, 1, 0), fov 55 over 480 columns (focal length 240 /
/// tan 27.5 = 461.0), +x to the right. The floor point (x, 0, 3.5) lies
/// 55.5 / sqrt(85) = 6.020 along the view, so it lands in column
/// 240 + 461.0 x / 6.020 = 240 + 76.6 x, row 292.9: the square edges x = 0
/// and x = 1 fall on columns 240.0 and 316.6. Squares are 1 wide (scale 1);
/// [0, 1] x [3, 4] in (x, z) has floor(x) + floor(-z) = -4, even: the first
/// (light) colour; its neighbours are dark.
#[test]
fn the_textures_golden_puts_the_checker_squares_where_the_camera_does() {
    let image = real_golden("textures");
    let light = |i| image.get_pixel(i, 292).0[0] > 180;
    let dark = |i| image.get_pixel(i, 292).0[0] < 120;
    assert!(dark(238) && dark(239), "left of x = 0");
    assert!(light(240) && light(241) && light(315), "from x = 0 to 1");
    assert!(dark(318) && dark(319), "right of x = 1");
}

/// The red ellipsoid of `ellipsoids.toml` (semi-axes a = 2.4, b = 1.2,
/// c = 1, centred on the view axis D = 10 away): its outline is the cone
/// from the eye tangent to it, half-angles atan(a / sqrt(D^2 - c^2)) and
/// atan(b / ...), so with the focal length f = 240 / tan 25 = 514.7 pixels
/// it is 2 f a / sqrt(99) = 248.3 pixels wide and 124.1 high.
#[test]
fn the_ellipsoids_golden_outlines_the_ellipse_the_axes_give() {
    let image = real_golden("ellipsoids");
    let red = |i, j| {
        let [r, g, _] = image.get_pixel(i, j).0;
        r > g.saturating_add(40)
    };
    let span = |cells: Vec<u32>| cells.last().unwrap() - cells.first().unwrap() + 1;
    let width = span((0..480).filter(|&i| red(i, 180)).collect());
    let height = span((0..360).filter(|&j| red(240, j)).collect());
    assert!(width.abs_diff(248) <= 1, "width {width}");
    assert!(height.abs_diff(124) <= 1, "height {height}");
}

#[test]
fn the_other_lab_goldens_hold_hand_worked_values() {
    let px = |name: &str, i, j| real_golden(name).get_pixel(i, j).0;
    // Pixel (0.5, 0.5) of the lab camera has dir (0.40, 0.32, -0.86), written
    // linearly as (d + 1) / 2: 0.70 -> 178, 0.66 -> 168, 0.07 -> 17 (+-1).
    let close = |got: u8, want: u8| got.abs_diff(want) <= 1;
    let [r, g, b] = px("gradient-OX", 0, 0);
    assert!(close(r, 178) && g == 0 && b == 0, "{r} {g} {b}");
    let [r, g, b] = px("gradient-OY", 0, 0);
    assert!(r == 0 && close(g, 168) && b == 0, "{r} {g} {b}");
    let [r, g, b] = px("gradient-OZ", 0, 0);
    assert!(r == 0 && g == 0 && close(b, 17), "{r} {g} {b}");
    // Bottom-right mirrors top-left in x: (-0.40 + 1) / 2 = 0.30 -> 76.
    assert!(close(px("gradient-OX", 499, 399)[0], 76));
    // Five patches 0, 0.25, 0.5, 0.75, 1: (int)(c * 255) linear, and with
    // c^(1/2.2) first: 0.25 -> 0.5325 -> 135, 0.5 -> 186, 0.75 -> 0.8774 -> 223.
    for (k, (linear, encoded)) in [(0, 0), (63, 135), (127, 186), (191, 223), (255, 255)]
        .into_iter()
        .enumerate()
    {
        let centre = 50 + 100 * k as u32;
        assert_eq!(px("calib-chart", centre, 50), [linear; 3], "patch {k}");
        assert_eq!(
            px("calib-chart-gamma-2.2", centre, 50),
            [encoded; 3],
            "patch {k}"
        );
    }
    // The lab's triangle: vertex (0.4, 0.3) goes to column 500 - 1.4 / 2 * 500 = 150,
    // row 400 - 1.3 / 2 * 400 = 140; translated by (0.2, 0.1) it is 50 columns
    // further left and 20 rows up. Midpoints of the top edges lie on the lines.
    let bg = [25, 25, 25]; // grey 0.1 without gamma: (int)(25.5)
    assert_eq!(px("triangle-2d", 5, 5), bg);
    assert_ne!(px("triangle-2d", 250, 140), bg);
    assert_ne!(px("triangle-2d", 200, 120), bg);
    assert_eq!(px("triangle-2d", 250, 130), bg);
}

/// The bench bunny (`scenes/bench/bunny.toml`, golden `bench-bunny`),
/// against numbers from outside the renderer: docs/src/performance.md's 24.6 %
/// of primary rays hitting the bunny (counted by Embree too), and the
/// colours the scene's values give under gamma 2.2, truncated to 8 bits.
#[test]
fn the_bench_bunny_golden_holds_the_bench_numbers() {
    let image = real_golden("bench-bunny");
    assert_eq!(image.dimensions(), (1920, 1080));
    // Background (0.1, 0.1, 0.15): 0.1^(1/2.2) = 0.3511 -> 89.5 -> 89,
    // 0.15^(1/2.2) = 0.4221 -> 107.6 -> 107.
    let background = [89, 89, 107];
    assert_eq!(image.get_pixel(0, 0).0, background);
    assert_eq!(image.get_pixel(1919, 1079).0, background);
    let pixels = image.pixels().count() as f64;
    let hits = image.pixels().filter(|p| p.0 != background).count() as f64;
    let share = 100.0 * hits / pixels;
    assert!((share - 24.6).abs() < 0.05, "{share:.3} % of pixels hit");
    // Shadowed or turned away from the light: ambient (0.09, 0.085, 0.075)
    // alone, 0.3347 -> 85, 0.3261 -> 83, 0.3081 -> 78. The undersides and
    // the shadow of the ear make about a tenth of the bunny.
    let ambient = image.pixels().filter(|p| p.0 == [85, 83, 78]).count() as f64;
    assert!(
        (0.02..0.2).contains(&(ambient / hits)),
        "{ambient} in shadow"
    );
    // Nothing brighter than ambient + full diffuse (0.9, 0.85, 0.75): 243, 236, 223.
    assert!(image
        .pixels()
        .all(|p| p.0[0] <= 243 && p.0[1] <= 236 && p.0[2] <= 223));
}

#[test]
fn a_render_changed_beyond_tolerance_fails_with_exact_counts() {
    let mut image = real_golden("reflectance2");
    flip_block(&mut image, 100, 50, 15, 14); // 210 pixels > 0.1 % of 200 000
    let result = check_as("reflectance2", image, &Manifest::default());
    assert_eq!(result.verdict(), "FAIL");
    assert!(!result.passed());
    let c = comparison(&result);
    assert_eq!(c.pixels, 200_000);
    assert_eq!(c.differing, 210);
    assert_eq!(c.max_diff, 128);
    // 210 pixels * 3 channels * 128 / (200 000 * 3)
    assert!((c.mean_diff - 0.1344).abs() < 1e-12, "{}", c.mean_diff);
    let table = golden::table(&[result]);
    assert!(
        table.contains("reflectance2") && table.contains("210") && table.contains("FAIL"),
        "{table}"
    );
}

#[test]
fn exactly_the_allowed_share_of_differing_pixels_passes() {
    let mut image = real_golden("reflectance2");
    flip_block(&mut image, 100, 50, 10, 20); // 200 pixels = 0.1 %
    let result = check_as("reflectance2", image, &Manifest::default());
    assert_eq!(comparison(&result).differing, 200);
    assert_eq!(result.verdict(), "PASS");
}

#[test]
fn a_render_changed_within_tolerance_passes() {
    let mut image = real_golden("shadows");
    for p in image.pixels_mut() {
        *p = Rgb(p.0.map(|c| if c >= 2 { c - 2 } else { c + 2 }));
    }
    let result = check_as("shadows", image, &Manifest::default());
    assert_eq!(result.verdict(), "PASS");
    let c = comparison(&result);
    assert_eq!((c.differing, c.max_diff), (0, 2));
    assert!((c.mean_diff - 2.0).abs() < 1e-12);
}

#[test]
fn the_manifest_sets_an_images_own_tolerance() {
    let mut image = real_golden("reflectance2");
    flip_block(&mut image, 100, 50, 15, 14);
    let manifest = Manifest::parse(
        "[scenes.reflectance2]\nmax_differing_percent = 0.2\n",
        Path::new("golden.toml"),
    )
    .unwrap();
    let result = check_as("reflectance2", image.clone(), &manifest);
    assert_eq!(result.verdict(), "PASS");
    assert_eq!(comparison(&result).differing, 210);

    let manifest = Manifest::parse(
        "[scenes.reflectance2]\nchannel_tolerance = 128\n",
        Path::new("golden.toml"),
    )
    .unwrap();
    let result = check_as("reflectance2", image, &manifest);
    assert_eq!(comparison(&result).differing, 0);
}

#[test]
fn a_render_of_another_size_fails_with_a_clear_message() {
    let image = real_golden("texture");
    let cropped = image::imageops::crop_imm(&image, 0, 0, 499, 400).to_image();
    let result = check_as("texture", cropped, &Manifest::default());
    assert_eq!(result.verdict(), "FAIL");
    assert_eq!(
        result.problem().unwrap(),
        "size differs: golden 500x400, render 499x400"
    );
    assert!(result.diff.is_none());
}

#[test]
fn a_missing_golden_is_not_a_pass() {
    let dir = tempfile::tempdir().unwrap();
    let case = Case::new("new-scene", || Ok(RgbImage::new(2, 2)));
    let result = golden::check(&[case], dir.path(), &Manifest::default())
        .pop()
        .unwrap();
    assert_eq!(result.outcome, Outcome::MissingGolden);
    assert_eq!(result.verdict(), "MISSING");
    assert!(result
        .problem()
        .unwrap()
        .contains("cargo xtask golden --bless new-scene"));
}

#[test]
fn a_scene_that_cannot_be_loaded_is_an_error_naming_the_place() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    std::fs::create_dir(&scenes).unwrap();
    std::fs::write(
        scenes.join("broken.toml"),
        "[camera]\neye = [0, 0, 10]\nfov = \"wide\"\n",
    )
    .unwrap();
    let cases = golden::scene_cases(&scenes).unwrap();
    let result = golden::check(&cases, dir.path(), &Manifest::default())
        .pop()
        .unwrap();
    assert_eq!(result.verdict(), "ERROR");
    let problem = result.problem().unwrap();
    assert!(problem.contains("broken.toml:3:"), "{problem}");
}

#[test]
fn every_toml_scene_file_is_a_case_in_name_order() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("sub/deeper")).unwrap();
    let files = [
        "b.toml",
        "a-x.toml",
        "a.toml",
        "c.json",
        "notes.txt",
        "sub/s.toml",
        "sub/deeper/d.toml",
        "sub/t.json",
    ];
    for file in files {
        std::fs::write(dir.path().join(file), "").unwrap();
    }
    let names: Vec<String> = golden::scene_cases(dir.path())
        .unwrap()
        .into_iter()
        .map(|c| c.name)
        .collect();
    assert_eq!(names, ["a", "a-x", "b", "sub-deeper-d", "sub-s"]);
}

/// `scenes/x-y.toml` and `scenes/x/y.toml` would share a golden: refused.
#[test]
fn a_scene_in_a_folder_whose_name_clashes_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    std::fs::create_dir_all(scenes.join("x")).unwrap();
    std::fs::write(scenes.join("x-y.toml"), "").unwrap();
    std::fs::write(scenes.join("x/y.toml"), "").unwrap();
    let err = golden::all_cases(dir.path()).err().unwrap().to_string();
    assert!(err.contains("\"x-y\""), "{err}");
}

#[test]
fn selecting_an_unknown_image_is_an_error_listing_the_known() {
    let cases = vec![Case::new("a", || Ok(RgbImage::new(1, 1)))];
    let err = golden::select(cases, &["b".to_string()])
        .err()
        .unwrap()
        .to_string();
    assert_eq!(err, "no image named b; known: a");
}

#[test]
fn bless_writes_new_and_changed_goldens_and_says_what_changed() {
    let dir = tempfile::tempdir().unwrap();
    let case = |image: RgbImage| Case::new("img", move || Ok(image.clone()));
    let grey = RgbImage::from_pixel(4, 5, Rgb([100, 100, 100]));

    let blessed = golden::bless(&[case(grey.clone())], dir.path()).unwrap();
    assert_eq!(
        blessed,
        [Blessed::New {
            name: "img".into(),
            size: (4, 5)
        }]
    );
    let blessed = golden::bless(&[case(grey.clone())], dir.path()).unwrap();
    assert_eq!(blessed, [Blessed::Unchanged { name: "img".into() }]);

    let mut changed = grey;
    changed.put_pixel(0, 0, Rgb([101, 100, 100]));
    changed.put_pixel(3, 4, Rgb([100, 90, 100]));
    let blessed = golden::bless(&[case(changed.clone())], dir.path()).unwrap();
    let Blessed::Changed { change, .. } = &blessed[0] else {
        panic!("{blessed:?}")
    };
    // Blessing counts every pixel that is not identical, even within tolerance.
    assert_eq!(
        (change.differing, change.pixels, change.max_diff),
        (2, 20, 10)
    );
    assert_eq!(
        blessed[0].to_string(),
        "changed    img: 2 of 20 pixels not identical (10.000 %; the check counts only those beyond tolerance), max diff 10, mean diff 0.1833"
    );
    let on_disk = image::open(dir.path().join("img.png")).unwrap().to_rgb8();
    assert_eq!(on_disk, changed);

    std::fs::write(dir.path().join("img.png"), "not a PNG").unwrap();
    let blessed = golden::bless(&[case(changed.clone())], dir.path()).unwrap();
    assert!(
        matches!(&blessed[0], Blessed::Unreadable { name, .. } if name == "img"),
        "{blessed:?}"
    );
    let on_disk = image::open(dir.path().join("img.png")).unwrap().to_rgb8();
    assert_eq!(on_disk, changed);
}

#[test]
fn bless_writes_nothing_when_a_render_fails() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        Case::new("good", || Ok(RgbImage::new(1, 1))),
        Case::new("bad", || anyhow::bail!("no light")),
    ];
    let err = golden::bless(&cases, dir.path()).unwrap_err();
    assert!(format!("{err:#}").contains("bad: render failed: no light"));
    assert!(!dir.path().join("good.png").exists());
}

#[test]
fn the_report_shows_failures_first_with_relative_image_paths() {
    let dir = tempfile::tempdir().unwrap();
    let golden_dir = dir.path().join("golden");
    let grey = RgbImage::from_pixel(3, 3, Rgb([100; 3]));
    golden::bless(
        &[
            Case::new("a-passes", {
                let g = grey.clone();
                move || Ok(g.clone())
            }),
            Case::new("b-fails", {
                let g = grey.clone();
                move || Ok(g.clone())
            }),
        ],
        &golden_dir,
    )
    .unwrap();
    let cases = [
        Case::new("a-passes", move || Ok(grey.clone())),
        Case::new("b-fails", || Ok(RgbImage::new(3, 3))),
        Case::new("c-missing", || Ok(RgbImage::new(3, 3))),
    ];
    let results = golden::check(&cases, &golden_dir, &Manifest::default());
    let report = dir.path().join("report");
    let index = xtask::golden::report::write(&report, &results).unwrap();
    let html = std::fs::read_to_string(&index).unwrap();

    let at = |s: &str| html.find(s).unwrap_or_else(|| panic!("{s} not in page"));
    assert!(at("<h2>b-fails") < at("<h2>a-passes"));
    assert!(at("<h2>c-missing") < at("<h2>a-passes"));
    assert!(html.contains("9 of 9 pixels differ (100.000 %)"));
    for file in [
        "a-passes-golden.png",
        "a-passes-actual.png",
        "a-passes-diff.png",
        "b-fails-diff.png",
        "c-missing-actual.png",
    ] {
        assert!(html.contains(&format!("src=\"{file}\"")), "{file}");
        assert!(report.join(file).is_file(), "{file}");
    }
    assert!(!report.join("c-missing-golden.png").exists());
    assert_eq!(xtask::golden::report::image_count(&results), 3 + 3 + 1);
    // A second report replaces the first whole.
    xtask::golden::report::write(&report, &results[..1]).unwrap();
    assert!(!report.join("b-fails-actual.png").exists());
}

#[test]
fn cargo_xtask_golden_prints_the_table_and_exits_by_the_result() {
    let target = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_xtask"))
            .args(args)
            .env("CARGO_TARGET_DIR", target.path())
            .output()
            .unwrap()
    };
    let ok = run(&["golden", "reflectance2", "texture"]);
    let stdout = String::from_utf8_lossy(&ok.stdout);
    assert!(ok.status.success(), "{stdout}");
    assert!(stdout.contains("2 images checked: 2 PASS"), "{stdout}");
    assert!(target.path().join("golden/index.html").is_file());
    assert!(target.path().join("golden/texture-diff.png").is_file());

    let unknown = run(&["golden", "no-such-scene"]);
    assert_eq!(unknown.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&unknown.stderr).contains("no image named no-such-scene"));
}
