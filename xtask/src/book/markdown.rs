//! The little of Markdown the book's checks read: fenced code blocks, links
//! and images, headings and their anchors. Standard library only, so that
//! `crates/tracer-cli/tests/book.rs` can share it (`#[path]`) to check the
//! book's scenes with the `tracer` binary itself.

/// A fenced code block: ```` ```toml ```` ... ```` ``` ````.
#[derive(Debug, Clone, PartialEq)]
pub struct Fence {
    /// The info string's first word (`toml`, `sh`, `text`), lowercase.
    pub lang: String,
    /// The body, its indent (that of the opening fence) taken off each line.
    pub body: String,
    /// The opening fence's line, from 1.
    pub line: usize,
}

/// A link's or an image's target, where it is in the text.
#[derive(Debug, Clone, PartialEq)]
pub struct Link {
    pub target: String,
    /// Byte range of `target` in the text.
    pub start: usize,
    pub line: usize,
    /// An image (`![..](..)`, `<img src>`), not a link.
    pub image: bool,
}

/// The fenced code blocks, in order. A fence may be indented (a block in a
/// list item); it ends at a fence of the same character at least as long.
pub fn fences(text: &str) -> Vec<Fence> {
    let mut out = Vec::new();
    // The open fence's marker and indent, and the block so far.
    let mut open: Option<(String, usize, Fence)> = None;
    for (i, line) in text.lines().enumerate() {
        let indent = line.len() - line.trim_start().len();
        let trimmed = line.trim_start();
        match open.take() {
            None => {
                if let Some((marker, info)) = fence_marker(trimmed) {
                    let lang = info.split([',', ' ']).next().unwrap_or("");
                    let fence = Fence {
                        lang: lang.to_ascii_lowercase(),
                        body: String::new(),
                        line: i + 1,
                    };
                    open = Some((marker, indent, fence));
                }
            }
            Some((marker, fence_indent, mut fence)) => {
                if closes(trimmed, &marker) {
                    out.push(fence);
                } else {
                    fence.body.push_str(&line[indent.min(fence_indent)..]);
                    fence.body.push('\n');
                    open = Some((marker, fence_indent, fence));
                }
            }
        }
    }
    // An unclosed fence runs to the end, as CommonMark reads it.
    out.extend(open.map(|(_, _, fence)| fence));
    out
}

/// Whether `line` (its indent taken off) closes a fence opened by `marker`.
fn closes(line: &str, marker: &str) -> bool {
    line.starts_with(marker) && line.trim_end().chars().all(|c| marker.starts_with(c))
}

/// ```` ``` ```` or `~~~` (three or more) and the info string after it.
fn fence_marker(line: &str) -> Option<(String, &str)> {
    let first = line.chars().next()?;
    if first != '`' && first != '~' {
        return None;
    }
    let count = line.chars().take_while(|&c| c == first).count();
    if count < 3 {
        return None;
    }
    let info = line[count..].trim();
    if first == '`' && info.contains('`') {
        return None;
    }
    Some((first.to_string().repeat(count), info))
}

/// Which lines are inside fenced blocks (fences included), by index.
fn fenced_lines(text: &str) -> Vec<bool> {
    let mut inside = Vec::new();
    let mut open: Option<String> = None;
    for line in text.lines() {
        let trimmed = line.trim_start();
        match &open {
            None => {
                if let Some((marker, _)) = fence_marker(trimmed) {
                    open = Some(marker);
                    inside.push(true);
                } else {
                    inside.push(false);
                }
            }
            Some(marker) => {
                if closes(trimmed, marker) {
                    open = None;
                }
                inside.push(true);
            }
        }
    }
    inside
}

/// Every link and image outside code: `[text](target)`, `![alt](target)`,
/// `[name]: target` definitions, and HTML `src="..."` and `href="..."`.
/// Also the files that mdBook's `{{#include FILE}}` puts into a fenced
/// block, as links (not images).
pub fn links(text: &str) -> Vec<Link> {
    let fenced = fenced_lines(text);
    let mut out = Vec::new();
    let mut offset = 0;
    for (i, line) in text.split_inclusive('\n').enumerate() {
        if fenced.get(i).copied().unwrap_or(false) {
            include_links(line, offset, i + 1, &mut out);
        } else {
            line_links(line, offset, i + 1, &mut out);
        }
        offset += line.len();
    }
    out
}

