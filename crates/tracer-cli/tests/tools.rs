//! The commands around the renderer: completions, new, convert.

mod common;

use common::tracer;
use scene_format::SceneKind;
use std::path::{Path, PathBuf};
use std::process::Output;

fn stdout_of(out: &Output) -> String {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout.clone()).unwrap()
}

/// The commands, as the README's table lists them.
const COMMANDS: [&str; 10] = [
    "new",
    "convert",
    "render",
    "calib-chart",
    "gamma",
    "check",
    "watch",
    "pack",
    "schema",
    "completions",
];

#[test]
fn bash_completions_offer_every_command_and_the_render_options() {
    let dir = tempfile::tempdir().unwrap();
    let script = stdout_of(&tracer(dir.path(), &["completions", "bash"]));
    assert!(
        script.contains("complete -F _tracer"),
        "registers the function"
    );
    // bash completes the first word from one list of the subcommands.
    let top = script
        .lines()
        .find(|l| l.contains("opts=") && l.contains("render"))
        .expect("the top-level word list");
    for command in COMMANDS {
        assert!(
            top.split([' ', '"']).any(|w| w == command),
            "{command}: {top}"
        );
    }
    for option in ["--samples", "--bit-depth", "--aov", "ray-dir-x"] {
        assert!(script.contains(option), "{option}");
    }
}

#[test]
fn every_shell_gets_a_script_naming_the_commands() {
    let dir = tempfile::tempdir().unwrap();
    for shell in ["bash", "zsh", "fish", "powershell", "elvish"] {
        let script = stdout_of(&tracer(dir.path(), &["completions", shell]));
        for command in COMMANDS {
            assert!(script.contains(command), "{shell}: {command}");
        }
    }
    let out = tracer(dir.path(), &["completions", "tcsh"]);
    assert_eq!(out.status.code(), Some(2), "an unknown shell is bad input");
}

/// `dir`'s files and folders copied into `to`, so converted scenes sit
/// beside the meshes and images they name.
fn copy_tree(dir: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let target = to.join(path.file_name().unwrap());
        if path.is_dir() {
            copy_tree(&path, &target);
        } else {
            std::fs::copy(&path, &target).unwrap();
        }
    }
}

fn scenes_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// Every scene file under `dir`, its path relative to `dir`.
fn scene_files(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    for sub in ["", "bench"] {
        for entry in std::fs::read_dir(dir.join(sub)).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "toml") {
                found.push(Path::new(sub).join(path.file_name().unwrap()));
            }
        }
    }
    found.sort();
    found
}

