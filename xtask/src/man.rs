//! `cargo xtask man`: one man page per `tracer` command (`tracer.1`,
//! `tracer-render.1`, `tracer-gamma-fit.1`, ...), made by clap_mangen from
//! the definition the binary parses, so they never drift from `--help`.

use anyhow::{Context, Result};
use std::path::{Path, PathBuf};

/// Writes the pages into `dir` (made if missing); returns their paths in
/// the order of the commands.
pub fn write_pages(dir: &Path) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot make {}", dir.display()))?;
    // As clap_mangen::generate_to, but every page's footer names the
    // program and its version (a subcommand's would show its own name).
    let mut cmd = tracer_cli::command().disable_help_subcommand(true);
    cmd.build();
    let source = format!("tracer {}", cmd.get_version().unwrap_or_default());
    let mut pages = Vec::new();
    write_tree(&cmd, &source, dir, &mut pages)?;
    Ok(pages)
}

fn write_tree(
    cmd: &clap::Command,
    source: &str,
    dir: &Path,
    pages: &mut Vec<PathBuf>,
) -> Result<()> {
    let page = clap_mangen::Man::new(cmd.clone()).source(source);
    let path = page
        .generate_to(dir)
        .with_context(|| format!("cannot write a man page in {}", dir.display()))?;
    pages.push(path);
    for sub in cmd.get_subcommands().filter(|s| !s.is_hide_set()) {
        write_tree(sub, source, dir, pages)?;
    }
    Ok(())
}
