//! What the command-line tests share: running `tracer` as a user would.
// Each test file uses its own part of this.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// `tracer ARGS` run in `dir`, to its end.
pub fn tracer(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tracer"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run tracer")
}
