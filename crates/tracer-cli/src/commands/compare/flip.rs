//! FLIP, the perceptual difference of Andersson et al. 2020 ("FLIP: A
//! Difference Evaluator for Alternating Images"), through NVIDIA's own C++
//! (the `nv-flip` crate), and its error map as the heat-map.

use image::RgbImage;

/// FLIP's verdict on an image against its reference.
pub struct Flip {
    /// The mean of the per-pixel error, 0 (identical) to 1: the one number
    /// FLIP's authors recommend.
    pub mean: f32,
    /// The per-pixel error in FLIP's magma colours: black none, through
    /// purple and orange, yellow the largest.
    pub heat_map: RgbImage,
}

/// The largest images FLIP is computed for: NVIDIA's code takes about 80
/// bytes a pixel (1.35 GB at 4096^2) and crashes, without a word, when an
/// allocation fails (at 8192^2 under 4 GB); larger images are compared
/// without it.
pub const MAX_PIXELS: u64 = 1 << 24;

/// Whether FLIP is computed for images of `image`'s size.
pub fn fits(image: &RgbImage) -> bool {
    u64::from(image.width()) * u64::from(image.height()) <= MAX_PIXELS
}

/// FLIP of `image` against `reference` (of one size; sRGB), seen at the
/// FLIP tool's default of 67 pixels per degree (a 0.7 m distant 24-inch
/// monitor of 3840 pixels across).
pub fn flip(image: &RgbImage, reference: &RgbImage) -> Flip {
    let flip_image =
        |i: &RgbImage| nv_flip::FlipImageRgb8::with_data(i.width(), i.height(), i.as_raw());
    let error = nv_flip::flip(
        flip_image(reference),
        flip_image(image),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    let mean = nv_flip::FlipPool::from_image(&error).mean();
    let colours = error.apply_color_lut(&nv_flip::magma_lut());
    let heat_map = RgbImage::from_raw(colours.width(), colours.height(), colours.to_vec())
        .expect("FLIP's map is of the images' size");
    Flip { mean, heat_map }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Rgb;

    #[test]
    fn images_over_4096_squared_are_not_given_to_flip() {
        assert!(fits(&RgbImage::new(4096, 4096)));
        assert!(!fits(&RgbImage::new(4097, 4096)));
        assert!(fits(&RgbImage::new(16384, 1024)));
    }

    #[test]
    fn identical_images_have_no_error_and_a_changed_pixel_shows() {
        let reference = RgbImage::from_pixel(32, 24, Rgb([90, 120, 200]));
        let same = flip(&reference, &reference);
        assert_eq!(same.mean, 0.0);
        let black = same.heat_map.get_pixel(0, 0).0;
        assert!(same.heat_map.pixels().all(|p| p.0 == black));
        let mut image = reference.clone();
        image.put_pixel(10, 5, Rgb([255, 255, 0]));
        let changed = flip(&image, &reference);
        assert!(changed.mean > 0.0);
        assert_ne!(changed.heat_map.get_pixel(10, 5).0, black);
        assert_eq!(changed.heat_map.get_pixel(30, 20).0, black);
    }
}
