//! The `cargo xtask` command line as clap defines it, in the library so that
//! the book's checks parse its commands with the very definition `main` does.

use clap::{Args, Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "cargo xtask",
    bin_name = "cargo xtask",
    about = "Project chores"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand)]
pub enum Command {
    Golden(GoldenArgs),
    /// Write the generated files the texture scenes read (images, an OBJ and its MTL)
    Assets,
    /// Benchmark the tracer against POV-Ray and Embree on the bench scenes (docs/src/performance.md)
    Bench(crate::bench::BenchArgs),
    /// Render a scene as N tiles in separate processes, merge them and
    /// compare with a single render, bit for bit (docs/src/guide/farm.md)
    FarmTest(crate::farm::FarmArgs),
    Man(ManArgs),
    /// Install Intel Open Image Denoise for `tracer render --denoise` (from
    /// PyPI's pyoidn wheel, with pip) into target/oidn
    Oidn,
    /// Write the book's denoising figures, docs/src/images/denoise-*.png:
    /// noisy, denoised and reference side by side (after `cargo xtask oidn`)
    DenoiseFigures,
    Web(WebArgs),
    /// Write docs/src/gallery.md: every scene's golden image with its file
    /// name and the command that renders it
    Gallery,
    Book(BookArgs),
    /// Run a command and print its peak memory and times (used by the bench)
    #[command(hide = true)]
    PeakOf {
        #[arg(required = true, trailing_var_arg = true, allow_hyphen_values = true)]
        command: Vec<std::ffi::OsString>,
    },
}

/// Write a man page per `tracer` command (tracer.1, tracer-render.1, ...)
#[derive(Args)]
pub struct ManArgs {
    /// The folder to write them in [default: target/man]
    #[arg(long, value_name = "DIR")]
    pub out: Option<std::path::PathBuf>,
}

/// Build the browser playground: one folder of static files (docs/src/guide/playground.md)
///
/// The page, its bundled scripts, the tracer built for wasm32 and every scene
/// of scenes/ with the files it reads. Any static web server can host it.
#[derive(Args)]
pub struct WebArgs {
    /// The folder to write [default: target/web]
    #[arg(long, value_name = "DIR")]
    pub out: Option<std::path::PathBuf>,
    /// Then serve it for trying, on ADDR [default: 127.0.0.1:8000]
    #[arg(long, value_name = "ADDR", num_args = 0..=1, default_missing_value = "127.0.0.1:8000")]
    pub serve: Option<String>,
}

/// Check every scene's render against its golden image in golden/
///
/// Renders every scene, compares each with golden/<NAME>.png (tolerances in
/// golden/golden.toml), prints a table and writes the report
/// target/golden/index.html. Exit status 1 when any image fails or has no golden.
#[derive(Args)]
pub struct GoldenArgs {
    /// Make the renders the new goldens (look at them first: target/golden/)
    #[arg(long)]
    pub bless: bool,
    /// Only these images (a golden's file stem, e.g. reflectance2) [default: all]
    #[arg(value_name = "NAME")]
    pub names: Vec<String>,
}

/// Build the book (docs/) into a folder of HTML pages, with mdBook
///
/// Writes the generated pages first (the scene keys' reference from the
/// schema, the commands' reference from clap, the gallery), checks every
/// page's links, images and commands, then builds with mdbook (installed
/// with `cargo install mdbook --locked` when missing).
#[derive(Args)]
pub struct BookArgs {
    /// The folder to write [default: target/book]
    #[arg(long, value_name = "DIR")]
    pub out: Option<std::path::PathBuf>,
    /// Only check the pages (links, images, commands, generated pages); build nothing
    #[arg(long)]
    pub check: bool,
}
