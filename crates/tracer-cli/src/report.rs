//! Scene errors shown as a user reads them: the message, the file, line
//! and column, the source line with the key path under a caret (miette).

use miette::{Diagnostic, GraphicalReportHandler, LabeledSpan, NamedSource, SourceSpan};
use scene_format::SceneError;
use std::fmt;

/// One scene diagnostic in miette's terms.
#[derive(Debug)]
struct SceneDiagnostic {
    message: String,
    source: NamedSource<String>,
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
        self.span.map(|_| &self.source as &dyn miette::SourceCode)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        let span = self.span?;
        let label = (!self.key_path.is_empty()).then(|| self.key_path.clone());
        Some(Box::new(std::iter::once(LabeledSpan::new_with_span(
            label, span,
        ))))
    }
}

/// The report of a scene error, ready for the terminal: one block per
/// diagnostic, with colours when `color` is set.
pub fn render(error: &SceneError, color: bool) -> String {
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
    for d in diagnostics {
        let message = match d.location {
            Some(_) => d.message.clone(),
            // Without a span miette shows no file; name it in the message.
            None => format!("{name}: {}", d.message),
        };
        let diagnostic = SceneDiagnostic {
            message,
            source: NamedSource::new(&name, text.clone()),
            span: d.span.clone().map(SourceSpan::from),
            key_path: d.path.to_string(),
        };
        // Writing to a String cannot fail.
        let _ = handler.render_report(&mut out, &diagnostic);
        out.push('\n');
    }
    out
}

/// Colours only on a terminal, and not when NO_COLOR is set (no-color.org).
pub fn color_wanted() -> bool {
    use std::io::IsTerminal;
    let no_color = matches!(std::env::var_os("NO_COLOR"), Some(v) if !v.is_empty());
    std::io::stderr().is_terminal() && !no_color
}

/// The loaded scene's warnings, one line each; shown even when quiet.
pub fn warnings(loaded: &tracer_pipeline::Loaded) {
    for w in &loaded.warnings {
        crate::console::note!(
            "warning: {}: `{}`: {}",
            loaded.name.display(),
            w.path,
            w.message
        );
    }
}
