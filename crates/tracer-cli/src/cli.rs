//! The `tracer` command and its subcommands.

use crate::{args, tool_args};
use clap::{CommandFactory, Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "tracer",
    version,
    about = "A data-driven ray tracer: scene file in, PNG out"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand)]
pub enum Command {
    Render(args::RenderArgs),
    CalibChart(args::CalibChartArgs),
    #[command(subcommand)]
    Gamma(args::GammaCommand),
    Check(args::CheckArgs),
    Watch(args::WatchArgs),
    Pack(args::PackArgs),
    Merge(args::MergeArgs),
    Explain(args::ExplainArgs),
    /// Print the JSON Schema of scene files (3D and 2D canvas), for editor
    /// completion and checking (e.g. `tracer schema > schema.json`)
    Schema,
    New(tool_args::NewArgs),
    Convert(tool_args::ConvertArgs),
    Completions(tool_args::CompletionsArgs),
    Compare(crate::compare_args::CompareArgs),
}

/// The clap definition of `tracer`, for completions and man pages.
pub fn command() -> clap::Command {
    Cli::command()
}
