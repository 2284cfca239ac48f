//! Text that came from a file or a file name (a material's name, an
//! image's path) as a terminal or a page shows it: control characters (a
//! terminal's escape sequences, a bell, a carriage return) and the
//! invisible characters that reorder text (bidirectional overrides,
//! embeddings, isolates and marks) written as visible escapes such as
//! `\u{1b}` and `\u{202e}`, so that no name drives the terminal or passes
//! for another name. Every message, report and page of the tracer that
//! shows such text goes through here.

use std::fmt;

/// Whether `c` is shown as an escape: a control character (Unicode's Cc:
/// C0, DEL, C1) or a bidirectional control (Unicode's Bidi_Control).
pub fn is_hidden_control(c: char) -> bool {
    c.is_control() || is_bidi_control(c)
}

/// The characters of Unicode's Bidi_Control property: the Arabic letter
/// mark, the left-to-right and right-to-left marks, the embeddings and
/// overrides (U+202A to U+202E) and the isolates (U+2066 to U+2069).
fn is_bidi_control(c: char) -> bool {
    matches!(
        c,
        '\u{061C}' | '\u{200E}' | '\u{200F}' | '\u{202A}'..='\u{202E}' | '\u{2066}'..='\u{2069}'
    )
}

/// `text` with every [`is_hidden_control`] character (line breaks too)
/// written as its escape, e.g. `\u{1b}`: for one line of a message.
pub fn escape_controls(text: &str) -> String {
    escaped(text, |_| false)
}

/// [`escape_controls`], keeping line breaks and tabs: for text of several
/// lines (a pixel's explanation, a message on stderr).
pub fn escape_controls_in_lines(text: &str) -> String {
    escaped(text, |c| c == '\n' || c == '\t')
}

fn escaped(text: &str, kept: impl Fn(char) -> bool) -> String {
    let hidden = |c: char| is_hidden_control(c) && !kept(c);
    if !text.chars().any(hidden) {
        return text.to_string();
    }
    text.chars()
        .map(|c| match c {
            c if hidden(c) => c.escape_unicode().to_string(),
            c => c.to_string(),
        })
        .collect()
}

/// A `fmt::Write` that writes through to `inner` with control characters
/// escaped as [`escape_controls_in_lines`] does: text of any length
/// escaped as it is written, never held whole.
pub struct VisibleWriter<W> {
    pub inner: W,
}

impl<W: fmt::Write> fmt::Write for VisibleWriter<W> {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let mut rest = s;
        while let Some((i, c)) = rest
            .char_indices()
            .find(|&(_, c)| is_hidden_control(c) && c != '\n' && c != '\t')
        {
            self.inner.write_str(&rest[..i])?;
            write!(self.inner, "{}", c.escape_unicode())?;
            rest = &rest[i + c.len_utf8()..];
        }
        self.inner.write_str(rest)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fmt::Write;

    #[test]
    fn terminal_escapes_and_bidi_overrides_are_made_visible() {
        let name = "red\u{1b}]0;PWNED\u{7}\u{1b}[2J";
        assert_eq!(escape_controls(name), "red\\u{1b}]0;PWNED\\u{7}\\u{1b}[2J");
        // Right-to-left override: "alice\u{202e}gnp.bob" shows as alicebob.png.
        assert_eq!(
            escape_controls("alice\u{202e}gnp.bob"),
            "alice\\u{202e}gnp.bob"
        );
        // C1 controls (0x9b is a CSI on some terminals) and DEL.
        assert_eq!(escape_controls("a\u{9b}2Jb\u{7f}"), "a\\u{9b}2Jb\\u{7f}");
        for c in ['\u{200e}', '\u{200f}', '\u{61c}', '\u{2066}', '\u{2069}'] {
            assert!(escape_controls(&c.to_string()).starts_with("\\u{"), "{c:?}");
        }
        // Letters of right-to-left scripts themselves are text, kept.
        assert_eq!(escape_controls("שלום"), "שלום");
        assert_eq!(escape_controls("a\nb"), "a\\u{a}b");
        assert_eq!(escape_controls_in_lines("a\n\tb\r\n"), "a\n\tb\\u{d}\n");
    }

    #[test]
    fn the_writer_escapes_as_the_function_does_across_writes() {
        let mut out = VisibleWriter {
            inner: String::new(),
        };
        for part in ["x\u{1b}[2J", "\n", "\u{202e}y", "z\r"] {
            out.write_str(part).unwrap();
        }
        assert_eq!(
            out.inner,
            escape_controls_in_lines("x\u{1b}[2J\n\u{202e}yz\r")
        );
    }
}
