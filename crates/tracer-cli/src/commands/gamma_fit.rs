//! `tracer gamma fit`: a display's gamma from luminances measured on the
//! calibration chart (the lab's Matlab step, exercise 17).

use crate::args::{FitArgs, GammaCommand};
use anyhow::{Context, Result};
use tracer_pipeline::{lab, output};

pub fn run(command: &GammaCommand) -> Result<()> {
    match command {
        GammaCommand::Fit(args) => fit(args),
    }
}

fn fit(args: &FitArgs) -> Result<()> {
    let report = lab::fit_gamma(&args.measurements)?;
    println!("gamma = {:.2}", report.fit.gamma);
    println!("RMSE = {:.4} (normalised luminance)", report.fit.rmse);
    if let Some(rmse) = report.corrected_rmse {
        println!("after correction: RMSE from linear = {rmse:.4}");
    }
    if let Some(plot) = &args.plot {
        let image = lab::gamma_plot(&report)?;
        output::write_image(&image, plot)
            .with_context(|| format!("cannot write the plot {}", plot.display()))?;
        eprintln!("plot -> {}", plot.display());
    }
    Ok(())
}
