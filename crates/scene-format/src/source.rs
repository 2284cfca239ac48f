//! Where a scene's files are read from: a folder of the file system, or a
//! zip archive made by `tracer pack`. The loaders read every file (scene,
//! included files, meshes) through a `Source`, so one loader serves both,
//! and the source records what was read (the files `tracer pack` stores and
//! the pipeline refuses to overwrite).

use crate::read::{open_capped, open_regular};
use std::cell::RefCell;
use std::io::{self, BufRead, BufReader, Cursor, Read, Seek};
use std::path::{Component, Path, PathBuf};
use std::sync::Mutex;

/// Largest zip archive opened (a packed scene with its meshes).
pub const MAX_ARCHIVE_BYTES: u64 = 4 * 1024 * 1024 * 1024;

/// The files of a scene, by path: a path names a file as the loader found
/// it (a scene's folder joined with a relative path from the scene).
pub trait Source {
    /// The file at `path`, read up to `cap` bytes (an `InvalidInput` error
    /// beyond). The path is recorded as read.
    fn open(&self, path: &Path, cap: u64) -> io::Result<Box<dyn BufRead + '_>>;

    /// How messages name the file at `path`.
    fn name(&self, path: &Path) -> PathBuf;

    /// The one identity of a file reached by several paths (`a/../b.toml`
    /// and `b.toml`), to tell a file included twice.
    fn identity(&self, path: &Path) -> PathBuf;

    /// Every file opened so far, each once, in the order first opened.
    fn files_read(&self) -> Vec<PathBuf>;

    /// The whole file at `path`, at most `cap` bytes.
    fn read(&self, path: &Path, cap: u64) -> io::Result<Vec<u8>> {
        let mut bytes = Vec::new();
        self.open(path, cap)?
            .take(cap + 1)
            .read_to_end(&mut bytes)?;
        if bytes.len() as u64 > cap {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("grew past {} bytes while it was read", cap),
            ));
        }
        Ok(bytes)
    }
}

/// The list of files read, each once.
#[derive(Debug, Default)]
struct Record(RefCell<Vec<PathBuf>>);

impl Record {
    fn add(&self, path: &Path) {
        let mut files = self.0.borrow_mut();
        if !files.iter().any(|f| f == path) {
            files.push(path.to_path_buf());
        }
    }
}

/// Files of the file system, paths as given (relative to the current folder
/// or absolute).
#[derive(Debug, Default)]
pub struct Folder {
    read: Record,
}

impl Folder {
    pub fn new() -> Self {
        Folder::default()
    }
}

impl Source for Folder {
    fn open(&self, path: &Path, cap: u64) -> io::Result<Box<dyn BufRead + '_>> {
        let file = open_capped(path, cap)?;
        self.read.add(path);
        Ok(Box::new(BufReader::new(file)))
    }

    fn name(&self, path: &Path) -> PathBuf {
        path.to_path_buf()
    }

    fn identity(&self, path: &Path) -> PathBuf {
        std::fs::canonicalize(path).unwrap_or_else(|_| normalize(path).unwrap_or_default())
    }

    fn files_read(&self) -> Vec<PathBuf> {
        self.read.0.borrow().clone()
    }
}

/// The files of a zip archive, by their paths inside it. Entries are read
/// into memory, each up to the cap the loader asks for; nothing is
/// extracted to disk, and an archive with an entry that would leave its
/// folder (`../x`, `/x`, `C:\x`) is refused whole when opened.
pub struct Archive {
    file: PathBuf,
    zip: Mutex<zip::ZipArchive<Box<dyn ReadSeek>>>,
    /// Bytes inflated so far, and the most allowed: a few times the sum of
    /// the entries' sizes, so a scene that reads one entry again and again
    /// (a bomb named by a thousand files) is stopped.
    inflated: std::cell::Cell<u64>,
    inflate_limit: u64,
    /// The archive's length: no entry's packed bytes can be more, whatever
    /// its header says.
    length: u64,
    /// The scene file inside: named by the manifest, or the only top-level
    /// `.toml`/`.json` entry.
    scene: PathBuf,
    read: Record,
}

