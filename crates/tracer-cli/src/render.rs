//! `tracer render`: scene file in, PNG out.

use crate::output::write_png_atomically;
use crate::BadInput;
use anyhow::Result;
use clap::Args;
use scene_format::{Format, SceneFile};
use std::path::{Path, PathBuf};
use std::time::Instant;
use tracer_core::Scene;

/// The scene rendered when none is given: the lab's final scene (table 1.10).
const DEFAULT_SCENE: &str = include_str!("../../../scenes/reflectance2.toml");
const DEFAULT_SCENE_NAME: &str = "reflectance2.toml";

/// Render a scene file to a PNG image.
#[derive(Args)]
pub struct RenderArgs {
    /// Scene file (.toml or .json). Without one, the lab's final scene
    /// (table 1.10, reflectance2) is rendered.
    pub scene: Option<PathBuf>,
    /// Output PNG [default: the scene's file name with .png, in the current folder]
    #[arg(short, long, value_name = "OUT.png")]
    pub output: Option<PathBuf>,
    /// Display gamma for encoding, overriding the scene's `[render] gamma`
    /// (1 writes linear values)
    #[arg(long, value_name = "G")]
    pub gamma: Option<f32>,
}

pub fn run(args: &RenderArgs) -> Result<()> {
    let (scene_name, mut file) = load(args.scene.as_deref())?;
    if let Some(gamma) = args.gamma {
        if !(gamma.is_finite() && gamma > 0.0) {
            return Err(BadInput(format!("--gamma: expected a number > 0, found {gamma}")).into());
        }
        file.render.gamma = gamma;
    }
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| default_output(&scene_name));
    let scene =
        Scene::prepare(&file).map_err(|e| BadInput(format!("{}: {e}", scene_name.display())))?;
    let start = Instant::now();
    let image = tracer_core::render(&scene);
    let elapsed = start.elapsed();
    write_png_atomically(&image.encode(&scene.encoding), &output)?;
    eprintln!(
        "rendered {} ({}x{}) in {:.3} s -> {}",
        scene_name.display(),
        scene.camera.width,
        scene.camera.height,
        elapsed.as_secs_f64(),
        output.display()
    );
    Ok(())
}

/// The scene's name (for messages and the default output) and its contents.
fn load(path: Option<&Path>) -> Result<(PathBuf, SceneFile)> {
    let name = path.map_or_else(|| PathBuf::from(DEFAULT_SCENE_NAME), Path::to_path_buf);
    let scene = match path {
        Some(path) => scene_format::load_path(path),
        None => scene_format::load_str(DEFAULT_SCENE, Format::Toml, &name),
    }?;
    Ok((name, scene))
}

fn default_output(scene: &Path) -> PathBuf {
    let stem = scene.file_stem().unwrap_or(scene.as_os_str());
    PathBuf::from(stem).with_extension("png")
}
