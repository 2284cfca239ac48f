//! The scene file format of the tracer: plain data read from TOML or JSON,
//! validated, with errors that say where. No rendering here.

pub mod error;
pub mod model;
pub mod obj;
pub mod validate;

pub use error::{Diagnostic, Location, SceneError};
pub use model::*;
pub use obj::mesh_warnings;

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

/// Reads, parses and validates the scene file at `path`, and reads the OBJ
/// files of its meshes (relative to the scene file's folder).
pub fn load_path(path: &Path) -> Result<SceneFile, SceneError> {
    let format = Format::from_path(path).ok_or_else(|| SceneError::UnknownFormat {
        file: path.to_path_buf(),
    })?;
    let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
        file: path.to_path_buf(),
        source,
    })?;
    let mut scene = load_str(&text, format, path)?;
    let base = path.parent().unwrap_or(Path::new(""));
    let diagnostics = obj::load_meshes(&mut scene, base);
    if diagnostics.is_empty() {
        Ok(scene)
    } else {
        Err(SceneError::Invalid {
            file: path.to_path_buf(),
            diagnostics,
        })
    }
}

/// Parses and validates scene text; `file` names it in errors. Meshes are
/// not read: see `obj::load_meshes`.
pub fn load_str(text: &str, format: Format, file: &Path) -> Result<SceneFile, SceneError> {
    let invalid = |diagnostics| SceneError::Invalid {
        file: file.to_path_buf(),
        diagnostics,
    };
    let scene = parse(text, format).map_err(|d| invalid(vec![d]))?;
    let diagnostics = validate::validate(&scene);
    if diagnostics.is_empty() {
        Ok(scene)
    } else {
        Err(invalid(diagnostics))
    }
}

fn parse(text: &str, format: Format) -> Result<SceneFile, Diagnostic> {
    match format {
        Format::Toml => toml::from_str(text).map_err(|e| Diagnostic {
            path: String::new(),
            message: e.message().trim_end().to_string(),
            location: e.span().map(|s| Location::from_offset(text, s.start)),
        }),
        Format::Json => serde_json::from_str(text).map_err(|e| Diagnostic {
            path: String::new(),
            message: strip_json_position(&e.to_string()),
            location: Some(Location {
                line: e.line(),
                column: e.column(),
            }),
        }),
    }
}

/// serde_json appends " at line L column C"; the location is kept apart.
fn strip_json_position(message: &str) -> String {
    match message.rfind(" at line ") {
        Some(i) => message[..i].to_string(),
        None => message.to_string(),
    }
}