fn include_links(line: &str, offset: usize, number: usize, out: &mut Vec<Link>) {
    let Some(at) = line.find("{{#include ") else {
        return;
    };
    let start = at + "{{#include ".len();
    let Some(len) = line[start..].find("}}") else {
        return;
    };
    // `FILE:10:20` or `FILE:anchor` takes part of the file.
    let target = line[start..start + len].trim();
    let file = target.split(':').next().unwrap_or(target);
    out.push(Link {
        target: file.to_string(),
        start: offset + start,
        line: number,
        image: false,
    });
}

fn line_links(line: &str, offset: usize, number: usize, out: &mut Vec<Link>) {
    let code = code_spans(line);
    let in_code = |at: usize| code.iter().any(|&(a, b)| at >= a && at < b);
    let bytes = line.as_bytes();
    // `[text](target)` and `![alt](target)`.
    let mut at = 0;
    while let Some(found) = line[at..].find("](") {
        let close = at + found;
        let start = close + 2;
        at = start;
        if in_code(close) {
            continue;
        }
        let Some(len) = line[start..].find(')') else {
            continue;
        };
        let raw = &line[start..start + len];
        // `[a](url "title")`: the target is the first word.
        let target = raw.split_whitespace().next().unwrap_or("");
        let target = target.trim_start_matches('<').trim_end_matches('>');
        let lead =
            raw.len() - raw.trim_start().len() + usize::from(raw.trim_start().starts_with('<'));
        let image = opening_bracket(&line[..close]).is_some_and(|o| o > 0 && bytes[o - 1] == b'!');
        out.push(Link {
            target: target.to_string(),
            start: offset + start + lead,
            line: number,
            image,
        });
    }
    // `[name]: target`, a link definition on its own line.
    let trimmed = line.trim_start();
    if trimmed.starts_with('[') && !trimmed.starts_with("[^") {
        if let Some(close) = trimmed.find("]:") {
            let rest = &trimmed[close + 2..];
            let target = rest.split_whitespace().next().unwrap_or("");
            if !target.is_empty() {
                let lead =
                    line.len() - trimmed.len() + close + 2 + (rest.len() - rest.trim_start().len());
                out.push(Link {
                    target: target.to_string(),
                    start: offset + lead,
                    line: number,
                    image: false,
                });
            }
        }
    }
    // HTML attributes.
    for (attr, image) in [("src=\"", true), ("href=\"", false)] {
        let mut at = 0;
        while let Some(found) = line[at..].find(attr) {
            let start = at + found + attr.len();
            at = start;
            if in_code(start) {
                continue;
            }
            if let Some(len) = line[start..].find('"') {
                out.push(Link {
                    target: line[start..start + len].to_string(),
                    start: offset + start,
                    line: number,
                    image,
                });
            }
        }
    }
}

/// The `[` that a `]` at the end of `before` closes, by nesting.
fn opening_bracket(before: &str) -> Option<usize> {
    let mut depth = 0usize;
    for (i, c) in before.char_indices().rev() {
        match c {
            ']' => depth += 1,
            '[' if depth == 0 => return Some(i),
            '[' => depth -= 1,
            _ => {}
        }
    }
    None
}

/// Byte ranges of the line's inline code spans (`` `..` ``), backticks
/// included.
fn code_spans(line: &str) -> Vec<(usize, usize)> {
    let bytes = line.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] != b'`' {
            i += 1;
            continue;
        }
        let run = bytes[i..].iter().take_while(|&&b| b == b'`').count();
        let ticks = &line[i..i + run];
        match line[i + run..].find(ticks) {
            Some(len) => {
                spans.push((i, i + run + len + run));
                i += run + len + run;
            }
            None => i += run,
        }
    }
    spans
}

