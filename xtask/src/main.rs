//! Project chores, the cargo-xtask way: `cargo xtask <task>`.

use std::process::ExitCode;

fn main() -> ExitCode {
    let task = std::env::args().nth(1);
    eprintln!("unknown task {task:?}\nusage: cargo xtask <task>");
    ExitCode::from(2)
}
