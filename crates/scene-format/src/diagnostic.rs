//! One problem found in a scene file, and where it is: the key path, the
//! message, and the span of the source text with its line and column.

use crate::key_path::KeyPath;
use std::ops::Range;

/// A line and column in the source text, both counted from 1; the column
/// counts characters, not bytes (what an editor shows).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Location {
    pub line: usize,
    pub column: usize,
}

impl Location {
    /// The location of a byte offset in `text`; columns count characters.
    /// Lines end at `\n`, `\r\n` or a lone `\r`.
    pub fn from_offset(text: &str, offset: usize) -> Location {
        Locator::new(text).location(offset)
    }
}

/// Locations of increasing offsets in one pass over the text, so locating
/// many diagnostics costs one reading of the file, not one each.
pub(crate) struct Locator<'a> {
    text: &'a str,
    offset: usize,
    at: Location,
}

impl<'a> Locator<'a> {
    pub(crate) fn new(text: &'a str) -> Self {
        Locator {
            text,
            offset: 0,
            at: Location { line: 1, column: 1 },
        }
    }

    /// The location of `offset`; cheapest when offsets come in order.
    pub(crate) fn location(&mut self, offset: usize) -> Location {
        let offset = floor_char_boundary(self.text, offset.min(self.text.len()));
        if offset < self.offset {
            *self = Locator::new(self.text);
        }
        let bytes = self.text.as_bytes();
        for (i, c) in self.text[self.offset..offset].char_indices() {
            let i = self.offset + i;
            let line_break = c == '\n' || (c == '\r' && bytes.get(i + 1) != Some(&b'\n'));
            if line_break {
                self.at = Location {
                    line: self.at.line + 1,
                    column: 1,
                };
            } else {
                self.at.column += 1;
            }
        }
        self.offset = offset;
        self.at
    }
}

/// `offset`, moved back to the start of the character it falls in.
pub(crate) fn floor_char_boundary(text: &str, mut offset: usize) -> usize {
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    offset
}

/// One problem in a scene file: what is wrong (`message`), at which key
/// (`path`), and, once located in the text, where (`span`, `location`).
/// Parse errors are located as they are made; validation gives a path
/// only, and the loader finds its span.
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
    /// A problem at `path`, not yet located in the text.
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
