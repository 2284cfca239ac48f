//! The key path of a key in TOML text that does not parse: the toml
//! crate's error (a duplicate key, a table defined twice) carries a span
//! but no path, and no span tree can be built from the file. The path is
//! read from the text before the span: the last table header (`[a.b]`,
//! `[[objects]]` counted to give `objects[2]`), the inline tables and
//! arrays open around the span, and the (dotted, quoted) key itself.
//!
//! One pass over the text up to the span, without recursion; lenient:
//! text it cannot read ends the walk with the path enclosing that point.

use crate::key_path::{KeyPath, Segment};
use std::collections::HashMap;
use std::ops::Range;

/// Where the key at a span was found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct KeyAt {
    /// The path of the key, or of the nearest enclosing table or array.
    pub path: KeyPath,
    /// The span is in a table header (`[camera]`), not a key = value.
    pub header: bool,
}

/// The key path of the key at `span` in `text`, from the text before it.
pub(super) fn key_at(text: &str, span: Range<usize>) -> KeyAt {
    Walker {
        bytes: text.as_bytes(),
        text,
        i: 0,
        span,
        table: KeyPath::root(),
        arrays_of_tables: HashMap::new(),
        stack: Vec::new(),
    }
    .walk()
}

enum Frame {
    /// An inline array at `path`, reading its element `index`.
    Array { path: KeyPath, index: usize },
    /// An inline table at `path`.
    Inline { path: KeyPath },
}

struct Walker<'a> {
    bytes: &'a [u8],
    text: &'a str,
    i: usize,
    span: Range<usize>,
    /// The path of the last table header.
    table: KeyPath,
    /// How many `[[x]]` headers each array of tables has had so far, by
    /// its resolved path (`objects[1].children`).
    arrays_of_tables: HashMap<String, usize>,
    stack: Vec<Frame>,
}

