//! The JSON Schema of scene files, for editors (completion, checking as
//! you type). Derived from the serde model, so it cannot drift from it.

use crate::model::SceneFile;

/// The schema as pretty-printed JSON.
pub fn json_schema() -> String {
    let schema = schemars::schema_for!(SceneFile);
    // Serialising a `serde_json::Value`-backed schema cannot fail.
    serde_json::to_string_pretty(&schema).expect("a schema is plain JSON")
}
