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

#[test]
fn threads_change_nothing_in_the_image() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene("reflectance2.toml");
    for (threads, out) in [("1", "one.png"), ("2", "two.png")] {
        let run = tracer(dir.path(), &["render", &s, "--threads", threads, "-o", out]);
        assert!(run.status.success());
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(
            stderr.contains(&format!("on {threads} threads")),
            "{stderr}"
        );
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
