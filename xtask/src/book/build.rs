//! The book's HTML, built by mdbook from a staged copy of `docs/`: mdbook
//! copies only the files under `src/`, and the pages show the goldens of
//! `golden/` and include scenes of `scenes/` by their paths in the
//! repository (so the pages read right on a forge too). The staged copy
//! holds each such file under `src/repo/`, its links rewritten to it.

use super::markdown;
use super::{pages, SRC};
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The mdBook release the book is built with (`book.toml` is its format).
pub const MDBOOK_VERSION: &str = "0.5.4";

/// Builds the book of `root` into `out` (emptied first).
pub fn build(root: &Path, out: &Path) -> Result<()> {
    let mdbook = mdbook()?;
    let stage = crate::target_dir().join("book-stage");
    stage_book(root, &stage)?;
    if out.exists() {
        std::fs::remove_dir_all(out).with_context(|| format!("cannot empty {}", out.display()))?;
    }
    let status = Command::new(&mdbook)
        .arg("build")
        .arg(&stage)
        .arg("--dest-dir")
        .arg(std::path::absolute(out)?)
        .status()
        .with_context(|| format!("cannot run {}", mdbook.display()))?;
    if !status.success() {
        bail!("mdbook build failed ({status})");
    }
    Ok(())
}

/// Copies `docs/book.toml` and `docs/src` into `stage`, with every file a
/// page links to outside `docs/src` under `src/repo/`.
pub fn stage_book(root: &Path, stage: &Path) -> Result<()> {
    if stage.exists() {
        std::fs::remove_dir_all(stage)
            .with_context(|| format!("cannot empty {}", stage.display()))?;
    }
    let src = root.join(SRC);
    let staged_src = stage.join("src");
    std::fs::create_dir_all(&staged_src)?;
    std::fs::copy(root.join("docs/book.toml"), stage.join("book.toml"))
        .context("cannot copy docs/book.toml")?;
    copy_tree(&src, &staged_src)?;
    for page in pages(root)?.into_iter().filter(|p| p.starts_with(&src)) {
        let text = std::fs::read_to_string(&page)?;
        let staged_page = staged_src.join(page.strip_prefix(&src)?);
        let rewritten = rewrite_outside_links(root, &src, &page, &text, &staged_src)?;
        std::fs::write(&staged_page, rewritten)?;
    }
    Ok(())
}

/// The page's text with each link to a file outside `src` pointing at its
/// copy under `staged_src/repo/`, which it makes.
fn rewrite_outside_links(
    root: &Path,
    src: &Path,
    page: &Path,
    text: &str,
    staged_src: &Path,
) -> Result<String> {
    let page_dir = page.parent().context("a page has a folder")?;
    let mut out = String::with_capacity(text.len());
    let mut copied_to = 0;
    let mut links = markdown::links(text);
    links.sort_by_key(|l| l.start);
    for link in links {
        let path = link.target.split('#').next().unwrap_or("");
        if path.is_empty() || path.contains("://") {
            continue;
        }
        let file = super::links::normalize(&page_dir.join(path));
        if file.starts_with(src) || !file.starts_with(root) || !file.is_file() {
            continue;
        }
        let in_repo = file.strip_prefix(root)?;
        let copy = staged_src.join("repo").join(in_repo);
        if let Some(parent) = copy.parent() {
            std::fs::create_dir_all(parent)?;
        }
        std::fs::copy(&file, &copy).with_context(|| format!("cannot copy {}", file.display()))?;
        let depth = page_dir.strip_prefix(src)?.components().count();
        let new_target = format!("{}repo/{}", "../".repeat(depth), super::shown(root, &file));
        out.push_str(&text[copied_to..link.start]);
        out.push_str(&new_target);
        copied_to = link.start + path.len();
    }
    out.push_str(&text[copied_to..]);
    Ok(out)
}

/// Copies the folder `from` into `to` (made if missing), files and folders.
pub fn copy_tree(from: &Path, to: &Path) -> Result<()> {
    std::fs::create_dir_all(to).with_context(|| format!("cannot make {}", to.display()))?;
    for entry in std::fs::read_dir(from)? {
        let path = entry?.path();
        let target = to.join(path.file_name().context("a named entry")?);
        if path.is_dir() {
            std::fs::create_dir_all(&target)?;
            copy_tree(&path, &target)?;
        } else {
            std::fs::copy(&path, &target)?;
        }
    }
    Ok(())
}

/// An mdbook of [`MDBOOK_VERSION`]'s series: on the `PATH`, in cargo's
/// `bin` folder (or `target/tools/bin`, where one of another series is
/// there), or installed there now with `cargo install`.
pub fn mdbook() -> Result<PathBuf> {
    let series = MDBOOK_VERSION
        .rsplit_once('.')
        .map_or(MDBOOK_VERSION, |(s, _)| s);
    let cargo_bin = cargo_home().join("bin").join("mdbook");
    let beside = crate::target_dir().join("tools/bin/mdbook");
    for candidate in [PathBuf::from("mdbook"), cargo_bin.clone(), beside] {
        if let Some(version) = version_of(&candidate) {
            if version.starts_with(&format!("v{series}."))
                || version.starts_with(&format!("{series}."))
            {
                return Ok(candidate);
            }
            eprintln!("{} is {version}, not {series}.x", candidate.display());
        }
    }
    // Another series found: the pinned one beside the build, not over it.
    let root = if version_of(&cargo_bin).is_some() {
        crate::target_dir().join("tools")
    } else {
        cargo_home()
    };
    eprintln!(
        "installing mdbook {MDBOOK_VERSION} into {} (cargo install; a few minutes)",
        root.display()
    );
    let status = Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()))
        .args([
            "install",
            "mdbook",
            "--locked",
            "--version",
            MDBOOK_VERSION,
            "--root",
        ])
        .arg(&root)
        .status()
        .context("cannot run cargo install")?;
    if !status.success() {
        bail!("cargo install mdbook failed ({status})");
    }
    Ok(root.join("bin").join("mdbook"))
}

fn version_of(mdbook: &Path) -> Option<String> {
    let out = Command::new(mdbook).arg("--version").output().ok()?;
    let text = String::from_utf8(out.stdout).ok()?;
    out.status
        .success()
        .then(|| text.split_whitespace().nth(1).unwrap_or("").to_string())
}

fn cargo_home() -> PathBuf {
    std::env::var_os("CARGO_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cargo")))
        .unwrap_or_else(|| PathBuf::from(".cargo"))
}