/// What a zip archive is read from: a file, or bytes in memory.
pub trait ReadSeek: Read + Seek + Send {}

impl<T: Read + Seek + Send> ReadSeek for T {}

/// How many times over a scene may read its archive's entries: an OBJ is
/// read, scanned for its bad line and for its first degenerate face.
const INFLATE_TIMES: u128 = 4;

/// The entry naming the scene file of an archive made by `tracer pack`.
pub const MANIFEST: &str = "tracer-pack.toml";

/// What the manifest holds.
#[derive(serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// The scene file inside the archive.
    pub scene: String,
}

impl Archive {
    /// Opens the archive at `file` and finds its scene file. The errors are
    /// `InvalidData` with a message for a reader.
    pub fn open(file: &Path) -> io::Result<Archive> {
        Archive::read_from(file, Box::new(open_regular(file, MAX_ARCHIVE_BYTES)?))
    }

    /// The archive of `bytes`, named `file` in messages: an archive checked
    /// before it is written.
    pub fn from_bytes(file: &Path, bytes: Vec<u8>) -> io::Result<Archive> {
        Archive::read_from(file, Box::new(Cursor::new(bytes)))
    }

    fn read_from(file: &Path, mut reader: Box<dyn ReadSeek>) -> io::Result<Archive> {
        let length = reader.seek(io::SeekFrom::End(0))?;
        reader.rewind()?;
        let zip = zip::ZipArchive::new(reader).map_err(zip_error)?;
        let zip = refuse_duplicate_names(zip)?;
        let sizes = zip.decompressed_size().unwrap_or(u128::MAX);
        let inflate_limit = u64::try_from(sizes.saturating_mul(INFLATE_TIMES))
            .unwrap_or(u64::MAX)
            .max(1 << 20);
        let mut archive = Archive {
            file: file.to_path_buf(),
            zip: Mutex::new(zip),
            inflated: std::cell::Cell::new(0),
            inflate_limit,
            length,
            scene: PathBuf::new(),
            read: Record::default(),
        };
        let names = archive.entry_names()?;
        archive.scene = archive.scene_entry(&names)?;
        Ok(archive)
    }

    /// The path of the scene file inside the archive.
    pub fn scene(&self) -> &Path {
        &self.scene
    }

    /// Every entry's name, checked to stay inside the archive's folder.
    fn entry_names(&self) -> io::Result<Vec<PathBuf>> {
        let zip = self
            .zip
            .lock()
            .map_err(|_| bad("the archive's reader failed"))?;
        let mut names = Vec::new();
        for name in zip.file_names() {
            match safe_entry(name) {
                Some(path) => names.push(path),
                None => {
                    return Err(bad(format!(
                        "entry `{}` would be read from outside the archive's folder; \
                         expected relative paths without `..`",
                        name.escape_debug()
                    )))
                }
            }
        }
        Ok(names)
    }

    fn scene_entry(&self, names: &[PathBuf]) -> io::Result<PathBuf> {
        if names.iter().any(|n| n == Path::new(MANIFEST)) {
            let bytes = self.entry(Path::new(MANIFEST), 64 * 1024)?;
            let text = String::from_utf8(bytes).map_err(bad)?;
            let manifest: Manifest = toml::from_str(&text).map_err(|e| {
                let before =
                    |s: std::ops::Range<usize>| &text.as_bytes()[..s.start.min(text.len())];
                let line = e
                    .span()
                    .map_or(1, |s| 1 + before(s).iter().filter(|&&b| b == b'\n').count());
                bad(format!(
                    "{MANIFEST}, line {line}: {}",
                    e.message().trim_end()
                ))
            })?;
            return normalize(Path::new(&manifest.scene)).ok_or_else(|| {
                bad(format!(
                    "{MANIFEST}: `scene` leaves the archive: {}",
                    manifest.scene
                ))
            });
        }
        let top: Vec<&PathBuf> = names
            .iter()
            .filter(|n| n.components().count() == 1 && crate::Format::from_path(n).is_some())
            .collect();
        match top[..] {
            [one] => Ok(one.clone()),
            _ => Err(bad(format!(
                "found {} top-level .toml/.json files and no {MANIFEST}; expected one scene file",
                top.len()
            ))),
        }
    }

