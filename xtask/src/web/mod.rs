//! `cargo xtask web`: the playground, one folder of static files: the page
//! (web/), its scripts bundled by esbuild (npm packages pinned by
//! web/package-lock.json), crates/web built for wasm32, and every scene of
//! scenes/ with the files it reads, listed in `scenes/index.json`; and the
//! book (`cargo xtask book`) as `book/`, when it has been built, which the
//! page's help link opens.

pub mod serve;
pub mod toolchain;

use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The lab's tables in the lab's order: the menu lists them first.
pub const LAB_SCENES: [&str; 12] = [
    "sphere-intersection.toml",
    "triangle-intersection.toml",
    "illumination-ambient.toml",
    "illumination-diffuse.toml",
    "illumination-specular.toml",
    "illumination.toml",
    "illumination-shininess-10.toml",
    "illumination-shininess-50.toml",
    "texture.toml",
    "shadows.toml",
    "reflectance.toml",
    "reflectance2.toml",
];

/// Builds the page into `out` (emptied first); the files it wrote.
pub fn build(root: &Path, out: &Path) -> Result<()> {
    let toolchain = toolchain::find()?;
    let wasm = toolchain::build(root, &crate::target_dir().join("wasm"), &toolchain)?;
    if out.exists() {
        std::fs::remove_dir_all(out).with_context(|| format!("cannot empty {}", out.display()))?;
    }
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    copy(&wasm, &out.join("tracer_web.wasm"))?;
    bundle(&root.join("web"), out)?;
    for page_file in ["index.html", "style.css"] {
        copy(&root.join("web").join(page_file), &out.join(page_file))?;
    }
    write_scenes(&root.join("scenes"), &out.join("scenes"))?;
    // The book beside the page, for its help link, when it has been built.
    let book = crate::book::default_out();
    if book.join("index.html").is_file() {
        crate::book::build::copy_tree(&book, &out.join("book"))?;
    }
    Ok(())
}

fn copy(from: &Path, to: &Path) -> Result<()> {
    if let Some(parent) = to.parent() {
        std::fs::create_dir_all(parent)?;
    }
    std::fs::copy(from, to)
        .with_context(|| format!("cannot copy {} to {}", from.display(), to.display()))?;
    Ok(())
}

/// The page's scripts bundled into `out` (`npm ci` first when the packages
/// installed are not those of the lock file: none yet, or a checkout that
/// changed it since).
fn bundle(web: &Path, out: &Path) -> Result<()> {
    if !packages_installed(web) {
        run(Command::new("npm")
            .args(["ci", "--no-audit", "--no-fund"])
            .current_dir(web))
        .context("npm ci in web/ (Node.js and npm are needed: Debian's nodejs and npm)")?;
    }
    let esbuild = web.join("node_modules/.bin/esbuild");
    run(Command::new(esbuild)
        .current_dir(web)
        .args([
            "src/main.js",
            "src/worker.js",
            "--bundle",
            "--minify",
            "--format=esm",
            "--log-level=warning",
        ])
        .arg(format!("--outdir={}", out.display())))
    .context("esbuild")
}

/// Whether `web/node_modules` holds the versions `web/package-lock.json`
/// names: npm keeps what it installed in `node_modules/.package-lock.json`.
fn packages_installed(web: &Path) -> bool {
    let versions = |path: &Path| -> Option<Vec<(String, String)>> {
        let text = std::fs::read_to_string(path).ok()?;
        let json: serde_json::Value = serde_json::from_str(&text).ok()?;
        let mut list: Vec<(String, String)> = json
            .get("packages")?
            .as_object()?
            .iter()
            // "" is the page's own package, which is not installed; an
            // optional one (esbuild's binary for another platform) may not be.
            .filter(|(name, p)| !name.is_empty() && p["optional"] != true)
            .map(|(name, p)| (name.clone(), p["version"].to_string()))
            .collect();
        list.sort();
        Some(list)
    };
    let wanted = versions(&web.join("package-lock.json"));
    let installed = versions(&web.join("node_modules/.package-lock.json"));
    wanted.is_some() && wanted == installed
}

fn run(command: &mut Command) -> Result<()> {
    let status = command
        .status()
        .with_context(|| format!("cannot run {:?}", command.get_program()))?;
    if !status.success() {
        bail!("{:?} failed ({status})", command.get_program());
    }
    Ok(())
}

/// One scene of the menu.
#[derive(Debug, serde::Serialize)]
pub struct SceneEntry {
    /// Its path under scenes/, `/`-separated.
    pub path: String,
    /// Whether it is one of the lab's tables.
    pub lab: bool,
    /// Whether it is path traced (`integrator = "path"`).
    pub path_traced: bool,
    /// The files it reads besides itself, paths under scenes/.
    pub files: Vec<String>,
}

