//! The lab's calibration chart (exercise 17, `CImage::plotCalibChart`): five
//! equal grey patches 0, 0.25, 0.5, 0.75, 1 side by side, to be measured on
//! a display with a luminance meter.

use glam::Vec3;
use tracer_core::image::{Encoding, LinearImage, Saturation};

/// The grey levels of the patches, left to right.
pub const CHART_LEVELS: [f32; 5] = [0.0, 0.25, 0.5, 0.75, 1.0];

/// The chart's size when none is asked for, (width, height) in pixels: 100
/// pixels per patch, as `tracer calib-chart` writes it and its golden holds.
pub const DEFAULT_CHART_SIZE: (u32, u32) = (500, 100);

/// How the chart is written: gamma `gamma` (1 = none, the lab's chart) and
/// the lab's saturation rule (the levels never exceed 1, so it never acts).
pub fn chart_encoding(gamma: f32) -> Encoding {
    Encoding {
        gamma,
        saturation: Saturation::White,
    }
}

/// The chart in linear values; patch k covers columns `k * W / 5` up to
/// `(k + 1) * W / 5` (equal when W is a multiple of 5), all rows.
pub fn calibration_chart(width: u32, height: u32) -> LinearImage {
    let mut image = LinearImage::new(width, height);
    let patches = CHART_LEVELS.len() as u64;
    for (k, pixel) in image.pixels.iter_mut().enumerate() {
        let column = k as u64 % u64::from(width);
        let patch = (column * patches / u64::from(width)) as usize;
        *pixel = Vec3::splat(CHART_LEVELS[patch]);
    }
    image
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bytes_per_patch(gamma: f32) -> Vec<u8> {
        let (width, height) = DEFAULT_CHART_SIZE;
        let image = calibration_chart(width, height).encode(&chart_encoding(gamma));
        (0..5)
            .map(|k| image.get_pixel(k * 100 + 50, 50).0[0])
            .collect()
    }

    #[test]
    fn without_gamma_the_patches_are_the_truncated_levels() {
        // (int)(c * 255): 0, 63.75, 127.5, 191.25, 255.
        assert_eq!(bytes_per_patch(1.0), [0, 63, 127, 191, 255]);
    }

    #[test]
    fn with_gamma_2_2_the_patches_are_encoded() {
        // 0.25^(1/2.2) = 0.53254 -> 135.8; 0.5^(1/2.2) = 0.72974 -> 186.08;
        // 0.75^(1/2.2) = 0.87742 -> 223.74.
        assert_eq!(bytes_per_patch(2.2), [0, 135, 186, 223, 255]);
    }

    #[test]
    fn the_five_patches_are_equal_and_fill_the_image() {
        let image = calibration_chart(500, 100);
        for k in 0..5u32 {
            let level = Vec3::splat(CHART_LEVELS[k as usize]);
            for i in k * 100..(k + 1) * 100 {
                assert_eq!(image.get(i, 0), level, "column {i}");
                assert_eq!(image.get(i, 99), level, "column {i}");
            }
        }
    }
}
