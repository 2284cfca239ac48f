//! Errors as the page reads them: JSON with the text `tracer check` prints
//! (the same code makes it) and each problem's file, line and column, for
//! the editor to mark.

use scene_format::{Location, SceneError};
use serde_json::{json, Value};
use tracer_pipeline::Error;

/// `{"text": ..., "problems": [{"file", "line", "column", "end_line",
/// "end_column", "key", "message"}]}`; `line` and `column` (1-based) are
/// null where a problem has no place, `end_line` and `end_column` (just
/// past the text it is about) where it has no span.
pub fn error_json(error: &Error) -> String {
    let problems = match error {
        Error::Scene(e) => problems(e),
        _ => Vec::new(),
    };
    json!({ "text": error.to_string(), "problems": problems }).to_string()
}

/// An error with no place: a file the page gave that cannot be read.
pub fn message_json(text: &str) -> String {
    json!({ "text": text, "problems": [] }).to_string()
}

fn problems(error: &SceneError) -> Vec<Value> {
    let mut out = Vec::new();
    for file_error in error.files() {
        let SceneError::Invalid {
            file,
            diagnostics,
            text,
        } = file_error
        else {
            continue;
        };
        for d in diagnostics {
            // Where the marked text ends (the editor marks that much).
            let end = d
                .span
                .as_ref()
                .filter(|span| span.end <= text.len())
                .map(|span| Location::from_offset(text, span.end));
            out.push(json!({
                "file": file.to_string_lossy(),
                "line": d.location.map(|l| l.line),
                "column": d.location.map(|l| l.column),
                "end_line": end.map(|l| l.line),
                "end_column": end.map(|l| l.column),
                "key": d.path.to_string(),
                "message": d.message,
            }));
        }
    }
    out
}

/// `{"samples": [done, of], "path": bool, "warnings": [{"text", "file",
/// "line", "column", "key", "message"}]}`: `path` when path traced.
pub fn notes_json(
    samples: (u32, u32),
    path: bool,
    warnings: &[tracer_pipeline::Warning],
) -> String {
    let warnings: Vec<Value> = warnings
        .iter()
        .map(|w| {
            json!({
                "text": w.text,
                "file": w.file.to_string_lossy(),
                "line": w.location.map(|l| l.line),
                "column": w.location.map(|l| l.column),
                "key": w.key,
                "message": w.message,
            })
        })
        .collect();
    json!({ "samples": [samples.0, samples.1], "path": path, "warnings": warnings }).to_string()
}
