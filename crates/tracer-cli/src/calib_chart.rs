//! `tracer calib-chart`: the lab's calibration chart for measuring a
//! display's gamma (five grey patches 0, 0.25, 0.5, 0.75, 1).

use crate::BadInput;
use anyhow::Result;
use clap::Args;
use lab_tools::calib::calibration_chart;
use std::path::PathBuf;
use tracer_cli::output::write_png_atomically;
use tracer_core::image::{Encoding, Saturation};

/// Write the calibration chart: five equal grey patches 0, 0.25, 0.5, 0.75, 1.
#[derive(Args)]
pub struct CalibChartArgs {
    /// Output PNG
    #[arg(short, long, value_name = "OUT.png", default_value = "chart.png")]
    pub output: PathBuf,
    /// Encode with display gamma G (c^(1/G)); without it no gamma encoding
    #[arg(long, value_name = "G")]
    pub gamma: Option<f32>,
    /// Image width in pixels (a multiple of 5 gives equal patches)
    #[arg(long, default_value_t = 500)]
    pub width: u32,
    /// Image height in pixels
    #[arg(long, default_value_t = 100)]
    pub height: u32,
}

/// Largest chart side; a display is far smaller.
const MAX_SIDE: u32 = 16384;

pub fn run(args: &CalibChartArgs) -> Result<()> {
    let gamma = match args.gamma {
        Some(g) => crate::gamma::checked_gamma(g)?,
        None => 1.0,
    };
    if !(5..=MAX_SIDE).contains(&args.width) || !(1..=MAX_SIDE).contains(&args.height) {
        return Err(BadInput(format!(
            "--width/--height: expected 5 to {MAX_SIDE} by 1 to {MAX_SIDE} pixels, found {}x{}",
            args.width, args.height
        ))
        .into());
    }
    let encoding = Encoding {
        gamma,
        saturation: Saturation::White,
    };
    let image = calibration_chart(args.width, args.height).encode(&encoding);
    write_png_atomically(&image, &args.output)?;
    eprintln!(
        "calibration chart (gamma {gamma}) -> {}",
        args.output.display()
    );
    Ok(())
}