/// Every scene of `scenes` (its folders too), lab tables first in the lab's
/// order, then the others by name, each with the files it reads (read as
/// `tracer render` reads them).
pub fn scene_entries(scenes: &Path) -> Result<Vec<SceneEntry>> {
    let mut entries = Vec::new();
    for (_, path) in crate::golden::scene_files(scenes)? {
        let loaded = tracer_pipeline::load(&tracer_pipeline::Input::File(path.clone()))
            .with_context(|| format!("{}: does not load", path.display()))?;
        let relative = |p: &Path| -> Result<String> {
            let rel = p.strip_prefix(scenes).with_context(|| {
                format!("{} reads {}, outside scenes/", path.display(), p.display())
            })?;
            // `a/../meshes/x.obj` is `meshes/x.obj` in the page's folder too.
            let rel = scene_format::source::normalize(rel).with_context(|| {
                format!("{} reads {}, outside scenes/", path.display(), p.display())
            })?;
            Ok(rel
                .iter()
                .map(|s| s.to_string_lossy())
                .collect::<Vec<_>>()
                .join("/"))
        };
        let files = loaded
            .files_read
            .iter()
            .filter(|f| **f != path)
            .map(|f| relative(f))
            .collect::<Result<_>>()?;
        let path = relative(&path)?;
        let path_traced = loaded.is_path_traced(&tracer_pipeline::Options::default());
        entries.push(SceneEntry {
            lab: LAB_SCENES.contains(&path.as_str()),
            path_traced,
            path,
            files,
        });
    }
    let rank = |e: &SceneEntry| {
        LAB_SCENES
            .iter()
            .position(|l| *l == e.path)
            .unwrap_or(usize::MAX)
    };
    entries.sort_by(|a, b| rank(a).cmp(&rank(b)).then_with(|| a.path.cmp(&b.path)));
    Ok(entries)
}

fn write_scenes(scenes: &Path, out: &Path) -> Result<()> {
    let entries = scene_entries(scenes)?;
    for entry in &entries {
        for file in std::iter::once(&entry.path).chain(&entry.files) {
            let to = out.join(file);
            if !to.exists() {
                copy(&scenes.join(file), &to)?;
            }
        }
    }
    let json = serde_json::to_string_pretty(&entries)?;
    std::fs::write(out.join("index.json"), json).context("cannot write scenes/index.json")?;
    Ok(())
}

/// The default folder of the page: `target/web`.
pub fn default_out() -> PathBuf {
    crate::target_dir().join("web")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packages_are_installed_again_when_the_lock_file_names_others() {
        let web = tempfile::tempdir().unwrap();
        std::fs::create_dir(web.path().join("node_modules")).unwrap();
        let lock = r#"{"packages": {"": {"name": "page"},
            "node_modules/three": {"version": "0.171.0"},
            "node_modules/@esbuild/darwin-arm64": {"version": "0.24.0", "optional": true}}}"#;
        std::fs::write(web.path().join("package-lock.json"), lock).unwrap();
        let installed = |packages: &str| {
            let hidden = format!(r#"{{"packages": {{{packages}}}}}"#);
            std::fs::write(web.path().join("node_modules/.package-lock.json"), hidden).unwrap();
            packages_installed(web.path())
        };
        assert!(!packages_installed(web.path()), "nothing installed yet");
        assert!(installed(r#""node_modules/three": {"version": "0.171.0"}"#));
        assert!(!installed(
            r#""node_modules/three": {"version": "0.170.0"}"#
        ));
        assert!(!installed(""));
        let more = r#""node_modules/three": {"version": "0.171.0"},
            "node_modules/gone": {"version": "1.0.0"}"#;
        assert!(!installed(more));
    }

    #[test]
    fn the_menu_lists_the_lab_first_then_every_scene_with_its_files() {
        let scenes = crate::workspace_root().join("scenes");
        let entries = scene_entries(&scenes).unwrap();
        let paths: Vec<&str> = entries.iter().map(|e| e.path.as_str()).collect();
        assert_eq!(paths[..12], LAB_SCENES);
        assert!(entries[..12].iter().all(|e| e.lab));
        assert!(entries[12..].iter().all(|e| !e.lab));
        let rest = &paths[12..];
        assert!(rest.windows(2).all(|w| w[0] < w[1]), "{rest:?}");
        assert_eq!(
            paths.len(),
            crate::golden::scene_files(&scenes).unwrap().len()
        );
        let files = |path: &str| &entries.iter().find(|e| e.path == path).unwrap().files;
        assert_eq!(files("bench/bunny.toml"), &["bench/bunny.obj"]);
        assert!(files("textures.toml").contains(&"meshes/labelled-box.mtl".to_string()));
        assert!(files("reflectance2.toml").is_empty());
        let path_traced = |path: &str| entries.iter().find(|e| e.path == path).unwrap().path_traced;
        assert!(path_traced("cornell-box.toml"));
        assert!(!path_traced("reflectance2.toml"));
    }
}
