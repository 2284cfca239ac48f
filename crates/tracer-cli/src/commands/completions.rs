//! `tracer completions SHELL`: the shell's completion script, on stdout.

use tracer_cli::tool_args::CompletionsArgs;

pub fn run(args: &CompletionsArgs) -> anyhow::Result<()> {
    let mut script = Vec::new();
    clap_complete::generate(
        args.shell,
        &mut tracer_cli::command(),
        "tracer",
        &mut script,
    );
    crate::console::stdout(&String::from_utf8(script)?)
}
