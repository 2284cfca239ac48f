//! Text to a `SceneFile` or `CanvasFile`, with every failure turned into a located diagnostic
//! in the user's words: key paths from serde_path_to_error, spans from the
//! parser or the locator, serde's messages rephrased.

use crate::error::Diagnostic;
use crate::locate::{self, json, KeyPath, Located};
use crate::Format;
use serde::de::DeserializeOwned;

/// The parsed file (a 3D scene or a 2D canvas), or the problems that
/// stopped parsing.
pub fn parse<T: DeserializeOwned>(text: &str, format: Format) -> Result<T, Vec<Diagnostic>> {
    if let Some(d) = check_text(text, format) {
        return Err(vec![d]);
    }
    match format {
        Format::Toml => parse_toml(text).map_err(|d| vec![d]),
        Format::Json => parse_json(text),
    }
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

fn parse_toml<T: DeserializeOwned>(text: &str) -> Result<T, Diagnostic> {
    let de = toml::Deserializer::parse(text).map_err(|e| toml_syntax(text, &e))?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = KeyPath::from_serde(e.path());
        let inner = e.into_inner();
        let (path, message, target) = rephrase(path, inner.message().trim_end());
        let d = Diagnostic::new(path.clone(), message);
        match (inner.span(), target) {
            // toml's own span is exact for values and unknown keys.
            (Some(span), Target::Value | Target::Key) => d.at(text, span),
            _ => locate_or_start(d, text, Format::Toml, &path, target),
        }
    })
}

fn toml_syntax(text: &str, e: &toml::de::Error) -> Diagnostic {
    // toml puts its hints on further lines; one line reads better.
    let message = e
        .message()
        .trim_end()
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ");
    let span = e.span().unwrap_or(0..0);
    let message = match (message.as_str(), text.get(span.clone())) {
        // toml names neither the key nor the fix.
        ("duplicate key", Some(key)) => format!("duplicate key `{key}`; expected each key once"),
        _ => message,
    };
    Diagnostic::new(KeyPath::root(), message).at(text, span)
}

fn parse_json<T: DeserializeOwned>(text: &str) -> Result<T, Vec<Diagnostic>> {
    let structure = json_structure_errors(text);
    if !structure.is_empty() {
        return Err(structure);
    }
    let mut de = serde_json::Deserializer::from_str(text);
    let result: Result<T, _> = serde_path_to_error::deserialize(&mut de);
    let scene = result.map_err(|e| {
        let path = KeyPath::from_serde(e.path());
        vec![json_error(text, path, e.into_inner())]
    })?;
    de.end()
        .map_err(|e| vec![json_error(text, KeyPath::root(), e)])?;
    Ok(scene)
}

/// What serde_json lets through or words poorly: a top level that is not
/// an object, and duplicate keys (serde_json keeps the last one silently).
/// Text that is not JSON at all is left to serde_json to report.
fn json_structure_errors(text: &str) -> Vec<Diagnostic> {
    let Ok(tree) = json::parse(text) else {
        return Vec::new();
    };
    if !matches!(tree.kind, locate::NodeKind::Table(_)) {
        let d = Diagnostic::new(
            KeyPath::root(),
            "expected a JSON object ({ \"camera\": ... }) at the top level",
        );
        return vec![d.at(text, tree.span)];
    }
    json::duplicate_keys(&tree)
        .into_iter()
        .map(|(path, span, first)| {
            let path = KeyPath(path);
            let first = crate::error::Location::from_offset(text, first.start);
            let name = path.last_key().unwrap_or_default().to_string();
            let message = format!(
                "duplicate key `{name}` {} (first defined at line {}, column {}); expected each key once",
                path.parent().in_table(),
                first.line,
                first.column
            );
            Diagnostic::new(path, message).at(text, span)
        })
        .collect()
}

fn json_error(text: &str, path: KeyPath, e: serde_json::Error) -> Diagnostic {
    let message = strip_json_position(&e.to_string());
    // serde_json's own position: where it stopped reading.
    let position = offset_of(text, e.line(), e.column());
    if e.is_syntax() || e.is_eof() || e.is_io() {
        let message = match message.as_str() {
            "number out of range" => "number out of range; expected a finite number".to_string(),
            _ => message,
        };
        return Diagnostic::new(KeyPath::root(), message).at(text, position);
    }
    let (path, message, target) = rephrase(path, &message);
    let d = Diagnostic::new(path.clone(), message);
    let d = locate_or_start(d, text, Format::Json, &path, target);
    match d.span {
        Some(_) => d,
        // The text is not JSON past this point, so the locator found nothing.
        None => d.at(text, position),
    }
}

