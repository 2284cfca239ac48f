//! `tracer render` in passes (path mode): samples 0..1, 1..2, 2..4, ...,
//! each pass's line printed, stopped by `--time-limit` (or `[render]
//! time_limit`) after the last pass that fits, and, with `--reference`, each
//! pass's error against that image.

use crate::console::note;
use std::time::Instant;
use tracer_pipeline::reference::rmse;
use tracer_pipeline::LinearImage;
use tracer_pipeline::Pass;

/// What a render in passes was asked for.
pub struct Plan {
    /// Seconds after which no pass starts that would not end by then.
    pub time_limit: Option<f64>,
    /// Whether the limit is `--time-limit`'s (the scene's own is warned
    /// about with the scene's warnings).
    pub limit_given: bool,
    pub reference: Option<LinearImage>,
}

/// The callback of `render_progressive`: prints each pass's line (unless
/// `quiet`, but for its error against a reference), and says whether the
/// next pass is to run; when the time limit stops it, says so.
pub fn on_pass(plan: &Plan, quiet: bool) -> impl FnMut(Pass) -> bool + '_ {
    let start = Instant::now();
    let mut pass_start = start;
    let (mut number, mut samples) = (0, 0);
    move |pass: Pass| {
        number += 1;
        let now = Instant::now();
        let (elapsed, this_pass) = (
            now.duration_since(start).as_secs_f64(),
            now.duration_since(pass_start).as_secs_f64(),
        );
        pass_start = now;
        let added = pass.samples - samples;
        samples = pass.samples;
        let error = plan.reference.as_ref().map(|r| {
            format!(
                ", RMSE {:.5} against the reference",
                rmse(&pass.picture.linear, r)
            )
        });
        if !quiet || plan.reference.is_some() {
            note!(
                "pass {number}: {} of {} samples a pixel, {elapsed:.3} s{}",
                pass.samples,
                pass.total,
                error.unwrap_or_default()
            );
        }
        let next = tracer_pipeline::next_pass_samples(pass.samples, pass.total);
        let Some(limit) = plan.time_limit else {
            return true;
        };
        if number == 1 && pass.total == 1 && plan.limit_given {
            note!("note: --time-limit has nothing to stop: 1 sample a pixel is one pass; ask for the most you want with --samples (up to 65536), and the limit stops the render sooner");
        }
        let estimate = tracer_pipeline::next_pass_seconds(this_pass, added, next);
        let fits = elapsed + estimate <= limit;
        if next > 0 && !fits {
            // 1e-300 as that, not as three hundred digits.
            let limit = if (1e-3..1e7).contains(&limit) {
                format!("{limit}")
            } else {
                format!("{limit:e}")
            };
            // Two digits that mean something: 0.04 s, not 0.0 s.
            let estimate = if estimate < 1.0 {
                format!("{estimate:.2}")
            } else {
                format!("{estimate:.1}")
            };
            note!(
                "stopped at {} of {} samples a pixel: the next pass ({next} more, about {estimate} s) would end after the time limit of {limit} s",
                pass.samples,
                pass.total
            );
        }
        fits
    }
}
