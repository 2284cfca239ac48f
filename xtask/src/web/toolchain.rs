//! Building crates/web for `wasm32-unknown-unknown` with whichever toolchain
//! the machine has: rustup's with the target installed, else Debian's
//! `rustc-web`/`cargo-web`/`rust-web-src`, which build the standard library
//! for the target themselves (`-Zbuild-std`) and link with an `rust-lld`.

use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::process::Command;

pub const TARGET: &str = "wasm32-unknown-unknown";

/// How the wasm is built here.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Toolchain {
    /// rustup's toolchain, its wasm32 target installed.
    Rustup,
    /// Debian's cargo and rustc (1.96) with the standard library's source,
    /// linked by `linker`.
    Debian { linker: PathBuf },
}

/// Debian's binaries and the standard library's source they build.
const DEBIAN_CARGO: &str = "/usr/bin/cargo";
const DEBIAN_RUSTC: &str = "/usr/bin/rustc";
const DEBIAN_STD_SOURCE: &str = "/usr/lib/rustlib/src/rust/library/std";

/// The toolchain to use, or an error that says what to install.
pub fn find() -> Result<Toolchain> {
    if rustup_has_target() {
        return Ok(Toolchain::Rustup);
    }
    let mut missing = Vec::new();
    for (path, package) in [
        (DEBIAN_CARGO, "cargo-web"),
        (DEBIAN_RUSTC, "rustc-web"),
        (DEBIAN_STD_SOURCE, "rust-web-src"),
    ] {
        if !Path::new(path).exists() {
            missing.push(package);
        }
    }
    let linker = rust_lld();
    if missing.is_empty() {
        if let Some(linker) = linker {
            return Ok(Toolchain::Debian { linker });
        }
    }
    if linker.is_none() {
        missing.push("rust-lld (rustup's toolchain has one; Debian: rust-web-llvm)");
    }
    bail!(
        "cannot build for {TARGET}: either `rustup target add {TARGET}`, or install \
         Debian's {} (apt-get install rustc-web cargo-web rust-web-src; .ci/run does)",
        missing.join(", ")
    )
}

fn rustup_has_target() -> bool {
    Command::new("rustup")
        .args(["target", "list", "--installed"])
        .output()
        .is_ok_and(|o| {
            o.status.success()
                && String::from_utf8_lossy(&o.stdout)
                    .lines()
                    .any(|l| l == TARGET)
        })
}

/// The `rust-lld` of rustup's toolchain, else Debian's.
fn rust_lld() -> Option<PathBuf> {
    let sysroot = Command::new("rustc")
        .env_remove("RUSTC")
        .args(["--print", "sysroot"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| PathBuf::from(String::from_utf8_lossy(&o.stdout).trim()));
    let rustup = sysroot.map(|s| s.join("lib/rustlib/x86_64-unknown-linux-gnu/bin/rust-lld"));
    rustup
        .into_iter()
        .chain([PathBuf::from("/usr/bin/rust-lld")])
        .find(|p| p.is_file())
}

/// Builds crates/web's `.wasm` (release) into `target_dir`; its path.
pub fn build(root: &Path, target_dir: &Path, toolchain: &Toolchain) -> Result<PathBuf> {
    let mut command = match toolchain {
        Toolchain::Rustup => Command::new("cargo"),
        Toolchain::Debian { .. } => Command::new(DEBIAN_CARGO),
    };
    // What the `cargo` running xtask (or a test) set is for its own build.
    for var in [
        "RUSTC",
        "RUSTDOC",
        "RUSTC_WRAPPER",
        "RUSTFLAGS",
        "CARGO_ENCODED_RUSTFLAGS",
        "CARGO_BUILD_TARGET",
        "CARGO_TARGET_DIR",
        "CARGO_MAKEFLAGS",
    ] {
        command.env_remove(var);
    }
    command.current_dir(root).args([
        "build",
        "--release",
        "--locked",
        "-p",
        "tracer-web",
        "--target",
        TARGET,
    ]);
    command.arg("--target-dir").arg(target_dir);
    // 128-bit SIMD (every current browser has it): glam's vectors use it as
    // they use SSE2 natively.
    command.env("RUSTFLAGS", "-C target-feature=+simd128");
    if let Toolchain::Debian { linker } = toolchain {
        command
            .env_remove("RUSTUP_TOOLCHAIN")
            .env("RUSTC", DEBIAN_RUSTC)
            // build-std is unstable: Debian's stable rustc allows it so.
            .env("RUSTC_BOOTSTRAP", "1")
            .env("CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_LINKER", linker)
            .args(["-Zbuild-std=std,panic_abort"]);
    }
    let status = command
        .status()
        .with_context(|| format!("cannot run cargo for {TARGET} ({toolchain:?})"))?;
    if !status.success() {
        bail!("the {TARGET} build of crates/web failed ({status}; {toolchain:?})");
    }
    Ok(target_dir.join(TARGET).join("release/tracer_web.wasm"))
}
