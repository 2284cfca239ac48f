//! The glTF reader: what it makes of the Khronos samples (their numbers
//! against `scenes/khronos/expected.json`, worked out by an independent
//! script: `xtask/peers/gltf_expected.py`), and how it refuses broken files:
//! each at its JSON path, with what was expected, never a panic.

use base64::engine::general_purpose::STANDARD as BASE64;
use base64::Engine;
use scene_format::gltf::{self, glb, GltfData, GltfError, Pick};
use scene_format::images::ImageCache;
use scene_format::source::Folder;
use scene_format::{Budget, GltfPick};
use std::path::{Path, PathBuf};

fn khronos(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/khronos")
        .join(name)
}

fn read_path(path: &Path, pick: &Pick) -> Result<GltfData, GltfError> {
    gltf::read(
        &Folder::new(),
        path,
        pick,
        &mut Budget::default(),
        &mut ImageCache::default(),
    )
}

fn read(name: &str) -> GltfData {
    read_path(&khronos(name), &Pick::default()).unwrap_or_else(|e| panic!("{name}: {e:?}"))
}

/// A glTF file of `json` written to a folder (with `files` beside it),
/// read; its error's path and message.
fn fails(json: &str, files: &[(&str, &[u8])]) -> (String, String) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.gltf");
    std::fs::write(&path, json).unwrap();
    for (name, bytes) in files {
        std::fs::write(dir.path().join(name), bytes).unwrap();
    }
    let e = read_path(&path, &Pick::default()).expect_err("a broken file");
    (e.failure.path.to_string(), e.failure.message)
}

/// A triangle's file: three positions in a 36-byte buffer (as base64),
/// with `extra` JSON members added at the top level.
fn triangle(accessor: &str, view: &str, buffer: &str) -> String {
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
        "accessors": [{accessor}], "bufferViews": [{view}], "buffers": [{buffer}]}}"#
    )
}

const POSITIONS: &str = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";
const ACCESSOR: &str = r#"{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}"#;
const VIEW: &str = r#"{"buffer": 0, "byteLength": 36}"#;

fn buffer() -> String {
    format!(r#"{{"byteLength": 36, "uri": "data:application/octet-stream;base64,{POSITIONS}"}}"#)
}

/// POSITIONS' bytes, decoded apart from the reader (by base64's strict
/// standard engine, not the reader's lenient one).
fn positions() -> Vec<u8> {
    BASE64.decode(POSITIONS).unwrap()
}

#[test]
fn a_well_formed_triangle_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.gltf");
    std::fs::write(&path, triangle(ACCESSOR, VIEW, &buffer())).unwrap();
    let data = read_path(&path, &Pick::default()).unwrap();
    assert_eq!(data.triangles(), 1);
    assert_eq!(data.bounds(), Some(([0.0; 3], [1.0, 1.0, 0.0])));
}

#[test]
fn the_same_triangle_reads_from_a_glb_and_a_bin_file() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = positions();
    let glb_path = dir.path().join("t.glb");
    let json = triangle(ACCESSOR, VIEW, r#"{"byteLength": 36}"#);
    std::fs::write(&glb_path, glb::assemble(&json, Some(&bytes))).unwrap();
    let data = read_path(&glb_path, &Pick::default()).unwrap();
    assert_eq!(data.bounds(), Some(([0.0; 3], [1.0, 1.0, 0.0])));
    let gltf_path = dir.path().join("t.gltf");
    let json = triangle(
        ACCESSOR,
        VIEW,
        r#"{"byteLength": 36, "uri": "t%20data.bin"}"#,
    );
    std::fs::write(&gltf_path, json).unwrap();
    std::fs::write(dir.path().join("t data.bin"), &bytes).unwrap();
    let data = read_path(&gltf_path, &Pick::default()).unwrap();
    assert_eq!(data.triangles(), 1);
}

#[test]
fn an_accessor_past_its_view_is_refused_before_reading() {
    let accessor = r#"{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3"}"#;
    let (path, message) = fails(&triangle(accessor, VIEW, &buffer()), &[]);
    assert_eq!(path, "meshes[0].primitives[0].attributes.POSITION");
    assert!(
        message.starts_with("accessors[0]: 4 elements of 12 bytes"),
        "{message}"
    );
    assert!(
        message.contains("past the end of bufferViews[0] (36 bytes)"),
        "{message}"
    );
}

