//! `tracer render` of a 2D canvas scene (a file with a `[canvas]` table).

use crate::render::RenderArgs;
use crate::BadInput;
use anyhow::Result;
use scene_format::CanvasFile;
use std::path::Path;
use tracer_cli::output::write_png_atomically;

/// Draws a canvas scene read from `path`.
pub fn draw(args: &RenderArgs, path: &Path, file: &CanvasFile) -> Result<()> {
    if args.aov.is_some() {
        return Err(BadInput(format!(
            "{}: --aov needs a 3D scene; this is a 2D canvas scene",
            path.display()
        ))
        .into());
    }
    let mut encoding = lab_tools::canvas::encoding(file);
    if let Some(gamma) = args.gamma {
        encoding.gamma = crate::gamma::checked_gamma(gamma)?;
    }
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| crate::render::default_output(path));
    let image = lab_tools::canvas::draw(file);
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
