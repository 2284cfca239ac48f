//! `schema.json` against the real scene files: every key of every file in
//! `scenes/` is described, every file validates (with an independent JSON
//! Schema validator, the `jsonschema` crate), a wrong file does not, and
//! every property of the schema carries a description.

use serde_json::{json, Value};
use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The committed schema, the one editors read (`scene-format`'s unit test
/// keeps it equal to `tracer schema`).
fn schema() -> Value {
    let text = std::fs::read_to_string(repo().join("schema.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// Every `*.toml` file under `scenes/`, its folders too, as JSON values.
fn scene_files() -> Vec<(String, Value)> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "toml") {
                out.push(path);
            }
        }
    }
    let root = repo().join("scenes");
    let mut paths = Vec::new();
    walk(&root, &mut paths);
    paths.sort();
    paths
        .into_iter()
        .map(|path| {
            let name = path.strip_prefix(&root).unwrap().display().to_string();
            let text = std::fs::read_to_string(&path).unwrap();
            let value: Value = toml::from_str(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
            (format!("scenes/{name}"), value)
        })
        .collect()
}

/// The schemas a value may be checked against at `node`: `$ref`s followed,
/// `anyOf`, `oneOf` and `if`'s `then`/`else` opened up.
fn alternatives<'a>(root: &'a Value, node: &'a Value) -> Vec<&'a Value> {
    if let Some(Value::String(reference)) = node.get("$ref") {
        let name = reference
            .strip_prefix("#/$defs/")
            .unwrap_or_else(|| panic!("a reference outside $defs: {reference}"));
        return alternatives(root, &root["$defs"][name]);
    }
    let mut out = Vec::new();
    for key in ["anyOf", "oneOf"] {
        if let Some(Value::Array(branches)) = node.get(key) {
            out.extend(branches.iter().flat_map(|b| alternatives(root, b)));
        }
    }
    for key in ["then", "else"] {
        if let Some(branch) = node.get(key) {
            out.extend(alternatives(root, branch));
        }
    }
    if out.is_empty() {
        out.push(node);
    }
    out
}

/// What a key of an object maps to under `schema`: its property schema and
/// whether it is a named property (which must be described) or an entry of
/// a map (`materials.NAME`, described by the map itself).
fn member<'a>(schema: &'a Value, key: &str) -> Option<(&'a Value, bool)> {
    if let Some(property) = schema.get("properties").and_then(|p| p.get(key)) {
        return Some((property, true));
    }
    match schema.get("additionalProperties") {
        Some(entry @ Value::Object(_)) => Some((entry, false)),
        _ => None,
    }
}

/// Walks `value` alongside `node`, adding to `out` the path of each key the
/// schema does not know or does not describe.
fn undescribed(root: &Value, node: &Value, value: &Value, path: &str, out: &mut Vec<String>) {
    let branches = alternatives(root, node);
    match value {
        Value::Object(map) => {
            // The branch that knows every key of the object (a canvas file
            // is not a 3D scene; an image texture is not a checker).
            let Some(branch) = branches
                .iter()
                .find(|b| map.keys().all(|k| member(b, k).is_some()))
            else {
                out.push(format!("{path}: keys {:?} fit no schema here", keys(map)));
                return;
            };
            for (key, item) in map {
                let (property, named) = member(branch, key).unwrap();
                let here = join(path, key);
                if named && property.get("description").is_none() {
                    out.push(format!("{here}: no description"));
                }
                undescribed(root, property, item, &here, out);
            }
        }
        Value::Array(items) => {
            let Some(schema) = branches.iter().find_map(|b| b.get("items")) else {
                out.push(format!("{path}: a list where the schema has none"));
                return;
            };
            for (i, item) in items.iter().enumerate() {
                undescribed(root, schema, item, &format!("{path}[{i}]"), out);
            }
        }
        _ => {}
    }
}

