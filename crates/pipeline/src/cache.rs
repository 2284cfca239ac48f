//! `--cache DIR`: a scene prepared once (meshes read, objects made, BVH
//! built) and kept in a file, which later renders of the same scene with
//! the same options read instead of preparing it again. A render farm's
//! tasks each render a part of one scene: without it, each pays the whole
//! preparation again.
//!
//! An entry is named by a key of the tracer's build, the scene file's real
//! path and bytes, and the render options; it holds the files the scene was
//! read from and their digest (the tiles' digest), checked again before the
//! entry is used, so a changed mesh, texture or included file is never
//! rendered from an old entry. Entries are written as images are, whole or
//! not at all (`PendingFile`), with a checksum of their bytes.

use crate::load::Input;
use crate::options::Options;
use crate::output::{OutputError, PendingFile};
use crate::scene3d::PreparedScene;
use crate::tiles::{add, add_file, digest_of};
use serde::{Deserialize, Serialize};
use std::io::ErrorKind;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What an entry starts with: the format, before the checksum and the data.
const MAGIC: &[u8] = b"tracer prepared scene 1\n";
/// Bytes of the checksum (BLAKE3) after the magic.
const CHECKSUM: usize = 32;

/// The folder of `--cache`.
#[derive(Debug, Clone)]
pub struct SceneCache {
    dir: PathBuf,
}

/// One scene's place in the cache.
#[derive(Debug, Clone)]
pub struct CacheEntry {
    pub path: PathBuf,
}

/// A scene prepared by an earlier render and kept, with what that render
/// knew of it.
#[derive(Debug)]
pub struct Cached {
    pub prepared: PreparedScene,
    /// The files the scene was read from (real paths), as `Loaded::files_read`.
    pub files_read: Vec<PathBuf>,
    /// The tiles' digest of the scene and options (`tiles::digest`).
    pub digest: String,
    /// The warnings its loading gave, as they were printed.
    pub warnings: Vec<String>,
}

/// What an entry's data is.
#[derive(Deserialize)]
struct Stored {
    files_read: Vec<PathBuf>,
    digest: String,
    warnings: Vec<String>,
    prepared: PreparedScene,
}

/// `Stored`, borrowed for writing (the same bytes).
#[derive(Serialize)]
struct ToStore<'a> {
    files_read: &'a [PathBuf],
    digest: &'a str,
    warnings: &'a [String],
    prepared: &'a PreparedScene,
}

/// Why a kept scene could not be kept.
#[derive(Debug, thiserror::Error)]
pub enum CacheError {
    #[error("{}: cannot make the folder: {source}", dir.display())]
    Folder {
        dir: PathBuf,
        source: std::io::Error,
    },
    #[error(transparent)]
    Write(#[from] OutputError),
    #[error("a scene with instances is not kept (each instance would hold its own copy of the shared mesh)")]
    Instances,
    #[error("this scene cannot be kept: {0}")]
    Encode(String),
}

impl SceneCache {
    pub fn new(dir: PathBuf) -> SceneCache {
        SceneCache { dir }
    }