impl Walker<'_> {
    fn walk(mut self) -> KeyAt {
        loop {
            self.skip_trivia();
            if self.i >= self.bytes.len() || self.i > self.span.start {
                return self.enclosing();
            }
            let c = self.bytes[self.i];
            let found = match self.stack.last_mut() {
                None if c == b'[' => self.header(),
                None => {
                    let base = self.table.clone();
                    self.key_value(base)
                }
                Some(Frame::Array { index, .. }) => match c {
                    b']' => {
                        self.i += 1;
                        self.stack.pop();
                        Step::Go
                    }
                    b',' => {
                        *index += 1;
                        self.i += 1;
                        Step::Go
                    }
                    _ => {
                        let Some(Frame::Array { path, index }) = self.stack.last() else {
                            unreachable!()
                        };
                        let path = path.index(*index);
                        self.value(path)
                    }
                },
                Some(Frame::Inline { path }) => match c {
                    b'}' => {
                        self.i += 1;
                        self.stack.pop();
                        Step::Go
                    }
                    b',' => {
                        self.i += 1;
                        Step::Go
                    }
                    _ => {
                        let base = path.clone();
                        self.key_value(base)
                    }
                },
            };
            match found {
                Step::Go => {}
                Step::Found(at) => return at,
                Step::Stuck => return self.enclosing(),
            }
        }
    }

    /// The path of what is open at this point: the table, and the inline
    /// tables and arrays in it.
    fn enclosing(&self) -> KeyAt {
        let path = match self.stack.last() {
            None => self.table.clone(),
            Some(Frame::Array { path, index }) => path.index(*index),
            Some(Frame::Inline { path }) => path.clone(),
        };
        KeyAt {
            path,
            header: false,
        }
    }

    /// `[a.b]` or `[[a.b]]`.
    fn header(&mut self) -> Step {
        self.i += 1;
        let array = self.bytes.get(self.i) == Some(&b'[');
        if array {
            self.i += 1;
        }
        let Some(parts) = self.keys() else {
            return Step::Stuck;
        };
        let hit = self.hit(&parts);
        let mut path = KeyPath::root();
        for (n, (key, _)) in parts.iter().enumerate() {
            path.0.push(Segment::Key(key.clone()));
            let last = n + 1 == parts.len();
            if hit == Some(n) {
                return Step::Found(KeyAt { path, header: true });
            }
            if array && last {
                let count = self.arrays_of_tables.entry(path.to_string()).or_insert(0);
                path.0.push(Segment::Index(*count));
                *count += 1;
            } else if let Some(count) = self.arrays_of_tables.get(&path.to_string()) {
                path.0.push(Segment::Index(count.saturating_sub(1)));
            }
        }
        self.table = path;
        self.skip_spaces();
        let close: &[u8] = if array { b"]]" } else { b"]" };
        if !self.bytes[self.i..].starts_with(close) {
            return Step::Stuck;
        }
        self.i += close.len();
        Step::Go
    }

    /// `a.b = value` in the table or inline table at `base`.
    fn key_value(&mut self, mut base: KeyPath) -> Step {
        let Some(parts) = self.keys() else {
            return Step::Stuck;
        };
        let hit = self.hit(&parts);
        for (n, (key, _)) in parts.into_iter().enumerate() {
            base.0.push(Segment::Key(key));
            if hit == Some(n) {
                return Step::Found(KeyAt {
                    path: base,
                    header: false,
                });
            }
        }
        self.skip_spaces();
        if self.bytes.get(self.i) != Some(&b'=') {
            return Step::Stuck;
        }
        self.i += 1;
        self.skip_spaces();
        self.value(base)
    }

    /// A value at `path`: an array or inline table is opened; a string or
    /// other scalar is skipped.
    fn value(&mut self, path: KeyPath) -> Step {
        match self.bytes.get(self.i) {
            Some(b'[') => {
                self.i += 1;
                self.stack.push(Frame::Array { path, index: 0 });
            }
            Some(b'{') => {
                self.i += 1;
                self.stack.push(Frame::Inline { path });
            }
            Some(b'"' | b'\'') => {
                self.string();
            }
            Some(_) => {
                let start = self.i;
                while let Some(c) = self.bytes.get(self.i) {
                    if matches!(c, b',' | b']' | b'}' | b'\n' | b'\r' | b'#') {
                        break;
                    }
                    self.i += 1;
                }
                if self.i == start {
                    return Step::Stuck;
                }
            }
            None => return Step::Stuck,
        }
        Step::Go
    }

    /// The index of the last of `parts` that the span touches.
    fn hit(&self, parts: &[(String, Range<usize>)]) -> Option<usize> {
        let Range { start, end } = self.span.clone();
        let end = end.max(start + 1);
        parts
            .iter()
            .rposition(|(_, r)| r.start < end && r.end > start)
    }

    /// A dotted key: its parts, unquoted, with their spans.
    fn keys(&mut self) -> Option<Vec<(String, Range<usize>)>> {
        let mut parts = Vec::new();
        loop {
            self.skip_spaces();
            let start = self.i;
            let key = match self.bytes.get(self.i)? {
                b'"' | b'\'' => {
                    let raw = self.string()?;
                    unquote(raw)
                }
                _ => {
                    while self
                        .bytes
                        .get(self.i)
                        .is_some_and(|c| c.is_ascii_alphanumeric() || matches!(c, b'_' | b'-'))
                    {
                        self.i += 1;
                    }
                    if self.i == start {
                        return None;
                    }
                    self.text[start..self.i].to_string()
                }
            };
            parts.push((key, start..self.i));
            self.skip_spaces();
            if self.bytes.get(self.i) == Some(&b'.') {
                self.i += 1;
            } else {
                return Some(parts);
            }
        }
    }

    /// Skips a basic, literal or multi-line string; its text with quotes.
    fn string(&mut self) -> Option<&str> {
        let start = self.i;
        let quote = self.bytes[self.i];
        let triple = [quote; 3];
        let multi = self.bytes[self.i..].starts_with(&triple);
        self.i += if multi { 3 } else { 1 };
        loop {
            let c = *self.bytes.get(self.i)?;
            if c == b'\\' && quote == b'"' {
                self.i += 2;
                continue;
            }
            if !multi && c == b'\n' {
                return None;
            }
            if c == quote && (!multi || self.bytes[self.i..].starts_with(&triple)) {
                self.i += if multi { 3 } else { 1 };
                // Up to two more quotes may end a multi-line string.
                while multi && self.bytes.get(self.i) == Some(&quote) {
                    self.i += 1;
                }
                return self.text.get(start..self.i);
            }
            self.i += 1;
        }
    }

    fn skip_spaces(&mut self) {
        while matches!(self.bytes.get(self.i), Some(b' ' | b'\t')) {
            self.i += 1;
        }
    }

    /// Spaces, line ends and comments.
    fn skip_trivia(&mut self) {
        loop {
            match self.bytes.get(self.i) {
                Some(b' ' | b'\t' | b'\n' | b'\r') => self.i += 1,
                Some(b'#') => {
                    while self.bytes.get(self.i).is_some_and(|&c| c != b'\n') {
                        self.i += 1;
                    }
                }
                _ => return,
            }
        }
    }
}

