//! `tracer new SCENE`: a starter scene that renders as it is.

use crate::console::note;
use crate::error::Outcome;
use scene_format::Format;
use std::io::Write;
use std::path::Path;
use tracer_cli::tool_args::NewArgs;

/// The starter scene, commented; `tracer new x.json` writes it as JSON.
pub const STARTER: &str = include_str!("starter.toml");

pub fn run(args: &NewArgs) -> Outcome {
    let path = &args.scene;
    let Some(format) = Format::from_path(path) else {
        note!(
            "error: {}: expected a .toml or .json file name",
            path.display()
        );
        return Outcome::BadInput;
    };
    let text = match format {
        Format::Toml => STARTER.to_string(),
        Format::Json => super::convert::convert(STARTER, Format::Toml, Format::Json)
            .expect("the starter scene is valid TOML"),
    };
    match write_new(path, &text) {
        Ok(()) => {
            note!(
                "wrote {}; render it with `tracer render {}`",
                path.display(),
                path.display()
            );
            write_schema_beside(path);
            Outcome::Ok
        }
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
            note!(
                "error: {} exists; expected a new file name (it is not overwritten)",
                path.display()
            );
            Outcome::BadInput
        }
        Err(e) => {
            note!("error: cannot write {}: {e}", path.display());
            Outcome::Failure
        }
    }
}

/// The `schema.json` the starter names (`#:schema ./schema.json`), beside
/// it, unless one is there: an editor then completes and checks the keys.
/// Not having it is no failure of `new`: said, and the scene stays.
fn write_schema_beside(scene: &Path) {
    let folder = scene.parent().unwrap_or(Path::new(""));
    let schema = folder.join("schema.json");
    match write_new(&schema, &scene_format::schema::json_schema()) {
        Ok(()) => note!(
            "wrote {} beside it, which the scene names: editors read it to complete and check the keys",
            schema.display()
        ),
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
        Err(e) => note!("note: cannot write {}: {e}", schema.display()),
    }
}

/// Writes `text` to a file that must not exist yet: `create_new` checks
/// and creates in one step, so no file is clobbered, even one made
/// meanwhile. A failed write removes the part written.
fn write_new(path: &Path, text: &str) -> std::io::Result<()> {
    let mut file = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)?;
    file.write_all(text.as_bytes()).inspect_err(|_| {
        let _ = std::fs::remove_file(path);
    })
}
