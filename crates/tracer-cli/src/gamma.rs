//! `tracer gamma fit`: a display's gamma from luminances measured on the
//! calibration chart (the lab's Matlab step, exercise 17).

use crate::BadInput;
use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use lab_tools::gamma_fit::{fit_measurements, linearity_rmse};
use lab_tools::gamma_plot::{plot_gamma, DEFAULT_SIZE};
use lab_tools::measurements::{normalised_points, parse_measurements};
use std::path::PathBuf;
use tracer_cli::output::write_png_atomically;

/// Measure a display's gamma.
#[derive(Subcommand)]
pub enum GammaCommand {
    Fit(FitArgs),
}

/// Fit y = x^gamma to luminances measured on the calibration chart.
///
/// The CSV has one row per patch: level (0 to 1), luminance (cd/m2) and
/// optionally the luminance measured after gamma correction; a header row
/// and `#` comment lines are allowed. Luminances are normalised by their
/// maximum before the least-squares fit.
#[derive(Args)]
pub struct FitArgs {
    /// Measurements, CSV
    pub measurements: PathBuf,
    /// Also draw the measured, fitted and correcting curves to this PNG
    #[arg(long, value_name = "gamma.png")]
    pub plot: Option<PathBuf>,
}

/// `--gamma` must be a number > 0.
pub fn checked_gamma(gamma: f32) -> Result<f32> {
    if gamma.is_finite() && gamma > 0.0 {
        Ok(gamma)
    } else {
        Err(BadInput(format!("--gamma: expected a number > 0, found {gamma}")).into())
    }
}

pub fn run(command: &GammaCommand) -> Result<()> {
    match command {
        GammaCommand::Fit(args) => fit(args),
    }
}

fn fit(args: &FitArgs) -> Result<()> {
    let path = &args.measurements;
    let text = std::fs::read_to_string(path).map_err(|e| {
        BadInput(format!(
            "{}: cannot read the measurements: {e}",
            path.display()
        ))
    })?;
    let rows =
        parse_measurements(&text).map_err(|e| BadInput(format!("{}: {e}", path.display())))?;
    let fit = fit_measurements(&rows);
    println!("gamma = {:.2}", fit.gamma);
    println!("RMSE = {:.4} (normalised luminance)", fit.rmse);
    let corrected = normalised_points(&rows, |m| m.corrected);
    if !corrected.is_empty() {
        println!(
            "after correction: RMSE from linear = {:.4}",
            linearity_rmse(&corrected)
        );
    }
    if let Some(plot) = &args.plot {
        let (width, height) = DEFAULT_SIZE;
        let image = plot_gamma(&rows, &fit, width, height)?;
        write_png_atomically(&image, plot)
            .with_context(|| format!("cannot write the plot {}", plot.display()))?;
        eprintln!("plot -> {}", plot.display());
    }
    Ok(())
}
