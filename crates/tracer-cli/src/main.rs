//! `tracer`: renders scene files (TOML or JSON) to PNG images.

mod args;
mod commands;
mod error;
mod progress;
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
    Render(args::RenderArgs),
    CalibChart(args::CalibChartArgs),
    #[command(subcommand)]
    Gamma(args::GammaCommand),
    Check(args::CheckArgs),
    /// Print the JSON Schema of scene files, for editor completion and
    /// checking (e.g. `tracer schema > schema.json`)
    Schema,
}

fn main() -> ExitCode {
    // clap exits with 2 on bad arguments, 0 for --help.
    let cli = Cli::parse();
    let outcome = match cli.command {
        Command::Render(args) => {
            error::finish(args.resolve().and_then(|a| commands::render::run(&a)))
        }
        Command::CalibChart(args) => {
            error::finish(args.resolve().and_then(|a| commands::calib_chart::run(&a)))
        }
        Command::Gamma(command) => error::finish(commands::gamma_fit::run(&command)),
        Command::Check(args) => commands::check::run(&args),
        Command::Schema => error::finish(commands::schema::run()),
    };
    outcome.into()
}
