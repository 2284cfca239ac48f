//! One image against its reference: the numbers, FLIP and its heat-map,
//! and the mistakes found; or, for images of different sizes, just that.

use super::diagnose::{self, Finding};
use super::flip::{self, Flip};
use super::input::Reference;
use super::metrics::{self, Difference};
use image::RgbImage;

/// What comparing an image with its reference found.
pub enum Comparison {
    /// Different sizes: nothing to compare pixel by pixel.
    Sizes {
        image: (u32, u32),
        reference: (u32, u32),
    },
    Compared {
        difference: Difference,
        /// None above [`flip::MAX_PIXELS`].
        flip: Option<Flip>,
        findings: Vec<Finding>,
    },
}

impl Comparison {
    /// `image` against `reference`; a pixel is off beyond `tolerance`
    /// levels.
    pub fn new(image: &RgbImage, reference_read: &Reference, tolerance: u8) -> Comparison {
        let reference = &reference_read.image;
        if image.dimensions() != reference_read.size {
            return Comparison::Sizes {
                image: image.dimensions(),
                reference: reference_read.size,
            };
        }
        let difference = metrics::difference(image, reference, tolerance);
        let findings = diagnose::diagnose(image, reference_read, tolerance, difference.differing);
        Comparison::Compared {
            flip: flip::fits(image).then(|| flip::flip(image, reference)),
            difference,
            findings,
        }
    }

    /// Whether no pixel is off by more than the tolerance.
    pub fn within_tolerance(&self) -> bool {
        matches!(self, Comparison::Compared { difference, .. } if difference.differing == 0)
    }

    /// The share of pixels off, 0 to 1; every pixel when the sizes differ.
    pub fn share(&self) -> f64 {
        match self {
            Comparison::Sizes { .. } => 1.0,
            Comparison::Compared { difference, .. } => difference.share(),
        }
    }

    /// FLIP's mean; `None` when the sizes differ or the images are too
    /// large for FLIP.
    pub fn flip_mean(&self) -> Option<f32> {
        match self {
            Comparison::Sizes { .. } => None,
            Comparison::Compared { flip, .. } => flip.as_ref().map(|f| f.mean),
        }
    }

    /// The heat-map; `None` when the sizes differ or the images are too
    /// large for FLIP.
    pub fn heat_map(&self) -> Option<&RgbImage> {
        match self {
            Comparison::Sizes { .. } => None,
            Comparison::Compared { flip, .. } => flip.as_ref().map(|f| &f.heat_map),
        }
    }

    /// The heat-map, taken out (the report writes it and keeps only the
    /// numbers); `None` as for [`heat_map`](Self::heat_map).
    pub fn take_heat_map(&mut self) -> Option<RgbImage> {
        match self {
            Comparison::Sizes { .. } => None,
            Comparison::Compared { flip, .. } => {
                flip.as_mut().map(|f| std::mem::take(&mut f.heat_map))
            }
        }
    }

    /// The mistakes that explain the difference, in words.
    pub fn diagnoses(&self) -> Vec<String> {
        match self {
            Comparison::Sizes { image, reference } => {
                vec![diagnose::size_message(*image, *reference)]
            }
            Comparison::Compared { findings, .. } => {
                findings.iter().map(Finding::message).collect()
            }
        }
    }

    /// The words of [`diagnoses`](Self::diagnoses) alone ("size", "mirror", ...).
    pub fn words(&self) -> Vec<&'static str> {
        match self {
            Comparison::Sizes { .. } => vec!["size"],
            Comparison::Compared { findings, .. } => findings.iter().map(Finding::word).collect(),
        }
    }

    /// Worst first: the larger share of pixels off, then the larger FLIP.
    pub fn worse_first(a: &Comparison, b: &Comparison) -> std::cmp::Ordering {
        let flip = |c: &Comparison| c.flip_mean().unwrap_or(f32::INFINITY);
        b.share()
            .total_cmp(&a.share())
            .then(flip(b).total_cmp(&flip(a)))
    }
}