/// The byte offset of serde_json's 1-based line and column (column counts
/// bytes; 0 means before the first byte of the line).
fn offset_of(text: &str, line: usize, column: usize) -> std::ops::Range<usize> {
    let line_start: usize = text
        .split_inclusive('\n')
        .take(line.saturating_sub(1))
        .map(str::len)
        .sum();
    let at = (line_start + column.saturating_sub(1)).min(text.len());
    at..at
}

/// serde_json appends " at line L column C"; the location is kept apart.
fn strip_json_position(message: &str) -> String {
    match message.rfind(" at line ") {
        Some(i) => message[..i].to_string(),
        None => message.to_string(),
    }
}

/// What a message is about: the value at the path, the key that names it,
/// or the table holding it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Target {
    Value,
    Key,
    Table,
}

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

/// serde's message in the user's words, with the path adjusted to what the
/// message is about.
fn rephrase(path: KeyPath, message: &str) -> (KeyPath, String, Target) {
    if let Some(rest) = message.strip_prefix("unknown field ") {
        return unknown_key(path, rest);
    }
    if let Some(rest) = message.strip_prefix("unknown variant ") {
        let (found, expected) = split_found(rest);
        let names = backticked(expected);
        let hint = suggestion(found, &names)
            .map(|s| format!("did you mean `{s}`?"))
            .unwrap_or_else(|| format!("expected one of {}", list(&names)));
        return (
            path,
            format!("unknown value `{found}`; {hint}"),
            Target::Value,
        );
    }
    if let Some(rest) = message.strip_prefix("missing field ") {
        let name = rest.trim_matches('`');
        let table = path.in_table();
        return (
            path.key(name),
            format!("missing key `{name}` {table}; it has no default"),
            Target::Table,
        );
    }
    if let Some(rest) = message.strip_prefix("duplicate field ") {
        let name = rest.trim_matches('`');
        let table = path.in_table();
        return (
            path.key(name),
            format!("duplicate key `{name}` {table}; expected each key once"),
            Target::Table,
        );
    }
    let wrong_value = ["invalid type: ", "invalid value: "]
        .iter()
        .find_map(|prefix| message.strip_prefix(prefix)?.split_once(", expected "));
    if let Some((found, expected)) = wrong_value {
        return (
            path,
            format!(
                "expected {}, found {}",
                expected_words(expected),
                found_words(found)
            ),
            Target::Value,
        );
    }
    if let Some(rest) = message.strip_prefix("invalid length ") {
        if let Some((n, expected)) = rest.split_once(", expected ") {
            return (
                path,
                format!(
                    "expected {}, found {n} element{}",
                    expected_words(expected),
                    plural(n)
                ),
                Target::Value,
            );
        }
    }
    (path, message.to_string(), Target::Value)
}

fn plural(n: &str) -> &'static str {
    if n == "1" {
        ""
    } else {
        "s"
    }
}

/// `unknown field `fvo`, expected one of `eye`, ...` -> "unknown key `fvo`
/// in [camera]; did you mean `fov`?". serde_path_to_error's path may or may
/// not end in the unknown key; it is made to end there.
fn unknown_key(path: KeyPath, rest: &str) -> (KeyPath, String, Target) {
    let (found, expected) = split_found(rest);
    let path = if path.last_key() == Some(found) {
        path
    } else {
        path.key(found)
    };
    let table = path.parent().in_table();
    let names = backticked(expected);
    let hint = match suggestion(found, &names) {
        Some(s) => format!("did you mean `{s}`?"),
        None if names.is_empty() => "this table takes no keys".to_string(),
        None => format!("expected one of {}", list(&names)),
    };
    (
        path,
        format!("unknown key `{found}` {table}; {hint}"),
        Target::Key,
    )
}

/// "`x`, expected ..." -> ("x", "expected ...").
fn split_found(rest: &str) -> (&str, &str) {
    let rest = rest.strip_prefix('`').unwrap_or(rest);
    match rest.find("`, ") {
        Some(i) => (&rest[..i], &rest[i + 3..]),
        None => (rest.trim_end_matches('`'), ""),
    }
}