    /// The bytes of the entry at `path` (normalized), at most `cap`.
    fn entry(&self, path: &Path, cap: u64) -> io::Result<Vec<u8>> {
        let name = entry_name(path).ok_or_else(|| not_found("leaves the archive"))?;
        let mut zip = self
            .zip
            .lock()
            .map_err(|_| bad("the archive's reader failed"))?;
        let entry = match zip.by_name(&name) {
            Ok(entry) => entry,
            Err(zip::result::ZipError::FileNotFound) => {
                return Err(not_found("no such file in the archive"))
            }
            Err(e) => return Err(zip_error(e)),
        };
        if entry.is_dir() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "is a folder, not a file",
            ));
        }
        if entry.size() > cap {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!(
                    "is {} bytes; files of this kind are read up to {cap}",
                    entry.size()
                ),
            ));
        }
        let declared = entry.size();
        // A forged header may claim more packed bytes than there are.
        too_packed(declared, entry.compressed_size().min(self.length))?;
        let inflated = self.inflated.get().saturating_add(declared);
        if inflated > self.inflate_limit {
            return Err(bad(format!(
                "the scene reads the archive's entries more than {INFLATE_TIMES} times over \
                 ({inflated} bytes inflated); expected each file to be named once"
            )));
        }
        self.inflated.set(inflated);
        // The declared size may lie (a zip bomb): never inflate past it.
        // Reserved whole, as growing by doubling may take twice the bytes.
        let mut bytes = Vec::with_capacity(usize::try_from(declared).unwrap_or(0));
        entry
            .take(declared + 1)
            .read_to_end(&mut bytes)
            .map_err(|e| bad(format!("the entry cannot be inflated: {e}")))?;
        if bytes.len() as u64 > declared {
            return Err(bad("an entry holds more than its declared size"));
        }
        Ok(bytes)
    }
}

impl Source for Archive {
    fn open(&self, path: &Path, cap: u64) -> io::Result<Box<dyn BufRead + '_>> {
        let bytes = self.entry(path, cap)?;
        self.read.add(path);
        Ok(Box::new(Cursor::new(bytes)))
    }

    fn name(&self, path: &Path) -> PathBuf {
        let inside = entry_name(path).unwrap_or_else(|| path.display().to_string());
        PathBuf::from(format!("{}:{inside}", self.file.display()))
    }

    fn identity(&self, path: &Path) -> PathBuf {
        normalize(path).unwrap_or_else(|| path.to_path_buf())
    }

    fn files_read(&self) -> Vec<PathBuf> {
        self.read.0.borrow().clone()
    }
}

/// Files held in memory, by path (relative, `/`-separated, as in a
/// folder): what the browser build (crates/web) reads a scene from, the
/// files given by the page. The same caps apply as on the file system.
#[derive(Debug, Default)]
pub struct Memory {
    files: std::collections::BTreeMap<PathBuf, Vec<u8>>,
    read: Record,
}

impl Memory {
    pub fn new() -> Self {
        Memory::default()
    }

    /// Adds (or replaces) the file at `path`; a path that climbs out of
    /// the folder (`../x`, `/x`) is refused.
    pub fn insert(&mut self, path: &Path, bytes: Vec<u8>) -> io::Result<()> {
        let key = normalize(path)
            .filter(|p| !p.as_os_str().is_empty())
            .ok_or_else(|| not_found("leaves the folder"))?;
        self.files.insert(key, bytes);
        Ok(())
    }

    /// Every file's path, in name order.
    pub fn paths(&self) -> Vec<PathBuf> {
        self.files.keys().cloned().collect()
    }
}

