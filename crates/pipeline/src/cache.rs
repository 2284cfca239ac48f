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
//! not at all (`PendingFile`), with a checksum of their bytes keyed by the
//! entry's name: an entry proves it was written by this build for this
//! scene and these options (another scene's entry copied under this name
//! fails it). Only a regular file of bounded size is read, and what it
//! holds is checked (`PreparedScene::check`) before it is used.

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
const MAGIC: &[u8] = b"tracer prepared scene 2\n";
/// Largest entry read: a scene of the most primitives the tracer builds
/// takes about 1.5 GB kept.
const MAX_ENTRY_BYTES: u64 = 4 << 30;
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
    /// The hash the name is made of, the key of the entry's checksum.
    key: [u8; 32],
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
    #[error("{}: cannot make the folder: {error}", dir.display())]
    Folder { dir: PathBuf, error: std::io::Error },
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
        let key = hash.finalize();
        let name = format!("{}.prepared", &key.to_hex()[..32]);
        Some(CacheEntry {
            path: self.dir.join(name),
            key: *key.as_bytes(),
        })
    }
}

impl CacheEntry {
    /// The kept scene: `Ok(None)` if there is none; `Err(why)` if the entry
    /// cannot be used (damaged, or a file the scene was read from changed).
    pub fn read(&self, input: &Input, options: &Options) -> Result<Option<Cached>, String> {
        let start = Instant::now();
        // A regular file only, of bounded size: a FIFO would hang the
        // render, a link to /dev/zero would be read until memory runs out.
        let bytes = match scene_format::read::read_capped(&self.path, MAX_ENTRY_BYTES) {
            Ok(bytes) => bytes,
            // None yet (or no folder, where a file stands: said when kept).
            Err(e) if matches!(e.kind(), ErrorKind::NotFound | ErrorKind::NotADirectory) => {
                return Ok(None)
            }
            Err(e) => return Err(format!("cannot read it: it {e}")),
        };
        let stored = decode(&bytes, &self.key)?;
        stored
            .prepared
            .scene
            .check_kept()
            .map_err(|why| format!("it holds an inconsistent scene ({why})"))?;
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
        bytes.extend_from_slice(blake3::keyed_hash(&self.key, &payload).as_bytes());
        bytes.extend_from_slice(&payload);
        let dir = self.path.parent().unwrap_or(Path::new("."));
        std::fs::create_dir_all(dir).map_err(|error| CacheError::Folder {
            dir: dir.to_path_buf(),
            error,
        })?;
        // As an image is written: whole or not at all, readable by others
        // as a new file is, and no temporary file left by Ctrl-C.
        PendingFile::create(&self.path)?.write_bytes(&bytes)?;
        Ok(())
    }
}

/// The prepared scene of an entry's payload (its checksum left aside),
/// checked as a render would use it: the `cache` fuzz target's way in.
pub fn decode_payload(payload: &[u8]) -> Result<PreparedScene, String> {
    let stored: Stored = postcard::from_bytes(payload).map_err(|e| e.to_string())?;
    stored.prepared.scene.check_kept()?;
    Ok(stored.prepared)
}

/// An entry's data, its format and checksum (keyed by `key`) checked.
fn decode(bytes: &[u8], key: &[u8; 32]) -> Result<Stored, String> {
    let damaged =
        || "it is damaged, of another format, or written for another scene or build".to_string();
    let rest = bytes.strip_prefix(MAGIC).ok_or_else(damaged)?;
    if rest.len() < CHECKSUM {
        return Err(damaged());
    }
    let (checksum, payload) = rest.split_at(CHECKSUM);
    if blake3::keyed_hash(key, payload).as_bytes() != checksum {
        return Err(damaged());
    }
    postcard::from_bytes(payload).map_err(|_| damaged())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bytes of a kept scene changed one at a time and signed again, as a
    /// writer with the key could: each is refused or renders, never a panic.
    #[test]
    fn a_signed_entry_with_changed_bytes_is_refused_or_renders() {
        let dir = tempfile::tempdir().unwrap();
        let scene =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/boxes.toml");
        let input = Input::File(scene);
        let options = Options {
            width: Some(24),
            ..Options::default()
        };
        let loaded = crate::load(&input).unwrap();
        let files_read = loaded.files_read.clone();
        let digest = crate::tiles::digest(&input, &loaded, &options).unwrap();
        let prepared = crate::prepare_taking(loaded, &options, "--cache").unwrap();
        let entry = SceneCache::new(dir.path().into())
            .entry(&input, &options)
            .unwrap();
        entry.write(&prepared, &files_read, &digest, &[]).unwrap();
        let bytes = std::fs::read(&entry.path).unwrap();
        let payload = &bytes[MAGIC.len() + CHECKSUM..];
        let (mut refused, mut rendered) = (0, 0);
        for at in (0..payload.len()).step_by(payload.len() / 400 + 1) {
            for flip in [1u8, 0x80, 0xff] {
                let mut changed = payload.to_vec();
                changed[at] ^= flip;
                match decode_payload(&changed) {
                    Ok(kept) => {
                        crate::render_prepared(&kept, &options, &|_| {}).unwrap();
                        rendered += 1;
                    }
                    Err(_) => refused += 1,
                }
            }
        }
        assert!(
            refused > 0 && rendered > 0,
            "{refused} refused, {rendered} rendered"
        );
    }
}
