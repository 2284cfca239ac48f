//! Where a key path is in the source text: validation speaks in key paths
//! only, and this maps a path to a span by walking the span tree of the
//! file, so any key added to the model gets located errors without further
//! work.

use crate::diagnostic::{floor_char_boundary, Diagnostic, Location, Locator};
use crate::key_path::{KeyPath, Segment};
use crate::span_tree::{tree, Node, NodeKind};
use crate::Format;
use std::collections::HashMap;
use std::ops::Range;

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

impl Node {
    /// Where `path` is in this tree: exactly, or the deepest table found
    /// on the way.
    pub fn locate(&self, path: &KeyPath) -> Located {
        TableIndex::default().locate(self, path)
    }
}

/// Gives each validation diagnostic the span of its key path, and sorts
/// them in file order. Linear in the file and the number of diagnostics.
pub(crate) fn locate_all(
    text: &str,
    format: Format,
    diagnostics: Vec<Diagnostic>,
) -> Vec<Diagnostic> {
    let Some(tree) = tree(text, format) else {
        return diagnostics;
    };
    let mut index = TableIndex::default();
    let mut located: Vec<Diagnostic> = diagnostics
        .into_iter()
        .map(|mut d| {
            let found = index.locate(&tree, &d.path);
            // A missing key (a default that fails a check) or a whole
            // table: point at the key that names the nearest table.
            let span = match (found.exact, &found.key) {
                (true, _) => found.value,
                (false, Some(key)) => key.clone(),
                (false, None) => found.value.start..found.value.start,
            };
            d.span = Some(span);
            d
        })
        .collect();
    // In file order, as a reader goes through the file.
    located.sort_by_key(|d| d.span.as_ref().map(|s| s.start));
    let mut locator = Locator::new(text);
    for d in &mut located {
        if let Some(span) = &d.span {
            let start = locator.location(span.start);
            d.location = Some(start);
            let end = floor_char_boundary(text, span.end.clamp(span.start, text.len()));
            let start_byte = floor_char_boundary(text, span.start.min(text.len()));
            d.span = Some(start_byte..end.max(start_byte));
        }
    }
    located
}

/// Where each of `paths` starts in `text` (where its key is found, as
/// [`locate_all`] places a diagnostic), in the order given; None for text
/// that does not parse. Linear in the file and the number of paths.
pub fn locate_each(text: &str, format: Format, paths: &[KeyPath]) -> Vec<Option<Location>> {
    let Some(tree) = tree(text, format) else {
        return vec![None; paths.len()];
    };
    let mut index = TableIndex::default();
    let starts: Vec<usize> = paths
        .iter()
        .map(|path| {
            let found = index.locate(&tree, path);
            match (found.exact, found.key) {
                (false, Some(key)) => key.start,
                _ => found.value.start,
            }
        })
        .collect();
    // The locator walks the text once when the offsets come in order.
    let mut order: Vec<usize> = (0..paths.len()).collect();
    order.sort_by_key(|&i| starts[i]);
    let mut locator = Locator::new(text);
    let mut locations = vec![None; paths.len()];
    for i in order {
        locations[i] = Some(locator.location(starts[i]));
    }
    locations
}

/// Key lookups in big tables (a thousand materials) by hash, built on
/// first use, so locating many diagnostics is not quadratic.
#[derive(Default)]
struct TableIndex<'t> {
    tables: HashMap<*const Node, HashMap<&'t str, &'t Entry>>,
}

/// A table entry of the span tree: key, key span, value.
type Entry = (String, Range<usize>, Node);

impl<'t> TableIndex<'t> {
    fn locate(&mut self, root: &'t Node, path: &KeyPath) -> Located {
        let mut node = root;
        let mut key = None;
        for segment in &path.0 {
            let next = match (&node.kind, segment) {
                (NodeKind::Table(entries), Segment::Key(k)) => self
                    .tables
                    .entry(node as *const Node)
                    .or_insert_with(|| {
                        // The last of duplicate keys (JSON) is the one read.
                        entries.iter().map(|e| (e.0.as_str(), e)).collect()
                    })
                    .get(k.as_str())
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
}