impl Source for Memory {
    fn open(&self, path: &Path, cap: u64) -> io::Result<Box<dyn BufRead + '_>> {
        let key = normalize(path).ok_or_else(|| not_found("leaves the folder"))?;
        let Some(bytes) = self.files.get(&key) else {
            if self.files.keys().any(|k| k.starts_with(&key)) {
                return Err(io::Error::new(
                    io::ErrorKind::InvalidInput,
                    "is a folder, not a file",
                ));
            }
            return Err(not_found("no such file"));
        };
        crate::read::check_size(bytes.len() as u64, cap)?;
        self.read.add(path);
        Ok(Box::new(Cursor::new(bytes.as_slice())))
    }

    fn name(&self, path: &Path) -> PathBuf {
        path.to_path_buf()
    }

    fn identity(&self, path: &Path) -> PathBuf {
        normalize(path).unwrap_or_else(|| path.to_path_buf())
    }

    fn files_read(&self) -> Vec<PathBuf> {
        self.read.0.borrow().clone()
    }
}

/// `path` with `.` and `a/..` taken out, or `None` when it is absolute or
/// climbs above its start.
pub fn normalize(path: &Path) -> Option<PathBuf> {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::Normal(part) => out.push(part),
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    return None;
                }
            }
            Component::RootDir | Component::Prefix(_) => return None,
        }
    }
    Some(out)
}

/// An entry's name as a relative path, or `None` if it would leave the
/// archive's folder (zip-slip) once extracted: `..`, absolute, a drive.
fn safe_entry(name: &str) -> Option<PathBuf> {
    if name.contains('\\') || name.contains('\0') {
        return None;
    }
    let path = Path::new(name);
    let clean = path
        .components()
        .all(|c| matches!(c, Component::Normal(_) | Component::CurDir));
    clean.then(|| path.components().collect())
}

/// The archive, unless two of its entries have one name: the zip crate
/// keeps the last of them without a word, so which file a scene reads would
/// be a guess. Its central directory is read again, header by header.
fn refuse_duplicate_names(
    zip: zip::ZipArchive<Box<dyn ReadSeek>>,
) -> io::Result<zip::ZipArchive<Box<dyn ReadSeek>>> {
    let (start, kept) = (zip.central_directory_start(), zip.len());
    let mut reader = zip.into_inner();
    reader.seek(io::SeekFrom::Start(start))?;
    if let Some(name) = first_repeated_name(&mut BufReader::new(&mut reader), kept)? {
        return Err(bad(format!(
            "the archive holds two entries named `{}`; expected each file once",
            name.escape_debug()
        )));
    }
    reader.rewind()?;
    zip::ZipArchive::new(reader).map_err(zip_error)
}

/// The first name found twice among the central directory's headers, read
/// from where `reader` is. There are more headers than the `kept` names
/// only if some name repeats, so at most `kept + 1` are read.
fn first_repeated_name(reader: &mut impl Read, kept: usize) -> io::Result<Option<String>> {
    const CENTRAL_HEADER: u32 = 0x0201_4b50;
    let mut seen = std::collections::HashSet::new();
    for _ in 0..=kept {
        // The signature alone first: the directory's end record after the
        // last header is shorter than a header.
        let mut header = [0; 46];
        reader.read_exact(&mut header[..4])?;
        if u32::from_le_bytes([header[0], header[1], header[2], header[3]]) != CENTRAL_HEADER {
            break;
        }
        reader.read_exact(&mut header[4..])?;
        let field = |at: usize| u16::from_le_bytes([header[at], header[at + 1]]);
        let mut name = vec![0; usize::from(field(28))];
        reader.read_exact(&mut name)?;
        let name = String::from_utf8_lossy(&name).into_owned();
        let rest = u64::from(field(30)) + u64::from(field(32));
        io::copy(&mut reader.take(rest), &mut io::sink())?;
        if !seen.insert(name.clone()) {
            return Ok(Some(name));
        }
    }
    Ok(None)
}

/// An entry larger than this may not pack more than [`MAX_PACKING`] times.
const BOMB_FLOOR: u64 = 16 * 1024 * 1024;
/// How many times smaller than its bytes a large entry may be packed:
/// scene files, meshes and images pack 2 to 20 times; a run of one
/// character packs a thousand times, a few bytes of archive making
/// gigabytes of memory.
const MAX_PACKING: u64 = 200;