fn load(path: &Path) -> SceneKind {
    scene_format::load_any(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// `kind` with its `$schema` and the directive it names, if any: a TOML
/// scene's `#:schema` directive is a comment its load leaves out, the JSON
/// member it becomes is read (the tracer ignores both).
fn schema_apart(kind: SceneKind) -> (SceneKind, Option<String>) {
    match kind {
        SceneKind::Scene3d(mut f) => {
            let schema = f.schema.take();
            (SceneKind::Scene3d(f), schema)
        }
        SceneKind::Canvas(mut c) => {
            let schema = c.schema.take();
            (SceneKind::Canvas(c), schema)
        }
    }
}

/// The path a TOML scene's `#:schema` directive names, if it has one.
fn directive(toml: &Path) -> Option<String> {
    let text = std::fs::read_to_string(toml).unwrap();
    let first = text.lines().next()?;
    Some(first.strip_prefix("#:schema")?.trim().to_string())
}

fn succeeds(out: Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn every_scene_converts_to_json_and_back_with_every_value() {
    let dir = tempfile::tempdir().unwrap();
    copy_tree(&scenes_dir(), dir.path());
    let files = scene_files(dir.path());
    assert!(files.len() >= 20, "{files:?}");
    for file in files {
        let toml = dir.path().join(&file);
        let json = toml.with_extension("json");
        let back = toml.with_file_name("back.toml");
        let name = |p: &Path| p.to_str().unwrap().to_string();
        succeeds(tracer(
            dir.path(),
            &["convert", &name(&toml), "-o", &name(&json)],
        ));
        succeeds(tracer(
            dir.path(),
            &["convert", &name(&json), "-o", &name(&back)],
        ));
        let original = load(&toml);
        let (from_json, schema) = schema_apart(load(&json));
        assert_eq!(from_json, original, "{}", file.display());
        assert_eq!(schema, directive(&toml), "{}: $schema", file.display());
        assert_eq!(load(&back), original, "{} and back", file.display());
        assert_eq!(
            directive(&back),
            directive(&toml),
            "{}: #:schema",
            file.display()
        );
        let text = std::fs::read_to_string(&json).unwrap();
        assert!(
            text.trim_start().starts_with('{'),
            "{}: JSON",
            file.display()
        );
    }
}

#[test]
fn a_converted_scene_renders_the_same_image() {
    let dir = tempfile::tempdir().unwrap();
    let toml = scenes_dir().join("reflectance2.toml");
    let toml = toml.to_str().unwrap();
    succeeds(tracer(dir.path(), &["convert", toml]));
    assert!(
        dir.path().join("reflectance2.json").is_file(),
        "default name"
    );
    succeeds(tracer(dir.path(), &["render", toml, "-o", "a.png", "-q"]));
    succeeds(tracer(
        dir.path(),
        &["render", "reflectance2.json", "-o", "b.png", "-q"],
    ));
    let a = image::open(dir.path().join("a.png")).unwrap().to_rgb8();
    let b = image::open(dir.path().join("b.png")).unwrap().to_rgb8();
    assert_eq!(a.dimensions(), (500, 400));
    assert!(a == b, "the images differ");
}

#[test]
fn schema_directive_and_member_convert_into_each_other() {
    let dir = tempfile::tempdir().unwrap();
    let text = "#:schema ../schema.json\n[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n";
    std::fs::write(dir.path().join("s.toml"), text).unwrap();
    succeeds(tracer(dir.path(), &["convert", "s.toml", "-o", "s.json"]));
    let text = std::fs::read_to_string(dir.path().join("s.json")).unwrap();
    assert!(
        text.contains("\n    \"eye\": [0, 0, 10],\n"),
        "a vector on one line: {text}"
    );
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(json["$schema"], "../schema.json");
    assert_eq!(json["camera"]["eye"], serde_json::json!([0, 0, 10]));
    succeeds(tracer(dir.path(), &["convert", "s.json", "-o", "t.toml"]));
    let back = std::fs::read_to_string(dir.path().join("t.toml")).unwrap();
    assert_eq!(back.lines().next(), Some("#:schema ../schema.json"));
    assert!(!back.contains("$schema"), "{back}");
}

/// A canvas names its schema as a 3D scene does: the JSON file keeps the
/// member, and the tracer reads past it.
#[test]
fn a_canvas_keeps_its_schema_directive_in_json() {
    let dir = tempfile::tempdir().unwrap();
    let text = "#:schema ../schema.json\n[canvas]\nwidth = 20\nheight = 10\n";
    std::fs::write(dir.path().join("c.toml"), text).unwrap();
    succeeds(tracer(dir.path(), &["convert", "c.toml", "-o", "c.json"]));
    let text = std::fs::read_to_string(dir.path().join("c.json")).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(json["$schema"], "../schema.json");
    succeeds(tracer(dir.path(), &["check", "c.json"]));
}

#[test]
fn a_bad_scene_is_reported_not_converted() {
    let dir = tempfile::tempdir().unwrap();
    let text = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nfov = 0\n";
    std::fs::write(dir.path().join("s.toml"), text).unwrap();
    let out = tracer(dir.path(), &["convert", "s.toml"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("s.toml:4:7"), "{err}");
    assert!(!dir.path().join("s.json").exists());
    let out = tracer(
        dir.path(),
        &["convert", &scene_path("shadows.toml"), "-o", "s.yaml"],
    );
    assert_eq!(out.status.code(), Some(2), "unknown output format");
}

fn scene_path(name: &str) -> String {
    scenes_dir().join(name).to_str().unwrap().to_string()
}

#[test]
fn the_starter_scene_renders_a_red_sphere_on_a_grey_floor() {
    let dir = tempfile::tempdir().unwrap();
    succeeds(tracer(dir.path(), &["new", "scene.toml"]));
    let text = std::fs::read_to_string(dir.path().join("scene.toml")).unwrap();
    assert_eq!(text.lines().next(), Some("#:schema ./schema.json"));
    // The schema it names is written beside it, and not over one there.
    let schema = std::fs::read_to_string(dir.path().join("schema.json")).unwrap();
    assert_eq!(schema, scene_format::schema::json_schema());
    std::fs::write(dir.path().join("schema.json"), "mine").unwrap();
    succeeds(tracer(dir.path(), &["new", "other.toml"]));
    assert_eq!(
        std::fs::read_to_string(dir.path().join("schema.json")).unwrap(),
        "mine"
    );
    succeeds(tracer(dir.path(), &["render", "scene.toml", "-q"]));
    let image = image::open(dir.path().join("scene.png")).unwrap().to_rgb8();
    assert_eq!(image.dimensions(), (640, 480));
    // The centre ray passes through look_at (0, 0.5, 0), inside the sphere.
    let centre = image.get_pixel(320, 240).0;
    assert!(centre[0] > 2 * centre[1].max(centre[2]), "red: {centre:?}");
    // The top row looks 10 degrees above the horizon, at the background
    // (0.05, 0.07, 0.12), encoded with gamma 2.2: c^(1/2.2) * 255.
    let top = image.get_pixel(320, 2).0;
    for (got, linear) in top.iter().zip([0.05f32, 0.07, 0.12]) {
        let expected = (linear.powf(1.0 / 2.2) * 255.0) as i32;
        assert!((*got as i32 - expected).abs() <= 1, "{top:?}");
    }
    // The bottom left corner meets the floor, away from the sphere's
    // shadow and reflection: lit grey (a little of the sky reflected).
    let floor = image.get_pixel(40, 475).0;
    let spread = floor.iter().max().unwrap() - floor.iter().min().unwrap();
    assert!(floor[0] > 100 && spread <= 12, "{floor:?}");
}

#[test]
fn new_never_overwrites_and_writes_json_too() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("mine.toml"), "keep").unwrap();
    let out = tracer(dir.path(), &["new", "mine.toml"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        std::fs::read_to_string(dir.path().join("mine.toml")).unwrap(),
        "keep"
    );
    assert_eq!(
        tracer(dir.path(), &["new", "x.yaml"]).status.code(),
        Some(2)
    );
    succeeds(tracer(dir.path(), &["new", "a.toml"]));
    succeeds(tracer(dir.path(), &["new", "a.json"]));
    let (SceneKind::Scene3d(toml), SceneKind::Scene3d(mut json)) = (
        load(&dir.path().join("a.toml")),
        load(&dir.path().join("a.json")),
    ) else {
        panic!("3D scenes expected");
    };
    assert_eq!(json.schema.take().as_deref(), Some("./schema.json"));
    assert_eq!(json, toml);
}

#[test]
fn convert_of_a_packed_scene_is_exit_2_saying_so() {
    let dir = tempfile::tempdir().unwrap();
    let boxes = scenes_dir().join("boxes.toml");
    let packed = tracer(
        dir.path(),
        &["pack", boxes.to_str().unwrap(), "-o", "b.zip"],
    );
    assert!(packed.status.success());
    for args in [
        &["convert", "b.zip"][..],
        &["convert", "b.zip", "-o", "b.json"],
    ] {
        let out = tracer(dir.path(), args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let message = String::from_utf8_lossy(&out.stderr);
        assert!(
            message.contains("b.zip: a packed scene (zip archive) is not converted"),
            "{message}"
        );
        assert!(!message.contains("UTF-8"), "{message}");
        assert!(!dir.path().join("b.json").exists());
    }
}
