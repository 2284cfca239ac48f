//! The page's side of a render in passes: each pass's pixels go to the
//! page as they are made (the image sharpens while a long path-traced
//! render runs), the rows of the pass under way as they are done (a few
//! times a second), and the scene's `time_limit` stops it after the last
//! pass that fits, by the rule of `tracer render`.

use crate::PassImage;
use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};

/// Rows of the current pass done, when the page was last told, and when
/// the passes began (the bits of f64s of seconds). One render runs at a
/// time in an instance.
static ROWS: AtomicU32 = AtomicU32::new(0);
static TOLD: AtomicU64 = AtomicU64::new(0);
static START: AtomicU64 = AtomicU64::new(0);

/// How often the page hears of rows done, at most.
const ROWS_EVERY_SECONDS: f64 = 0.25;

/// The pipeline's `rows_done`: `n` more rows of the current pass done;
/// 0 as the passes begin, the scene loaded and prepared, which is when
/// the time limit's clock starts (as `tracer render`'s does).
pub fn rows_done(n: u32) {
    if n == 0 {
        START.store(now_seconds().to_bits(), Ordering::Relaxed);
        return;
    }
    let rows = ROWS.fetch_add(n, Ordering::Relaxed) + n;
    let now = now_seconds();
    if now - f64::from_bits(TOLD.load(Ordering::Relaxed)) >= ROWS_EVERY_SECONDS {
        TOLD.store(now.to_bits(), Ordering::Relaxed);
        send_rows(rows);
    }
}

/// The time of a render in passes, read from the page's clock (the wasm
/// has none of its own), from the start of its passes.
pub struct PassClock {
    pass_start: f64,
    samples: u32,
}

impl PassClock {
    pub fn new() -> PassClock {
        let now = now_seconds();
        ROWS.store(0, Ordering::Relaxed);
        START.store(now.to_bits(), Ordering::Relaxed);
        PassClock {
            pass_start: now,
            samples: 0,
        }
    }

    /// Sends `pass` to the page (but the last, which is the render's
    /// answer); whether the next pass is to run.
    pub fn pass(&mut self, pass: &PassImage) -> bool {
        if pass.samples < pass.total {
            send(pass);
        }
        ROWS.store(0, Ordering::Relaxed);
        let now = now_seconds();
        let start = f64::from_bits(START.load(Ordering::Relaxed));
        // The first pass from the start of the passes, not of the load.
        let pass_start = if self.samples == 0 {
            start
        } else {
            self.pass_start
        };
        let this_pass = now - pass_start;
        let added = pass.samples - self.samples;
        (self.pass_start, self.samples) = (now, pass.samples);
        let next = tracer_pipeline::next_pass_samples(pass.samples, pass.total);
        match pass.time_limit {
            Some(limit) if next > 0 => {
                let estimate = tracer_pipeline::next_pass_seconds(this_pass, added, next);
                now - start + estimate <= limit
            }
            _ => true,
        }
    }
}

#[cfg(target_arch = "wasm32")]
mod imports {
    #[link(wasm_import_module = "env")]
    extern "C" {
        /// The page's clock, in milliseconds (`performance.now()`).
        pub fn tracer_now_ms() -> f64;
        /// A pass's RGBA pixels of the region, for the page to show.
        pub fn tracer_pass(samples: u32, total: u32, ptr: *const u8, len: usize);
        /// Rows of the region done in the pass under way.
        pub fn tracer_rows(rows: u32);
    }
}

#[cfg(target_arch = "wasm32")]
fn now_seconds() -> f64 {
    // SAFETY: an import of the page that takes nothing.
    unsafe { imports::tracer_now_ms() / 1000.0 }
}

#[cfg(target_arch = "wasm32")]
fn send(pass: &PassImage) {
    let rgba = pass.rgba;
    // SAFETY: the page copies the bytes during the call.
    unsafe { imports::tracer_pass(pass.samples, pass.total, rgba.as_ptr(), rgba.len()) }
}

/// Natively (the tests) there is no page: no pass is sent, and the clock
/// is the process's.
#[cfg(not(target_arch = "wasm32"))]
fn now_seconds() -> f64 {
    use std::sync::OnceLock;
    use std::time::Instant;
    static START: OnceLock<Instant> = OnceLock::new();
    START.get_or_init(Instant::now).elapsed().as_secs_f64()
}

#[cfg(target_arch = "wasm32")]
fn send_rows(rows: u32) {
    // SAFETY: an import of the page that takes a number.
    unsafe { imports::tracer_rows(rows) }
}

#[cfg(not(target_arch = "wasm32"))]
fn send(_: &PassImage) {}

#[cfg(not(target_arch = "wasm32"))]
fn send_rows(_: u32) {}

#[cfg(test)]
mod tests {
    use super::*;

    fn pass(samples: u32, total: u32, time_limit: Option<f64>) -> PassImage<'static> {
        PassImage {
            rgba: &[],
            samples,
            total,
            time_limit,
        }
    }

    #[test]
    fn a_time_limit_stops_before_a_pass_that_would_end_after_it() {
        let mut clock = PassClock::new();
        assert!(clock.pass(&pass(1, 64, None)), "no limit: on to the end");
        let mut clock = PassClock::new();
        assert!(clock.pass(&pass(1, 64, Some(1e6))));
        assert!(!clock.pass(&pass(2, 64, Some(0.0))), "past the limit");
        // The last pass has no next one to stop.
        let mut clock = PassClock::new();
        assert!(clock.pass(&pass(64, 64, Some(0.0))));
    }
}