    /// Where the scene of `input` rendered with `options` is kept; None
    /// when it cannot be named (the scene file or the tracer's own file
    /// cannot be read): the render then prepares the scene as without a
    /// cache.
    pub fn entry(&self, input: &Input, options: &Options) -> Option<CacheEntry> {
        let mut hash = blake3::Hasher::new();
        add(&mut hash, MAGIC);
        add(&mut hash, env!("CARGO_PKG_VERSION").as_bytes());
        // Another build of the tracer may lay its scenes out otherwise.
        let exe = std::env::current_exe().ok()?.metadata().ok()?;
        let built = exe.modified().ok()?.duration_since(std::time::UNIX_EPOCH);
        add(
            &mut hash,
            format!("{} {:?}", exe.len(), built.ok()?).as_bytes(),
        );
        match input {
            Input::File(path) => {
                // The same file elsewhere may name other meshes beside it.
                let real = path.canonicalize().ok()?;
                add(&mut hash, real.to_string_lossy().as_bytes());
                add_file(&mut hash, path).ok()?;
            }
            Input::DefaultScene => add(&mut hash, crate::load::DEFAULT_SCENE.as_bytes()),
        }
        let options = Options {
            part: None,
            ..*options
        };
        add(&mut hash, format!("{options:?}").as_bytes());
        let name = format!("{}.prepared", &hash.finalize().to_hex()[..32]);
        Some(CacheEntry {
            path: self.dir.join(name),
        })
    }
}

impl CacheEntry {
    /// The kept scene: `Ok(None)` if there is none; `Err(why)` if the entry
    /// cannot be used (damaged, or a file the scene was read from changed).
    pub fn read(&self, input: &Input, options: &Options) -> Result<Option<Cached>, String> {
        let start = Instant::now();
        let bytes = match std::fs::read(&self.path) {
            Ok(bytes) => bytes,
            // None yet (or no folder, where a file stands: said when kept).
            Err(e) if matches!(e.kind(), ErrorKind::NotFound | ErrorKind::NotADirectory) => {
                return Ok(None)
            }
            Err(e) => return Err(format!("cannot read it: {e}")),
        };
        let stored = decode(&bytes)?;
        let size = stored.prepared.size();
        let digest =
            digest_of(input, &stored.files_read, options, size).map_err(|e| e.to_string())?;
        if digest != stored.digest {
            return Err("a file the scene was read from has changed".into());
        }
        let mut prepared = stored.prepared;
        prepared.prepare_seconds = start.elapsed().as_secs_f64();
        Ok(Some(Cached {
            prepared,
            files_read: stored.files_read,
            digest: stored.digest,
            warnings: stored.warnings,
        }))
    }

    /// Keeps `prepared`, read from `files_read`, with its tiles' `digest` and
    /// the `warnings` its loading printed; written whole or not at all.
    pub fn write(
        &self,
        prepared: &PreparedScene,
        files_read: &[PathBuf],
        digest: &str,
        warnings: &[String],
    ) -> Result<(), CacheError> {
        if prepared.scene.has_instances() {
            return Err(CacheError::Instances);
        }
        let files_read: Vec<PathBuf> = files_read
            .iter()
            .map(|p| p.canonicalize().unwrap_or_else(|_| p.clone()))
            .collect();
        let stored = ToStore {
            files_read: &files_read,
            digest,
            warnings,
            prepared,
        };
        let payload =
            postcard::to_allocvec(&stored).map_err(|e| CacheError::Encode(e.to_string()))?;
        let mut bytes = Vec::with_capacity(MAGIC.len() + CHECKSUM + payload.len());
        bytes.extend_from_slice(MAGIC);
        bytes.extend_from_slice(blake3::hash(&payload).as_bytes());
        bytes.extend_from_slice(&payload);
        let dir = self.path.parent().unwrap_or(Path::new("."));
        std::fs::create_dir_all(dir).map_err(|source| CacheError::Folder {
            dir: dir.to_path_buf(),
            source,
        })?;
        // As an image is written: whole or not at all, readable by others
        // as a new file is, and no temporary file left by Ctrl-C.
        PendingFile::create(&self.path)?.write_bytes(&bytes)?;
        Ok(())
    }
}

/// An entry's data, its format and checksum checked.
fn decode(bytes: &[u8]) -> Result<Stored, String> {
    let damaged = || "it is damaged or of another format".to_string();
    let rest = bytes.strip_prefix(MAGIC).ok_or_else(damaged)?;
    if rest.len() < CHECKSUM {
        return Err(damaged());
    }
    let (checksum, payload) = rest.split_at(CHECKSUM);
    if blake3::hash(payload).as_bytes() != checksum {
        return Err(damaged());
    }
    postcard::from_bytes(payload).map_err(|_| damaged())
}
