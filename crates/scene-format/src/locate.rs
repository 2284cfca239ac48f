//! Key paths (`objects[2].sphere.radius`) and where they are in the source
//! text. Validation speaks in key paths only; this module maps a path to a
//! span by walking a span-keeping parse of the file, so any key added to the
//! model gets located errors without further work.

use crate::Format;
use std::fmt;
use std::ops::Range;

/// One step of a key path: a table key or an array index.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Segment {
    Key(String),
    Index(usize),
}

/// A path from the top of the file to one value, e.g. `objects[2].sphere.radius`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct KeyPath(pub Vec<Segment>);

impl KeyPath {
    pub fn root() -> KeyPath {
        KeyPath(Vec::new())
    }

    /// This path extended by a table key.
    pub fn key(&self, key: &str) -> KeyPath {
        let mut p = self.clone();
        p.0.push(Segment::Key(key.to_string()));
        p
    }

    /// This path extended by an array index.
    pub fn index(&self, i: usize) -> KeyPath {
        let mut p = self.clone();
        p.0.push(Segment::Index(i));
        p
    }

    pub fn is_root(&self) -> bool {
        self.0.is_empty()
    }

    /// The path without its last step (the table holding the value).
    pub fn parent(&self) -> KeyPath {
        let mut p = self.clone();
        p.0.pop();
        p
    }

    /// The last key of the path, if it ends in a key.
    pub fn last_key(&self) -> Option<&str> {
        match self.0.last() {
            Some(Segment::Key(k)) => Some(k),
            _ => None,
        }
    }

    /// Where a key of the table at this path sits, as a user says it:
    /// "in [camera]", "in [materials.red]", "in `objects[2].sphere`", or
    /// "at the top level".
    pub fn in_table(&self) -> String {
        if self.is_root() {
            "at the top level".to_string()
        } else if self.0.iter().all(|s| matches!(s, Segment::Key(_))) {
            format!("in [{self}]")
        } else {
            format!("in `{self}`")
        }
    }

    /// Converts serde_path_to_error's path; unknown steps end it.
    pub fn from_serde(path: &serde_path_to_error::Path) -> KeyPath {
        use serde_path_to_error::Segment as S;
        let mut out = Vec::new();
        for segment in path.iter() {
            match segment {
                S::Seq { index } => out.push(Segment::Index(*index)),
                S::Map { key } => out.push(Segment::Key(key.clone())),
                S::Enum { .. } => {}
                S::Unknown => break,
            }
        }
        KeyPath(out)
    }
}

impl KeyPath {
    /// Reads a path as `Display` writes it: `objects[2].sphere.radius`,
    /// `materials."my red".diffuse`. Lenient: text it cannot split is
    /// taken as a key.
    pub fn parse(text: &str) -> KeyPath {
        let mut segments = Vec::new();
        let mut chars = text.chars().peekable();
        let mut key = String::new();
        while let Some(c) = chars.next() {
            match c {
                '.' => push_key(&mut segments, &mut key),
                '"' if key.is_empty() => {
                    let mut quoted = String::from('"');
                    for q in chars.by_ref() {
                        quoted.push(q);
                        if q == '"' && !quoted.ends_with("\\\"") {
                            break;
                        }
                    }
                    key = serde_json::from_str(&quoted).unwrap_or(quoted);
                }
                '[' => {
                    push_key(&mut segments, &mut key);
                    let digits: String = chars.by_ref().take_while(|&d| d != ']').collect();
                    match digits.parse() {
                        Ok(i) => segments.push(Segment::Index(i)),
                        Err(_) => segments.push(Segment::Key(format!("[{digits}]"))),
                    }
                }
                _ => key.push(c),
            }
        }
        push_key(&mut segments, &mut key);
        KeyPath(segments)
    }
}

fn push_key(segments: &mut Vec<Segment>, key: &mut String) {
    if !key.is_empty() {
        segments.push(Segment::Key(std::mem::take(key)));
    }
}