#[test]
fn counts_that_would_need_gigabytes_are_refused_before_allocating() {
    for count in ["1152921504606846976", "4000000000"] {
        let accessor = format!(
            r#"{{"bufferView": 0, "componentType": 5126, "count": {count}, "type": "VEC3"}}"#
        );
        let (path, message) = fails(&triangle(&accessor, VIEW, &buffer()), &[]);
        assert_eq!(path, "meshes[0].primitives[0].attributes.POSITION");
        assert!(message.contains("expected at most"), "{message}");
    }
    // Within the cap but past the view: refused by its range.
    let accessor = r#"{"bufferView": 0, "componentType": 5126, "count": 50000000, "type": "VEC3"}"#;
    let (_, message) = fails(&triangle(accessor, VIEW, &buffer()), &[]);
    assert!(
        message.contains("past the end of bufferViews[0]"),
        "{message}"
    );
}

#[test]
fn a_view_past_its_buffer_is_refused() {
    let view = r#"{"buffer": 0, "byteOffset": 12, "byteLength": 36}"#;
    let (path, message) = fails(&triangle(ACCESSOR, view, &buffer()), &[]);
    assert_eq!(path, "meshes[0].primitives[0].attributes.POSITION");
    assert!(
        message.contains(
            "bufferViews[0] runs from byte 12 for 36 bytes, past the end of buffers[0] (36 bytes)"
        ),
        "{message}"
    );
}

#[test]
fn a_buffer_shorter_than_it_claims_is_refused() {
    let buffer = format!(
        r#"{{"byteLength": 48, "uri": "data:application/octet-stream;base64,{POSITIONS}"}}"#
    );
    let (path, message) = fails(&triangle(ACCESSOR, VIEW, &buffer), &[]);
    assert_eq!(path, "buffers[0].byteLength");
    assert!(
        message.contains("claims 48 bytes but holds 36"),
        "{message}"
    );
}

#[test]
fn a_missing_bin_file_is_named() {
    let (path, message) = fails(
        &triangle(ACCESSOR, VIEW, r#"{"byteLength": 36, "uri": "gone.bin"}"#),
        &[],
    );
    assert_eq!(path, "buffers[0].uri");
    assert!(message.starts_with("cannot read `gone.bin`"), "{message}");
}

#[test]
fn a_texture_s_missing_texture_image_or_view_is_located() {
    // The triangle with a base colour texture of `textures` and `images`.
    let textured = |textures: serde_json::Value, images: serde_json::Value| {
        let mut doc: serde_json::Value =
            serde_json::from_str(&triangle(ACCESSOR, VIEW, &buffer())).unwrap();
        doc["meshes"][0]["primitives"][0]["material"] = 0.into();
        doc["materials"] =
            serde_json::json!([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]);
        doc["textures"] = textures;
        doc["images"] = images;
        fails(&doc.to_string(), &[])
    };
    use serde_json::json;
    let cases = [
        (
            textured(json!([]), json!([])),
            "materials[0].pbrMetallicRoughness.baseColorTexture.index",
            "expected an index of `textures`, but the file has none; found 0",
        ),
        (
            textured(json!([{"source": 2}]), json!([{"uri": "a.png"}])),
            "textures[0].source",
            "expected an index of `images` (0 to 0), found 2",
        ),
        (
            textured(json!([{"source": 0}]), json!([{"bufferView": 5}])),
            "images[0].bufferView",
            "expected an index of `bufferViews` (0 to 0), found 5",
        ),
    ];
    for ((path, message), want_path, want_message) in cases {
        assert_eq!(path, want_path, "{message}");
        assert_eq!(message, want_message, "{path}");
    }
}

#[test]
fn a_data_uri_that_is_not_base64_is_refused() {
    let buffer = r#"{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAA*AAA"}"#;
    let (path, message) = fails(&triangle(ACCESSOR, VIEW, buffer), &[]);
    assert_eq!(path, "buffers[0].uri");
    assert!(message.contains("not base64: character 5"), "{message}");
}

#[test]
fn an_index_past_the_vertices_is_refused() {
    let json = r#"{"asset": {"version": "2.0"}, "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                      {"bufferView": 1, "componentType": 5121, "count": 3, "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 1, "byteLength": 3}],
        "buffers": [BUFFER, {"byteLength": 3, "uri": "data:application/octet-stream;base64,AAEH"}]}"#
        .replace("BUFFER", &buffer());
    let (path, message) = fails(&json, &[]);
    assert_eq!(path, "meshes[0].primitives[0].indices");
    assert_eq!(
        message,
        "index 2 is 7, past the 3 vertices of the primitive's POSITION; expected indices below 3"
    );
}

