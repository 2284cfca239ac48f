//! How far an image is from its reference, pixel by pixel, in 8-bit levels.

use image::RgbImage;

/// How many of the differing pixels are listed, in reading order.
pub const FIRST_SHOWN: usize = 5;

/// One pixel of both images: X counts columns from the left, Y rows from
/// the top, (0, 0) the top-left pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pixel {
    pub x: u32,
    pub y: u32,
    pub image: [u8; 3],
    pub reference: [u8; 3],
}

impl Pixel {
    /// The largest channel difference.
    pub fn difference(&self) -> u8 {
        channel_difference(self.image, self.reference)
    }
}

/// The numbers of one comparison of two images of one size.
#[derive(Debug, Clone, PartialEq)]
pub struct Difference {
    pub pixels: u64,
    /// Pixels with a channel off by more than the tolerance.
    pub differing: u64,
    /// The first pixel with the largest channel difference; `None` when
    /// the images are identical.
    pub largest: Option<Pixel>,
    /// The mean of the squared channel differences, in levels squared.
    pub mse: f64,
    /// The first [`FIRST_SHOWN`] differing pixels, in reading order.
    pub first: Vec<Pixel>,
}

impl Difference {
    /// The share of the pixels off, 0 to 1.
    pub fn share(&self) -> f64 {
        if self.pixels == 0 {
            0.0
        } else {
            self.differing as f64 / self.pixels as f64
        }
    }

    /// Peak signal-to-noise ratio in dB; `None` (infinite) when identical.
    pub fn psnr(&self) -> Option<f64> {
        (self.mse > 0.0).then(|| 10.0 * (255.0 * 255.0 / self.mse).log10())
    }
}

/// The largest difference of two colours' channels.
pub fn channel_difference(a: [u8; 3], b: [u8; 3]) -> u8 {
    (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0)
}

/// `image` against `reference` (of one size): a pixel differs when a
/// channel is off by more than `tolerance` levels.
pub fn difference(image: &RgbImage, reference: &RgbImage, tolerance: u8) -> Difference {
    let mut d = Difference {
        pixels: u64::from(image.width()) * u64::from(image.height()),
        differing: 0,
        largest: None,
        mse: 0.0,
        first: Vec::new(),
    };
    let mut squares = 0u64;
    for ((x, y, a), b) in image.enumerate_pixels().zip(reference.pixels()) {
        let pixel = Pixel {
            x,
            y,
            image: a.0,
            reference: b.0,
        };
        squares += (0..3)
            .map(|c| u64::from(a.0[c].abs_diff(b.0[c])).pow(2))
            .sum::<u64>();
        let off = pixel.difference();
        if off > d.largest.map_or(0, |p| p.difference()) {
            d.largest = Some(pixel);
        }
        if off > tolerance {
            d.differing += 1;
            if d.first.len() < FIRST_SHOWN {
                d.first.push(pixel);
            }
        }
    }
    d.mse = squares as f64 / (3 * d.pixels.max(1)) as f64;
    d
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Rgb;

    #[test]
    fn counts_only_pixels_beyond_the_tolerance_and_finds_the_largest() {
        let reference = RgbImage::from_pixel(3, 2, Rgb([100, 100, 100]));
        let mut image = reference.clone();
        image.put_pixel(0, 0, Rgb([102, 100, 100])); // within: 2 <= 2
        image.put_pixel(2, 0, Rgb([100, 97, 100])); // beyond: 3 > 2
        image.put_pixel(1, 1, Rgb([100, 100, 160])); // the largest
        let d = difference(&image, &reference, 2);
        assert_eq!(d.differing, 2);
        assert!((d.share() - 2.0 / 6.0).abs() < 1e-12);
        let largest = d.largest.unwrap();
        assert_eq!((largest.x, largest.y, largest.difference()), (1, 1, 60));
        let first: Vec<(u32, u32)> = d.first.iter().map(|p| (p.x, p.y)).collect();
        assert_eq!(first, [(2, 0), (1, 1)]);
        // (4 + 9 + 3600) / 18 channel values
        assert!((d.mse - 3613.0 / 18.0).abs() < 1e-9);
        assert!((d.psnr().unwrap() - 10.0 * (65025.0 / d.mse).log10()).abs() < 1e-9);
    }

    #[test]
    fn identical_images_have_no_largest_difference_and_infinite_psnr() {
        let image = RgbImage::from_pixel(4, 4, Rgb([1, 2, 3]));
        let d = difference(&image, &image, 0);
        assert_eq!((d.differing, d.largest, d.psnr()), (0, None, None));
    }
}
