//! Measuring a display's gamma without Matlab (lab section 6, exercise 17):
//! normalised luminances fitted to `y = x^gamma` by least squares (as the
//! lab's `cftool` does).

use crate::measurements::{normalised_points, Measurement, MeasurementError};

/// A fitted `y = x^gamma` and its root-mean-square error on the points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GammaFit {
    pub gamma: f64,
    pub rmse: f64,
}

/// The gamma range searched; displays lie well inside it.
pub const GAMMA_RANGE: (f64, f64) = (0.05, 20.0);

/// Sum of squared residuals of `y = x^gamma`.
pub fn sse(points: &[(f64, f64)], gamma: f64) -> f64 {
    points
        .iter()
        .map(|&(x, y)| (x.powf(gamma) - y).powi(2))
        .sum()
}

/// Least squares fit of `y = x^gamma` to normalised points: a scan over a
/// log-spaced grid finds the basin of the smallest error, golden-section
/// search narrows it down.
pub fn fit_gamma(points: &[(f64, f64)]) -> GammaFit {
    const STEPS: usize = 2000;
    let (lo, hi) = GAMMA_RANGE;
    let ratio = (hi / lo).powf(1.0 / STEPS as f64);
    let grid: Vec<f64> = (0..=STEPS).map(|k| lo * ratio.powi(k as i32)).collect();
    let best = (0..grid.len())
        .min_by(|&a, &b| sse(points, grid[a]).total_cmp(&sse(points, grid[b])))
        .unwrap_or(0);
    let a = grid[best.saturating_sub(1)];
    let b = grid[(best + 1).min(STEPS)];
    let gamma = golden_section(|g| sse(points, g), a, b);
    let rmse = (sse(points, gamma) / points.len().max(1) as f64).sqrt();
    GammaFit { gamma, rmse }
}

/// The minimum of a function unimodal on [a, b].
fn golden_section(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    let inv_phi = (5f64.sqrt() - 1.0) / 2.0;
    let mut c = b - inv_phi * (b - a);
    let mut d = a + inv_phi * (b - a);
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..200 {
        if b - a <= 1e-12 * b.abs().max(1.0) {
            break;
        }
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - inv_phi * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + inv_phi * (b - a);
            fd = f(d);
        }
    }
    (a + b) / 2.0
}

/// The fit of a measurement file: levels against luminances normalised by
/// their maximum. A fit at an end of [`GAMMA_RANGE`] is an error: the
/// least-squares minimum lies outside it, so the number would be the
/// search's bound, not the display's gamma.
pub fn fit_measurements(rows: &[Measurement]) -> Result<GammaFit, MeasurementError> {
    let fit = fit_gamma(&normalised_points(rows, |m| Some(m.luminance)));
    let (lo, hi) = GAMMA_RANGE;
    // Golden-section search stops within 1e-12 of a bound it is pushed to.
    if fit.gamma <= lo * (1.0 + 1e-6) || fit.gamma >= hi * (1.0 - 1e-6) {
        return Err(MeasurementError {
            line: None,
            message: format!(
                "the fit reached the end of the gamma range searched ({lo} to {hi}), so no gamma fits these luminances; are they of this chart's patches, in order?"
            ),
        });
    }
    Ok(fit)
}

/// RMSE of normalised corrected measurements from the straight line y = x:
/// how close to linear the corrected display is.
pub fn linearity_rmse(points: &[(f64, f64)]) -> f64 {
    let sum: f64 = points.iter().map(|&(x, y)| (y - x).powi(2)).sum();
    (sum / points.len().max(1) as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measurements::parse_measurements;

    #[test]
    fn exact_power_law_data_give_back_their_gamma() {
        for gamma in [1.0, 1.8, 2.2, 2.3, 2.6] {
            let points: Vec<(f64, f64)> = [0.0, 0.25, 0.5, 0.75, 1.0]
                .iter()
                .map(|&x: &f64| (x, x.powf(gamma)))
                .collect();
            let fit = fit_gamma(&points);
            assert!((fit.gamma - gamma).abs() < 1e-6, "{fit:?} for {gamma}");
            assert!(fit.rmse < 1e-6);
        }
    }

    #[test]
    fn noisy_data_agree_with_a_brute_force_scan() {
        // Luminances of a gamma-2.3 display with a black level and noise.
        let points = [
            (0.0, 0.002),
            (0.25, 0.047),
            (0.5, 0.199),
            (0.75, 0.526),
            (1.0, 1.0),
        ];
        let fit = fit_gamma(&points);
        // An independent minimiser: every gamma from 1 to 4 in steps of 1e-5.
        let brute = (100_000..=400_000)
            .map(|k| k as f64 * 1e-5)
            .min_by(|&a, &b| sse(&points, a).total_cmp(&sse(&points, b)))
            .unwrap();
        assert!((fit.gamma - brute).abs() < 2e-5, "{} vs {brute}", fit.gamma);
        assert!((fit.gamma - 2.3).abs() < 0.05);
        let rmse = (sse(&points, fit.gamma) / 5.0).sqrt();
        assert_eq!(fit.rmse, rmse);
    }

    #[test]
    fn a_fit_of_measurements_normalises_them_first() {
        let rows = parse_measurements("level,luminance\n0,0.5\n0.5,25\n1,100\n").unwrap();
        // 0.5^gamma = 0.25 -> gamma = 2 (0 -> 0.005 pulls a hair off 2).
        assert!((fit_measurements(&rows).unwrap().gamma - 2.0).abs() < 1e-3);
    }

    #[test]
    fn a_fit_stuck_at_an_end_of_the_range_is_an_error() {
        // 0.5^gamma = 1e-9 wants gamma 30; 0.5^gamma = 0.9999 wants 1.4e-4.
        for text in ["0,1e-9\n0.5,1e-9\n1,1\n", "0,0.9999\n0.5,0.9999\n1,1\n"] {
            let rows = parse_measurements(text).unwrap();
            let err = fit_measurements(&rows).unwrap_err().to_string();
            assert!(err.contains("end of the gamma range"), "{err}");
        }
    }
}
