//! Project chores, the cargo-xtask way: `cargo xtask <task>`.

use clap::Parser;
use std::process::ExitCode;
use xtask::cli::{BookArgs, Cli, Command, GoldenArgs, ManArgs, WebArgs};

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
        Command::DenoiseFigures => denoise_figures(),
        Command::Web(args) => web(&args),
        Command::Gallery => gallery(),
        Command::Book(args) => book(&args),
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

fn denoise_figures() -> anyhow::Result<ExitCode> {
    for path in xtask::bench::denoise_figure::write_all(&xtask::workspace_root())? {
        println!("wrote {}", path.display());
    }
    Ok(ExitCode::SUCCESS)
}

fn gallery() -> anyhow::Result<ExitCode> {
    let path = xtask::gallery::write(&xtask::workspace_root())?;
    println!("wrote {}", path.display());
    Ok(ExitCode::SUCCESS)
}

fn book(args: &BookArgs) -> anyhow::Result<ExitCode> {
    let root = xtask::workspace_root();
    for path in xtask::book::write_generated(&root)? {
        println!("wrote {}", path.display());
    }
    let problems = xtask::book::check(&root)?;
    for problem in &problems {
        eprintln!("{problem}");
    }
    if !problems.is_empty() {
        eprintln!("{} problems in the book's pages", problems.len());
        return Ok(ExitCode::FAILURE);
    }
    if args.check {
        println!("the book's pages are sound");
        return Ok(ExitCode::SUCCESS);
    }
    let out = args.out.clone().unwrap_or_else(xtask::book::default_out);
    xtask::book::build(&root, &out)?;
    println!("the book is in {}", out.join("index.html").display());
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
