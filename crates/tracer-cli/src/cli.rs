//! The `tracer` command and its subcommands.

use crate::{args, tool_args};
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

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

/// The clap definition of `tracer`, for completions and man pages: the
/// derived one, its help ending with where the book is.
pub fn command() -> clap::Command {
    Cli::command().after_help(book_note())
}

/// The arguments, parsed by [`command`] (so `--help` names the book).
pub fn parse() -> Cli {
    let matches = command().get_matches();
    // The derived definition and `command()` differ only in help text.
    Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit())
}

/// Where to read more: the book's pages in the repository, and the HTML
/// `cargo xtask book` builds, where it has been built beside the source
/// this binary was built from.
pub fn book_note() -> String {
    let mut note = String::from(
        "The book (a tutorial, a guide by task, every scene key and every message): \
         docs/src/ in the tracer's repository, from docs/src/SUMMARY.md; \
         `cargo xtask book` builds it into target/book/.",
    );
    let built =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/book/index.html");
    if let Ok(path) = built.canonicalize() {
        note.push_str(&format!(" Built here: {}", path.display()));
    }
    note
}
