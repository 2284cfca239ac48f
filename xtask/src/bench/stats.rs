//! Summaries of repeated measurements.

/// The median (the upper one of an even count).
pub fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs[xs.len() / 2]
}

/// The lowest and the highest.
pub fn range(xs: &[f64]) -> (f64, f64) {
    let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (lo, hi)
}

/// "lowest-highest" of runs' ratios, e.g. `1.54x-2.03x`.
pub fn spread(xs: &[f64]) -> String {
    let (lo, hi) = range(xs);
    format!("{lo:.2}x-{hi:.2}x")
}
