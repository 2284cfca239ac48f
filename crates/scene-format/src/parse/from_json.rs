//! JSON text to a value, through serde_json, with what serde_json lets
//! through (duplicate keys, a top level that is not an object) caught by
//! the span-keeping reader first.

use super::locate_or_start;
use super::rephrase::rephrase;
use crate::diagnostic::{Diagnostic, Locator};
use crate::json_spans;
use crate::key_path::{KeyPath, Segment};
use crate::span_tree::{Node, NodeKind};
use crate::Format;
use serde::de::DeserializeOwned;
use std::ops::Range;

pub(super) fn parse_json<T: DeserializeOwned>(text: &str) -> Result<T, Vec<Diagnostic>> {
    let structure = json_structure_errors(text);
    if !structure.is_empty() {
        return Err(structure);
    }
    let mut nulls = NullMembers::of(text);
    loop {
        let read = nulls.text.as_deref().unwrap_or(text);
        let mut de = serde_json::Deserializer::from_str(read);
        let result: Result<T, _> = serde_path_to_error::deserialize(&mut de);
        match result {
            Ok(scene) => {
                de.end()
                    .map_err(|e| vec![json_error(text, KeyPath::root(), e)])?;
                return Ok(scene);
            }
            Err(e) => {
                let path = KeyPath::from_serde(e.path());
                let e = e.into_inner();
                // A null refused where a key's value is needed means the
                // key left out: read again without it. A key unknown is
                // unknown whatever its value.
                let unknown = e.to_string().starts_with("unknown ");
                if unknown || !nulls.leave_out(&path, text) {
                    return Err(vec![json_error(text, path, e)]);
                }
            }
        }
    }
}

/// The text's object members valued `null`, and the text with those
/// serde refused blanked out (with one comma beside each). A null member
/// means the same as a missing key; one of an unknown key is still an
/// unknown key, so only the nulls serde cannot take are left out. Blanks
/// keep every other byte where it was, so messages point into the text as
/// written.
struct NullMembers {
    /// Each null member's key path and its span, key to value.
    members: Vec<(KeyPath, Range<usize>)>,
    /// The text with the members left out so far, once there is one.
    text: Option<String>,
}

impl NullMembers {
    fn of(text: &str) -> NullMembers {
        let mut members = Vec::new();
        if let Ok(tree) = json_spans::parse(text) {
            null_members(&tree, text, &mut Vec::new(), &mut members);
        }
        NullMembers {
            members,
            text: None,
        }
    }

    /// Leaves out the null member at `path` of `text`, and every other of
    /// the same key name in the same top-level table (`materials.*.
    /// shininess`): serde refuses a null there too, or takes it as the key
    /// left out, and a file is read again once per such name, not once per
    /// null (a known name: serde reports an unknown one first). False when
    /// `path` is no null member.
    fn leave_out(&mut self, path: &KeyPath, text: &str) -> bool {
        if !self.members.iter().any(|(p, _)| p == path) {
            return false;
        }
        let alike = |p: &KeyPath| {
            p == path
                || (p.0.first() == path.0.first()
                    && p.last_key().is_some()
                    && p.last_key() == path.last_key())
        };
        let (chosen, kept): (Vec<_>, Vec<_>) = std::mem::take(&mut self.members)
            .into_iter()
            .partition(|(p, _)| alike(p));
        self.members = kept;
        let mut bytes = self
            .text
            .take()
            .unwrap_or_else(|| text.to_string())
            .into_bytes();
        for (_, span) in chosen {
            blank(&mut bytes, span);
        }
        // Only ASCII bytes were replaced, by spaces: still UTF-8.
        self.text = Some(String::from_utf8(bytes).unwrap_or_else(|_| text.to_string()));
        true
    }
}

/// Blanks the member at `member` and one comma beside it (the one after
/// it, or else the one before).
fn blank(bytes: &mut [u8], member: Range<usize>) {
    bytes[member.clone()].fill(b' ');
    let after = bytes[member.end..]
        .iter()
        .position(|b| !b.is_ascii_whitespace());
    let before = bytes[..member.start]
        .iter()
        .rposition(|b| !b.is_ascii_whitespace());
    let comma = match (after, before) {
        (Some(i), _) if bytes[member.end + i] == b',' => Some(member.end + i),
        (_, Some(i)) if bytes[i] == b',' => Some(i),
        _ => None,
    };
    if let Some(i) = comma {
        bytes[i] = b' ';
    }
}

