//! Pixel-by-pixel comparison of a render with its golden image, and the
//! heat map that shows where they differ.

use image::{Rgb, RgbImage};

/// When a render still counts as its golden image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    /// A pixel differs when any channel differs by more than this many 8-bit levels.
    pub channel: u8,
    /// The image passes when at most this percentage of its pixels differ.
    pub max_differing_percent: f64,
}

impl Default for Tolerance {
    fn default() -> Self {
        Tolerance {
            channel: 2,
            max_differing_percent: 0.1,
        }
    }
}

/// How far a render is from its golden image.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    pub pixels: u64,
    /// Pixels with a channel difference above the tolerance.
    pub differing: u64,
    /// The largest channel difference, in 8-bit levels.
    pub max_diff: u8,
    /// The mean absolute channel difference over every channel of every pixel,
    /// in 8-bit levels.
    pub mean_diff: f64,
}

impl Comparison {
    pub fn differing_percent(&self) -> f64 {
        if self.pixels == 0 {
            0.0
        } else {
            self.differing as f64 * 100.0 / self.pixels as f64
        }
    }

    pub fn passes(&self, tolerance: &Tolerance) -> bool {
        self.differing as f64 * 100.0 <= tolerance.max_differing_percent * self.pixels as f64
    }
}

/// Golden and render have different sizes: nothing to compare pixel by pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SizeMismatch {
    pub golden: (u32, u32),
    pub actual: (u32, u32),
}

impl std::fmt::Display for SizeMismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (gw, gh) = self.golden;
        let (aw, ah) = self.actual;
        write!(f, "size differs: golden {gw}x{gh}, render {aw}x{ah}")
    }
}

pub fn compare(
    golden: &RgbImage,
    actual: &RgbImage,
    tolerance: &Tolerance,
) -> Result<Comparison, SizeMismatch> {
    check_sizes(golden, actual)?;
    let mut differing = 0;
    let mut max_diff = 0;
    let mut sum: u64 = 0;
    for (g, a) in golden.pixels().zip(actual.pixels()) {
        let d = channel_diffs(g, a);
        let pixel_max = d.into_iter().max().unwrap_or(0);
        max_diff = max_diff.max(pixel_max);
        differing += u64::from(pixel_max > tolerance.channel);
        sum += d.iter().map(|&c| u64::from(c)).sum::<u64>();
    }
    let pixels = u64::from(golden.width()) * u64::from(golden.height());
    let mean_diff = if pixels == 0 {
        0.0
    } else {
        sum as f64 / (pixels * 3) as f64
    };
    Ok(Comparison {
        pixels,
        differing,
        max_diff,
        mean_diff,
    })
}

fn check_sizes(golden: &RgbImage, actual: &RgbImage) -> Result<(), SizeMismatch> {
    if golden.dimensions() == actual.dimensions() {
        Ok(())
    } else {
        Err(SizeMismatch {
            golden: golden.dimensions(),
            actual: actual.dimensions(),
        })
    }
}

fn channel_diffs(g: &Rgb<u8>, a: &Rgb<u8>) -> [u8; 3] {
    [0, 1, 2].map(|c| g.0[c].abs_diff(a.0[c]))
}

/// Colours of the heat map, explained on the report page.
pub mod heat {
    /// A pixel within tolerance but not identical.
    pub const WITHIN: [u8; 3] = [40, 90, 255];
    /// A pixel just beyond tolerance; the largest differences go to yellow.
    pub const BEYOND_LOW: [u8; 3] = [255, 0, 0];
    pub const BEYOND_HIGH: [u8; 3] = [255, 255, 0];
}

