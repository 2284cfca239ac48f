//! The arguments of `tracer compare`.

use clap::Args;
use std::path::PathBuf;

/// Compare an image with what it should be: another image, or a scene
/// rendered as `tracer render` renders it
///
/// Prints the share of pixels off by more than the tolerance, the largest
/// difference and where, PSNR and FLIP (the perceptual difference of
/// Andersson et al. 2020), the first pixels that differ, and in words the
/// usual mistakes that explain a difference: a different size, a mirror
/// image, gamma applied twice, not at all or another one, a shift of half a pixel or of
/// one, swapped channels, or two of these at once. Exit status: 0 within
/// tolerance, 1 not, 2 bad input or an output that cannot be written.
///
/// With --report, every image in a folder named after a scene (a class's
/// submissions) against that scene: a web page and a CSV, worst first.
#[derive(Args)]
pub struct CompareArgs {
    /// The image to check (.png or .jpg, 8 or 16 bits)
    #[arg(
        value_name = "IMAGE",
        required_unless_present = "report",
        conflicts_with = "report"
    )]
    pub image: Option<PathBuf>,
    /// What it should be: an image, or a scene file (.toml, .json, or a .zip
    /// made by `tracer pack`), rendered first
    #[arg(value_name = "REFERENCE", required_unless_present = "report")]
    pub reference: Option<PathBuf>,
    /// Write the heat-map of the difference (FLIP's error in its magma
    /// colours: black none, yellow the most) to this .png or .jpg; with
    /// --report, the folder to write the report to [default: no heat-map;
    /// with --report, `report`]
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// A pixel is off when a channel differs by more than N of 255 (as the
    /// golden check counts)
    #[arg(long, value_name = "N", default_value_t = 2)]
    pub tolerance: u8,
    /// Compare every image in DIR (and its folders) named after a scene
    /// with that scene's render: `illumination.png`, `alice/illumination.png`
    /// or `illumination-alice.png` against `illumination.toml`; writes
    /// `index.html` and `report.csv`
    #[arg(long, value_name = "DIR")]
    pub report: Option<PathBuf>,
    /// Paths a pixel of a path-traced scene rendered as the reference, as
    /// `tracer render --samples N` gives them [default: the scene's
    /// `samples`]
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub samples: Option<u32>,
    /// The scenes the images of --report are named after [default: scenes]
    #[arg(long, value_name = "DIR", requires = "report")]
    pub scenes: Option<PathBuf>,
}
