//! Writing output files whole or not at all, in the format their
//! extension names.

use std::io::Write;
use std::path::{Path, PathBuf};

/// Why an output file was not written; the file is then as it was before.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("cannot encode the {format}")]
    Encode {
        format: &'static str,
        #[source]
        source: image::ImageError,
    },
    #[error("cannot create a file in {}", dir.display())]
    Create {
        dir: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("cannot write {}", path.display())]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// The image file formats written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    Png,
}

impl ImageFormat {
    /// The format for an output path. Only PNG is written so far, whatever
    /// the extension (as the tracer always did); EXR and the others join here.
    pub fn for_path(_path: &Path) -> ImageFormat {
        ImageFormat::Png
    }

    fn name(self) -> &'static str {
        match self {
            ImageFormat::Png => "PNG",
        }
    }
}

/// Writes `image` to `path`, in the format of its extension, through a
/// temporary file in the same folder and a rename: a failure leaves no
/// partial file and an existing image untouched.
pub fn write_image(image: &image::RgbImage, path: &Path) -> Result<(), OutputError> {
    write_atomically(&encode(image, ImageFormat::for_path(path))?, path)
}

/// The bytes of an image file in `format`.
pub fn encode(image: &image::RgbImage, format: ImageFormat) -> Result<Vec<u8>, OutputError> {
    let encoder = match format {
        ImageFormat::Png => image::ImageFormat::Png,
    };
    let mut bytes = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut bytes), encoder)
        .map_err(|source| OutputError::Encode {
            format: format.name(),
            source,
        })?;
    Ok(bytes)
}

/// Writes `bytes` to `path` whole or not at all (see `write_image`).
pub fn write_atomically(bytes: &[u8], path: &Path) -> Result<(), OutputError> {
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
        .map_err(|source| OutputError::Create {
            dir: dir.to_path_buf(),
            source,
        })?;
    let write_error = |source| OutputError::Write {
        path: path.to_path_buf(),
        source,
    };
    tmp.write_all(bytes)
        .and_then(|()| tmp.as_file().sync_all())
        .map_err(write_error)?;
    tmp.persist(path).map_err(|e| write_error(e.error))?;
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
        assert!(err.to_string().contains("cannot create a file in"));
        assert!(!path.exists());
    }

    #[test]
    fn an_image_is_written_as_png_whatever_its_extension() {
        let dir = tempfile::tempdir().unwrap();
        let image = image::RgbImage::from_pixel(3, 2, image::Rgb([10, 20, 30]));
        for name in ["a.png", "b.jpg", "c"] {
            let path = dir.path().join(name);
            write_image(&image, &path).unwrap();
            let bytes = std::fs::read(&path).unwrap();
            assert_eq!(bytes, encode(&image, ImageFormat::Png).unwrap(), "{name}");
            assert!(bytes.starts_with(b"\x89PNG"), "{name}");
        }
    }
}
