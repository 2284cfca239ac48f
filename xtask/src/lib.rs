//! Project chores, the cargo-xtask way: `cargo xtask <task>`. The tasks live
//! here as a library so that tests run them in-process.

pub mod assets;
pub mod bench;
pub mod book;
pub mod cli;
pub mod farm;
pub mod gallery;
pub mod golden;
pub mod man;
pub mod oidn;
pub mod web;

use std::path::{Path, PathBuf};

/// The workspace root: the folder above `xtask/`.
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask sits inside the workspace folder")
        .to_path_buf()
}

/// Cargo's target folder: `CARGO_TARGET_DIR` when set, else `<workspace>/target`.
pub fn target_dir() -> PathBuf {
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(dir) if !dir.is_empty() => {
            let dir = PathBuf::from(dir);
            // Cargo reads a relative CARGO_TARGET_DIR from the current folder.
            std::env::current_dir().map_or(dir.clone(), |cwd| cwd.join(dir))
        }
        _ => workspace_root().join("target"),
    }
}