fn keys(map: &serde_json::Map<String, Value>) -> Vec<&str> {
    map.keys().map(String::as_str).collect()
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

fn undescribed_keys(schema: &Value, scene: &Value) -> Vec<String> {
    let mut out = Vec::new();
    undescribed(schema, schema, scene, "", &mut out);
    out
}

#[test]
fn every_key_of_every_scene_file_is_described() {
    let schema = schema();
    let files = scene_files();
    // The lab's 3D tables and canvas scenes, the scenes beyond it, the bench's.
    assert!(files.len() >= 23, "{} scene files", files.len());
    assert!(files
        .iter()
        .any(|(name, _)| name == "scenes/bench/bunny.toml"));
    assert!(files.iter().any(|(name, _)| name == "scenes/robot.toml"));
    let mut problems = Vec::new();
    for (name, scene) in &files {
        let missing = undescribed_keys(&schema, scene);
        problems.extend(missing.into_iter().map(|p| format!("{name}: {p}")));
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The walk above can fail: a key the schema lacks, and one it has without
/// a description, are both named with their paths.
#[test]
fn the_key_walk_names_unknown_and_undescribed_keys() {
    let schema = schema();
    let robot = json!({
        "canvas": { "width": 10, "colour": [1, 1, 1] },
        "shapes": [{ "group": [{ "circle": { "radius": 1, "centre": [0, 0] } }] }]
    });
    let found = undescribed_keys(&schema, &robot);
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(found[0].starts_with("canvas: keys"), "{found:?}");
    assert!(
        found[1].starts_with("shapes[0].group[0].circle: keys"),
        "{found:?}"
    );

    let mut stripped = schema.clone();
    let circle = &mut stripped["$defs"]["Circle"]["properties"]["radius"];
    circle.as_object_mut().unwrap().remove("description");
    let good = json!({ "canvas": {}, "shapes": [{ "circle": { "radius": 1 } }] });
    assert!(undescribed_keys(&schema, &good).is_empty());
    assert_eq!(
        undescribed_keys(&stripped, &good),
        ["shapes[0].circle.radius: no description"]
    );
}

/// Every property anywhere in the schema, 3D and canvas alike, has a
/// description for an editor to show.
#[test]
fn every_property_of_the_schema_is_described() {
    fn walk(node: &Value, path: &str, out: &mut Vec<String>) {
        match node {
            Value::Object(map) => {
                if let Some(Value::Object(properties)) = map.get("properties") {
                    for (key, property) in properties {
                        if property.get("description").is_none() {
                            out.push(format!("{path}.properties.{key}"));
                        }
                    }
                }
                for (key, child) in map {
                    walk(child, &format!("{path}.{key}"), out);
                }
            }
            Value::Array(items) => {
                for (i, child) in items.iter().enumerate() {
                    walk(child, &format!("{path}[{i}]"), out);
                }
            }
            _ => {}
        }
    }
    let schema = schema();
    let mut missing = Vec::new();
    walk(&schema, "", &mut missing);
    assert!(missing.is_empty(), "no description: {missing:#?}");
    // The walk saw both kinds of file.
    let defs = &schema["$defs"];
    for def in [
        "SceneFile",
        "Camera",
        "Material",
        "CanvasFile",
        "CanvasShape",
        "Circle",
    ] {
        assert!(defs[def]["properties"].is_object(), "{def}");
    }
}

fn validator() -> jsonschema::Validator {
    jsonschema::validator_for(&schema()).unwrap()
}

/// Each error as "instance path: message", for a failure to show.
fn errors(validator: &jsonschema::Validator, value: &Value) -> Vec<String> {
    validator
        .iter_errors(value)
        .map(|e| format!("{}: {e}", e.instance_path()))
        .collect()
}

#[test]
fn every_scene_file_validates_against_the_schema() {
    let validator = validator();
    let mut problems = Vec::new();
    for (name, scene) in scene_files() {
        problems.extend(
            errors(&validator, &scene)
                .into_iter()
                .map(|e| format!("{name}: {e}")),
        );
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

fn scene(name: &str) -> Value {
    let text = std::fs::read_to_string(repo().join("scenes").join(name)).unwrap();
    toml::from_str(&text).unwrap()
}

/// The validator rejects a wrong file, and the error is at the wrong value:
/// the schema checks 2D and 3D files against their own kind.
#[test]
fn the_schema_rejects_wrong_scenes_at_the_wrong_value() {
    let validator = validator();
    let mut robot = scene("robot.toml");
    robot["shapes"][0]["group"][1]["circle"]["radius"] = json!("small");
    let found = errors(&validator, &robot);
    assert!(
        found
            .iter()
            .any(|e| e.starts_with("/shapes/0/group/1/circle/radius:")),
        "{found:?}"
    );

    let mut shadows = scene("shadows.toml");
    shadows["camera"]["fov"] = json!("wide");
    let found = errors(&validator, &shadows);
    assert!(
        found.iter().any(|e| e.starts_with("/camera/fov:")),
        "{found:?}"
    );

    // A 3D key in a canvas file, a canvas key in a 3D file, a range.
    let mut mixed = scene("triangle-2d.toml");
    mixed["lights"] = json!([]);
    assert!(!validator.is_valid(&mixed));
    let mut mixed = scene("texture.toml");
    mixed["shapes"] = json!([]);
    assert!(!validator.is_valid(&mixed));
    let mut negative = scene("robot.toml");
    negative["canvas"]["background"] = json!([0.1, -0.1, 0.1]);
    let found = errors(&validator, &negative);
    assert!(
        found.iter().any(|e| e.starts_with("/canvas/background/1:")),
        "{found:?}"
    );
    // A canvas file still needs its `canvas` table to be one; a 3D file its camera.
    assert!(!validator.is_valid(&json!({ "shapes": [] })));
    assert!(validator.is_valid(&json!({ "canvas": {}, "$schema": "./schema.json" })));
}

/// A file of `tests/include/`, TOML or JSON by its extension.
fn include_fixture(name: &str) -> Value {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/include")
        .join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    if name.ends_with(".json") {
        serde_json::from_str(&text).unwrap()
    } else {
        toml::from_str(&text).unwrap()
    }
}

/// A file a scene includes has neither `camera` nor `canvas`: the same
/// schema (and directive) serves it, every key described.
#[test]
fn included_files_are_described_and_validate() {
    let schema = schema();
    let validator = validator();
    for name in [
        "good/scene.toml",
        "good/lib/common.toml",
        "good/lib/nested.toml",
        "good/lib/more.json",
    ] {
        let file = include_fixture(name);
        assert_eq!(
            undescribed_keys(&schema, &file),
            Vec::<String>::new(),
            "{name}"
        );
        assert_eq!(errors(&validator, &file), Vec::<String>::new(), "{name}");
    }
}

/// The included files with a mistake, each rejected at it: an included file
/// is checked as one, not let through for lacking a camera.
#[test]
fn wrong_included_files_are_rejected_at_the_wrong_value() {
    let validator = validator();
    for (name, at) in [
        (
            "value-in-included/lib/materials.toml",
            "/materials/shiny/shininess:",
        ),
        ("unknown-key-in-included/materials.toml", "/materials/red:"),
        ("several-files/objects.toml", "/objects/0/sphere/radius:"),
        ("json-included/lights.json", "/lights/1/color/1:"),
    ] {
        let found = errors(&validator, &include_fixture(name));
        assert!(found.iter().any(|e| e.starts_with(at)), "{name}: {found:?}");
    }
    // Only the scene file sets the render settings.
    assert!(!validator.is_valid(&json!({ "render": { "samples": 4 } })));
}
