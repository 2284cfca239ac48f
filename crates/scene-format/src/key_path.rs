//! Key paths: `objects[2].sphere.radius`, the address of one value in a
//! scene file. Validation speaks in key paths only; `locate` finds where
//! a path is in the text.

use std::fmt;

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

#[cfg(test)]
mod tests {
    use super::*;

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
}
