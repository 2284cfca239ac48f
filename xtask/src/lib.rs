//! Project chores, the cargo-xtask way: `cargo xtask <task>`. The tasks live
//! here as a library so that tests run them in-process.

pub mod bench;
pub mod browser;
pub mod compare;
pub mod golden;
pub mod manifest;
pub mod report;

use anyhow::{Context, Result};
use std::io::Write;
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

/// Writes `bytes` to `path` through a temporary file in the same folder and a
/// rename: a failure leaves no partial file and an existing file untouched.
pub fn write_atomically(bytes: &[u8], path: &Path) -> Result<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut tmp = tempfile::Builder::new()
        .prefix(".xtask-")
        .suffix(".tmp")
        .tempfile_in(dir)
        .with_context(|| format!("cannot create a file in {}", dir.display()))?;
    tmp.write_all(bytes)
        .and_then(|()| tmp.as_file().sync_all())
        .with_context(|| format!("cannot write {}", path.display()))?;
    tmp.persist(path)
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

/// The PNG bytes of an image.
pub fn png_bytes(image: &image::RgbImage) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .context("cannot encode the PNG")?;
    Ok(bytes)
}
