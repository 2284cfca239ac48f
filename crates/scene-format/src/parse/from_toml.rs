//! TOML text to a value, through the toml crate.

use super::locate_or_start;
use super::rephrase::{rephrase, Target};
use crate::diagnostic::Diagnostic;
use crate::key_path::KeyPath;
use crate::Format;
use serde::de::DeserializeOwned;

pub(super) fn parse_toml<T: DeserializeOwned>(text: &str) -> Result<T, Diagnostic> {
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
