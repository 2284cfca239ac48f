//! The error of loading a scene file: the file could not be read, is of an
//! unknown type, or holds problems (diagnostics); and how the problems read
//! as text, each with its source line and a caret.

use crate::diagnostic::{floor_char_boundary, Diagnostic, Location};
use crate::excerpt::{excerpt, Excerpt, MAX_SHOWN};
use crate::visible::escape_controls;
use std::path::{Path, PathBuf};

/// Why a scene file could not be loaded. Its `Display` is the whole report
/// for a user: the file, and for `Invalid` every diagnostic with its source
/// line and a caret under the place.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read (missing, unreadable).
    #[error("{file}: cannot read the scene file: {source}")]
    Io {
        file: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The file's extension is neither `.toml` nor `.json`.
    #[error("{file}: unknown scene file type; expected a .toml or .json file, a glTF model (.gltf, .glb) or a .zip of `tracer pack`")]
    UnknownFormat { file: PathBuf },
    /// The file was read but holds problems: a parse error (the first
    /// one only) or every value that failed validation, in file order.
    #[error("{}", render_diagnostics(file, text, diagnostics))]
    Invalid {
        file: PathBuf,
        /// The source text (lossily decoded if it was not UTF-8), for
        /// showing the lines the diagnostics point at.
        text: String,
        diagnostics: Vec<Diagnostic>,
    },
    /// Problems in several files: a scene and files it includes, one error
    /// (`Invalid`) per file, in the order the files were read.
    #[error("{}", .0.iter().map(|e| e.to_string()).collect::<Vec<_>>().join("\n\n"))]
    Several(Vec<SceneError>),
}

impl SceneError {
    /// The problems found in the file; empty unless `Invalid`. For
    /// `Several`, those of the first file (see [`SceneError::files`]).
    pub fn diagnostics(&self) -> &[Diagnostic] {
        match self {
            SceneError::Invalid { diagnostics, .. } => diagnostics,
            SceneError::Several(errors) => errors.first().map_or(&[], |e| e.diagnostics()),
            _ => &[],
        }
    }

    /// Each file's error: this one, or each of `Several`.
    pub fn files(&self) -> Vec<&SceneError> {
        match self {
            SceneError::Several(errors) => errors.iter().flat_map(|e| e.files()).collect(),
            _ => vec![self],
        }
    }

    /// One error of the errors of several files: the one, or `Several`.
    pub fn of_files(mut errors: Vec<SceneError>) -> SceneError {
        if errors.len() == 1 {
            errors.remove(0)
        } else {
            SceneError::Several(errors)
        }
    }
}

/// Every diagnostic as a compiler-style message with the source line and a
/// caret, e.g.
///
/// ```text
/// error: unknown key `fvo` in [camera]; did you mean `fov`?
///  --> bad.toml:4:1 (camera.fvo)
///   |
/// 4 | fvo = 50
///   | ^^^
/// ```
fn render_diagnostics(file: &Path, text: &str, diagnostics: &[Diagnostic]) -> String {
    // Thousands of problems are one mistake repeated: the first ones say
    // what it is, and the output stays small.
    let mut blocks: Vec<String> = diagnostics
        .iter()
        .take(MAX_SHOWN)
        .map(|d| render_one(file, text, d))
        .collect();
    if let Some(more) = more_problems(diagnostics.len()) {
        blocks.push(format!("{}: {more}", file.display()));
    }
    blocks.join("\n\n")
}

/// "and N more problems", when more than `MAX_SHOWN` were found.
pub fn more_problems(count: usize) -> Option<String> {
    (count > MAX_SHOWN).then(|| {
        let more = count - MAX_SHOWN;
        let s = if more == 1 { "" } else { "s" };
        format!("and {more} more problem{s} (only the first {MAX_SHOWN} are shown)")
    })
}

fn render_one(file: &Path, text: &str, d: &Diagnostic) -> String {
    let mut out = format!(
        "error: {}\n --> {}",
        escape_controls(&d.message),
        file.display()
    );
    if let Some(loc) = d.location {
        out += &format!(":{}:{}", loc.line, loc.column);
    }
    if !d.path.is_root() {
        out += &escape_controls(&format!(" ({})", d.path));
    }
    if let (Some(span), Some(_)) = (&d.span, d.location) {
        // The fields are public: make any span safe to slice with.
        let start = floor_char_boundary(text, span.start.min(text.len()));
        let line = Location::from_offset(text, start).line;
        out += &snippet(&excerpt(text, span.clone(), line, 0));
    }
    out
}

fn snippet(e: &Excerpt) -> String {
    let number = e.first_line + e.line;
    let pad = " ".repeat(number.to_string().len());
    format!(
        "\n{pad} |\n{number} | {}\n{pad} | {}{}",
        e.lines[e.line],
        " ".repeat(e.column),
        "^".repeat(e.len)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::key_path::KeyPath;
    use std::ops::Range;

    fn report(text: &str, span: Range<usize>) -> String {
        let mut d = Diagnostic::new(KeyPath::root().key("k"), "bad").at(text, 0..0);
        d.span = Some(span);
        SceneError::Invalid {
            file: PathBuf::from("f.toml"),
            text: text.to_string(),
            diagnostics: vec![d],
        }
        .to_string()
    }

    #[test]
    fn the_caret_sits_under_the_span_counting_characters() {
        let text = "a = 1\nkey = \"grün\" # x\n";
        let start = text.find("# x").unwrap();
        let d = Diagnostic::new(KeyPath::root().key("k"), "bad").at(text, start..start + 3);
        assert_eq!(
            d.location,
            Some(Location {
                line: 2,
                column: 14
            })
        );
        let r = report(text, start..start + 3);
        let lines: Vec<&str> = r.lines().collect();
        assert_eq!(lines[3], "2 | key = \"grün\" # x");
        assert_eq!(lines[4], "  |              ^^^");
    }

    #[test]
    fn any_span_renders_without_panicking() {
        let text = "ü\n";
        let reversed = Range { start: 2, end: 1 };
        for span in [0..1, 1..2, 5..9, reversed, 0..100] {
            assert!(report(text, span).starts_with("error: bad"));
        }
    }

    #[test]
    fn long_lines_show_a_window_around_the_caret() {
        let text = format!("{}X{}", "a".repeat(300), "b".repeat(300));
        let r = report(&text, 300..301);
        let lines: Vec<&str> = r.lines().collect();
        let caret = lines[4].find('^').unwrap();
        assert_eq!(lines[3].as_bytes()[caret], b'X');
        assert!(lines[3].len() < 120);
    }
}
