//! The scene file format of the tracer: plain data read from TOML or JSON,
//! validated, with errors that say where. No rendering here.

pub mod budget;
pub mod canvas;
pub mod checks;
pub mod diagnostic;
pub mod error;
pub mod excerpt;
pub mod gltf;
pub mod images;
pub mod include;
pub mod json_spans;
pub mod key_path;
mod load;
pub mod locate;
pub mod model;
pub mod mtl;
pub mod obj;
mod obj_text;
mod parse;
pub mod ply;
pub mod polygon;
pub mod read;
pub mod repeated_faces;
pub mod schema;
pub mod source;
pub mod span_node;
pub mod span_tree;
mod suggest;
pub mod validate;
pub mod visible;

pub use budget::{Budget, MAX_TRIANGLES};
pub use canvas::CanvasFile;
pub use checks::warnings;
pub use diagnostic::{Diagnostic, Location};
pub use error::SceneError;
pub use include::Origins;
pub use key_path::{KeyPath, Segment};
pub use load::{
    load_any, load_any_str, load_bytes, load_file, load_file_or_part, load_from, load_path,
    load_str, Checked, LoadedScene, SceneKind,
};
pub use model::*;
pub use obj::mesh_warnings;
pub use suggest::suggestion;

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
