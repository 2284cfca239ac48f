//! TOML text to a value, through the toml crate.

use super::locate_or_start;
use super::rephrase::{rephrase, Target};
use super::toml_key_at::key_at;
use crate::diagnostic::Diagnostic;
use crate::key_path::{KeyPath, Segment};
use crate::Format;
use serde::de::DeserializeOwned;
use std::ops::Range;

pub(super) fn parse_toml<T: DeserializeOwned>(text: &str) -> Result<T, Diagnostic> {
    let de = toml::Deserializer::parse(text).map_err(|e| toml_syntax(text, &e))?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = KeyPath::from_serde(e.path());
        let inner = e.into_inner();
        let (path, mut message, target) = rephrase(path, inner.message().trim_end());
        if inner
            .span()
            .and_then(|s| text.get(s))
            .is_some_and(is_datetime)
        {
            // toml hands serde a date as a table: say what was written.
            message = message.replace("found a table", "found a date or time");
        }
        let d = Diagnostic::new(path.clone(), message);
        match (inner.span(), target) {
            // toml's own span is exact for values and unknown keys.
            (Some(span), Target::Value | Target::Key) => d.at(text, span),
            _ => locate_or_start(d, text, Format::Toml, &path, target),
        }
    })
}

/// Whether a value's text is a TOML date, time or date-time (`1979-05-27`,
/// `07:32:00`).
fn is_datetime(value: &str) -> bool {
    value.parse::<toml::value::Datetime>().is_ok()
}

/// The most steps of a key path shown for a value nested too deep.
const MAX_SHOWN_DEPTH: usize = 6;

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
    if message == "duplicate key" {
        return duplicate(text, span);
    }
    if message == "recursion limit" {
        return deep_key(text);
    }
    if message.starts_with("cannot recurse further") {
        // The parser's words, and no key: say which value, and the fix.
        let mut path = key_at(text, span.clone()).path;
        // `x`, not `x[0][0]...` or `x.a.a...` eighty times: no scene key
        // is deeper than six steps (`objects[0].transform[2].rotate`).
        path.0.truncate(MAX_SHOWN_DEPTH);
        while matches!(path.0.last(), Some(Segment::Index(_))) {
            path.0.pop();
        }
        let message = "arrays or inline tables nested too deep to read; \
                       expected at most a few levels, as in `triangle = [[0, 0, 0], ...]`";
        return Diagnostic::new(path, message).at(text, span);
    }
    Diagnostic::new(KeyPath::root(), message).at(text, span)
}

/// The key of a line of TOML: before its `=`, or its table header's.
fn key_of(line: &str) -> &str {
    let key = line.split('=').next().unwrap_or_default();
    key.trim().trim_matches(|c| c == '[' || c == ']').trim()
}

/// toml's "recursion limit" for a key of too many dotted parts names no
/// place: the line whose key has the most parts is taken to be it.
fn deep_key(text: &str) -> Diagnostic {
    let mut offset = 0;
    let mut deepest = (0, 0, "");
    for line in text.split_inclusive('\n') {
        let key = key_of(line);
        let parts = key.split('.').count();
        if parts > deepest.0 {
            let start = offset + (key.as_ptr() as usize - line.as_ptr() as usize);
            deepest = (parts, start, key);
        }
        offset += line.len();
    }
    let (parts, start, key) = deepest;
    let path = KeyPath(
        key.split('.')
            .take(MAX_SHOWN_DEPTH)
            .map(|k| Segment::Key(k.trim().trim_matches('"').to_string()))
            .collect(),
    );
    let message = format!(
        "a key of {parts} dotted parts, more than can be read; expected at most a few, as in `materials.red.diffuse`"
    );
    Diagnostic::new(path, message).at(text, start..start + key.len())
}

