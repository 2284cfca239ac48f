//! The arguments of the commands around the renderer: starting a scene,
//! converting it, shell completions.

use clap::Args;
use std::path::PathBuf;

/// Write a short commented starter scene (a camera, a light, a floor and a
/// sphere) that renders as it is. An existing file is never overwritten.
#[derive(Args)]
pub struct NewArgs {
    /// The scene file to write: .toml, or .json for the same scene in JSON
    #[arg(value_name = "SCENE.toml")]
    pub scene: PathBuf,
}

/// Convert a scene file between TOML and JSON, keeping every value and the
/// structure (comments are lost; a `#:schema` directive becomes `$schema`
/// and back). Included files are converted on their own.
#[derive(Args)]
pub struct ConvertArgs {
    /// Scene file (.toml or .json), 3D or 2D canvas
    #[arg(value_name = "SCENE")]
    pub scene: PathBuf,
    /// The file to write, its format by its extension [default: the scene's
    /// file name with the other format's extension, in the current folder]
    #[arg(short, long, value_name = "OUT.json|OUT.toml")]
    pub output: Option<PathBuf>,
}

/// Print a shell's completion script for `tracer` to stdout, e.g.
/// `tracer completions bash > ~/.local/share/bash-completion/completions/tracer`
#[derive(Args)]
pub struct CompletionsArgs {
    /// The shell
    pub shell: clap_complete::Shell,
}
