//! Reading an input file (a scene, an OBJ, a CSV) with bounds: only a
//! regular file, and no larger than a cap. `/dev/zero`, a FIFO or a
//! runaway file would otherwise be read until memory runs out.

use std::fs::File;
use std::io::{self, Read};
use std::path::Path;

const MIB: u64 = 1024 * 1024;

/// Largest scene file read (far above any hand-written scene).
pub const MAX_SCENE_BYTES: u64 = 64 * MIB;
/// Largest OBJ file read (a scanned model of tens of millions of faces).
pub const MAX_OBJ_BYTES: u64 = 1024 * MIB;
/// Largest measurements CSV read.
pub const MAX_CSV_BYTES: u64 = 64 * MIB;

/// Opens `path` for reading at most `cap` bytes, or an error of kind
/// `InvalidInput` that says why not: a folder, not a regular file (a device,
/// a FIFO, a socket), or larger than `cap`. Symbolic links are followed.
pub fn open_capped(path: &Path, cap: u64) -> io::Result<io::Take<File>> {
    // The file may grow while it is read: never past the cap (+1 to tell).
    Ok(open_regular(path, cap)?.take(cap + 1))
}

/// Opens `path`, a regular file of at most `cap` bytes as it is opened
/// (see [`open_capped`]), for a reader that seeks (a zip archive).
pub fn open_regular(path: &Path, cap: u64) -> io::Result<File> {
    // Checked before opening (opening a FIFO waits for a writer), and again
    // on the opened file, in case it was swapped in between.
    check(&std::fs::metadata(path)?, cap)?;
    let file = File::open(path)?;
    check(&file.metadata()?, cap)?;
    Ok(file)
}

fn check(meta: &std::fs::Metadata, cap: u64) -> io::Result<()> {
    let refuse = |message: String| Err(io::Error::new(io::ErrorKind::InvalidInput, message));
    if meta.is_dir() {
        return refuse("is a folder, not a file".to_string());
    }
    if !meta.is_file() {
        return refuse("is not a regular file (a device, a pipe or a socket)".to_string());
    }
    check_size(meta.len(), cap)
}

/// An `InvalidInput` error unless a file of `len` bytes is within `cap`:
/// the one message for every source of files (disk, memory).
pub(crate) fn check_size(len: u64, cap: u64) -> io::Result<()> {
    if len > cap {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "is {}; files of this kind are read up to {}",
                size(len),
                size(cap)
            ),
        ));
    }
    Ok(())
}

/// The whole of a regular file of at most `cap` bytes (see [`open_capped`]).
pub fn read_capped(path: &Path, cap: u64) -> io::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    open_capped(path, cap)?.read_to_end(&mut bytes)?;
    if bytes.len() as u64 > cap {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("grew past {} while it was read", size(cap)),
        ));
    }
    Ok(bytes)
}

/// A byte count as people read it: "64 MiB", "1 GiB", "1.5 KiB", "12 bytes".
fn size(bytes: u64) -> String {
    let units = [("GiB", 1024 * MIB), ("MiB", MIB), ("KiB", 1024)];
    for (unit, scale) in units {
        if bytes >= scale {
            let value = bytes as f64 / scale as f64;
            return if bytes.is_multiple_of(scale) {
                format!("{} {unit}", bytes / scale)
            } else {
                format!("{value:.1} {unit}")
            };
        }
    }
    format!("{bytes} bytes")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_regular_file_within_the_cap_is_read_whole() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f.toml");
        std::fs::write(&path, b"12345").unwrap();
        assert_eq!(read_capped(&path, 5).unwrap(), b"12345");
    }

    #[test]
    fn a_file_over_the_cap_is_refused_before_it_is_read() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big.toml");
        // Sparse: its size says 65 MiB, no data is written.
        let file = File::create(&path).unwrap();
        file.set_len(MAX_SCENE_BYTES + MIB).unwrap();
        let err = read_capped(&path, MAX_SCENE_BYTES).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidInput);
        assert_eq!(
            err.to_string(),
            "is 65 MiB; files of this kind are read up to 64 MiB"
        );
    }

    #[cfg(unix)]
    #[test]
    fn devices_fifos_and_folders_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let zero = read_capped(Path::new("/dev/zero"), MAX_SCENE_BYTES).unwrap_err();
        assert!(zero.to_string().contains("not a regular file"), "{zero}");
        let fifo = dir.path().join("fifo.toml");
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(made.success());
        // Refused without waiting for a writer.
        let err = read_capped(&fifo, MAX_SCENE_BYTES).unwrap_err();
        assert!(err.to_string().contains("not a regular file"), "{err}");
        let folder = read_capped(dir.path(), MAX_SCENE_BYTES).unwrap_err();
        assert_eq!(folder.to_string(), "is a folder, not a file");
    }

    #[test]
    fn sizes_read_as_people_write_them() {
        assert_eq!(size(12), "12 bytes");
        assert_eq!(size(1536), "1.5 KiB");
        assert_eq!(size(MAX_OBJ_BYTES), "1 GiB");
    }
}