/// Paths written as text (`"camera.fov"`) work wherever a path is taken,
/// so validation code may build them either way.
impl From<&str> for KeyPath {
    fn from(text: &str) -> KeyPath {
        KeyPath::parse(text)
    }
}

impl From<String> for KeyPath {
    fn from(text: String) -> KeyPath {
        KeyPath::parse(&text)
    }
}

impl From<&String> for KeyPath {
    fn from(text: &String) -> KeyPath {
        KeyPath::parse(text)
    }
}

impl From<&KeyPath> for KeyPath {
    fn from(path: &KeyPath) -> KeyPath {
        path.clone()
    }
}

impl PartialEq<str> for KeyPath {
    fn eq(&self, other: &str) -> bool {
        *self == KeyPath::parse(other)
    }
}

impl PartialEq<&str> for KeyPath {
    fn eq(&self, other: &&str) -> bool {
        *self == KeyPath::parse(other)
    }
}

impl fmt::Display for KeyPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, segment) in self.0.iter().enumerate() {
            match segment {
                Segment::Index(n) => write!(f, "[{n}]")?,
                Segment::Key(k) => {
                    if i > 0 {
                        f.write_str(".")?;
                    }
                    if is_bare_key(k) {
                        f.write_str(k)?;
                    } else {
                        write!(f, "{k:?}")?;
                    }
                }
            }
        }
        Ok(())
    }
}

/// A key TOML accepts without quotes.
fn is_bare_key(k: &str) -> bool {
    !k.is_empty()
        && k.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// Where a key path points in the text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Located {
    /// The span of the value (or of the nearest enclosing value found).
    pub value: Range<usize>,
    /// The span of the key naming the value, when the path ends in a key
    /// that is present.
    pub key: Option<Range<usize>>,
    /// Whether the whole path was found; if not, the spans are those of the
    /// deepest table on the way (e.g. for a missing key).
    pub exact: bool,
}

/// The location of `path` in `text`, or `None` if the text does not parse.
pub fn locate(text: &str, format: Format, path: &KeyPath) -> Option<Located> {
    Some(tree(text, format)?.locate(path))
}

/// The span-keeping tree of `text`, or `None` if the text does not parse.
pub fn tree(text: &str, format: Format) -> Option<Node> {
    match format {
        Format::Toml => toml_tree(text),
        Format::Json => json::parse(text).ok(),
    }
}

/// A parsed document reduced to what locating needs: spans and nesting.
#[derive(Debug)]
pub struct Node {
    pub span: Range<usize>,
    pub kind: NodeKind,
}

#[derive(Debug)]
pub enum NodeKind {
    /// Entries in file order: key, key span, value.
    Table(Vec<(String, Range<usize>, Node)>),
    Array(Vec<Node>),
    Scalar,
}

impl Node {
    pub fn locate(&self, path: &KeyPath) -> Located {
        let mut node = self;
        let mut key = None;
        for segment in &path.0 {
            let next = match (&node.kind, segment) {
                // With duplicate keys (JSON) the last one is the one read.
                (NodeKind::Table(entries), Segment::Key(k)) => entries
                    .iter()
                    .rev()
                    .find(|(name, _, _)| name == k)
                    .map(|(_, span, value)| (Some(span.clone()), value)),
                (NodeKind::Array(items), Segment::Index(i)) => items.get(*i).map(|v| (None, v)),
                _ => None,
            };
            match next {
                Some((k, n)) => {
                    key = k;
                    node = n;
                }
                None => {
                    return Located {
                        value: node.span.clone(),
                        key,
                        exact: false,
                    }
                }
            }
        }
        Located {
            value: node.span.clone(),
            key,
            exact: true,
        }
    }
}

fn toml_tree(text: &str) -> Option<Node> {
    let table = toml::de::DeTable::parse(text).ok()?;
    let span = table.span();
    Some(Node {
        span,
        kind: toml_table(table.get_ref()),
    })
}

fn toml_table(table: &toml::de::DeTable<'_>) -> NodeKind {
    NodeKind::Table(
        table
            .iter()
            .map(|(k, v)| (k.get_ref().to_string(), k.span(), toml_node(v)))
            .collect(),
    )
}

