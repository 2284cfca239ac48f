//! `cargo xtask book`: the book in `docs/` (mdBook: `docs/book.toml`,
//! `docs/src/SUMMARY.md`). Its generated pages (the scene keys from the
//! schema, the commands from clap, the gallery) are written here, its pages
//! checked (links, images, anchors, commands), and the HTML built by mdbook.
//! The checks need no mdbook: the tests run them.

pub mod build;
pub use build::build;
pub mod commands;
pub mod links;
pub mod markdown;
pub mod reference;

use anyhow::{Context, Result};
use std::path::{Path, PathBuf};

/// The book's pages, relative to the workspace root.
pub const SRC: &str = "docs/src";
/// The page of every scene file key, made from the schema.
pub const KEYS_PAGE: &str = "docs/src/reference/scene-keys.md";
/// The page of every command's `--help`, made from clap.
pub const COMMANDS_PAGE: &str = "docs/src/reference/commands.md";

/// Where the book is built by default: `target/book`.
pub fn default_out() -> PathBuf {
    crate::target_dir().join("book")
}

/// A generated page: its path under the root and its text now.
pub fn generated(root: &Path) -> Result<Vec<(&'static str, String)>> {
    Ok(vec![
        (KEYS_PAGE, reference::render(root)?),
        (COMMANDS_PAGE, commands::reference_page()),
        (crate::gallery::GALLERY, crate::gallery::render(root)?),
    ])
}

/// Writes the generated pages; their paths.
pub fn write_generated(root: &Path) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    for (page, text) in generated(root)? {
        let path = root.join(page);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)?;
        }
        std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))?;
        written.push(path);
    }
    Ok(written)
}

/// Every page of the book (`docs/src/**/*.md`), sorted, and the README.
pub fn pages(root: &Path) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    markdown_files(&root.join(SRC), &mut out)?;
    out.sort();
    out.push(root.join("README.md"));
    Ok(out)
}

fn markdown_files(dir: &Path, out: &mut Vec<PathBuf>) -> Result<()> {
    for entry in std::fs::read_dir(dir).with_context(|| format!("cannot list {}", dir.display()))? {
        let path = entry?.path();
        if path.is_dir() {
            markdown_files(&path, out)?;
        } else if path.extension().is_some_and(|e| e == "md") {
            out.push(path);
        }
    }
    Ok(())
}

/// `path` relative to `root`, `/`-separated, for messages.
pub fn shown(root: &Path, path: &Path) -> String {
    let rel = path.strip_prefix(root).unwrap_or(path);
    rel.iter()
        .map(|p| p.to_string_lossy())
        .collect::<Vec<_>>()
        .join("/")
}

/// Every problem of the book's pages, one line each (`page:line: what`):
/// links and images that do not resolve, pages missing from the summary,
/// commands that `tracer` or `cargo xtask` would refuse, generated pages
/// that are stale. Empty when the book is sound.
pub fn check(root: &Path) -> Result<Vec<String>> {
    let mut problems = links::check(root)?;
    problems.extend(commands::check(root)?);
    for (page, text) in generated(root)? {
        let committed = std::fs::read_to_string(root.join(page)).unwrap_or_default();
        if committed != text {
            problems.push(format!(
                "{page}: stale (it is generated): run cargo xtask book --check"
            ));
        }
    }
    Ok(problems)
}
