//! `--reference`: an image to measure a render's error against, as pbrt's
//! `--mse-reference-image`, so equal-time comparisons need no other tool.

use crate::Error;
use std::path::Path;
use tracer_core::LinearImage;

/// Largest reference file read: a float EXR of the largest image a render
/// makes is about 3 GiB; references are of renders far smaller.
const MAX_REFERENCE_BYTES: u64 = 1 << 30;

/// The linear values of the image at `path` (any format the `image` crate
/// reads; an EXR or HDR keeps them as rendered), which must be
/// `width` x `height`.
pub fn read_reference(path: &Path, (width, height): (u32, u32)) -> Result<LinearImage, Error> {
    let bad = |message: String| Error::Reference {
        path: path.to_path_buf(),
        message,
    };
    let bytes = scene_format::read::read_capped(path, MAX_REFERENCE_BYTES)
        .map_err(|e| bad(e.to_string()))?;
    let open = || {
        image::ImageReader::new(std::io::Cursor::new(&bytes[..]))
            .with_guessed_format()
            .map_err(|e| bad(e.to_string()))
    };
    let mut reader = open()?;
    // An 8-bit image holds display values, gamma-encoded: its error against
    // the linear render would mean nothing.
    match reader.format() {
        Some(image::ImageFormat::OpenExr | image::ImageFormat::Hdr) => {}
        other => {
            let what = other.map_or("not an image file".to_string(), |f| {
                format!(
                    "a {} image, of display values",
                    f.extensions_str()[0].to_uppercase()
                )
            });
            return Err(bad(format!(
                "is {what}; expected a linear .exr or .hdr image (tracer render SCENE -o reference.exr)"
            )));
        }
    }
    // Its size from its header first: a larger image would only be
    // refused by the decoder's memory limit.
    let size = open()?
        .into_dimensions()
        .map_err(|e| bad(scene_format::images::unreadable(e)))?;
    if size != (width, height) {
        return Err(bad(format!(
            "{}x{}, but the render is {width}x{height}; expected an image of the render's size",
            size.0, size.1
        )));
    }
    // What the decoder may take: a float image of the render's size, with
    // room for its alpha, and no more (a file's header may claim any size).
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(u64::from(width) * u64::from(height) * 32 + (1 << 20));
    reader.limits(limits);
    let image = reader
        .decode()
        .map_err(|e| bad(scene_format::images::unreadable(e)))?
        .into_rgb32f();
    if image.pixels().flat_map(|p| p.0).any(|x| !x.is_finite()) {
        return Err(bad(
            "has values that are not finite numbers (NaN or infinite); expected a rendered image"
                .to_string(),
        ));
    }
    let mut linear = LinearImage::new(width, height);
    for (pixel, p) in linear.pixels.iter_mut().zip(image.pixels()) {
        *pixel = glam::Vec3::from(p.0);
    }
    Ok(linear)
}

/// The root mean square of the difference of `a` and `b` (of one size), over
/// every pixel and channel.
pub fn rmse(a: &LinearImage, b: &LinearImage) -> f64 {
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        // In f64: the square of a difference of large floats overflows f32.
        .map(|(x, y)| (x.as_dvec3() - y.as_dvec3()).length_squared())
        .sum();
    (sum / (3 * a.pixels.len().max(1)) as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn image(pixels: &[Vec3]) -> LinearImage {
        let mut image = LinearImage::new(pixels.len() as u32, 1);
        image.pixels.copy_from_slice(pixels);
        image
    }

    #[test]
    fn the_error_of_large_values_is_finite() {
        // Their difference squared, 1e60, is past the largest f32.
        let a = image(&[Vec3::splat(1e30), Vec3::ZERO]);
        let b = image(&[Vec3::ZERO, Vec3::ZERO]);
        let expected = (3.0 * 1e60f64 / 6.0).sqrt();
        assert!(
            (rmse(&a, &b) / expected - 1.0).abs() < 1e-6,
            "{}",
            rmse(&a, &b)
        );
        assert_eq!(rmse(&b, &b), 0.0);
    }

    #[test]
    fn a_reference_with_values_that_are_not_numbers_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("nan.exr");
        let floats = vec![0.5f32, f32::NAN, 0.5, 0.25, 0.25, 0.25];
        image::Rgb32FImage::from_raw(2, 1, floats)
            .unwrap()
            .save(&path)
            .unwrap();
        let error = read_reference(&path, (2, 1)).unwrap_err().to_string();
        assert!(error.contains("not finite numbers"), "{error}");
    }
}
