//! The linear image and its encoding for a display: the over-saturation
//! rule, gamma, 8-bit truncation (lab sections 5.3, 6 and 7), and the same
//! rule at 16 bits.

use crate::gamma_table::GammaTable;
pub use crate::gamma_table::{quantize, quantize16};
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// What happens to a colour with a channel over 1 (lab 5.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Saturation {
    /// The lab's rule: any channel over 1 makes the whole pixel white.
    #[default]
    White,
    /// Each channel is clamped to 1 on its own.
    Clamp,
}

/// Linear RGB, row 0 at the top; pixel (i, j) at `pixels[j * width + i]`.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
}

/// How linear colours become 8-bit values.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Encoding {
    /// 1.0 writes the linear values; the lab's default is 2.2.
    pub gamma: f32,
    pub saturation: Saturation,
}

impl Default for Encoding {
    fn default() -> Self {
        Encoding {
            gamma: 2.2,
            saturation: Saturation::White,
        }
    }
}

impl LinearImage {
    pub fn new(width: u32, height: u32) -> Self {
        LinearImage {
            width,
            height,
            pixels: vec![Vec3::ZERO; width as usize * height as usize],
        }
    }

    pub fn get(&self, i: u32, j: u32) -> Vec3 {
        self.pixels[(j * self.width + i) as usize]
    }

    /// The 8-bit RGB image a display gets: each pixel's `encode_pixel`,
    /// its gamma and truncation by table (the same bytes, tested).
    pub fn encode(&self, encoding: &Encoding) -> image::RgbImage {
        let mut bytes = vec![0; 3 * self.pixels.len()];
        let pixels = bytes.chunks_exact_mut(3).zip(&self.pixels);
        match GammaTable::new(encoding.gamma) {
            Some(table) => {
                for (out, &c) in pixels {
                    let [r, g, b] = saturated(c, encoding);
                    out.copy_from_slice(&[table.code(r), table.code(g), table.code(b)]);
                }
            }
            None => {
                for (out, &c) in pixels {
                    out.copy_from_slice(&encode_pixel(c, encoding));
                }
            }
        }
        image::RgbImage::from_raw(self.width, self.height, bytes)
            .expect("the buffer holds exactly width * height pixels")
    }

    /// The 16-bit RGB image: the same saturation rule and gamma as
    /// [`encode`](Self::encode), truncated to 16 bits ([`quantize16`]).
    pub fn encode16(&self, encoding: &Encoding) -> image::ImageBuffer<image::Rgb<u16>, Vec<u16>> {
        let values = self
            .pixels
            .iter()
            .flat_map(|&c| display_values(c, encoding).map(quantize16))
            .collect();
        image::ImageBuffer::from_raw(self.width, self.height, values)
            .expect("the buffer holds exactly width * height pixels")
    }
}

/// The saturation rule, then gamma `c^(1/gamma)` on floats, then `(int)(c * 255)`.
pub fn encode_pixel(colour: Vec3, encoding: &Encoding) -> [u8; 3] {
    display_values(colour, encoding).map(quantize)
}

/// The saturation rule and gamma: what a display gets, in 0..=1, before
/// quantisation to 8 or 16 bits.
fn display_values(colour: Vec3, encoding: &Encoding) -> [f32; 3] {
    let inv = 1.0 / encoding.gamma;
    saturated(colour, encoding).map(|x| x.powf(inv))
}

/// The saturation rule, then each channel clamped to 0..=1.
#[inline(always)]
fn saturated(colour: Vec3, encoding: &Encoding) -> [f32; 3] {
    let saturated = match encoding.saturation {
        Saturation::White if colour.max_element() > 1.0 => Vec3::ONE,
        _ => colour,
    };
    saturated.clamp(Vec3::ZERO, Vec3::ONE).to_array()
}

#[cfg(test)]
mod tests {
    use super::*;

    const LINEAR: Encoding = Encoding {
        gamma: 1.0,
        saturation: Saturation::White,
    };

    #[test]
    fn quantisation_truncates() {
        assert_eq!(quantize(1.0), 255);
        assert_eq!(quantize(0.5), 127); // 127.5 truncated
        assert_eq!(quantize(0.999), 254);
        assert_eq!(quantize(-0.2), 0);
        assert_eq!(quantize(f32::NAN), 0);
    }

    #[test]
    fn quantisation_at_16_bits_truncates_and_divides_by_257_to_8_bits() {
        assert_eq!(quantize16(1.0), 65535);
        assert_eq!(quantize16(0.5), 32767); // 32767.5 truncated
        assert_eq!(quantize16(-0.2), 0);
        assert_eq!(quantize16(f32::NAN), 0);
        for c in [0.0, 0.1, 0.25, 0.5, 0.7297, 0.999, 1.0] {
            assert_eq!(quantize16(c) / 257, u16::from(quantize(c)), "{c}");
        }
    }

    #[test]
    fn white_rule_turns_any_over_saturated_pixel_white() {
        assert_eq!(
            encode_pixel(Vec3::new(1.2, 0.1, 0.0), &LINEAR),
            [255, 255, 255]
        );
        assert_eq!(
            encode_pixel(Vec3::new(1.0, 0.1, 0.0), &LINEAR),
            [255, 25, 0]
        );
    }

    #[test]
    fn clamp_rule_clamps_each_channel() {
        let clamp = Encoding {
            saturation: Saturation::Clamp,
            ..LINEAR
        };
        assert_eq!(encode_pixel(Vec3::new(1.2, 0.1, 0.0), &clamp), [255, 25, 0]);
    }

    #[test]
    fn gamma_is_applied_before_truncation() {
        let g = Encoding {
            gamma: 2.2,
            ..LINEAR
        };
        // 0.5^(1/2.2) = 0.7297 -> 186.08 -> 186
        assert_eq!(encode_pixel(Vec3::splat(0.5), &g), [186; 3]);
        assert_eq!(encode_pixel(Vec3::splat(0.0), &g), [0; 3]);
        assert_eq!(encode_pixel(Vec3::splat(1.0), &g), [255; 3]);
    }
}
