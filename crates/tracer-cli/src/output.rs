//! Writing output files whole or not at all.

use anyhow::{Context, Result};
use std::io::Write;
use std::path::Path;

/// Writes `image` as PNG to `path` through a temporary file in the same
/// folder and a rename: a failure leaves no partial file and an existing
/// image untouched.
pub fn write_png_atomically(image: &image::RgbImage, path: &Path) -> Result<()> {
    write_atomically(&png_bytes(image)?, path)
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

pub fn write_atomically(bytes: &[u8], path: &Path) -> Result<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".tracer-").suffix(".tmp");
    #[cfg(unix)]
    builder.permissions(permissions_for(path));
    let mut tmp = builder
        .tempfile_in(dir)
        .with_context(|| format!("cannot create a file in {}", dir.display()))?;
    tmp.write_all(bytes)
        .and_then(|()| tmp.as_file().sync_all())
        .with_context(|| format!("cannot write {}", path.display()))?;
    tmp.persist(path)
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

/// The mode of the file being replaced, or an ordinary file's (rw-r--r--,
/// less the umask): a temporary file is created readable by its owner
/// only, and the renamed image would keep that.
#[cfg(unix)]
fn permissions_for(path: &Path) -> std::fs::Permissions {
    use std::os::unix::fs::PermissionsExt;
    let mode = std::fs::metadata(path).map_or(0o644, |m| m.permissions().mode() & 0o7777);
    std::fs::Permissions::from_mode(mode)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn leftovers(dir: &Path) -> Vec<String> {
        std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .filter(|n| n.starts_with(".tracer-"))
            .collect()
    }

    #[test]
    fn a_write_replaces_the_old_file_whole() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.png");
        std::fs::write(&path, b"an old, longer image file").unwrap();
        write_atomically(b"new", &path).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
        assert!(leftovers(dir.path()).is_empty());
    }

    #[test]
    fn a_failed_write_leaves_the_target_and_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        // The rename onto a non-empty folder fails after the data is written.
        let target = dir.path().join("image.png");
        std::fs::create_dir(&target).unwrap();
        std::fs::write(target.join("keep"), b"old").unwrap();
        assert!(write_atomically(b"new", &target).is_err());
        assert_eq!(std::fs::read(target.join("keep")).unwrap(), b"old");
        assert!(leftovers(dir.path()).is_empty());
    }

    #[cfg(unix)]
    #[test]
    fn a_new_file_is_readable_by_all_and_a_replaced_one_keeps_its_mode() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        let new = dir.path().join("new.png");
        write_atomically(b"new", &new).unwrap();
        // As a plain write would make it (0o666 less the umask), less
        // others' and the group's write permission.
        let plain = dir.path().join("plain.png");
        std::fs::write(&plain, b"plain").unwrap();
        assert_eq!(mode(&new), mode(&plain) & 0o644);
        let old = dir.path().join("old.png");
        std::fs::write(&old, b"old").unwrap();
        std::fs::set_permissions(&old, std::fs::Permissions::from_mode(0o640)).unwrap();
        write_atomically(b"new", &old).unwrap();
        assert_eq!(mode(&old), 0o640);
    }

    #[test]
    fn a_missing_folder_is_an_error_not_a_panic() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("no/such/folder/out.png");
        let err = write_atomically(b"new", &path).unwrap_err();
        assert!(format!("{err:#}").contains("cannot create a file in"));
        assert!(!path.exists());
    }
}
