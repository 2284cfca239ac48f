//! The book's denoising figures (`cargo xtask denoise-figures`, and
//! `cargo xtask bench --only denoise` from its own renders): a scene at 16
//! paths a pixel noisy, the same render denoised, and Mitsuba's reference,
//! side by side in one PNG with each panel's RMSE against the reference
//! written under it. Every panel is encoded as `tracer render` writes a
//! PNG (the scene's gamma and saturation rule, `Picture::to_rgb8`), the
//! reference included, so the three differ only in their values.

use super::path_peers::{self, BenchScene};
use anyhow::{anyhow, Context, Result};
use image::RgbImage;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use std::path::{Path, PathBuf};
use tracer_pipeline::{Input, LinearImage, Options, Picture, Rendered};

/// The paths a pixel of the figures' renders.
pub const SPP: u32 = 16;

/// The scenes with a figure, as the path bench has them.
pub const SCENES: [BenchScene; 2] = [path_peers::CORNELL_BOX, path_peers::MATERIALS];

/// The space round and between the panels, and the strip of labels below.
pub const GAP: u32 = 12;
pub const LABEL_HEIGHT: u32 = 46;
/// A panel narrower than this is enlarged by a whole factor (pixels kept
/// square and sharp, so the noise shows as it is).
const LEAST_WIDTH: u32 = 480;
const FONT: &str = "sans-serif";
const FONT_SIZE: f64 = 15.0;
const BACKGROUND: [u8; 3] = [255, 255, 255];
const TEXT: RGBColor = RGBColor(40, 40, 40);

/// One panel: its picture (already encoded for display) and two lines
/// of label.
pub struct Panel {
    pub image: RgbImage,
    pub title: String,
    pub note: String,
}

/// How many times a panel `width` pixels wide is enlarged.
pub fn enlargement(width: u32) -> u32 {
    LEAST_WIDTH.div_ceil(width.max(1)).max(1)
}

/// The figure's size for three panels of `(width, height)`.
pub fn figure_size((width, height): (u32, u32)) -> (u32, u32) {
    (3 * width + 4 * GAP, height + GAP + LABEL_HEIGHT)
}

/// The top-left corner of panel `i` (0, 1, 2) of a figure whose panels are
/// `width` wide.
pub fn panel_origin(i: u32, width: u32) -> (u32, u32) {
    (GAP + i * (width + GAP), GAP)
}

/// Where a scene's figure goes: `docs/src/images/denoise-<scene>.png`.
pub fn path(root: &Path, bench: &BenchScene) -> PathBuf {
    let stem = Path::new(bench.scene)
        .file_stem()
        .map_or_else(|| bench.scene.into(), |s| s.to_string_lossy());
    root.join("docs/src/images")
        .join(format!("denoise-{stem}.png"))
}

/// Renders both scenes at [`SPP`] paths a pixel, denoised, and writes
/// their figures.
pub fn write_all(root: &Path) -> Result<Vec<PathBuf>> {
    if let Err(e) = tracer_pipeline::denoise::available() {
        anyhow::bail!("{e}");
    }
    let mut written = Vec::new();
    for bench in SCENES {
        eprintln!("denoise figure: {} at {SPP} paths a pixel ...", bench.scene);
        let reference =
            super::denoise::to_linear(&path_peers::read_image(&root.join(bench.reference))?);
        let loaded = tracer_pipeline::load(&Input::File(root.join(bench.scene)))?;
        let options = Options {
            samples: Some(SPP),
            denoise: true,
            ..Options::default()
        };
        let rendered = tracer_pipeline::render(&loaded, &options, &|_| {})?;
        written.push(write(root, &bench, &rendered, &reference)?);
    }
    Ok(written)
}

/// Writes the figure of `rendered` (a denoised render at [`SPP`] paths a
/// pixel of `bench`'s scene) against `reference`.
pub fn write(
    root: &Path,
    bench: &BenchScene,
    rendered: &Rendered,
    reference: &LinearImage,
) -> Result<PathBuf> {
    let figure = figure(rendered, reference)?;
    let path = path(root, bench);
    tracer_pipeline::output::write_image(&figure, &path)
        .with_context(|| format!("cannot write {}", path.display()))?;
    eprintln!("denoise figure: wrote {}", path.display());
    Ok(path)
}

/// The figure of a denoised render against its reference.
pub fn figure(rendered: &Rendered, reference: &LinearImage) -> Result<RgbImage> {
    let denoising = rendered
        .denoising
        .as_ref()
        .context("the render was not denoised")?;
    let noisy = denoising
        .noisy
        .as_ref()
        .context("a whole image is denoised")?;
    let denoised = &rendered.image.linear;
    let encoding = rendered.image.encoding;
    let k = enlargement(denoised.width);
    let size = (denoised.width * k, denoised.height * k);
    let panel = |linear: &LinearImage| {
        Picture {
            linear: linear.clone(),
            encoding,
        }
        .enlarged(size)
        .to_rgb8()
    };
    let error = |linear: &LinearImage| {
        format!(
            "RMSE {:.4} (below 1: {:.4})",
            tracer_pipeline::reference::rmse(linear, reference),
            super::denoise::dim(linear, reference)
        )
    };
    compose(&[
        Panel {
            image: panel(noisy),
            title: format!("noisy, {SPP} paths a pixel"),
            note: error(noisy),
        },
        Panel {
            image: panel(denoised),
            title: format!("denoised (OIDN), {SPP} paths a pixel"),
            note: error(denoised),
        },
        Panel {
            image: panel(reference),
            title: "reference (Mitsuba 3)".into(),
            note: "what the RMSEs are measured against".into(),
        },
    ])
}

/// Three panels of one size side by side, each with its label centred
/// below it.
pub fn compose(panels: &[Panel; 3]) -> Result<RgbImage> {
    let (w, h) = panels[0].image.dimensions();
    if panels.iter().any(|p| p.image.dimensions() != (w, h)) {
        anyhow::bail!("the panels differ in size");
    }
    let (width, height) = figure_size((w, h));
    let mut out = RgbImage::from_pixel(width, height, image::Rgb(BACKGROUND));
    for (i, panel) in (0..).zip(panels) {
        let (x, y) = panel_origin(i, w);
        image::imageops::replace(&mut out, &panel.image, i64::from(x), i64::from(y));
    }
    register_embedded_font();
    {
        let root = BitMapBackend::with_buffer(out.as_mut(), (width, height)).into_drawing_area();
        let fail = |e| anyhow!("cannot write the labels: {e}");
        let face: FontDesc = (FONT, FONT_SIZE).into_font();
        let font = face.color(&TEXT);
        let line = (FONT_SIZE * 1.3) as i32;
        for (i, panel) in (0..).zip(panels) {
            let (x, _) = panel_origin(i, w);
            let top = (GAP + h) as i32 + line / 3;
            for (row, text) in [&panel.title, &panel.note].into_iter().enumerate() {
                let (tw, _) = face.box_size(text).map_err(|e| anyhow!("{e}"))?;
                let left = x as i32 + (w as i32 - tw as i32) / 2;
                let at = (left.max(x as i32), top + row as i32 * line);
                root.draw(&Text::new(text.clone(), at, font.clone()))
                    .map_err(fail)?;
            }
        }
        root.present().map_err(fail)?;
    }
    Ok(out)
}

fn register_embedded_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // Compiled in: it fails only if the bytes were bad.
        let _ = register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
    });
}
