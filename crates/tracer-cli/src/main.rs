//! `tracer`: renders scene files (TOML or JSON) to PNG images.

mod commands;
mod console;
mod error;
mod progress;
mod report;

use std::process::ExitCode;
use tracer_cli::{args, Command};

fn main() -> ExitCode {
    // clap exits with 2 on bad arguments, 0 for --help.
    let cli = tracer_cli::parse();
    #[cfg(unix)]
    signals::remove_outputs_on_signal();
    let outcome = match cli.command {
        Command::Render(args) => {
            error::finish(args.resolve().and_then(|a| commands::render::run(&a)))
        }
        Command::CalibChart(args) => {
            error::finish(args.resolve().and_then(|a| commands::calib_chart::run(&a)))
        }
        Command::Gamma(command) => error::finish(commands::gamma_fit::run(&command)),
        Command::Check(args) => commands::check::run(&args),
        Command::Watch(args) => {
            error::finish(args.resolve().and_then(|a| commands::watch::run(&a)))
        }
        Command::Pack(args) => error::finish(commands::pack::run(&args)),
        Command::Merge(args) => error::finish(commands::merge::run(&args)),
        Command::Explain(args) => {
            error::finish(args.resolve().and_then(|a| commands::explain::run(&a)))
        }
        Command::Schema => error::finish(commands::schema::run()),
        Command::New(args) => commands::new::run(&args),
        Command::Convert(args) => error::finish(commands::convert::run(&args)),
        Command::Completions(args) => error::finish(commands::completions::run(&args)),
        Command::Compare(args) => commands::compare::run(&args),
    };
    outcome.into()
}

#[cfg(unix)]
mod signals {
    use crate::console::note;
    use signal_hook::consts::{SIGINT, SIGTERM};

    /// On SIGINT or SIGTERM, removes the temporary output files in flight
    /// (they would be left behind) and exits 128 + the signal, as a shell
    /// reports a process it killed: 130 for Ctrl-C, 143 for SIGTERM.
    pub fn remove_outputs_on_signal() {
        let mut signals = match signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) {
            Ok(s) => s,
            Err(e) => {
                // The default handling stays: only the cleanup is lost.
                note!("warning: cannot handle signals: {e}");
                return;
            }
        };
        std::thread::spawn(move || {
            if let Some(signal) = signals.forever().next() {
                // Held to the exit: nothing is renamed into place after it.
                let _removed = tracer_pipeline::output::remove_pending_files();
                std::process::exit(128 + signal);
            }
        });
    }
}
