//! `tracer pack`: a scene and every file it reads (included files, meshes)
//! in one zip archive, which `tracer render` and `tracer check` read as
//! they read the scene.
//!
//! The files keep their places relative to each other: each is stored at
//! its path below the deepest folder that holds them all, so a mesh at
//! `../meshes/x.obj` from the scene is still there from the stored scene,
//! and no entry is absolute or climbs with `..`. The entry `tracer-pack.toml`
//! names the scene file. A file named by an OBJ's `mtllib` or an MTL's
//! `map_Kd` must lie below the folder of the scene's own files: a model
//! from the internet does not take `/etc/passwd` into the archive.

use crate::load::{load, Input};
use crate::output::{check_not_an_input, OutputError, PendingFile};
use crate::Error;
use scene_format::read::{read_capped, MAX_OBJ_BYTES};
use scene_format::source::{Archive, Manifest, MANIFEST};
use std::io::{Cursor, Write};
use std::path::{Component, Path, PathBuf};
use zip::write::SimpleFileOptions;

/// What `pack` stored.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Packed {
    /// The entries, the scene file's first (the manifest left out).
    pub entries: Vec<String>,
    /// The size of the archive in bytes.
    pub bytes: usize,
}

/// Why a scene was not packed, beyond the scene's own errors.
#[derive(Debug, thiserror::Error)]
pub enum PackError {
    #[error("{}: expected an output ending in .zip", .0.display())]
    NotZip(PathBuf),
    #[error("{}: the scene is an archive already; pack its scene file", .0.display())]
    AlreadyPacked(PathBuf),
    #[error("{}: a packed scene (zip archive) is not converted; convert the .toml or .json scene file it holds (unzip it)", .0.display())]
    NotConverted(PathBuf),
    #[error("{}: cannot read it to pack it: {error}", file.display())]
    Read {
        file: PathBuf,
        error: std::io::Error,
    },
    #[error("{}:{line}: `{keyword}` names {}, outside {} where the scene's own files are; a pack holds only those", file.display(), named.display(), root.display())]
    Outside {
        file: PathBuf,
        line: usize,
        keyword: &'static str,
        named: PathBuf,
        root: PathBuf,
    },
    #[error("{}: the packed scene would not load (an absolute path in it?):\n{message}", file.display())]
    Unreadable { file: PathBuf, message: String },
    #[error("{}: cannot make the archive: {source}", file.display())]
    Zip {
        file: PathBuf,
        source: zip::result::ZipError,
    },
}

impl PackError {
    /// Whether the user's input is at fault rather than the machine.
    pub fn is_bad_input(&self) -> bool {
        match self {
            PackError::NotZip(_)
            | PackError::AlreadyPacked(_)
            | PackError::NotConverted(_)
            | PackError::Unreadable { .. }
            | PackError::Outside { .. } => true,
            PackError::Read { error, .. } => error.kind() != std::io::ErrorKind::Other,
            PackError::Zip { .. } => false,
        }
    }
}

/// Packs the scene file `scene` and the files it reads into the zip
/// archive `output`, written whole or not at all. A scene with errors is
/// refused with them, and no archive is written.
pub fn pack(scene: &Path, output: &Path) -> Result<Packed, Error> {
    let is_zip = |p: &Path| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("zip"));
    if !is_zip(output) {
        return Err(PackError::NotZip(output.to_path_buf()).into());
    }
    if is_zip(scene) {
        return Err(PackError::AlreadyPacked(scene.to_path_buf()).into());
    }
    check_not_an_input(output, &[scene])?;
    let pending = PendingFile::create(output)?;
    let loaded = load(&Input::File(scene.to_path_buf()))?;
    check_not_an_input(output, &loaded.files_read)?;
    check_references(&loaded.files_read)?;
    let names = entry_names(&loaded.files_read).map_err(|source| OutputError::Write {
        path: output.to_path_buf(),
        source,
    })?;
    // One file reached by two paths (`a.obj`, `./a.obj`) is stored once.
    let mut files = Vec::new();
    let mut stored: Vec<String> = Vec::new();
    for (file, name) in loaded.files_read.iter().zip(names) {
        if !stored.contains(&name) {
            files.push(file.clone());
            stored.push(name);
        }
    }
    let bytes = archive(output, &files, &stored)?;
    check_archive(output, &bytes, &stored[0])?;
    let size = bytes.len();
    pending.write_bytes(&bytes)?;
    Ok(Packed {
        entries: stored,
        bytes: size,
    })
}

