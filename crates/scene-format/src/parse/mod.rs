//! Text to a `SceneFile` or `CanvasFile`, with every failure turned into a located diagnostic
//! in the user's words: key paths from serde_path_to_error, spans from the
//! parser or the locator, serde's messages rephrased.
//!
//! - `from_toml`, `from_json`: each syntax's parse and its errors;
//! - `rephrase`: serde's messages in the user's words;
//! - `toml_key_at`: the key path of a key in TOML that does not parse.

mod from_json;
mod from_toml;
mod rephrase;
mod toml_key_at;

use crate::diagnostic::Diagnostic;
use crate::key_path::KeyPath;
use crate::key_path::Segment;
use crate::locate::{self, Located};
use crate::span_tree::{self, Node, NodeKind};
use crate::Format;
use from_json::parse_json;
use from_toml::parse_toml;
use rephrase::Target;
use serde::de::DeserializeOwned;
use serde::Serialize;

/// The parsed file (a 3D scene or a 2D canvas), or the problems that
/// stopped parsing.
pub fn parse<T: DeserializeOwned + Serialize>(
    text: &str,
    format: Format,
) -> Result<T, Vec<Diagnostic>> {
    if let Some(d) = check_text(text, format) {
        return Err(vec![d]);
    }
    match format {
        Format::Toml => {
            let value: T = parse_toml(text).map_err(|d| vec![d])?;
            misread(text, format, value)
        }
        Format::Json => {
            let value: T = parse_json(text)?;
            misread(text, format, value)
        }
    }
}

/// `value`, unless serde read some of `text` otherwise than it is written:
/// toml reads the first elements of a fixed-length array and drops the
/// rest without a word, and serde reads a table written as an array by
/// position (`camera = [[0, 0, 5], ...]`).
fn misread<T: Serialize>(text: &str, format: Format, value: T) -> Result<T, Vec<Diagnostic>> {
    let misread = misread_values(text, format, &value);
    if misread.is_empty() {
        Ok(value)
    } else {
        Err(misread)
    }
}

/// Arrays in the text longer than what was read into `value`, or read as
/// tables: the value written back and compared with the text's span tree.
fn misread_values<T: Serialize>(text: &str, format: Format, value: &T) -> Vec<Diagnostic> {
    let (Some(tree), Ok(read)) = (span_tree::tree(text, format), serde_json::to_value(value))
    else {
        return Vec::new();
    };
    let mut out = Vec::new();
    compare(text, format, &tree, &read, &mut KeyPath::root(), &mut out);
    out.sort_by_key(|d| d.span.as_ref().map(|s| s.start));
    out
}

fn compare(
    text: &str,
    format: Format,
    node: &Node,
    read: &serde_json::Value,
    path: &mut KeyPath,
    out: &mut Vec<Diagnostic>,
) {
    use serde_json::Value;
    match (&node.kind, read) {
        (NodeKind::Table(entries), Value::Object(map)) => {
            for (key, _, child) in entries {
                if let Some(v) = map.get(key) {
                    path.0.push(Segment::Key(key.clone()));
                    compare(text, format, child, v, path, out);
                    path.0.pop();
                }
            }
        }
        (NodeKind::Array(_), Value::Object(_)) => {
            let d = Diagnostic::new(path.clone(), table_as_array(format));
            out.push(d.at(text, node.span.clone()));
        }
        (NodeKind::Array(items), Value::Array(kept)) => {
            if items.len() > kept.len() {
                let d = Diagnostic::new(path.clone(), too_long(items, kept.len()));
                out.push(d.at(text, node.span.clone()));
                return;
            }
            for (i, (child, v)) in items.iter().zip(kept).enumerate() {
                path.0.push(Segment::Index(i));
                compare(text, format, child, v, path, out);
                path.0.pop();
            }
        }
        _ => {}
    }
}

/// What a table written as an array is told: its keys are named.
pub(super) fn table_as_array(format: Format) -> &'static str {
    match format {
        Format::Toml => {
            "expected a table of named keys (`{ key = value, ... }` or a `[header]`), \
             found an array"
        }
        Format::Json => "expected an object of named keys ({\"key\": value, ...}), found an array",
    }
}

/// "expected 3 numbers, found 4" for an array of `items` of which
/// `expected` are read.
pub(crate) fn too_long(items: &[Node], expected: usize) -> String {
    let what = match items.first().map(|n| &n.kind) {
        Some(NodeKind::Array(_)) => "vertices",
        Some(NodeKind::Scalar) => "numbers",
        _ => "elements",
    };
    format!("expected {expected} {what}, found {}", items.len())
}

/// Files that are not scene text at all: empty, or binary.
fn check_text(text: &str, format: Format) -> Option<Diagnostic> {
    if let Some(i) = text.find('\0') {
        let d = Diagnostic::new(
            KeyPath::root(),
            "found a NUL byte; expected a text file (is this a binary file?)",
        );
        return Some(d.at(text, i..i + 1));
    }
    if text.trim().is_empty() {
        let expected = match format {
            Format::Toml => "a scene with at least a [camera] table",
            Format::Json => "a JSON object with at least a \"camera\" key",
        };
        let d = Diagnostic::new(
            KeyPath::root(),
            format!("the file is empty; expected {expected}"),
        );
        return Some(d.at(text, 0..0));
    }
    None
}

/// The diagnostic for bytes that are not UTF-8: the file is binary or in
/// another encoding. `text` is the lossy decoding of `bytes`.
pub fn not_utf8(bytes: &[u8], text: &str, error: std::str::Utf8Error) -> Diagnostic {
    let offset = error.valid_up_to();
    let d = Diagnostic::new(
        KeyPath::root(),
        format!(
            "found byte 0x{:02x}, which is not UTF-8 text; expected a UTF-8 text file (is this a binary file?)",
            bytes[offset]
        ),
    );
    // The lossy text matches `bytes` up to the first bad byte.
    d.at(text, offset..offset + 1)
}

/// `d` pointing at what it is about, when the text parses far enough to
/// find `path`.
fn locate_or_start(
    d: Diagnostic,
    text: &str,
    format: Format,
    path: &KeyPath,
    target: Target,
) -> Diagnostic {
    match locate::locate(text, format, path) {
        Some(found) => {
            let span = pick_span(&found, target, path);
            d.at(text, span)
        }
        None => d,
    }
}

fn pick_span(found: &Located, target: Target, path: &KeyPath) -> std::ops::Range<usize> {
    match (target, &found.key) {
        (Target::Key | Target::Table, Some(key)) => key.clone(),
        // A key missing at the top level: point at the start of the file,
        // not at all of it.
        (Target::Table, None) if path.0.len() <= 1 => found.value.start..found.value.start,
        _ => found.value.clone(),
    }
}
