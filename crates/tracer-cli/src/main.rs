//! `tracer`: renders scene files (TOML or JSON) to PNG images.

mod aov;
mod calib_chart;
mod canvas;
mod check;
mod gamma;
mod progress;
mod render;
mod report;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "tracer",
    version,
    about = "A data-driven ray tracer: scene file in, PNG out"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    Render(render::RenderArgs),
    CalibChart(calib_chart::CalibChartArgs),
    #[command(subcommand)]
    Gamma(gamma::GammaCommand),
    Check(check::CheckArgs),
    /// Print the JSON Schema of scene files, for editor completion and
    /// checking (e.g. `tracer schema > schema.json`)
    Schema,
}

/// Exit status for bad input (a scene or the arguments); 1 is any other failure.
pub const EXIT_BAD_INPUT: u8 = 2;

/// An error whose cause is the user's input, not the machine.
#[derive(Debug)]
pub struct BadInput(pub String);

impl std::fmt::Display for BadInput {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BadInput {}

fn main() -> ExitCode {
    // clap exits with 2 on bad arguments, 0 for --help.
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render::run(&args),
        Command::CalibChart(args) => calib_chart::run(&args),
        Command::Gamma(command) => gamma::run(&command),
        Command::Check(args) => {
            return match check::run(&args) {
                check::Outcome::Ok => ExitCode::SUCCESS,
                check::Outcome::BadInput => ExitCode::from(EXIT_BAD_INPUT),
                check::Outcome::Failure => ExitCode::FAILURE,
            }
        }
        Command::Schema => {
            println!("{}", scene_format::schema::json_schema());
            Ok(())
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => report_error(&e),
    }
}

fn report_error(e: &anyhow::Error) -> ExitCode {
    if let Some(scene) = e.downcast_ref::<scene_format::SceneError>() {
        eprint!("{}", report::render(scene, report::color_wanted()));
        return if report::is_bad_input(scene) {
            ExitCode::from(EXIT_BAD_INPUT)
        } else {
            ExitCode::FAILURE
        };
    }
    eprintln!("error: {e:#}");
    if e.downcast_ref::<BadInput>().is_some() {
        ExitCode::from(EXIT_BAD_INPUT)
    } else {
        ExitCode::FAILURE
    }
}
