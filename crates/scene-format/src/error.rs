//! Errors of loading a scene file, each pointing at where the problem is.

use crate::locate::KeyPath;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// A line and column in the source text, both counted from 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Location {
    pub line: usize,
    pub column: usize,
}

impl Location {
    /// The location of a byte offset in `text`; columns count characters.
    pub fn from_offset(text: &str, offset: usize) -> Location {
        let offset = floor_char_boundary(text, offset.min(text.len()));
        let before = &text[..offset];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = before[line_start..].chars().count() + 1;
        Location { line, column }
    }
}

fn floor_char_boundary(text: &str, mut offset: usize) -> usize {
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    offset
}

/// One problem in a scene file.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostic {
    /// The key path, e.g. `objects[2].sphere.radius`; empty for the whole file.
    pub path: KeyPath,
    /// What was found and what was expected.
    pub message: String,
    /// The bytes of the source the message is about, once located.
    pub span: Option<Range<usize>>,
    /// `span`'s start as line and column.
    pub location: Option<Location>,
}

impl Diagnostic {
    pub fn new(path: impl Into<KeyPath>, message: impl Into<String>) -> Self {
        Diagnostic {
            path: path.into(),
            message: message.into(),
            span: None,
            location: None,
        }
    }

    /// This diagnostic pointing at `span` of `text`.
    pub fn at(mut self, text: &str, span: Range<usize>) -> Self {
        let start = floor_char_boundary(text, span.start.min(text.len()));
        let end = floor_char_boundary(text, span.end.clamp(start, text.len()));
        self.location = Some(Location::from_offset(text, start));
        self.span = Some(start..end);
        self
    }
}

#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("{file}: cannot read the scene file: {source}")]
    Io {
        file: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{file}: unknown scene file type; expected a .toml or .json file")]
    UnknownFormat { file: PathBuf },
    #[error("{}", render_diagnostics(file, text, diagnostics))]
    Invalid {
        file: PathBuf,
        /// The source text (lossily decoded if it was not UTF-8), for
        /// showing the lines the diagnostics point at.
        text: String,
        diagnostics: Vec<Diagnostic>,
    },
}

impl SceneError {
    pub fn diagnostics(&self) -> &[Diagnostic] {
        match self {
            SceneError::Invalid { diagnostics, .. } => diagnostics,
            _ => &[],
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
    let blocks: Vec<String> = diagnostics
        .iter()
        .map(|d| render_one(file, text, d))
        .collect();
    blocks.join("\n\n")
}

fn render_one(file: &Path, text: &str, d: &Diagnostic) -> String {
    let mut out = format!("error: {}\n --> {}", d.message, file.display());
    if let Some(loc) = d.location {
        out += &format!(":{}:{}", loc.line, loc.column);
    }
    if !d.path.is_root() {
        out += &format!(" ({})", d.path);
    }
    if let (Some(span), Some(_)) = (&d.span, d.location) {
        // The fields are public: make any span safe to slice with.
        let start = floor_char_boundary(text, span.start.min(text.len()));
        let end = floor_char_boundary(text, span.end.clamp(start, text.len()));
        out += &snippet(text, &(start..end), Location::from_offset(text, start));
    }
    out
}

/// Lines longer than this are shown as a window around the caret.
const SNIPPET_WIDTH: usize = 100;

fn snippet(text: &str, span: &Range<usize>, loc: Location) -> String {
    let line_start = text[..span.start].rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[span.start..]
        .find('\n')
        .map_or(text.len(), |i| span.start + i);
    let line: Vec<char> = text[line_start..line_end]
        .trim_end_matches('\r')
        .chars()
        .map(printable)
        .collect();
    let caret_from = loc.column - 1;
    let caret_len = text[span.start..span.end.min(line_end)]
        .chars()
        .count()
        .max(1);
    // Keep the caret in view on long lines (minified JSON).
    let skip = if line.len() <= SNIPPET_WIDTH {
        0
    } else {
        caret_from.saturating_sub(SNIPPET_WIDTH / 2)
    };
    let shown: String = line.iter().skip(skip).take(SNIPPET_WIDTH).collect();
    let caret_len = caret_len.min(SNIPPET_WIDTH.saturating_sub(caret_from - skip).max(1));
    let gutter = loc.line.to_string().len();
    let pad = " ".repeat(gutter);
    format!(
        "\n{pad} |\n{} | {}{}\n{pad} | {}{}",
        loc.line,
        if skip > 0 { "..." } else { "" },
        shown,
        " ".repeat(caret_from - skip + if skip > 0 { 3 } else { 0 }),
        "^".repeat(caret_len)
    )
}

/// Tabs and control characters would shift the caret; show them as one
/// visible character each.
fn printable(c: char) -> char {
    match c {
        '\t' => ' ',
        c if c.is_control() => '\u{FFFD}',
        c => c,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
