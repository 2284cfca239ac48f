//! The `tracer` binary as a user runs it.

mod common;

use common::tracer;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `relative` to this crate's folder, as an argument for `tracer`.
fn from_crate(relative: &str) -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(relative);
    p.to_str().unwrap().to_string()
}

fn scene(name: &str) -> String {
    from_crate(&format!("../../scenes/{name}"))
}

#[test]
fn render_without_a_scene_writes_the_lab_final_scene() {
    let dir = tempfile::tempdir().unwrap();
    let out = tracer(dir.path(), &["render"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let default = image::open(dir.path().join("reflectance2.png")).unwrap();
    let out = tracer(
        dir.path(),
        &["render", &scene("reflectance2.toml"), "-o", "explicit.png"],
    );
    assert!(out.status.success());
    let explicit = image::open(dir.path().join("explicit.png")).unwrap();
    assert_eq!((default.width(), default.height()), (500, 400));
    assert!(default == explicit);
}

#[test]
fn default_output_is_the_scene_stem_in_the_current_folder() {
    let dir = tempfile::tempdir().unwrap();
    let out = tracer(dir.path(), &["render", &scene("sphere-intersection.toml")]);
    assert!(out.status.success());
    assert!(dir.path().join("sphere-intersection.png").is_file());
}

#[test]
fn bad_scene_exits_2_and_leaves_the_old_image() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(
        &bad,
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nfvo = 50\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("bad.png"), b"old").unwrap();
    let out = tracer(dir.path(), &["render", "bad.toml"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("bad.toml:4:1"), "{stderr}");
    assert!(stderr.contains("fvo"), "{stderr}");
    assert_eq!(std::fs::read(dir.path().join("bad.png")).unwrap(), b"old");
}

#[test]
fn gamma_flag_overrides_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene("illumination-ambient.toml");
    let out = tracer(
        dir.path(),
        &["render", &s, "--gamma", "1", "-o", "linear.png"],
    );
    assert!(out.status.success());
    let img = image::open(dir.path().join("linear.png"))
        .unwrap()
        .to_rgb8();
    // Linear 0.3 -> (int)(0.3 * 255) = 76.
    assert_eq!(img.get_pixel(250, 200).0, [76, 0, 0]);
    for bad in ["0", "-1"] {
        let out = tracer(dir.path(), &["render", &s, "--gamma", bad]);
        assert_eq!(out.status.code(), Some(2));
        // The gamma's own message, not clap's "unexpected argument".
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            stderr.contains("--gamma: expected a number > 0"),
            "{stderr}"
        );
    }
}

fn rgb(path: &Path) -> image::RgbImage {
    image::open(path).unwrap().to_rgb8()
}

