//! serde's error messages in the user's words: scene-file names for Rust
//! types, "did you mean" for misspelt keys and values, and the key path
//! moved to what the message is about.

use crate::key_path::KeyPath;
use crate::suggest::{hint, list_all, suggestion, synonym_hint};

/// What a message is about: the value at the path, the key that names it,
/// or the table holding it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Target {
    Value,
    Key,
    Table,
}

/// serde's message in the user's words, with the path adjusted to what the
/// message is about.
pub(super) fn rephrase(path: KeyPath, message: &str) -> (KeyPath, String, Target) {
    if let Some(rest) = message.strip_prefix("unknown field ") {
        return unknown_key(path, rest);
    }
    if let Some(rest) = message.strip_prefix("unknown variant ") {
        let (found, expected) = split_found(rest);
        let names = backticked(expected);
        let hint = hint(found, &names);
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
    // toml's own words for an enum (a name like `saturation`, or a
    // one-key table like a canvas transform step).
    match message {
        "wanted string or table" => {
            return (
                path,
                "expected a name in quotes or a table with one key".to_string(),
                Target::Value,
            )
        }
        "wanted exactly 1 element, more than 1 element" => {
            return (
                path,
                "expected a table with exactly one key, found several".to_string(),
                Target::Value,
            )
        }
        // toml's words for a prefix without digits (`0x`) as for 2^64.
        "integer number overflowed" => {
            return (
                path,
                "not a number that can be read (too large, or `0x`, `0o`, `0b` without digits); \
                 expected a number such as 10 or 2.5"
                    .to_string(),
                Target::Value,
            )
        }
        "wanted exactly 1 element, found 0 elements" => {
            return (
                path,
                "expected a table with exactly one key, found none".to_string(),
                Target::Value,
            )
        }
        _ => {}
    }
    let wrong_value = ["invalid type: ", "invalid value: "]
        .iter()
        .find_map(|prefix| message.strip_prefix(prefix)?.split_once(", expected "));
    if let Some((found, expected)) = wrong_value {
        let expected = key_range(&path, expected).unwrap_or_else(|| expected_words(expected));
        return (
            path,
            format!("expected {expected}, found {}", found_words(found)),
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
    // A table's keys are few: all are listed.
    let hint = match suggestion(found, &names) {
        Some(s) => format!("did you mean `{s}`?"),
        None if names.is_empty() => "this table takes no keys".to_string(),
        None => synonym_hint(found, &names)
            .unwrap_or_else(|| format!("expected one of {}", list_all(&names))),
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

/// The range of a whole-number key whose validation allows less than its
/// type does: `samples = -4` is told the samples' range, not the type's.
fn key_range(path: &KeyPath, expected: &str) -> Option<String> {
    use crate::validate::{MAX_DEPTH_CAP, MAX_IMAGE_SIDE, MAX_PATH_SAMPLES, MAX_SAMPLES};
    if expected.trim() != "u32" {
        return None;
    }
    let key = path.to_string();
    let range = match key.as_str() {
        "render.samples" => format!(
            "a whole number of samples from 1 to {MAX_SAMPLES} (to {MAX_PATH_SAMPLES} with integrator = \"path\")"
        ),
        "render.light_samples" => format!("a whole number of samples from 1 to {MAX_SAMPLES}"),
        "render.max_depth" => format!("a whole number from 0 to {MAX_DEPTH_CAP}"),
        "camera.width" | "camera.height" => {
            format!("a whole number of pixels from 1 to {MAX_IMAGE_SIDE}")
        }
        _ => return None,
    };
    Some(range)
}

/// serde's Rust type names in scene-file words.
fn expected_words(expected: &str) -> String {
    let e = expected.trim();
    match e {
        "f32" | "f64" => "a number".to_string(),
        "u32" => "a whole number from 0 to 4294967295".to_string(),
        "u64" | "usize" => "a whole number >= 0".to_string(),
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
                // serde writes integers past 64 bits as "`N` as i128".
                let value = value
                    .trim_end_matches(" as i128")
                    .trim_end_matches(" as u128")
                    .trim_matches('`');
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
        // A key validated to less than its type is told its own range.
        let (_, m, _) = rephrase(
            camera.key("width"),
            "invalid value: integer `-5`, expected u32",
        );
        assert_eq!(
            m,
            "expected a whole number of pixels from 1 to 16384, found -5"
        );
        let render = KeyPath::root().key("render");
        let (_, m, _) = rephrase(
            render.key("max_depth"),
            "invalid type: floating point `2.5`, expected u32",
        );
        assert_eq!(m, "expected a whole number from 0 to 64, found 2.5");
        let (_, m, _) = rephrase(
            KeyPath::root().key("canvas").key("width"),
            "invalid value: integer `4294967296`, expected u32",
        );
        assert_eq!(
            m,
            "expected a whole number from 0 to 4294967295, found 4294967296"
        );
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
