//! `tracer gamma fit`: a display's gamma from luminances measured on the
//! calibration chart (the lab's Matlab step, exercise 17).

use crate::args::{FitArgs, GammaCommand};
use crate::console::{self, note};
use anyhow::Result;
use tracer_pipeline::output::{check_not_an_input, PendingOutput};
use tracer_pipeline::{lab, Error};

pub fn run(command: &GammaCommand) -> Result<()> {
    match command {
        GammaCommand::Fit(args) => fit(args),
    }
}

fn fit(args: &FitArgs) -> Result<()> {
    // The plot's path is checked before the fit: a wrong one fails first.
    let plot = match &args.plot {
        Some(plot) => {
            check_not_an_input(plot, &[&args.measurements]).map_err(Error::from)?;
            Some(PendingOutput::create_8bit(plot).map_err(Error::from)?)
        }
        None => None,
    };
    let report = lab::fit_gamma(&args.measurements)?;
    let mut text = format!(
        "gamma = {:.2}\nRMSE = {:.4} (normalised luminance)\n",
        report.fit.gamma, report.fit.rmse
    );
    if let Some(rmse) = report.corrected_rmse {
        text += &format!("after correction: RMSE from linear = {rmse:.4}\n");
    }
    console::stdout(&text)?;
    if let Some(plot) = plot {
        let image = lab::gamma_plot(&report)?;
        let path = plot.path().to_path_buf();
        plot.write_image(&image).map_err(Error::from)?;
        note!("plot -> {}", path.display());
    }
    Ok(())
}
