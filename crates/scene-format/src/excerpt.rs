//! The part of the source a diagnostic shows: its line and neighbours, cut
//! to a window around the span on long lines, control characters made
//! visible. Both renderers (this crate's text report, the CLI's miette
//! report) use it, so a minified file is never printed whole and a terminal
//! escape inside a name never reaches the terminal.

use crate::diagnostic::floor_char_boundary;
use crate::visible::is_hidden_control;
use std::ops::Range;

/// Lines longer than this many characters are shown as a window of it.
pub const WIDTH: usize = 100;
/// Marks the text left out of a windowed line.
pub const CUT: &str = "...";
/// At most this many diagnostics are shown per file; the rest are counted.
pub const MAX_SHOWN: usize = 100;

/// The source lines around a span, ready to print.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Excerpt {
    /// The number (from 1) of the first line in `lines`.
    pub first_line: usize,
    /// The lines shown, windowed and made printable.
    pub lines: Vec<String>,
    /// The index in `lines` of the line the span starts on.
    pub line: usize,
    /// Where the underline starts in that line, in characters from 0.
    pub column: usize,
    /// How many characters to underline, at least 1.
    pub len: usize,
}

/// Line breaks are `\n`, `\r\n` and a lone `\r` (old Mac files).
fn is_break(bytes: &[u8], i: usize) -> bool {
    match bytes[i] {
        b'\n' => true,
        b'\r' => bytes.get(i + 1) != Some(&b'\n'),
        _ => false,
    }
}

/// The byte ranges of the lines of `text`, without their line breaks.
fn line_of(text: &str, offset: usize) -> Range<usize> {
    let bytes = text.as_bytes();
    let start = (0..offset)
        .rev()
        .find(|&i| is_break(bytes, i))
        .map_or(0, |i| i + 1);
    let end = (offset..bytes.len())
        .find(|&i| bytes[i] == b'\n' || bytes[i] == b'\r')
        .unwrap_or(bytes.len());
    start..end
}

/// The line before the one starting at `start`, if any.
fn previous_line(text: &str, start: usize) -> Option<Range<usize>> {
    if start == 0 {
        return None;
    }
    let mut end = start - 1;
    if end > 0 && text.as_bytes()[end] == b'\n' && text.as_bytes()[end - 1] == b'\r' {
        end -= 1;
    }
    Some(line_of(text, end))
}

/// The line after the one ending at `end`, if any.
fn next_line(text: &str, end: usize) -> Option<Range<usize>> {
    let bytes = text.as_bytes();
    if end >= bytes.len() {
        return None;
    }
    let next = if bytes[end] == b'\r' && bytes.get(end + 1) == Some(&b'\n') {
        end + 2
    } else {
        end + 1
    };
    (next < bytes.len()).then(|| line_of(text, next))
}

/// A character as printed: tabs as one space, control characters (a
/// terminal escape, a bell) and bidirectional controls as the replacement
/// character, so the caret stays aligned and the terminal is not driven
/// by the file.
pub fn printable(c: char) -> char {
    match c {
        '\t' => ' ',
        c if is_hidden_control(c) => '\u{FFFD}',
        c => c,
    }
}

/// The excerpt of `text` showing `span` with `context` lines either side.
/// `line_number` is the number of the span's line (from 1).
pub fn excerpt(text: &str, span: Range<usize>, line_number: usize, context: usize) -> Excerpt {
    let start = floor_char_boundary(text, span.start.min(text.len()));
    let end = floor_char_boundary(text, span.end.clamp(start, text.len()));
    let main = line_of(text, start);
    let column = text[main.start..start].chars().count();
    let len = text[start..end.min(main.end).max(start)]
        .chars()
        .count()
        .max(1);
    let line_chars = text[main.clone()].chars().count();
    // The window: the whole line when short; else WIDTH columns with the
    // caret in the middle, the same columns for the neighbours.
    let skip = if line_chars <= WIDTH {
        0
    } else {
        column.saturating_sub(WIDTH / 2)
    };
    let cut = |range: Range<usize>| window(&text[range], skip);
    let mut before = Vec::new();
    let mut at = main.start;
    while before.len() < context {
        match previous_line(text, at) {
            Some(r) => {
                at = r.start;
                before.push(cut(r));
            }
            None => break,
        }
    }
    before.reverse();
    let mut lines = before;
    let line = lines.len();
    lines.push(cut(main.clone()));
    let mut at = main.end;
    for _ in 0..context {
        match next_line(text, at) {
            Some(r) => {
                at = r.end;
                lines.push(cut(r));
            }
            None => break,
        }
    }
    let marker = if skip > 0 { CUT.len() } else { 0 };
    let column = column - skip + marker;
    let shown = lines[line].chars().count();
    Excerpt {
        first_line: line_number - line,
        line,
        column,
        len: len.min(shown.saturating_sub(column)).max(1),
        lines,
    }
}

/// `line` from character `skip` on, at most WIDTH characters, with CUT
/// where text was left out.
fn window(line: &str, skip: usize) -> String {
    let total = line.chars().count();
    let mut out = String::new();
    if skip > 0 {
        out += CUT;
    }
    out.extend(line.chars().skip(skip).take(WIDTH).map(printable));
    if skip > 0 && total > skip + WIDTH {
        out += CUT;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::visible::escape_controls;

    #[test]
    fn lone_carriage_returns_end_lines() {
        let text = "a = 1\rb = 2\rc = 3\r";
        let at = text.find('b').unwrap();
        let e = excerpt(text, at..at + 1, 2, 1);
        assert_eq!(e.lines, ["a = 1", "b = 2", "c = 3"]);
        assert_eq!((e.first_line, e.line, e.column), (1, 1, 0));
    }

    #[test]
    fn long_lines_are_windowed_around_the_span() {
        let text = format!("{}X{}", " ".repeat(70_000), "y".repeat(70_000));
        let e = excerpt(&text, 70_000..70_001, 1, 1);
        assert_eq!(e.lines.len(), 1);
        assert!(e.lines[0].len() <= WIDTH + 2 * CUT.len());
        assert_eq!(e.lines[0].chars().nth(e.column), Some('X'));
    }

    #[test]
    fn control_characters_are_not_echoed() {
        let text = "name = \"\u{1b}[31mred\"\n";
        let e = excerpt(text, 0..4, 1, 0);
        assert!(!e.lines[0].contains('\u{1b}'));
        assert_eq!(escape_controls("a\u{1b}b"), "a\\u{1b}b");
    }
}
