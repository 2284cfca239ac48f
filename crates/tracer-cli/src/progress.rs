//! The progress bar of a render, on stderr: it appears only once a render
//! has taken half a second, so quick renders print nothing but their summary.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

const SHOW_AFTER: Duration = Duration::from_millis(500);

pub struct Progress {
    bar: ProgressBar,
    /// When the rows began: the first report, after loading and preparing.
    start: OnceLock<Instant>,
    enabled: bool,
    shown: AtomicBool,
}

impl Progress {
    /// A bar over `rows` rows; never drawn when `quiet` or when stderr is
    /// not a terminal (a log file would fill with bars).
    pub fn new(rows: u64, quiet: bool) -> Progress {
        let bar = ProgressBar::with_draw_target(Some(rows), ProgressDrawTarget::hidden());
        let style = ProgressStyle::with_template(
            "rendering [{bar:40}] {percent:>3}% {elapsed} elapsed, ETA {eta}",
        )
        .map(|s| s.progress_chars("=> "));
        if let Ok(style) = style {
            bar.set_style(style);
        }
        Progress {
            bar,
            start: OnceLock::new(),
            enabled: !quiet && std::io::stderr().is_terminal(),
            shown: AtomicBool::new(false),
        }
    }

    /// Called from the render threads as `rows` more rows are done (0
    /// when the rows begin).
    pub fn rows_done(&self, rows: u32) {
        let start = self.start.get_or_init(|| {
            // Preparing the scene is not rendering: time and ETA from here.
            self.bar.reset_elapsed();
            self.bar.reset_eta();
            Instant::now()
        });
        self.bar.inc(rows.into());
        if self.enabled
            && start.elapsed() >= SHOW_AFTER
            && !self.shown.swap(true, Ordering::Relaxed)
        {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
    }

    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
