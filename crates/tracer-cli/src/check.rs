//! `tracer check`: validate scene files without rendering.

use crate::report;
use clap::Args;
use std::path::PathBuf;

/// Check scene files for mistakes without rendering them; every problem
/// found is reported, with its file, line, column and key.
#[derive(Args)]
pub struct CheckArgs {
    /// Scene files (.toml or .json): 3D scenes or 2D canvas scenes
    #[arg(required = true, value_name = "SCENE")]
    pub scenes: Vec<PathBuf>,
}

/// What checking found, worst first: any machine failure, else any bad
/// scene, else all good.
#[derive(Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Outcome {
    Ok,
    BadInput,
    Failure,
}

pub fn run(args: &CheckArgs) -> Outcome {
    let color = report::color_wanted();
    let mut outcome = Outcome::Ok;
    let mut bad = 0;
    for scene in &args.scenes {
        match scene_format::load_any(scene) {
            Ok(_) => eprintln!("ok: {}", scene.display()),
            Err(e) => {
                bad += 1;
                eprint!("{}", report::render(&e, color));
                let this = if report::is_bad_input(&e) {
                    Outcome::BadInput
                } else {
                    Outcome::Failure
                };
                outcome = outcome.max(this);
            }
        }
    }
    if bad > 0 {
        eprintln!(
            "{bad} of {} scene file{} failed the check",
            args.scenes.len(),
            if args.scenes.len() == 1 { "" } else { "s" }
        );
    }
    outcome
}
