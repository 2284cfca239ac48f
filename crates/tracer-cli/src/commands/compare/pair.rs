//! `tracer compare IMAGE REFERENCE`: one image against an image or a
//! scene's render, in words on stdout, and its heat-map with `-o`.

use super::comparison::Comparison;
use super::diagnose::pixels;
use super::input::{read_image, read_reference, Reference};
use super::metrics::{Difference, Pixel};
use crate::console::{self, note};
use anyhow::Result;
use std::fmt::Write as _;
use std::path::Path;
use tracer_pipeline::output::{check_not_an_input, PendingOutput};
use tracer_pipeline::Error;

/// Compares and reports; true when the image is within tolerance.
pub fn run(
    image: &Path,
    reference: &Path,
    heat_map: Option<&Path>,
    tolerance: u8,
    samples: Option<u32>,
) -> Result<bool> {
    // The heat-map's path is checked (and its file made) before the work.
    let pending = match heat_map {
        Some(path) => {
            check_not_an_input(path, &[image, reference]).map_err(Error::from)?;
            Some(PendingOutput::create_8bit(path).map_err(Error::from)?)
        }
        None => None,
    };
    let picture = read_image(image)?;
    let reference_read = read_reference(reference, Some(picture.dimensions()), samples)?;
    if let Some(pending) = &pending {
        check_not_an_input(pending.path(), &reference_read.files_read).map_err(Error::from)?;
    }
    let comparison = Comparison::new(&picture, &reference_read, tolerance);
    match (pending, comparison.heat_map()) {
        (Some(pending), Some(map)) => {
            let path = pending.path().to_path_buf();
            pending.write_image(map).map_err(Error::from)?;
            note!("heat-map -> {}", path.display());
        }
        (Some(_), None) if matches!(comparison, Comparison::Sizes { .. }) => {
            note!("no heat-map: the sizes differ")
        }
        (Some(_), None) => note!("no heat-map: it is FLIP's, not computed for images this large"),
        (None, Some(_)) if !comparison.within_tolerance() => {
            note!("(-o heatmap.png draws where they differ)");
        }
        (None, _) => {}
    }
    if let Some(paths) = reference_read.path_samples {
        // Of images of one size only: another size is the mistake to fix.
        if !comparison.within_tolerance() && comparison.heat_map().is_some() {
            note!(
                "the reference is path traced ({paths} paths a pixel): another render's \
                 noise differs from its noise pixel by pixel. Judge by PSNR and FLIP, or \
                 render both with more paths (tracer render --samples N, then \
                 tracer compare --samples N)"
            );
        }
    }
    let names = Names {
        image,
        reference,
        reference_read: &reference_read,
        image_size: picture.dimensions(),
    };
    // File names in it have their control characters made visible.
    let text = text(&names, &comparison, tolerance);
    console::stdout(&scene_format::visible::escape_controls_in_lines(&text))?;
    Ok(comparison.within_tolerance())
}

/// What the report names.
struct Names<'a> {
    image: &'a Path,
    reference: &'a Path,
    reference_read: &'a Reference,
    image_size: (u32, u32),
}

/// The report on stdout.
fn text(names: &Names, comparison: &Comparison, tolerance: u8) -> String {
    let (w, h) = names.image_size;
    let (rw, rh) = names.reference_read.size;
    let read = names.reference_read;
    let rendered = match (&read.scene, read.image.dimensions() == read.size) {
        (Some(_), true) => "rendered, ",
        (Some(_), false) => "a scene not rendered, its camera's ",
        (None, _) => "",
    };
    let mut out = format!(
        "image      {} ({w}x{h})\nreference  {} ({rendered}{rw}x{rh})\n",
        names.image.display(),
        names.reference.display()
    );
    if let Comparison::Compared {
        difference, flip, ..
    } = comparison
    {
        out += &numbers(difference, flip.as_ref().map(|f| f.mean), tolerance);
    }
    for line in comparison.diagnoses() {
        let _ = writeln!(out, "{line}");
    }
    if let Comparison::Compared { difference, .. } = comparison {
        out += &first_pixels(difference, names.reference_read.scene.as_deref());
    }
    out += &verdict(comparison, tolerance);
    out
}

