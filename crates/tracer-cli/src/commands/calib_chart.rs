//! `tracer calib-chart`: the lab's calibration chart for measuring a
//! display's gamma (five grey patches 0, 0.25, 0.5, 0.75, 1).

use crate::args::CalibChart;
use anyhow::Result;
use tracer_pipeline::{lab, output, Gamma};

pub fn run(args: &CalibChart) -> Result<()> {
    let image = lab::chart(args.width, args.height, args.gamma)?;
    output::write_image(&image, &args.output)?;
    eprintln!(
        "calibration chart (gamma {}) -> {}",
        args.gamma.map_or(1.0, Gamma::get),
        args.output.display()
    );
    Ok(())
}
