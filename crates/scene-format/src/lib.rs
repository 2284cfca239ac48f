//! The scene file format of the tracer: plain data read from TOML or JSON,
//! validated, with errors that say where. No rendering here.

pub mod canvas;
pub mod error;
pub mod model;
pub mod obj;
pub mod validate;

pub use canvas::CanvasFile;
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

/// What a scene file describes: a 3D scene or a 2D canvas.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneKind {
    Scene3d(SceneFile),
    Canvas(CanvasFile),
}

/// Reads, parses and validates the file at `path`, a 3D scene or, when it
/// has a top-level `[canvas]` table, a 2D canvas scene.
pub fn load_any(path: &Path) -> Result<SceneKind, SceneError> {
    let format = Format::from_path(path).ok_or_else(|| SceneError::UnknownFormat {
        file: path.to_path_buf(),
    })?;
    let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
        file: path.to_path_buf(),
        source,
    })?;
    load_any_str(&text, format, path)
}

/// `load_any` on text; `file` names it in errors.
pub fn load_any_str(text: &str, format: Format, file: &Path) -> Result<SceneKind, SceneError> {
    if !has_canvas_table(text, format) {
        return load_str(text, format, file).map(SceneKind::Scene3d);
    }
    let invalid = |diagnostics| SceneError::Invalid {
        file: file.to_path_buf(),
        diagnostics,
    };
    let canvas: CanvasFile = parse(text, format).map_err(|d| invalid(vec![d]))?;
    let diagnostics = canvas::validate(&canvas);
    if diagnostics.is_empty() {
        Ok(SceneKind::Canvas(canvas))
    } else {
        Err(invalid(diagnostics))
    }
}

/// Whether the text has a top-level `canvas` key. Text that does not parse
/// is left to the 3D loader, whose error says where.
fn has_canvas_table(text: &str, format: Format) -> bool {
    match format {
        Format::Toml => toml::from_str::<toml::Table>(text).is_ok_and(|t| t.contains_key("canvas")),
        Format::Json => {
            serde_json::from_str::<serde_json::Value>(text).is_ok_and(|v| v.get("canvas").is_some())
        }
    }
}

fn parse<T: serde::de::DeserializeOwned>(text: &str, format: Format) -> Result<T, Diagnostic> {
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