fn numbers(d: &Difference, flip: Option<f32>, tolerance: u8) -> String {
    let largest = match d.largest {
        Some(p) => format!(
            "{} of 255 at ({}, {}): image {}, reference {}",
            p.difference(),
            p.x,
            p.y,
            rgb(p.image),
            rgb(p.reference)
        ),
        None => "0 (identical)".to_string(),
    };
    let psnr = d
        .psnr()
        .map_or("infinite (identical)".to_string(), |p| format!("{p:.2} dB"));
    let flip = match flip {
        Some(flip) => format!("{flip:.4} (mean: 0 identical, 1 the most different)"),
        None => format!(
            "not computed: the images are over {} pixels (4096 x 4096)",
            super::flip::MAX_PIXELS
        ),
    };
    format!(
        "off        {} of the pixels ({} of {}) by more than {tolerance} of 255 in a channel\n\
         largest    {largest}\n\
         PSNR       {psnr}\n\
         FLIP       {flip}\n",
        percent(d.share()),
        d.differing,
        d.pixels,
    )
}

/// A share as a percentage, never rounded to 0 when some pixels are off.
pub fn percent(share: f64) -> String {
    let p = share * 100.0;
    if p > 0.0 && p < 0.001 {
        format!("{p:.1e} %")
    } else {
        format!("{p:.3} %")
    }
}

pub fn rgb([r, g, b]: [u8; 3]) -> String {
    format!("({r}, {g}, {b})")
}

/// The first differing pixels, each with the command that explains it
/// when the reference is a scene.
fn first_pixels(d: &Difference, scene: Option<&Path>) -> String {
    if d.first.is_empty() {
        return String::new();
    }
    let mut out = String::from(
        "first differing pixels (x from the left, y from the top, (0, 0) the top-left):\n",
    );
    for p in &d.first {
        let _ = write!(
            out,
            "  ({}, {})  image {}, reference {}",
            p.x,
            p.y,
            rgb(p.image),
            rgb(p.reference)
        );
        if let Some(scene) = scene {
            let _ = write!(out, "  {}", explain_command(scene, p));
        }
        out.push('\n');
    }
    out
}

/// `tracer explain SCENE X Y`, the scene quoted for a shell when needed.
pub fn explain_command(scene: &Path, p: &Pixel) -> String {
    format!("tracer explain {} {} {}", shell_word(scene), p.x, p.y)
}

fn shell_word(path: &Path) -> String {
    let text = path.display().to_string();
    let plain = |c: char| c.is_ascii_alphanumeric() || "-_./+,:@%".contains(c);
    if !text.is_empty() && text.chars().all(plain) {
        text
    } else {
        format!("'{}'", text.replace('\'', r"'\''"))
    }
}

fn verdict(comparison: &Comparison, tolerance: u8) -> String {
    match comparison {
        Comparison::Sizes { .. } => "not within tolerance: the sizes differ\n".to_string(),
        Comparison::Compared { difference, .. } if difference.differing == 0 => {
            format!("within tolerance: no pixel is off by more than {tolerance} of 255\n")
        }
        Comparison::Compared { difference, .. } => format!(
            "not within tolerance: {} off by more than {tolerance} of 255\n",
            pixels(difference.differing)
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scene_path_is_quoted_for_the_shell_only_when_needed() {
        let p = Pixel {
            x: 3,
            y: 4,
            image: [0; 3],
            reference: [0; 3],
        };
        assert_eq!(
            explain_command(Path::new("scenes/a-b.toml"), &p),
            "tracer explain scenes/a-b.toml 3 4"
        );
        assert_eq!(
            explain_command(Path::new("my scenes/it's.toml"), &p),
            r"tracer explain 'my scenes/it'\''s.toml' 3 4"
        );
    }

    #[test]
    fn a_tiny_share_is_not_shown_as_zero() {
        assert_eq!(percent(0.0), "0.000 %");
        assert_eq!(percent(0.5), "50.000 %");
        assert_eq!(percent(1.0 / 200_000.0), "5.0e-4 %");
    }
}
