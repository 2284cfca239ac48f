//! Project chores, the cargo-xtask way: `cargo xtask <task>`.

use clap::{Args, Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "cargo xtask",
    bin_name = "cargo xtask",
    about = "Project chores"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    Golden(GoldenArgs),
    /// Write the generated files the texture scenes read (images, an OBJ and its MTL)
    Assets,
    /// Benchmark the tracer against POV-Ray and Embree on the bench scenes (docs/performance.md)
    Bench(xtask::bench::BenchArgs),
    /// Render a scene as N tiles in separate processes, merge them and
    /// compare with a single render, bit for bit (docs/farm.md)
    FarmTest(xtask::farm::FarmArgs),
    Man(ManArgs),
    /// Install Intel Open Image Denoise for `tracer render --denoise` (from
    /// PyPI's pyoidn wheel, with pip) into target/oidn
    Oidn,
    Web(WebArgs),
    /// Write docs/gallery.md: every scene's golden image with its file name
    /// and the command that renders it
    Gallery,
    /// Run a command and print its peak memory and times (used by the bench)
    #[command(hide = true)]
    PeakOf {
        #[arg(required = true, trailing_var_arg = true, allow_hyphen_values = true)]
        command: Vec<std::ffi::OsString>,
    },
}

/// Write a man page per `tracer` command (tracer.1, tracer-render.1, ...)
#[derive(Args)]
struct ManArgs {
    /// The folder to write them in [default: target/man]
    #[arg(long, value_name = "DIR")]
    out: Option<std::path::PathBuf>,
}

/// Build the browser playground: one folder of static files (docs: README, In the browser)
///
/// The page, its bundled scripts, the tracer built for wasm32 and every scene
/// of scenes/ with the files it reads. Any static web server can host it.
#[derive(Args)]
struct WebArgs {
    /// The folder to write [default: target/web]
    #[arg(long, value_name = "DIR")]
    out: Option<std::path::PathBuf>,
    /// Then serve it for trying, on ADDR [default: 127.0.0.1:8000]
    #[arg(long, value_name = "ADDR", num_args = 0..=1, default_missing_value = "127.0.0.1:8000")]
    serve: Option<String>,
}

/// Check every scene's render against its golden image in golden/
///
/// Renders every scene, compares each with golden/<NAME>.png (tolerances in
/// golden/golden.toml), prints a table and writes the report
/// target/golden/index.html. Exit status 1 when any image fails or has no golden.
#[derive(Args)]
struct GoldenArgs {
    /// Make the renders the new goldens (look at them first: target/golden/)
    #[arg(long)]
    bless: bool,
    /// Only these images (a golden's file stem, e.g. reflectance2) [default: all]
    #[arg(value_name = "NAME")]
    names: Vec<String>,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Golden(args) => golden(&args),
        Command::Assets => {
            xtask::assets::write_all(&xtask::workspace_root()).map(|()| ExitCode::SUCCESS)
        }
        Command::Bench(args) => xtask::bench::run(&args).map(|()| ExitCode::SUCCESS),
        Command::FarmTest(args) => xtask::farm::run(&args).map(|()| ExitCode::SUCCESS),
        Command::Man(args) => man(&args),
        Command::Oidn => xtask::oidn::install().map(|_| ExitCode::SUCCESS),
        Command::Web(args) => web(&args),
        Command::Gallery => gallery(),
        Command::PeakOf { command } => {
            xtask::bench::memory::peak_of(&command).map(|()| ExitCode::SUCCESS)
        }
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn golden(args: &GoldenArgs) -> anyhow::Result<ExitCode> {
    let root = xtask::workspace_root();
    if args.bless {
        for change in xtask::golden::run_bless(&root, &args.names)? {
            println!("{change}");
        }
        return Ok(ExitCode::SUCCESS);
    }
    let report_dir = xtask::target_dir().join("golden");
    let summary = xtask::golden::run_check(&root, &args.names, &report_dir)?;
    println!("{}", summary.table);
    println!("report: {}", summary.report.display());
    Ok(if summary.all_passed() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

fn man(args: &ManArgs) -> anyhow::Result<ExitCode> {
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| xtask::target_dir().join("man"));
    let pages = xtask::man::write_pages(&dir)?;
    println!("{} man pages in {}", pages.len(), dir.display());
    Ok(ExitCode::SUCCESS)
}

fn gallery() -> anyhow::Result<ExitCode> {
    let path = xtask::gallery::write(&xtask::workspace_root())?;
    println!("wrote {}", path.display());
    Ok(ExitCode::SUCCESS)
}

fn web(args: &WebArgs) -> anyhow::Result<ExitCode> {
    let out = args.out.clone().unwrap_or_else(xtask::web::default_out);
    xtask::web::build(&xtask::workspace_root(), &out)?;
    println!("the page is in {}", out.display());
    if let Some(addr) = &args.serve {
        let bound = xtask::web::serve::start(&out, addr)?;
        println!("serving it at http://{bound}/ (Ctrl-C stops)");
        loop {
            std::thread::park();
        }
    }
    Ok(ExitCode::SUCCESS)
}
