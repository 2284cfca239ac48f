//! Errors of loading a scene file, each pointing at where the problem is.

use std::fmt;
use std::path::PathBuf;

/// A line and column in the source text, both counted from 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Location {
    pub line: usize,
    pub column: usize,
}

impl Location {
    /// The location of a byte offset in `text`; columns count characters.
    pub fn from_offset(text: &str, offset: usize) -> Location {
        let offset = offset.min(text.len());
        let before = &text[..floor_char_boundary(text, offset)];
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
    pub path: String,
    pub message: String,
    pub location: Option<Location>,
}

impl Diagnostic {
    pub fn new(path: impl Into<String>, message: impl Into<String>) -> Self {
        Diagnostic {
            path: path.into(),
            message: message.into(),
            location: None,
        }
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
    #[error("{}", render_diagnostics(file, diagnostics))]
    Invalid {
        file: PathBuf,
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

fn render_diagnostics(file: &std::path::Path, diagnostics: &[Diagnostic]) -> String {
    let lines: Vec<String> = diagnostics
        .iter()
        .map(|d| format!("{}", DiagnosticLine { file, d }))
        .collect();
    lines.join("\n")
}

struct DiagnosticLine<'a> {
    file: &'a std::path::Path,
    d: &'a Diagnostic,
}

impl fmt::Display for DiagnosticLine<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(loc) = self.d.location {
            write!(f, ":{}:{}", loc.line, loc.column)?;
        }
        if !self.d.path.is_empty() {
            write!(f, ": `{}`", self.d.path)?;
        }
        write!(f, ": {}", self.d.message)
    }
}
