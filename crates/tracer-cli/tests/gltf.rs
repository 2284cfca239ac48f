//! glTF files at the command line: `check --json`'s fixed keys, a broken
//! file's exit status, `convert` to a scene that renders, `pack` with the
//! file's .bin and image.

use base64::engine::general_purpose::STANDARD as BASE64;
use base64::Engine;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn tracer(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tracer"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

fn khronos(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/khronos")
        .join(name)
        .canonicalize()
        .unwrap()
}

#[test]
fn check_json_gives_triangles_and_bounds_in_the_files_coordinates() {
    let dir = tempfile::tempdir().unwrap();
    let model = khronos("SimpleMeshes.gltf");
    let out = tracer(dir.path(), &["check", "--json", model.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let line: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(line["triangles"], 2);
    assert_eq!(line["bounds"]["min"], serde_json::json!([0.0, 0.0, 0.0]));
    assert_eq!(line["bounds"]["max"], serde_json::json!([2.0, 1.0, 0.0]));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("2 objects, 2 triangles, 0 lights, 0 cameras"),
        "{stderr}"
    );
}

#[test]
fn a_broken_file_is_bad_input_at_its_json_path() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(khronos("Cameras.gltf")).unwrap();
    let broken = text.replacen("\"count\" : 4,", "\"count\" : 40,", 1);
    assert_ne!(broken, text);
    std::fs::write(dir.path().join("m.gltf"), broken).unwrap();
    for command in ["check", "render"] {
        let out = tracer(dir.path(), &[command, "m.gltf"]);
        assert_eq!(out.status.code(), Some(2), "{command}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            stderr.contains("meshes[0].primitives[0].attributes.POSITION"),
            "{stderr}"
        );
        assert!(stderr.contains("m.gltf:47:"), "{stderr}");
    }
    assert!(!dir.path().join("m.png").exists());
}

#[test]
fn convert_writes_a_scene_that_holds_the_model_and_renders() {
    let dir = tempfile::tempdir().unwrap();
    let model = khronos("Box.gltf");
    let out = tracer(
        dir.path(),
        &["convert", model.to_str().unwrap(), "-o", "box.toml"],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(dir.path().join("box.toml")).unwrap();
    let scene: toml::Table = toml::from_str(&text).unwrap();
    assert_eq!(scene["render"]["integrator"].as_str(), Some("path"));
    assert_eq!(scene["camera"]["handedness"].as_str(), Some("right"));
    assert!(text.contains("[objects.gltf]"), "{text}");
    let out = tracer(dir.path(), &["check", "box.toml"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn pack_keeps_the_bin_file_and_the_image() {
    let dir = tempfile::tempdir().unwrap();
    // BoxTextured with its buffer and image as files beside it.
    let text = std::fs::read_to_string(khronos("BoxTextured.gltf")).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    // A data URI's bytes, decoded apart from the reader.
    let payload = |uri: &serde_json::Value| {
        let text = uri.as_str().unwrap().split(',').nth(1).unwrap();
        BASE64.decode(text).unwrap()
    };
    let (image, buffer) = (
        payload(&doc["images"][0]["uri"]),
        payload(&doc["buffers"][0]["uri"]),
    );
    doc["images"][0]["uri"] = "box%20texture.png".into();
    doc["buffers"][0]["uri"] = "box.bin".into();
    std::fs::write(dir.path().join("box.gltf"), doc.to_string()).unwrap();
    std::fs::write(dir.path().join("box texture.png"), image).unwrap();
    std::fs::write(dir.path().join("box.bin"), buffer).unwrap();
    let out = tracer(dir.path(), &["pack", "box.gltf", "-o", "box.zip"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let file = std::fs::File::open(dir.path().join("box.zip")).unwrap();
    let mut names: Vec<String> = zip::ZipArchive::new(file)
        .unwrap()
        .file_names()
        .map(String::from)
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["box texture.png", "box.bin", "box.gltf", "tracer-pack.toml"]
    );
    let out = tracer(dir.path(), &["check", "box.zip"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