enum Step {
    Go,
    Found(KeyAt),
    Stuck,
}

/// A quoted key's name: `'a b'` -> `a b`; `"a\"b"` -> `a"b`.
fn unquote(raw: &str) -> String {
    if let Some(inner) = raw.strip_prefix('\'') {
        return inner.strip_suffix('\'').unwrap_or(inner).to_string();
    }
    let inner = raw.strip_prefix('"').unwrap_or(raw);
    let inner = inner.strip_suffix('"').unwrap_or(inner);
    let mut out = String::new();
    let mut chars = inner.chars();
    while let Some(c) = chars.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        match chars.next() {
            Some('n') => out.push('\n'),
            Some('t') => out.push('\t'),
            Some('r') => out.push('\r'),
            Some('b') => out.push('\u{8}'),
            Some('f') => out.push('\u{c}'),
            Some('e') => out.push('\u{1b}'),
            Some(c @ ('u' | 'U' | 'x')) => {
                let n = match c {
                    'x' => 2,
                    'u' => 4,
                    _ => 8,
                };
                let hex: String = chars.by_ref().take(n).collect();
                match u32::from_str_radix(&hex, 16).ok().and_then(char::from_u32) {
                    Some(c) => out.push(c),
                    None => out.push_str(&hex),
                }
            }
            Some(c) => out.push(c),
            None => {}
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The path at the `@` in `marked`, with the marker removed; the span
    /// runs to the end of the key.
    fn at(marked: &str) -> (String, bool) {
        let start = marked.find('@').unwrap();
        let text = marked.replacen('@', "", 1);
        let end = text[start..]
            .find([' ', '=', ']', '.'])
            .map_or(text.len(), |n| start + n);
        let found = key_at(&text, start..end);
        (found.path.to_string(), found.header)
    }

    /// The toml crate's own error span on `text`, and the path there.
    fn toml_error(text: &str) -> (String, bool) {
        let e = toml::de::DeTable::parse(text).expect_err(text);
        let span = e.span().unwrap();
        let found = key_at(text, span);
        (found.path.to_string(), found.header)
    }

    fn key(p: &str) -> (String, bool) {
        (p.to_string(), false)
    }

    #[test]
    fn the_key_after_the_last_header() {
        assert_eq!(at("[camera]\nfov = 5\n@fov = 6\n"), key("camera.fov"));
        assert_eq!(at("a = 1\n@a = 2\n"), key("a"));
        assert_eq!(
            at("[materials.red]\n@diffuse = 1\n"),
            key("materials.red.diffuse")
        );
        assert_eq!(at("[ materials . red ]\n@x = 1\n"), key("materials.red.x"));
    }

    #[test]
    fn arrays_of_tables_are_counted() {
        let text = "[[objects]]\nmaterial = 'a'\n[[objects]]\nmaterial = 'b'\n@material = 'c'\n";
        assert_eq!(at(text), key("objects[1].material"));
        let text = "[[objects]]\n[[objects]]\n[[objects.kids]]\n[[objects.kids]]\n[objects.kids.sphere]\n@r = 1\n";
        assert_eq!(at(text), key("objects[1].kids[1].sphere.r"));
        let text = "[[a]]\n[[a.b]]\n[[a]]\n[[a.b]]\n@x = 1\n";
        assert_eq!(at(text), key("a[1].b[0].x"));
    }

    #[test]
    fn comments_and_strings_with_brackets_are_not_headers() {
        let text = "[camera]\n# [lights]\nname = \"[lights]\"\ns = '[x]'\nm = \"\"\"\n[lights]\n\"\"\"\nl = '''\n[y]\n'''\n@fov = 1\n";
        assert_eq!(at(text), key("camera.fov"));
        let text = "[camera]\neye = [\n  0, # [z]\n  [1],\n]\n@fov = 1\n";
        assert_eq!(at(text), key("camera.fov"));
        let text = "[camera]\ns = \"a\\\"[b]\"\n@fov = 1\n";
        assert_eq!(at(text), key("camera.fov"));
    }

    #[test]
    fn quoted_and_dotted_keys() {
        assert_eq!(
            at("[materials.\"my red\"]\n@diffuse = 1\n"),
            key("materials.\"my red\".diffuse")
        );
        assert_eq!(at("['a.b'.c]\n@d = 1\n"), key("\"a.b\".c.d"));
        assert_eq!(at("[camera]\nx.y = 1\nx.@y = 2\n"), key("camera.x.y"));
        assert_eq!(at("\"q\\u0041\" = 1\n@b = 2\n"), key("b"));
    }

    #[test]
    fn keys_in_inline_tables_and_arrays() {
        assert_eq!(at("[camera]\nt = { a = 1, @a = 2 }\n"), key("camera.t.a"));
        assert_eq!(
            at("objects = [{ m = 1 }, { m = 2, @m = 3 }]\n"),
            key("objects[1].m")
        );
        assert_eq!(
            at("x = [[1, 2], [{ a = { @b = 1 } }]]\n"),
            key("x[1][0].a.b")
        );
    }

    #[test]
    fn tables_defined_twice_are_headers() {
        assert_eq!(
            at("[camera]\nfov = 1\n[@camera]\n"),
            ("camera".to_string(), true)
        );
        assert_eq!(
            at("[materials.red]\n[materials.@red]\n"),
            ("materials.red".to_string(), true)
        );
    }

    #[test]
    fn agrees_with_the_toml_crates_spans() {
        assert_eq!(
            toml_error("[camera]\nfov = 1\nfov = 2\n"),
            key("camera.fov")
        );
        assert_eq!(
            toml_error("[camera]\nfov = 1\n[camera]\n"),
            ("camera".to_string(), true)
        );
        assert_eq!(
            toml_error("[[objects]]\nm = 1\n[[objects]]\nm = 1\nm = 2\n"),
            key("objects[1].m")
        );
        assert_eq!(toml_error("[c]\nx.y = 1\nx.y = 2\n"), key("c.x.y"));
        assert_eq!(toml_error("t = { a = 1, a = 2 }\n"), key("t.a"));
    }

    #[test]
    fn text_it_cannot_read_gives_the_enclosing_path() {
        assert_eq!(at("[camera]\n= 1\n@fov = 2\n"), key("camera"));
        assert_eq!(key_at("", 5..6).path, KeyPath::root());
        assert_eq!(key_at("[a]\n'unclosed\n", 10..11).path.to_string(), "a");
    }
}
