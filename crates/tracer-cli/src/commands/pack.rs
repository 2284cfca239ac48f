//! `tracer pack`: a scene and the files it reads in one zip archive.

use crate::args::PackArgs;
use crate::console::note;
use std::path::PathBuf;

pub fn run(args: &PackArgs) -> anyhow::Result<()> {
    let output = args.output.clone().unwrap_or_else(|| default_output(args));
    let packed = tracer_pipeline::pack::pack(&args.scene, &output)?;
    if !args.quiet {
        let n = packed.entries.len();
        note!(
            "packed {} ({n} file{}, {} bytes) -> {}",
            args.scene.display(),
            if n == 1 { "" } else { "s" },
            packed.bytes,
            output.display()
        );
    }
    Ok(())
}

/// The scene's file name with `.zip`, in the current folder.
fn default_output(args: &PackArgs) -> PathBuf {
    let stem = args.scene.file_stem().unwrap_or_default();
    PathBuf::from(stem).with_extension("zip")
}
