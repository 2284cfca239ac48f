//! No file of the core imports, through others, a file that imports it:
//! each concept's file can be read (and changed) knowing only what it
//! uses. The check reads `crate::` and `super::` paths in every source
//! file (its tests left out), links each file to the module file a path
//! names, and fails on any circle of files.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

#[test]
fn no_file_of_the_core_imports_itself_through_others() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let files = sources(&src, &src);
    assert!(files.len() > 50, "read {} files", files.len());
    let graph = imports(&files);
    assert_eq!(
        circles(&graph),
        Vec::<Vec<String>>::new(),
        "these files import each other in a circle (import what both need from a file of its own)"
    );
}

#[test]
fn the_check_finds_a_circle() {
    let files = BTreeMap::from([
        ("a.rs".to_string(), "use crate::b::B;".to_string()),
        ("b.rs".to_string(), "use crate::{c::{self, C}};".to_string()),
        ("c/mod.rs".to_string(), "pub mod d;".to_string()),
        ("c/d.rs".to_string(), "use super::super::a::A;".to_string()),
        (
            "e.rs".to_string(),
            "use crate::a;\n#[cfg(test)]\nmod tests { use crate::e; }".to_string(),
        ),
    ]);
    let graph = imports(&files);
    assert_eq!(graph["b.rs"], BTreeSet::from(["c/mod.rs".to_string()]));
    assert_eq!(graph["c/d.rs"], BTreeSet::from(["a.rs".to_string()]));
    assert_eq!(circles(&graph), Vec::<Vec<String>>::new());
    let mut files = files;
    files.insert("c/mod.rs".into(), "pub mod d;\nuse crate::c::d::D;".into());
    let circles = circles(&imports(&files));
    assert_eq!(circles, vec![vec!["a.rs", "b.rs", "c/d.rs", "c/mod.rs"]]);
}

/// Every `.rs` file below `dir`, by its path from `root`, with its text.
fn sources(root: &Path, dir: &Path) -> BTreeMap<String, String> {
    let mut files = BTreeMap::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path: PathBuf = entry.unwrap().path();
        if path.is_dir() {
            files.extend(sources(root, &path));
        } else if path.extension().is_some_and(|e| e == "rs") {
            let name = path.strip_prefix(root).unwrap().to_string_lossy();
            let text = std::fs::read_to_string(&path).unwrap();
            files.insert(name.replace('\\', "/"), text);
        }
    }
    files
}

/// The module a file is (`a/b.rs` and `a/b/mod.rs` are `a::b`).
fn module_of(file: &str) -> Vec<String> {
    let mut parts: Vec<String> = file
        .trim_end_matches(".rs")
        .split('/')
        .map(String::from)
        .collect();
    if matches!(parts.last().map(String::as_str), Some("mod" | "lib")) {
        parts.pop();
    }
    parts
}

/// For each file, the files whose modules its `crate::` and `super::`
/// paths name (itself left out).
fn imports(files: &BTreeMap<String, String>) -> BTreeMap<String, BTreeSet<String>> {
    let by_module: BTreeMap<Vec<String>, &String> =
        files.keys().map(|f| (module_of(f), f)).collect();
    files
        .iter()
        .map(|(file, text)| {
            let code = text.split("#[cfg(test)]").next().unwrap_or("");
            let here = module_of(file);
            let targets = paths(code)
                .into_iter()
                .filter_map(|path| absolute(&here, &path))
                .filter_map(|path| {
                    (1..=path.len())
                        .rev()
                        .find_map(|n| by_module.get(&path[..n]).copied())
                })
                .filter(|target| *target != file)
                .cloned()
                .collect();
            (file.clone(), targets)
        })
        .collect()
}

/// `path` (starting `crate` or `super`) from the root, as seen in module
/// `here`.
fn absolute(here: &[String], path: &[String]) -> Option<Vec<String>> {
    let mut segments = path.iter().peekable();
    let mut base = match segments.next()?.as_str() {
        "crate" => Vec::new(),
        _ => here[..here.len().checked_sub(1)?].to_vec(),
    };
    while segments.peek().is_some_and(|s| *s == "super") {
        base.pop()?;
        segments.next();
    }
    base.extend(segments.filter(|s| *s != "self").cloned());
    Some(base)
}

/// Every path starting `crate::` or `super::` in `code`, a `{...}` group's
/// items each its own path.
fn paths(code: &str) -> Vec<Vec<String>> {
    let mut found = Vec::new();
    let bytes = code.as_bytes();
    for start in ["crate::", "super::"] {
        for (at, _) in code.match_indices(start) {
            // Not inside a longer path (`super::super::`, `x::crate`).
            let inside = at > 0
                && matches!(bytes[at - 1], b'_' | b':' | b'0'..=b'9' | b'a'..=b'z' | b'A'..=b'Z');
            if !inside {
                expand(&code[at..], Vec::new(), &mut found);
            }
        }
    }
    found
}

/// The paths `text` begins with, after `prefix`: one, or a group's.
fn expand(text: &str, mut prefix: Vec<String>, found: &mut Vec<Vec<String>>) {
    let mut rest = text;
    loop {
        let word: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        if word.is_empty() {
            break;
        }
        rest = &rest[word.len()..];
        prefix.push(word);
        if let Some(after) = rest.strip_prefix("::") {
            rest = after;
        } else {
            break;
        }
    }
    if let Some(group) = rest.strip_prefix('{') {
        for item in top_level_items(group) {
            expand(item.trim_start(), prefix.clone(), found);
        }
    } else if !prefix.is_empty() {
        found.push(prefix);
    }
}

/// The comma-separated items of a group opened just before `text`.
fn top_level_items(text: &str) -> Vec<&str> {
    let (mut depth, mut start, mut items) = (0, 0, Vec::new());
    for (i, c) in text.char_indices() {
        match c {
            '{' => depth += 1,
            '}' if depth == 0 => {
                items.push(&text[start..i]);
                return items;
            }
            '}' => depth -= 1,
            ',' if depth == 0 => {
                items.push(&text[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    items
}

/// The circles of `graph`: its strongly connected parts of two files or
/// more (Tarjan's algorithm), each sorted.
fn circles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct Walk<'a> {
        graph: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        found: Vec<Vec<String>>,
    }
    impl<'a> Walk<'a> {
        fn visit(&mut self, v: &'a str) {
            let i = self.index.len();
            self.index.insert(v, i);
            self.low.insert(v, i);
            self.stack.push(v);
            for w in self.graph.get(v).into_iter().flatten() {
                if !self.index.contains_key(w.as_str()) {
                    self.visit(w);
                    let low = self.low[v].min(self.low[w.as_str()]);
                    self.low.insert(v, low);
                } else if self.stack.contains(&w.as_str()) {
                    let low = self.low[v].min(self.index[w.as_str()]);
                    self.low.insert(v, low);
                }
            }
            if self.low[v] == self.index[v] {
                let at = self.stack.iter().rposition(|s| *s == v).unwrap();
                let mut part: Vec<String> = self.stack.drain(at..).map(String::from).collect();
                if part.len() > 1 {
                    part.sort();
                    self.found.push(part);
                }
            }
        }
    }
    let mut walk = Walk {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        found: Vec::new(),
    };
    for v in graph.keys() {
        if !walk.index.contains_key(v.as_str()) {
            walk.visit(v);
        }
    }
    walk.found
}
