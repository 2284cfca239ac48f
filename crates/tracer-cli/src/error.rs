//! How a run ends: the exit status (0 done, 2 bad input, 1 anything else)
//! and the error message on stderr.

use crate::console::{self, note, ClosedPipe};
use crate::report;
use scene_format::SceneError;
use std::process::ExitCode;

/// Exit status for bad input (a scene or the arguments); 1 is any other failure.
pub const EXIT_BAD_INPUT: u8 = 2;

/// What a run came to, worst last: `max` of two outcomes is the worse.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Outcome {
    Ok,
    BadInput,
    Failure,
}

impl From<Outcome> for ExitCode {
    fn from(outcome: Outcome) -> ExitCode {
        match outcome {
            Outcome::Ok => ExitCode::SUCCESS,
            Outcome::BadInput => ExitCode::from(EXIT_BAD_INPUT),
            Outcome::Failure => ExitCode::FAILURE,
        }
    }
}

/// The outcome of a command: errors are reported on stderr, a scene
/// error with its source lines.
pub fn finish(result: anyhow::Result<()>) -> Outcome {
    match result {
        Ok(()) => Outcome::Ok,
        Err(e) => report_error(&e),
    }
}

fn report_error(e: &anyhow::Error) -> Outcome {
    if e.is::<ClosedPipe>() {
        // Whoever read stdout has all they wanted (`tracer schema | head`).
        return Outcome::Ok;
    }
    if let Some(scene) = scene_error(e) {
        console::stderr_report(&report::render(scene, report::color_wanted()));
        return scene_outcome(scene);
    }
    note!("error: {e:#}");
    match e.downcast_ref::<tracer_pipeline::Error>() {
        Some(p) if p.is_bad_input() => Outcome::BadInput,
        _ => Outcome::Failure,
    }
}

/// The scene error behind `e`, as loading returns it or inside a pipeline error.
fn scene_error(e: &anyhow::Error) -> Option<&SceneError> {
    match e.downcast_ref::<tracer_pipeline::Error>() {
        Some(tracer_pipeline::Error::Scene(scene)) => Some(scene),
        _ => e.downcast_ref::<SceneError>(),
    }
}

/// Bad input unless the machine failed to read the file.
pub fn scene_outcome(error: &SceneError) -> Outcome {
    if tracer_pipeline::scene_error_is_bad_input(error) {
        Outcome::BadInput
    } else {
        Outcome::Failure
    }
}
