//! The JSON Schema of scene files, for editors (completion, checking as
//! you type). Derived from the serde models, so it cannot drift from them:
//! one schema for both kinds of file, a 3D scene or a 2D canvas.

use crate::canvas::CanvasFile;
use crate::include::IncludedFile;
use crate::model::SceneFile;
use serde_json::{json, Value};

/// The schema as pretty-printed JSON.
pub fn json_schema() -> String {
    let mut value = schema_value();
    drop_null(&mut value);
    describe_variant_keys(&mut value);
    tidy_defaults(&mut value);
    // Serialising a `serde_json::Value` cannot fail.
    serde_json::to_string_pretty(&value).expect("a schema is plain JSON")
}

/// A file with a top-level `canvas` key is a canvas scene, one with a
/// `camera` a 3D scene (as `load_any` decides), one with neither a file a
/// 3D scene includes. `if`/`then`/`else` rather than `oneOf`: an editor
/// then reports a mistake against the one kind the file is, instead of
/// "valid under none of the alternatives".
fn schema_value() -> Value {
    let mut generator = schemars::generate::SchemaSettings::default().into_generator();
    let scene = generator.subschema_for::<SceneFile>();
    let canvas = generator.subschema_for::<CanvasFile>();
    let included = generator.subschema_for::<IncludedFile>();
    let meta = generator.settings().meta_schema.clone();
    let definitions = generator.take_definitions(true);
    json!({
        "$schema": meta,
        "title": "tracer scene file",
        "description": "A 3D scene (`camera`, `render`, `lights`, `materials`, \
            `objects`, `include`); with a top-level `canvas` table, a 2D canvas \
            scene (`canvas`, `shapes`); with neither `canvas` nor `camera`, a file \
            a 3D scene includes (`include`, `materials`, `lights`, `objects`).",
        "type": "object",
        "if": { "required": ["canvas"] },
        "then": canvas,
        "else": {
            "if": { "required": ["camera"] },
            "then": scene,
            "else": included,
        },
        "$defs": definitions,
    })
}

/// An enum variant written as a one-key table (`{ translate = [..] }`, an
/// alternative of a `oneOf`) has its documentation on the table; editors
/// show a key's own description, so it is copied onto the key.
fn describe_variant_keys(value: &mut Value) {
    match value {
        Value::Object(map) => {
            if let Some(Value::Array(variants)) = map.get_mut("oneOf") {
                variants.iter_mut().for_each(describe_the_one_key);
            }
            map.values_mut().for_each(describe_variant_keys);
        }
        Value::Array(items) => items.iter_mut().for_each(describe_variant_keys),
        _ => {}
    }
}

fn describe_the_one_key(variant: &mut Value) {
    let Some(description) = variant.get("description").cloned() else {
        return;
    };
    if let Some(Value::Object(properties)) = variant.get_mut("properties") {
        if let (1, Some(Value::Object(key))) = (properties.len(), properties.values_mut().next()) {
            key.entry("description").or_insert(description);
        }
    }
}

/// Defaults and examples are f32 values widened to f64 (0.01 becomes
/// 0.009999999776482582); show them as written, as the f32's shortest decimal.
fn tidy_defaults(value: &mut Value) {
    match value {
        Value::Object(map) => {
            for (key, member) in map.iter_mut() {
                if key == "default" || key == "examples" {
                    as_written(member);
                } else {
                    tidy_defaults(member);
                }
            }
        }
        Value::Array(items) => items.iter_mut().for_each(tidy_defaults),
        _ => {}
    }
}

fn as_written(value: &mut Value) {
    match value {
        Value::Number(n) if n.is_f64() => {
            let shortest = (n.as_f64().unwrap_or_default() as f32).to_string();
            if let Ok(tidy) = serde_json::from_str(&shortest) {
                *value = tidy;
            }
        }
        Value::Array(items) => items.iter_mut().for_each(as_written),
        Value::Object(map) => map.values_mut().for_each(as_written),
        _ => {}
    }
}