/// toml names neither the key, nor its table, nor the fix: the key path is
/// read from the text before the second occurrence, which `span` is.
fn duplicate(text: &str, span: Range<usize>) -> Diagnostic {
    let at = key_at(text, span.clone());
    let message = match (at.header, at.path.last_key()) {
        (true, _) => {
            let table = if at.path.0.iter().all(|s| matches!(s, Segment::Key(_))) {
                format!("[{}]", at.path)
            } else {
                format!("`{}`", at.path)
            };
            format!("duplicate table {table}; expected each table once")
        }
        (false, Some(key)) => format!(
            "duplicate key `{key}` {}; expected each key once",
            at.path.parent().in_table()
        ),
        // The key was not found: its text, in the nearest enclosing table.
        (false, None) => format!(
            "duplicate key `{}` {}; expected each key once",
            text.get(span.clone()).unwrap_or_default(),
            at.path.in_table()
        ),
    };
    Diagnostic::new(at.path, message).at(text, span)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SceneFile;

    #[test]
    fn a_value_nested_past_the_parsers_depth_is_named_by_its_key() {
        let deep = format!("{}{}", "[".repeat(10_000), "]".repeat(10_000));
        let text = format!("[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nx = {deep}\n");
        let d = parse_toml::<SceneFile>(&text).unwrap_err();
        assert_eq!(d.path.to_string(), "camera.x");
        assert!(
            d.message
                .starts_with("arrays or inline tables nested too deep"),
            "{}",
            d.message
        );
        assert_eq!(d.location.map(|l| l.line), Some(4));
        let tables = format!("{}1{}", "{ a = ".repeat(10_000), " }".repeat(10_000));
        let text = format!("x = {tables}\n[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n");
        let d = parse_toml::<SceneFile>(&text).unwrap_err();
        assert!(d.path.0.len() <= MAX_SHOWN_DEPTH, "{}", d.path);
        assert!(d.path.to_string().starts_with("x.a"), "{}", d.path);
    }

    #[test]
    fn a_date_where_a_value_is_expected_is_called_a_date() {
        for (value, expected) in [
            ("1979-05-27", "an array of 3 elements"),
            ("07:32:00", "an array of 3 elements"),
            ("1979-05-27T07:32:00Z", "an array of 3 elements"),
        ] {
            let text = format!("[camera]\neye = {value}\nlook_at = [0, 0, 0]\n");
            let d = parse_toml::<SceneFile>(&text).unwrap_err();
            assert_eq!(
                d.message,
                format!("expected {expected}, found a date or time"),
                "{value}"
            );
            assert_eq!(d.location.map(|l| (l.line, l.column)), Some((2, 7)));
        }
        // An inline table is still a table.
        let text = "[camera]\neye = { x = 1 }\nlook_at = [0, 0, 0]\n";
        let d = parse_toml::<SceneFile>(text).unwrap_err();
        assert!(d.message.ends_with("found a table"), "{}", d.message);
        assert!(!is_datetime("-5") && !is_datetime("12") && !is_datetime("[1-2]"));
    }

    #[test]
    fn a_hexadecimal_prefix_without_digits_is_not_called_an_overflow() {
        let text = "[camera]\neye = 0x\nlook_at = [0, 0, 0]\n";
        let d = parse_toml::<SceneFile>(text).unwrap_err();
        assert!(
            d.message.starts_with("not a number that can be read"),
            "{}",
            d.message
        );
        assert_eq!(d.path.to_string(), "camera.eye");
        assert_eq!(d.location.map(|l| (l.line, l.column)), Some((2, 7)));
    }

    #[test]
    fn a_key_of_too_many_dotted_parts_is_placed_at_its_line() {
        let deep = vec!["a"; 100].join(".");
        for text in [
            format!("[camera]\neye = [0, 0, 10]\n{deep} = 1\n"),
            format!("[camera]\neye = [0, 0, 10]\n[[{deep}]]\n"),
        ] {
            let d = parse_toml::<SceneFile>(&text).unwrap_err();
            assert!(
                d.message.starts_with("a key of 100 dotted parts"),
                "{}",
                d.message
            );
            assert_eq!(
                d.location.map(|l| (l.line, l.column)),
                Some((3, 1 + text.lines().nth(2).unwrap().find('a').unwrap()))
            );
            assert_eq!(d.path.0.len(), MAX_SHOWN_DEPTH);
        }
    }
}