/// The ids of the page's headings, as mdBook (and GitHub) make them: the
/// heading's text lowercased, spaces as `-`, other punctuation left out,
/// a repeated id numbered (`-1`, `-2`).
pub fn heading_ids(text: &str) -> Vec<String> {
    let fenced = fenced_lines(text);
    let mut ids: Vec<String> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if fenced.get(i).copied().unwrap_or(false) {
            continue;
        }
        let Some(title) = heading_text(line) else {
            continue;
        };
        let base = anchor_of(&title);
        let mut id = base.clone();
        let mut n = 1;
        while ids.contains(&id) {
            id = format!("{base}-{n}");
            n += 1;
        }
        ids.push(id);
    }
    ids
}

/// The text of an ATX heading (`## Title`), without its `#`s.
fn heading_text(line: &str) -> Option<String> {
    if line.starts_with("    ") {
        return None;
    }
    let trimmed = line.trim_start();
    let level = trimmed.chars().take_while(|&c| c == '#').count();
    if !(1..=6).contains(&level) {
        return None;
    }
    let rest = &trimmed[level..];
    if !(rest.is_empty() || rest.starts_with(' ')) {
        return None;
    }
    Some(rest.trim().trim_end_matches('#').trim().to_string())
}

/// A heading's anchor: its visible text (links' text, no backticks or
/// emphasis) lowercased, whitespace as `-`, only letters, digits, `-` and
/// `_` kept.
pub fn anchor_of(title: &str) -> String {
    visible_text(title)
        .chars()
        .filter_map(|c| {
            if c.is_alphanumeric() || c == '_' || c == '-' {
                Some(c.to_lowercase().next().unwrap_or(c))
            } else if c.is_whitespace() {
                Some('-')
            } else {
                None
            }
        })
        .collect()
}

/// `[text](url)` as `text`; other characters as they are.
fn visible_text(title: &str) -> String {
    let mut out = String::new();
    let mut rest = title;
    while let Some(open) = rest.find('[') {
        out.push_str(&rest[..open]);
        let after = &rest[open + 1..];
        match after.find("](") {
            Some(close) if after[close + 2..].contains(')') => {
                out.push_str(&after[..close]);
                let tail = &after[close + 2..];
                rest = &tail[tail.find(')').map_or(tail.len(), |p| p + 1)..];
            }
            _ => {
                out.push('[');
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fences_keep_their_language_body_and_line() {
        let text = "intro\n\n```toml\n[camera]\n```\n\n- item\n\n  ```sh\n  tracer render\n  ```\n";
        let found = fences(text);
        assert_eq!(found.len(), 2);
        assert_eq!(found[0].lang, "toml");
        assert_eq!(found[0].body, "[camera]\n");
        assert_eq!(found[0].line, 3);
        assert_eq!(found[1].lang, "sh");
        assert_eq!(found[1].body, "tracer render\n");
    }

    #[test]
    fn links_outside_code_with_their_places() {
        let text = "See [the guide](guide/a.md#x) and ![pic](img/p.png).\n\
                    `[not](a link)`\n```\n[no](link)\n```\n<img src=\"b.png\" width=\"3\">\n[def]: c.md\n";
        let found = links(text);
        let targets: Vec<&str> = found.iter().map(|l| l.target.as_str()).collect();
        assert_eq!(targets, ["guide/a.md#x", "img/p.png", "b.png", "c.md"]);
        assert!(!found[0].image && found[1].image && found[2].image);
        assert_eq!(&text[found[1].start..found[1].start + 9], "img/p.png");
        assert_eq!(found[2].line, 6);
    }

    #[test]
    fn an_include_in_a_block_is_a_link_to_its_file() {
        let text = "```toml\n{{#include ../../scenes/a.toml:3:9}}\n```\n";
        let found = links(text);
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].target, "../../scenes/a.toml");
        assert_eq!(
            &text[found[0].start..found[0].start + 19],
            "../../scenes/a.toml"
        );
    }

    #[test]
    fn heading_ids_as_mdbook_makes_them() {
        let text = "# Scene files\n## `camera.fov`\n```\n# not a heading\n```\n## Scene files\n\
                    ### The [lab](x.md)'s tables, one by one\n";
        assert_eq!(
            heading_ids(text),
            [
                "scene-files",
                "camerafov",
                "scene-files-1",
                "the-labs-tables-one-by-one"
            ]
        );
    }
}