fn toml_node(value: &toml::Spanned<toml::de::DeValue<'_>>) -> Node {
    use toml::de::DeValue;
    let kind = match value.get_ref() {
        DeValue::Table(t) => toml_table(t),
        DeValue::Array(a) => NodeKind::Array(a.iter().map(toml_node).collect()),
        _ => NodeKind::Scalar,
    };
    Node {
        span: value.span(),
        kind,
    }
}

/// A small span-keeping JSON reader. serde_json keeps no spans and takes
/// the last of duplicate keys silently; this one keeps every key with its
/// span so both can be reported.
pub mod json {
    use super::{Node, NodeKind};
    use std::ops::Range;

    /// Deeper nesting than any scene needs; keeps the reader off the stack limit.
    const MAX_DEPTH: usize = 128;

    /// The document tree, or the offset where the text stops being JSON.
    pub fn parse(text: &str) -> Result<Node, usize> {
        let mut p = Parser {
            bytes: text.as_bytes(),
            pos: 0,
        };
        let node = p.value(0)?;
        p.skip_ws();
        if p.pos != p.bytes.len() {
            return Err(p.pos);
        }
        Ok(node)
    }

    /// Every key that appears twice in one object: (key, span of the
    /// second appearance, span of the first), in file order.
    pub fn duplicate_keys(node: &Node) -> Vec<(Vec<super::Segment>, Range<usize>, Range<usize>)> {
        let mut out = Vec::new();
        walk_duplicates(node, &mut Vec::new(), &mut out);
        out
    }

    type Duplicate = (Vec<super::Segment>, Range<usize>, Range<usize>);

    fn walk_duplicates(node: &Node, path: &mut Vec<super::Segment>, out: &mut Vec<Duplicate>) {
        match &node.kind {
            NodeKind::Table(entries) => {
                for (i, (key, span, value)) in entries.iter().enumerate() {
                    path.push(super::Segment::Key(key.clone()));
                    if let Some((_, first, _)) = entries[..i].iter().find(|(k, _, _)| k == key) {
                        out.push((path.clone(), span.clone(), first.clone()));
                    }
                    walk_duplicates(value, path, out);
                    path.pop();
                }
            }
            NodeKind::Array(items) => {
                for (i, item) in items.iter().enumerate() {
                    path.push(super::Segment::Index(i));
                    walk_duplicates(item, path, out);
                    path.pop();
                }
            }
            NodeKind::Scalar => {}
        }
    }

