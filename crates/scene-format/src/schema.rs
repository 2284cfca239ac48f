//! The JSON Schema of scene files, for editors (completion, checking as
//! you type). Derived from the serde model, so it cannot drift from it.

use crate::model::SceneFile;

/// The schema as pretty-printed JSON.
pub fn json_schema() -> String {
    let schema = schemars::schema_for!(SceneFile);
    let mut value = schema.to_value();
    drop_null(&mut value);
    // Serialising a `serde_json::Value` cannot fail.
    serde_json::to_string_pretty(&value).expect("a schema is plain JSON")
}

/// TOML has no null: an optional key is simply left out. schemars allows
/// `null` for every `Option`, which makes editors say "not valid under any
/// of the schemas in anyOf" instead of naming the wrong key; take it out.
fn drop_null(value: &mut serde_json::Value) {
    use serde_json::Value;
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