#[test]
fn a_canvas_scene_is_drawn_without_gamma() {
    let dir = tempfile::tempdir().unwrap();
    let out = tracer(dir.path(), &["render", &scene("triangle-2d.toml")]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let img = rgb(&dir.path().join("triangle-2d.png"));
    assert_eq!(img.dimensions(), (500, 400));
    // The template's grey 0.1 without gamma: (int)(0.1 * 255) = 25.
    assert_eq!(img.get_pixel(5, 5).0, [25, 25, 25]);
    // The vertical edge x = 0.4 is column 500 * 0.6 / 2 = 150: columns 149
    // and 150, red; halfway between y = 0.3 and -0.3, row 200.
    assert_eq!(img.get_pixel(149, 200).0, [255, 0, 0]);
    assert_eq!(img.get_pixel(150, 200).0, [255, 0, 0]);
    assert_eq!(img.get_pixel(152, 200).0, [25, 25, 25]);
    // Translated by (0.2, 0.1): 50 columns left, 20 rows up, green.
    assert_eq!(img.get_pixel(99, 180).0, [0, 255, 0]);
    assert_eq!(img.get_pixel(100, 180).0, [0, 255, 0]);
    let out = tracer(
        dir.path(),
        &["render", &scene("robot.toml"), "--aov", "depth"],
    );
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn aov_ray_dir_x_writes_the_labs_gradient() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene("sphere-intersection.toml");
    let out = tracer(dir.path(), &["render", &s, "--aov", "ray-dir-x"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let img = rgb(&dir.path().join("sphere-intersection-ray-dir-x.png"));
    // Top-left direction (249.5, 199.5, -536.127) / 624.086: x = 0.39979,
    // (x + 1) / 2 * 255 = 178.47 -> 178, written linearly.
    assert_eq!(img.get_pixel(0, 0).0, [178, 0, 0]);
    let out = tracer(dir.path(), &["render", &s, "--aov", "colour"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn calib_chart_writes_five_patches_with_and_without_gamma() {
    let dir = tempfile::tempdir().unwrap();
    let patches = |name: &str| -> Vec<u8> {
        let img = rgb(&dir.path().join(name));
        (0..5)
            .map(|k| img.get_pixel(k * 100 + 50, 50).0[0])
            .collect()
    };
    assert!(tracer(dir.path(), &["calib-chart"]).status.success());
    assert_eq!(patches("chart.png"), [0, 63, 127, 191, 255]);
    let out = tracer(
        dir.path(),
        &["calib-chart", "-o", "g.png", "--gamma", "2.2"],
    );
    assert!(out.status.success());
    // c^(1/2.2) * 255 truncated: 135.79, 186.08, 223.74.
    assert_eq!(patches("g.png"), [0, 135, 186, 223, 255]);
    let out = tracer(dir.path(), &["calib-chart", "--gamma", "-1"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--gamma: expected a number > 0"),
        "{stderr}"
    );
}

#[test]
fn gamma_fit_prints_gamma_and_draws_the_plot() {
    let dir = tempfile::tempdir().unwrap();
    let csv = scene("gamma/sample-measurements.csv");
    let out = tracer(dir.path(), &["gamma", "fit", &csv, "--plot", "gamma.png"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.starts_with("gamma = 2.28\nRMSE = "), "{stdout}");
    assert_eq!(rgb(&dir.path().join("gamma.png")).dimensions(), (800, 600));
}

#[test]
fn a_bad_measurement_file_exits_2_naming_the_row() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("m.csv"),
        "level,luminance\n0,0.4\n0.5,-2\n1,250\n",
    )
    .unwrap();
    let out = tracer(dir.path(), &["gamma", "fit", "m.csv", "--plot", "p.png"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("m.csv: row 3: luminance"), "{stderr}");
    assert!(!dir.path().join("p.png").exists());
    let out = tracer(dir.path(), &["gamma", "fit", "missing.csv"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn threads_change_nothing_in_the_image() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene("reflectance2.toml");
    for (threads, out) in [("1", "one.png"), ("2", "two.png")] {
        let run = tracer(dir.path(), &["render", &s, "--threads", threads, "-o", out]);
        assert!(run.status.success());
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(stderr.contains(&format!("on {threads} thread")), "{stderr}");
        assert!(stderr.contains("Mrays/s"), "{stderr}");
        // stderr is a pipe here, not a terminal: no progress bar.
        assert!(!stderr.contains("rendering ["), "{stderr}");
    }
    let one = std::fs::read(dir.path().join("one.png")).unwrap();
    assert_eq!(one, std::fs::read(dir.path().join("two.png")).unwrap());
    let zero = tracer(dir.path(), &["render", &s, "--threads", "0"]);
    assert_eq!(zero.status.code(), Some(2));
}

#[test]
fn a_path_mode_summary_says_the_estimator_it_used_as_keys() {
    // Path mode chooses these where the file is silent (the bunny's room
    // sets none of them); the summary tells a user what to set.
    let dir = tempfile::tempdir().unwrap();
    let s = scene("cornell-bunny.toml");
    let run = tracer(dir.path(), &["render", &s, "--samples", "1", "-o", "b.png"]);
    assert!(run.status.success());
    let stderr = String::from_utf8_lossy(&run.stderr);
    let keys = "path_reuse = 8, camera_rays = 8, adaptive = true -> b.png";
    assert!(stderr.contains(keys), "{stderr}");
    // The lab's Whitted mode has none.
    let s = scene("reflectance2.toml");
    let run = tracer(dir.path(), &["render", &s, "-o", "r.png"]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!stderr.contains("path_reuse"), "{stderr}");
}

#[test]
fn quiet_prints_nothing_on_success() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene("sphere-intersection.toml");
    let out = tracer(dir.path(), &["render", &s, "--quiet"]);
    assert!(out.status.success());
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.path().join("sphere-intersection.png").is_file());
}

#[test]
fn the_summary_counts_scene_objects_and_mesh_triangles_apart() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("quad.obj"),
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("m.toml"),
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nwidth = 40\nheight = 30\n\
         [[objects]]\nmesh = { obj = \"quad.obj\" }\n\
         [[objects]]\nsphere = { center = [0, 0, -3], radius = 1 }\n",
    )
    .unwrap();
    let out = tracer(dir.path(), &["render", "m.toml"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("(40x30, 2 objects, 3 primitives)"),
        "{stderr}"
    );
    let out = tracer(dir.path(), &["render", &scene("reflectance2.toml")]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("(500x400, 5 objects)"), "{stderr}");
}

#[test]
fn a_missing_mesh_file_exits_2_and_names_the_key() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("m.toml"),
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
         [[objects]]\nmesh = { obj = \"gone.obj\" }\n",
    )
    .unwrap();
    let out = tracer(dir.path(), &["render", "m.toml"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("objects[0].mesh.obj"), "{stderr}");
    assert!(stderr.contains("gone.obj"), "{stderr}");
    assert!(!dir.path().join("m.png").exists());
}

fn bad(name: &str) -> String {
    from_crate(&format!("../scene-format/tests/bad/{name}"))
}

#[test]
fn check_reports_every_error_of_every_file_and_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    let out = tracer(
        dir.path(),
        &[
            "check",
            &bad("many-errors.toml"),
            &scene("shadows.toml"),
            &bad("unknown-key.json"),
        ],
    );
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    for expected in [
        "many-errors.toml:4:7",
        "camera.fov",
        "many-errors.toml:5:9",
        "camera.width",
        "materials.red.reflectance",
        "objects[0].sphere.radius",
        "many-errors.toml:12:12",
        "unknown material `green`",
        "ok: ",
        "unknown-key.json:5:5",
        "did you mean `fov`?",
        "\"fvo\": 50",
        "2 of 3 scene files failed the check",
    ] {
        assert!(stderr.contains(expected), "{expected:?} not in:\n{stderr}");
    }
    assert!(std::fs::read_dir(dir.path()).unwrap().next().is_none());
}

#[test]
fn check_passes_every_lab_scene() {
    let dir = tempfile::tempdir().unwrap();
    let scenes: Vec<String> = std::fs::read_dir(scene(""))
        .unwrap()
        .map(|e| e.unwrap().path().to_str().unwrap().to_string())
        .filter(|p| p.ends_with(".toml") || p.ends_with(".json"))
        .collect();
    assert!(scenes.len() >= 12);
    let mut args = vec!["check"];
    args.extend(scenes.iter().map(String::as_str));
    let out = tracer(dir.path(), &args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn exit_status_is_2_for_bad_arguments_and_missing_scenes() {
    let dir = tempfile::tempdir().unwrap();
    assert_eq!(
        tracer(dir.path(), &["render", "--bogus"]).status.code(),
        Some(2)
    );
    assert_eq!(tracer(dir.path(), &["check"]).status.code(), Some(2));
    let out = tracer(dir.path(), &["check", "no-such-scene.toml"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no-such-scene.toml"));
    let out = tracer(dir.path(), &["render", "scene.yaml"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn a_failed_write_exits_1_and_leaves_what_was_there() {
    let dir = tempfile::tempdir().unwrap();
    // An output path that cannot be replaced: a non-empty folder.
    let target = dir.path().join("out.png");
    std::fs::create_dir(&target).unwrap();
    std::fs::write(target.join("keep"), b"old").unwrap();
    let out = tracer(
        dir.path(),
        &[
            "render",
            &scene("sphere-intersection.toml"),
            "-o",
            "out.png",
        ],
    );
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(std::fs::read(target.join("keep")).unwrap(), b"old");
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(names.len(), 1, "a temporary file was left behind");
}

#[test]
fn schema_is_json_describing_the_scene_keys() {
    let dir = tempfile::tempdir().unwrap();
    let out = tracer(dir.path(), &["schema"]);
    assert!(out.status.success());
    let schema: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let camera = &schema["$defs"]["Camera"];
    assert_eq!(camera["additionalProperties"], false);
    let mut keys: Vec<&str> = camera["properties"]
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    keys.sort();
    let expected = [
        "aperture",
        "eye",
        "focus_distance",
        "fov",
        "handedness",
        "height",
        "look_at",
        "projection",
        "up",
        "view_width",
        "width",
    ];
    assert_eq!(keys, expected);
    assert_eq!(camera["required"], serde_json::json!(["eye", "look_at"]));
}

#[test]
fn quiet_prints_nothing_for_an_aov_or_a_canvas_scene() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        [
            "render",
            &scene("sphere-intersection.toml"),
            "--aov",
            "depth",
            "--quiet",
        ],
        ["render", &scene("robot.toml"), "-o", "robot.png", "--quiet"],
    ] {
        let out = tracer(dir.path(), &args);
        assert!(out.status.success(), "{args:?}");
        assert!(
            out.stderr.is_empty(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    assert!(dir.path().join("sphere-intersection-depth.png").is_file());
    assert!(dir.path().join("robot.png").is_file());
}

/// A scene whose mesh has one face of zero area, next to a good one.
fn scene_with_a_degenerate_face(dir: &Path) {
    std::fs::write(
        dir.join("flat.obj"),
        "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nv 2 -1 0\nf 1 2 3\nf 1 2 4\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("m.toml"),
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nwidth = 40\nheight = 30\n\
         [[objects]]\nmesh = { obj = \"flat.obj\" }\n",
    )
    .unwrap();
}

#[test]
fn mesh_warnings_are_shown_on_every_render_path_even_when_quiet() {
    let dir = tempfile::tempdir().unwrap();
    scene_with_a_degenerate_face(dir.path());
    for args in [
        &["render", "m.toml", "--aov", "normal"][..],
        &["render", "m.toml", "--aov", "depth", "--quiet"],
        &["render", "m.toml", "--quiet"],
    ] {
        let out = tracer(dir.path(), args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{args:?}: {stderr}");
        assert!(
            stderr.contains(
                "warning: m.toml: `objects[0].mesh.obj`: 1 degenerate (zero-area) faces left out"
            ),
            "{args:?}: {stderr}"
        );
    }
    let out = tracer(dir.path(), &["check", "m.toml"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("1 degenerate"), "{stderr}");
}

#[test]
fn threads_are_honoured_by_an_aov_and_change_nothing_in_it() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene("shadows.toml");
    for (threads, out) in [("1", "one.png"), ("2", "two.png")] {
        let run = tracer(
            dir.path(),
            &[
                "render",
                &s,
                "--aov",
                "normal",
                "--threads",
                threads,
                "-o",
                out,
            ],
        );
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success(), "{stderr}");
        // The summary names the pool the AOV was rendered on.
        assert!(stderr.contains(&format!("on {threads} thread")), "{stderr}");
    }
    let one = std::fs::read(dir.path().join("one.png")).unwrap();
    assert_eq!(one, std::fs::read(dir.path().join("two.png")).unwrap());
    let zero = tracer(
        dir.path(),
        &["render", &s, "--aov", "normal", "--threads", "0"],
    );
    assert_eq!(zero.status.code(), Some(2));
}

/// `tracer check` on `text` written as `s.toml`: its stderr.
fn check_stderr(text: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), text).unwrap();
    let out = tracer(dir.path(), &["check", "s.toml"]);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{stderr}");
    stderr
}

#[test]
fn likely_mistakes_are_warnings_not_errors() {
    let camera = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n";
    let light = "[[lights]]\nposition = [0, 0, 10]\n";
    let sphere = "[[objects]]\nsphere = { center = [0, 0, 0], radius = 1 }\n";
    let no_lights = check_stderr(&format!("{camera}{sphere}"));
    assert!(
        no_lights.contains("warning: s.toml: `lights`: no lights: ambient is added once per light"),
        "{no_lights}"
    );
    let no_objects = check_stderr(&format!("{camera}{light}"));
    assert!(no_objects.contains("`objects`: no objects"), "{no_objects}");
    let behind = check_stderr(&format!(
        "{camera}{light}[[objects]]\nsphere = {{ center = [0, 0, 20], radius = 1 }}\n"
    ));
    assert!(
        behind.contains("`camera.look_at`: nothing is in front of the camera"),
        "{behind}"
    );
    let bytes = check_stderr(&format!(
        "{camera}{light}[materials.red]\ndiffuse = [200, 0, 0]\n{sphere}material = \"red\"\n"
    ));
    assert!(
        bytes.contains("`materials.red.diffuse`: a channel above 1 in [200, 0, 0]"),
        "{bytes}"
    );
    let glass = "[materials.glass]\ntransmittance = 0.9\nreflectance = 0.1\nfresnel = true\n";
    let pane = check_stderr(&format!(
        "{camera}{light}{glass}[[objects]]\ntriangle = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\nmaterial = \"glass\"\n"
    ));
    for expected in [
        "`objects[0].material`: a transparent material on a single triangle",
        "`materials.glass.reflectance`: ignored with `fresnel = true`",
        "`render.max_depth`: 1: a ray can enter a transparent object but not leave it",
    ] {
        assert!(pane.contains(expected), "{expected}\n{pane}");
    }
    let blur = check_stderr(&format!(
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\naperture = 0.1\n{light}{sphere}"
    ));
    assert!(
        blur.contains("`render.samples`: 1: with an aperture"),
        "{blur}"
    );
    let fine = check_stderr(&format!("{camera}{light}{sphere}"));
    assert!(!fine.contains("warning"), "{fine}");
}

#[test]
fn the_lab_scenes_give_no_warnings() {
    let dir = tempfile::tempdir().unwrap();
    let scenes: Vec<String> = std::fs::read_dir(scene(""))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| p.to_str().unwrap().to_string())
        .collect();
    let mut args = vec!["check"];
    args.extend(scenes.iter().map(String::as_str));
    let out = tracer(dir.path(), &args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("warning"), "{stderr}");
}

#[test]
fn a_render_mostly_forced_white_suggests_clamp() {
    let dir = tempfile::tempdir().unwrap();
    // A bright sphere filling the view: the lab's rule whitens most of it.
    let text = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nwidth = 40\nheight = 30\n\
                [[lights]]\nposition = [0, 0, 10]\ncolor = [3, 3, 3]\n\
                [[objects]]\nsphere = { center = [0, 0, 0], radius = 4 }\n\
                material = { diffuse = [0.8, 0.2, 0.2] }\n";
    std::fs::write(dir.path().join("s.toml"), text).unwrap();
    let out = tracer(dir.path(), &["render", "s.toml", "--quiet"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("warning: s.toml: "), "{stderr}");
    assert!(stderr.contains("saturation = \"clamp\""), "{stderr}");
    let clamped = text.replace("[[lights]]", "[render]\nsaturation = \"clamp\"\n[[lights]]");
    std::fs::write(dir.path().join("s.toml"), clamped).unwrap();
    let out = tracer(dir.path(), &["render", "s.toml", "--quiet"]);
    assert!(!String::from_utf8_lossy(&out.stderr).contains("warning"));
}

/// `tracer check` on `text` written to `dir/name`: its exit code and stderr.
fn check_text(dir: &Path, name: &str, text: &str) -> (Option<i32>, String) {
    std::fs::write(dir.join(name), text).unwrap();
    let out = tracer(dir, &["check", name]);
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

const CAMERA_JSON: &str = r#""camera": {"eye": [0, 0, 10], "look_at": [0, 0, 0]}"#;

#[test]
fn an_error_far_along_a_long_line_shows_a_window_of_it() {
    let dir = tempfile::tempdir().unwrap();
    // Past column 65,535 miette panicked (exit 101).
    let text = format!(
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nfov = {}500\n",
        " ".repeat(70_000)
    );
    let (code, err) = check_text(dir.path(), "far.toml", &text);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("far.toml:4:70007]"), "{err}");
    assert!(err.contains("500"), "{err}");
    assert!(err.len() < 2_000, "{} bytes:\n{err}", err.len());

    // A minified JSON file: 10,000 lights on one line, two bad colours.
    let lights: Vec<String> = (0..10_000)
        .map(|i| {
            let c = if i == 5_000 || i == 9_000 { -1 } else { 1 };
            format!(r#"{{"position":[{i},0,0],"color":[1,{c},1]}}"#)
        })
        .collect();
    let text = format!(r#"{{{CAMERA_JSON},"lights":[{}]}}"#, lights.join(","));
    assert!(text.len() > 300_000 && !text.contains('\n'));
    let (code, err) = check_text(dir.path(), "minified.json", &text);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("lights[5000].color"), "{err}");
    assert!(err.contains("lights[9000].color"), "{err}");
    assert!(err.len() < 4_000, "{} bytes:\n{err}", err.len());
}

#[test]
fn thousands_of_problems_show_the_first_hundred_and_a_count() {
    let dir = tempfile::tempdir().unwrap();
    // 20,000 negative radii: every one is found, a hundred are shown.
    let objects: String = (0..20_000)
        .map(|i| format!("[[objects]]\nsphere = {{ center = [{i}, 0, 0], radius = -1 }}\n"))
        .collect();
    let text = format!("[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n{objects}");
    let (code, err) = check_text(dir.path(), "many.toml", &text);
    assert_eq!(code, Some(2), "{err}");
    assert_eq!(
        err.matches("expected a radius from 1e-4 to 1e6").count(),
        100,
        "{err}"
    );
    assert!(err.contains("objects[99].sphere.radius"));
    assert!(!err.contains("objects[100].sphere.radius"));
    assert!(err.contains("and 19900 more problems"), "{err}");
}

#[test]
fn unknown_names_list_at_most_ten_known_ones() {
    let dir = tempfile::tempdir().unwrap();
    // 5,000 materials and 5,000 objects naming none of them: each message
    // used to list all 5,000 names (280 MB in all).
    let materials: Vec<String> = (0..5_000)
        .map(|i| format!(r#""material{i}": {{"diffuse": [1, 0, 0]}}"#))
        .collect();
    let objects: Vec<String> = (0..5_000)
        .map(|i| format!(r#"{{"sphere": {{"center": [0, 0, 0], "radius": 1}}, "material": "nothing like it {i}"}}"#))
        .collect();
    let text = format!(
        "{{{CAMERA_JSON},\n\"materials\": {{{}}},\n\"objects\": [\n{}\n]}}",
        materials.join(",\n"),
        objects.join(",\n")
    );
    let (code, err) = check_text(dir.path(), "names.json", &text);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("and 4990 more"), "{err}");
    assert!(err.len() < 100_000, "{} bytes", err.len());
}

fn stderr_of(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The temporary output files left in `dir`.
fn leftovers(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".tracer-") && n.ends_with(".tmp"))
        .collect()
}

/// A small scene with a mesh, `m.toml` and `m.obj`.
fn scene_with_a_mesh(dir: &Path) {
    std::fs::write(dir.join("m.obj"), "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::write(
        dir.join("m.toml"),
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nwidth = 40\nheight = 30\n\
         [[objects]]\nmesh = { obj = \"m.obj\" }\n",
    )
    .unwrap();
}

#[test]
fn an_output_that_is_an_input_is_refused_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    scene_with_a_mesh(d);
    let scene_text = std::fs::read(d.join("m.toml")).unwrap();
    let obj_text = std::fs::read(d.join("m.obj")).unwrap();
    // The OBJ under an image's name (a hard link), and the CSV too: only
    // the file's identity tells them from an output.
    std::fs::hard_link(d.join("m.obj"), d.join("mesh.png")).unwrap();
    std::fs::write(d.join("m.csv"), "level,luminance\n0,0.5\n0.5,40\n1,200\n").unwrap();
    std::fs::hard_link(d.join("m.csv"), d.join("csv.png")).unwrap();
    for args in [
        &["render", "m.toml", "-o", "m.toml"][..],
        &["render", "m.toml", "-o", "./m.toml"],
        &["render", "m.toml", "-o", "mesh.png"],
        &["render", "m.toml", "-o", "m.obj"],
        &["gamma", "fit", "m.csv", "--plot", "m.csv"],
        &["gamma", "fit", "m.csv", "--plot", "./csv.png"],
        &["gamma", "fit", "csv.png", "--plot", "csv.png"],
        &["calib-chart", "-o", "m.toml"],
    ] {
        let out = tracer(d, args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr_of(&out));
        assert!(out.stdout.is_empty(), "{args:?}: no work was done");
    }
    let out = tracer(d, &["render", "m.toml", "-o", "mesh.png"]);
    assert!(
        stderr_of(&out).contains("refusing to overwrite"),
        "{}",
        stderr_of(&out)
    );
    assert_eq!(std::fs::read(d.join("m.toml")).unwrap(), scene_text);
    assert_eq!(std::fs::read(d.join("m.obj")).unwrap(), obj_text);
    assert!(std::fs::read(d.join("m.csv"))
        .unwrap()
        .starts_with(b"level"));
    assert!(leftovers(d).is_empty());
}

#[test]
fn a_reference_that_is_the_output_is_refused_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cornell = scene("cornell-box.toml");
    // A reference the render's size: the render would be measured against
    // it, then written over it.
    image::Rgb32FImage::from_pixel(8, 8, image::Rgb([0.5, 0.25, 0.125]))
        .save(d.join("mine.exr"))
        .unwrap();
    std::fs::hard_link(d.join("mine.exr"), d.join("linked.exr")).unwrap();
    let before = std::fs::read(d.join("mine.exr")).unwrap();
    for (output, reference) in [("mine.exr", "mine.exr"), ("linked.exr", "./mine.exr")] {
        let args = [
            "render",
            &cornell,
            "-o",
            output,
            "--reference",
            reference,
            "--width",
            "8",
            "--samples",
            "1",
        ];
        let out = tracer(d, &args);
        let stderr = stderr_of(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            stderr.contains("the output is the input") && stderr.contains("refusing"),
            "{stderr}"
        );
    }
    assert_eq!(std::fs::read(d.join("mine.exr")).unwrap(), before);
    assert!(leftovers(d).is_empty());
}

#[test]
fn an_output_extension_the_tracer_cannot_write_is_refused_with_the_list() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let s = scene("sphere-intersection.toml");
    for name in ["x.tif", "x.webp", "noext"] {
        for args in [
            &["render", &s, "-o", name][..],
            &["calib-chart", "-o", name],
            &[
                "gamma",
                "fit",
                &scene("gamma/sample-measurements.csv"),
                "--plot",
                name,
            ],
        ] {
            let out = tracer(d, args);
            let stderr = stderr_of(&out);
            assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
            assert!(
                stderr.contains("the image formats written are: .png, .jpg, .jpeg, .exr, .hdr"),
                "{stderr}"
            );
            assert!(out.stdout.is_empty(), "{args:?}: the fit was not made");
        }
        assert!(!d.join(name).exists());
    }
    // A chart or a plot has no linear values: refused before the work.
    for args in [
        &["calib-chart", "-o", "x.exr"][..],
        &[
            "gamma",
            "fit",
            &scene("gamma/sample-measurements.csv"),
            "--plot",
            "x.hdr",
        ],
    ] {
        let out = tracer(d, args);
        let stderr = stderr_of(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains("only the 8-bit formats"), "{stderr}");
        assert!(out.stdout.is_empty(), "{args:?}: the fit was not made");
    }
    assert!(leftovers(d).is_empty());
    let out = tracer(d, &["render", &s, "-o", "upper.PNG"]);
    assert!(out.status.success(), "{}", stderr_of(&out));
    assert!(std::fs::read(d.join("upper.PNG"))
        .unwrap()
        .starts_with(b"\x89PNG"));
}

#[test]
fn a_bad_output_path_fails_before_the_scene_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The scene is bad too: the output's error, not the scene's, shows
    // that the output was checked first (before loading and rendering).
    std::fs::write(d.join("bad.toml"), "[camera]\nfvo = 1\n").unwrap();
    std::fs::create_dir(d.join("folder.png")).unwrap();
    for (output, expected) in [
        (
            "missing/out.png",
            "missing/out.png: the folder missing does not exist",
        ),
        ("folder.png", "cannot write over a folder"),
    ] {
        let out = tracer(d, &["render", "bad.toml", "-o", output]);
        let stderr = stderr_of(&out);
        assert_eq!(out.status.code(), Some(1), "{output}: {stderr}");
        assert!(stderr.contains(expected), "{output}: {stderr}");
        assert!(!stderr.contains("fvo"), "{output}: {stderr}");
    }
    assert!(leftovers(d).is_empty());
}

#[test]
fn a_full_stdout_exits_1_and_a_closed_one_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let csv = scene("gamma/sample-measurements.csv");
    for args in [&["schema"][..], &["gamma", "fit", &csv]] {
        let out = Command::new(env!("CARGO_BIN_EXE_tracer"))
            .args(args)
            .current_dir(d)
            .stdout(std::fs::File::create("/dev/full").unwrap())
            .output()
            .unwrap();
        let stderr = stderr_of(&out);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains("cannot write to stdout"), "{stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
    // `true` has exited (closing the pipe) by the time tracer writes.
    let out = Command::new("sh")
        .arg("-c")
        .arg("{ sleep 0.5; \"$0\" schema; echo $? > status; } | true")
        .arg(env!("CARGO_BIN_EXE_tracer"))
        .current_dir(d)
        .output()
        .unwrap();
    assert!(out.status.success());
    assert_eq!(stderr_of(&out), "");
    assert_eq!(std::fs::read_to_string(d.join("status")).unwrap(), "0\n");
}

#[test]
fn a_full_stderr_does_not_stop_the_image() {
    let dir = tempfile::tempdir().unwrap();
    // Its degenerate face gives a warning before the render.
    scene_with_a_degenerate_face(dir.path());
    let out = Command::new(env!("CARGO_BIN_EXE_tracer"))
        .args(["render", "m.toml"])
        .current_dir(dir.path())
        .stderr(std::fs::File::create("/dev/full").unwrap())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(rgb(&dir.path().join("m.png")).dimensions(), (40, 30));
}

#[cfg(unix)]
#[test]
fn sigterm_during_a_render_removes_the_temporary_output() {
    use std::os::unix::process::ExitStatusExt;
    use std::time::{Duration, Instant};
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The bench's bunny, large and on one thread: seconds of work.
    let bench = std::fs::read_to_string(scene("bench/bunny.toml")).unwrap();
    let bench = bench
        .replace("width = 1920", "width = 3000")
        .replace("height = 1080", "height = 3000")
        .replace("\"bunny.obj\"", &format!("{:?}", scene("bench/bunny.obj")));
    std::fs::write(d.join("big.toml"), bench).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_tracer"))
        .args(["render", "big.toml", "--threads", "1", "--quiet"])
        .current_dir(d)
        .spawn()
        .unwrap();
    // The temporary output is made before the scene is read.
    let start = Instant::now();
    while leftovers(d).is_empty() {
        assert!(
            start.elapsed() < Duration::from_secs(20),
            "no temporary file"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    std::thread::sleep(Duration::from_millis(300));
    let kill = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let status = child.wait().unwrap();
    // 128 + SIGTERM, as a shell reports a process it terminated.
    assert_eq!(status.code(), Some(143), "{status:?} {:?}", status.signal());
    assert!(leftovers(d).is_empty(), "{:?}", leftovers(d));
    assert!(!d.join("big.png").exists());
}

#[cfg(unix)]
#[test]
fn devices_fifos_and_oversized_files_as_inputs_are_refused_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::os::unix::fs::symlink("/dev/zero", d.join("zero.toml")).unwrap();
    std::os::unix::fs::symlink("/dev/urandom", d.join("random.obj")).unwrap();
    std::fs::write(
        d.join("m.toml"),
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
         [[objects]]\nmesh = { obj = \"random.obj\" }\n",
    )
    .unwrap();
    assert!(Command::new("mkfifo")
        .arg(d.join("fifo.csv"))
        .status()
        .unwrap()
        .success());
    // Sparse: 65 MiB by its size, nothing written.
    let big = std::fs::File::create(d.join("big.json")).unwrap();
    big.set_len(65 << 20).unwrap();
    for (args, expected) in [
        (&["render", "zero.toml"][..], "zero.toml: cannot read the scene file: is not a regular file"),
        (&["check", "zero.toml"], "is not a regular file"),
        (&["render", "m.toml"], "cannot load `random.obj`: is not a regular file"),
        (&["gamma", "fit", "fifo.csv"], "fifo.csv: cannot read the measurements: is not a regular file"),
        (&["check", "big.json"], "big.json: cannot read the scene file: is 65 MiB; files of this kind are read up to 64 MiB"),
    ] {
        let out = tracer(d, args);
        let stderr = stderr_of(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
    }
}

#[test]
fn a_folder_or_an_unreadable_file_as_the_scene_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("folder.toml")).unwrap();
    std::fs::write(d.join("bad.toml"), "[camera]\nfvo = 1\n").unwrap();
    let out = tracer(d, &["render", "folder.toml"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr_of(&out));
    assert!(stderr_of(&out).contains("folder.toml: cannot read the scene file: is a folder"));
    let good = scene("shadows.toml");
    let mut check = vec!["check", good.as_str(), "bad.toml", "folder.toml"];
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let locked = d.join("locked.toml");
        std::fs::write(&locked, "[camera]\n").unwrap();
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o000)).unwrap();
        // Root reads it anyway; then there is nothing to test.
        if std::fs::read(&locked).is_err() {
            let out = tracer(d, &["render", "locked.toml"]);
            assert_eq!(out.status.code(), Some(2), "{}", stderr_of(&out));
            check.push("locked.toml");
        }
    }
    let out = tracer(d, &check);
    let stderr = stderr_of(&out);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("ok: "), "{stderr}");
}

#[test]
fn width_or_height_alone_keeps_the_view_and_its_shape() {
    let dir = tempfile::tempdir().unwrap();
    for (flag, value) in [("--width", "250"), ("--height", "200")] {
        let out = tracer(
            dir.path(),
            &[
                "render",
                &scene("sphere-intersection.toml"),
                flag,
                value,
                "-o",
                "half.png",
            ],
        );
        assert!(out.status.success(), "{flag}");
        let half = rgb(&dir.path().join("half.png"));
        assert_eq!(half.dimensions(), (250, 200), "{flag}");
        // The small sphere projects to (353, 146) of the 500x400 image (the
        // goldens' hand-worked value): (176, 73) at half the size; its
        // mirror place stays black.
        assert_eq!(half.get_pixel(176, 73).0, [0, 186, 0], "{flag}");
        assert_eq!(half.get_pixel(73, 73).0, [0, 0, 0], "{flag}");
    }
}

#[test]
fn samples_smooth_the_edges_and_keep_flat_colours() {
    let dir = tempfile::tempdir().unwrap();
    let render = |samples: &str| {
        let out = tracer(
            dir.path(),
            &[
                "render",
                &scene("sphere-intersection.toml"),
                "--samples",
                samples,
                "-o",
                "s.png",
            ],
        );
        assert!(out.status.success());
        rgb(&dir.path().join("s.png"))
    };
    let greens = |image: &image::RgbImage| {
        let mut values: Vec<u8> = image.pixels().map(|p| p.0[1]).collect();
        values.sort();
        values.dedup();
        values
    };
    // One ray per pixel: a hit is (0, 0.5, 0) -> 186, a miss 0, nothing between.
    assert_eq!(greens(&render("1")), [0, 186]);
    let smooth = render("16");
    assert!(greens(&smooth).len() > 10, "edges take partial values");
    // Inside the sphere every sample hits: the same flat colour.
    assert_eq!(smooth.get_pixel(250, 200).0, [0, 186, 0]);
}

#[test]
fn options_of_3d_renders_are_refused_for_a_canvas_and_sizes_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    let robot = scene("robot.toml");
    let out = tracer(dir.path(), &["render", &robot, "--samples", "4"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("--samples needs a 3D scene"), "{stderr}");

    let lab = scene("sphere-intersection.toml");
    // 500x400 at a height of 16384 keeps its shape at 20480 wide: too wide.
    let out = tracer(dir.path(), &["render", &lab, "--height", "16384"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("20480x16384 pixels"), "{stderr}");

    for bad in [["--samples", "0"], ["--samples", "5000"], ["--width", "0"]] {
        let out = tracer(dir.path(), &["render", &lab, bad[0], bad[1]]);
        assert_eq!(out.status.code(), Some(2), "{bad:?}");
    }
    assert!(!dir.path().join("sphere-intersection.png").exists());
    assert!(!dir.path().join("robot.png").exists());
}

#[test]
fn bit_depth_16_and_gamma_are_refused_where_the_format_cannot_hold_them() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The scene is bad too: the option's error shows it came before the
    // scene was read, so before any render.
    std::fs::write(d.join("bad.toml"), "[camera]\nfvo = 1\n").unwrap();
    for (args, expected) in [
        (
            &["render", "bad.toml", "-o", "x.jpg", "--bit-depth", "16"][..],
            "--bit-depth 16 is for .png outputs; JPEG files are written at 8 bits",
        ),
        (
            &["render", "bad.toml", "-o", "x.exr", "--bit-depth", "16"],
            "--bit-depth 16 is for .png outputs; OpenEXR files",
        ),
        (
            &["render", "bad.toml", "-o", "x.hdr", "--gamma", "2.2"],
            "--gamma encodes for a display; Radiance HDR files hold",
        ),
    ] {
        let out = tracer(d, args);
        let stderr = stderr_of(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{stderr}");
        assert!(!stderr.contains("fvo"), "{stderr}");
    }
    let out = tracer(d, &["render", "bad.toml", "--bit-depth", "12"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(leftovers(d).is_empty());
}

#[test]
fn a_canvas_scene_writes_16_bit_png_and_exr() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let robot = scene("robot.toml");
    for args in [
        &["render", &robot, "-o", "r8.png"][..],
        &["render", &robot, "-o", "r16.png", "--bit-depth", "16"],
        &["render", &robot, "-o", "r.exr"],
    ] {
        let out = tracer(d, args);
        assert!(out.status.success(), "{args:?}: {}", stderr_of(&out));
    }
    let r8 = image::open(d.join("r8.png")).unwrap().into_rgb8();
    let r16 = image::open(d.join("r16.png")).unwrap();
    let r16 = r16.as_rgb16().expect("a 16-bit PNG");
    for (a, b) in r8.pixels().zip(r16.pixels()) {
        assert_eq!(a.0, b.0.map(|v| (v / 257) as u8));
    }
    let exr = image::open(d.join("r.exr")).unwrap().into_rgb32f();
    assert_eq!(exr.dimensions(), r8.dimensions());
}

#[test]
fn a_packed_scene_checks_and_renders_as_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    scene_with_a_mesh(d);
    std::fs::write(d.join("look.toml"), "[[lights]]\nposition = [0, 0, 10]\n").unwrap();
    let text = std::fs::read_to_string(d.join("m.toml")).unwrap();
    std::fs::write(
        d.join("m.toml"),
        format!("include = [\"look.toml\"]\n{text}"),
    )
    .unwrap();
    let out = tracer(d, &["pack", "m.toml"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr_of(&out));
    assert!(stderr_of(&out).contains("(3 files,"), "{}", stderr_of(&out));
    let out = tracer(d, &["check", "m.zip"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr_of(&out));
    let out = tracer(d, &["render", "m.zip", "-o", "zip.png", "-q"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr_of(&out));
    let out = tracer(d, &["render", "m.toml", "-o", "toml.png", "-q"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr_of(&out));
    let (zip, toml) = (rgb(&d.join("zip.png")), rgb(&d.join("toml.png")));
    assert_eq!(zip.as_raw(), toml.as_raw());
    // The lit triangle shows: not all of the image is black.
    assert!(toml.as_raw().iter().any(|&b| b > 0));
}

#[test]
fn pack_of_a_scene_with_a_missing_mesh_exits_2_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    scene_with_a_mesh(d);
    std::fs::remove_file(d.join("m.obj")).unwrap();
    let out = tracer(d, &["pack", "m.toml", "-o", "m.zip"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = stderr_of(&out);
    // `mesh = { obj = "m.obj" }` is line 7; the value starts at column 16.
    assert!(stderr.contains("m.toml:7:16"), "{stderr}");
    assert!(stderr.contains("objects[0].mesh.obj"), "{stderr}");
    assert!(!d.join("m.zip").exists());
    assert!(leftovers(d).is_empty());
}

#[test]
fn an_error_in_an_included_file_names_it_in_the_report() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("lib")).unwrap();
    std::fs::write(
        d.join("lib/look.json"),
        "{\"lights\": [{\"position\": [0, 0]}]}\n",
    )
    .unwrap();
    std::fs::write(
        d.join("s.toml"),
        "include = [\"lib/look.json\"]\n[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n",
    )
    .unwrap();
    let out = tracer(d, &["check", "s.toml"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = stderr_of(&out);
    // `[0, 0]` starts at column 26 of lib/look.json's first line.
    assert!(stderr.contains("lib/look.json:1:26"), "{stderr}");
    assert!(stderr.contains("lights[0].position"), "{stderr}");
}

#[test]
fn an_included_file_is_checked_and_converted_on_its_own() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(
        d.join("look.toml"),
        "[materials.red]\ndiffuse = [1, 0, 0]\n",
    )
    .unwrap();
    // `red` is defined by another file of the scene: not a problem alone.
    let stage = "include = [\"look.toml\"]\n[[objects]]\n\
                 sphere = { center = [0, 0, 0], radius = 1 }\nmaterial = \"blue\"\n";
    std::fs::write(d.join("stage.toml"), stage).unwrap();
    let out = tracer(d, &["check", "--part", "look.toml", "stage.toml"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr_of(&out));
    assert!(
        stderr_of(&out).contains("ok: stage.toml, as a file for a scene to include"),
        "{}",
        stderr_of(&out)
    );
    // Without --part, a file without a camera is not "ok": a student who
    // forgot it is told that rendering needs one, and the exit is 1.
    let out = tracer(d, &["check", "stage.toml"]);
    let stderr = stderr_of(&out);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("warning: stage.toml has no [camera], so it cannot be rendered")
            && stderr.contains("tracer check --part stage.toml")
            && !stderr.contains("ok:"),
        "{stderr}"
    );
    let out = tracer(d, &["convert", "stage.toml"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr_of(&out));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("stage.json")).unwrap()).unwrap();
    assert_eq!(json["include"][0], "look.toml");
    assert_eq!(json["objects"][0]["material"], "blue");

    // Its values, includes and meshes are still checked, located.
    std::fs::write(
        d.join("bad.toml"),
        "include = [\"none.toml\"]\n[[objects]]\nsphere = { center = [0, 0, 0], radius = -1 }\n",
    )
    .unwrap();
    let out = tracer(d, &["convert", "bad.toml"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr_of(&out).contains("bad.toml:1:12"),
        "{}",
        stderr_of(&out)
    );
    std::fs::write(
        d.join("bad.toml"),
        "[[objects]]\nsphere = { center = [0, 0, 0], radius = -1 }\n",
    )
    .unwrap();
    let out = tracer(d, &["check", "bad.toml"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr_of(&out).contains("bad.toml:2:41"),
        "{}",
        stderr_of(&out)
    );
    assert!(!d.join("bad.json").exists());
    // A scene that forgot its camera but sets `render` is still a scene,
    // and so is one with a misspelt table, whose hint names the scene's key.
    std::fs::write(d.join("nocam.toml"), "[render]\nsamples = 4\n").unwrap();
    let out = tracer(d, &["check", "nocam.toml"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr_of(&out).contains("missing key `camera`"),
        "{}",
        stderr_of(&out)
    );
    let camra =
        "[camra]\neye = [0, 0, 1]\n[[objects]]\nsphere = { center = [0, 0, 0], radius = 1 }\n";
    std::fs::write(d.join("camra.toml"), camra).unwrap();
    let out = tracer(d, &["check", "camra.toml"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr_of(&out).contains("did you mean `camera`?"),
        "{}",
        stderr_of(&out)
    );
    // The warnings of its own items are shown, not the scene's.
    std::fs::write(
        d.join("red.toml"),
        "[materials.red]\ndiffuse = [255, 0, 0]\n",
    )
    .unwrap();
    let out = tracer(d, &["check", "--part", "red.toml"]);
    assert_eq!(out.status.code(), Some(0));
    let stderr = stderr_of(&out);
    assert!(
        stderr.contains("`materials.red.diffuse`: a channel above 1"),
        "{stderr}"
    );
    assert!(!stderr.contains("no lights"), "{stderr}");
}

#[test]
fn check_shows_the_problems_of_each_file_of_a_scene() {
    let dir = tempfile::tempdir().unwrap();
    let scene = from_crate("../scene-format/tests/include/several-files/scene.toml");
    let out = tracer(dir.path(), &["check", &scene]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = stderr_of(&out);
    // One block in the scene file, one in the file it includes.
    assert!(stderr.contains("several-files/scene.toml:6:7"), "{stderr}");
    assert!(
        stderr.contains("several-files/objects.toml:2:41"),
        "{stderr}"
    );
    assert!(
        stderr.contains("1 of 1 scene file failed the check"),
        "{stderr}"
    );
}

#[test]
fn path_mode_on_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let cornell = scene("cornell-box.toml");
    let small = ["--samples", "2", "--width", "32", "--threads", "2"];
    // An AOV does not trace light: no integrator goes with it.
    let out = tracer(
        dir.path(),
        &[
            "render",
            &cornell,
            "--integrator",
            "path",
            "--aov",
            "normal",
        ],
    );
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--integrator") && stderr.contains("--aov"),
        "{stderr}"
    );
    // A misspelt integrator is named with the ones there are.
    let out = tracer(dir.path(), &["render", &cornell, "--integrator", "pth"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("whitted") && stderr.contains("path"),
        "{stderr}"
    );
    // Above 4096 samples only in path mode.
    let shadows = scene("shadows.toml");
    let out = tracer(
        dir.path(),
        &["render", &shadows, "--samples", "5000", "-o", "x.png"],
    );
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("path mode"), "{stderr}");
    assert!(!dir.path().join("x.png").exists());
    // A lab scene in path mode: its ambient is warned about once, and the
    // linear light of the Cornell box's lamp is kept in an EXR.
    let mut args = vec!["render", &shadows, "--integrator", "path", "-o", "s.png"];
    args.extend(small);
    let out = tracer(dir.path(), &args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        stderr.matches("ignored in path mode").count(),
        1,
        "{stderr}"
    );
    // Its point lights, 10 units away, leave it nearly black: said, with why.
    assert!(
        stderr.contains("nearly black") && stderr.contains("square of the distance"),
        "{stderr}"
    );
    // A tile's mean is not the image's: not judged.
    let mut args = vec!["render", &shadows, "--integrator", "path", "-o", "t.exr"];
    args.extend(["--tile", "0/2"]);
    args.extend(small);
    let out = tracer(dir.path(), &args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success() && !stderr.contains("nearly black"),
        "{stderr}"
    );
    let mut args = vec!["render", &cornell, "-o", "c.exr"];
    args.extend(small);
    let out = tracer(dir.path(), &args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let exr = image::open(dir.path().join("c.exr")).unwrap().to_rgb32f();
    let brightest = exr.pixels().map(|p| p.0[0]).fold(0.0, f32::max);
    assert!(brightest > 10.0, "{brightest}");
}

#[test]
fn time_limit_and_reference_render_in_passes() {
    let dir = tempfile::tempdir().unwrap();
    let cornell = scene("cornell-box.toml");
    let reference = from_crate("../tracer-core/tests/data/cornell-box-mitsuba.exr");
    // A limit far beyond the render: every pass, and the image of a plain
    // render; each pass's error against Mitsuba's image falls.
    let small = ["--samples", "8", "--threads", "2"];
    let mut args = vec!["render", &cornell, "-o", "plain.png"];
    args.extend(small);
    assert!(tracer(dir.path(), &args).status.success());
    let mut args = vec![
        "render",
        &cornell,
        "-o",
        "passes.png",
        "--time-limit",
        "600",
    ];
    args.extend(["--reference", &reference]);
    args.extend(small);
    let out = tracer(dir.path(), &args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(rgb(&dir.path().join("plain.png")) == rgb(&dir.path().join("passes.png")));
    let errors: Vec<f64> = stderr
        .lines()
        .filter_map(|l| l.split("RMSE ").nth(1))
        .map(|r| r.split(' ').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(errors.len(), 4, "passes of 1, 2, 4, 8: {stderr}");
    assert!(errors.windows(2).all(|e| e[1] < e[0]), "{errors:?}");
    // A limit that a tiny render already takes: its first pass, said.
    let mut args = vec!["render", &cornell, "-o", "cut.png", "--time-limit", "1e-9"];
    args.extend(["--samples", "64"]);
    let out = tracer(dir.path(), &args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("stopped at 1 of 64 samples"), "{stderr}");
    // Whitted mode has no passes; a reference of another size is refused.
    let shadows = scene("shadows.toml");
    let out = tracer(dir.path(), &["render", &shadows, "--time-limit", "5"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("needs path mode"));
    let mut args = vec![
        "render",
        &cornell,
        "--reference",
        &reference,
        "--width",
        "64",
    ];
    args.extend(["-o", "wrong.png"]);
    let out = tracer(dir.path(), &args);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("256x256, but the render is 64x64"),
        "{stderr}"
    );
    assert!(!dir.path().join("wrong.png").exists());
    // Told from its header: decoding a much larger one passed the memory the
    // render's size allows, and said only "Memory limit exceeded".
    image::Rgb32FImage::new(1024, 1024)
        .save(dir.path().join("large.exr"))
        .unwrap();
    let mut args = vec!["render", &cornell, "--reference", "large.exr"];
    args.extend(["--width", "32", "-o", "small.png"]);
    let out = tracer(dir.path(), &args);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("1024x1024, but the render is 32x32"),
        "{stderr}"
    );
    // A PNG holds display values: its error would mean nothing.
    let args = [
        "render",
        &cornell,
        "--reference",
        "plain.png",
        "-o",
        "png.png",
    ];
    let out = tracer(dir.path(), &args);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("is a PNG image, of display values; expected a linear .exr or .hdr"),
        "{stderr}"
    );
    // A time limit with one sample a pixel has nothing to stop: said.
    let mut args = vec!["render", &cornell, "--time-limit", "60", "-o", "one.png"];
    args.extend(["--samples", "1", "--width", "32", "--height", "32"]);
    let out = tracer(dir.path(), &args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("--time-limit has nothing to stop"),
        "{stderr}"
    );
}

#[test]
fn environment_images_are_checked_and_physically_based_scenes_render_in_both_modes() {
    let dir = tempfile::tempdir().unwrap();
    // A sky three times as wide as high: read, with a warning.
    let wide = image::Rgb32FImage::from_pixel(24, 8, image::Rgb([0.5, 0.6, 0.9]));
    wide.save(dir.path().join("wide.hdr")).unwrap();
    let png = image::RgbImage::from_pixel(16, 8, image::Rgb([100, 150, 250]));
    png.save(dir.path().join("sky.png")).unwrap();
    let scene = |sky: &str| {
        format!(
            "[camera]\neye = [0, 1, 5]\nlook_at = [0, 0.5, 0]\nwidth = 24\nheight = 16\n\
             [render]\nintegrator = \"path\"\nsamples = 4\n\
             [environment]\nimage = \"{sky}\"\n\
             [[objects]]\nsphere = {{ center = [0, 0.5, 0], radius = 0.5 }}\n\
             material = {{ base_color = [0.9, 0.6, 0.2], metallic = 1, roughness = 0.3 }}\n\
             [[objects]]\nsphere = {{ center = [1.2, 0.5, 0], radius = 0.5 }}\n\
             material = {{ transmission = 1, roughness = 0.1 }}\n"
        )
    };
    std::fs::write(dir.path().join("wide.toml"), scene("wide.hdr")).unwrap();
    std::fs::write(dir.path().join("png.toml"), scene("sky.png")).unwrap();
    let out = tracer(dir.path(), &["render", "wide.toml"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("24x8: a latitude-longitude image is twice as wide"),
        "{stderr}"
    );
    // Whitted mode shades the same materials by their lab reading.
    let out = tracer(
        dir.path(),
        &[
            "render",
            "wide.toml",
            "--integrator",
            "whitted",
            "-o",
            "w.png",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = tracer(dir.path(), &["render", "png.toml"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("png.toml:10:9")
            && stderr.contains("expected a Radiance .hdr or an OpenEXR .exr"),
        "{stderr}"
    );
}

#[test]
fn explain_prints_the_tree_and_its_json_has_the_fixed_keys() {
    let dir = tempfile::tempdir().unwrap();
    let illumination = scene("illumination.toml");
    let out = tracer(dir.path(), &["explain", &illumination, "250", "200"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for words in [
        "primary ray",
        "N.L",
        "(N.H)^n",
        "shadow ray",
        "gamma 2.2",
        "(192, 112, 112)",
    ] {
        assert!(text.contains(words), "{words}: {text}");
    }
    // The image's pixel is what explain says it is.
    let png = dir.path().join("i.png");
    tracer(dir.path(), &["render", &illumination, "-o", "i.png"]);
    assert_eq!(rgb(&png).get_pixel(250, 200).0, [192, 112, 112]);
    let out = tracer(
        dir.path(),
        &["explain", &illumination, "250", "200", "--json"],
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["version"], 1);
    assert_eq!(json["pixel"], serde_json::json!([250, 200]));
    assert_eq!(json["rgb8"], serde_json::json!([192, 112, 112]));
    assert_eq!(json["linear"].as_array().unwrap().len(), 3);
    let ray = &json["ray"];
    assert_eq!(ray["origin"], serde_json::json!([0.0, 0.0, 10.0]));
    let direction: Vec<f64> = serde_json::from_value(ray["direction"].clone()).unwrap();
    let length = direction.iter().map(|d| d * d).sum::<f64>().sqrt();
    assert!((length - 1.0).abs() < 1e-6, "{length}");
    for key in ["t", "point", "normal"] {
        assert!(
            ray["hit"][key].is_number() || ray["hit"][key].is_array(),
            "{key}"
        );
    }
    // A ray that misses has a null hit; a pixel outside is bad input.
    let out = tracer(dir.path(), &["explain", &illumination, "0", "0", "--json"]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(json["ray"]["hit"].is_null());
    let out = tracer(dir.path(), &["explain", &illumination, "500", "0"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("500x400"));
    // Path mode: the path's light and BSDF samples and their MIS weights.
    let out = tracer(
        dir.path(),
        &[
            "explain",
            &scene("cornell-box.toml"),
            "128",
            "100",
            "--sample",
            "3",
        ],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("light sample") && text.contains("MIS weight"),
        "{text}"
    );
    // Its JSON: each event's `event` and fields beside `throughput` and
    // `added`, as the book lists them (docs/src/reference/explain-json.md).
    let cornell = scene("cornell-box.toml");
    let args = ["explain", &cornell, "128", "100", "--sample", "3", "--json"];
    let out = tracer(dir.path(), &args);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let events = json["events"].as_array().unwrap();
    assert_eq!(events[0]["event"], "vertex", "{}", json["events"]);
    assert!(events[0]["depth"].is_u64(), "{}", events[0]);
    assert!(events
        .iter()
        .all(|e| e["throughput"].is_array() && e["added"].is_array()));
    assert!(events
        .iter()
        .any(|e| e["event"] == "light_sample" && e["weight"].is_f64()));
}

/// Nested glass spheres under `lights` point lights, 16x16: each ray of the
/// tree has every light's terms, and the tree has hundreds of rays.
fn glass_under_lights(dir: &Path, lights: usize) -> &'static str {
    let mut text = String::from(
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nwidth = 16\nheight = 16\n\
         [render]\nmax_depth = 12\n\
         [materials.glass]\ndiffuse = [0.1, 0.1, 0.1]\ntransmittance = 0.9\nfresnel = true\n",
    );
    for radius in [3.0, 2.5, 2.0, 1.5, 1.0] {
        text += &format!(
            "[[objects]]\nsphere = {{ center = [0, 0, 0], radius = {radius} }}\nmaterial = \"glass\"\n"
        );
    }
    for k in 0..lights {
        let (x, y) = ((k % 20) as f32 - 10.0, (k / 20) as f32 - 7.0);
        text += &format!("[[lights]]\nposition = [{x}, {y}, 8]\ncolor = [0.01, 0.01, 0.01]\n");
    }
    std::fs::write(dir.join("glass.toml"), text).unwrap();
    "glass.toml"
}

#[test]
fn explain_keeps_its_tree_within_its_limit_and_says_what_it_left_out() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let glass = glass_under_lights(d, 300);
    // The whole tree has about 17,500 events (3.9 MB of text, 23 MB of
    // JSON); the issue's, of 300 lights too, 387 MB.
    let out = tracer(d, &["explain", glass, "8", "8"]);
    assert!(out.status.success(), "{}", stderr_of(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.stdout.len() < 3_000_000, "{} bytes", out.stdout.len());
    assert!(
        text.contains("note: the tree is cut at its limit of 10000 events")
            && text.contains("--max-events N")
            && text.contains("not kept (the tree's limit"),
        "{}",
        &text[..2000]
    );
    // The pixel is still the whole sample's, and the image's.
    let last = text.lines().last().unwrap();
    assert!(last.contains("the rendered pixel"), "{last}");
    let out = tracer(d, &["explain", glass, "8", "8", "--json"]);
    assert!(out.stdout.len() < 16_000_000, "{} bytes", out.stdout.len());
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["cut"]["kept"], 10_000, "{}", json["cut"]);
    assert!(json["cut"]["left_out"].as_u64().unwrap() > 1000);

    // A smaller limit, and one light's terms alone.
    let out = tracer(d, &["explain", glass, "8", "8", "--max-events", "40"]);
    assert!(out.status.success(), "{}", stderr_of(&out));
    assert!(out.stdout.len() < 20_000, "{} bytes", out.stdout.len());
    assert!(String::from_utf8_lossy(&out.stdout).contains("limit of 40 events"));
    let out = tracer(d, &["explain", glass, "8", "8", "--light", "7"]);
    assert!(out.status.success(), "{}", stderr_of(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("only the terms of lights[7]"),
        "{}",
        &text[..2000]
    );
    assert!(text.contains("lights[7]: ambient") && !text.contains("lights[8]: ambient"));
    assert!(!text.contains("the tree is cut"), "{}", &text[..2000]);
    let out = tracer(d, &["explain", glass, "8", "8", "--light", "300"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr_of(&out).contains("--light 300: the scene has 300 light(s)"));
}

#[test]
fn explain_escapes_control_and_bidi_characters_of_names() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A name that would set the terminal's title and clear the screen,
    // and one that reverses the text after it.
    let scene = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nwidth = 8\nheight = 8\n\
         [materials.\"red\\u001b]0;PWNED\\u0007\\u001b[2J\\u202egnp.\"]\ndiffuse = [1, 0, 0]\n\
         [[objects]]\nsphere = { center = [0, 0, 0], radius = 3 }\n\
         material = \"red\\u001b]0;PWNED\\u0007\\u001b[2J\\u202egnp.\"\n\
         [[lights]]\nposition = [0, 5, 10]\ncolor = [1, 1, 1]\n";
    std::fs::write(d.join("s.toml"), scene).unwrap();
    let out = tracer(d, &["explain", "s.toml", "4", "4"]);
    assert!(out.status.success(), "{}", stderr_of(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    for hidden in ['\u{1b}', '\u{7}', '\u{202e}'] {
        assert!(!text.contains(hidden), "{hidden:?} echoed: {text}");
    }
    assert!(
        text.contains("`red\\u{1b}]0;PWNED\\u{7}\\u{1b}[2J\\u{202e}gnp.`"),
        "{text}"
    );
    let out = tracer(d, &["explain", "s.toml", "4", "4", "--json"]);
    let json = String::from_utf8(out.stdout).unwrap();
    assert!(
        !json.contains('\u{1b}') && !json.contains('\u{202e}'),
        "{json}"
    );
    let value: serde_json::Value = serde_json::from_str(&json).unwrap();
    let names = value["names"].to_string();
    assert!(names.contains("red\\u001b]0;PWNED"), "{names}");
    // The JSON's strings are the names themselves, escaped only in the text.
    assert!(json.contains("\\u202egnp."), "{json}");
}

#[test]
fn an_hdr_output_keeps_values_beyond_rgbe_as_its_largest_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // An emission of 3e38 is accepted; RGBE holds at most about 1.69e38,
    // above which the encoder wrote black.
    std::fs::write(
        d.join("hot.toml"),
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nwidth = 4\nheight = 4\n\
         [materials.hot]\nemission = [3e38, 0, 0]\n\
         [[objects]]\nsphere = { center = [0, 0, 0], radius = 5 }\nmaterial = \"hot\"\n",
    )
    .unwrap();
    let out = tracer(d, &["render", "hot.toml", "-o", "hot.hdr", "--quiet"]);
    let stderr = stderr_of(&out);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("hold values above 1.695e38, the largest a Radiance .hdr holds"),
        "{stderr}"
    );
    let image = image::open(d.join("hot.hdr")).unwrap().to_rgb32f();
    let [r, ..] = image.get_pixel(2, 2).0;
    assert!(r > 1.6e38, "{r:e}: written black");
}

/// An OBJ of `n` triangles (a strip), and a scene placing it `objects`
/// times with an emitting material, in `integrator` mode.
fn emitting_instances(dir: &Path, n: usize, objects: usize, integrator: &str) {
    let mut obj = String::new();
    for k in 0..=n + 1 {
        obj += &format!("v {} {} 0\n", k / 2, k % 2);
    }
    for k in 1..=n {
        obj += &format!("f {} {} {}\n", k, k + 1, k + 2);
    }
    std::fs::write(dir.join("strip.obj"), obj).unwrap();
    let mut scene = format!(
        "[camera]\neye = [0, 0, 50]\nlook_at = [0, 0, 0]\nwidth = 8\nheight = 8\n\
         [render]\nintegrator = \"{integrator}\"\n[materials.lamp]\nemission = [1, 1, 1]\n"
    );
    for k in 0..objects {
        scene += &format!(
            "[[objects]]\nmesh = {{ obj = \"strip.obj\" }}\nmaterial = \"lamp\"\n\
             transform = {{ translate = [0, {k}, 0] }}\n"
        );
    }
    std::fs::write(dir.join("lamps.toml"), scene).unwrap();
}

#[test]
fn instances_of_an_emitting_mesh_count_their_lights_against_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // 1,001 objects placing one mesh of 20,000 emitting triangles: 21,001
    // primitives to trace, but in path mode 20 million lights, one per
    // triangle per object (about 3.8 GB): refused before any is made, at
    // the object that passes the limit.
    emitting_instances(d, 20_000, 1001, "path");
    let out = tracer(d, &["check", "lamps.toml"]);
    let stderr = stderr_of(&out);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("objects[998].mesh")
            && stderr.contains("20000999 primitives")
            && stderr.contains("20000 emitting triangles, each a light of its own in path mode"),
        "{stderr}"
    );
    // In Whitted mode they are no lights: the scene is checked fine, and
    // asking for path mode on the command line is refused the same way.
    emitting_instances(d, 20_000, 1001, "whitted");
    let out = tracer(d, &["check", "lamps.toml"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr_of(&out));
    let args = [
        "render",
        "lamps.toml",
        "--integrator",
        "path",
        "-o",
        "l.png",
    ];
    let out = tracer(d, &args);
    let stderr = stderr_of(&out);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("objects[998].mesh"), "{stderr}");
    assert!(!d.join("l.png").exists());
}