/// TOML has no null: an optional key is simply left out. schemars allows
/// `null` for every `Option`, which makes editors say "not valid under any
/// of the schemas in anyOf" instead of naming the wrong key; take it out.
fn drop_null(value: &mut Value) {
    match value {
        Value::Object(map) => {
            if let Some(Value::Array(types)) = map.get_mut("type") {
                types.retain(|t| t != "null");
                if types.len() == 1 {
                    let only = types.remove(0);
                    map.insert("type".to_string(), only);
                }
            }
            if let Some(Value::Array(alternatives)) = map.get_mut("anyOf") {
                alternatives.retain(|a| a.get("type").and_then(Value::as_str) != Some("null"));
                if let [Value::Object(only)] = alternatives.as_slice() {
                    let only = only.clone();
                    map.remove("anyOf");
                    map.extend(only);
                }
            }
            map.values_mut().for_each(drop_null);
        }
        Value::Array(items) => items.iter_mut().for_each(drop_null),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::validate::{MAX_COORDINATE, MAX_DEPTH_CAP, MAX_IMAGE_SIDE, MIN_FOV, MIN_RADIUS};

    #[test]
    fn the_schema_states_the_validation_limits() {
        let schema: serde_json::Value = serde_json::from_str(&json_schema()).unwrap();
        let defs = &schema["$defs"];
        let camera = &defs["Camera"]["properties"];
        assert_eq!(camera["width"]["maximum"], MAX_IMAGE_SIDE);
        assert_eq!(camera["height"]["minimum"], 1);
        assert_eq!(camera["fov"]["exclusiveMaximum"], 180);
        assert_eq!(camera["fov"]["minimum"], MIN_FOV);
        assert_eq!(
            defs["RenderSettings"]["properties"]["max_depth"]["maximum"],
            MAX_DEPTH_CAP
        );
        let radius = &defs["Sphere"]["properties"]["radius"];
        assert_eq!(radius["minimum"], MIN_RADIUS);
        assert_eq!(radius["maximum"], MAX_COORDINATE);
        // The canvas's, as canvas::validate checks them.
        let canvas = &defs["Canvas"]["properties"];
        assert_eq!(canvas["width"]["maximum"], MAX_IMAGE_SIDE);
        assert_eq!(canvas["height"]["minimum"], 1);
        assert_eq!(canvas["gamma"]["exclusiveMinimum"], 0);
        assert_eq!(canvas["background"]["items"]["minimum"], 0);
        let circle = &defs["Circle"]["properties"]["radius"];
        assert_eq!(circle["exclusiveMinimum"], 0);
        let shape = &defs["CanvasShape"]["properties"];
        assert_eq!(shape["polygon"]["minItems"], 3);
        assert_eq!(shape["color"]["items"]["minimum"], 0);
    }

    /// Defaults read as the model's constants, not as widened f32 values.
    #[test]
    fn defaults_are_shown_as_written() {
        let schema: serde_json::Value = serde_json::from_str(&json_schema()).unwrap();
        let defs = &schema["$defs"];
        let render = &defs["RenderSettings"]["properties"];
        assert_eq!(render["min_energy"]["default"], json!(0.01));
        assert_eq!(render["gamma"]["default"], json!(2.2));
        let canvas = &defs["Canvas"]["properties"];
        assert_eq!(canvas["background"]["default"], json!([0.1, 0.1, 0.1]));
        assert_eq!(defs["Material"]["properties"]["ior"]["default"], json!(1.5));
        assert_eq!(defs["Camera"]["properties"]["fov"]["default"], json!(50));
    }

    /// The root picks the kind of file by its `canvas` key, as `load_any`,
    /// then by its `camera`: a 3D scene or a file it includes.
    #[test]
    fn the_root_tells_a_canvas_from_a_3d_scene() {
        let schema: serde_json::Value = serde_json::from_str(&json_schema()).unwrap();
        assert_eq!(schema["if"], json!({ "required": ["canvas"] }));
        assert_eq!(schema["then"]["$ref"], "#/$defs/CanvasFile");
        let not_canvas = &schema["else"];
        assert_eq!(not_canvas["if"], json!({ "required": ["camera"] }));
        assert_eq!(not_canvas["then"]["$ref"], "#/$defs/SceneFile");
        assert_eq!(not_canvas["else"]["$ref"], "#/$defs/IncludedFile");
        let included = &schema["$defs"]["IncludedFile"]["properties"];
        let mut keys: Vec<&String> = included.as_object().unwrap().keys().collect();
        keys.sort();
        assert_eq!(
            keys,
            ["$schema", "include", "lights", "materials", "objects"]
        );
        let canvas = &schema["$defs"]["CanvasFile"];
        assert_eq!(canvas["required"], json!(["canvas"]));
        assert_eq!(canvas["additionalProperties"], false);
    }

    /// `schema.json` (at the top of the repository) is what editors read;
    /// it must be the schema of this model.
    #[test]
    fn the_committed_schema_is_current() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../schema.json");
        let committed = std::fs::read_to_string(path).unwrap_or_default();
        assert!(
            committed.trim_end() == json_schema().trim_end(),
            "schema.json is stale; regenerate it with\n  \
             cargo run --release --bin tracer -- schema > schema.json"
        );
    }
}
