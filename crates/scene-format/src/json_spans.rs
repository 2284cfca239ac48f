//! A small span-keeping JSON reader. serde_json keeps no spans and takes
//! the last of duplicate keys silently; this one keeps every key with its
//! span so both can be reported.

use crate::key_path::Segment;
use crate::span_node::{Node, NodeKind};
use std::collections::hash_map::{Entry, HashMap};
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
pub fn duplicate_keys(node: &Node) -> Vec<(Vec<Segment>, Range<usize>, Range<usize>)> {
    let mut out = Vec::new();
    walk_duplicates(node, &mut Vec::new(), &mut out);
    out
}

type Duplicate = (Vec<Segment>, Range<usize>, Range<usize>);

fn walk_duplicates(node: &Node, path: &mut Vec<Segment>, out: &mut Vec<Duplicate>) {
    match &node.kind {
        NodeKind::Table(entries) => {
            // By hash: a table of 100k names must not take n^2 comparisons.
            let mut first_seen: HashMap<&str, &Range<usize>> = HashMap::new();
            for (key, span, value) in entries {
                path.push(Segment::Key(key.clone()));
                match first_seen.entry(key.as_str()) {
                    Entry::Occupied(first) => {
                        out.push((path.clone(), span.clone(), (*first.get()).clone()))
                    }
                    Entry::Vacant(slot) => {
                        slot.insert(span);
                    }
                }
                walk_duplicates(value, path, out);
                path.pop();
            }
        }
        NodeKind::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                path.push(Segment::Index(i));
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::KeyPath;

    #[test]
    fn json_reader_finds_duplicates_and_rejects_junk() {
        let text = r#"{"a": 1, "b": {"c": 1, "c": 2}, "a": 3}"#;
        let tree = parse(text).unwrap();
        let dups = duplicate_keys(&tree);
        assert_eq!(dups.len(), 2);
        assert_eq!(KeyPath(dups[0].0.clone()).to_string(), "b.c");
        assert_eq!(&text[dups[0].1.clone()], "\"c\"");
        assert_eq!(KeyPath(dups[1].0.clone()).to_string(), "a");
        assert!(parse("{\"a\": }").is_err());
        assert!(parse("[1, 2").is_err());
        assert!(parse(&"[".repeat(10_000)).is_err());
        // Escaped keys compare by value.
        let tree = parse(r#"{"\u0061": 1, "a": 2}"#).unwrap();
        assert_eq!(duplicate_keys(&tree).len(), 1);
    }
}