/// The names in backticks in serde's "expected one of `a`, `b`".
fn backticked(s: &str) -> Vec<&str> {
    s.split('`').skip(1).step_by(2).collect()
}

fn list(names: &[&str]) -> String {
    names
        .iter()
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The known name closest to a misspelt one, if it is close enough to be
/// a likely typo (a third of the letters or fewer wrong, at least one).
pub fn suggestion<'a>(found: &str, known: &[&'a str]) -> Option<&'a str> {
    let found_lower = found.to_lowercase();
    let allowed = (found.chars().count() / 3).max(1);
    known
        .iter()
        .map(|k| (strsim::damerau_levenshtein(&found_lower, k), *k))
        .filter(|(d, _)| *d <= allowed)
        .min_by_key(|(d, _)| *d)
        .map(|(_, k)| k)
}

/// serde's Rust type names in scene-file words.
fn expected_words(expected: &str) -> String {
    let e = expected.trim();
    match e {
        "f32" | "f64" => "a number".to_string(),
        "u32" | "u64" | "usize" => "a whole number >= 0".to_string(),
        "a string" | "a borrowed string" => "a string".to_string(),
        "a sequence" => "an array".to_string(),
        "a map" => "a table".to_string(),
        "an array of length 3" => "an array of 3 elements".to_string(),
        _ if e.starts_with("struct ") => "a table".to_string(),
        _ if e.starts_with("enum ") => "a name in quotes".to_string(),
        _ => e.to_string(),
    }
}

/// serde's description of a found value: `integer `5`` -> `5`.
fn found_words(found: &str) -> String {
    let f = found.trim();
    match f {
        "map" => "a table".to_string(),
        "sequence" => "an array".to_string(),
        _ => {
            if let Some((kind, value)) = f.split_once(' ') {
                let value = value.trim_matches('`');
                match kind {
                    "integer" | "floating" => value
                        .trim_start_matches("point ")
                        .trim_matches('`')
                        .to_string(),
                    "string" => format!("the string {value}"),
                    "boolean" => format!("`{value}`"),
                    _ => f.to_string(),
                }
            } else {
                f.to_string()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggestions_catch_typos_and_not_strangers() {
        let camera = ["eye", "look_at", "up", "fov", "width", "height"];
        assert_eq!(suggestion("fvo", &camera), Some("fov"));
        assert_eq!(suggestion("lookat", &camera), Some("look_at"));
        assert_eq!(suggestion("heigth", &camera), Some("height"));
        assert_eq!(suggestion("Width", &camera), Some("width"));
        assert_eq!(suggestion("zoom", &camera), None);
        assert_eq!(suggestion("position", &camera), None);
    }

    #[test]
    fn serde_messages_are_rephrased() {
        let camera = KeyPath::root().key("camera");
        let (p, m, t) = rephrase(
            camera.clone(),
            "unknown field `fvo`, expected one of `eye`, `look_at`, `up`, `fov`",
        );
        assert_eq!(p.to_string(), "camera.fvo");
        assert_eq!(m, "unknown key `fvo` in [camera]; did you mean `fov`?");
        assert_eq!(t, Target::Key);
        let (_, m, _) = rephrase(
            camera.key("fov"),
            "invalid type: string \"wide\", expected f32",
        );
        assert_eq!(m, "expected a number, found the string \"wide\"");
        let (_, m, _) = rephrase(
            camera.key("width"),
            "invalid value: integer `-5`, expected u32",
        );
        assert_eq!(m, "expected a whole number >= 0, found -5");
        let (_, m, _) = rephrase(
            camera.key("eye"),
            "invalid length 2, expected an array of length 3",
        );
        assert_eq!(m, "expected an array of 3 elements, found 2 elements");
        let (p, m, t) = rephrase(camera, "missing field `eye`");
        assert_eq!(p.to_string(), "camera.eye");
        assert_eq!(m, "missing key `eye` in [camera]; it has no default");
        let (_, m, _) = rephrase(KeyPath::root(), "missing field `camera`");
        assert_eq!(
            m,
            "missing key `camera` at the top level; it has no default"
        );
        assert_eq!(t, Target::Table);
    }
}
