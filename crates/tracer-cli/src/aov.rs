//! `tracer render --aov NAME`: an image of one quantity per pixel (the lab's
//! ray-direction images, normals, depth) instead of the shaded colour.

use crate::render::RenderArgs;
use crate::BadInput;
use anyhow::Result;
use clap::ValueEnum;
use scene_format::SceneFile;
use std::path::{Path, PathBuf};
use tracer_cli::output::write_png_atomically;
use tracer_core::aov::{Aov, AOV_ENCODING};
use tracer_core::{Output, RenderJob};

/// The AOV names on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum AovArg {
    /// (dir.x + 1) / 2 of each primary ray in red (the lab's gradient-OX.png)
    RayDirX,
    /// (dir.y + 1) / 2 in green (gradient-OY.png)
    RayDirY,
    /// (dir.z + 1) / 2 in blue (gradient-OZ.png)
    RayDirZ,
    /// (n + 1) / 2 of the surface normal at the nearest hit
    Normal,
    /// Distance to the nearest hit: near bright, far dark, no hit black
    Depth,
}

impl From<AovArg> for Aov {
    fn from(a: AovArg) -> Aov {
        match a {
            AovArg::RayDirX => Aov::RayDirX,
            AovArg::RayDirY => Aov::RayDirY,
            AovArg::RayDirZ => Aov::RayDirZ,
            AovArg::Normal => Aov::Normal,
            AovArg::Depth => Aov::Depth,
        }
    }
}

/// Renders the AOV of a 3D scene; written linearly unless `--gamma` is given.
pub fn run(args: &RenderArgs, aov: AovArg, scene_name: &Path, file: &SceneFile) -> Result<()> {
    let aov = Aov::from(aov);
    let mut encoding = AOV_ENCODING;
    if let Some(gamma) = args.gamma {
        encoding.gamma = crate::gamma::checked_gamma(gamma)?;
    }
    let output = args.output.clone().unwrap_or_else(|| {
        let stem = crate::render::default_output(scene_name);
        let stem = stem.file_stem().unwrap_or_default().to_string_lossy();
        PathBuf::from(format!("{stem}-{}.png", aov.name()))
    });
    let scene = tracer_core::prepare(file)
        .map_err(|e| BadInput(format!("{}: {e}", scene_name.display())))?;
    let job = RenderJob::full(&scene).with_output(Output::Aov(aov));
    let image = tracer_core::render(&scene, &job, &|_| {}).image;
    write_png_atomically(&image.encode(&encoding), &output)?;
    eprintln!(
        "rendered {} of {} -> {}",
        aov.name(),
        scene_name.display(),
        output.display()
    );
    Ok(())
}
