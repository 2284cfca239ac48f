//! `tracer compare`: an image against an image or a scene's render (the
//! numbers, a heat-map, the mistakes that explain the difference), or with
//! `--report` a class's images against their scenes.

mod class;
mod comparison;
mod diagnose;
mod flip;
mod input;
mod metrics;
mod page;
mod pair;

use crate::console::note;
use crate::error::{self, Outcome};
use input::BadInput;
use std::path::Path;
use tracer_cli::compare_args::CompareArgs;

pub fn run(args: &CompareArgs) -> Outcome {
    let result = match (&args.report, &args.image, &args.reference) {
        (Some(dir), _, _) => {
            let scenes = args.scenes.as_deref().unwrap_or(Path::new("scenes"));
            let out = args.output.as_deref().unwrap_or(Path::new("report"));
            class::run(dir, scenes, out, args.tolerance, args.samples)
        }
        (None, Some(image), Some(reference)) => {
            let heat_map = args.output.as_deref();
            pair::run(image, reference, heat_map, args.tolerance, args.samples)
        }
        (None, _, _) => unreachable!("clap requires IMAGE and REFERENCE without --report"),
    };
    match result {
        Ok(true) => Outcome::Ok,
        // Exit 1: not within tolerance, as a golden that fails its check.
        Ok(false) => Outcome::Failure,
        Err(e) => match e.downcast_ref::<BadInput>() {
            Some(bad) => {
                note!("error: {bad}");
                Outcome::BadInput
            }
            // Exit 1 means "not within tolerance" here: any other failure
            // (a heat-map or report that cannot be written) is 2, so that
            // a script never takes it for a verdict.
            None => match error::finish(Err(e)) {
                // A closed stdout: whoever read it has all they wanted.
                Outcome::Ok => Outcome::Ok,
                _ => Outcome::BadInput,
            },
        },
    }
}
