//! Finding and loading Intel Open Image Denoise (OIDN) 2 at run time: the
//! tracer builds and runs without it, and `--denoise` asks for it only when
//! used. The library is looked for in the project's folder that
//! `cargo xtask oidn` fills (`target/oidn/lib`, from PyPI's `pyoidn`
//! wheel), then in `pyoidn`'s own folder when that package is installed
//! (`pip install pyoidn`); no environment variable is read.

use super::DenoiseError;
use libloading::Library;
use std::ffi::{c_char, c_void, CStr};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// The file loaded: the version `cargo xtask oidn` installs (its soname is
/// `libOpenImageDenoise.so.2`; the `.so.2.5.1` name is the one the wheel
/// ships whole).
const LIBRARY_FILE: &str = "libOpenImageDenoise.so.2.5.1";

/// The folder `cargo xtask oidn` fills (`lib/` and `bin/`, the layout the
/// library's own run path expects): in the workspace this tracer was built
/// from, so an installed `tracer` finds it too.
pub fn project_folder() -> PathBuf {
    super::workspace().join("target/oidn")
}

/// OIDN's handles (opaque pointers).
pub(super) type Handle = *mut c_void;

/// The C functions of OIDN 2's API that the denoiser calls (names as in
/// `OpenImageDenoise/oidn.h`).
pub(super) struct Api {
    pub new_device: unsafe extern "C" fn(i32) -> Handle,
    pub set_device_int: unsafe extern "C" fn(Handle, *const c_char, i32),
    pub get_device_int: unsafe extern "C" fn(Handle, *const c_char) -> i32,
    pub commit_device: unsafe extern "C" fn(Handle),
    pub get_device_error: unsafe extern "C" fn(Handle, *mut *const c_char) -> i32,
    pub release_device: unsafe extern "C" fn(Handle),
    pub new_filter: unsafe extern "C" fn(Handle, *const c_char) -> Handle,
    #[allow(clippy::type_complexity)]
    pub set_shared_filter_image: unsafe extern "C" fn(
        Handle,
        *const c_char,
        *mut c_void,
        i32,
        usize,
        usize,
        usize,
        usize,
        usize,
    ),
    pub set_filter_bool: unsafe extern "C" fn(Handle, *const c_char, bool),
    pub set_filter_int: unsafe extern "C" fn(Handle, *const c_char, i32),
    pub get_filter_int: unsafe extern "C" fn(Handle, *const c_char) -> i32,
    pub commit_filter: unsafe extern "C" fn(Handle),
    pub execute_filter: unsafe extern "C" fn(Handle),
    pub release_filter: unsafe extern "C" fn(Handle),
    /// Where it was loaded from, for messages.
    pub path: PathBuf,
    /// Kept loaded for the process's life: the functions above point into it.
    _library: Library,
}

/// The API, loaded once per process (or why it cannot be).
pub(super) fn api() -> Result<&'static Api, DenoiseError> {
    static API: OnceLock<Result<Api, DenoiseError>> = OnceLock::new();
    API.get_or_init(|| load(&find()?))
        .as_ref()
        .map_err(Clone::clone)
}

/// Whether the library can be loaded: `--denoise` checks before rendering.
pub fn available() -> Result<(), DenoiseError> {
    api().map(|_| ())
}

/// The library's path: the project's folder first, then pyoidn's.
fn find() -> Result<PathBuf, DenoiseError> {
    let candidates = [Some(project_folder().join("lib")), pyoidn_lib_folder()];
    find_in(candidates.into_iter().flatten())
}

/// The library in the first of `folders` that has it, or the error that
/// names them and the command that installs it.
pub fn find_in(folders: impl IntoIterator<Item = PathBuf>) -> Result<PathBuf, DenoiseError> {
    let mut looked = Vec::new();
    for folder in folders {
        let path = folder.join(LIBRARY_FILE);
        if path.is_file() {
            return Ok(path);
        }
        looked.push(folder);
    }
    Err(DenoiseError::Missing { looked })
}

/// `pyoidn/oidn/lib` of the `pyoidn` package that `python3` would import,
/// found without importing it (its spec alone: no NumPy loaded).
fn pyoidn_lib_folder() -> Option<PathBuf> {
    let script = "import importlib.util as u; s = u.find_spec('pyoidn'); \
                  print(s.submodule_search_locations[0] if s else '')";
    let output = Command::new("python3").args(["-c", script]).output().ok()?;
    let folder = String::from_utf8(output.stdout).ok()?;
    let folder = folder.trim();
    (output.status.success() && !folder.is_empty()).then(|| Path::new(folder).join("oidn/lib"))
}

/// Loads the library at `path` and looks up every function.
fn load(path: &Path) -> Result<Api, DenoiseError> {
    let bad = |message: String| DenoiseError::Load {
        path: path.to_path_buf(),
        message,
    };
    // SAFETY: OIDN's initialisers only set up its own state; the library
    // stays loaded for the process's life (kept in `Api`).
    let library = unsafe { Library::new(path) }.map_err(|e| bad(e.to_string()))?;
    macro_rules! function {
        ($name:literal) => {
            // SAFETY: the type is the C declaration of `$name` in OIDN 2's
            // oidn.h; the pointer is used only while `library` is loaded.
            *unsafe { library.get(concat!($name, "\0").as_bytes()) }
                .map_err(|e| bad(format!("{}: {e}", $name)))?
        };
    }
    Ok(Api {
        new_device: function!("oidnNewDevice"),
        set_device_int: function!("oidnSetDeviceInt"),
        get_device_int: function!("oidnGetDeviceInt"),
        commit_device: function!("oidnCommitDevice"),
        get_device_error: function!("oidnGetDeviceError"),
        release_device: function!("oidnReleaseDevice"),
        new_filter: function!("oidnNewFilter"),
        set_shared_filter_image: function!("oidnSetSharedFilterImage"),
        set_filter_bool: function!("oidnSetFilterBool"),
        set_filter_int: function!("oidnSetFilterInt"),
        get_filter_int: function!("oidnGetFilterInt"),
        commit_filter: function!("oidnCommitFilter"),
        execute_filter: function!("oidnExecuteFilter"),
        release_filter: function!("oidnReleaseFilter"),
        path: path.to_path_buf(),
        _library: library,
    })
}

/// A NUL-terminated name for OIDN's parameters.
pub(super) fn c_name(name: &'static CStr) -> *const c_char {
    name.as_ptr()
}
