//! The commands around the renderer: completions, new, convert.

use std::path::Path;
use std::process::{Command, Output};

fn tracer(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tracer"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run tracer")
}

fn stdout_of(out: &Output) -> String {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout.clone()).unwrap()
}

/// The commands, as the README lists them.
const COMMANDS: [&str; 8] = [
    "render",
    "calib-chart",
    "gamma",
    "check",
    "watch",
    "pack",
    "schema",
    "completions",
];

#[test]
fn bash_completions_offer_every_command_and_the_render_options() {
    let dir = tempfile::tempdir().unwrap();
    let script = stdout_of(&tracer(dir.path(), &["completions", "bash"]));
    assert!(
        script.contains("complete -F _tracer"),
        "registers the function"
    );
    // bash completes the first word from one list of the subcommands.
    let top = script
        .lines()
        .find(|l| l.contains("opts=") && l.contains("render"))
        .expect("the top-level word list");
    for command in COMMANDS {
        assert!(
            top.split([' ', '"']).any(|w| w == command),
            "{command}: {top}"
        );
    }
    for option in ["--samples", "--bit-depth", "--aov", "ray-dir-x"] {
        assert!(script.contains(option), "{option}");
    }
}

#[test]
fn every_shell_gets_a_script_naming_the_commands() {
    let dir = tempfile::tempdir().unwrap();
    for shell in ["bash", "zsh", "fish", "powershell", "elvish"] {
        let script = stdout_of(&tracer(dir.path(), &["completions", shell]));
        for command in COMMANDS {
            assert!(script.contains(command), "{shell}: {command}");
        }
    }
    let out = tracer(dir.path(), &["completions", "tcsh"]);
    assert_eq!(out.status.code(), Some(2), "an unknown shell is bad input");
}
