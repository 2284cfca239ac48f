//! The scene file format of the tracer: plain data read from TOML or JSON,
//! validated, with errors that say where. No rendering here.

pub mod error;
pub mod locate;
pub mod model;
mod parse;
pub mod schema;
pub mod validate;

pub use error::{Diagnostic, Location, SceneError};
pub use locate::KeyPath;
pub use model::*;
pub use parse::suggestion;

use std::path::Path;

/// The syntax of a scene file, picked by its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Toml,
    Json,
}

impl Format {
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "toml" => Some(Format::Toml),
            "json" => Some(Format::Json),
            _ => None,
        }
    }
}

/// Reads, parses and validates the scene file at `path`.
pub fn load_path(path: &Path) -> Result<SceneFile, SceneError> {
    let format = Format::from_path(path).ok_or_else(|| SceneError::UnknownFormat {
        file: path.to_path_buf(),
    })?;
    let bytes = std::fs::read(path).map_err(|source| SceneError::Io {
        file: path.to_path_buf(),
        source,
    })?;
    load_bytes(&bytes, format, path)
}

/// Parses and validates a scene file's bytes; `file` names it in errors.
/// Bytes that are not UTF-8 text are reported, not read lossily.
pub fn load_bytes(bytes: &[u8], format: Format, file: &Path) -> Result<SceneFile, SceneError> {
    match std::str::from_utf8(bytes) {
        Ok(text) => load_str(text, format, file),
        Err(e) => {
            let text = String::from_utf8_lossy(bytes).into_owned();
            let d = parse::not_utf8(bytes, &text, e);
            Err(SceneError::Invalid {
                file: file.to_path_buf(),
                text,
                diagnostics: vec![d],
            })
        }
    }
}

/// Parses and validates scene text; `file` names it in errors. A parse
/// error stops at the first problem; validation reports all it finds.
pub fn load_str(text: &str, format: Format, file: &Path) -> Result<SceneFile, SceneError> {
    let invalid = |diagnostics| SceneError::Invalid {
        file: file.to_path_buf(),
        text: text.to_string(),
        diagnostics,
    };
    let scene = parse::parse(text, format).map_err(invalid)?;
    let diagnostics = validate::validate(&scene);
    if diagnostics.is_empty() {
        Ok(scene)
    } else {
        Err(invalid(locate_all(text, format, diagnostics)))
    }
}

/// Gives each validation diagnostic the span of its key path.
fn locate_all(text: &str, format: Format, diagnostics: Vec<Diagnostic>) -> Vec<Diagnostic> {
    let Some(tree) = locate::tree(text, format) else {
        return diagnostics;
    };
    let mut located: Vec<Diagnostic> = diagnostics
        .into_iter()
        .map(|d| {
            let found = tree.locate(&d.path);
            // A missing key (a default that fails a check) or a whole
            // table: point at the key that names the nearest table.
            let span = match (found.exact, &found.key) {
                (true, _) => found.value,
                (false, Some(key)) => key.clone(),
                (false, None) => found.value.start..found.value.start,
            };
            d.at(text, span)
        })
        .collect();
    // In file order, as a reader goes through the file.
    located.sort_by_key(|d| d.span.as_ref().map(|s| s.start));
    located
}

#[cfg(test)]
mod tests {
    use super::*;

    const CAMERA: &str = r#""camera": {"eye": [0, 0, 10], "look_at": [0, 0, 0]}"#;

    #[test]
    fn json_scenes_may_name_their_schema() {
        let text = format!(r#"{{"$schema": "./schema.json", {CAMERA}}}"#);
        let scene = load_str(&text, Format::Json, Path::new("s.json")).unwrap();
        assert_eq!(scene.schema.as_deref(), Some("./schema.json"));
    }

    #[test]
    fn other_extensions_are_refused() {
        let err = load_path(Path::new("scene.yaml")).unwrap_err();
        assert!(matches!(err, SceneError::UnknownFormat { .. }));
    }

    #[test]
    fn a_defaulted_value_that_fails_points_at_its_table() {
        // `up` is not in the file; its default [0, 1, 0] is parallel to
        // the view direction here.
        let text = "[camera]\neye = [0, 5, 0]\nlook_at = [0, 0, 0]\n";
        let err = load_str(text, Format::Toml, Path::new("s.toml")).unwrap_err();
        let d = &err.diagnostics()[0];
        assert_eq!(d.path.to_string(), "camera.up");
        assert_eq!(d.location, Some(Location { line: 1, column: 2 }));
    }
}