/// Refuses a large entry packed far tighter than a scene's files pack.
fn too_packed(declared: u64, compressed: u64) -> io::Result<()> {
    if declared > BOMB_FLOOR && declared > compressed.max(1).saturating_mul(MAX_PACKING) {
        return Err(bad(format!(
            "the entry inflates from {compressed} to {declared} bytes, over {MAX_PACKING} \
             times; expected a scene's files, which pack far less (a zip bomb?)"
        )));
    }
    Ok(())
}

/// The zip entry name of a path inside the archive: `/`-separated.
fn entry_name(path: &Path) -> Option<String> {
    let parts: Vec<String> = normalize(path)?
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    (!parts.is_empty()).then(|| parts.join("/"))
}

/// A zip error for a reader: a cut or damaged archive says so, where the
/// zip crate says only "i/o error".
fn zip_error(e: zip::result::ZipError) -> io::Error {
    use zip::result::ZipError;
    match e {
        ZipError::Io(_) | ZipError::InvalidArchive(_) => bad(format!(
            "the archive is damaged or cut short ({e}); expected a whole zip file"
        )),
        other => bad(other),
    }
}

fn bad(e: impl ToString) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, e.to_string())
}

fn not_found(message: &str) -> io::Error {
    io::Error::new(io::ErrorKind::NotFound, message.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_large_entry_packed_past_the_limit_is_refused() {
        assert!(too_packed(BOMB_FLOOR, 1).is_ok());
        assert!(too_packed(BOMB_FLOOR + 1, (BOMB_FLOOR + 1).div_ceil(MAX_PACKING)).is_ok());
        assert!(too_packed(BOMB_FLOOR + 1, (BOMB_FLOOR + 1) / MAX_PACKING).is_err());
        let err = too_packed(1 << 30, 1 << 20).unwrap_err();
        assert!(err.to_string().contains("over 200 times"), "{err}");
        assert!(too_packed(1 << 30, 0).is_err());
    }

    #[test]
    fn files_in_memory_are_read_like_a_folder_with_the_same_caps() {
        let mut memory = Memory::new();
        memory
            .insert(Path::new("meshes/a.obj"), b"v 0 0 0".to_vec())
            .unwrap();
        assert!(memory.insert(Path::new("../x.obj"), Vec::new()).is_err());
        let read = memory
            .read(Path::new("scenes/../meshes/./a.obj"), 100)
            .unwrap();
        assert_eq!(read, b"v 0 0 0");
        let big = memory.read(Path::new("meshes/a.obj"), 4).unwrap_err();
        assert_eq!(big.kind(), io::ErrorKind::InvalidInput);
        assert_eq!(
            big.to_string(),
            "is 7 bytes; files of this kind are read up to 4 bytes"
        );
        let folder = memory.read(Path::new("meshes"), 100).unwrap_err();
        assert_eq!(folder.to_string(), "is a folder, not a file");
        let missing = memory.read(Path::new("b.obj"), 100).unwrap_err();
        assert_eq!(missing.kind(), io::ErrorKind::NotFound);
        assert_eq!(
            memory.files_read(),
            [PathBuf::from("scenes/../meshes/./a.obj")]
        );
    }

    #[test]
    fn paths_climbing_out_are_not_normalized() {
        assert_eq!(
            normalize(Path::new("scenes/../meshes/./x.obj")),
            Some(PathBuf::from("meshes/x.obj"))
        );
        assert_eq!(normalize(Path::new("a/../../x")), None);
        assert_eq!(normalize(Path::new("/etc/passwd")), None);
    }

    #[test]
    fn unsafe_entry_names_are_told() {
        assert!(safe_entry("scenes/a.toml").is_some());
        for name in [
            "../a.toml",
            "a/../../b",
            "/etc/passwd",
            "a\\..\\b",
            "a/../b",
        ] {
            assert_eq!(safe_entry(name), None, "{name}");
        }
    }
}
