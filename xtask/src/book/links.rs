//! Every relative link and image of the book and the README resolves: to a
//! file of the repository, to a page of the book's summary, to a heading of
//! that page. A book page links outside `docs/src` only to files (images,
//! scenes), which the build copies in; never to another Markdown page.

use super::markdown::{self, Link};
use super::{pages, shown, SRC};
use anyhow::{Context, Result};
use std::collections::BTreeMap;
use std::path::{Component, Path, PathBuf};

/// The problems, one line each.
pub fn check(root: &Path) -> Result<Vec<String>> {
    let src = root.join(SRC);
    let pages = pages(root)?;
    let mut texts = BTreeMap::new();
    for page in &pages {
        let text = std::fs::read_to_string(page)
            .with_context(|| format!("cannot read {}", page.display()))?;
        texts.insert(page.clone(), text);
    }
    // Its entries are links, checked with the others.
    let summary = summary_pages(
        &src,
        texts
            .get(&src.join("SUMMARY.md"))
            .map_or("", String::as_str),
    );
    let mut problems = Vec::new();
    if !src.join("SUMMARY.md").is_file() {
        problems.push("docs/src/SUMMARY.md: missing: mdbook needs it".to_string());
    }
    for page in &pages {
        let in_book = page.starts_with(&src);
        if in_book && page.file_name().is_some_and(|n| n != "SUMMARY.md") && !summary.contains(page)
        {
            problems.push(format!(
                "{}: not in SUMMARY.md, so the built book leaves it out",
                shown(root, page)
            ));
        }
        for link in markdown::links(&texts[page]) {
            if let Some(problem) = link_problem(root, &src, page, &link, &texts, &summary) {
                problems.push(format!("{}:{}: {problem}", shown(root, page), link.line));
            }
        }
    }
    Ok(problems)
}

/// The pages SUMMARY.md lists, as paths.
fn summary_pages(src: &Path, summary: &str) -> Vec<PathBuf> {
    markdown::links(summary)
        .into_iter()
        .filter(|l| !l.target.is_empty() && !is_external(&l.target))
        .map(|l| normalize(&src.join(l.target.split('#').next().unwrap_or(""))))
        .collect()
}

fn is_external(target: &str) -> bool {
    target.contains("://") || target.starts_with("mailto:")
}

/// `a/b/../c` as `a/c`, without reading the file system.
pub fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for part in path.components() {
        match part {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

fn link_problem(
    root: &Path,
    src: &Path,
    page: &Path,
    link: &Link,
    texts: &BTreeMap<PathBuf, String>,
    summary: &[PathBuf],
) -> Option<String> {
    let target = link.target.as_str();
    if target.is_empty() {
        return Some("an empty link".to_string());
    }
    if is_external(target) {
        return None;
    }
    let (path, fragment) = match target.split_once('#') {
        Some((path, fragment)) => (path, Some(fragment)),
        None => (target, None),
    };
    let file = if path.is_empty() {
        page.to_path_buf()
    } else {
        normalize(&page.parent()?.join(path))
    };
    let in_book = page.starts_with(src);
    if !file.starts_with(root) {
        return Some(format!("`{target}` leaves the repository"));
    }
    if !file.exists() {
        return Some(format!("`{target}` does not exist"));
    }
    if file.is_dir() {
        // GitHub shows a folder; the built book cannot.
        return in_book.then(|| format!("`{target}` is a folder: link a file"));
    }
    if link.image && !is_image(&file) {
        return Some(format!("`{target}` is not an image"));
    }
    let markdown = file.extension().is_some_and(|e| e == "md");
    if in_book && markdown && !file.starts_with(src) {
        return Some(format!(
            "`{target}` is a page outside the book, which the built book cannot show"
        ));
    }
    if in_book && markdown && !summary.contains(&file) {
        return Some(format!("`{target}` is not in SUMMARY.md"));
    }
    let fragment = fragment?;
    if !markdown {
        return Some(format!(
            "`{target}`: an anchor in a file that is not a page"
        ));
    }
    let text = texts.get(&file)?;
    let ids = markdown::heading_ids(text);
    (!ids.iter().any(|id| id == fragment)).then(|| {
        format!(
            "`{target}`: no heading of {} has the anchor `{fragment}`",
            shown(root, &file)
        )
    })
}

fn is_image(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| {
        matches!(
            e.to_ascii_lowercase().as_str(),
            "png" | "jpg" | "jpeg" | "svg" | "gif"
        )
    })
}
