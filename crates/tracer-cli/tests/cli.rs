//! The `tracer` binary as a user runs it.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn tracer(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tracer"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run tracer")
}

fn scene(name: &str) -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    p.to_str().unwrap().to_string()
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
    let out = tracer(dir.path(), &["render", &s, "--gamma", "0"]);
    assert_eq!(out.status.code(), Some(2));
}
