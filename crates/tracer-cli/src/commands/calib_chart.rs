//! `tracer calib-chart`: the lab's calibration chart for measuring a
//! display's gamma (five grey patches 0, 0.25, 0.5, 0.75, 1).

use crate::args::CalibChart;
use crate::console::note;
use anyhow::Result;
use tracer_pipeline::output::PendingOutput;
use tracer_pipeline::{lab, Error, Gamma};

pub fn run(args: &CalibChart) -> Result<()> {
    // An output that is not an image (`-o scene.toml`) is refused here.
    let output = PendingOutput::create_8bit(&args.output).map_err(Error::from)?;
    let image = lab::chart(args.width, args.height, args.gamma)?;
    output.write_image(&image).map_err(Error::from)?;
    note!(
        "calibration chart (gamma {}) -> {}",
        args.gamma.map_or(1.0, Gamma::get),
        args.output.display()
    );
    Ok(())
}