/// Where the images differ: identical pixels are the golden image dimmed to a
/// quarter of its brightness (to see where one is), pixels that differ within
/// tolerance blue, beyond tolerance red to yellow with the size of the difference.
pub fn heat_map(
    golden: &RgbImage,
    actual: &RgbImage,
    tolerance: &Tolerance,
) -> Result<RgbImage, SizeMismatch> {
    check_sizes(golden, actual)?;
    let mut map = RgbImage::new(golden.width(), golden.height());
    for ((g, a), out) in golden.pixels().zip(actual.pixels()).zip(map.pixels_mut()) {
        let d = channel_diffs(g, a).into_iter().max().unwrap_or(0);
        *out = Rgb(heat_colour(g, d, tolerance.channel));
    }
    Ok(map)
}

fn heat_colour(golden: &Rgb<u8>, diff: u8, tolerance: u8) -> [u8; 3] {
    if diff == 0 {
        let [r, g, b] = golden.0.map(u32::from);
        let grey = ((r * 299 + g * 587 + b * 114) / 1000 / 4) as u8;
        [grey; 3]
    } else if diff <= tolerance {
        heat::WITHIN
    } else {
        // sqrt so that small excesses already move visibly toward yellow.
        let t = f32::from(diff - tolerance) / f32::from(255 - tolerance);
        let green = (t.sqrt() * 255.0) as u8;
        [heat::BEYOND_LOW[0], green, heat::BEYOND_HIGH[2]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn solid(w: u32, h: u32, c: [u8; 3]) -> RgbImage {
        RgbImage::from_pixel(w, h, Rgb(c))
    }

    #[test]
    fn identical_images_have_no_difference() {
        let a = solid(4, 3, [10, 20, 30]);
        let c = compare(&a, &a, &Tolerance::default()).unwrap();
        assert_eq!(
            c,
            Comparison {
                pixels: 12,
                differing: 0,
                max_diff: 0,
                mean_diff: 0.0
            }
        );
    }

    #[test]
    fn a_pixel_differs_only_beyond_the_channel_tolerance() {
        let golden = solid(2, 1, [100, 100, 100]);
        let mut actual = golden.clone();
        actual.put_pixel(0, 0, Rgb([102, 100, 100])); // within: 2 <= 2
        actual.put_pixel(1, 0, Rgb([100, 97, 100])); // beyond: 3 > 2
        let c = compare(&golden, &actual, &Tolerance::default()).unwrap();
        assert_eq!(c.differing, 1);
        assert_eq!(c.max_diff, 3);
        // (2 + 3) / (2 pixels * 3 channels)
        assert!((c.mean_diff - 5.0 / 6.0).abs() < 1e-12);
    }

    #[test]
    fn passing_allows_exactly_the_percentage() {
        let tolerance = Tolerance::default(); // 0.1 %
        let c = |differing| Comparison {
            pixels: 200_000,
            differing,
            max_diff: 255,
            mean_diff: 1.0,
        };
        assert!(c(200).passes(&tolerance));
        assert!(!c(201).passes(&tolerance));
    }

    #[test]
    fn different_sizes_are_reported_not_compared() {
        let err = compare(
            &solid(4, 3, [0; 3]),
            &solid(3, 4, [0; 3]),
            &Tolerance::default(),
        )
        .unwrap_err();
        assert_eq!(err.to_string(), "size differs: golden 4x3, render 3x4");
    }

    #[test]
    fn heat_map_marks_each_kind_of_pixel() {
        let golden = solid(3, 1, [200, 200, 200]);
        let mut actual = golden.clone();
        actual.put_pixel(1, 0, Rgb([201, 200, 200]));
        actual.put_pixel(2, 0, Rgb([200, 200, 0]));
        let map = heat_map(&golden, &actual, &Tolerance::default()).unwrap();
        assert_eq!(map.get_pixel(0, 0).0, [50; 3]); // 200 / 4
        assert_eq!(map.get_pixel(1, 0).0, heat::WITHIN);
        // (200 - 2) / 253 = 0.7826, sqrt 0.8847 -> 225
        assert_eq!(map.get_pixel(2, 0).0, [255, 225, 0]);
    }
}
