//! The lab's images that are not scene renders: the calibration chart and
//! the gamma fit of measurements taken on it, with its plot.

use crate::options::Gamma;
use crate::Error;
use image::RgbImage;
use lab_tools::gamma_fit::{fit_measurements, linearity_rmse, GammaFit};
use lab_tools::measurements::{normalised_points, parse_measurements, Measurement};
use std::path::Path;

pub use lab_tools::calib::DEFAULT_CHART_SIZE;
#[cfg(not(target_arch = "wasm32"))]
pub use lab_tools::gamma_plot::DEFAULT_SIZE as DEFAULT_PLOT_SIZE;

/// Largest chart side; a display is far smaller.
pub const MAX_CHART_SIDE: u32 = 16384;

/// The calibration chart, `width` x `height` pixels (at least 5 wide, one
/// pixel per patch), encoded with `gamma` (without: none, as the lab's).
pub fn chart(width: u32, height: u32, gamma: Option<Gamma>) -> Result<RgbImage, Error> {
    if !(5..=MAX_CHART_SIDE).contains(&width) || !(1..=MAX_CHART_SIDE).contains(&height) {
        return Err(Error::ChartSize {
            width,
            height,
            max: MAX_CHART_SIDE,
        });
    }
    let encoding = lab_tools::calib::chart_encoding(gamma.map_or(1.0, Gamma::get));
    // Every row is the same: one encoded, then repeated, so a chart of
    // 16384x16384 takes its 8-bit pixels only (it took five times more
    // as floats first).
    let row = lab_tools::calib::calibration_chart(width, 1).encode(&encoding);
    let pixels = row.as_raw().repeat(height as usize);
    Ok(RgbImage::from_raw(width, height, pixels).expect("height rows of the row's width"))
}

/// A display's gamma fitted to the measurements of one file.
#[derive(Debug, Clone, PartialEq)]
pub struct GammaReport {
    pub rows: Vec<Measurement>,
    pub fit: GammaFit,
    /// How far the luminances measured after correction are from linear
    /// (RMSE of the normalised values); `None` when none were measured.
    pub corrected_rmse: Option<f64>,
}

/// Reads a measurements CSV and fits `y = x^gamma` to it.
pub fn fit_gamma(csv: &Path) -> Result<GammaReport, Error> {
    let bad = |message: String| Error::Measurements {
        file: csv.to_path_buf(),
        message,
    };
    let bytes = scene_format::read::read_capped(csv, scene_format::read::MAX_CSV_BYTES)
        .map_err(|e| bad(format!("cannot read the measurements: {e}")))?;
    let text = String::from_utf8(bytes).map_err(|e| {
        bad(format!(
            "cannot read the measurements: not UTF-8 text ({e})"
        ))
    })?;
    let rows = parse_measurements(&text).map_err(|e| bad(e.to_string()))?;
    let fit = fit_measurements(&rows).map_err(|e| bad(e.to_string()))?;
    let corrected = normalised_points(&rows, |m| m.corrected);
    let corrected_rmse = (!corrected.is_empty()).then(|| linearity_rmse(&corrected));
    Ok(GammaReport {
        rows,
        fit,
        corrected_rmse,
    })
}

/// The plot of a fit, [`DEFAULT_PLOT_SIZE`] pixels.
#[cfg(not(target_arch = "wasm32"))]
pub fn gamma_plot(report: &GammaReport) -> Result<RgbImage, Error> {
    let (width, height) = DEFAULT_PLOT_SIZE;
    Ok(lab_tools::gamma_plot::plot_gamma(
        &report.rows,
        &report.fit,
        width,
        height,
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chart_is_its_linear_image_encoded_whatever_its_size() {
        for (width, height, gamma) in [(7, 3, 2.2), (5, 1, 1.0), (13, 4, 1.8)] {
            let made = chart(width, height, Some(Gamma::new(gamma).unwrap())).unwrap();
            let encoding = lab_tools::calib::chart_encoding(gamma);
            let whole = lab_tools::calib::calibration_chart(width, height).encode(&encoding);
            assert_eq!(made, whole, "{width}x{height}");
        }
    }

    #[test]
    fn the_default_chart_has_five_patches_of_100_pixels() {
        let (width, height) = DEFAULT_CHART_SIZE;
        let image = chart(width, height, None).unwrap();
        assert_eq!(image.dimensions(), (500, 100));
        let patches: Vec<u8> = (0..5).map(|k| image.get_pixel(k * 100, 0).0[0]).collect();
        assert_eq!(patches, [0, 63, 127, 191, 255]);
    }

    #[test]
    fn a_chart_narrower_than_its_patches_is_bad_input() {
        let err = chart(4, 100, None).unwrap_err();
        assert!(err.is_bad_input());
        assert_eq!(
            err.to_string(),
            "--width/--height: expected 5 to 16384 by 1 to 16384 pixels, found 4x100"
        );
    }

    #[test]
    fn a_missing_measurements_file_is_bad_input() {
        let err = fit_gamma(Path::new("no/such/measurements.csv")).unwrap_err();
        assert!(err.is_bad_input());
        assert!(err
            .to_string()
            .starts_with("no/such/measurements.csv: cannot read the measurements"));
    }
}