/// The key paths and spans (key to value) of the members valued `null`
/// below `node`, in file order; `path` is `node`'s.
fn null_members(
    node: &Node,
    text: &str,
    path: &mut Vec<Segment>,
    out: &mut Vec<(KeyPath, Range<usize>)>,
) {
    match &node.kind {
        NodeKind::Table(entries) => {
            for (key, key_span, value) in entries {
                path.push(Segment::Key(key.clone()));
                if text.get(value.span.clone()) == Some("null") {
                    out.push((KeyPath(path.clone()), key_span.start..value.span.end));
                } else {
                    null_members(value, text, path, out);
                }
                path.pop();
            }
        }
        NodeKind::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                path.push(Segment::Index(i));
                null_members(item, text, path, out);
                path.pop();
            }
        }
        NodeKind::Scalar => {}
    }
}

/// What serde_json lets through or words poorly: a top level that is not
/// an object, and duplicate keys (serde_json keeps the last one silently).
/// Text that is not JSON at all is left to serde_json to report.
fn json_structure_errors(text: &str) -> Vec<Diagnostic> {
    let Ok(tree) = json_spans::parse(text) else {
        return Vec::new();
    };
    if !matches!(tree.kind, NodeKind::Table(_)) {
        let d = Diagnostic::new(
            KeyPath::root(),
            "expected a JSON object ({ \"camera\": ... }) at the top level",
        );
        return vec![d.at(text, tree.span)];
    }
    // One locator for all: thousands of duplicates must not each read the
    // file from the start.
    let (mut locator, mut first_locator) = (Locator::new(text), Locator::new(text));
    json_spans::duplicate_keys(&tree)
        .into_iter()
        .map(|(path, span, first)| {
            let path = KeyPath(path);
            let first = first_locator.location(first.start);
            let name = path.last_key().unwrap_or_default().to_string();
            let message = format!(
                "duplicate key `{name}` {} (first defined at line {}, column {}); expected each key once",
                path.parent().in_table(),
                first.line,
                first.column
            );
            let mut d = Diagnostic::new(path, message);
            d.location = Some(locator.location(span.start));
            d.span = Some(span);
            d
        })
        .collect()
}

fn json_error(text: &str, path: KeyPath, e: serde_json::Error) -> Diagnostic {
    let message = strip_json_position(&e.to_string());
    // serde_json's own position: where it stopped reading.
    let position = offset_of(text, e.line(), e.column());
    if e.is_syntax() && message == "trailing characters" && !path.is_root() {
        if let Some(d) = too_long_array(text, &path, position.start) {
            return d;
        }
    }
    if e.is_syntax() || e.is_eof() || e.is_io() {
        if message == "number out of range" {
            let message = "number out of range; expected a finite number";
            // serde_json stops at the number's end and names no key; the
            // span reader finds the number and its key path.
            if let Some((path, span)) = json_spans::parse(text)
                .ok()
                .and_then(|tree| value_at(&tree, position.start.saturating_sub(1)))
            {
                return Diagnostic::new(path, message).at(text, span);
            }
            return Diagnostic::new(KeyPath::root(), message).at(text, position);
        }
        return Diagnostic::new(KeyPath::root(), message).at(text, position);
    }
    let (path, message, target) = rephrase(path, &message);
    let d = Diagnostic::new(path.clone(), message);
    let d = locate_or_start(d, text, Format::Json, &path, target);
    match d.span {
        Some(_) => d,
        // The text is not JSON past this point, so the locator found nothing.
        None => d.at(text, position),
    }
}

/// The byte offset of serde_json's 1-based line and column (column counts
/// bytes; 0 means before the first byte of the line).
fn offset_of(text: &str, line: usize, column: usize) -> std::ops::Range<usize> {
    let line_start: usize = text
        .split_inclusive('\n')
        .take(line.saturating_sub(1))
        .map(str::len)
        .sum();
    let at = (line_start + column.saturating_sub(1)).min(text.len());
    at..at
}

/// serde_json appends " at line L column C"; the location is kept apart.
fn strip_json_position(message: &str) -> String {
    match message.rfind(" at line ") {
        Some(i) => message[..i].to_string(),
        None => message.to_string(),
    }
}

/// serde_json stops at the first element past a fixed-length array's end
/// and calls the rest "trailing characters": say what was expected, at the
/// array.
fn too_long_array(text: &str, path: &KeyPath, stopped_at: usize) -> Option<Diagnostic> {
    let tree = json_spans::parse(text).ok()?;
    let found = tree.locate(path);
    let NodeKind::Array(items) = &tree_node(&tree, path)?.kind else {
        return None;
    };
    let expected = items.iter().filter(|n| n.span.end <= stopped_at).count();
    // Items of several kinds are a table's values written in order (a
    // vector's or a triangle's are all alike): serde read them by position.
    let kind = |n: &crate::span_tree::Node| std::mem::discriminant(&n.kind);
    let mixed = items.iter().any(|n| kind(n) != kind(&items[0]));
    let message = if mixed {
        super::table_as_array(crate::Format::Json).to_string()
    } else {
        super::too_long(items, expected)
    };
    Some(Diagnostic::new(path.clone(), message).at(text, found.value))
}

