//! Scene errors shown as a user reads them: the message, the file, line
//! and column, the source line with the key path under a caret (miette).

use miette::{
    Diagnostic, GraphicalReportHandler, LabeledSpan, MietteSpanContents, SourceSpan, SpanContents,
};
use scene_format::error::more_problems;
use scene_format::excerpt::{excerpt, MAX_SHOWN};
use scene_format::visible::escape_controls;
use scene_format::SceneError;
use std::fmt;

/// One scene diagnostic in miette's terms.
#[derive(Debug)]
struct SceneDiagnostic {
    message: String,
    source: Option<Excerpted>,
    span: Option<SourceSpan>,
    key_path: String,
}

impl fmt::Display for SceneDiagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for SceneDiagnostic {}

impl Diagnostic for SceneDiagnostic {
    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        self.source.as_ref().map(|s| s as &dyn miette::SourceCode)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        let span = self.span?;
        let label = (!self.key_path.is_empty()).then(|| self.key_path.clone());
        Some(Box::new(std::iter::once(LabeledSpan::new_with_span(
            label, span,
        ))))
    }
}

/// The lines around a diagnostic, windowed on long lines (see
/// `scene_format::excerpt`): miette is given these few lines rather than
/// the file, which keeps the report small and miette off columns it cannot
/// count (it panics past 65,535). Line numbers and the header's column are
/// those of the file.
#[derive(Debug)]
struct Excerpted {
    name: String,
    text: String,
    /// The file's line number (from 0) of the excerpt's first line.
    first_line: usize,
    /// The excerpt's line (from 0) that holds the span.
    line: usize,
    /// Added to miette's column on that line to give the file's.
    column_shift: usize,
}

impl miette::SourceCode for Excerpted {
    fn read_span<'a>(
        &'a self,
        span: &SourceSpan,
        before: usize,
        after: usize,
    ) -> Result<Box<dyn SpanContents<'a> + 'a>, miette::MietteError> {
        let inner = self.text.read_span(span, before, after)?;
        let column = if inner.line() == self.line {
            inner.column() + self.column_shift
        } else {
            inner.column()
        };
        Ok(Box::new(MietteSpanContents::new_named(
            self.name.clone(),
            inner.data(),
            *inner.span(),
            inner.line() + self.first_line,
            column,
            inner.line_count(),
        )))
    }
}

/// The excerpt of `text` for `d` and the span to underline in it.
fn excerpted(
    name: &str,
    text: &str,
    d: &scene_format::Diagnostic,
) -> Option<(Excerpted, SourceSpan)> {
    let (span, location) = (d.span.clone()?, d.location?);
    let e = excerpt(text, span, location.line, 1);
    let line_start: usize = e.lines[..e.line].iter().map(|l| l.len() + 1).sum();
    let line = &e.lines[e.line];
    let byte = |chars: usize| {
        line.char_indices()
            .nth(chars)
            .map_or(line.len(), |(i, _)| i)
    };
    let start = byte(e.column);
    let end = byte(e.column + e.len);
    let source = Excerpted {
        name: name.to_string(),
        text: e.lines.join("\n"),
        first_line: e.first_line - 1,
        line: e.line,
        // miette counts the columns of the excerpt's line; the file's
        // column is further right when the line was windowed.
        column_shift: (location.column - 1).saturating_sub(e.column),
    };
    Some((
        source,
        SourceSpan::from(line_start + start..line_start + end),
    ))
}

/// The report of a scene error, ready for the terminal: one block per
/// diagnostic (the first `MAX_SHOWN`), with colours when `color` is set.
pub fn render(error: &SceneError, color: bool) -> String {
    error
        .files()
        .into_iter()
        .map(|e| render_file(e, color))
        .collect()
}

/// [`render`] of one file's error.
fn render_file(error: &SceneError, color: bool) -> String {
    let SceneError::Invalid {
        file,
        text,
        diagnostics,
    } = error
    else {
        return format!("error: {error}\n");
    };
    let theme = if color {
        miette::GraphicalTheme::unicode()
    } else {
        miette::GraphicalTheme::unicode_nocolor()
    };
    let handler = GraphicalReportHandler::new_themed(theme).with_context_lines(1);
    let name = file.display().to_string();
    let mut out = String::new();
    for d in diagnostics.iter().take(MAX_SHOWN) {
        let found = excerpted(&name, text, d);
        let message = escape_controls(&d.message);
        let message = match found {
            Some(_) => message,
            // Without a span miette shows no file; name it in the message.
            None => format!("{name}: {message}"),
        };
        let (source, span) = found.map_or((None, None), |(s, span)| (Some(s), Some(span)));
        let diagnostic = SceneDiagnostic {
            message,
            source,
            span,
            key_path: escape_controls(&d.path.to_string()),
        };
        // Writing to a String cannot fail.
        let _ = handler.render_report(&mut out, &diagnostic);
        out.push('\n');
    }
    if let Some(more) = more_problems(diagnostics.len()) {
        out += &format!("{name}: {more}\n");
    }
    out
}

/// Colours only on a terminal, and not when NO_COLOR is set (no-color.org).
pub fn color_wanted() -> bool {
    use std::io::IsTerminal;
    let no_color = matches!(std::env::var_os("NO_COLOR"), Some(v) if !v.is_empty());
    std::io::stderr().is_terminal() && !no_color
}

/// The loaded scene's warnings as `options` render it, one line each;
/// shown even when quiet.
pub fn warnings(loaded: &tracer_pipeline::Loaded, options: &tracer_pipeline::Options) {
    for line in loaded.warning_lines(options) {
        crate::console::note!("{line}");
    }
}

/// For `explain` and `compare`, which render every sample: a scene's
/// `time_limit` would make the render depend on the machine's speed.
pub fn time_limit_unused(loaded: &tracer_pipeline::Loaded, options: &tracer_pipeline::Options) {
    if let Some(limit) = loaded.time_limit_not_kept(options) {
        crate::console::note!(
            "note: the scene's time_limit ({limit} s) is not used here: every sample is rendered; \
             `tracer render` stops sooner when the limit runs out, so its pixels may be the mean of fewer samples"
        );
    }
}