    struct Parser<'a> {
        bytes: &'a [u8],
        pos: usize,
    }

    impl Parser<'_> {
        fn peek(&self) -> Option<u8> {
            self.bytes.get(self.pos).copied()
        }

        fn skip_ws(&mut self) {
            while matches!(self.peek(), Some(b' ' | b'\t' | b'\n' | b'\r')) {
                self.pos += 1;
            }
        }

        fn expect(&mut self, b: u8) -> Result<(), usize> {
            if self.peek() == Some(b) {
                self.pos += 1;
                Ok(())
            } else {
                Err(self.pos)
            }
        }

        fn value(&mut self, depth: usize) -> Result<Node, usize> {
            if depth > MAX_DEPTH {
                return Err(self.pos);
            }
            self.skip_ws();
            let start = self.pos;
            let kind = match self.peek().ok_or(self.pos)? {
                b'{' => self.object(depth)?,
                b'[' => self.array(depth)?,
                b'"' => {
                    self.string()?;
                    NodeKind::Scalar
                }
                _ => {
                    self.scalar()?;
                    NodeKind::Scalar
                }
            };
            Ok(Node {
                span: start..self.pos,
                kind,
            })
        }

        fn object(&mut self, depth: usize) -> Result<NodeKind, usize> {
            self.expect(b'{')?;
            let mut entries = Vec::new();
            self.skip_ws();
            if self.peek() == Some(b'}') {
                self.pos += 1;
                return Ok(NodeKind::Table(entries));
            }
            loop {
                self.skip_ws();
                let key_start = self.pos;
                let key = self.string()?;
                let key_span = key_start..self.pos;
                self.skip_ws();
                self.expect(b':')?;
                let value = self.value(depth + 1)?;
                entries.push((key, key_span, value));
                self.skip_ws();
                match self.peek() {
                    Some(b',') => self.pos += 1,
                    Some(b'}') => {
                        self.pos += 1;
                        return Ok(NodeKind::Table(entries));
                    }
                    _ => return Err(self.pos),
                }
            }
        }

        fn array(&mut self, depth: usize) -> Result<NodeKind, usize> {
            self.expect(b'[')?;
            let mut items = Vec::new();
            self.skip_ws();
            if self.peek() == Some(b']') {
                self.pos += 1;
                return Ok(NodeKind::Array(items));
            }
            loop {
                items.push(self.value(depth + 1)?);
                self.skip_ws();
                match self.peek() {
                    Some(b',') => self.pos += 1,
                    Some(b']') => {
                        self.pos += 1;
                        return Ok(NodeKind::Array(items));
                    }
                    _ => return Err(self.pos),
                }
            }
        }

        /// A string, decoded (escapes matter: keys are compared by value).
        fn string(&mut self) -> Result<String, usize> {
            self.expect(b'"')?;
            let mut out = Vec::new();
            loop {
                let b = self.peek().ok_or(self.pos)?;
                self.pos += 1;
                match b {
                    b'"' => return String::from_utf8(out).map_err(|_| self.pos),
                    b'\\' => self.escape(&mut out)?,
                    _ => out.push(b),
                }
            }
        }

        fn escape(&mut self, out: &mut Vec<u8>) -> Result<(), usize> {
            let b = self.peek().ok_or(self.pos)?;
            self.pos += 1;
            let c = match b {
                b'"' => '"',
                b'\\' => '\\',
                b'/' => '/',
                b'b' => '\u{8}',
                b'f' => '\u{c}',
                b'n' => '\n',
                b'r' => '\r',
                b't' => '\t',
                b'u' => self.unicode_escape()?,
                _ => return Err(self.pos - 1),
            };
            let mut buf = [0; 4];
            out.extend_from_slice(c.encode_utf8(&mut buf).as_bytes());
            Ok(())
        }

        fn unicode_escape(&mut self) -> Result<char, usize> {
            let hi = self.hex4()?;
            if (0xD800..0xDC00).contains(&hi) {
                // A surrogate pair: \uD83D\uDE00.
                if self.bytes.get(self.pos..self.pos + 2) == Some(b"\\u") {
                    self.pos += 2;
                    let lo = self.hex4()?;
                    if (0xDC00..0xE000).contains(&lo) {
                        let c = 0x10000 + ((hi - 0xD800) << 10) + (lo - 0xDC00);
                        return char::from_u32(c).ok_or(self.pos);
                    }
                }
                return Ok(char::REPLACEMENT_CHARACTER);
            }
            Ok(char::from_u32(hi).unwrap_or(char::REPLACEMENT_CHARACTER))
        }

        fn hex4(&mut self) -> Result<u32, usize> {
            let digits = self.bytes.get(self.pos..self.pos + 4).ok_or(self.pos)?;
            let s = std::str::from_utf8(digits).map_err(|_| self.pos)?;
            let v = u32::from_str_radix(s, 16).map_err(|_| self.pos)?;
            self.pos += 4;
            Ok(v)
        }

        /// A number, `true`, `false` or `null`; checked loosely, since
        /// serde_json has already accepted the text when spans are wanted.
        fn scalar(&mut self) -> Result<(), usize> {
            let start = self.pos;
            while matches!(
                self.peek(),
                Some(b'0'..=b'9' | b'-' | b'+' | b'.' | b'e' | b'E' | b'a'..=b'z')
            ) {
                self.pos += 1;
            }
            if self.pos == start {
                Err(self.pos)
            } else {
                Ok(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn path(steps: &[Segment]) -> KeyPath {
        KeyPath(steps.to_vec())
    }

    fn k(s: &str) -> Segment {
        Segment::Key(s.to_string())
    }

    #[test]
    fn key_paths_print_as_users_write_them() {
        let p = KeyPath::root()
            .key("objects")
            .index(2)
            .key("sphere")
            .key("radius");
        assert_eq!(p.to_string(), "objects[2].sphere.radius");
        assert_eq!(
            KeyPath::root().key("materials").key("my red").to_string(),
            "materials.\"my red\""
        );
        assert_eq!(KeyPath::root().key("camera").in_table(), "in [camera]");
        assert_eq!(
            KeyPath::root().key("objects").index(0).in_table(),
            "in `objects[0]`"
        );
        assert_eq!(KeyPath::root().in_table(), "at the top level");
    }

    #[test]
    fn key_paths_read_back_what_they_print() {
        for text in [
            "objects[2].sphere.radius",
            "materials.\"my red\".diffuse",
            "materials.\"a.b\"",
            "lights[0]",
            "[3]",
            "",
        ] {
            let path = KeyPath::parse(text);
            assert_eq!(path.to_string(), text);
        }
        assert_eq!(
            KeyPath::parse("objects[2].sphere"),
            KeyPath::root().key("objects").index(2).key("sphere")
        );
        assert_eq!(
            KeyPath::parse("materials.\"a.b\"").0,
            vec![k("materials"), k("a.b")]
        );
        assert_eq!(KeyPath::root().key("camera").key("fov"), "camera.fov");
    }

    #[test]
    fn toml_paths_find_keys_and_values() {
        let text =
            "[camera]\nfov = 50\n\n[[objects]]\nsphere = { center = [0, 0, 0], radius = 1.6 }\n";
        let at = |p: &KeyPath| {
            let l = locate(text, Format::Toml, p).unwrap();
            (&text[l.value.clone()], l.key.map(|k| &text[k]), l.exact)
        };
        assert_eq!(
            at(&path(&[k("camera"), k("fov")])),
            ("50", Some("fov"), true)
        );
        assert_eq!(
            at(&path(&[
                k("objects"),
                Segment::Index(0),
                k("sphere"),
                k("radius")
            ])),
            ("1.6", Some("radius"), true)
        );
        let missing = locate(text, Format::Toml, &path(&[k("camera"), k("eye")])).unwrap();
        assert!(!missing.exact);
        assert_eq!(missing.key.map(|k| &text[k]), Some("camera"));
    }

    #[test]
    fn json_paths_find_keys_and_values() {
        let text =
            r#"{"camera": {"fov": 50, "eye": [0, 0, 1]}, "objects": [{"sphere": {"radius": -1}}]}"#;
        let l = locate(
            text,
            Format::Json,
            &path(&[k("objects"), Segment::Index(0), k("sphere"), k("radius")]),
        )
        .unwrap();
        assert_eq!(&text[l.value], "-1");
        assert_eq!(&text[l.key.unwrap()], "\"radius\"");
        let l = locate(text, Format::Json, &path(&[k("camera"), k("eye")])).unwrap();
        assert_eq!(&text[l.value], "[0, 0, 1]");
    }

    #[test]
    fn json_reader_finds_duplicates_and_rejects_junk() {
        let text = r#"{"a": 1, "b": {"c": 1, "c": 2}, "a": 3}"#;
        let tree = json::parse(text).unwrap();
        let dups = json::duplicate_keys(&tree);
        assert_eq!(dups.len(), 2);
        assert_eq!(KeyPath(dups[0].0.clone()).to_string(), "b.c");
        assert_eq!(&text[dups[0].1.clone()], "\"c\"");
        assert_eq!(KeyPath(dups[1].0.clone()).to_string(), "a");
        assert!(json::parse("{\"a\": }").is_err());
        assert!(json::parse("[1, 2").is_err());
        assert!(json::parse(&"[".repeat(10_000)).is_err());
        // Escaped keys compare by value.
        let tree = json::parse(r#"{"\u0061": 1, "a": 2}"#).unwrap();
        assert_eq!(json::duplicate_keys(&tree).len(), 1);
    }
}
