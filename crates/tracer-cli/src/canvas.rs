//! `tracer render` of a 2D canvas scene (a file with a `[canvas]` table).

use crate::output::write_png_atomically;
use crate::render::RenderArgs;
use crate::BadInput;
use anyhow::Result;
use scene_format::{CanvasFile, SceneKind};
use std::path::Path;

/// Draws the scene if it is a canvas scene and says whether it was; a 3D
/// scene is left to the caller.
pub fn render_if_canvas(args: &RenderArgs) -> Result<bool> {
    let Some(path) = args.scene.as_deref() else {
        return Ok(false);
    };
    match scene_format::load_any(path).map_err(|e| BadInput(e.to_string()))? {
        SceneKind::Scene3d(_) => Ok(false),
        SceneKind::Canvas(file) => draw(args, path, &file).map(|()| true),
    }
}

fn draw(args: &RenderArgs, path: &Path, file: &CanvasFile) -> Result<()> {
    if args.aov.is_some() {
        return Err(BadInput(format!(
            "{}: --aov needs a 3D scene; this is a 2D canvas scene",
            path.display()
        ))
        .into());
    }
    let mut encoding = tracer_core::canvas::encoding(file);
    if let Some(gamma) = args.gamma {
        encoding.gamma = crate::gamma::checked_gamma(gamma)?;
    }
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| crate::render::default_output(path));
    let image = tracer_core::canvas::draw(file);
    write_png_atomically(&image.encode(&encoding), &output)?;
    eprintln!(
        "drew {} ({}x{}) -> {}",
        path.display(),
        image.width,
        image.height,
        output.display()
    );
    Ok(())
}