/// The node at `path`, if the whole path is there.
fn tree_node<'t>(
    tree: &'t crate::span_tree::Node,
    path: &KeyPath,
) -> Option<&'t crate::span_tree::Node> {
    use crate::key_path::Segment;
    let mut node = tree;
    for segment in &path.0 {
        node = match (&node.kind, segment) {
            (NodeKind::Table(entries), Segment::Key(k)) => {
                &entries.iter().rev().find(|(name, _, _)| name == k)?.2
            }
            (NodeKind::Array(items), Segment::Index(i)) => items.get(*i)?,
            _ => return None,
        };
    }
    Some(node)
}

/// The key path and span of the innermost scalar holding byte `offset`.
fn value_at(
    tree: &crate::span_tree::Node,
    offset: usize,
) -> Option<(KeyPath, std::ops::Range<usize>)> {
    use crate::key_path::Segment;
    let mut node = tree;
    let mut path = KeyPath::root();
    loop {
        let inside = |n: &crate::span_tree::Node| n.span.contains(&offset);
        let next = match &node.kind {
            NodeKind::Table(entries) => entries
                .iter()
                .find(|(_, _, v)| inside(v))
                .map(|(k, _, v)| (Segment::Key(k.clone()), v)),
            NodeKind::Array(items) => items
                .iter()
                .enumerate()
                .find(|(_, v)| inside(v))
                .map(|(i, v)| (Segment::Index(i), v)),
            NodeKind::Scalar => return Some((path, node.span.clone())),
        };
        let (segment, child) = next?;
        path.0.push(segment);
        node = child;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SceneFile;

    const WITHOUT: &str = r#"{
  "camera": { "eye": [0, 0, 5], "look_at": [0, 0, 0] },
  "lights": [{ "position": [0, 5, 5] }],
  "objects": [{ "sphere": { "center": [0, 0, 0], "radius": 1 } }]
}"#;

    #[test]
    fn a_null_member_means_the_same_as_a_missing_key() {
        let with = r#"{
  "camera": { "eye": [0, 0, 5], "fov": null, "look_at": [0, 0, 0], "width": null },
  "render": null,
  "lights": [{ "color": null, "position": [0, 5, 5] }],
  "objects": [{ "sphere": { "center": [0, 0, 0], "radius": 1 }, "material": null }],
  "materials": null
}"#;
        let expected = parse_json::<SceneFile>(WITHOUT).unwrap();
        let parsed = parse_json::<SceneFile>(with).unwrap();
        assert_eq!(
            serde_json::to_value(parsed).unwrap(),
            serde_json::to_value(expected).unwrap()
        );
        let render = r#"{ "render": { "gamma": null, "integrator": null, "samples": null },"#;
        let text = format!("{render}{}", &WITHOUT[1..]);
        assert!(parse_json::<SceneFile>(&text).is_ok());
    }

    #[test]
    fn a_mistake_after_a_null_member_is_placed_in_the_text_as_written() {
        let text = "{\n  \"camera\": { \"fov\": null, \"eye\": [0, 0, 5], \"look_at\": [0, 0, 0], \"up\": 7 }\n}";
        let d = &parse_json::<SceneFile>(text).unwrap_err()[0];
        assert_eq!(d.path.to_string(), "camera.up");
        assert_eq!(d.location.map(|l| (l.line, l.column)), Some((2, 74)));
        // Many nulls of one key are left out together, and a misspelt key
        // among them is still misspelt.
        let materials: Vec<String> = (0..200)
            .map(|k| format!("\"m{k}\": {{ \"shininess\": null, \"diffuse\": [1, 0, 0] }}"))
            .collect();
        let text = format!(
            "{{ \"materials\": {{ {}, \"odd\": {{ \"difuse\": null }} }},{}",
            materials.join(", "),
            &WITHOUT[1..]
        );
        let d = &parse_json::<SceneFile>(&text).unwrap_err()[0];
        assert!(d.message.contains("unknown key `difuse`"), "{}", d.message);
        // A misspelt key is misspelt whatever its value.
        let text = WITHOUT.replace("\"look_at\"", "\"fvo\": null, \"look_at\"");
        let d = &parse_json::<SceneFile>(&text).unwrap_err()[0];
        assert!(d.message.contains("unknown key `fvo`"), "{}", d.message);
        // A null in an array is a value, not a member: still a mistake.
        let text = WITHOUT.replace("[0, 0, 5]", "[0, null, 5]");
        let d = &parse_json::<SceneFile>(&text).unwrap_err()[0];
        assert_eq!(d.path.to_string(), "camera.eye[1]");
    }
}