/// Refuses a file named by an OBJ's `mtllib` or an MTL's `map_Kd` that
/// lies outside the folder holding the scene's own files (the scene, its
/// includes, its meshes and images): an OBJ from the internet naming
/// `/etc/passwd` or `../../../.ssh/id_rsa` would otherwise be packed with it.
fn check_references(files: &[PathBuf]) -> Result<(), PackError> {
    let absolute = |f: &Path| std::path::absolute(f).map(|a| lexical(&a)).ok();
    // Every name on a reference line that resolves to a file read, with
    // where it was named.
    let mut named = Vec::new();
    for file in files {
        let keyword = match file.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("obj") => "mtllib",
            Some(e) if e.eq_ignore_ascii_case("mtl") => "map_Kd",
            _ => continue,
        };
        let Ok(bytes) = read_capped(file, MAX_OBJ_BYTES) else {
            continue;
        };
        let folder = file.parent().unwrap_or(Path::new("."));
        let text = String::from_utf8_lossy(&bytes);
        for (n, line) in text.lines().enumerate() {
            let Some(rest) = line.trim_start().strip_prefix(keyword) else {
                continue;
            };
            // A name may hold spaces, and `map_Kd` options come before it:
            // the whole rest and each word are tried.
            let rest = rest.trim();
            for name in std::iter::once(rest).chain(rest.split_whitespace()) {
                if let Some(path) = absolute(&folder.join(name)) {
                    named.push((file.clone(), n + 1, keyword, path));
                }
            }
        }
    }
    let read: Vec<PathBuf> = files.iter().filter_map(|f| absolute(f)).collect();
    let own: Vec<PathBuf> = read
        .iter()
        .filter(|f| !named.iter().any(|(_, _, _, p)| p == *f))
        .cloned()
        .collect();
    let Some(first) = own.first() else {
        return Ok(());
    };
    let mut root = first.parent().unwrap_or(Path::new("/")).to_path_buf();
    for path in &own[1..] {
        while !path.starts_with(&root) && root.pop() {}
    }
    for (file, line, keyword, path) in named {
        if read.contains(&path) && !path.starts_with(&root) {
            return Err(PackError::Outside {
                file,
                line,
                keyword,
                named: path,
                root,
            });
        }
    }
    Ok(())
}

/// Loads the scene from the archive's bytes, as `tracer render` will: a
/// scene whose paths do not resolve inside (an absolute path to a mesh) is
/// refused rather than packed broken.
fn check_archive(output: &Path, bytes: &[u8], scene: &str) -> Result<(), PackError> {
    let unreadable = |message: String| PackError::Unreadable {
        file: output.to_path_buf(),
        message,
    };
    let archive =
        Archive::from_bytes(output, bytes.to_vec()).map_err(|e| unreadable(e.to_string()))?;
    scene_format::load_from(&archive, Path::new(scene))
        .map(drop)
        .map_err(|e| unreadable(e.to_string()))
}

/// The zip archive's bytes: the manifest naming the scene (the first
/// file), then every file under its entry name. Times are left at the zip
/// default, so packing the same files gives the same bytes.
fn archive(output: &Path, files: &[PathBuf], names: &[String]) -> Result<Vec<u8>, PackError> {
    let zip_error = |source| PackError::Zip {
        file: output.to_path_buf(),
        source,
    };
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let options = SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .large_file(false);
    let manifest = Manifest {
        scene: names[0].clone(),
    };
    // A string of one key always serializes.
    let text = toml::to_string(&manifest).unwrap_or_default();
    zip.start_file(MANIFEST, options).map_err(zip_error)?;
    zip.write_all(text.as_bytes())
        .map_err(|e| zip_error(e.into()))?;
    for (file, name) in files.iter().zip(names) {
        let bytes = read_capped(file, MAX_OBJ_BYTES).map_err(|error| PackError::Read {
            file: file.clone(),
            error,
        })?;
        let options = options.large_file(bytes.len() as u64 >= u32::MAX as u64);
        zip.start_file(name.as_str(), options).map_err(zip_error)?;
        zip.write_all(&bytes).map_err(|e| zip_error(e.into()))?;
    }
    Ok(zip.finish().map_err(zip_error)?.into_inner())
}

/// Each file's entry name: its path below the deepest folder holding them
/// all, `/`-separated.
fn entry_names(files: &[PathBuf]) -> std::io::Result<Vec<String>> {
    let absolute: Vec<PathBuf> = files
        .iter()
        .map(|f| std::path::absolute(f).map(|a| lexical(&a)))
        .collect::<Result<_, _>>()?;
    let mut common = absolute[0].parent().unwrap_or(Path::new("/")).to_path_buf();
    for path in &absolute[1..] {
        while !path.starts_with(&common) {
            if !common.pop() {
                break;
            }
        }
    }
    Ok(absolute
        .iter()
        .map(|path| {
            let below = path.strip_prefix(&common).unwrap_or(path);
            below
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect::<Vec<_>>()
                .join("/")
        })
        .collect())
}

/// An absolute path with `.` and `a/..` taken out, as the archive reader
/// resolves paths (not through symbolic links).
fn lexical(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entries_are_below_the_deepest_common_folder() {
        let files = [
            PathBuf::from("/w/scenes/a.toml"),
            PathBuf::from("/w/scenes/lib/m.toml"),
            PathBuf::from("/w/scenes/../meshes/x.obj"),
        ];
        assert_eq!(
            entry_names(&files).unwrap(),
            ["scenes/a.toml", "scenes/lib/m.toml", "meshes/x.obj"]
        );
        let alone = [PathBuf::from("/w/scenes/a.toml")];
        assert_eq!(entry_names(&alone).unwrap(), ["a.toml"]);
    }
}
