//! The arguments of the commands around the renderer: starting a scene,
//! converting it, shell completions.

use clap::Args;

/// Print a shell's completion script for `tracer` to stdout, e.g.
/// `tracer completions bash > ~/.local/share/bash-completion/completions/tracer`
#[derive(Args)]
pub struct CompletionsArgs {
    /// The shell
    pub shell: clap_complete::Shell,
}