#[test]
fn an_accessor_index_out_of_range_is_refused() {
    let json = triangle(ACCESSOR, VIEW, &buffer()).replace(r#""POSITION": 0"#, r#""POSITION": 9"#);
    let (path, message) = fails(&json, &[]);
    assert_eq!(path, "meshes[0].primitives[0].attributes.POSITION");
    assert_eq!(
        message,
        "expected an index of `accessors` (0 to 0), found 9"
    );
}

#[test]
fn a_wrong_type_is_reported_at_its_json_path() {
    let json = triangle(ACCESSOR, VIEW, &buffer()).replace(r#""mesh": 0"#, r#""mesh": "zero""#);
    let (path, message) = fails(&json, &[]);
    assert_eq!(path, "nodes[0].mesh");
    assert!(message.contains("expected glTF 2.0's JSON"), "{message}");
}

#[test]
fn a_required_extension_not_read_is_an_error() {
    let json = triangle(ACCESSOR, VIEW, &buffer()).replacen(
        '{',
        r#"{"extensionsRequired": ["KHR_draco_mesh_compression"], "#,
        1,
    );
    let (path, message) = fails(&json, &[]);
    assert_eq!(path, "extensionsRequired[0]");
    assert!(
        message.contains("`KHR_draco_mesh_compression`"),
        "{message}"
    );
}

/// The triangle's file with material `material` (JSON) on its primitive.
fn with_material(material: &str) -> String {
    triangle(ACCESSOR, VIEW, &buffer())
        .replace(r#"{"POSITION": 0}}"#, r#"{"POSITION": 0}, "material": 0}"#)
        .replacen('{', &format!(r#"{{"materials": [{material}], "#), 1)
}

#[test]
fn alpha_modes_become_a_cutoff_on_the_texture_s_alpha() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.gltf");
    // MASK compares factor x texel with the cutoff: the texel alone with
    // cutoff / factor; BLEND is MASK at 0.5; OPAQUE and a cutoff of 0 cut
    // nothing; a factor of 0 cuts everything.
    for (material, cutoff) in [
        (r#"{"alphaMode": "MASK"}"#, Some(0.5)),
        (r#"{"alphaMode": "MASK", "alphaCutoff": 0.3}"#, Some(0.3)),
        (
            r#"{"alphaMode": "MASK", "alphaCutoff": 0.3, "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.5]}}"#,
            Some(0.6),
        ),
        (r#"{"alphaMode": "BLEND", "alphaCutoff": 0.9}"#, Some(0.5)),
        (r#"{"alphaMode": "OPAQUE", "alphaCutoff": 0.9}"#, None),
        (r#"{"alphaMode": "MASK", "alphaCutoff": 0}"#, None),
        (
            r#"{"alphaMode": "MASK", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0]}}"#,
            Some(f32::INFINITY),
        ),
    ] {
        std::fs::write(&path, with_material(material)).unwrap();
        let data = read_path(&path, &Pick::default()).unwrap();
        assert_eq!(data.materials[0].alpha_cutoff, cutoff, "{material}");
        let blend = data.warnings.iter().any(|(at, message)| {
            *at == "materials[0].alphaMode" && message.contains("BLEND is read as MASK")
        });
        assert_eq!(blend, material.contains("BLEND"), "{material}");
    }
}

#[test]
fn a_wrong_alpha_mode_or_cutoff_is_refused_at_its_key() {
    let (path, message) = fails(&with_material(r#"{"alphaMode": "CLIP"}"#), &[]);
    assert_eq!(path, "materials[0].alphaMode");
    assert!(message.contains(r#"found "CLIP""#), "{message}");
    let mask = r#"{"alphaMode": "MASK", "alphaCutoff": -0.5}"#;
    let (path, message) = fails(&with_material(mask), &[]);
    assert_eq!(path, "materials[0].alphaCutoff");
    assert!(
        message.contains("expected a number >= 0, found -0.5"),
        "{message}"
    );
}

#[test]
fn a_cycle_of_nodes_is_refused() {
    let json = triangle(ACCESSOR, VIEW, &buffer()).replace(
        r#""nodes": [{"mesh": 0}]"#,
        r#""nodes": [{"mesh": 0, "children": [1]}, {"children": [0]}]"#,
    );
    let (path, message) = fails(&json, &[]);
    assert!(path.starts_with("nodes["), "{path}");
    assert!(
        message.contains("cycle") || message.contains("already a child"),
        "{message}"
    );
}

#[test]
fn broken_glb_files_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let json = triangle(ACCESSOR, VIEW, r#"{"byteLength": 36}"#);
    let whole = glb::assemble(&json, Some(&positions()));
    let cases: Vec<(Vec<u8>, &str)> = vec![
        (whole[..whole.len() - 10].to_vec(), "truncated"),
        ([b"glTX".as_slice(), &whole[4..]].concat(), "magic `glTF`"),
        (whole[..8].to_vec(), "12-byte header"),
        (glb::assemble(&json, None), "expected a `uri`"),
    ];
    for (bytes, expected) in cases {
        let path = dir.path().join("t.glb");
        std::fs::write(&path, &bytes).unwrap();
        let e = read_path(&path, &Pick::default()).expect_err(expected);
        assert!(
            e.message().contains(expected),
            "{expected}: {}",
            e.message()
        );
    }
}

#[test]
fn a_picked_scene_or_node_must_exist() {
    let path = khronos("Box.gltf");
    let pick = Pick {
        node: Some(GltfPick::Name("Mesh".into())),
        ..Pick::default()
    };
    let e = read_path(&path, &pick).expect_err("no such node");
    assert!(
        e.message().contains("no node named `Mesh`"),
        "{}",
        e.message()
    );
    let pick = Pick {
        scene: Some(GltfPick::Index(3)),
        ..Pick::default()
    };
    let e = read_path(&path, &pick).expect_err("no such scene");
    assert_eq!(e.message(), "there is no scene 3: expected one of 0");
    // Node 1 alone, where its parent (turning +Z up to +Y up) places it.
    let pick = Pick {
        node: Some(GltfPick::Index(1)),
        ..Pick::default()
    };
    let data = read_path(&path, &pick).unwrap();
    assert_eq!(data.placed.len(), 1);
    // Column 1 (where +Y goes) is -Z: the parent turns the model.
    assert_eq!(data.placed[0].matrix[4..8], [0.0, 0.0, -1.0, 0.0]);
}

#[test]
fn a_mesh_used_by_two_nodes_is_read_once() {
    let data = read("SimpleMeshes.gltf");
    assert_eq!(data.placed.len(), 2);
    assert_eq!(data.meshes.iter().flatten().count(), 1);
    assert_eq!(data.triangles(), 2);
}

#[test]
fn a_texture_is_read_with_its_image_and_sampler() {
    let data = read("BoxTextured.gltf");
    let texture = data.materials[0].texture.as_ref().expect("a texture");
    let scene_format::TextureRef::Image(image) = texture else {
        panic!("{texture:?}");
    };
    let pixels = image.data.as_ref().expect("decoded");
    assert_eq!((pixels.width, pixels.height), (211, 211));
    assert_eq!(image.wrap, scene_format::Wrap::Repeat);
}

/// The samples' triangle counts, bounds and camera poses against
/// `scenes/khronos/expected.json`, made by `xtask/peers/gltf_expected.py`
/// from the spec alone (Python's standard library, no glTF package).
#[test]
fn the_samples_match_numbers_worked_out_apart() {
    let text = std::fs::read_to_string(khronos("expected.json")).unwrap();
    let expected: serde_json::Value = serde_json::from_str(&text).unwrap();
    let near =
        |a: f64, b: f64, what: &str| assert!((a - b).abs() < 1e-5, "{what}: {a} against {b}");
    let vec3 =
        |v: &serde_json::Value| -> [f64; 3] { std::array::from_fn(|k| v[k].as_f64().unwrap()) };
    let samples = expected.as_object().unwrap();
    assert_eq!(samples.len(), 4, "{:?}", samples.keys());
    for (name, e) in samples {
        let data = read(name);
        assert_eq!(
            data.triangles() as u64,
            e["triangles"].as_u64().unwrap(),
            "{name}"
        );
        let (lo, hi) = data.bounds().unwrap();
        for k in 0..3 {
            near(
                f64::from(lo[k]),
                vec3(&e["bounds"]["min"])[k],
                &format!("{name} min"),
            );
            near(
                f64::from(hi[k]),
                vec3(&e["bounds"]["max"])[k],
                &format!("{name} max"),
            );
        }
        let cameras = e["cameras"].as_array().unwrap();
        assert_eq!(data.cameras.len(), cameras.len(), "{name}");
        for (c, want) in data.cameras.iter().zip(cameras) {
            let c = &c.camera;
            for (key, got) in [("eye", c.eye), ("look_at", c.look_at), ("up", c.up)] {
                for (g, w) in got.iter().zip(vec3(&want[key])) {
                    near(f64::from(*g), w, &format!("{name} {key}"));
                }
            }
            let aspect = f64::from(c.width) / f64::from(c.height);
            let want_aspect = want["aspect"].as_f64().unwrap();
            assert!(
                (aspect - want_aspect).abs() < 2.0 / f64::from(c.height),
                "{name}"
            );
            match (want.get("fov"), want.get("view_width")) {
                (Some(fov), _) => near(f64::from(c.fov), fov.as_f64().unwrap(), "fov"),
                (_, Some(w)) => near(
                    f64::from(c.view_width.unwrap()),
                    w.as_f64().unwrap(),
                    "width",
                ),
                _ => panic!("{want}"),
            }
            assert_eq!(c.handedness, scene_format::Handedness::Right);
        }
    }
}
